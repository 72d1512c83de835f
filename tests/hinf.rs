//! Robust H-infinity filter of paper 002: the LMI design (Clarabel) checked independently
//! of the solver — the assembled LMI with nalgebra, stability and the H-infinity norm of the
//! filter-error system over a grid of the true orbit-rate error — for the paper's case, two
//! other orbits, an infeasible request, the paper's published matrices and the open-loop
//! observer design.
#![cfg(feature = "hinf")]
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use relnav::hinf::design::{design_observer, design_open_loop, design_paper, DesignOptions};
use relnav::hinf::verify::{delta_grid, observer_error_norm, spectral_radius, verify_filter};
use relnav::hinf::*;
use relnav::types::{Mat6, State, Vec3};

fn closed_loop(spec: &HinfSpec) -> (HinfPlant, impl Fn(f64) -> Mat6 + '_) {
    (
        HinfPlant::paper_closed_loop(spec, &PAPER_K, PAPER_MASS),
        move |d| HinfPlant::paper_closed_loop_at(spec, &PAPER_K, PAPER_MASS, d),
    )
}

/// `dA1 = Ha F Ea` reproduces the CW matrix's change with `w = w0 (1 + delta)` exactly
/// (paper 002 sec. 4), and `F^T F <= I` on `|delta| <= delta_bar`.
#[test]
fn uncertainty_structure_reproduces_da1() {
    for w0 in [PAPER_W0, 1.1e-3] {
        let db = 0.05;
        for delta in delta_grid(db, 9) {
            let da1 = cw_a(w0 * (1.0 + delta)) - cw_a(w0);
            let model = paper_ha(w0) * paper_f(delta, db) * paper_ea(w0, db);
            assert!((da1 - model).abs().max() < 1e-15 * (1.0 + da1.abs().max()));
            let f = paper_f(delta, db);
            assert!((f.transpose() * f).diagonal().max() <= 1.0 + 1e-12);
        }
    }
}

fn check_paper_case(spec: &HinfSpec) -> (f64, f64) {
    let (plant, a_of) = closed_loop(spec);
    let d = design_paper(&plant, spec.period, &DesignOptions::default())
        .unwrap_or_else(|e| panic!("design failed for {spec:?}: {e}"));
    eprintln!(
        "w0 {:e}: gamma {:.5}, {} in {} iterations, {:.3} s, max eig {:e}\nA_F {:.5}B_F {:.5}C_F {:.5}",
        spec.w0,
        d.gamma,
        d.status,
        d.iterations,
        d.solve_time,
        d.lmi_max_eig,
        d.matrices.a_f,
        d.matrices.b_f,
        d.matrices.c_f
    );
    assert!(
        d.lmi_max_eig < 0.0,
        "LMI not negative definite: {}",
        d.lmi_max_eig
    );
    assert!(d.gamma.is_finite() && d.gamma > 0.0);
    let v = verify_filter(&plant, &d.matrices, &delta_grid(spec.delta_bar, 11), &a_of);
    assert!(v.max_spectral_radius < 1.0, "unstable error system: {v:?}");
    // the LMI certifies the norm for every admissible delta: the sweep must stay below gamma
    assert!(
        v.worst_norm <= d.gamma,
        "norm {} > gamma {}",
        v.worst_norm,
        d.gamma
    );
    (d.gamma, v.worst_norm)
}

#[test]
fn paper_case_is_feasible_and_verified_and_beats_the_published_filter() {
    let spec = HinfSpec::paper();
    let (gamma, ours) = check_paper_case(&spec);
    let (plant, a_of) = closed_loop(&spec);
    let published = HinfMatrices::paper_published();
    let v = verify_filter(&plant, &published, &delta_grid(spec.delta_bar, 11), &a_of);
    assert!(
        v.max_spectral_radius < 1.0,
        "published filter unstable: {v:?}"
    );
    eprintln!(
        "paper 002: gamma {gamma:.5}, our worst-case norm {ours:.5}, published filter's {:.5}",
        v.worst_norm
    );
    assert!(
        ours <= v.worst_norm,
        "ours {ours} worse than published {}",
        v.worst_norm
    );
}

#[test]
fn other_orbits_are_feasible_and_verified() {
    // 12 h orbit and a 90 min low Earth orbit, same K, mass, noise scalings and period
    for period_s in [12.0 * 3600.0, 5400.0] {
        let spec = HinfSpec {
            w0: std::f64::consts::TAU / period_s,
            ..HinfSpec::paper()
        };
        let (g, n) = check_paper_case(&spec);
        eprintln!("orbit {period_s} s: gamma {g:.5}, worst norm {n:.5}");
    }
}

#[test]
fn impossible_uncertainty_is_reported_infeasible() {
    // |delta| <= 50 on a 90 min orbit: w up to 51 w0; no filter can be certified
    let spec = HinfSpec {
        w0: std::f64::consts::TAU / 5400.0,
        delta_bar: 50.0,
        ..HinfSpec::paper()
    };
    let (plant, _) = closed_loop(&spec);
    match design_paper(&plant, spec.period, &DesignOptions::default()) {
        Err(e) => {
            assert_eq!(e.kind, HinfErrorKind::Infeasible, "{e}");
            assert!(!e.message.is_empty());
        }
        Ok(d) => panic!("expected infeasible, got gamma {}", d.gamma),
    }
}

#[test]
fn invalid_spec_is_rejected() {
    let spec = HinfSpec {
        period: -1.0,
        ..HinfSpec::paper()
    };
    let e = design_open_loop(&spec, &DesignOptions::default()).err();
    assert_eq!(e.map(|e| e.kind), Some(HinfErrorKind::InvalidArgument));
}

/// Open loop: the CW transition has eigenvalues on the unit circle, so the paper's
/// augmented LMI (which contains the plant state) admits no solution; the observer design
/// does, and its error dynamics are stable for every delta on the grid.
#[test]
fn open_loop_needs_the_observer_form() {
    let spec = HinfSpec::paper();
    let plant = HinfPlant::open_loop(&spec);
    let a = nalgebra::DMatrix::from_fn(6, 6, |i, j| plant.a[(i, j)]);
    assert!(spectral_radius(&a) >= 1.0 - 1e-12);
    assert!(design_paper(&plant, spec.period, &DesignOptions::default()).is_err());
    let d = design_observer(&plant, spec.period, &DesignOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(d.lmi_max_eig < 0.0);
    let g = d.matrices.b_f;
    let v = observer_error_norm(&plant, &g, &delta_grid(spec.delta_bar, 11), |dl| {
        HinfPlant::open_loop_at(&spec, dl)
    });
    assert!(v.max_spectral_radius < 1.0, "{v:?}");
    assert!(v.worst_norm <= d.gamma, "{v:?} vs gamma {}", d.gamma);
    // the form of the result: A_F = A - G C, C_F = I, E_F = Gamma(T)
    assert!((d.matrices.a_f + g * plant.c - plant.a).abs().max() < 1e-12);
    assert_eq!(d.matrices.e_f, plant.g);
}

/// Without uncertainty and with `u = K x` inside `A`, the observer design reaches the same
/// optimal gamma as the paper's Corollary 1 (the optimum is attained in observer form).
#[test]
fn observer_design_reduces_to_the_paper_result() {
    let spec = HinfSpec {
        delta_bar: 0.0,
        ..HinfSpec::paper()
    };
    let (plant, _) = closed_loop(&spec);
    let opts = DesignOptions::default();
    let p = design_paper(&plant, spec.period, &opts).unwrap_or_else(|e| panic!("{e}"));
    let o = design_observer(&plant, spec.period, &opts).unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "delta_bar = 0: paper gamma {}, observer gamma {}",
        p.gamma, o.gamma
    );
    assert!((p.gamma - o.gamma).abs() < 1e-3 * p.gamma);
}

/// The runtime filter with the observer design follows a thrusting chaser on the open-loop
/// CW orbit (truth: closed-form CW with exact ZOH thrust) to the noise-free accuracy.
#[test]
fn runtime_observer_tracks_a_thrusting_chaser() {
    let spec = HinfSpec::paper();
    let d = design_open_loop(&spec, &DesignOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let model = relnav::dynamics::CwModel::new(spec.w0);
    let mut x = State::from_row_slice(&[600.0, 550.0, 1040.0, 0.02, -0.08, 0.03]);
    let mut f = HinfFilter::new(
        d.matrices,
        State::from_row_slice(&[630.0, 520.0, 1000.0, 0.0, 0.0, 0.0]),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    for k in 0..3000 {
        let a = Vec3::new(1e-3 * ((k / 500) % 2) as f64, -5e-4, 2e-4);
        let y = x.fixed_rows::<3>(0).into_owned();
        f.step(Some(&y), &a);
        x = model.propagate(&x, &a, spec.period);
    }
    let e = f.state() - x;
    assert!(e.norm() < 1e-6, "error {e}");
}
