/* Every function of include/relnav.h, linked against the flight library
 * (scripts/build-flight.sh writes the table every_fns.h from the header): a program that
 * can reach all of them, in which the script counts the panic paths left (none). It also
 * checks what the flight library leaves out: each answers "not in this build". */
#include <relnav.h>
#include <stdalign.h>
#include <stdio.h>
#include <string.h>

/* fixed width on every target, arm-none-eabi's short enums included */
_Static_assert(sizeof(relnav_status) == sizeof(int32_t), "relnav_status is an int32_t");
_Static_assert(sizeof(relnav_filter) == sizeof(int32_t), "relnav_filter is an int32_t");

void *const every[] = {
#include "every_fns.h"
};

static alignas(RELNAV_ESTIMATOR_STORAGE_ALIGN) unsigned char storage[RELNAV_ESTIMATOR_STORAGE_SIZE];

static int refused(relnav_status st, const char *what) {
    int ok = st == RELNAV_ERROR_NOT_IMPLEMENTED && strstr(relnav_last_error(), "not in this build") != NULL;
    printf("%s: %s (%s)\n", what, ok ? "not in this build" : "UNEXPECTED", relnav_last_error());
    return ok;
}

int main(void) {
    int good = 1;
    relnav_config cfg = relnav_config_default();
    relnav_estimator *est = NULL;
    good &= refused(relnav_estimator_new(&cfg, &est), "relnav_estimator_new");
    const int32_t absent[] = {RELNAV_FILTER_PF, RELNAV_FILTER_RPF, RELNAV_FILTER_UPF, RELNAV_FILTER_GAPF, RELNAV_FILTER_CGAPF, RELNAV_FILTER_HINF};
    for (size_t i = 0; i < sizeof absent / sizeof absent[0]; i++) {
        cfg = relnav_config_default();
        cfg.filter = absent[i];
        char what[64];
        snprintf(what, sizeof what, "relnav_estimator_init, filter %d", (int)absent[i]);
        good &= refused(relnav_estimator_init(storage, sizeof storage, &cfg, &est), what);
    }
    cfg = relnav_config_default();
    cfg.range_bank = 3;
    good &= refused(relnav_estimator_init(storage, sizeof storage, &cfg, &est), "relnav_estimator_init, range_bank 3");
    relnav_hinf_matrices m;
    memset(&m, 0, sizeof m);
    const double x0[6] = {0};
    relnav_hinf_filter *h = NULL;
    good &= refused(relnav_hinf_filter_new(&m, x0, &h), "relnav_hinf_filter_new");
    relnav_hinf_spec spec;
    cfg = relnav_config_default();
    good &= refused(relnav_config_hinf_spec(&cfg, &spec), "relnav_config_hinf_spec");
    relnav_hinf_result result;
    memset(&spec, 0, sizeof spec);
    good &= refused(relnav_hinf_design(&spec, &result), "relnav_hinf_design");
    /* read through a volatile, so that the table and every function in it stay linked */
    void *volatile sink = NULL;
    for (size_t i = 0; i < sizeof every / sizeof every[0]; i++) sink = every[i];
    (void)sink;
    /* (no %zu: newlib's printf, on the bare-metal targets, has none) */
    printf("%lu functions linked\n", (unsigned long)(sizeof every / sizeof every[0]));
    return good ? 0 : 1;
}
