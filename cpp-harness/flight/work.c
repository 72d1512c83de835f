/* Work per step of the flight library's filters, in instructions (scripts/build-flight.sh
 * runs it under valgrind --tool=callgrind --collect-atstart=no): each measured call is
 * collected alone and dumped with its label, "filter/orbit/kind"; the script reads each
 * dump's total and prints, per filter, the median of the nominal steps and the worst step
 * of every kind. Outside callgrind the requests do nothing and the program just runs. */
#include <relnav.h>
#include <math.h>
#include <stdalign.h>
#include <stdio.h>
#include <valgrind/callgrind.h>

static alignas(RELNAV_ESTIMATOR_STORAGE_ALIGN) unsigned char storage[RELNAV_ESTIMATOR_STORAGE_SIZE];

/* One step of `kind`, measured. */
static void measured(const char *label, relnav_estimator *est, const double *thrust, const double *z,
                     const double *cam, const double *gpos, const double *gvel, double dt) {
    CALLGRIND_ZERO_STATS;
    CALLGRIND_TOGGLE_COLLECT;
    relnav_status st = (cam || gpos || gvel) ? relnav_estimator_step_sensors(est, thrust, z, cam, gpos, gvel, dt)
                                             : relnav_estimator_step(est, thrust, z, dt);
    CALLGRIND_TOGGLE_COLLECT;
    CALLGRIND_DUMP_STATS_AT(label);
    (void)st;
}

/* Paper 000's geometry drifting slowly: a radio reading at step k. */
static void reading(int k, double z[3]) {
    double t = (double)k;
    double r[3] = {400.0 + 0.1 * t, 500.0 + 0.1 * t, 200.0 - 0.1 * t};
    double rho = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    double az = atan2(r[1], r[0]);
    if (az < 0.0) az += 2.0 * M_PI;
    z[0] = rho + 0.3 * sin(1.3 * t);
    z[1] = az + 1e-3 * cos(2.1 * t);
    z[2] = asin(r[2] / rho) + 1e-3 * sin(2.9 * t);
}

int main(void) {
    const int32_t filters[] = {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF, RELNAV_FILTER_AQUKF, RELNAV_FILTER_IMM, RELNAV_FILTER_REKF};
    const char *names[] = {"ekf", "ukf", "aqukf", "imm", "rekf"};
    const double zero[3] = {0.0, 0.0, 0.0}, burn[3] = {0.0, 2.0, -1.0}, huge[3] = {1e6, -1e6, 1e6};
    const double cam[2] = {0.9, 0.3}, gpos[3] = {400.0, 500.0, 200.0}, gvel[3] = {0.1, 0.1, -0.1};
    const double z_near[3] = {1e-9, 0.5, 0.1}, z_outlier[3] = {5000.0, 3.0, -1.2}, z_pole[3] = {700.0, 0.0, 1.5707963267948966};
    char label[96];
    for (size_t f = 0; f < sizeof filters / sizeof filters[0]; f++) {
        for (int ecc = 0; ecc < 2; ecc++) {
            const char *orbit = ecc ? "e0.5" : "circular";
            relnav_config cfg = relnav_config_default();
            cfg.filter = filters[f];
            cfg.eccentricity = ecc ? 0.5 : 0.0;
            cfg.noise_model = RELNAV_NOISE_MIXTURE;
            relnav_estimator *est = NULL;
            if (relnav_estimator_init(storage, sizeof storage, &cfg, &est) != RELNAV_OK) {
                fprintf(stderr, "%s %s: %s\n", names[f], orbit, relnav_last_error());
                return 1;
            }
            double z[3];
            int k = 0;
            for (; k < 20; k++) {
                reading(k, z);
                relnav_estimator_step(est, zero, z, 1.0);
            }
#define STEP(kind, thrust, zz, c, gp, gv, dt)                                             \
    do {                                                                                 \
        snprintf(label, sizeof label, "%s/%s/%s", names[f], orbit, kind);                \
        measured(label, est, thrust, zz, c, gp, gv, dt);                                 \
    } while (0)
            for (int i = 0; i < 40; i++, k++) {
                reading(k, z);
                STEP("nominal", zero, z, NULL, NULL, NULL, 1.0);
            }
            for (int i = 0; i < 3; i++, k++) {
                reading(k, z);
                STEP("burn", burn, z, NULL, NULL, NULL, 1.0);
                STEP("dropout", burn, NULL, NULL, NULL, NULL, 1.0);
                STEP("every sensor", zero, z, cam, gpos, gvel, 1.0);
                STEP("outlier", zero, z_outlier, NULL, NULL, NULL, 1.0);
                STEP("pole", zero, z_pole, NULL, NULL, NULL, 1.0);
                STEP("zero range", zero, z_near, NULL, NULL, NULL, 1.0);
                STEP("huge thrust", huge, z, NULL, NULL, NULL, 1.0);
                STEP("10 s step", zero, z, NULL, NULL, NULL, 10.0);
                STEP("3000 s step", zero, z, NULL, NULL, NULL, 3000.0);
                relnav_estimator_reset(est);
                for (int w = 0; w < 5; w++, k++) {
                    reading(k, z);
                    relnav_estimator_step(est, zero, z, 1.0);
                }
            }
            relnav_estimator_deinit(est);
        }
    }
    return 0;
}
