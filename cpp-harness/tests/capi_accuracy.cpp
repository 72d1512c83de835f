// Test (a): paper 000's example through the relnav C ABI, EKF and UKF, without and with a
// 60 s burn. Truth: our own closed-form CW solution (cross-checked with RK4 here). Asserts
// the paper's accuracy bar over `--runs` seeded runs (default 20; memcheck runs use fewer).
// Issue 12: the same burn NOT told to the filters, which are tuned for the quiet phase: the
// gated AQUKF and the IMM (code 10, with its mode probabilities) against the UKF.

#include "capi_runner.hpp"
#include "check.hpp"
#include "scenario.hpp"

#include <relnav.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
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
void check_truth(bool with_rk4) {
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

    // 2. Closed form (with the zero-order-hold burn) == RK4 at 1 ms. It checks only this
    // harness's own C++ (600 000 RK4 steps): skipped in the reduced (valgrind) run, where
    // it took half the time and exercised no relnav memory; the plain test runs it.
    const Paper000 pb = paper000_with_burn();
    const auto cf = truth_trajectory(pb);
    if (with_rk4) {
        const auto rk = truth_trajectory_rk4(pb, 1e-3);
        const double dpos = max_abs_diff(cf, rk, 0, 3), dvel = max_abs_diff(cf, rk, 3, 6);
        std::printf("truth check: closed form vs RK4 (1 ms), burn scenario: max |dpos| = %.3g m, "
                    "max |dvel| = %.3g m/s\n", dpos, dvel);
        CHECK(dpos < 1e-6);
        CHECK(dvel < 1e-8);
    } else {
        std::printf("truth check: closed form vs RK4 skipped in the reduced run (the full run has it)\n");
    }

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

// Frame conversions for all three I/O frames (frame 2 in scenario.hpp); our own, from the
// frame definitions: 1 = canonical; 3 = (along-track, minus normal, nadir).
Vec6 to_canonical(int frame, const Vec6& s) {
    if (frame == 1) return s;
    if (frame == 2) return state_frame2_to_canonical(s);
    return {-s[2], s[0], -s[1], -s[5], s[3], -s[4]};  // x_c = -z3, y_c = x3, z_c = -y3
}
Vec6 from_canonical(int frame, const Vec6& c) {
    if (frame == 1) return c;
    if (frame == 2) return state_canonical_to_frame2(c);
    return {c[1], -c[2], -c[0], c[4], -c[5], -c[3]};
}
Vec3 vec_to_canonical(int frame, const Vec3& v) {
    const Vec6 s = to_canonical(frame, {v[0], v[1], v[2], 0.0, 0.0, 0.0});
    return {s[0], s[1], s[2]};
}

// relnav's time update (mean) and measurement model against our own, in every frame.
void check_models() {
    double worst_exact = 0.0, worst_euler = 0.0, worst_innov = 0.0;
    const Vec6 xio = {405.0, -505.0, 205.0, 0.3, -0.2, 0.1};
    const Vec3 thrust = {2.0, -1.0, 0.5};
    for (int frame = 1; frame <= 3; ++frame)
        for (int filter : {RELNAV_FILTER_EKF, RELNAV_FILTER_UKF})
            for (double n : {kTwoPi / 7200.0, 1.1e-3, 7.29e-5})
                for (double dt : {0.01, 1.0, 60.0, 600.0})
                    for (int disc : {RELNAV_DISCRETIZATION_EXACT, RELNAV_DISCRETIZATION_EULER}) {
                        relnav_config c = relnav_config_default();
                        c.filter = filter;
                        c.frame = frame;
                        c.mean_motion = n;
                        c.discretization = disc;
                        for (int i = 0; i < 6; ++i) c.x0[i] = xio[static_cast<size_t>(i)];
                        relnav_estimator* e = nullptr;
                        CHECK(estimator_new(&c, &e) == RELNAV_OK);
                        if (!e) continue;
                        CHECK(relnav_estimator_predict(e, thrust.data(), dt) == RELNAV_OK);
                        Vec6 got{};
                        CHECK(relnav_estimator_get_state(e, got.data()) == RELNAV_OK);
                        const Vec3 f = thrust;
                        const Vec3 a = vec_to_canonical(frame, {f[0] / c.chaser_mass, f[1] / c.chaser_mass,
                                                                f[2] / c.chaser_mass});
                        const Vec6 xc = to_canonical(frame, xio);
                        Vec6 want;
                        if (disc == RELNAV_DISCRETIZATION_EXACT) {
                            want = from_canonical(frame, cw_propagate(xc, n, dt, a));
                        } else {  // Euler: x + T (A x + B a)
                            const Vec6 d = cw_rhs(xc, n, a);
                            Vec6 xe;
                            for (int i = 0; i < 6; ++i) xe[static_cast<size_t>(i)] = xc[static_cast<size_t>(i)] + dt * d[static_cast<size_t>(i)];
                            want = from_canonical(frame, xe);
                        }
                        double rel = 0.0;
                        for (size_t i = 0; i < 6; ++i)
                            rel = std::max(rel, std::fabs(got[i] - want[i]) / (1.0 + std::fabs(want[i])));
                        double& worst = disc == RELNAV_DISCRETIZATION_EXACT ? worst_exact : worst_euler;
                        worst = std::max(worst, rel);
                        CHECK_MSG(rel < 1e-9, "predict differs from the closed form: frame " + std::to_string(frame) +
                                                  " filter " + std::to_string(filter) + " n " + std::to_string(n) +
                                                  " dt " + std::to_string(dt) + " disc " + std::to_string(disc) +
                                                  ": " + std::to_string(rel));
                        estimator_free(e);

                        // Measurement model: innovation = z - h(prior), azimuth wrapped to (-pi, pi].
                        if (disc != RELNAV_DISCRETIZATION_EXACT || dt != 1.0 || filter != RELNAV_FILTER_EKF) continue;
                        CHECK(estimator_new(&c, &e) == RELNAV_OK);
                        if (!e) continue;
                        const Vec3 h = radio_measurement(xio);
                        const Vec3 z = {h[0] + 0.7, wrap_2pi(h[1] + 3.1), h[2] - 0.002};
                        CHECK(relnav_estimator_update(e, z.data()) == RELNAV_OK);
                        Vec3 innov{};
                        double nis = -1.0;
                        CHECK(relnav_estimator_get_innovation(e, innov.data(), &nis) == RELNAV_OK);
                        const Vec3 expect = {0.7, 3.1, -0.002};
                        for (size_t i = 0; i < 3; ++i) worst_innov = std::max(worst_innov, std::fabs(innov[i] - expect[i]));
                        CHECK_MSG(std::fabs(innov[0] - 0.7) < 1e-9 && std::fabs(innov[1] - 3.1) < 1e-9 &&
                                      std::fabs(innov[2] + 0.002) < 1e-9,
                                  "innovation differs from z - h(x) in frame " + std::to_string(frame));
                        CHECK(std::isfinite(nis) && nis > 0.0);
                        estimator_free(e);
                    }
    std::printf("model check: predict vs own CW (frames 1-3, EKF/UKF, 3 n, 4 dt): max rel diff exact %.3g, "
                "Euler %.3g; innovation vs own h(x): %.3g\n", worst_exact, worst_euler, worst_innov);
}

void run_case(const std::string& name, const Paper000& p, int filter, int runs) {
    const auto truth = truth_trajectory(p);
    std::vector<Run> est;
    double nees_sum = 0.0;  // consistency diagnostic: mean normalised position error^2 / axis
    long nees_n = 0;
    // FNV-1a over the bytes of every estimate and sigma: the flight library's build of
    // this test must print the full library's (ctest capi_accuracy_flight_bits)
    std::uint64_t sum = 1469598103934665603ULL;
    auto hash = [&sum](const Vec6& v) {
        unsigned char b[sizeof(double) * 6];
        std::memcpy(b, v.data(), sizeof b);
        for (unsigned char c : b) {
            sum ^= c;
            sum *= 1099511628211ULL;
        }
    };
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
        for (size_t k = 0; k < tr.state.size(); ++k) {
            hash(tr.state[k]);
            hash(tr.sigma[k]);
        }
        est.push_back(tr.state);
    }
    const Bar bar;
    const Stats s = evaluate(est, truth, bar);
    print_table_row(name, s);
    std::printf("%-22s      checksum of every estimate and sigma %016llx\n", "",
                static_cast<unsigned long long>(sum));
    const int f = check_bar(name, s, bar, kFullRuns);
    for (int i = 0; i < f; ++i) record_failure(__FILE__, __LINE__, name + ": accuracy bar");
    const double nees = nees_sum / static_cast<double>(nees_n);
    std::printf("%-22s      mean (err/sigma)^2 per position axis after 80 s = %.3f\n", "", nees);
    // Loose consistency check: the reported sigma must be the right order of magnitude.
    CHECK_MSG(nees > 0.05 && nees < 20.0, name + ": sigma inconsistent with the actual error");
}

#ifndef RELNAV_FLIGHT  // no particle filters in the flight library
// A particle filter through the C ABI: CGA-PF (code 8, `particles` particles, its seed = the
// run index) on paper 000's example (`p.steps` long). Particle filters are checked against what they do on
// this example, not the Kalman filters' per-axis bar: their velocity error after 600 s
// is a few cm/s, above paper 000's 0.02 m/s (see crates/core/src/estimators/pf/mod.rs). Checked: the
// position RMSE after 80 s < 0.5 m, every final position error < 1 m, the effective
// sample size in [1, particles] at every step, and a second estimator with the same seed
// reproducing the first bit for bit over the first fifth of the run.
void run_pf_case(const Paper000& p, int runs, int particles) {
    const std::string name = "CGA-PF " + std::to_string(particles) + " p.";
    const auto truth = truth_trajectory(p);
    std::vector<Run> est;
    double worst_final = 0.0, ess_min = 1e300, ess_max = 0.0;
    bool reproducible = true;
    for (int seed = 0; seed < runs; ++seed) {
        const auto z = noisy_measurements(p, truth, static_cast<std::uint64_t>(seed));
        relnav_config cfg = relnav_config_default();
        cfg.filter = RELNAV_FILTER_CGAPF;
        cfg.seed = static_cast<std::uint64_t>(seed);
        cfg.particles = particles;
        relnav_estimator* a = nullptr;
        relnav_estimator* b = nullptr;
        CHECK(estimator_new(&cfg, &a) == RELNAV_OK && estimator_new(&cfg, &b) == RELNAV_OK);
        if (!a || !b) {
            estimator_free(a);
            estimator_free(b);
            return;
        }
        Run r;
        const double u[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < p.steps; ++k) {
            const double* zk = z[static_cast<size_t>(k)].data();
            if (relnav_estimator_step(a, u, zk, p.dt) != RELNAV_OK) {
                record_failure(__FILE__, __LINE__, name + " step failed: " + relnav_last_error());
                break;
            }
            Vec6 x{};
            double ess = 0.0;
            CHECK(relnav_estimator_get_state(a, x.data()) == RELNAV_OK);
            CHECK(relnav_estimator_get_ess(a, &ess) == RELNAV_OK);
            ess_min = std::min(ess_min, ess);
            ess_max = std::max(ess_max, ess);
            if (k < p.steps / 5) {  // the twin with the same seed, over the first fifth
                Vec6 y{};
                CHECK(relnav_estimator_step(b, u, zk, p.dt) == RELNAV_OK);
                CHECK(relnav_estimator_get_state(b, y.data()) == RELNAV_OK);
                reproducible = reproducible && std::memcmp(x.data(), y.data(), sizeof(double) * 6) == 0;
            }
            r.push_back(x);
        }
        estimator_free(a);
        estimator_free(b);
        if (r.size() != static_cast<size_t>(p.steps)) return;
        const Vec6& last = r.back();
        double d2 = 0.0;
        for (size_t i = 0; i < 3; ++i) d2 += (last[i] - truth.back()[i]) * (last[i] - truth.back()[i]);
        worst_final = std::max(worst_final, std::sqrt(d2));
        est.push_back(r);
    }
    const Stats s = evaluate(est, truth, Bar{});
    print_table_row(name, s);
    std::printf("%-22s      worst final position error %.3f m; ess in [%.1f, %.1f] of %d; same seed %s\n", "",
                worst_final, ess_min, ess_max, particles, reproducible ? "bit-identical" : "DIFFERS");
    CHECK_MSG(s.pos_rmse < 0.5, name + ": position RMSE after 80 s " + std::to_string(s.pos_rmse) + " m");
    CHECK_MSG(worst_final < 1.0, name + ": final position error " + std::to_string(worst_final) + " m");
    CHECK_MSG(ess_min >= 1.0 && ess_max <= particles, name + ": ess outside [1, particles]");
    CHECK_MSG(reproducible, name + ": two estimators with the same seed differ");
}

#endif

// Issue 12: the 60 s burn of paper000_with_burn() is NOT told to the filters (zero thrust
// in), and every filter is tuned for the quiet phase (no position noise, a velocity noise
// of 1e-8 m^2/s^3; the AQUKF starts its q_vv there). After the burn's start, the gated
// AQUKF's, the window AQUKF's and the IMM's position RMSE must be at most half the UKF's
// (issue 12's bar); the IMM's mode probabilities must sum to one at every step, stay on the
// quiet mode before the burn (> 0.9) and, during it, lift the manoeuvring modes at least a
// hundredfold above their stationary probability (2e-4 with the defaults; this 2.3 mm/s^2
// burn is small beside the burn mode's 1e-3 m^2/s^3, so they need not dominate: measured
// 0.12 at the peak of the mean over runs). Recovery: first time after the burn's end from
// which the position RMSE over runs stays below 1 m.
void run_unreported_burn_case(int runs) {
    const Paper000 p = paper000_with_burn();
    const auto truth = truth_trajectory(p);
    struct Filter {
        const char* name;
        int code;
        int law;
    };
    const Filter filters[] = {{"UKF", RELNAV_FILTER_UKF, RELNAV_ADAPTATION_GATED},
                              {"AQUKF gated", RELNAV_FILTER_AQUKF, RELNAV_ADAPTATION_GATED},
                              {"AQUKF window", RELNAV_FILTER_AQUKF, RELNAV_ADAPTATION_WINDOW},
                              {"IMM", RELNAV_FILTER_IMM, RELNAV_ADAPTATION_GATED}};
    const size_t n = static_cast<size_t>(p.steps);
    double ukf_after = 0.0;
    std::printf("\nunreported burn (2, -1, 0.5) N, 100-160 s; filters tuned for the quiet phase\n");
    for (const Filter& f : filters) {
        std::vector<double> sq(n, 0.0);  // sum over runs of |dr|^2 at estimate time k + 1
        double mu_sum_err = 0.0, manoeuvre_peak = 0.0, quiet_mode_before = 0.0;
        int quiet_count = 0;
        for (int seed = 0; seed < runs; ++seed) {
            const auto z = noisy_measurements(p, truth, static_cast<std::uint64_t>(seed));
            relnav_config c = relnav_config_default();
            c.filter = f.code;
            c.aq_law = f.law;
            for (int i = 0; i < 3; ++i) {
                c.q_pos[i] = 0.0;
                c.q_vel[i] = 1e-8;
            }
            relnav_estimator* e = nullptr;
            CHECK(estimator_new(&c, &e) == RELNAV_OK);
            if (!e) return;
            const double u[3] = {0.0, 0.0, 0.0};
            std::vector<double> manoeuvre(n, 0.0);
            for (size_t k = 0; k < n; ++k) {
                if (relnav_estimator_step(e, u, z[k].data(), p.dt) != RELNAV_OK) {
                    record_failure(__FILE__, __LINE__, std::string(f.name) + ": step failed: " + relnav_last_error());
                    break;
                }
                Vec6 x{};
                double mu[3] = {0.0, 0.0, 0.0};
                CHECK(relnav_estimator_get_state(e, x.data()) == RELNAV_OK);
                CHECK(relnav_estimator_get_mode_probabilities(e, mu) == RELNAV_OK);
                for (size_t i = 0; i < 3; ++i) sq[k] += (x[i] - truth[k + 1][i]) * (x[i] - truth[k + 1][i]);
                if (f.code == RELNAV_FILTER_IMM) {
                    mu_sum_err = std::max(mu_sum_err, std::fabs(mu[0] + mu[1] + mu[2] - 1.0));
                    manoeuvre[k] = mu[1] + mu[2];
                    if (k + 1 >= 50 && k + 1 < 100) {
                        quiet_mode_before += mu[0];
                        ++quiet_count;
                    }
                } else {
                    CHECK(std::isnan(mu[0]) && std::isnan(mu[1]) && std::isnan(mu[2]));
                }
            }
            estimator_free(e);
            for (size_t k = 100; k < 160; ++k) manoeuvre_peak = std::max(manoeuvre_peak, manoeuvre[k] / runs);
        }
        // position RMSE over runs and estimate times t >= 100 s (from the burn's start)
        double sum = 0.0;
        long cnt = 0;
        for (size_t k = 99; k < n; ++k) {
            sum += sq[k];
            cnt += runs;
        }
        const double after = std::sqrt(sum / static_cast<double>(cnt));
        // recovery below 1 m after the burn's end (estimate times t >= 160 s)
        double recovery = -1.0;  // never
        for (size_t k = n; k-- > 159;) {
            if (std::sqrt(sq[k] / runs) >= 1.0) {
                if (k + 1 < n) recovery = static_cast<double>(k + 2) - 160.0;
                break;
            }
            if (k == 159) recovery = 0.0;
        }
        if (f.code == RELNAV_FILTER_UKF) ukf_after = after;
        char rec[32];
        if (recovery < 0.0)
            std::snprintf(rec, sizeof rec, "never");
        else
            std::snprintf(rec, sizeof rec, "%.0f s", recovery);
        std::printf("  %-13s position RMSE from 100 s: %.3f m (%.3f of the UKF's); recovery below 1 m: %s\n", f.name,
                    after, after / ukf_after, rec);
        if (f.code != RELNAV_FILTER_UKF)
            CHECK_MSG(after <= 0.5 * ukf_after, std::string(f.name) + ": " + std::to_string(after) +
                                                     " m is not at most half the UKF's " + std::to_string(ukf_after));
        if (f.code == RELNAV_FILTER_IMM) {
            std::printf("  IMM: mean mode-1 probability 50-100 s %.4f, peak mean manoeuvre probability in the burn "
                        "%.3f, worst |sum - 1| %.2g\n",
                        quiet_mode_before / quiet_count, manoeuvre_peak, mu_sum_err);
            CHECK(mu_sum_err < 1e-12);
            CHECK(quiet_mode_before / quiet_count > 0.9);
            relnav_config d = relnav_config_default();
            double w[3], total = 0.0;
            for (int j = 0; j < 3; ++j) total += (w[j] = 1.0 / (1.0 - d.imm_p_stay[j]));
            const double stationary = (w[1] + w[2]) / total;
            CHECK_MSG(manoeuvre_peak > 100.0 * stationary,
                      "IMM: manoeuvre probability " + std::to_string(manoeuvre_peak) + " vs stationary " +
                          std::to_string(stationary));
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = parse_runs(argc, argv, kFullRuns);
#ifdef RELNAV_FLIGHT
    std::printf("flight library: ");
#endif
    std::printf("relnav %s, capi_accuracy with %d run(s) per case%s\n", relnav_version(), runs,
                runs < kFullRuns ? " (reduced: per-axis bar applied to the RMSE over time)" : "");
    Paper000 plain;
    const Paper000 burn = paper000_with_burn();
    check_defaults(plain);
    check_truth(runs >= kFullRuns);
    check_models();

    std::printf("\nerror = estimate at t+1 after the step at t minus truth at t+1; times 80..600 s\n");
    print_table_header();
    run_case("EKF", plain, RELNAV_FILTER_EKF, runs);
    run_case("UKF", plain, RELNAV_FILTER_UKF, runs);
    run_case("EKF burn 100-160s", burn, RELNAV_FILTER_EKF, runs);
    run_case("UKF burn 100-160s", burn, RELNAV_FILTER_UKF, runs);
    run_case("AQUKF (gated)", plain, RELNAV_FILTER_AQUKF, runs);
    run_case("IMM", plain, RELNAV_FILTER_IMM, runs);
    std::printf("bar: every per-time RMS < 0.5 m (pos) / 0.02 m/s (vel); position RMSE < 0.4 m\n");
    run_unreported_burn_case(std::min(runs, 8));
#ifdef RELNAV_FLIGHT
    std::printf("\nparticle filters: not in the flight library (skipped)\n");
#else
    if (runs >= kFullRuns) {
        run_pf_case(plain, 4, 1500);
    } else {  // reduced (e.g. under valgrind): one 100 s run with 500 particles
        Paper000 short_run;
        short_run.steps = 100;
        run_pf_case(short_run, 1, 500);
    }
#endif
    return finish("capi_accuracy");
}
