/* Stack depth of the flight library's calls, measured (scripts/build-flight.sh): each call
 * runs on a thread of its own whose stack (STACK bytes, a buffer of this program) is first
 * filled with a pattern; the depth is how far below the top the pattern was overwritten.
 * Every filter of the flight library, nominal and adversarial inputs (a dropout, a burn,
 * every sensor at once, a near-zero range, a long step, a saved state restored; frames 1-3,
 * circular and eccentric orbits), and the runtime H-infinity filter; every function of the
 * header is called (the queries, texts and refusals together). Prints one line per call
 * with the deepest use seen, less the thread's own frames, and exits 1 if any exceeds the
 * bound given as the first argument (bytes). A measured depth over these inputs, not a
 * bound over every path. */
#define _GNU_SOURCE
#include <relnav.h>
#include <pthread.h>
#include <stdalign.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define STACK (1024 * 1024)
#define PATTERN 0xA5

static alignas(64) unsigned char stack_mem[STACK];
static alignas(RELNAV_ESTIMATOR_STORAGE_ALIGN) unsigned char storage[RELNAV_ESTIMATOR_STORAGE_SIZE];
static alignas(RELNAV_HINF_FILTER_STORAGE_ALIGN) unsigned char hinf_storage[RELNAV_HINF_FILTER_STORAGE_SIZE];
static uint8_t state_buf[65536];

typedef void (*call_fn)(void);
static call_fn current;

static void *trampoline(void *arg) {
    (void)arg;
    current();
    return NULL;
}

/* Deepest stack use of `f` [bytes] (the thread's own frames included: a few hundred). */
static size_t depth(call_fn f) {
    memset(stack_mem, PATTERN, sizeof stack_mem);
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstack(&attr, stack_mem, sizeof stack_mem);
    current = f;
    pthread_t t;
    if (pthread_create(&t, &attr, trampoline, NULL) != 0) {
        perror("pthread_create");
        exit(2);
    }
    pthread_join(t, NULL);
    pthread_attr_destroy(&attr);
    size_t i = 0;
    while (i < sizeof stack_mem && stack_mem[i] == PATTERN) i++;
    return sizeof stack_mem - i;
}

static relnav_estimator *est;
static relnav_config cfg;
static relnav_status last;
static const double thrust0[3] = {0.0, 0.0, 0.0};
static const double thrust1[3] = {0.0, 2.0, -1.0};
static const double z0[3] = {670.8204, 0.896055, 0.302746};
static const double z_near[3] = {1e-6, 0.5, 0.1};
static const double cam[2] = {0.896055, 0.302746};
static const double gpos[3] = {400.0, 500.0, 200.0};
static const double gvel[3] = {0.1, 0.1, -0.1};
static size_t saved_len;

static void c_init(void) { last = relnav_estimator_init(storage, sizeof storage, &cfg, &est); }
static void c_step(void) { last = relnav_estimator_step(est, thrust0, z0, 1.0); }
static void c_step_dropout(void) { last = relnav_estimator_step(est, thrust1, NULL, 1.0); }
static void c_step_long(void) { last = relnav_estimator_step(est, thrust1, z0, 3000.0); }
static void c_step_near(void) { last = relnav_estimator_step(est, thrust0, z_near, 1.0); }
static void c_step_sensors(void) { last = relnav_estimator_step_sensors(est, thrust1, z0, cam, gpos, gvel, 1.0); }
static void c_predict(void) { last = relnav_estimator_predict(est, thrust1, 1.0); }
static void c_update(void) { last = relnav_estimator_update(est, z0); }
static void c_get(void) {
    double x[6], p[36], s[6], e[12], nu[3], nis, q[3], mu[3];
    relnav_config c;
    last = relnav_estimator_get_state(est, x);
    last = relnav_estimator_get_covariance(est, p);
    last = relnav_estimator_get_sigma(est, s);
    last = relnav_estimator_get_estimate(est, e);
    last = relnav_estimator_get_config(est, &c);
    last = relnav_estimator_get_innovation(est, nu, &nis);
    last = relnav_estimator_get_q_vv(est, q);
    last = relnav_estimator_get_mode_probabilities(est, mu);
    double ess, acc, gamma, h2, diag[8], range_sigma;
    int32_t certified;
    relnav_hinf_design_info info;
    last = relnav_estimator_get_ess(est, &ess);
    last = relnav_estimator_get_pf_acceptance(est, &acc);
    last = relnav_estimator_get_hinf_gamma(est, &gamma);
    last = relnav_estimator_get_hinf_h2_norm(est, &h2);
    last = relnav_estimator_get_hinf_certified(est, &certified);
    last = relnav_estimator_get_hinf_design(est, &info);
    last = relnav_estimator_get_sensor_diagnostics(est, diag, &range_sigma);
}
static void c_save(void) { last = relnav_estimator_save(est, state_buf, sizeof state_buf, &saved_len); }
static void c_restore(void) { last = relnav_estimator_restore(est, state_buf, saved_len); }
static void c_restore_bad(void) {
    state_buf[saved_len / 2] ^= 0x40;
    last = relnav_estimator_restore(est, state_buf, saved_len);
    state_buf[saved_len / 2] ^= 0x40;
}
static void c_reset(void) { last = relnav_estimator_reset(est); }
static void c_validate(void) { last = relnav_config_validate(&cfg); }
static void c_deinit(void) { last = relnav_estimator_deinit(est); }
static void c_nothing(void) { last = RELNAV_OK; }

/* the runtime H-infinity filter: an observer with an output map that is not the identity */
static relnav_hinf_matrices hm;
static relnav_hinf_filter *hf;
static const double hx0[6] = {400.0, 500.0, 200.0, 0.1, 0.1, -0.1};
static const double ha[3] = {0.0, 2e-3, 0.0};
static void h_init(void) { last = relnav_hinf_filter_init(hinf_storage, sizeof hinf_storage, &hm, hx0, &hf); }
static void h_step(void) { last = relnav_hinf_filter_step(hf, gpos, ha); }
static void h_step_dropout(void) { last = relnav_hinf_filter_step(hf, NULL, ha); }
static void h_get(void) {
    double x[6];
    last = relnav_hinf_filter_get_state(hf, x);
}
static void h_deinit(void) { last = relnav_hinf_filter_deinit(hf); }
/* the calls that hold no estimator: queries, texts, the refusals of what the flight
 * library leaves out, the no-op frees */
static void c_other(void) {
    size_t size, align;
    relnav_hinf_spec spec;
    relnav_hinf_result result;
    relnav_estimator *e = NULL;
    relnav_hinf_filter *h = NULL;
    double x0[6] = {0};
    last = relnav_estimator_storage(&size, &align);
    last = relnav_hinf_filter_storage(&size, &align);
    volatile const char *t = relnav_version();
    t = relnav_status_string(RELNAV_ERROR_NUMERICAL);
    t = relnav_hinf_riccati_failure_string(1);
    (void)t;
    last = relnav_estimator_new(&cfg, &e);
    last = relnav_hinf_filter_new(&hm, x0, &h);
    last = relnav_config_hinf_spec(&cfg, &spec);
    memset(&spec, 0, sizeof spec);
    last = relnav_hinf_design(&spec, &result);
    relnav_estimator_free(NULL);
    relnav_hinf_filter_free(NULL);
}

struct call {
    const char *name;
    call_fn f;
    size_t worst;
};

int main(int argc, char **argv) {
    size_t bound = argc > 1 ? strtoul(argv[1], NULL, 10) : 0;
    struct call calls[] = {
        {"relnav_config_validate", c_validate, 0},
        {"relnav_estimator_init", c_init, 0},
        {"relnav_estimator_step", c_step, 0},
        {"relnav_estimator_step (dropout, thrust)", c_step_dropout, 0},
        {"relnav_estimator_step (3000 s)", c_step_long, 0},
        {"relnav_estimator_step (zero range)", c_step_near, 0},
        {"relnav_estimator_step_sensors (all)", c_step_sensors, 0},
        {"relnav_estimator_predict", c_predict, 0},
        {"relnav_estimator_update", c_update, 0},
        {"relnav_estimator_get_*", c_get, 0},
        {"queries, texts, refusals, frees", c_other, 0},
        {"relnav_estimator_save", c_save, 0},
        {"relnav_estimator_restore", c_restore, 0},
        {"relnav_estimator_restore (corrupted)", c_restore_bad, 0},
        {"relnav_estimator_reset", c_reset, 0},
        {"relnav_estimator_deinit", c_deinit, 0},
    };
    const size_t n = sizeof calls / sizeof calls[0];
    const int32_t filters[] = {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF, RELNAV_FILTER_AQUKF, RELNAV_FILTER_IMM, RELNAV_FILTER_REKF};
    const int32_t frames[] = {1, 2, 3};
    for (size_t fi = 0; fi < sizeof filters / sizeof filters[0]; fi++) {
        for (size_t ri = 0; ri < 3; ri++) {
            for (int ecc = 0; ecc < 2; ecc++) {
                cfg = relnav_config_default();
                cfg.filter = filters[fi];
                cfg.frame = frames[ri];
                cfg.noise_model = ecc ? RELNAV_NOISE_MIXTURE : RELNAV_NOISE_GAUSSIAN;
                cfg.eccentricity = ecc ? 0.5 : 0.0;
                for (size_t k = 0; k < n; k++) {
                    size_t d = depth(calls[k].f);
                    if (k == 1 && last != RELNAV_OK) {
                        fprintf(stderr, "init failed for filter %d: %s\n", (int)filters[fi], relnav_last_error());
                        return 2;
                    }
                    if (d > calls[k].worst) calls[k].worst = d;
                }
            }
        }
    }
    struct call hinf_calls[] = {
        {"relnav_hinf_filter_init", h_init, 0},
        {"relnav_hinf_filter_step", h_step, 0},
        {"relnav_hinf_filter_step (dropout)", h_step_dropout, 0},
        {"relnav_hinf_filter_get_state", h_get, 0},
        {"relnav_hinf_filter_deinit", h_deinit, 0},
    };
    const size_t nh = sizeof hinf_calls / sizeof hinf_calls[0];
    memset(&hm, 0, sizeof hm);
    hm.period = 1.0;
    for (int i = 0; i < 6; i++) {
        hm.a_f[7 * i] = 0.5;
        for (int j = 0; j < 6; j++) hm.c_f[6 * i + j] = (i == j) ? 1.0 : 0.01 * (double)(i + j);
    }
    for (int i = 0; i < 3; i++) {
        hm.a_f[6 * i + i + 3] = 1.0;
        hm.b_f[3 * i + i] = 0.5;
        hm.e_f[3 * (i + 3) + i] = 1.0;
    }
    for (size_t k = 0; k < nh; k++) {
        hinf_calls[k].worst = depth(hinf_calls[k].f);
        if (k == 0 && last != RELNAV_OK) {
            fprintf(stderr, "relnav_hinf_filter_init failed: %s\n", relnav_last_error());
            return 2;
        }
    }
    /* the thread's own start-up frames, counted in every figure above: subtracted */
    size_t base = depth(c_nothing);
    size_t worst = 0;
    for (size_t k = 0; k < n; k++) {
        size_t d = calls[k].worst > base ? calls[k].worst - base : 0;
        printf("%-42s %7zu bytes\n", calls[k].name, d);
        if (d > worst) worst = d;
    }
    for (size_t k = 0; k < nh; k++) {
        size_t d = hinf_calls[k].worst > base ? hinf_calls[k].worst - base : 0;
        printf("%-42s %7zu bytes\n", hinf_calls[k].name, d);
        if (d > worst) worst = d;
    }
    printf("deepest: %zu bytes (bound %zu; the thread's own %zu bytes subtracted)\n", worst, bound, base);
    return bound && worst > bound ? 1 : 0;
}
