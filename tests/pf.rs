//! Particle filters: convergence to the Kalman filter on a linear-Gaussian problem as N
//! grows, the literal SIR's collapse on paper 000 and its honest fix, parameter checks.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use rand::Rng;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use relnav::dynamics::{CwModel, Discretization};
use relnav::estimators::pf::resample::Resampler;
use relnav::estimators::pf::{Kernel, ParticleFilter, PfInit, PfKind, PfParams};
use relnav::estimators::{Ekf, Estimator};
use relnav::frames::Frame;
use relnav::nav::NavConfig;
use relnav::sensors::{CartesianSensor, MeasurementModel, RadioSensor};
use relnav::types::{Mat3, Mat6, State, Vec3};

/// Mean over time of |x_pf - x_kf| (position) on a linear-Gaussian problem where the KF
/// is the exact posterior mean.
fn pf_vs_kf(particles: usize, seed: u64) -> (f64, f64) {
    let model =
        CwModel::new(1e-3).discretize(1.0, &(Mat3::identity() * 1e-2), Discretization::Exact);
    let sensor = CartesianSensor {
        frame: Frame::RadialAlongNormal,
        sigma: 1.0,
    };
    let x0 = State::from_row_slice(&[100.0, 50.0, -20.0, 0.1, 0.0, 0.05]);
    let p0 = Mat6::from_diagonal(&State::from_row_slice(&[4.0, 4.0, 4.0, 0.01, 0.01, 0.01]));
    let mut kf = Ekf::new(x0, p0);
    let params = PfParams {
        particles,
        init: PfInit::Prior,
        seed,
        ..Default::default()
    };
    let mut pf = ParticleFilter::new(x0, p0, params);
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let mut xt =
        x0 + State::from_fn(|i, _| p0[(i, i)].sqrt() * rng.sample::<f64, _>(StandardNormal));
    let q = nalgebra::SymmetricEigen::new(model.q);
    let qs = q.eigenvectors
        * Mat6::from_diagonal(&q.eigenvalues.map(|v| v.max(0.0).sqrt()))
        * q.eigenvectors.transpose();
    let mut sum = 0.0;
    let mut sd = 0.0;
    let steps = 60;
    for _ in 0..steps {
        let z = sensor.predict(&xt.fixed_rows::<3>(0).into_owned()).unwrap()
            + Vec3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal));
        kf.update(&sensor, &z).unwrap();
        pf.update(&sensor, &z).unwrap();
        sum += (pf.state() - kf.state()).fixed_rows::<3>(0).norm();
        sd += kf.covariance().fixed_view::<3, 3>(0, 0).trace().sqrt();
        kf.predict(&model, &Vec3::zeros()).unwrap();
        pf.predict(&model, &Vec3::zeros()).unwrap();
        xt = model.phi * xt + qs * State::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal));
    }
    (sum / steps as f64, sd / steps as f64)
}

#[test]
fn sir_converges_to_the_kalman_filter_as_n_grows() {
    let avg = |n: usize| (0..4).map(|s| pf_vs_kf(n, s).0).sum::<f64>() / 4.0;
    let (e1, e2, e3) = (avg(100), avg(1000), avg(10_000));
    let sd = pf_vs_kf(100, 0).1;
    eprintln!("|pf - kf|: N=100 {e1}, 1000 {e2}, 10000 {e3}; posterior sd {sd}");
    // Monte Carlo error of a weighted mean falls like 1/sqrt(N_eff): a factor ~3.2 per
    // decade; demand 2 (the resampling noise and the 4-seed average leave margin)
    assert!(
        e2 < e1 / 2.0 && e3 < e2 / 2.0,
        "|pf - kf|: N=100 {e1}, 1000 {e2}, 10000 {e3}"
    );
    // and at N = 10^4 the PF's mean is within a tenth of a posterior standard deviation
    assert!(
        e3 < 0.1 * sd,
        "N = 10000 still {e3} m from the KF (posterior sd {sd} m)"
    );
}

/// Paper 000's example, noise-free truth here: run a PF (generator seed `seed`,
/// measurement-noise seed `seed + 12`) for 100 steps, return the final position error and
/// the ESS right after the first update.
fn paper000_pf(init: PfInit, kernel: Option<Kernel>, seed: u64) -> (f64, f64) {
    let cfg = NavConfig::default();
    let f = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    d.q += f.cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&[
        0.09, 0.000625, 0.0025, 1e-6, 1e-6, 1e-6,
    ])));
    let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
    let params = PfParams {
        particles: 2000,
        resampler: Resampler::Multinomial,
        init,
        kernel: kernel.unwrap_or_default(),
        seed,
        ..PfParams::new(if kernel.is_some() {
            PfKind::Rpf
        } else {
            PfKind::Sir
        })
    };
    let mut pf = ParticleFilter::new(cfg.initial_state(), cfg.initial_covariance(), params);
    let mut rng = ChaCha8Rng::seed_from_u64(seed + 12);
    let x0 = f.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    let mut xt = model.phi(1.0) * x0; // first measurement after one step
    pf.predict(&d, &Vec3::zeros()).unwrap();
    let mut first_ess = f64::NAN;
    for k in 0..100 {
        let z = sensor
            .measure(&xt.fixed_rows::<3>(0).into_owned(), &mut rng)
            .unwrap();
        pf.update(&sensor, &z).unwrap();
        // ESS of the first update that weighs (the first-measurement init consumes k = 0)
        if (init == PfInit::Prior && k == 0) || (init == PfInit::FirstMeasurement && k == 1) {
            first_ess = pf.ess();
        }
        pf.predict(&d, &Vec3::zeros()).unwrap();
        xt = model.phi(1.0) * xt;
    }
    ((pf.state() - xt).fixed_rows::<3>(0).norm(), first_ess)
}

#[test]
fn literal_sir_collapses_on_paper000_and_first_measurement_init_fixes_it() {
    const SEEDS: std::ops::Range<u64> = 0..8;
    let rms = |errs: &[f64]| (errs.iter().map(|e| e * e).sum::<f64>() / errs.len() as f64).sqrt();
    for seed in SEEDS {
        let (err_literal, ess_literal) = paper000_pf(PfInit::Prior, None, seed);
        assert!(
            ess_literal < 2.0,
            "literal SIR, seed {seed}: ESS {ess_literal} after the first update"
        );
        assert!(
            err_literal > 10.0,
            "literal SIR, seed {seed}: final error only {err_literal} m"
        );
    }
    // first-measurement init alone: the positions are right but the velocities are the
    // prior's 2000 draws, none closer than ~0.1 m/s to the truth, and the paper's 1e-3 m/s
    // process noise cannot refine them. Whether a run drifts depends on how close its best
    // velocity draws happen to be (measured after 100 s over these 8 seeds: five runs
    // within 0.3 m, one 1.2 m, two 10 and 17 m; RMS 7 m), so the statement is about the
    // RMS over seeds
    let fm: Vec<f64> = SEEDS
        .map(|s| paper000_pf(PfInit::FirstMeasurement, None, s).0)
        .collect();
    assert!(rms(&fm) > 2.0, "first-measurement init alone: {fm:?} m");
    // regularisation after each resampling refines the velocities: decimetres in every
    // run, as the EKF
    for kernel in [Kernel::Gaussian, Kernel::Epanechnikov] {
        for seed in SEEDS {
            let (err, _) = paper000_pf(PfInit::FirstMeasurement, Some(kernel), seed);
            assert!(
                err < 0.5,
                "{kernel:?}, seed {seed}: final position error {err} m"
            );
        }
    }
}

#[test]
fn bad_parameters_are_rejected() {
    let p = PfParams {
        particles: 0,
        ..Default::default()
    };
    assert!(p.validate().unwrap_err().contains("particles"));
    for t in [0.0, -0.1, 1.5, f64::NAN] {
        let p = PfParams {
            threshold: t,
            ..Default::default()
        };
        assert!(p.validate().unwrap_err().contains("threshold"), "{t}");
    }
    assert!(PfParams::default().validate().is_ok());
}

/// Run a built-in scenario with only the `keep` filters, `runs` runs, `duration` seconds.
fn reproduce(
    name: &str,
    keep: &[&str],
    runs: u32,
    duration: f64,
) -> Vec<relnav::eval::metrics::Summary> {
    use relnav::eval::{builtin::BUILTIN, metrics::summarize, runner, scenario::Scenario};
    let (_, _, text) = BUILTIN.iter().find(|(_, n, _)| *n == name).unwrap();
    let mut s = Scenario::from_toml(text).unwrap();
    s.filters.retain(|f| keep.contains(&f.label.as_str()));
    assert_eq!(s.filters.len(), keep.len(), "{keep:?}");
    s.simulation.duration = duration;
    let r = runner::run(
        &s,
        &runner::Options {
            runs: Some(runs),
            threads: 2,
            ..Default::default()
        },
    )
    .unwrap();
    summarize(&r)
}

fn row<'a>(
    sm: &'a [relnav::eval::metrics::Summary],
    label: &str,
) -> &'a relnav::eval::metrics::Summary {
    sm.iter().find(|s| s.label == label).unwrap()
}

/// Paper 000 (radio, 0.5 m / 0.01 deg), 20 runs over its 600 s, errors averaged after
/// 80 s. Bars: the paper's 0.4 m for position; position and velocity against the PCRLB. A
/// particle filter's velocity error is heavy-tailed across runs (impoverishment strikes
/// some runs much harder), so the campaign is the full 20 runs of the reproduction: with
/// 8 runs the CGA-PF's velocity efficiency was measured at 4.1, over 20 at 1.69 (1.29
/// with the previous generator); RPF 1.31 / 4.26 (docs/evaluation.md). The literal SIR
/// and the SIR without regularisation fail, as documented (measured 670 m and 56 m).
#[test]
fn paper000_particle_filters_meet_their_reproduced_bars() {
    let sm = reproduce(
        "paper000",
        &["SIR PF (literal)", "SIR PF", "RPF", "CGA-PF"],
        20,
        600.0,
    );

    let cga = row(&sm, "CGA-PF");
    assert!(cga.rmse_pos < 0.4, "CGA-PF position RMSE {}", cga.rmse_pos);
    assert!(
        cga.efficiency_pos.unwrap() < 1.3 && cga.efficiency_vel.unwrap() < 3.0,
        "CGA-PF efficiency {:?} / {:?}",
        cga.efficiency_pos,
        cga.efficiency_vel
    );
    let rpf = row(&sm, "RPF");
    assert!(rpf.rmse_pos < 0.4, "RPF position RMSE {}", rpf.rmse_pos);
    assert!(
        rpf.efficiency_vel.unwrap() < 8.0,
        "RPF velocity efficiency {:?}",
        rpf.efficiency_vel
    );
    // the failures the module documentation explains
    assert!(row(&sm, "SIR PF (literal)").rmse_pos > 50.0);
    assert!(row(&sm, "SIR PF").rmse_pos > 2.0);
}

/// Paper 003 (lidar, contaminated Gaussian zeta = 0.2): every particle filter beats the
/// Gaussian EKF by at least 15 % in position (the 100-run reproduction: 26-28 %), and the
/// unscented ones come within 15 % of a 10 000-particle SIR on the same runs (100 runs:
/// 3.1 %; 16 runs of heavy-tailed errors scatter by several per cent).
#[test]
fn paper003_particle_filters_beat_the_gaussian_filters() {
    let labels = [
        "EKF",
        "PF",
        "RPF",
        "UPF",
        "GA-PF",
        "CGA-PF",
        "PF N=10000 (reference)",
    ];
    let sm = reproduce("paper003", &labels, 16, 100.0);
    for s in &sm {
        eprintln!("{}: {:.2} m", s.label, s.rmse_pos);
    }
    let ekf = row(&sm, "EKF").rmse_pos;
    let reference = row(&sm, "PF N=10000 (reference)").rmse_pos;
    for l in ["PF", "RPF", "UPF", "GA-PF", "CGA-PF"] {
        let s = row(&sm, l);
        assert_eq!(s.failed_runs, 0, "{l}");
        assert!(s.rmse_pos < 0.85 * ekf, "{l}: {} vs EKF {ekf}", s.rmse_pos);
    }
    for l in ["UPF", "CGA-PF"] {
        let r = row(&sm, l).rmse_pos;
        assert!(r < 1.15 * reference, "{l}: {r} vs reference {reference}");
    }
}
