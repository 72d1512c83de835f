/* The flight library against the full library, bit for bit: the same program, linked
 * against each (scripts/build-flight.sh), runs every filter the flight library has, and
 * the runtime H-infinity filter, over the same inputs and prints each final estimate's
 * bits in hexadecimal with a checksum of every state and covariance along the way. The
 * two outputs must be identical. */
#include <relnav.h>
#include <math.h>
#include <stdalign.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

static alignas(RELNAV_ESTIMATOR_STORAGE_ALIGN) unsigned char storage[RELNAV_ESTIMATOR_STORAGE_SIZE];
static alignas(RELNAV_HINF_FILTER_STORAGE_ALIGN) unsigned char hinf_storage[RELNAV_HINF_FILTER_STORAGE_SIZE];

/* FNV-1a over the bytes of n doubles. */
static uint64_t fnv(uint64_t h, const double *v, size_t n) {
    const unsigned char *b = (const unsigned char *)v;
    for (size_t i = 0; i < n * sizeof(double); i++) {
        h ^= b[i];
        h *= 1099511628211ULL;
    }
    return h;
}

/* Each value's bits in hexadecimal, then a newline: exact, and within what every C
 * library's printf has (newlib's, on the bare-metal targets, has no %a). */
static void print_bits(const double *v, size_t n) {
    for (size_t i = 0; i < n; i++) {
        uint64_t u;
        memcpy(&u, &v[i], sizeof u);
        printf(" %016llx", (unsigned long long)u);
    }
    printf("\n");
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
    print_bits(x, 6);
    relnav_estimator_deinit(est);
    return 1;
}

/* out (r x c) = a (r x n) b (n x c), row-major */
static void matmul(double *out, const double *a, const double *b, int r, int n, int c) {
    for (int i = 0; i < r; i++)
        for (int j = 0; j < c; j++) {
            double v = 0.0;
            for (int k = 0; k < n; k++) v += a[n * i + k] * b[c * k + j];
            out[c * i + j] = v;
        }
}

/* The runtime H-infinity filter with gains loaded as data: an observer of a double
 * integrator (period 1 s, gains 0.5 and 0.1) written in the coordinates x_f = S^-1 x,
 * S = [I 0; 0.2 I I], so that its output map C_F = S is not the identity and starting
 * at x0 inverts it. */
static int run_hinf(void) {
    double a[36] = {0}, b[18] = {0}, e[18] = {0}, s_[36] = {0}, s_inv[36] = {0}, t[36];
    for (int i = 0; i < 3; i++) {
        a[6 * i + i] = 1.0 - 0.5;
        a[6 * i + i + 3] = 1.0;
        a[6 * (i + 3) + i] = -0.1;
        a[6 * (i + 3) + i + 3] = 1.0;
        b[3 * i + i] = 0.5;
        b[3 * (i + 3) + i] = 0.1;
        e[3 * i + i] = 0.5;
        e[3 * (i + 3) + i] = 1.0;
    }
    for (int i = 0; i < 6; i++) s_[7 * i] = s_inv[7 * i] = 1.0;
    for (int i = 0; i < 3; i++) {
        s_[6 * (i + 3) + i] = 0.2;
        s_inv[6 * (i + 3) + i] = -0.2;
    }
    relnav_hinf_matrices m;
    memset(&m, 0, sizeof m);
    m.period = 1.0;
    matmul(t, a, s_, 6, 6, 6);
    matmul(m.a_f, s_inv, t, 6, 6, 6);
    matmul(m.b_f, s_inv, b, 6, 6, 3);
    matmul(m.e_f, s_inv, e, 6, 6, 3);
    memcpy(m.c_f, s_, sizeof s_);
    const double x0[6] = {410.0, 495.0, 205.0, 0.0, 0.1, 0.0};
    relnav_hinf_filter *f = NULL;
    relnav_status st = relnav_hinf_filter_init(hinf_storage, sizeof hinf_storage, &m, x0, &f);
    if (st != RELNAV_OK) {
        printf("hinf: init %s: %s\n", relnav_status_string(st), relnav_last_error());
        return 0;
    }
    uint64_t h = 1469598103934665603ULL;
    double x[6];
    for (int k = 0; k < 400; k++) {
        double t = (double)k;
        double y[3] = {400.0 + 0.1 * t + 0.5 * sin(1.7 * t), 500.0 + 0.1 * t + 0.5 * cos(2.3 * t), 200.0 + 0.1 * t};
        double a[3] = {0.0, (k >= 100 && k < 160) ? 2e-3 : 0.0, 0.0};
        st = relnav_hinf_filter_step(f, (k % 7 == 3) ? NULL : y, a);
        if (st != RELNAV_OK) {
            printf("hinf: step %d %s: %s\n", k, relnav_status_string(st), relnav_last_error());
            break;
        }
        relnav_hinf_filter_get_state(f, x);
        h = fnv(h, x, 6);
    }
    printf("hinf: checksum %016llx state", (unsigned long long)h);
    print_bits(x, 6);
    relnav_hinf_filter_deinit(f);
    return st == RELNAV_OK;
}

int main(void) {
    const int32_t filters[] = {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF, RELNAV_FILTER_AQUKF, RELNAV_FILTER_IMM, RELNAV_FILTER_REKF};
    int good = 1;
    for (size_t i = 0; i < sizeof filters / sizeof filters[0]; i++) {
        good &= run(filters[i], RELNAV_NOISE_GAUSSIAN);
        good &= run(filters[i], RELNAV_NOISE_MIXTURE);
    }
    good &= run_hinf();
    return good ? 0 : 1;
}
