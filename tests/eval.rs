//! The evaluation engine: the PCRLB equals the Kalman covariance on a linear-Gaussian
//! scenario (the KF is efficient there), the EKF is consistent on paper 000, and results
//! do not depend on the thread count.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use relnav_core::estimators::Estimator;
use relnav_core::params::Value;
use relnav_eval::builtin;
use relnav_eval::metrics::summarize;
use relnav_eval::runner::{run, Options};
use relnav_eval::scenario::Scenario;
use relnav_eval::sim::Prepared;

/// Linear-Gaussian: Cartesian position measurements, white Gaussian process and
/// measurement noise, the truth's initial state drawn from the filters' prior, and a KF
/// that knows all of it.
const LINEAR: &str = r#"
name = "linear"
title = "linear-Gaussian check"
frame = "along_radial_antinormal"
[orbit]
period = 5400.0
[truth]
initial_state = [300.0, -200.0, 100.0, 0.2, 0.1, -0.1]
initial_sigma = [20.0, 20.0, 20.0, 0.5, 0.5, 0.5]
chaser_mass = 500.0
accel_psd = 1e-6
process_noise = [0.01, 0.02, 0.03, 1e-6, 2e-6, 3e-6]
[sensor]
kind = "cartesian"
sigma_position = 2.0
period = 2.0
dropouts = [{ start = 100.0, stop = 150.0 }]
[simulation]
duration = 300.0
step = 1.0
runs = 400
seed = 7
convergence_time = 50.0
convergence_threshold = [5.0, 0.5]
[[filter]]
label = "KF"
kind = "ekf"
initial_state = [300.0, -200.0, 100.0, 0.2, 0.1, -0.1]
sigma_pos0 = 20.0
sigma_vel0 = 0.5
accel_psd = 1e-6
process_noise = [0.01, 0.02, 0.03, 1e-6, 2e-6, 3e-6]
"#;

#[test]
fn pcrlb_equals_the_kalman_covariance_on_a_linear_gaussian_scenario() {
    let s = Scenario::from_toml(LINEAR).unwrap();
    let r = run(
        &s,
        &Options {
            threads: 2,
            ..Default::default()
        },
    )
    .unwrap();
    let bound = r.pcrlb.clone().unwrap();
    // the KF's own covariance, from the same prepared model (deterministic for a linear KF)
    let prep = Prepared::new(&s).unwrap();
    let f = &prep.filters[0];
    let mut kf = f.instantiate(0).unwrap();
    let frame = s.io_frame();
    let mut z_dummy = relnav_core::types::Vec3::new(1.0, 2.0, 3.0);
    assert_eq!(bound.len(), prep.steps + 1);
    for (k, b) in bound.iter().enumerate() {
        if prep.measured[k] {
            kf.update(f.sensor.as_ref().unwrap(), &z_dummy).unwrap();
            z_dummy *= -1.0; // the covariance does not depend on the data
        }
        let p = frame.cov_from_canonical(kf.covariance());
        for i in 0..6 {
            let rel = (p[(i, i)] / b[i] - 1.0).abs();
            assert!(
                rel < 1e-9,
                "t = {k}: axis {i}: KF {} vs PCRLB {}",
                p[(i, i)],
                b[i]
            );
        }
        if k < prep.steps {
            kf.predict(&f.model, &relnav_core::types::Vec3::zeros())
                .unwrap();
        }
    }
    // and the Monte Carlo error matches the bound: efficiency 1 within sampling error.
    // Averaged over M = 400 runs, the per-time MSE has relative sd sqrt(2/M) = 7 %; the
    // average over 250 times (correlated over ~10 steps) brings it to ~1.5 %, i.e. under
    // 1 % on the RMSE ratio: 3 % is > 3 sigma.
    let sm = &summarize(&r)[0];
    let (ep, ev) = (sm.efficiency_pos.unwrap(), sm.efficiency_vel.unwrap());
    assert!(
        (ep - 1.0).abs() < 0.03 && (ev - 1.0).abs() < 0.03,
        "efficiency {ep} / {ev}"
    );
}

#[test]
fn ekf_is_consistent_on_paper000() {
    let (_, text) = builtin::for_paper("000")[0];
    let mut s = Scenario::from_toml(text).unwrap();
    s.filters.retain(|f| f.label == "EKF");
    let r = run(&s, &Options::default()).unwrap();
    let sm = summarize(&r);
    let ekf = sm.iter().find(|x| x.label == "EKF").unwrap();
    let nees = ekf.nees.as_ref().unwrap();
    // the run-averaged NEES at each time is chi2(6M)/M when consistent: ~95 % of the
    // times must fall in the per-time two-sided 95 % band (successive times are
    // correlated, so the fraction itself scatters by a few per cent)
    assert!(
        nees.in_band > 0.90,
        "NEES: {:.1} % of times in band",
        100.0 * nees.in_band
    );
    assert!(
        (nees.avg / 6.0 - 1.0).abs() < 0.1,
        "NEES average {}",
        nees.avg
    );
    let nis = ekf.nis.as_ref().unwrap();
    assert!(
        nis.in_band > 0.90,
        "NIS: {:.1} % of times in band",
        100.0 * nis.in_band
    );
    // with the paper's Q driving the truth the EKF is efficient (RMSE = sqrt(PCRLB))
    assert!((ekf.efficiency_pos.unwrap() - 1.0).abs() < 0.05);
    assert!(
        ekf.rmse_pos < 0.4,
        "paper 000: position within 0.4 m; got {}",
        ekf.rmse_pos
    );
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let (_, text) = builtin::for_paper("000")[0];
    let mut s = Scenario::from_toml(text).unwrap();
    // the Kalman filters and two particle filters (their seeds are per run and filter)
    s.filters
        .retain(|f| ["EKF", "UKF", "RPF", "CGA-PF"].contains(&f.label.as_str()));
    for f in &mut s.filters {
        let n = f.params.resolved().particles.min(300) as i64;
        f.params.set("particles", &[Value::Int(n)]).unwrap();
    }
    s.simulation.duration = 120.0;
    let one = run(
        &s,
        &Options {
            runs: Some(9),
            threads: 1,
            ..Default::default()
        },
    )
    .unwrap();
    let two = run(
        &s,
        &Options {
            runs: Some(9),
            threads: 2,
            ..Default::default()
        },
    )
    .unwrap();
    let strip = |mut r: relnav_eval::results::McResult| {
        for f in &mut r.filters {
            f.us_per_step = 0.0;
        }
        r
    };
    // compared as text: a particle filter's NIS is NaN, and NaN != NaN
    assert_eq!(format!("{:?}", strip(one)), format!("{:?}", strip(two)));
}

/// The chunks of a campaign run anywhere, in any order, and travel as bytes: reduced in
/// chunk order they give exactly `run`'s result (what the Python package's Dask campaigns
/// rely on). Partial sums out of order or from another campaign are refused.
#[test]
fn chunks_computed_apart_reduce_to_the_runners_result() {
    use relnav_eval::runner::{Campaign, Partial};
    use std::sync::atomic::{AtomicBool, AtomicU64};
    let (_, text) = builtin::for_paper("000")[0];
    let mut s = Scenario::from_toml(text).unwrap();
    s.filters
        .retain(|f| ["EKF", "UKF", "RPF"].contains(&f.label.as_str()));
    for f in &mut s.filters {
        let n = f.params.resolved().particles.min(200) as i64;
        f.params.set("particles", &[Value::Int(n)]).unwrap();
    }
    s.simulation.duration = 60.0;
    let whole = run(
        &s,
        &Options {
            runs: Some(10),
            threads: 2,
            ..Default::default()
        },
    )
    .unwrap();
    let c = Campaign::new(&s, Some(10)).unwrap();
    assert_eq!(c.chunks().len(), 3); // 4 + 4 + 2 runs
    let (done, cancel) = (AtomicU64::new(0), AtomicBool::new(false));
    // computed last chunk first, each through its bytes
    let mut bytes: Vec<(usize, Vec<u8>)> = (0..3)
        .rev()
        .map(|i| (i, c.run_chunk(i, &done, &cancel).unwrap().to_bytes()))
        .collect();
    bytes.sort_by_key(|(i, _)| *i);
    let parts: Vec<Partial> = bytes
        .iter()
        .map(|(_, b)| Partial::from_bytes(b).unwrap())
        .collect();
    assert_eq!(parts[1].to_bytes(), bytes[1].1, "bytes round trip");
    let mut r = c.reducer();
    let err = r.add(&c, &parts[1]).unwrap_err();
    assert!(err.contains("expected chunk 0"), "{err}");
    for p in &parts {
        r.add(&c, p).unwrap();
    }
    assert!(r.add(&c, &parts[2]).is_err(), "a chunk added twice");
    let apart = c.finish(r);
    let strip = |mut r: relnav_eval::results::McResult| {
        for f in &mut r.filters {
            f.us_per_step = 0.0;
        }
        r
    };
    assert_eq!(format!("{:?}", strip(whole)), format!("{:?}", strip(apart)));
    // another campaign's sums do not fit
    let other = Campaign::new(&s, Some(12)).unwrap();
    let mut r = other.reducer();
    for p in &parts[..2] {
        r.add(&other, p).unwrap(); // the first two chunks are the same runs
    }
    assert!(
        r.add(&other, &parts[2]).is_err(),
        "runs 8..10 are not chunk 2 of 12 runs"
    );
    // damaged bytes are refused, not misread
    let b = &bytes[0].1;
    assert!(Partial::from_bytes(&b[..b.len() - 1]).is_err());
    assert!(Partial::from_bytes(&[b.as_slice(), &[0]].concat()).is_err());
    assert!(Partial::from_bytes(b"RNPART99").is_err());
}

#[test]
fn every_builtin_scenario_runs() {
    for (name, text) in builtin::for_paper("all") {
        let mut s = Scenario::from_toml(text).unwrap();
        // every filter of every file runs; short runs keep the particle filters cheap
        s.simulation.duration = s.simulation.duration.min(40.0);
        let r = run(
            &s,
            &Options {
                runs: Some(2),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(r.runs, 2, "{name}");
        assert!(r.filters.iter().all(|f| f.mse.len() == r.t.len()), "{name}");
    }
}

/// Relative GNSS position and velocity are linear: the Kalman filters are the Bayes filter
/// there, and each is within 1.1x of the multi-sensor PCRLB (the Monte Carlo RMSE of 10
/// runs over 1,100 correlated times is within a few per cent of its mean).
#[test]
fn kalman_filters_reach_the_pcrlb_on_relative_gnss() {
    let text = builtin::by_name("sensors_gnss_leo").unwrap();
    let mut s = Scenario::from_toml(text).unwrap();
    s.filters
        .retain(|f| f.kind() != relnav_core::nav::FilterKind::Rpf);
    let r = run(
        &s,
        &Options {
            runs: Some(10),
            ..Default::default()
        },
    )
    .unwrap();
    for x in summarize(&r) {
        let (e, ev) = (x.efficiency_pos.unwrap(), x.efficiency_vel.unwrap());
        if x.label == "H-inf" {
            // its design for GNSS position and velocity (hinf_sensors = 12); its track
            // initiation is the Kalman filter of the design's noise model, whose robustness
            // term (the orbit rate within 5 %) is process noise the truth does not have
            // (measured: 1.03 / 1.13)
            assert!(e <= 1.1 && ev <= 1.2, "{}: {e} / {ev}", x.label);
            continue;
        }
        assert!(e <= 1.1 && e > 0.9, "{}: {e}", x.label);
        assert!(ev <= 1.1, "{}", x.label);
    }
}

/// Where the H-infinity design claims to win, it does: on the far-to-near handover with
/// the truth's orbit rate 3 % off every filter's (inside the design's bound of 5 %), the
/// H-infinity filter designed for the camera and GNSS position (`hinf_sensors` = 6; the
/// radio and lidar enter as fixes of their own weight) has less than half the position
/// RMSE of the EKF, the AQUKF and the IMM (measured over 5 runs: 2.4 m against 20.3, 7.3
/// and 8.9 m).
#[test]
fn hinf_beats_the_kalman_filters_under_an_orbit_rate_error_at_handover() {
    let text = builtin::by_name("sensors_handover_rate_error").unwrap();
    let mut s = Scenario::from_toml(text).unwrap();
    s.filters
        .retain(|f| ["EKF", "AQUKF", "IMM", "H-inf"].contains(&f.label.as_str()));
    assert_eq!(s.filters.len(), 4);
    let r = run(
        &s,
        &Options {
            runs: Some(3),
            ..Default::default()
        },
    )
    .unwrap();
    let rows = summarize(&r);
    let rmse = |l: &str| rows.iter().find(|x| x.label == l).unwrap().rmse_pos;
    let h = rmse("H-inf");
    for l in ["EKF", "AQUKF", "IMM"] {
        assert!(h < 0.5 * rmse(l), "H-inf {h} m against {l} {} m", rmse(l));
    }
}

/// Angles-only acquisition (camera alone, V-bar hold 2 km behind, range known to 30 %,
/// two known burns), the scenario's 50 runs, after the second burn, against the run-wise
/// bound: the EKF alone is within 2x; the UKF and the IMM as range-parameterised banks
/// (`range_bank` = 7) are within 1.3x with the time-averaged NEES inside the per-time 95 %
/// band of the 50-run average and at least 3/4 of the times in it; alone they are not
/// (the reason for the bank). The range itself: before the first burn one filter reports
/// less than half the range uncertainty the bound keeps (its range has collapsed) and
/// after the burns half its actual range error; a bank reports what it has (RMS error over
/// RMS `range_sigma` within 0.8-1.25).
#[test]
fn range_banks_reach_the_bound_on_angles_only_acquisition() {
    let text = builtin::by_name("sensors_angles_only").unwrap();
    let mut s = Scenario::from_toml(text).unwrap();
    s.filters
        .retain(|f| ["EKF", "UKF", "UKF bank", "IMM bank"].contains(&f.label.as_str()));
    assert_eq!(s.filters.len(), 4);
    let r = run(&s, &Options::default()).unwrap();
    // the range: what each filter reports (range_sigma) against its RMS error, before the
    // first burn (590 s: angles alone, the range unobservable) and after the second
    let after: Vec<usize> = (0..r.t.len()).filter(|&k| r.t[k] >= 1900.0).collect();
    let rms = |v: &[f64]| (after.iter().map(|&k| v[k]).sum::<f64>() / after.len() as f64).sqrt();
    let bound_590 = r.range_bound_runs[590].sqrt();
    assert!(
        bound_590 > 450.0,
        "run-wise range bound at 590 s: {bound_590}"
    );
    for f in &r.filters {
        let (sigma_590, err_590) = (f.range_var[590].sqrt(), f.range_mse[590].sqrt());
        let (err, sigma) = (rms(&f.range_mse), rms(&f.range_var));
        println!(
            "{}: range at 590 s: error {err_590:.0} m, range_sigma {sigma_590:.0} m (bound \
             {bound_590:.0} m); after the burns: error {err:.1} m, range_sigma {sigma:.1} m",
            f.label
        );
        if f.label.ends_with("bank") {
            assert!(sigma_590 > 0.7 * bound_590, "{}: {sigma_590}", f.label);
            assert!(
                err / sigma > 0.8 && err / sigma < 1.25,
                "{}: {err} / {sigma}",
                f.label
            );
        } else {
            // one filter claims the range it cannot know, and twice the precision it has
            assert!(sigma_590 < 0.5 * bound_590, "{}: {sigma_590}", f.label);
            assert!(err / sigma > 1.5, "{}: {err} / {sigma}", f.label);
        }
    }
    for x in summarize(&r) {
        let ratio = x.efficiency_runs_pos.unwrap();
        let nees = x.nees.clone().unwrap();
        println!(
            "{}: {ratio:.3} x the run-wise bound, NEES {:.2} (band {:.2}-{:.2}, {:.0} % in it)",
            x.label,
            nees.avg,
            nees.band.0,
            nees.band.1,
            100.0 * nees.in_band
        );
        assert_eq!(x.failed_runs, 0, "{}", x.label);
        match x.label.as_str() {
            "EKF" => assert!(ratio <= 2.0, "EKF: {ratio}"),
            "UKF" => assert!(ratio > 1.3, "the UKF alone: {ratio}"),
            _ => {
                assert!(ratio <= 1.3, "{}: {ratio}", x.label);
                assert!(
                    nees.avg > nees.band.0 && nees.avg < nees.band.1 && nees.in_band >= 0.75,
                    "{}: NEES {nees:?}",
                    x.label
                );
            }
        }
    }
}

/// Angles-only acquisition with the particle prior (`pf_prior = particle`: a Gaussian per
/// particle), 500 particles, the scenario's first 12 runs: after the second burn every kind
/// is within 1.2 times the run-wise bound with its time-averaged NEES inside the per-time
/// 95 % band of a 12-run average. Between the burns (the range partly observed, its
/// posterior skewed) every kind's position RMSE is below 0.6 times the EKF's and the UKF's
/// and within 1.15 times the best range-parameterised bank's: the bank is a Gaussian sum
/// too, and over many runs the two are level there (`docs/results.md`); over 12 runs the
/// kinds scatter by about a tenth about the bank.
#[test]
fn particle_prior_reaches_the_bound_on_angles_only_acquisition() {
    let text = builtin::by_name("sensors_angles_only").unwrap();
    let mut s = Scenario::from_toml(text).unwrap();
    s.filters.retain(|f| {
        f.label.ends_with("(particle prior)")
            || ["EKF", "UKF", "EKF bank", "UKF bank"].contains(&f.label.as_str())
    });
    assert_eq!(s.filters.len(), 9);
    let r = run(
        &s,
        &Options {
            runs: Some(12),
            ..Options::default()
        },
    )
    .unwrap();
    let between: Vec<usize> = (0..r.t.len())
        .filter(|&k| r.t[k] >= 660.0 && r.t[k] < 1800.0)
        .collect();
    let rmse_between = |f: &relnav_eval::results::FilterStats| {
        let sum: f64 = between
            .iter()
            .map(|&k| f.mse[k][..3].iter().sum::<f64>())
            .sum();
        (sum / between.len() as f64).sqrt()
    };
    let best = |banks: bool| {
        r.filters
            .iter()
            .filter(|f| !f.label.ends_with("(particle prior)"))
            .filter(|f| f.label.ends_with("bank") == banks)
            .map(rmse_between)
            .fold(f64::INFINITY, f64::min)
    };
    let (single, bank) = (best(false), best(true));
    for (f, x) in r.filters.iter().zip(summarize(&r)) {
        let ratio = x.efficiency_runs_pos.unwrap();
        let nees = x.nees.clone().unwrap();
        let b = rmse_between(f);
        println!(
            "{}: between the burns {b:.1} m (best single Kalman filter {single:.1} m, best \
             bank {bank:.1} m); after: \
             {ratio:.3} x the run-wise bound, NEES {:.2} (band {:.2}-{:.2})",
            x.label, nees.avg, nees.band.0, nees.band.1
        );
        assert_eq!(x.failed_runs, 0, "{}", x.label);
        if x.label.ends_with("(particle prior)") {
            assert!(ratio <= 1.2, "{}: {ratio}", x.label);
            assert!(
                nees.avg > nees.band.0 && nees.avg < nees.band.1,
                "{}: NEES {nees:?}",
                x.label
            );
            assert!(b < 0.6 * single, "{}: {b} against {single}", x.label);
            assert!(b < 1.15 * bank, "{}: {b} against {bank}", x.label);
        }
    }
}

/// The particle prior's terms (EKF and UKF) update with the [sensor]'s density, as the
/// robust EKF does (the engine gives both the density; the point particles weigh with it
/// themselves); the Gaussian-prior points keep the Gaussian setting.
#[test]
fn particle_prior_ekf_terms_get_the_sensor_density() {
    use relnav_core::nav::NoiseKind;
    let s = Scenario::from_toml(builtin::by_name("pf_lidar_wide_prior").unwrap()).unwrap();
    let n = s.orbit.mean_motion().unwrap();
    let model = |label: &str| {
        let f = s.filters.iter().find(|f| f.label == label).unwrap();
        f.nav_config(&s, n).unwrap().noise_model
    };
    for label in [
        "Robust EKF",
        "SIR (particle prior)",
        "RPF (particle prior)",
        "GA-PF (particle prior)",
        "UPF (particle prior)",
    ] {
        assert_eq!(model(label), NoiseKind::Mixture, "{label}");
    }
    for label in ["EKF", "SIR"] {
        assert_eq!(model(label), NoiseKind::Gaussian, "{label}");
    }
}

/// On the far-to-near handover (camera, radio inside 1 km, lidar inside 200 m, GNSS with
/// outages) no filter's estimate jumps at a change of the sensor set by more than 3 sigma
/// of the uncertainty it reported just before, on any axis.
#[test]
fn no_estimate_jumps_at_a_sensor_handover() {
    use rand::SeedableRng;
    let text = builtin::by_name("sensors_handover").unwrap();
    let s = Scenario::from_toml(text).unwrap();
    let prep = Prepared::new(&s).unwrap();
    for run_index in 0..2u64 {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(run_index);
        let run = prep.simulate_truth(&mut rng);
        let present =
            |k: usize| -> Vec<bool> { run.extra.iter().map(|e| e[k].is_some()).collect() };
        let handovers: Vec<usize> = (1..=prep.steps)
            .filter(|&k| present(k) != present(k - 1))
            .collect();
        // the camera every second; the radio's and lidar's starts, GNSS's outages
        assert!(handovers.len() >= 6, "{handovers:?}");
        for f in &prep.filters {
            // the H-infinity filter reports no covariance: a 3-sigma criterion has no sigma
            if f.config.filter == relnav_core::nav::FilterKind::Hinf {
                continue;
            }
            let mut est = f.instantiate(run_index).unwrap();
            let mut before = (relnav_core::types::State::zeros(), [0.0; 6]);
            for k in 0..=prep.steps {
                for (i, sensor) in prep.sensors.iter().enumerate() {
                    if let Some(z) = &run.extra[i][k] {
                        sensor.nav.apply(&mut est, &z[..sensor.nav.dim()]).unwrap();
                    }
                }
                let e = est.state() - run.states[k];
                if handovers.contains(&k) {
                    for a in 0..6 {
                        let jump = (e[a] - before.0[a]).abs();
                        assert!(
                            jump <= 3.0 * before.1[a],
                            "{} run {run_index}, t = {k} s, axis {a}: the error jumps by {jump:.3e}, \
                             3 sigma before was {:.3e}",
                            f.label,
                            3.0 * before.1[a]
                        );
                    }
                }
                let p = est.covariance();
                before = (e, std::array::from_fn(|a| p[(a, a)].sqrt()));
                if k < prep.steps {
                    est.predict(
                        &f.model_at(k as f64 * prep.dt, prep.dt),
                        &prep.burn_accel[k],
                    )
                    .unwrap();
                }
            }
        }
    }
}

/// The bound along each run's own truth: with one run it is the PCRLB itself; with
/// several it is at or above it (Jensen's inequality), and with angles only, before any
/// burn, it keeps the range as unknown as the prior (the range is unobservable under linear
/// dynamics), while the PCRLB, which averages the information of runs whose lines of sight
/// differ, claims it known to a few metres.
#[test]
fn the_run_wise_bound_keeps_angles_only_range_unobservable() {
    let text = builtin::by_name("sensors_angles_only").unwrap();
    let mut s = Scenario::from_toml(text).unwrap();
    s.simulation.duration = 300.0; // before the first burn (600 s)
    s.filters.truncate(1);
    let one = run(
        &s,
        &Options {
            runs: Some(1),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(one.pcrlb_runs, one.pcrlb);
    let many = run(
        &s,
        &Options {
            runs: Some(8),
            ..Default::default()
        },
    )
    .unwrap();
    let (b, w) = (many.pcrlb.unwrap(), many.pcrlb_runs.unwrap());
    for (k, (bk, wk)) in b.iter().zip(&w).enumerate() {
        for i in 0..6 {
            assert!(
                wk[i] >= bk[i] * (1.0 - 1e-9),
                "t = {k}, axis {i}: {} < {}",
                wk[i],
                bk[i]
            );
        }
    }
    // the along-track (range) axis at 300 s: the prior's 600 m projected on the lines of
    // sight, against the PCRLB's few metres
    let (bound_y, runs_y) = (b[300][1].sqrt(), w[300][1].sqrt());
    println!("along-track bound at 300 s, 8 runs: PCRLB {bound_y:.2} m, run-wise {runs_y:.1} m");
    assert!(runs_y > 400.0, "run-wise range bound {runs_y} m");
    assert!(
        bound_y < runs_y / 10.0,
        "PCRLB {bound_y} m vs run-wise {runs_y} m"
    );
}
