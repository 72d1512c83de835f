// The declared camera and relative-GNSS sensors through the C ABI
// (`relnav_estimator_step_sensors`) against this harness's own truth: the CW closed form
// written here (canonical frame), the GNSS readings and the camera's line of sight formed
// and perturbed here. With GNSS (position every step, velocity every second step) and
// the camera, the EKF and the UKF end well inside one fix's error; the per-step NIS is
// reported for the sensors that gave a reading and NaN for the others; a bad flagged
// reading is refused naming the sensor, with the estimate unchanged; a null reading is
// no reading. With the camera alone and two known burns, a range-parameterised bank of
// EKFs (range_bank) finds the range the prior only knew to 30 %. The H-infinity filter
// designed for the camera and GNSS position and velocity (hinf_sensors = 14) takes the
// same readings (its NIS and range_sigma are NaN: it has no covariance).

#include "check.hpp"

#include <relnav.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kN = 2.0 * kPi / 7200.0;
constexpr int kSteps = 120;
constexpr double kSigGnss = 0.05, kSigVel = 5e-4, kSigCam = 1e-3;

// The CW closed form (x radial, y along-track, z normal) from x0 over t.
std::array<double, 6> cw(const std::array<double, 6>& x0, double t) {
    const double s = std::sin(kN * t), c = std::cos(kN * t);
    const double x = x0[0], y = x0[1], z = x0[2], vx = x0[3], vy = x0[4], vz = x0[5];
    return {
        (4.0 - 3.0 * c) * x + s / kN * vx + 2.0 / kN * (1.0 - c) * vy,
        6.0 * (s - kN * t) * x + y + 2.0 / kN * (c - 1.0) * vx + (4.0 * s - 3.0 * kN * t) / kN * vy,
        c * z + s / kN * vz,
        3.0 * kN * s * x + c * vx + 2.0 * s * vy,
        6.0 * kN * (c - 1.0) * x - 2.0 * s * vx + (4.0 * c - 3.0) * vy,
        -kN * s * z + c * vz,
    };
}

double run(int filter) {
    relnav_config c = relnav_config_default();
    c.filter = filter;
    c.frame = RELNAV_FRAME_RADIAL_ALONG_NORMAL;
    c.mean_motion = kN;
    c.sigma_gnss = kSigGnss;
    c.sigma_gnss_velocity = kSigVel;
    c.sigma_camera = kSigCam;
    c.hinf_sensors = 2 + 4 + 8;
    c.accel_psd = 1e-14;
    for (int i = 0; i < 3; ++i) c.q_pos[i] = c.q_vel[i] = 0.0;
    const std::array<double, 6> x0{500.0, 400.0, 200.0, 0.05, 0.05, 0.05};
    relnav_estimator* est = nullptr;
    CHECK(relnav_estimator_new(&c, &est) == RELNAV_OK);
    std::mt19937_64 rng(35);
    std::normal_distribution<double> g(0.0, 1.0);
    const double thrust[3] = {0.0, 0.0, 0.0};
    double sum = 0.0;
    int count = 0;
    for (int k = 0; k < kSteps; ++k) {
        const auto x = cw(x0, k);
        const double rho = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        const double cam[2] = {std::fmod(std::atan2(x[1], x[0]) + 2.0 * kPi, 2.0 * kPi) + kSigCam * g(rng),
                               std::asin(x[2] / rho) + kSigCam * g(rng)};
        double pos[3], vel[3];
        for (int i = 0; i < 3; ++i) {
            pos[i] = x[static_cast<size_t>(i)] + kSigGnss * g(rng);
            vel[i] = x[static_cast<size_t>(3 + i)] + kSigVel * g(rng);
        }
        const bool with_vel = k % 2 == 0;
        CHECK(relnav_estimator_step_sensors(est, thrust, nullptr, cam, pos, with_vel ? vel : nullptr, 1.0) ==
              RELNAV_OK);
        double nis[4], range_sigma = 0.0;
        CHECK(relnav_estimator_get_sensor_diagnostics(est, nis, &range_sigma) == RELNAV_OK);
        if (filter == RELNAV_FILTER_HINF) {
            for (double v : nis) CHECK(std::isnan(v));
            CHECK(std::isnan(range_sigma));
        } else {
            CHECK(std::isnan(nis[0]) && std::isfinite(nis[1]) && std::isfinite(nis[2]));
            CHECK(std::isfinite(nis[3]) == with_vel);
            CHECK(range_sigma > 0.0 && range_sigma < 1.0);
        }
        double s[6];
        CHECK(relnav_estimator_get_state(est, s) == RELNAV_OK);
        if (k >= kSteps / 2) {
            const auto t1 = cw(x0, k + 1);
            double e2 = 0.0;
            for (int i = 0; i < 3; ++i) e2 += (s[i] - t1[static_cast<size_t>(i)]) * (s[i] - t1[static_cast<size_t>(i)]);
            sum += e2;
            ++count;
        }
    }
    // a bad flagged reading: refused naming the camera, the estimate kept
    double before[6], after[6];
    CHECK(relnav_estimator_get_state(est, before) == RELNAV_OK);
    const double bad[2] = {0.1, 2.0};
    CHECK(relnav_estimator_step_sensors(est, thrust, nullptr, bad, nullptr, nullptr, 1.0) != RELNAV_OK);
    CHECK(std::strstr(relnav_last_error(), "camera") != nullptr);
    CHECK(relnav_estimator_get_state(est, after) == RELNAV_OK);
    CHECK(std::memcmp(before, after, sizeof before) == 0);
    relnav_estimator_free(est);
    return std::sqrt(sum / count);
}

// The CW equations with a thrust acceleration a (canonical frame), one RK4 step of h.
std::array<double, 6> rk4(const std::array<double, 6>& x, const double a[3], double h) {
    auto f = [&](const std::array<double, 6>& y) {
        return std::array<double, 6>{y[3], y[4], y[5], 3.0 * kN * kN * y[0] + 2.0 * kN * y[4] + a[0],
                                     -2.0 * kN * y[3] + a[1], -kN * kN * y[2] + a[2]};
    };
    auto add = [](const std::array<double, 6>& y, const std::array<double, 6>& d, double w) {
        std::array<double, 6> r{};
        for (size_t i = 0; i < 6; ++i) r[i] = y[i] + w * d[i];
        return r;
    };
    const auto k1 = f(x), k2 = f(add(x, k1, h / 2)), k3 = f(add(x, k2, h / 2)), k4 = f(add(x, k3, h));
    std::array<double, 6> r{};
    for (size_t i = 0; i < 6; ++i) r[i] = x[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    return r;
}

// Angles-only acquisition: the camera alone, a V-bar hold estimated 2 km behind with the
// range known to 600 m (sigma_range0), the truth dy metres nearer, two known burns; the
// EKF as a range-parameterised bank of seven (range_bank). Before the burns the range's
// 1-sigma stays near the prior's (angles alone say nothing of it), after them it is below
// a fifth of it and the position error within 3 of it. Returns the final error.
double angles_only(double dy) {
    relnav_config c = relnav_config_default();
    c.filter = RELNAV_FILTER_EKF;
    c.frame = RELNAV_FRAME_RADIAL_ALONG_NORMAL;
    c.mean_motion = kN;
    c.chaser_mass = 100.0;
    const double x0[6] = {0.0, -2000.0, 0.0, 0.0, 0.0, 0.0};
    std::memcpy(c.x0, x0, sizeof x0);
    c.sigma_pos0 = 20.0;
    c.sigma_range0 = 600.0;
    c.sigma_vel0 = 0.01;
    c.sigma_camera = kSigCam;
    c.range_bank = 7;
    c.accel_psd = 1e-14;
    for (int i = 0; i < 3; ++i) c.q_pos[i] = c.q_vel[i] = 0.0;
    relnav_estimator* est = nullptr;
    CHECK(relnav_estimator_new(&c, &est) == RELNAV_OK);
    std::mt19937_64 rng(351);
    std::normal_distribution<double> g(0.0, 1.0);
    std::array<double, 6> x{3.0, -2000.0 + dy, -2.0, 0.0, 0.0, 0.0};
    double sigma_before = 0.0, range_sigma = 0.0, err = 0.0;
    for (int k = 0; k < 2400; ++k) {
        double thrust[3] = {0.0, 0.0, 0.0};
        if (k >= 600 && k < 660) thrust[0] = 0.05;
        if (k >= 1800 && k < 1860) {
            thrust[0] = -0.03;
            thrust[1] = 0.05;
        }
        const double rho = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        const double cam[2] = {std::fmod(std::atan2(x[1], x[0]) + 2.0 * kPi, 2.0 * kPi) + kSigCam * g(rng),
                               std::asin(x[2] / rho) + kSigCam * g(rng)};
        CHECK(relnav_estimator_step_sensors(est, thrust, nullptr, cam, nullptr, nullptr, 1.0) == RELNAV_OK);
        const double a[3] = {thrust[0] / c.chaser_mass, thrust[1] / c.chaser_mass, thrust[2] / c.chaser_mass};
        for (int j = 0; j < 10; ++j) x = rk4(x, a, 0.1);
        double nis[4];
        CHECK(relnav_estimator_get_sensor_diagnostics(est, nis, &range_sigma) == RELNAV_OK);
        CHECK(std::isfinite(nis[1]));
        if (k == 590) sigma_before = range_sigma;
    }
    double s[6];
    CHECK(relnav_estimator_get_state(est, s) == RELNAV_OK);
    for (size_t i = 0; i < 3; ++i) err += (s[i] - x[i]) * (s[i] - x[i]);
    err = std::sqrt(err);
    std::printf("angles only, truth %+.0f m in range: range sigma %.1f m before the burns, %.1f m at the end; "
                "final error %.2f m\n",
                dy, sigma_before, range_sigma, err);
    CHECK(sigma_before > 450.0 && sigma_before < 650.0);
    CHECK(range_sigma < sigma_before / 5.0);
    CHECK(err < 3.0 * range_sigma);
    relnav_estimator_free(est);
    return err;
}

}  // namespace

int main() {
    for (double dy : {-500.0, -150.0, 250.0, 700.0}) angles_only(dy);
    for (int filter : {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF, RELNAV_FILTER_HINF}) {
        const double rms = run(filter);
        std::printf("filter %d: RMS position %.4f m with GNSS and the camera (one fix: %.4f m)\n", filter, rms,
                    std::sqrt(3.0) * kSigGnss);
        CHECK(rms < 0.5 * std::sqrt(3.0) * kSigGnss);
    }
    return harness::finish("capi_sensors");
}
