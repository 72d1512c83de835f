// Drive paper 000's scenario through the relnav C ABI (shared by capi_accuracy and
// fmu_master, which compares the FMU against it).
#pragma once

#include "check.hpp"
#include "estimator_handle.hpp"
#include "scenario.hpp"

#include <relnav.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace harness {

struct Trace {
    std::vector<Vec6> state;  // estimate at t = 1 .. steps (after the step at t - 1)
    std::vector<Vec6> sigma;  // 1-sigma at the same times
    bool ok = true;
};

// The configuration used for the scenario: relnav's defaults (paper 000) with `filter`.
inline relnav_config scenario_config(int filter) {
    relnav_config cfg = relnav_config_default();
    cfg.filter = filter;
    return cfg;
}

// Which epochs carry a measurement: all of them, unless `gap_from <= t < gap_to`.
struct Gaps {
    double from = 0.0;
    double to = 0.0;
    bool valid_at(double t) const { return !(t >= from && t < to); }
};

inline Trace run_capi(const Paper000& p, const std::vector<Vec3>& z, int filter,
                      const Gaps& gaps = Gaps{}) {
    Trace tr;
    relnav_config cfg = scenario_config(filter);
    relnav_estimator* est = nullptr;
    relnav_status st = estimator_new(&cfg, &est);
    if (st != RELNAV_OK || est == nullptr) {
        record_failure(__FILE__, __LINE__,
                       std::string("estimator_new failed: ") + relnav_last_error());
        tr.ok = false;
        return tr;
    }
    tr.state.reserve(static_cast<size_t>(p.steps));
    tr.sigma.reserve(static_cast<size_t>(p.steps));
    for (int k = 0; k < p.steps; ++k) {
        const double t = k * p.dt;
        const Vec3 u = p.thrust_at(t);
        const double* zk = gaps.valid_at(t) ? z[static_cast<size_t>(k)].data() : nullptr;
        st = relnav_estimator_step(est, u.data(), zk, p.dt);
        if (st != RELNAV_OK) {
            record_failure(__FILE__, __LINE__,
                           "relnav_estimator_step at t=" + std::to_string(t) + " returned " +
                               std::to_string(static_cast<int>(st)) + ": " + relnav_last_error());
            tr.ok = false;
            break;
        }
        Vec6 x{}, s{};
        CHECK(relnav_estimator_get_state(est, x.data()) == RELNAV_OK);
        CHECK(relnav_estimator_get_sigma(est, s.data()) == RELNAV_OK);
        tr.state.push_back(x);
        tr.sigma.push_back(s);
    }
    estimator_free(est);
    return tr;
}

// Largest relative difference between two traces (states and sigmas); exact zeros count
// as equal (the FMU masters compare the FMUs against the C ABI with it).
inline double max_rel_diff(const Trace& a, const Trace& b) {
    if (a.state.size() != b.state.size()) return std::numeric_limits<double>::infinity();
    double m = 0.0;
    auto upd = [&m](double p, double q) {
        if (p == q) return;
        const double scale = std::max(std::fabs(p), std::fabs(q));
        m = std::max(m, std::isfinite(scale) && scale > 0 ? std::fabs(p - q) / scale
                                                          : std::numeric_limits<double>::infinity());
    };
    for (size_t k = 0; k < a.state.size(); ++k)
        for (size_t i = 0; i < 6; ++i) {
            upd(a.state[k][i], b.state[k][i]);
            upd(a.sigma[k][i], b.sigma[k][i]);
        }
    return m;
}

}  // namespace harness
