/* The flight library against the full library, bit for bit: the same program, linked
 * against each (scripts/build-flight.sh), runs every filter the flight library has over
 * the same inputs and prints each final estimate as hexadecimal floats with a checksum of
 * every state and covariance along the way. The two outputs must be identical. */
#include <relnav.h>
#include <math.h>
#include <stdalign.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

static alignas(RELNAV_ESTIMATOR_STORAGE_ALIGN) unsigned char storage[RELNAV_ESTIMATOR_STORAGE_SIZE];

/* FNV-1a over the bytes of n doubles. */
static uint64_t fnv(uint64_t h, const double *v, size_t n) {
    const unsigned char *b = (const unsigned char *)v;
    for (size_t i = 0; i < n * sizeof(double); i++) {
        h ^= b[i];
        h *= 1099511628211ULL;
    }
    return h;
}

static int run(int32_t filter, int32_t noise) {
    relnav_config cfg = relnav_config_default();
    cfg.filter = filter;
    cfg.noise_model = noise;
    relnav_estimator *est = NULL;
    relnav_status st = relnav_estimator_init(storage, sizeof storage, &cfg, &est);
    if (st != RELNAV_OK) {
        printf("filter %d noise %d: init %s: %s\n", (int)filter, (int)noise, relnav_status_string(st), relnav_last_error());
        return 0;
    }
    uint64_t h = 1469598103934665603ULL;
    double x[6], p[36];
    for (int k = 0; k < 400; k++) {
        /* a drifting position with a wobble; a burn between steps 100 and 160 */
        double t = (double)k;
        double r[3] = {400.0 + 0.1 * t + 3.0 * sin(0.05 * t), 500.0 + 0.1 * t, 200.0 + 0.1 * t + 2.0 * cos(0.03 * t)};
        double rho = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        double az = atan2(r[1], r[0]);
        if (az < 0.0) az += 2.0 * M_PI;
        double z[3] = {rho + 0.5 * sin(1.7 * t), az + 1e-3 * cos(2.3 * t), asin(r[2] / rho) + 1e-3 * sin(3.1 * t)};
        double thrust[3] = {0.0, 0.0, 0.0};
        if (k >= 100 && k < 160) thrust[1] = 2.0;
        st = relnav_estimator_step(est, thrust, (k % 7 == 3) ? NULL : z, 1.0);
        if (st != RELNAV_OK) {
            printf("filter %d noise %d: step %d %s: %s\n", (int)filter, (int)noise, k, relnav_status_string(st), relnav_last_error());
            break;
        }
        relnav_estimator_get_state(est, x);
        relnav_estimator_get_covariance(est, p);
        h = fnv(h, x, 6);
        h = fnv(h, p, 36);
    }
    printf("filter %d noise %d: checksum %016llx state", (int)filter, (int)noise, (unsigned long long)h);
    for (int i = 0; i < 6; i++) printf(" %a", x[i]);
    printf("\n");
    relnav_estimator_deinit(est);
    return 1;
}

int main(void) {
    const int32_t filters[] = {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF, RELNAV_FILTER_AQUKF, RELNAV_FILTER_IMM, RELNAV_FILTER_REKF};
    int good = 1;
    for (size_t i = 0; i < sizeof filters / sizeof filters[0]; i++) {
        good &= run(filters[i], RELNAV_NOISE_GAUSSIAN);
        good &= run(filters[i], RELNAV_NOISE_MIXTURE);
    }
    return good ? 0 : 1;
}
