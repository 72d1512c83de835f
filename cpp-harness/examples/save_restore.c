/* relnav save and restore: a checkpoint of an estimator, a branch from it, and a refusal. */
#include <relnav.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Ten seconds of paper 000's example from the estimator's current state; the estimate after them. */
static relnav_status ten_steps(relnav_estimator *est, int t0, double out[6]) {
    const double thrust[3] = {0.0, 0.0, 0.0};
    for (int t = t0; t < t0 + 10; ++t) {
        const double z[3] = {670.8204 + 0.01 * t, 0.896055, 0.302746}; /* range [m], azimuth, elevation [rad] */
        relnav_status st = relnav_estimator_step(est, thrust, z, 1.0);
        if (st != RELNAV_OK) return st;
    }
    return relnav_estimator_get_state(est, out);
}

int main(void) {
    relnav_config cfg = relnav_config_default();
    cfg.filter = RELNAV_FILTER_UKF;
    relnav_estimator *est = NULL, *other = NULL;
    uint8_t *buf = NULL;
    double x[6], first[6], again[6];
    size_t len = 0;
    int good = relnav_estimator_new(&cfg, &est) == RELNAV_OK
            && ten_steps(est, 0, x) == RELNAV_OK
            && relnav_estimator_save(est, NULL, 0, &len) == RELNAV_OK /* size query: depends on cfg only */
            && (buf = malloc(len)) != NULL
            && relnav_estimator_save(est, buf, len, &len) == RELNAV_OK  /* checkpoint at t = 10 s */
            && ten_steps(est, 10, first) == RELNAV_OK
            && relnav_estimator_restore(est, buf, len) == RELNAV_OK     /* back to t = 10 s */
            && ten_steps(est, 10, again) == RELNAV_OK;
    if (!good) {
        fprintf(stderr, "relnav: %s\n", relnav_last_error());
    } else {
        printf("state of %zu bytes; continued after restore: %s\n", len,
               memcmp(first, again, sizeof first) == 0 ? "bit for bit" : "DIFFERENT");
        good = memcmp(first, again, sizeof first) == 0;
        cfg.filter = RELNAV_FILTER_EKF; /* another configuration refuses the state, and stays as it was */
        relnav_status st = relnav_estimator_new(&cfg, &other);
        if (st == RELNAV_OK) st = relnav_estimator_restore(other, buf, len);
        printf("into an EKF: %s (%s)\n", relnav_status_string(st), relnav_last_error());
        good = good && st == RELNAV_ERROR_INVALID_STATE;
    }
    free(buf);
    relnav_estimator_free(other);
    relnav_estimator_free(est);
    return good ? 0 : 1;
}
