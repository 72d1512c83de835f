// Issue 34: the C ABI on an eccentric orbit against this harness's own truth. Target and
// chaser are integrated here as two point masses around the Earth (RK4 on the 12 inertial
// states, 0.5 s substeps; its own Hill frame, thrust held along the rotating Hill axes),
// the radio measurements formed and perturbed here. The EKF and the UKF with
// `eccentricity` 0.5 stay at the measurement level through perigee; the same filters on the
// CW model (`eccentricity` 0) do not; out-of-domain eccentricities are refused by name.

#include "check.hpp"

#include <relnav.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

using V3 = std::array<double, 3>;
using S12 = std::array<double, 12>;

constexpr double kMu = 3.986004418e14;
constexpr double kPi = 3.14159265358979323846;
constexpr double kPeriod = 16000.0;
constexpr double kE = 0.5;
constexpr double kNu0 = -2.0;
constexpr double kIncl = 30.0 * kPi / 180.0;
constexpr double kDt = 10.0;
constexpr int kSteps = 400;
constexpr double kMass = 100.0;

V3 cross(const V3& a, const V3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 scale(const V3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }

// Rows: radial, along-track (h x r), orbit normal; and the frame's rotation rate.
void hill(const double* target, std::array<V3, 3>& rows, double& rate) {
    const V3 r{target[0], target[1], target[2]}, v{target[3], target[4], target[5]};
    const V3 h = cross(r, v);
    const V3 xr = scale(r, 1.0 / std::sqrt(dot(r, r)));
    const V3 zn = scale(h, 1.0 / std::sqrt(dot(h, h)));
    rows = {xr, cross(zn, xr), zn};
    rate = std::sqrt(dot(h, h)) / dot(r, r);
}

S12 rhs(const S12& y, const V3& accel_hill) {
    std::array<V3, 3> rows{};
    double w = 0.0;
    hill(y.data(), rows, w);
    S12 d{};
    for (int body = 0; body < 2; ++body) {
        const double* s = y.data() + 6 * body;
        const double rn = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
        for (int i = 0; i < 3; ++i) {
            d[static_cast<size_t>(6 * body + i)] = s[3 + i];
            double a = -kMu * s[i] / (rn * rn * rn);
            if (body == 1)
                for (int j = 0; j < 3; ++j) a += rows[static_cast<size_t>(j)][static_cast<size_t>(i)] * accel_hill[static_cast<size_t>(j)];
            d[static_cast<size_t>(6 * body + 3 + i)] = a;
        }
    }
    return d;
}

std::array<double, 6> relative(const S12& y) {
    std::array<V3, 3> rows{};
    double w = 0.0;
    hill(y.data(), rows, w);
    V3 dr{}, dv{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            dr[static_cast<size_t>(i)] += rows[static_cast<size_t>(i)][static_cast<size_t>(j)] * (y[static_cast<size_t>(6 + j)] - y[static_cast<size_t>(j)]);
            dv[static_cast<size_t>(i)] += rows[static_cast<size_t>(i)][static_cast<size_t>(j)] * (y[static_cast<size_t>(9 + j)] - y[static_cast<size_t>(3 + j)]);
        }
    }
    const V3 wxr = cross({0.0, 0.0, w}, dr);
    return {dr[0], dr[1], dr[2], dv[0] - wxr[0], dv[1] - wxr[1], dv[2] - wxr[2]};
}

struct Truth {
    std::vector<std::array<double, 6>> states;
    std::vector<V3> accel;  // held over step k, Hill axes
};

Truth integrate(const std::array<double, 6>& rel0) {
    const double n = 2.0 * kPi / kPeriod;
    const double a = std::cbrt(kMu / (n * n));
    const double p = a * (1.0 - kE * kE);
    const double r = p / (1.0 + kE * std::cos(kNu0));
    const double vs = std::sqrt(kMu / p);
    const V3 pos{r * std::cos(kNu0), r * std::sin(kNu0), 0.0};
    const V3 vel{-vs * std::sin(kNu0), vs * (kE + std::cos(kNu0)), 0.0};
    auto incline = [](const V3& u) {
        return V3{u[0], u[1] * std::cos(kIncl), u[1] * std::sin(kIncl)};
    };
    S12 y{};
    const V3 tp = incline(pos), tv = incline(vel);
    for (int i = 0; i < 3; ++i) {
        y[static_cast<size_t>(i)] = tp[static_cast<size_t>(i)];
        y[static_cast<size_t>(3 + i)] = tv[static_cast<size_t>(i)];
    }
    std::array<V3, 3> rows{};
    double w = 0.0;
    hill(y.data(), rows, w);
    const V3 dr{rel0[0], rel0[1], rel0[2]};
    const V3 wxr = cross({0.0, 0.0, w}, dr);
    const V3 dv{rel0[3] + wxr[0], rel0[4] + wxr[1], rel0[5] + wxr[2]};
    for (int i = 0; i < 3; ++i) {
        double pi = 0.0, vi = 0.0;
        for (int j = 0; j < 3; ++j) {
            pi += rows[static_cast<size_t>(j)][static_cast<size_t>(i)] * dr[static_cast<size_t>(j)];
            vi += rows[static_cast<size_t>(j)][static_cast<size_t>(i)] * dv[static_cast<size_t>(j)];
        }
        y[static_cast<size_t>(6 + i)] = tp[static_cast<size_t>(i)] + pi;
        y[static_cast<size_t>(9 + i)] = tv[static_cast<size_t>(i)] + vi;
    }
    Truth t;
    t.states.push_back(relative(y));
    for (int k = 0; k < kSteps; ++k) {
        const double tk = k * kDt;
        V3 acc{0.0, 0.0, 0.0};
        if (tk >= 300.0 && tk < 360.0) acc = {0.0, 0.05 / kMass, 0.0};
        if (tk >= 1200.0 && tk < 1260.0) acc = {0.02 / kMass, -0.05 / kMass, 0.01 / kMass};
        t.accel.push_back(acc);
        const int sub = 20;
        const double h = kDt / sub;
        for (int j = 0; j < sub; ++j) {
            const S12 k1 = rhs(y, acc);
            S12 tmp{};
            for (size_t i = 0; i < 12; ++i) tmp[i] = y[i] + 0.5 * h * k1[i];
            const S12 k2 = rhs(tmp, acc);
            for (size_t i = 0; i < 12; ++i) tmp[i] = y[i] + 0.5 * h * k2[i];
            const S12 k3 = rhs(tmp, acc);
            for (size_t i = 0; i < 12; ++i) tmp[i] = y[i] + h * k3[i];
            const S12 k4 = rhs(tmp, acc);
            for (size_t i = 0; i < 12; ++i) y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        t.states.push_back(relative(y));
    }
    return t;
}

// RMS position error over the second half of a run through relnav's C ABI (frame 1, the
// canonical frame: measurements and thrust as the truth gives them).
double run(const Truth& truth, int filter, double eccentricity, unsigned seed) {
    relnav_config c = relnav_config_default();
    c.filter = filter;
    c.frame = RELNAV_FRAME_RADIAL_ALONG_NORMAL;
    c.mean_motion = 2.0 * kPi / kPeriod;
    c.eccentricity = eccentricity;
    c.true_anomaly0 = kNu0;
    c.chaser_mass = kMass;
    c.sigma_pos0 = 10.0;
    c.sigma_vel0 = 0.01;
    c.accel_psd = 1e-12;
    for (int i = 0; i < 3; ++i) {
        c.q_pos[i] = 0.0;
        c.q_vel[i] = 0.0;
    }
    const double off[6] = {5.0, -5.0, 3.0, 0.0, 0.0, 0.0};
    for (int i = 0; i < 6; ++i) c.x0[i] = truth.states[0][static_cast<size_t>(i)] + off[i];
    relnav_estimator* est = nullptr;
    CHECK(relnav_estimator_new(&c, &est) == RELNAV_OK);
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    const double sr = c.sigma_range, sa = c.sigma_angle;
    double sum = 0.0;
    int count = 0;
    for (int k = 0; k < kSteps; ++k) {
        const auto& x = truth.states[static_cast<size_t>(k)];
        const double rng_ = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        double az = std::atan2(x[1], x[0]) + sa * g(rng);
        az = std::fmod(az + 4.0 * kPi, 2.0 * kPi);
        const double z[3] = {rng_ + sr * g(rng), az, std::asin(x[2] / rng_) + sa * g(rng)};
        const V3& acc = truth.accel[static_cast<size_t>(k)];
        const double thrust[3] = {acc[0] * kMass, acc[1] * kMass, acc[2] * kMass};
        CHECK(relnav_estimator_step(est, thrust, z, kDt) == RELNAV_OK);
        double s[6];
        CHECK(relnav_estimator_get_state(est, s) == RELNAV_OK);
        if (k + 1 >= kSteps / 2) {
            const auto& t1 = truth.states[static_cast<size_t>(k + 1)];
            double e2 = 0.0;
            for (int i = 0; i < 3; ++i) e2 += (s[i] - t1[static_cast<size_t>(i)]) * (s[i] - t1[static_cast<size_t>(i)]);
            sum += e2;
            ++count;
        }
    }
    relnav_estimator_free(est);
    return std::sqrt(sum / count);
}

}  // namespace

int main() {
    const Truth truth = integrate({30.0, -1000.0, 20.0, 0.0, 0.0, 0.01});
    for (int filter : {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF}) {
        const double ell = run(truth, filter, kE, 34);
        const double cw = run(truth, filter, 0.0, 34);
        std::printf("filter %d: RMS position %.3f m on the elliptic model, %.3f m on CW\n", filter, ell, cw);
        CHECK(ell < 0.5);
        CHECK(cw > 5.0);
    }
    for (double bad : {-0.1, 0.995, 1.0, std::nan("")}) {
        relnav_config c = relnav_config_default();
        c.eccentricity = bad;
        CHECK(relnav_config_validate(&c) != RELNAV_OK);
        CHECK(std::strstr(relnav_last_error(), "eccentricity") != nullptr);
    }
    return harness::finish("capi_eccentric");
}
