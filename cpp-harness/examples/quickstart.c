/* relnav quickstart: one EKF step of paper 000's example through the C ABI. The estimator
 * lives in static storage (relnav_estimator_init): no heap, so the same program links
 * against the full library and the flight library (scripts/build-flight.sh). */
#include <relnav.h>
#include <stdalign.h>
#include <stdio.h>

/* Print the reason of a failed call; returns 1 on success, 0 on failure. */
static int ok(relnav_status st, const char *what) {
    if (st == RELNAV_OK) return 1;
    fprintf(stderr, "%s: %s: %s\n", what, relnav_status_string(st), relnav_last_error());
    return 0;
}

static alignas(RELNAV_ESTIMATOR_STORAGE_ALIGN) unsigned char storage[RELNAV_ESTIMATOR_STORAGE_SIZE];

int main(void) {
    relnav_config cfg = relnav_config_default(); /* paper 000: frame 2, EKF, 7200 s orbit */
    relnav_estimator *est = NULL;
    if (!ok(relnav_estimator_init(storage, sizeof storage, &cfg, &est), "relnav_estimator_init")) return 1;

    const double thrust[3] = {0.0, 0.0, 0.0};          /* [N], held constant over the step */
    const double z[3] = {670.8204, 0.896055, 0.302746}; /* range [m], azimuth, elevation [rad] at t = 0 */
    double x[6], sigma[6];
    int good = ok(relnav_estimator_step(est, thrust, z, 1.0), "relnav_estimator_step") /* update, then predict 1 s */
            && ok(relnav_estimator_get_state(est, x), "relnav_estimator_get_state")
            && ok(relnav_estimator_get_sigma(est, sigma), "relnav_estimator_get_sigma");
    if (good) {
        printf("relnav %s, estimate at t = 1 s:\n", relnav_version());
        printf("  position [m]   %9.3f %9.3f %9.3f  (1 sigma %.3f %.3f %.3f)\n", x[0], x[1], x[2], sigma[0], sigma[1], sigma[2]);
        printf("  velocity [m/s] %9.5f %9.5f %9.5f  (1 sigma %.5f %.5f %.5f)\n", x[3], x[4], x[5], sigma[3], sigma[4], sigma[5]);
    }
    relnav_estimator_deinit(est);
    return good ? 0 : 1;
}
