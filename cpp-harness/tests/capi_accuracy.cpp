// Test (a): paper 000's example through the relnav C ABI, EKF and UKF, without and with a
// 60 s burn. Truth: our own closed-form CW solution (cross-checked with RK4 here). Asserts
// the paper's accuracy bar over `--runs` seeded runs (default 20; memcheck runs use fewer).

#include "capi_runner.hpp"
#include "check.hpp"
#include "scenario.hpp"

#include <relnav.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace harness;

namespace {

constexpr int kFullRuns = 20;

double max_abs_diff(const std::vector<Vec6>& a, const std::vector<Vec6>& b, int from, int to) {
    double m = 0.0;
    for (size_t k = 0; k < a.size(); ++k)
        for (int i = from; i < to; ++i)
            m = std::max(m, std::fabs(a[k][static_cast<size_t>(i)] - b[k][static_cast<size_t>(i)]));
    return m;
}

// relnav's defaults must be paper 000's example, otherwise the scenario is not the paper's.
void check_defaults(const Paper000& p) {
    const relnav_config c = relnav_config_default();
    CHECK(c.filter == RELNAV_FILTER_EKF);
    CHECK(c.frame == RELNAV_FRAME_ALONG_RADIAL_ANTINORMAL);
    CHECK(std::fabs(c.mean_motion - p.mean_motion) <= 1e-15 * p.mean_motion);
    CHECK(c.chaser_mass == p.chaser_mass);
    CHECK(c.sigma_range == p.sigma_range);
    CHECK(std::fabs(c.sigma_angle - p.sigma_angle) <= 1e-15);
    for (int i = 0; i < 6; ++i) CHECK(c.x0[i] == p.estimate0[static_cast<size_t>(i)]);
    CHECK(relnav_config_validate(&c) == RELNAV_OK);
}

// The truth must be right before it can judge anything.
void check_truth() {
    // 1. Step-by-step closed form == closed form from the epoch (no thrust).
    Paper000 p;
    const auto stepped = truth_trajectory(p);
    double worst = 0.0;
    const Vec6 c0 = state_frame2_to_canonical(p.truth0);
    for (int k = 0; k <= p.steps; ++k) {
        const Vec6 direct = state_canonical_to_frame2(cw_propagate(c0, p.mean_motion, k * p.dt));
        for (int i = 0; i < 6; ++i)
            worst = std::max(worst, std::fabs(direct[static_cast<size_t>(i)] -
                                              stepped[static_cast<size_t>(k)][static_cast<size_t>(i)]));
    }
    std::printf("truth check: stepped vs epoch closed form, max |diff| = %.3g\n", worst);
    CHECK(worst < 1e-9);

    // 2. Closed form (with the zero-order-hold burn) == RK4 at 1 ms.
    const Paper000 pb = paper000_with_burn();
    const auto cf = truth_trajectory(pb);
    const auto rk = truth_trajectory_rk4(pb, 1e-3);
    const double dpos = max_abs_diff(cf, rk, 0, 3), dvel = max_abs_diff(cf, rk, 3, 6);
    std::printf("truth check: closed form vs RK4 (1 ms), burn scenario: max |dpos| = %.3g m, "
                "max |dvel| = %.3g m/s\n", dpos, dvel);
    CHECK(dpos < 1e-6);
    CHECK(dvel < 1e-8);

    // 3. The burn must actually move the chaser (otherwise the burn case tests nothing).
    const Vec6& a = stepped.back();
    const Vec6& b = cf.back();
    const double sep = std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                 (a[2] - b[2]) * (a[2] - b[2]));
    std::printf("truth check: burn displaces the chaser by %.1f m at t = 600 s\n", sep);
    CHECK(sep > 50.0);

    // 4. Measurement definition on the initial geometry (frame 2).
    const Vec3 z = radio_measurement(p.truth0);
    CHECK(std::fabs(z[0] - std::sqrt(400.0 * 400 + 500.0 * 500 + 200.0 * 200)) < 1e-12);
    CHECK(std::fabs(z[1] - std::atan2(500.0, 400.0)) < 1e-15);
    CHECK(std::fabs(z[2] - std::asin(200.0 / z[0])) < 1e-15);
    CHECK(std::fabs(wrap_2pi(-0.25) - (kTwoPi - 0.25)) < 1e-15);
}

void run_case(const std::string& name, const Paper000& p, int filter, int runs) {
    const auto truth = truth_trajectory(p);
    std::vector<Run> est;
    double nees_sum = 0.0;  // consistency diagnostic: mean normalised position error^2 / axis
    long nees_n = 0;
    for (int seed = 0; seed < runs; ++seed) {
        const auto z = noisy_measurements(p, truth, static_cast<std::uint64_t>(seed));
        const Trace tr = run_capi(p, z, filter);
        if (!tr.ok || tr.state.size() != static_cast<size_t>(p.steps)) {
            record_failure(__FILE__, __LINE__, name + ": run did not complete");
            return;
        }
        for (size_t k = 79; k < tr.state.size(); ++k)
            for (size_t i = 0; i < 3; ++i) {
                const double e = (tr.state[k][i] - truth[k + 1][i]) / tr.sigma[k][i];
                nees_sum += e * e;
                ++nees_n;
            }
        est.push_back(tr.state);
    }
    const Bar bar;
    const Stats s = evaluate(est, truth, bar);
    print_table_row(name, s);
    const int f = check_bar(name, s, bar, kFullRuns);
    for (int i = 0; i < f; ++i) record_failure(__FILE__, __LINE__, name + ": accuracy bar");
    const double nees = nees_sum / static_cast<double>(nees_n);
    std::printf("%-22s      mean (err/sigma)^2 per position axis after 80 s = %.3f\n", "", nees);
    // Loose consistency check: the reported sigma must be the right order of magnitude.
    CHECK_MSG(nees > 0.05 && nees < 20.0, name + ": sigma inconsistent with the actual error");
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = parse_runs(argc, argv, kFullRuns);
    std::printf("relnav %s, capi_accuracy with %d run(s) per case%s\n", relnav_version(), runs,
                runs < kFullRuns ? " (reduced: per-axis bar applied to the RMSE over time)" : "");
    Paper000 plain;
    const Paper000 burn = paper000_with_burn();
    check_defaults(plain);
    check_truth();

    std::printf("\nerror = estimate at t+1 after the step at t minus truth at t+1; times 80..600 s\n");
    print_table_header();
    run_case("EKF", plain, RELNAV_FILTER_EKF, runs);
    run_case("UKF", plain, RELNAV_FILTER_UKF, runs);
    run_case("EKF burn 100-160s", burn, RELNAV_FILTER_EKF, runs);
    run_case("UKF burn 100-160s", burn, RELNAV_FILTER_UKF, runs);
    std::printf("bar: every per-time RMS < 0.5 m (pos) / 0.02 m/s (vel); position RMSE < 0.4 m\n");
    return finish("capi_accuracy");
}
