// The declared camera and relative-GNSS sensors through the C ABI
// (`relnav_estimator_step_sensors`) against this harness's own truth: the CW closed form
// written here (canonical frame), the GNSS readings and the camera's line of sight formed
// and perturbed here. With GNSS (position every step, velocity every second step) and
// the camera, the EKF and the UKF end well inside one fix's error; the per-step NIS is
// reported for the sensors that gave a reading and NaN for the others; a bad flagged
// reading is refused naming the sensor, with the estimate unchanged; a null reading is
// no reading.

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
        CHECK(std::isnan(nis[0]) && std::isfinite(nis[1]) && std::isfinite(nis[2]));
        CHECK(std::isfinite(nis[3]) == with_vel);
        CHECK(range_sigma > 0.0 && range_sigma < 1.0);
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

}  // namespace

int main() {
    for (int filter : {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF}) {
        const double rms = run(filter);
        std::printf("filter %d: RMS position %.4f m with GNSS and the camera (one fix: %.4f m)\n", filter, rms,
                    std::sqrt(3.0) * kSigGnss);
        CHECK(rms < 0.5 * std::sqrt(3.0) * kSigGnss);
    }
    return harness::finish("capi_sensors");
}
