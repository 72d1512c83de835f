//! Particle filters: the literal SIR's convergence to the Kalman filter on a
//! linear-Gaussian problem as N grows, and the moving filters' agreement with it at any
//! N; the literal SIR's collapse on paper 000 and its fixes; degeneration with small
//! process noise without moves; thread-count independence of the parallel path;
//! parameter checks; the papers' examples through the evaluation engine.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use rand::Rng;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use relnav_core::dynamics::{CwModel, Discretization};
use relnav_core::estimators::pf::resample::Resampler;
use relnav_core::estimators::pf::{Kernel, ParticleFilter, PfInit, PfKind, PfParams, PfPrior};
use relnav_core::estimators::{Ekf, Estimator};
use relnav_core::frames::Frame;
use relnav_core::nav::{FilterKind, NavConfig, Navigator};
use relnav_core::sensors::{CartesianSensor, MeasurementModel, RadioSensor};
use relnav_core::types::{Mat3, Mat6, State, Vec3};

/// Mean over time of |x_pf - x_kf| (position) on a linear-Gaussian problem where the KF
/// is the exact posterior mean, and the mean posterior position sd.
fn pf_vs_kf(particles: usize, seed: u64) -> (f64, f64) {
    pf_vs_kf_with(particles, seed, false)
}

fn pf_vs_kf_with(particles: usize, seed: u64, moves: bool) -> (f64, f64) {
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
        moves,
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

/// The literal SIR (no moves): its Monte Carlo error falls with N.
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

/// With moves, on a linear measurement with Gaussian noise the rejuvenation's Gaussian
/// proposal is the target itself: every proposal is accepted and the control-variate
/// moments are the Kalman update of the predictive moments, which are propagated exactly
/// — the filter is the Kalman filter to rounding, at any particle count (here 100).
#[test]
fn moving_sir_is_the_kalman_filter_on_a_linear_gaussian_problem() {
    for seed in 0..3 {
        let (e, sd) = pf_vs_kf_with(100, seed, true);
        assert!(
            e < 1e-9 * sd,
            "seed {seed}: {e} m from the KF (posterior sd {sd} m)"
        );
    }
}

/// Paper 000's example, noise-free truth here: run a PF (generator seed `seed`,
/// measurement-noise seed `seed + 12`) for 100 steps, return the final position error and
/// the ESS right after the first update. `kernel`: an RPF with it, else a SIR.
fn paper000_pf(init: PfInit, kernel: Option<Kernel>, seed: u64, moves: bool) -> (f64, f64) {
    let kind = if kernel.is_some() {
        PfKind::Rpf
    } else {
        PfKind::Sir
    };
    paper000_pf_kind(kind, init, kernel.unwrap_or_default(), seed, moves)
}

fn paper000_pf_kind(
    kind: PfKind,
    init: PfInit,
    kernel: Kernel,
    seed: u64,
    moves: bool,
) -> (f64, f64) {
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
        kernel,
        seed,
        moves,
        ..PfParams::new(kind)
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
        let (err_literal, ess_literal) = paper000_pf(PfInit::Prior, None, seed, false);
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
        .map(|s| paper000_pf(PfInit::FirstMeasurement, None, s, false).0)
        .collect();
    assert!(rms(&fm) > 2.0, "first-measurement init alone: {fm:?} m");
    // plain regularisation after each resampling refines the velocities: decimetres in
    // every run, as the EKF; so does the MH-accepted kernel of the moving RPF
    for moves in [false, true] {
        for kernel in [Kernel::Gaussian, Kernel::Epanechnikov] {
            for seed in SEEDS {
                let (err, _) = paper000_pf(PfInit::FirstMeasurement, Some(kernel), seed, moves);
                assert!(
                    err < 0.5,
                    "{kernel:?} (moves {moves}), seed {seed}: final position error {err} m"
                );
            }
        }
    }
    // with the moves every kind reaches decimetres in every run, even from the prior (the
    // rejuvenation replaces the collapsed set by draws from the Gaussian update)
    for kind in [PfKind::Sir, PfKind::Upf, PfKind::Gapf, PfKind::Cgapf] {
        for init in [PfInit::FirstMeasurement, PfInit::Prior] {
            for seed in 0..3 {
                let (err, _) = paper000_pf_kind(kind, init, Kernel::Gaussian, seed, true);
                assert!(
                    err < 0.5,
                    "{kind:?} from {init:?}, seed {seed}: final position error {err} m"
                );
            }
        }
    }
}

/// Paper 000's geometry with an honest small process noise: a quiet truth (no process
/// noise), filters told a white acceleration of 1e-10 m^2/s^3 and nothing else, 300 s at
/// 1 Hz. Position and velocity RMSE over t >= 80 s of the navigator's predicted estimate,
/// per seed, for one filter kind; the EKF's on the same measurements.
fn small_q_run(filter: FilterKind, pf_move: bool, seed: u64) -> (f64, f64) {
    let cfg = NavConfig {
        filter,
        pf_move,
        pf_prior: PfPrior::Gaussian,
        seed,
        accel_psd: 1e-10,
        q_pos: [0.0; 3],
        q_vel: [0.0; 3],
        ..Default::default()
    };
    let f = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let phi = model.phi(1.0);
    let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
    let mut rng = ChaCha8Rng::seed_from_u64(1000 + seed);
    let mut xt = f.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    let mut nav = Navigator::new(&cfg).unwrap();
    let (mut sp, mut sv, mut n) = (0.0, 0.0, 0.0);
    for k in 0..300 {
        let z = sensor
            .measure(&xt.fixed_rows::<3>(0).into_owned(), &mut rng)
            .unwrap();
        nav.step(&[0.0; 3], Some(&[z.x, z.y, z.z]), 1.0).unwrap();
        xt = phi * xt;
        if k + 1 >= 80 {
            let e = nav.state() - f.state_from_canonical(&xt);
            sp += e.fixed_rows::<3>(0).norm_squared();
            sv += e.fixed_rows::<3>(3).norm_squared();
            n += 1.0;
        }
    }
    ((sp / n).sqrt(), (sv / n).sqrt())
}

/// Small honest process noise: every kind with its moves stays within the particle
/// filters' margins of the EKF (1.3 times its position RMSE, 2 times its velocity RMSE) in
/// every seed, where the literal SIR degenerates (more than 3 times the EKF's position
/// error in every seed; through the FMU, hundreds of times).
#[test]
fn small_process_noise_moving_filters_match_the_ekf_literal_sir_degenerates() {
    for seed in 0..2 {
        let (ep, ev) = small_q_run(FilterKind::Ekf, true, seed);
        for kind in [
            FilterKind::Pf,
            FilterKind::Rpf,
            FilterKind::Upf,
            FilterKind::Gapf,
            FilterKind::Cgapf,
        ] {
            let (p, v) = small_q_run(kind, true, seed);
            eprintln!(
                "seed {seed} {}: pos {p:.4} m ({:.2} x EKF), vel {v:.6} m/s ({:.2} x EKF)",
                kind.name(),
                p / ep,
                v / ev
            );
            assert!(
                p < 1.3 * ep && v < 2.0 * ev,
                "{kind:?} seed {seed}: {p} / {v} vs EKF {ep} / {ev}"
            );
        }
        let (p, _) = small_q_run(FilterKind::Pf, false, seed);
        assert!(p > 3.0 * ep, "literal SIR seed {seed}: {p} m vs EKF {ep} m");
    }
}

/// From `PARALLEL_MIN_PARTICLES` particles on the particle loops run in chunks with their
/// own generators: one, two or three worker threads give bit-identical particles,
/// weights, means, covariances, resampling counts and move acceptances for every kind, with
/// and without moves, in runs where a resampling happened.
#[test]
fn parallel_path_is_independent_of_the_thread_count() {
    use relnav_core::estimators::pf::PARALLEL_MIN_PARTICLES;
    let cfg = NavConfig::default();
    let f = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    d.q += f.cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&[
        0.09, 0.000625, 0.0025, 1e-6, 1e-6, 1e-6,
    ])));
    let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
    let x0 = f.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    let particles = PARALLEL_MIN_PARTICLES + 1001; // a short last chunk
    for (kind, moves) in PfKind::ALL
        .into_iter()
        .flat_map(|k| [(k, true), (k, false)])
    {
        let run = |threads: usize| {
            let params = PfParams {
                particles,
                seed: 5,
                moves,
                threads,
                ..PfParams::new(kind)
            };
            let mut pf = ParticleFilter::new(cfg.initial_state(), cfg.initial_covariance(), params);
            let mut rng = ChaCha8Rng::seed_from_u64(3);
            let mut xt = x0;
            for _ in 0..4 {
                let z = sensor
                    .measure(&xt.fixed_rows::<3>(0).into_owned(), &mut rng)
                    .unwrap();
                pf.update(&sensor, &z).unwrap();
                pf.predict(&d, &Vec3::new(1e-3, 0.0, 0.0)).unwrap();
                xt = d.phi * xt;
            }
            let counts = (pf.resample_count(), pf.move_acceptance().to_bits());
            let (x, w) = pf.particles();
            (
                x.to_vec(),
                w.to_vec(),
                *pf.state(),
                *pf.covariance(),
                pf.ess(),
                counts,
            )
        };
        let one = run(1);
        assert!(one.2.iter().all(|v| v.is_finite()));
        assert!(
            one.5 .0 >= 1,
            "{kind:?} (moves {moves}): no resampling in the run"
        );
        for threads in [2, 3] {
            let other = run(threads);
            assert!(
                one.0 == other.0 && one.1 == other.1,
                "{kind:?} (moves {moves}): particles differ with {threads} threads"
            );
            assert!(
                one.2 == other.2 && one.3 == other.3 && one.4 == other.4,
                "{kind:?} (moves {moves}): moments differ with {threads} threads"
            );
            assert_eq!(
                one.5, other.5,
                "{kind:?} (moves {moves}): resamplings or acceptance differ with {threads} threads"
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
    // a Gaussian per particle: at most MAX_GAUSSIAN_SUM of them
    use relnav_core::estimators::pf::{PfPrior, MAX_GAUSSIAN_SUM};
    let p = PfParams {
        particles: MAX_GAUSSIAN_SUM + 1,
        prior: PfPrior::Particle,
        ..Default::default()
    };
    assert!(p.validate().unwrap_err().contains("pf_prior = particle"));
    let p = PfParams {
        particles: MAX_GAUSSIAN_SUM + 1,
        ..Default::default()
    };
    assert!(p.validate().is_ok());
    for t in [0.0, -0.1, 1.5, f64::NAN] {
        let p = PfParams {
            threshold: t,
            ..Default::default()
        };
        assert!(p.validate().unwrap_err().contains("threshold"), "{t}");
    }
    let p = PfParams {
        threads: relnav_core::estimators::pf::MAX_THREADS + 1,
        ..Default::default()
    };
    assert!(p.validate().unwrap_err().contains("threads"));
    assert!(PfParams::default().validate().is_ok());
    // the literal unscented filters need a transition density, the moving ones do not
    let cfg = NavConfig {
        filter: FilterKind::Upf,
        q_pos: [0.0; 3],
        q_vel: [0.0; 3],
        accel_psd: 0.0,
        ..Default::default()
    };
    assert!(cfg.validate().is_ok());
    let literal = NavConfig {
        pf_move: false,
        pf_prior: PfPrior::Gaussian,
        ..cfg
    };
    assert!(literal.validate().unwrap_err().message.contains("pf_move"));
}

/// Run a built-in scenario with only the `keep` filters, `runs` runs, `duration` seconds.
fn reproduce(
    name: &str,
    keep: &[&str],
    runs: u32,
    duration: f64,
) -> Vec<relnav_eval::metrics::Summary> {
    use relnav_eval::{builtin::BUILTIN, metrics::summarize, runner, scenario::Scenario};
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
    sm: &'a [relnav_eval::metrics::Summary],
    label: &str,
) -> &'a relnav_eval::metrics::Summary {
    sm.iter().find(|s| s.label == label).unwrap()
}

/// Paper 000 (radio, 0.5 m / 0.01 deg, the paper's process noise driving the truth), 8
/// runs over its 600 s, errors averaged after 80 s. With their moves every particle filter
/// is as good as the EKF, which sits on the PCRLB here (efficiency 0.98 / 1.00): the
/// paper's 0.4 m, and within 10 % of the bound in position and velocity (an efficient
/// estimator's RMSE over 8 runs scatters by a few per cent around the bound; the EKF's is
/// asserted the same way). The literal SIR and the SIR without moves fail, as documented
/// (docs/filters.md, "`pf_move`: Gaussian-prior moves").
#[test]
fn paper000_particle_filters_meet_their_reproduced_bars() {
    let moving = ["SIR PF", "RPF", "UPF", "GA-PF", "CGA-PF"];
    let literal = [
        "SIR PF (literal)",
        "RPF (literal)",
        "UPF (literal)",
        "GA-PF (literal)",
        "CGA-PF (literal)",
    ];
    let mut labels = vec!["EKF", "SIR PF (no move)"];
    labels.extend(moving);
    labels.extend(literal);
    let sm = reproduce("paper000", &labels, 8, 600.0);
    for s in &sm {
        eprintln!(
            "{}: {:.3} m, {:.4} m/s, efficiency {:?} / {:?}",
            s.label, s.rmse_pos, s.rmse_vel, s.efficiency_pos, s.efficiency_vel
        );
    }
    for l in moving.iter().chain(&["EKF"]) {
        let s = row(&sm, l);
        assert_eq!(s.failed_runs, 0, "{l}");
        assert!(s.rmse_pos < 0.4, "{l}: position RMSE {}", s.rmse_pos);
        let (ep, ev) = (s.efficiency_pos.unwrap(), s.efficiency_vel.unwrap());
        assert!(ep < 1.1 && ev < 1.1, "{l}: efficiency {ep} / {ev}");
    }
    // the failures the module documentation explains: as written (drawn from the 50 m
    // prior) every kind misses the paper's bar by far; the CGA-PF, whose UKF proposal
    // reaches the measurement, least (docs/results.md)
    for l in literal {
        assert!(row(&sm, l).rmse_pos > 2.0, "{l}");
    }
    assert!(row(&sm, "SIR PF (no move)").rmse_pos > 2.0);
}

/// Paper 003's example with the papers' filters as written (`move = false`: drawn from the
/// prior, multinomial resampling, the genetic operators accepted on the likelihood ratio)
/// beside the same kinds with the moves, on the same 16 runs: as written each kind is
/// behind in velocity, where the likelihood does not reach (the 100-run figures:
/// docs/results.md), and none fails.
#[test]
fn paper003_filters_as_written_trail_the_moved_ones() {
    const KINDS: [&str; 5] = ["PF", "RPF", "UPF", "GA-PF", "CGA-PF"];
    let literal: Vec<String> = KINDS.iter().map(|k| format!("{k} (literal)")).collect();
    let mut labels: Vec<&str> = KINDS.to_vec();
    labels.extend(literal.iter().map(String::as_str));
    let sm = reproduce("paper003", &labels, 16, 100.0);
    for (k, l) in KINDS.iter().zip(&literal) {
        let (moved, written) = (row(&sm, k), row(&sm, l));
        eprintln!(
            "{k}: {:.2} m {:.3} m/s; as written {:.2} m {:.3} m/s",
            moved.rmse_pos, moved.rmse_vel, written.rmse_pos, written.rmse_vel
        );
        assert_eq!(written.failed_runs, 0, "{l}");
        assert!(
            written.rmse_vel > 1.1 * moved.rmse_vel,
            "{l}: {} vs {}",
            written.rmse_vel,
            moved.rmse_vel
        );
    }
}

/// Paper 003 (lidar, contaminated Gaussian zeta = 0.2): every particle filter beats the
/// Gaussian EKF by at least 15 % in position, and the unscented ones come within 15 % of a
/// 10 000-particle SIR on the same runs: wide margins, because 16 runs of heavy-tailed
/// errors scatter by several per cent (the 100-run figures: docs/results.md, "Paper 003:
/// lidar with heavy-tailed noise"). The robust EKF (code 11, its Gaussian-sum update) is
/// on the same runs at least 15 % below the EKF and within 1.15 times every particle
/// filter.
#[test]
fn paper003_particle_filters_beat_the_gaussian_filters() {
    const PARTICLE: [&str; 6] = [
        "PF",
        "RPF",
        "UPF",
        "GA-PF",
        "CGA-PF",
        "PF N=10000 (reference)",
    ];
    let mut labels = vec!["EKF", "REKF"];
    labels.extend(PARTICLE);
    let sm = reproduce("paper003", &labels, 16, 100.0);
    for s in &sm {
        eprintln!("{}: {:.2} m", s.label, s.rmse_pos);
    }
    let ekf = row(&sm, "EKF").rmse_pos;
    let reference = row(&sm, "PF N=10000 (reference)").rmse_pos;
    for l in &PARTICLE[..5] {
        let s = row(&sm, l);
        assert_eq!(s.failed_runs, 0, "{l}");
        assert!(s.rmse_pos < 0.85 * ekf, "{l}: {} vs EKF {ekf}", s.rmse_pos);
    }
    for l in ["UPF", "CGA-PF"] {
        let r = row(&sm, l).rmse_pos;
        assert!(r < 1.15 * reference, "{l}: {r} vs reference {reference}");
    }
    let rekf = row(&sm, "REKF");
    assert_eq!(rekf.failed_runs, 0);
    assert!(
        rekf.rmse_pos < 0.85 * ekf,
        "REKF: {} vs EKF {ekf}",
        rekf.rmse_pos
    );
    for l in PARTICLE {
        let r = row(&sm, l).rmse_pos;
        assert!(
            rekf.rmse_pos < 1.15 * r,
            "REKF: {} vs {l} {r}",
            rekf.rmse_pos
        );
    }
}

/// Every particle filter kind, literal and with moves, gives the same bits with its hot
/// loops dispatched to AVX2 (`relnav_core::numerics::simd::dispatch`, where the CPU has it) as
/// on the baseline path (`with_baseline`): particles, weights, mean and covariance after
/// steps of paper 000's model (one thread: the override is per thread).
#[test]
fn dispatched_and_baseline_filters_agree_bit_for_bit() {
    use relnav_core::numerics::simd::with_baseline;
    let cfg = NavConfig::default();
    let f = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    let q = [cfg.q_pos, cfg.q_vel].concat();
    d.q += f.cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&q)));
    let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
    let x0 = f.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    for kind in [
        PfKind::Sir,
        PfKind::Rpf,
        PfKind::Gapf,
        PfKind::Upf,
        PfKind::Cgapf,
    ] {
        for moves in [false, true] {
            let run = || {
                let params = PfParams {
                    particles: 203,
                    seed: 7,
                    threads: 1,
                    moves,
                    ..PfParams::new(kind)
                };
                let mut pf =
                    ParticleFilter::new(cfg.initial_state(), cfg.initial_covariance(), params);
                let mut rng = ChaCha8Rng::seed_from_u64(1);
                for k in 0..12 {
                    let x = model.phi(k as f64) * x0;
                    let z = sensor
                        .measure(&x.fixed_rows::<3>(0).into_owned(), &mut rng)
                        .unwrap();
                    pf.update(&sensor, &z).unwrap();
                    pf.predict(&d, &Vec3::zeros()).unwrap();
                }
                let (x, w) = pf.particles();
                let mut bits: Vec<u64> = x
                    .iter()
                    .flat_map(|s| s.iter().map(|v| v.to_bits()))
                    .collect();
                bits.extend(w.iter().map(|v| v.to_bits()));
                bits.extend(pf.state().iter().map(|v| v.to_bits()));
                bits.extend(pf.covariance().iter().map(|v| v.to_bits()));
                bits
            };
            let fast = run();
            let base = with_baseline(run);
            assert!(fast == base, "{} moves {moves}", kind.name());
        }
    }
}

/// The per-step move acceptance (relnav.fmu's `pf_acceptance`, the C ABI's
/// `relnav_estimator_get_pf_acceptance`): after a step with a reading, every kind with
/// moves reports the fraction of that step's moves accepted, the change of its cumulative
/// counts, in [0, 1]; a step without a reading moves nothing (NaN); the literal SIR
/// (`pf_move = false`) moves nothing; a Kalman filter has no moves; a reset clears it.
#[test]
fn step_acceptance_is_the_fraction_of_the_steps_moves_accepted() {
    use relnav_core::nav::AnyFilter;
    let counts = |nav: &Navigator| match nav.filter() {
        AnyFilter::Pf(pf) => pf.move_counts(),
        _ => (0, 0),
    };
    let codes = [4, 5, 6, 7, 8];
    for (code, moves) in codes
        .into_iter()
        .map(|c| (c, true))
        .chain([(4, false), (1, false)])
    {
        let cfg = NavConfig {
            filter: FilterKind::from_code(code).unwrap(),
            particles: 400,
            pf_move: moves,
            pf_prior: PfPrior::Gaussian,
            ..NavConfig::default()
        };
        let mut nav = Navigator::new(&cfg).unwrap();
        assert!(nav.step_acceptance().is_nan());
        let sensor = RadioSensor::new(cfg.frame, cfg.sigma_range, cfg.sigma_angle);
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let xt = cfg.initial_state();
        let mut seen = 0;
        for k in 0..6 {
            let z = sensor
                .measure(&xt.fixed_rows::<3>(0).into_owned(), &mut rng)
                .unwrap();
            let before = counts(&nav);
            let reading = k != 3;
            let z = [z[0], z[1], z[2]];
            nav.step(&[0.0; 3], reading.then_some(&z), 1.0).unwrap();
            let after = counts(&nav);
            let a = nav.step_acceptance();
            if after.0 > before.0 {
                let expect = (after.1 - before.1) as f64 / (after.0 - before.0) as f64;
                assert_eq!(a.to_bits(), expect.to_bits(), "code {code} step {k}");
                assert!((0.0..=1.0).contains(&a), "code {code} step {k}: {a}");
                seen += 1;
            } else {
                assert!(a.is_nan(), "code {code} step {k}: {a}");
            }
            if !reading {
                assert!(a.is_nan(), "code {code}: a step without a reading moved");
            }
        }
        if moves {
            assert!(seen >= 4, "code {code}: moves in {seen} of 5 updates");
        } else {
            assert_eq!(seen, 0, "code {code} without moves");
        }
        nav.reset();
        assert!(nav.step_acceptance().is_nan());
    }
}

/// The particle prior (a Gaussian per particle) on paper 000's radio example, 40 terms:
/// the same seed gives the same bits, another seed other ones; the terms are resampled;
/// after a resampling the SIR's copies are still copies (it resamples only) while every
/// other kind has separated them (its kernel moves every copy but the first); the sum's
/// mean and covariance are its terms' (within plus between).
#[test]
fn particle_prior_resamples_and_only_the_sir_keeps_copies() {
    use relnav_core::estimators::pf::PfPrior;
    use relnav_core::estimators::GaussianSumPf;
    let cfg = NavConfig::default();
    let f = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
    let x0 = f.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    let (m0, p0) = (cfg.initial_state(), cfg.initial_covariance());
    let run = |kind: PfKind, seed: u64| {
        let params = PfParams {
            particles: 40,
            seed,
            prior: PfPrior::Particle,
            ..PfParams::new(kind)
        };
        let mut g = GaussianSumPf::new(m0, p0, &params, None);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut xt = x0;
        let mut distinct = Vec::new();
        for _ in 0..30 {
            let z = sensor
                .measure(&xt.fixed_rows::<3>(0).into_owned(), &mut rng)
                .unwrap();
            let before = g.stats().1;
            g.update(&sensor, &z).unwrap();
            if g.stats().1 > before {
                let mut means: Vec<[u64; 6]> = g
                    .terms()
                    .iter()
                    .map(|(_, m, _)| core::array::from_fn(|i| m[i].to_bits()))
                    .collect();
                means.sort_unstable();
                means.dedup();
                distinct.push(means.len());
            }
            g.predict(&d, &Vec3::zeros()).unwrap();
            xt = d.phi * xt;
        }
        // the output is the sum's moments
        let terms = g.terms();
        let mean: State = terms.iter().map(|(w, m, _)| m * *w).sum();
        let cov: Mat6 = terms
            .iter()
            .map(|(w, m, p)| (p + (m - mean) * (m - mean).transpose()) * *w)
            .sum();
        assert!((mean - g.state()).amax() <= 1e-9 * mean.amax(), "{kind:?}");
        assert!(
            (cov - g.covariance()).amax() <= 1e-9 * cov.amax(),
            "{kind:?}"
        );
        (g.state().map(f64::to_bits), distinct)
    };
    for kind in PfKind::ALL {
        let (a, distinct) = run(kind, 9);
        assert_eq!(a, run(kind, 9).0, "{kind:?}: not reproducible");
        assert_ne!(a, run(kind, 10).0, "{kind:?}: the seed changes nothing");
        assert!(!distinct.is_empty(), "{kind:?}: never resampled");
        if kind == PfKind::Sir {
            assert!(distinct.iter().all(|&n| n < 40), "SIR: {distinct:?}");
        } else {
            assert!(distinct.iter().all(|&n| n == 40), "{kind:?}: {distinct:?}");
        }
    }
}
