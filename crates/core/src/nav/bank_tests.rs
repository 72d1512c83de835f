//! The range-parameterised bank (`range_bank`, [`crate::estimators::bank`]) through the
//! navigator: on relative GNSS it ends where one filter ends (the data outweigh the shape
//! of the prior), a failed step changes nothing, its diagnostics are the mixture's, and
//! the configuration refuses it where it has no meaning.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use super::*;
use crate::dynamics::CwModel;
use crate::estimators::MAX_BANK;
use crate::frames::Frame;
use crate::numerics::state::Persist;

/// The hold of the angles-only scenario: 2 km behind on V-bar, range known to 600 m.
fn hold(filter: FilterKind, bank: usize) -> NavConfig {
    NavConfig {
        filter,
        frame: Frame::RadialAlongNormal,
        x0: [0.0, -2000.0, 0.0, 0.0, 0.0, 0.0],
        sigma_pos0: 20.0,
        sigma_range0: 600.0,
        sigma_vel0: 0.01,
        accel_psd: 1e-10,
        range_bank: bank,
        ..NavConfig::default()
    }
}

/// A GNSS reading of the truth `(0, -1700, 3)` (the prior is 300 m off in range), noise
/// drawn from a fixed sequence.
fn fix(k: usize) -> [f64; 3] {
    let e = |i: usize| ((k * 7 + i * 3) % 11) as f64 / 11.0 - 0.5;
    [0.05 * e(0), -1700.0 + 0.05 * e(1), 3.0 + 0.05 * e(2)]
}

#[test]
fn on_position_fixes_a_bank_ends_where_one_filter_ends() {
    for filter in [FilterKind::Ekf, FilterKind::Ukf, FilterKind::Imm] {
        let mut one = Navigator::new(&hold(filter, 1)).unwrap();
        let mut bank = Navigator::new(&hold(filter, 5)).unwrap();
        // before any measurement the mixture is the prior itself
        assert!((bank.state() - one.state()).norm() < 1e-9);
        assert!((bank.covariance() - one.covariance()).norm() < 1e-6);
        for k in 0..200 {
            let r = Readings {
                gnss_position: Some(fix(k)),
                ..Readings::default()
            };
            one.step_readings(&[0.0; 3], &r, 1.0).unwrap();
            bank.step_readings(&[0.0; 3], &r, 1.0).unwrap();
        }
        let (a, b) = (one.state(), bank.state());
        assert!((a - b).norm() < 1e-6, "{filter:?}: {a} vs {b}");
        let (pa, pb) = (one.covariance(), bank.covariance());
        assert!((pa - pb).norm() < 1e-6 * pa.norm(), "{filter:?}");
        if filter == FilterKind::Imm {
            let mu = bank.mode_probabilities().unwrap();
            assert!((mu.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{mu:?}");
        }
    }
}

#[test]
fn a_failed_bank_step_changes_nothing() {
    let cfg = hold(FilterKind::Ukf, 4);
    let mut f = build_filter(&cfg).unwrap();
    let model = CwModel::new(cfg.mean_motion);
    let mut d = model.discretize(1.0, &(Mat3::identity() * 1e-10), cfg.discretization);
    let mut before = Vec::new();
    f.save_state(&mut crate::numerics::state::Writer::new(&mut before));
    d.q[(0, 0)] = f64::INFINITY;
    assert!(f.predict(&d, &Vec3::zeros()).is_err());
    let mut after = Vec::new();
    f.save_state(&mut crate::numerics::state::Writer::new(&mut after));
    assert_eq!(before, after);
}

#[test]
fn the_bank_reports_the_mixture() {
    let mut nav = Navigator::new(&hold(FilterKind::Ekf, 7)).unwrap();
    let r = Readings {
        camera: Some([-core::f64::consts::FRAC_PI_2 + 1e-3, 0.0]),
        ..Readings::default()
    };
    nav.step_readings(&[0.0; 3], &r, 1.0).unwrap();
    let AnyFilter::Bank(b) = nav.filter() else {
        panic!("not a bank")
    };
    assert_eq!(b.len(), 7);
    let w: f64 = b.weighted().map(|(w, _)| w).sum();
    assert!((w - 1.0).abs() < 1e-12);
    // the camera's NIS is the mixture's, finite; the range's sigma is the mixture's, near
    // the prior's 600 m (one line of sight says nothing about the range)
    assert!(nav.step_nis()[1].is_finite());
    let s = nav.range_sigma();
    assert!(s > 500.0 && s < 650.0, "range sigma {s}");
    // a reset starts the members again from the prior
    let first = {
        let mut x = Vec::new();
        Navigator::new(&hold(FilterKind::Ekf, 7))
            .unwrap()
            .save_state(&mut x);
        x
    };
    nav.reset();
    let mut again = Vec::new();
    nav.save_state(&mut again);
    assert_eq!(first, again);
}

#[test]
fn a_bank_needs_a_kalman_filter_and_a_line_of_sight() {
    for kind in [FilterKind::Pf, FilterKind::Rpf, FilterKind::Hinf] {
        let e = hold(kind, 3).validate().unwrap_err();
        assert!(
            e.message
                .contains("range_bank = 3 needs a Kalman-type filter"),
            "{e}"
        );
    }
    let at_target = NavConfig {
        x0: [0.0; 6],
        sigma_range0: 0.0,
        ..hold(FilterKind::Ekf, 3)
    };
    let e = at_target.validate().unwrap_err();
    assert!(e.message.contains("x0, y0, z0"), "{e}");
    let e = NavConfig {
        range_bank: MAX_BANK + 1,
        ..hold(FilterKind::Ekf, 1)
    }
    .validate()
    .unwrap_err();
    assert!(e.message.contains("range_bank"), "{e}");
}

#[test]
fn sigma_range0_spreads_the_prior_along_the_line_of_sight_alone() {
    let cfg = NavConfig {
        x0: [300.0, -400.0, 0.0, 0.0, 0.0, 0.0],
        ..hold(FilterKind::Ekf, 1)
    };
    let p = cfg.initial_covariance();
    let x0 = cfg.initial_state();
    let r = Vec3::new(x0[0], x0[1], x0[2]);
    assert!((r.norm() - 500.0).abs() < 1e-9);
    let u = r / r.norm();
    let block = p.fixed_view::<3, 3>(0, 0).into_owned();
    assert!((u.dot(&(block * u)) - 600.0f64.powi(2)).abs() < 1e-6);
    let across = u.cross(&Vec3::z()).normalize();
    assert!((across.dot(&(block * across)) - 400.0).abs() < 1e-9);
    assert!((block * Vec3::z() - Vec3::z() * 400.0).norm() < 1e-9);
}
