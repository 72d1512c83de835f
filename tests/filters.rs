//! Filter behaviour on the library API: paper 000's example against the published figures,
//! UKF = KF on the linear time update, covariance health over 10^5 steps, the azimuth cut
//! and the poles. Truth here is the closed-form CW solution evaluated directly (the Python
//! and C++ suites use their own independent truths).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use relnav_core::dynamics::{CwModel, Discretization};
use relnav_core::estimators::{Ekf, Estimator, Ukf, UkfParams};
use relnav_core::frames::Frame;
use relnav_core::nav::{FilterKind, NavConfig, Navigator};
use relnav_core::sensors::RadioSensor;
use relnav_core::types::{Mat3, Mat6, State, Vec3};

/// Per-axis RMSE over `runs` seeded runs of paper 000's example; returns
/// (worst per-axis RMSE for t >= 80 s, position RMSE over 80..600 s).
fn paper000(cfg: &NavConfig, runs: u64) -> ([f64; 6], f64) {
    let f = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
    let steps = 600;
    let mut se = vec![[0.0f64; 6]; steps + 1];
    for run in 0..runs {
        let mut rng = ChaCha8Rng::seed_from_u64(1000 + run);
        let mut nav = Navigator::new(cfg).unwrap();
        let x0 = State::from_row_slice(&[400.0, 500.0, 200.0, 0.0, 0.0, 0.0]);
        let x0c = f.state_to_canonical(&x0);
        for k in 0..steps {
            let xt = model.phi(k as f64) * x0c;
            let z = sensor
                .measure(&xt.fixed_rows::<3>(0).into_owned(), &mut rng)
                .unwrap();
            nav.step(&[0.0; 3], Some(&[z.x, z.y, z.z]), 1.0).unwrap();
            let truth = f.state_from_canonical(&(model.phi((k + 1) as f64) * x0c));
            let e = nav.state() - truth;
            for i in 0..6 {
                se[k + 1][i] += e[i] * e[i] / runs as f64;
            }
        }
    }
    let mut worst = [0.0f64; 6];
    let mut pos = 0.0;
    for row in se.iter().skip(80) {
        for i in 0..6 {
            worst[i] = worst[i].max(row[i].sqrt());
        }
        pos += row[0] + row[1] + row[2];
    }
    (worst, (pos / (steps - 79) as f64).sqrt())
}

#[test]
fn paper000_published_figures_ekf_and_ukf() {
    for filter in [FilterKind::Ekf, FilterKind::Ukf] {
        for discretization in [Discretization::Exact, Discretization::Euler] {
            let cfg = NavConfig {
                filter,
                discretization,
                ..Default::default()
            };
            let (worst, pos) = paper000(&cfg, 20);
            // paper 000: every axis below 0.5 m and 0.02 m/s after 80 s; position within 0.4 m
            for (i, w) in worst.iter().enumerate() {
                let bar = if i < 3 { 0.5 } else { 0.02 };
                assert!(
                    *w < bar,
                    "{filter:?} {discretization:?} axis {i}: {w} >= {bar}"
                );
            }
            assert!(
                pos < 0.4,
                "{filter:?} {discretization:?}: position RMSE {pos}"
            );
        }
    }
}

#[test]
fn ukf_time_update_equals_kalman_for_linear_dynamics() {
    let model = CwModel::new(1.1e-3);
    let d = model.discretize(7.0, &(Mat3::identity() * 1e-6), Discretization::Exact);
    let x = State::from_row_slice(&[100.0, -50.0, 20.0, 0.1, 0.2, -0.05]);
    let mut p = Mat6::from_fn(|i, j| 0.3_f64.powi((i as i32 - j as i32).abs()));
    p = p * p.transpose() + Mat6::identity();
    let a = Vec3::new(1e-3, 0.0, -2e-3);
    for params in [
        UkfParams::default(),
        UkfParams {
            alpha: 0.5,
            beta: 2.0,
            kappa: -3.0,
        },
    ] {
        let mut ukf = Ukf::new(x, p, params);
        let mut ekf = Ekf::new(x, p);
        ukf.predict(&d, &a).unwrap();
        ekf.predict(&d, &a).unwrap();
        assert!((ukf.state() - ekf.state()).norm() < 1e-9);
        assert!((ukf.covariance() - ekf.covariance()).norm() < 1e-9 * ekf.covariance().norm());
        // the sigma-point time update through the same linear map (the unscented transform
        // the UKF's `predict` replaces by its exact Kalman form) agrees to rounding
        let mut sigma = Ukf::new(x, p, params);
        sigma.predict_with(&d.q, |s| Ok(d.apply(s, &a))).unwrap();
        assert!((sigma.state() - ekf.state()).norm() < 1e-9);
        assert!((sigma.covariance() - ekf.covariance()).norm() < 1e-9 * ekf.covariance().norm());
    }
}

fn assert_spd(p: &Mat6, what: &str) {
    assert!((p - p.transpose()).norm() == 0.0, "{what}: not symmetric");
    assert!(p.cholesky().is_some(), "{what}: not positive definite\n{p}");
}

/// 10^5 steps with measurements every step, long gaps and both filters: the covariance
/// stays exactly symmetric and positive definite, and the error stays consistent.
#[test]
fn covariance_stays_spd_over_1e5_steps() {
    for filter in [FilterKind::Ekf, FilterKind::Ukf] {
        let cfg = NavConfig {
            filter,
            accel_psd: 1e-10,
            ..Default::default()
        };
        let f = cfg.frame;
        let model = CwModel::new(cfg.mean_motion);
        let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
        let mut nav = Navigator::new(&cfg).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(42);
        // a bounded relative orbit (vy = -2 n x canonical) so the geometry stays regular
        let n = cfg.mean_motion;
        let mut xt = State::from_row_slice(&[300.0, 400.0, 100.0, 0.0, -2.0 * n * 300.0, 0.05]);
        let step = model.phi(1.0);
        for k in 0..100_000 {
            let gap = (k / 5000) % 4 == 3 && k % 5000 < 300; // 300 s outages
            let z = sensor
                .measure(&xt.fixed_rows::<3>(0).into_owned(), &mut rng)
                .unwrap();
            let zm = [z.x, z.y, z.z];
            nav.step(&[0.0; 3], if gap { None } else { Some(&zm) }, 1.0)
                .unwrap();
            xt = step * xt;
            if k % 997 == 0 {
                assert_spd(nav.filter().covariance(), &format!("{filter:?} step {k}"));
            }
        }
        assert_spd(nav.filter().covariance(), &format!("{filter:?} end"));
        let e = nav.state() - f.state_from_canonical(&xt);
        let p = nav.covariance();
        for i in 0..6 {
            assert!(
                e[i].abs() < 5.0 * p[(i, i)].sqrt(),
                "{filter:?} axis {i}: {} vs sigma {}",
                e[i],
                p[(i, i)].sqrt()
            );
        }
    }
}

/// A chaser whose azimuth sweeps across the 0 / 2 pi cut: no jump in the estimate.
#[test]
fn azimuth_cut_is_crossed_smoothly() {
    for filter in [FilterKind::Ekf, FilterKind::Ukf] {
        // canonical frame: azimuth = atan2(along, radial); a chaser on the +radial axis,
        // moving along-track through zero: azimuth goes 2 pi - eps -> 0 + eps
        let n = 2.0 * std::f64::consts::PI / 7200.0;
        let x0 = [500.0, -30.0, 50.0, 0.0, 0.5, 0.0];
        let cfg = NavConfig {
            filter,
            frame: Frame::RadialAlongNormal,
            x0: [505.0, -25.0, 45.0, 0.0, 0.4, 0.0],
            sigma_pos0: 20.0,
            sigma_vel0: 0.5,
            q_pos: [0.01; 3],
            q_vel: [1e-6; 3],
            mean_motion: n,
            ..Default::default()
        };
        let model = CwModel::new(n);
        let sensor = RadioSensor::new(cfg.frame, cfg.sigma_range, cfg.sigma_angle);
        let mut nav = Navigator::new(&cfg).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut xt = State::from_row_slice(&x0);
        let mut crossed = false;
        for _ in 0..120 {
            let z = sensor
                .measure(&xt.fixed_rows::<3>(0).into_owned(), &mut rng)
                .unwrap();
            crossed |= z.y < 0.1;
            nav.step(&[0.0; 3], Some(&[z.x, z.y, z.z]), 1.0).unwrap();
            xt = model.phi(1.0) * xt;
            let e = nav.state() - xt;
            if crossed {
                assert!(
                    e.fixed_rows::<3>(0).norm() < 2.0,
                    "{filter:?}: jump at the cut, error {e}"
                );
            }
        }
        assert!(crossed);
    }
}

/// Straight above the target (elevation -> 90 deg) the azimuth is ignored and the filter
/// keeps working on range and elevation; at zero range the update is refused.
#[test]
fn poles_and_zero_range() {
    for filter in [FilterKind::Ekf, FilterKind::Ukf] {
        let cfg = NavConfig {
            filter,
            frame: Frame::RadialAlongNormal,
            x0: [0.0, 0.0, 300.0, 0.0, 0.0, 0.0],
            sigma_pos0: 1e-3,
            ..Default::default()
        };
        let mut nav = Navigator::new(&cfg).unwrap();
        let z = [300.0, 1.0, std::f64::consts::FRAC_PI_2];
        let info = nav.update(&z).unwrap();
        assert!(!info.azimuth_used);
        assert!(nav.state().iter().all(|v| v.is_finite()));
        // zero range: refused, estimate unchanged
        let cfg0 = NavConfig {
            filter,
            x0: [0.0; 6],
            ..Default::default()
        };
        let mut nav0 = Navigator::new(&cfg0).unwrap();
        let before = nav0.state();
        let err = nav0
            .step(&[0.0; 3], Some(&[1.0, 0.0, 0.0]), 1.0)
            .unwrap_err();
        assert!(err.message.contains("range"), "{}", err.message);
        assert_eq!(nav0.state(), before);
    }
}

#[test]
fn invalid_configurations_name_the_parameter() {
    let cases: Vec<(NavConfig, &str)> = vec![
        (
            NavConfig {
                chaser_mass: 0.0,
                ..Default::default()
            },
            "chaser_mass",
        ),
        (
            NavConfig {
                mean_motion: f64::NAN,
                ..Default::default()
            },
            "mean_motion",
        ),
        (
            NavConfig {
                sigma_range: -1.0,
                ..Default::default()
            },
            "sigma_range",
        ),
        (
            NavConfig {
                q_vel: [0.0, -1.0, 0.0],
                ..Default::default()
            },
            "q_vel_y",
        ),
        (
            NavConfig {
                x0: [0.0, f64::INFINITY, 0.0, 0.0, 0.0, 0.0],
                ..Default::default()
            },
            "y0",
        ),
        (
            NavConfig {
                filter: FilterKind::Hinf,
                hinf_delta_bar: -1.0,
                ..Default::default()
            },
            "delta_bar",
        ),
        (
            NavConfig {
                filter: FilterKind::Rpf,
                particles: 0,
                ..Default::default()
            },
            "particles",
        ),
        (
            NavConfig {
                resample_threshold: 1.5,
                ..Default::default()
            },
            "resample_threshold",
        ),
        (
            NavConfig {
                noise_zeta: 1.0,
                ..Default::default()
            },
            "noise_zeta",
        ),
        (
            NavConfig {
                noise_scale: 0.5,
                ..Default::default()
            },
            "noise_scale",
        ),
        (
            NavConfig {
                noise_dof: 2.0,
                ..Default::default()
            },
            "noise_dof",
        ),
        (
            // the literal unscented proposal needs Q > 0 (with the moves, the default, it
            // does not collapse and Q = 0 is allowed)
            NavConfig {
                filter: FilterKind::Upf,
                q_pos: [0.0; 3],
                q_vel: [0.0; 3],
                pf_move: false,
                pf_prior: relnav_core::estimators::pf::PfPrior::Gaussian,
                ..Default::default()
            },
            "q_pos",
        ),
        (
            NavConfig {
                filter: FilterKind::Ukf,
                ukf_alpha: 1.0,
                ukf_beta: 2.0,
                ukf_kappa: -6.0,
                ..Default::default()
            },
            "ukf_kappa",
        ),
    ];
    for (cfg, needle) in cases {
        let e = Navigator::new(&cfg).unwrap_err();
        assert!(e.message.contains(needle), "{needle}: {}", e.message);
    }
    let mut nav = Navigator::new(&NavConfig::default()).unwrap();
    assert!(nav
        .step(&[0.0; 3], None, 0.0)
        .unwrap_err()
        .message
        .contains("step"));
    assert!(nav
        .step(&[f64::NAN, 0.0, 0.0], None, 1.0)
        .unwrap_err()
        .message
        .contains("thrust"));
    assert!(nav.update(&[1.0, f64::NAN, 0.0]).is_err());
    assert!(nav
        .update(&[-1.0, 0.0, 0.0])
        .unwrap_err()
        .message
        .contains("range"));
    assert!(nav
        .update(&[1.0, 0.0, 1.6])
        .unwrap_err()
        .message
        .contains("elevation"));
    // huge initial sigma whose variance overflows; NaN UKF parameter with the EKF selected;
    // a mean motion outside any orbit; tiny numbers are printed readably
    let e = Navigator::new(&NavConfig {
        sigma_pos0: 1e200,
        ..Default::default()
    })
    .unwrap_err();
    assert!(
        e.message.contains("sigma_pos0") && e.message.contains("1e200"),
        "{}",
        e.message
    );
    let e = Navigator::new(&NavConfig {
        ukf_alpha: f64::NAN,
        ..Default::default()
    })
    .unwrap_err();
    assert!(e.message.contains("UKF"), "{}", e.message);
    let e = Navigator::new(&NavConfig {
        mean_motion: 1e-300,
        ..Default::default()
    })
    .unwrap_err();
    assert!(
        e.message.contains("mean_motion") && e.message.len() < 200,
        "{}",
        e.message
    );
    let e = Navigator::new(&NavConfig {
        chaser_mass: -1e-300,
        ..Default::default()
    })
    .unwrap_err();
    assert!(e.message.contains("-1e-300"), "{}", e.message);
}
