// Test (c): the error contract of the relnav C ABI. Every null pointer argument, non-finite
// inputs and configuration fields, bad step sizes and masses, unknown and unimplemented
// codes, and the singular (zero-range) geometry: each call must return the documented
// status, leave a fresh non-empty relnav_last_error() message, never crash, and leave the
// estimator exactly as it was (checked bitwise, and against a twin that never saw the
// failing calls).

#include "check.hpp"

#include <relnav.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <vector>

using namespace harness;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
const double kNonFinite[] = {kNaN, kInf, -kInf};

int g_cases = 0;

std::string last_error() {
    const char* m = relnav_last_error();
    return m ? std::string(m) : std::string("<NULL>");
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

std::string fmt(double v) {
    char b[64];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

// Everything observable about an estimator, compared bitwise (NaN-safe).
struct Snapshot {
    double state[6];
    double cov[36];
    double sigma[6];
    double innov[3];
    double nis;
    bool operator==(const Snapshot& o) const {
        return std::memcmp(state, o.state, sizeof state) == 0 && std::memcmp(cov, o.cov, sizeof cov) == 0 &&
               std::memcmp(sigma, o.sigma, sizeof sigma) == 0 && std::memcmp(innov, o.innov, sizeof innov) == 0 &&
               std::memcmp(&nis, &o.nis, sizeof nis) == 0;
    }
};

Snapshot snapshot(const relnav_estimator* e) {
    Snapshot s;
    std::memset(&s, 0, sizeof s);
    CHECK(relnav_estimator_get_state(e, s.state) == RELNAV_OK);
    CHECK(relnav_estimator_get_covariance(e, s.cov) == RELNAV_OK);
    CHECK(relnav_estimator_get_sigma(e, s.sigma) == RELNAV_OK);
    CHECK(relnav_estimator_get_innovation(e, s.innov, &s.nis) == RELNAV_OK);
    return s;
}

// Two different known failures, used to show that the call under test writes its own message.
std::string prime(int which) {
    if (which == 0) {
        CHECK(relnav_config_validate(nullptr) == RELNAV_ERROR_NULL_POINTER);
    } else {
        relnav_config c = relnav_config_default();
        c.sigma_vel0 = -123.456;
        CHECK(relnav_config_validate(&c) == RELNAV_ERROR_INVALID_ARGUMENT);
    }
    return last_error();
}

// Run `call` (which must fail with `expected`) twice, after two different primed messages:
// both runs give `expected` and the same non-empty message, different from the primes,
// containing `keyword` (case-insensitive) if given; `est` (if any) is unchanged.
void expect_fail(const std::string& name, relnav_status expected, const std::function<relnav_status()>& call,
                 const relnav_estimator* est = nullptr, const std::string& keyword = "") {
    ++g_cases;
    Snapshot before{};
    if (est) before = snapshot(est);
    const std::string p0 = prime(0);
    const relnav_status s0 = call();
    const std::string m0 = last_error();
    const std::string p1 = prime(1);
    const relnav_status s1 = call();
    const std::string m1 = last_error();
    std::printf("  %-58s -> %d (%s): %s\n", name.c_str(), static_cast<int>(s0), relnav_status_string(s0), m0.c_str());
    CHECK_MSG(s0 == expected && s1 == expected,
              name + ": expected status " + std::to_string(static_cast<int>(expected)) + ", got " +
                  std::to_string(static_cast<int>(s0)) + " / " + std::to_string(static_cast<int>(s1)));
    CHECK_MSG(!m0.empty() && m0 != "<NULL>", name + ": empty relnav_last_error()");
    // The primes differ, so equal messages after both calls prove the call wrote its own.
    CHECK(p0 != p1);
    CHECK_MSG(!(m0 == p0 && m1 == p1), name + ": relnav_last_error() was not updated by the failing call");
    CHECK_MSG(m0 == m1, name + ": message differs between identical calls: '" + m0 + "' vs '" + m1 + "'");
    if (!keyword.empty())
        CHECK_MSG(lower(m0).find(lower(keyword)) != std::string::npos,
                  name + ": message '" + m0 + "' does not mention '" + keyword + "'");
    if (est) CHECK_MSG(snapshot(est) == before, name + ": estimator changed by a failing call");
}

void check_static_functions() {
    std::printf("static functions\n");
    // Before any failure the message is the empty string (not NULL).
    const char* m = relnav_last_error();
    CHECK(m != nullptr);
    CHECK(m != nullptr && m[0] == '\0');

    const char* v = relnav_version();
    CHECK(v != nullptr && std::strlen(v) >= 5);
    int a = -1, b = -1, c = -1;
    CHECK(v != nullptr && std::sscanf(v, "%d.%d.%d", &a, &b, &c) == 3 && a >= 0 && b >= 0 && c >= 0);
    std::printf("  relnav_version() = %s\n", v ? v : "<NULL>");

    std::vector<std::string> names;
    for (int s = 0; s <= 8; ++s) {
        const char* n = relnav_status_string(s);
        CHECK(n != nullptr && n[0] != '\0');
        if (n) {
            CHECK(std::string(n) != "unknown status");
            names.emplace_back(n);
        }
    }
    std::sort(names.begin(), names.end());
    CHECK(std::unique(names.begin(), names.end()) == names.end());
    for (int s : {-1, 9, 1000, INT_MIN, INT_MAX}) {
        const char* n = relnav_status_string(s);
        CHECK(n != nullptr && std::string(n) == "unknown status");
    }
    CHECK(relnav_status_string(RELNAV_OK) == std::string("ok"));

    // The message is per thread: a failure on another thread does not touch ours, and a
    // successful call leaves the last message in place.
    const std::string mine = prime(1);
    std::string theirs;
    std::thread th([&theirs] {
        const char* t0 = relnav_last_error();
        CHECK(t0 != nullptr && t0[0] == '\0');
        CHECK(relnav_config_validate(nullptr) == RELNAV_ERROR_NULL_POINTER);
        theirs = relnav_last_error();
    });
    th.join();
    CHECK(!theirs.empty() && theirs != mine);
    CHECK(last_error() == mine);
    relnav_config ok_cfg = relnav_config_default();
    CHECK(relnav_config_validate(&ok_cfg) == RELNAV_OK);
    CHECK(last_error() == mine);
}

// An estimator that has seen a few measurements (non-trivial state, covariance, innovation).
relnav_estimator* make_estimator(const relnav_config& cfg, int steps) {
    relnav_estimator* e = nullptr;
    CHECK(relnav_estimator_new(&cfg, &e) == RELNAV_OK && e != nullptr);
    const double u[3] = {0.5, -0.25, 0.1};
    for (int k = 0; k < steps && e; ++k) {
        const double z[3] = {670.0 + 0.1 * k, 0.8960 + 1e-5 * k, 0.3027 - 1e-5 * k};
        CHECK(relnav_estimator_step(e, u, z, 1.0) == RELNAV_OK);
    }
    return e;
}

void check_null_pointers(relnav_estimator* est) {
    std::printf("null pointers\n");
    const relnav_config cfg = relnav_config_default();
    const double u[3] = {0.0, 0.0, 0.0};
    const double z[3] = {670.0, 0.896, 0.3027};
    double out6[6], out36[36], innov[3], nis = 0.0;
    relnav_config cout{};
    constexpr auto NP = RELNAV_ERROR_NULL_POINTER;

    expect_fail("config_validate(NULL)", NP, [] { return relnav_config_validate(nullptr); }, nullptr, "config");
    relnav_estimator* out = reinterpret_cast<relnav_estimator*>(&nis);  // any non-null sentinel
    expect_fail("estimator_new(NULL, &out)", NP, [&] { return relnav_estimator_new(nullptr, &out); }, nullptr, "config");
    CHECK_MSG(out == nullptr, "estimator_new must set *out to NULL on error");
    expect_fail("estimator_new(&cfg, NULL)", NP, [&] { return relnav_estimator_new(&cfg, nullptr); }, nullptr, "out");
    expect_fail("estimator_new(NULL, NULL)", NP, [&] { return relnav_estimator_new(nullptr, nullptr); });

    expect_fail("predict(NULL, thrust, 1)", NP, [&] { return relnav_estimator_predict(nullptr, u, 1.0); }, est, "estimator");
    expect_fail("predict(est, NULL, 1)", NP, [&] { return relnav_estimator_predict(est, nullptr, 1.0); }, est, "thrust");
    expect_fail("update(NULL, z)", NP, [&] { return relnav_estimator_update(nullptr, z); }, est, "estimator");
    expect_fail("update(est, NULL)", NP, [&] { return relnav_estimator_update(est, nullptr); }, est, "z");
    expect_fail("step(NULL, thrust, z, 1)", NP, [&] { return relnav_estimator_step(nullptr, u, z, 1.0); }, est, "estimator");
    expect_fail("step(NULL, thrust, NULL, 1)", NP, [&] { return relnav_estimator_step(nullptr, u, nullptr, 1.0); }, est, "estimator");
    expect_fail("step(est, NULL, z, 1)", NP, [&] { return relnav_estimator_step(est, nullptr, z, 1.0); }, est, "thrust");
    expect_fail("step(est, NULL, NULL, 1)", NP, [&] { return relnav_estimator_step(est, nullptr, nullptr, 1.0); }, est, "thrust");

    // Getters: a null estimator must not touch the output buffer.
    const double sentinel = -777.0;
    std::fill(std::begin(out6), std::end(out6), sentinel);
    expect_fail("get_state(NULL, out)", NP, [&] { return relnav_estimator_get_state(nullptr, out6); }, est, "estimator");
    CHECK(std::all_of(std::begin(out6), std::end(out6), [&](double d) { return d == sentinel; }));
    expect_fail("get_state(est, NULL)", NP, [&] { return relnav_estimator_get_state(est, nullptr); }, est, "out");
    std::fill(std::begin(out36), std::end(out36), sentinel);
    expect_fail("get_covariance(NULL, out)", NP, [&] { return relnav_estimator_get_covariance(nullptr, out36); }, est, "estimator");
    CHECK(std::all_of(std::begin(out36), std::end(out36), [&](double d) { return d == sentinel; }));
    expect_fail("get_covariance(est, NULL)", NP, [&] { return relnav_estimator_get_covariance(est, nullptr); }, est, "out");
    std::fill(std::begin(out6), std::end(out6), sentinel);
    expect_fail("get_sigma(NULL, out)", NP, [&] { return relnav_estimator_get_sigma(nullptr, out6); }, est, "estimator");
    CHECK(std::all_of(std::begin(out6), std::end(out6), [&](double d) { return d == sentinel; }));
    expect_fail("get_sigma(est, NULL)", NP, [&] { return relnav_estimator_get_sigma(est, nullptr); }, est, "out");
    expect_fail("reset(NULL)", NP, [&] { return relnav_estimator_reset(nullptr); }, est, "estimator");
    expect_fail("get_config(NULL, &cfg)", NP, [&] { return relnav_estimator_get_config(nullptr, &cout); }, est, "estimator");
    expect_fail("get_config(est, NULL)", NP, [&] { return relnav_estimator_get_config(est, nullptr); }, est, "out");
    expect_fail("get_innovation(NULL, innov, &nis)", NP, [&] { return relnav_estimator_get_innovation(nullptr, innov, &nis); }, est, "estimator");
    expect_fail("get_innovation(est, NULL, &nis)", NP, [&] { return relnav_estimator_get_innovation(est, nullptr, &nis); }, est, "innovation");
    expect_fail("get_innovation(est, innov, NULL)", NP, [&] { return relnav_estimator_get_innovation(est, innov, nullptr); }, est, "nis");
    expect_fail("get_innovation(est, NULL, NULL)", NP, [&] { return relnav_estimator_get_innovation(est, nullptr, nullptr); }, est);

    relnav_estimator_free(nullptr);  // documented no-op
    ++g_cases;
    std::printf("  relnav_estimator_free(NULL): ok\n");
}

void check_non_finite_inputs(relnav_estimator* est) {
    std::printf("non-finite inputs, bad step sizes\n");
    constexpr auto IA = RELNAV_ERROR_INVALID_ARGUMENT;
    const double z_ok[3] = {670.0, 0.896, 0.3027};
    for (int i = 0; i < 3; ++i) {
        for (double bad : kNonFinite) {
            double u[3] = {0.1, 0.2, 0.3};
            u[i] = bad;
            const std::string tag = "thrust[" + std::to_string(i) + "]=" + fmt(bad);
            expect_fail("predict " + tag, IA, [&] { return relnav_estimator_predict(est, u, 1.0); }, est, "thrust");
            expect_fail("step " + tag + " with z", IA, [&] { return relnav_estimator_step(est, u, z_ok, 1.0); }, est, "thrust");
            expect_fail("step " + tag + " without z", IA, [&] { return relnav_estimator_step(est, u, nullptr, 1.0); }, est, "thrust");
            double z[3] = {670.0, 0.896, 0.3027};
            z[i] = bad;
            const double u0[3] = {0.0, 0.0, 0.0};
            const std::string ztag = "z[" + std::to_string(i) + "]=" + fmt(bad);
            expect_fail("update " + ztag, IA, [&] { return relnav_estimator_update(est, z); }, est, "measurement");
            expect_fail("step " + ztag, IA, [&] { return relnav_estimator_step(est, u0, z, 1.0); }, est, "measurement");
        }
    }
    const double u0[3] = {0.0, 0.0, 0.0};
    for (double dt : {0.0, -0.0, -1.0, -1e-300, kNaN, kInf, -kInf}) {
        const std::string tag = "dt=" + fmt(dt);
        expect_fail("predict " + tag, IA, [&] { return relnav_estimator_predict(est, u0, dt); }, est);
        expect_fail("step " + tag + " with z", IA, [&] { return relnav_estimator_step(est, u0, z_ok, dt); }, est);
        expect_fail("step " + tag + " without z", IA, [&] { return relnav_estimator_step(est, u0, nullptr, dt); }, est);
    }
    // Several faults at once: still an error, still nothing changes.
    const double ubad[3] = {kNaN, kInf, -kInf};
    const double zbad[3] = {kNaN, kNaN, kNaN};
    expect_fail("step with everything non-finite", IA, [&] { return relnav_estimator_step(est, ubad, zbad, kNaN); }, est);
}

using Mutator = std::function<void(relnav_config&)>;

// Configuration checks through both relnav_config_validate and relnav_estimator_new.
void expect_config_fail(const std::string& name, relnav_status expected, const Mutator& mutate,
                        const std::string& keyword) {
    relnav_config c = relnav_config_default();
    mutate(c);
    expect_fail("config_validate " + name, expected, [&] { return relnav_config_validate(&c); }, nullptr, keyword);
    relnav_estimator* out = reinterpret_cast<relnav_estimator*>(&c);  // non-null sentinel
    expect_fail("estimator_new " + name, expected, [&] { return relnav_estimator_new(&c, &out); }, nullptr, keyword);
    CHECK_MSG(out == nullptr, name + ": *out not NULL after a failed relnav_estimator_new");
    if (out != nullptr && out != reinterpret_cast<relnav_estimator*>(&c)) relnav_estimator_free(out);
}

void expect_config_ok(const std::string& name, const Mutator& mutate) {
    ++g_cases;
    relnav_config c = relnav_config_default();
    mutate(c);
    const relnav_status v = relnav_config_validate(&c);
    CHECK_MSG(v == RELNAV_OK, name + ": valid config rejected: " + last_error());
    relnav_estimator* e = nullptr;
    const relnav_status s = relnav_estimator_new(&c, &e);
    CHECK_MSG(s == RELNAV_OK && e != nullptr, name + ": relnav_estimator_new failed: " + last_error());
    if (e) {
        const double u[3] = {1.0, -1.0, 0.5};
        const double z[3] = {670.8, 0.896, 0.3027};
        CHECK_MSG(relnav_estimator_step(e, u, z, 1.0) == RELNAV_OK, name + ": step failed: " + last_error());
        double x[6];
        CHECK(relnav_estimator_get_state(e, x) == RELNAV_OK);
        CHECK_MSG(std::all_of(std::begin(x), std::end(x), [](double d) { return std::isfinite(d); }),
                  name + ": non-finite state");
        relnav_estimator_free(e);
    }
    std::printf("  %-58s -> ok\n", name.c_str());
}

void check_config() {
    std::printf("configuration\n");
    constexpr auto IA = RELNAV_ERROR_INVALID_ARGUMENT;
    struct Field {
        const char* name;
        double relnav_config::*member;
        bool strictly_positive;
    };
    const Field scalars[] = {
        {"mean_motion", &relnav_config::mean_motion, true},
        {"chaser_mass", &relnav_config::chaser_mass, true},
        {"sigma_range", &relnav_config::sigma_range, true},
        {"sigma_angle", &relnav_config::sigma_angle, true},
        {"sigma_pos0", &relnav_config::sigma_pos0, true},
        {"sigma_vel0", &relnav_config::sigma_vel0, true},
        {"accel_psd", &relnav_config::accel_psd, false},
    };
    for (const Field& f : scalars) {
        std::vector<double> bad = {kNaN, kInf, -kInf, -1.0, -1e-300};
        if (f.strictly_positive) bad.push_back(0.0);
        for (double v : bad)
            expect_config_fail(std::string(f.name) + "=" + fmt(v), IA,
                               [&](relnav_config& c) { c.*f.member = v; }, f.name);
    }
    const char* axes[3] = {"x", "y", "z"};
    const char* x0_names[6] = {"x0", "y0", "z0", "vx0", "vy0", "vz0"};
    for (int i = 0; i < 6; ++i)
        for (double v : kNonFinite)
            expect_config_fail(std::string(x0_names[i]) + "=" + fmt(v), IA, [&](relnav_config& c) { c.x0[i] = v; },
                               x0_names[i]);
    for (int i = 0; i < 3; ++i)
        for (double v : {kNaN, kInf, -kInf, -1.0}) {
            const std::string qp = std::string("q_pos_") + axes[i], qv = std::string("q_vel_") + axes[i];
            expect_config_fail(qp + "=" + fmt(v), IA, [&](relnav_config& c) { c.q_pos[i] = v; }, qp);
            expect_config_fail(qv + "=" + fmt(v), IA, [&](relnav_config& c) { c.q_vel[i] = v; }, qv);
        }
    // UKF parameters (checked when the UKF is selected).
    for (double v : {kNaN, kInf, -kInf, 0.0, -1.0})
        expect_config_fail("ukf ukf_alpha=" + fmt(v), IA,
                           [&](relnav_config& c) { c.filter = RELNAV_FILTER_UKF; c.ukf_alpha = v; }, "ukf");
    for (double v : kNonFinite) {
        expect_config_fail("ukf ukf_beta=" + fmt(v), IA,
                           [&](relnav_config& c) { c.filter = RELNAV_FILTER_UKF; c.ukf_beta = v; }, "ukf");
        expect_config_fail("ukf ukf_kappa=" + fmt(v), IA,
                           [&](relnav_config& c) { c.filter = RELNAV_FILTER_UKF; c.ukf_kappa = v; }, "ukf");
    }
    for (double v : {-6.0, -7.0})  // alpha^2 (6 + kappa) must be > 0
        expect_config_fail("ukf ukf_kappa=" + fmt(v), IA,
                           [&](relnav_config& c) { c.filter = RELNAV_FILTER_UKF; c.ukf_kappa = v; }, "kappa");

    // Unknown codes.
    for (int v : {0, -1, 12, 100, INT_MIN, INT_MAX})
        expect_config_fail("filter=" + std::to_string(v), IA, [&](relnav_config& c) { c.filter = v; }, "filter");
    for (int v : {0, -1, 4, 100, INT_MIN, INT_MAX})
        expect_config_fail("frame=" + std::to_string(v), IA, [&](relnav_config& c) { c.frame = v; }, "frame");
    for (int v : {0, -1, 3, 100, INT_MIN, INT_MAX})
        expect_config_fail("discretization=" + std::to_string(v), IA, [&](relnav_config& c) { c.discretization = v; },
                           "discretization");
    // H-infinity design inputs out of their domain.
    expect_config_fail("filter=9, hinf_period=-1", IA,
                       [&](relnav_config& c) { c.filter = RELNAV_FILTER_HINF; c.hinf_period = -1.0; }, "period");
    // Issue 12: the AQUKF's adaptation law and gate, the IMM's modes (code 10).
    for (int v : {0, 3, -1})
        expect_config_fail("aq_law=" + std::to_string(v), IA, [&](relnav_config& c) { c.aq_law = v; }, "aq_law");
    for (int v : {0, 129, -5})
        expect_config_fail("aq_gate_window=" + std::to_string(v), IA, [&](relnav_config& c) { c.aq_gate_window = v; },
                           "aq_gate_window");
    for (double v : {0.0, 1.0, kNaN})
        expect_config_fail("aq_gate_quantile=" + fmt(v), IA, [&](relnav_config& c) { c.aq_gate_quantile = v; },
                           "aq_gate_quantile");
    for (int v : {1, 4, -1})
        expect_config_fail("imm_modes=" + std::to_string(v), IA,
                           [&](relnav_config& c) { c.filter = RELNAV_FILTER_IMM; c.imm_modes = v; }, "imm_modes");
    for (double v : {-1e-6, kNaN, kInf})
        expect_config_fail("imm_accel_psd[1]=" + fmt(v), IA, [&](relnav_config& c) { c.imm_accel_psd[1] = v; },
                           "imm_accel_psd_2");
    for (double v : {0.0, 1.0, kNaN})
        expect_config_fail("imm_p_stay[2]=" + fmt(v), IA, [&](relnav_config& c) { c.imm_p_stay[2] = v; },
                           "imm_p_stay_3");
    // Particle-filter and noise-model fields: out of their domain, named in the message.
    for (int v : {0, -1, 2000001, INT_MIN})
        expect_config_fail("particles=" + std::to_string(v), IA, [&](relnav_config& c) { c.particles = v; },
                           "particles");
    for (int v : {0, 6, 7, INT_MIN})
        expect_config_fail("resampler=" + std::to_string(v), IA, [&](relnav_config& c) { c.resampler = v; },
                           "resampler");
    for (double v : {0.0, -0.5, 1.5, kNaN, kInf})
        expect_config_fail("resample_threshold=" + fmt(v), IA,
                           [&](relnav_config& c) { c.resample_threshold = v; }, "resample_threshold");
    for (int v : {0, 4})
        expect_config_fail("noise_model=" + std::to_string(v), IA, [&](relnav_config& c) { c.noise_model = v; },
                           "noise_model");
    for (double v : {1.0, -0.1, kNaN})
        expect_config_fail("noise_zeta=" + fmt(v), IA, [&](relnav_config& c) { c.noise_zeta = v; }, "noise_zeta");
    for (double v : {0.5, kInf, kNaN})
        expect_config_fail("noise_scale=" + fmt(v), IA, [&](relnav_config& c) { c.noise_scale = v; }, "noise_scale");
    for (double v : {2.0, 1.0, kNaN})
        expect_config_fail("noise_dof=" + fmt(v), IA, [&](relnav_config& c) { c.noise_dof = v; }, "noise_dof");
    // Filter 3 (AQUKF, paper 001) and its fields.
    expect_config_ok("filter=3", [](relnav_config& c) { c.filter = RELNAV_FILTER_AQUKF; });
    for (int v : {0, -1, 513, INT_MIN})
        expect_config_fail("window=" + std::to_string(v), IA, [&](relnav_config& c) { c.window = v; }, "window");
    for (double v : {-1e-9, kNaN})
        expect_config_fail("q_vv_floor=" + fmt(v), IA, [&](relnav_config& c) { c.q_vv_floor = v; }, "q_vv_floor");
    for (double v : {0.0, kInf, kNaN})
        expect_config_fail("q_vv_ceiling=" + fmt(v), IA, [&](relnav_config& c) { c.q_vv_ceiling = v; },
                           "q_vv_ceiling");
    {
        // relnav_estimator_get_q_vv: the initial q_vel for the AQUKF, NaN for the EKF,
        // a null output pointer refused.
        for (int f : {RELNAV_FILTER_AQUKF, RELNAV_FILTER_EKF}) {
            relnav_config c = relnav_config_default();
            c.filter = f;
            relnav_estimator* e = nullptr;
            CHECK(relnav_estimator_new(&c, &e) == RELNAV_OK);
            double q[3] = {0.0, 0.0, 0.0};
            CHECK(relnav_estimator_get_q_vv(e, q) == RELNAV_OK);
            for (int i = 0; i < 3; ++i)
                CHECK(f == RELNAV_FILTER_AQUKF ? q[i] == c.q_vel[i] : std::isnan(q[i]));
            CHECK(relnav_estimator_get_q_vv(e, nullptr) == RELNAV_ERROR_NULL_POINTER);
            relnav_estimator_free(e);
        }
    }

    // Valid corner cases must be accepted.
    expect_config_ok("no process noise at all", [](relnav_config& c) {
        c.accel_psd = 0.0;
        for (int i = 0; i < 3; ++i) c.q_pos[i] = c.q_vel[i] = 0.0;
    });
    expect_config_ok("accel_psd=1e-8", [](relnav_config& c) { c.accel_psd = 1e-8; });
    expect_config_ok("seed=UINT64_MAX", [](relnav_config& c) { c.seed = UINT64_MAX; });
    for (int r : {RELNAV_RESAMPLER_MULTINOMIAL, RELNAV_RESAMPLER_SYSTEMATIC, RELNAV_RESAMPLER_STRATIFIED,
                  RELNAV_RESAMPLER_RESIDUAL, RELNAV_RESAMPLER_AUTO})
        for (int nm : {RELNAV_NOISE_GAUSSIAN, RELNAV_NOISE_MIXTURE, RELNAV_NOISE_STUDENT_T})
            expect_config_ok("cgapf resampler=" + std::to_string(r) + " noise_model=" + std::to_string(nm),
                             [=](relnav_config& c) {
                                 c.filter = RELNAV_FILTER_CGAPF;
                                 c.particles = 200;
                                 c.resampler = r;
                                 c.noise_model = nm;
                             });
    expect_config_ok("rpf particles=1 resample_threshold=1", [](relnav_config& c) {
        c.filter = RELNAV_FILTER_RPF;
        c.particles = 1;
        c.resample_threshold = 1.0;
    });
    expect_config_ok("ukf kappa=-5.5", [](relnav_config& c) { c.filter = RELNAV_FILTER_UKF; c.ukf_kappa = -5.5; });
    for (int f : {1, 2, 4, 5, 6, 7, 8})
        for (int fr : {1, 2, 3})
            for (int d : {1, 2})
                expect_config_ok("filter=" + std::to_string(f) + " frame=" + std::to_string(fr) +
                                     " discretization=" + std::to_string(d),
                                 [=](relnav_config& c) { c.filter = f; c.frame = fr; c.discretization = d; });
    {
        // Observation only (an EKF does not use the UKF parameters): is NaN there rejected?
        relnav_config c = relnav_config_default();
        c.ukf_alpha = kNaN;
        const relnav_status s = relnav_config_validate(&c);
        std::printf("  note: filter=1 with ukf_alpha=NaN -> %s\n", relnav_status_string(s));
    }
}

void check_singular_geometry() {
    std::printf("singular geometry (estimate at zero range)\n");
    for (int f : {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF}) {
        relnav_config c = relnav_config_default();
        c.filter = f;
        for (double& v : c.x0) v = 0.0;
        relnav_estimator* e = nullptr;
        CHECK(relnav_estimator_new(&c, &e) == RELNAV_OK && e != nullptr);
        if (!e) continue;
        const double z[3] = {670.8, 0.896, 0.3027};
        const double u[3] = {0.0, 0.0, 0.0};
        const std::string tag = f == RELNAV_FILTER_EKF ? "ekf" : "ukf";
        expect_fail(tag + " update at zero range", RELNAV_ERROR_NUMERICAL, [&] { return relnav_estimator_update(e, z); }, e);
        expect_fail(tag + " step with z at zero range", RELNAV_ERROR_NUMERICAL,
                    [&] { return relnav_estimator_step(e, u, z, 1.0); }, e);
        ++g_cases;
        CHECK(relnav_estimator_step(e, u, nullptr, 1.0) == RELNAV_OK);  // prediction alone is fine
        relnav_estimator_free(e);
    }
}

// A configuration that passes every field check but whose initial covariance overflows
// (sigma_pos0^2 or sigma_vel0^2 > DBL_MAX) must either be refused, or give a usable
// estimator; it must never report a NaN variance as a sigma of 0.
void check_overflowing_initial_covariance() {
    std::printf("initial covariance overflow\n");
    for (const char* field : {"sigma_pos0", "sigma_vel0"}) {
        ++g_cases;
        relnav_config c = relnav_config_default();
        (std::strcmp(field, "sigma_pos0") == 0 ? c.sigma_pos0 : c.sigma_vel0) = 1e200;
        relnav_estimator* e = nullptr;
        const relnav_status st = relnav_estimator_new(&c, &e);
        std::printf("  %s=1e200: relnav_estimator_new -> %s\n", field, relnav_status_string(st));
        if (st != RELNAV_OK) {
            CHECK(st == RELNAV_ERROR_INVALID_ARGUMENT && e == nullptr);
            CHECK(last_error().find(field) != std::string::npos);
            continue;
        }
        double cov[36], sigma[6];
        CHECK(relnav_estimator_get_covariance(e, cov) == RELNAV_OK);
        CHECK(relnav_estimator_get_sigma(e, sigma) == RELNAV_OK);
        const bool cov_ok = std::all_of(std::begin(cov), std::end(cov), [](double d) { return !std::isnan(d); });
        const bool sigma_ok = std::none_of(std::begin(sigma), std::end(sigma), [](double d) { return d == 0.0; });
        const double u[3] = {0.0, 0.0, 0.0};
        const relnav_status step = relnav_estimator_step(e, u, nullptr, 1.0);
        if (!(cov_ok && sigma_ok && step == RELNAV_OK))
            record_failure(__FILE__, __LINE__,
                           std::string(field) + "=1e200 is accepted, but the covariance holds NaN (cov[0] = " +
                               fmt(cov[0]) + "), get_sigma reports " + fmt(sigma[0]) +
                               ", and a plain prediction returns " + relnav_status_string(step));
        relnav_estimator_free(e);
    }
}

void check_success_paths() {
    std::printf("success paths\n");
    for (int f : {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF}) {
        ++g_cases;
        relnav_config c = relnav_config_default();
        c.filter = f;
        c.seed = 42;
        relnav_estimator* e = nullptr;
        CHECK(relnav_estimator_new(&c, &e) == RELNAV_OK && e != nullptr);
        if (!e) continue;
        relnav_config back{};
        CHECK(relnav_estimator_get_config(e, &back) == RELNAV_OK);
        CHECK(back.filter == c.filter && back.frame == c.frame && back.discretization == c.discretization);
        CHECK(back.mean_motion == c.mean_motion && back.chaser_mass == c.chaser_mass && back.seed == c.seed);
        CHECK(std::memcmp(back.x0, c.x0, sizeof c.x0) == 0 && std::memcmp(back.q_pos, c.q_pos, sizeof c.q_pos) == 0 &&
              std::memcmp(back.q_vel, c.q_vel, sizeof c.q_vel) == 0);
        CHECK(back.sigma_range == c.sigma_range && back.sigma_angle == c.sigma_angle &&
              back.sigma_pos0 == c.sigma_pos0 && back.sigma_vel0 == c.sigma_vel0 && back.accel_psd == c.accel_psd);
        CHECK(back.ukf_alpha == c.ukf_alpha && back.ukf_beta == c.ukf_beta && back.ukf_kappa == c.ukf_kappa);

        const Snapshot initial = snapshot(e);
        CHECK(std::memcmp(initial.state, c.x0, sizeof c.x0) == 0);
        for (int i = 0; i < 6; ++i) {
            const double s = i < 3 ? c.sigma_pos0 : c.sigma_vel0;
            CHECK(std::fabs(initial.cov[7 * i] - s * s) <= 1e-12 * s * s);
            CHECK(std::fabs(initial.sigma[i] - s) <= 1e-12 * s);
        }
        CHECK(std::isnan(initial.innov[0]) && std::isnan(initial.innov[1]) && std::isnan(initial.innov[2]) &&
              std::isnan(initial.nis));

        // update + predict == step; the innovation is defined afterwards.
        relnav_estimator* e2 = nullptr;
        CHECK(relnav_estimator_new(&c, &e2) == RELNAV_OK && e2 != nullptr);
        const double z[3] = {670.5, 0.8961, 0.3026};
        const double u[3] = {2.0, -1.0, 0.5};
        CHECK(relnav_estimator_step(e, u, z, 1.0) == RELNAV_OK);
        if (e2) {
            CHECK(relnav_estimator_update(e2, z) == RELNAV_OK);
            CHECK(relnav_estimator_predict(e2, u, 1.0) == RELNAV_OK);
            CHECK_MSG(snapshot(e) == snapshot(e2), "step != update + predict");
            relnav_estimator_free(e2);
        }
        const Snapshot after = snapshot(e);
        CHECK(std::isfinite(after.nis) && after.nis >= 0.0);
        for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 6; ++j) CHECK(std::fabs(after.cov[6 * i + j] - after.cov[6 * j + i]) <= 1e-12 * (1.0 + std::fabs(after.cov[6 * i + j])));
        CHECK(after.sigma[0] < c.sigma_pos0);  // the measurement helped

        // reset returns to the initial estimate.
        CHECK(relnav_estimator_reset(e) == RELNAV_OK);
        CHECK_MSG(snapshot(e) == initial, "reset does not restore the initial estimate");
        relnav_estimator_free(e);
    }
}

// relnav_estimator_get_hinf_design: the route record of filter 9's design, a null-safe
// getter, and "no route" for the other filters.
void check_hinf_design_record() {
    std::printf("=== H-infinity design record ===\n");
    relnav_config c = relnav_config_default();
    c.filter = RELNAV_FILTER_HINF;
    c.hinf_design = RELNAV_HINF_OBSERVER;  // the gamma-optimal observer: the Riccati route
    relnav_estimator* e = nullptr;
    CHECK(relnav_estimator_new(&c, &e) == RELNAV_OK);
    if (!e) return;
    relnav_hinf_design_info info{};
    CHECK(relnav_estimator_get_hinf_design(e, &info) == RELNAV_OK);
    CHECK(info.route == RELNAV_HINF_ROUTE_RICCATI && info.observer_route == RELNAV_HINF_ROUTE_RICCATI);
    CHECK(info.riccati_failure == RELNAV_HINF_RICCATI_OK && info.riccati_steps > 0 && info.iterations == 0);
    CHECK(std::isfinite(info.solve_time) && info.solve_time > 0.0);
    CHECK(relnav_estimator_get_hinf_design(e, nullptr) == RELNAV_ERROR_NULL_POINTER);
    CHECK(relnav_estimator_get_hinf_design(nullptr, &info) == RELNAV_ERROR_NULL_POINTER);
    relnav_estimator_free(e);
    c = relnav_config_default();  // the EKF: no design
    CHECK(relnav_estimator_new(&c, &e) == RELNAV_OK);
    if (!e) return;
    CHECK(relnav_estimator_get_hinf_design(e, &info) == RELNAV_OK);
    CHECK(info.route == RELNAV_HINF_ROUTE_NONE && info.iterations == 0 && std::isnan(info.solve_time));
    relnav_estimator_free(e);
    // the readable reasons of the Riccati route's failure codes
    CHECK(std::string(relnav_hinf_riccati_failure_string(RELNAV_HINF_RICCATI_OK)) == "none");
    std::vector<std::string> reasons;
    for (int code = RELNAV_HINF_RICCATI_SINGULAR_MEASUREMENT_NOISE; code <= RELNAV_HINF_RICCATI_CERTIFICATION_FAILED;
         ++code) {
        const char* r = relnav_hinf_riccati_failure_string(code);
        CHECK(r != nullptr && r[0] != '\0' && std::string(r).find("unknown") == std::string::npos);
        if (r) reasons.emplace_back(r);
    }
    std::sort(reasons.begin(), reasons.end());
    CHECK(reasons.size() == 4 && std::unique(reasons.begin(), reasons.end()) == reasons.end());
    for (int code : {5, -1, INT_MAX, INT_MIN})
        CHECK(std::string(relnav_hinf_riccati_failure_string(code)) == "unknown Riccati failure code");
}

}  // namespace

int main() {
    check_static_functions();

    relnav_config cfg = relnav_config_default();
    for (int filter : {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF}) {
        std::printf("=== estimator with filter %d ===\n", filter);
        cfg.filter = filter;
        relnav_estimator* est = make_estimator(cfg, 5);
        relnav_estimator* twin = make_estimator(cfg, 5);  // never sees a failing call
        if (!est || !twin) return finish("capi_errors");
        check_null_pointers(est);
        check_non_finite_inputs(est);
        CHECK_MSG(snapshot(est) == snapshot(twin), "estimator differs from its twin after the failing calls");
        // ... and it still works exactly like the twin.
        const double u[3] = {1.0, 2.0, -0.5};
        const double z[3] = {671.0, 0.8962, 0.3025};
        CHECK(relnav_estimator_step(est, u, z, 1.0) == RELNAV_OK);
        CHECK(relnav_estimator_step(twin, u, z, 1.0) == RELNAV_OK);
        CHECK_MSG(snapshot(est) == snapshot(twin), "estimator differs from its twin after a good step");
        relnav_estimator_free(est);
        relnav_estimator_free(twin);
    }
    check_config();
    check_singular_geometry();
    check_success_paths();
    check_overflowing_initial_covariance();
    check_hinf_design_record();
    std::printf("%d cases\n", g_cases);
    return finish("capi_errors");
}
