//! The C ABI (`include/relnav.h`) from Rust, as a C caller uses it: the particle-filter and
//! noise-model fields of `relnav_config` (defaults, validation with a message naming the
//! field, round trip), `relnav_estimator_get_ess`, `relnav_estimator_get_pf_acceptance`,
//! seeded reproducibility, the noise
//! model's variance in the Kalman filters, a failed particle-filter step changing nothing
//! (or, after a committed update, refusing to go on until reset), the AQUKF's adaptation
//! law and the IMM (code 10) with `relnav_estimator_get_mode_probabilities`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use relnav::*;
use relnav_core::noise::NoiseModel;
use std::ffi::CStr;

const OK: relnav_status = relnav_status::RELNAV_OK;
const INVALID: relnav_status = relnav_status::RELNAV_ERROR_INVALID_ARGUMENT;

fn last_error() -> String {
    // SAFETY: relnav_last_error returns a valid NUL-terminated string.
    unsafe { CStr::from_ptr(relnav_last_error()) }
        .to_string_lossy()
        .into_owned()
}

fn validate(c: &relnav_config) -> relnav_status {
    // SAFETY: a valid config.
    unsafe { relnav_config_validate(c) }
}

struct Est(*mut relnav_estimator);

impl Est {
    fn new(c: &relnav_config) -> Self {
        let mut p = std::ptr::null_mut();
        // SAFETY: valid pointers.
        let st = unsafe { relnav_estimator_new(c, &mut p) };
        assert_eq!(st, OK, "{}", last_error());
        Est(p)
    }
    fn step(&self, z: Option<&[f64; 3]>) -> relnav_status {
        self.step_with(&[0.0; 3], z, 1.0)
    }
    fn step_with(&self, thrust: &[f64; 3], z: Option<&[f64; 3]>, dt: f64) -> relnav_status {
        let zp = z.map_or(std::ptr::null(), |z| z.as_ptr());
        // SAFETY: live handle, 3 doubles each.
        unsafe { relnav_estimator_step(self.0, thrust.as_ptr(), zp, dt) }
    }
    fn state(&self) -> [f64; 6] {
        let mut x = [0.0; 6];
        // SAFETY: live handle, 6 doubles.
        assert_eq!(
            unsafe { relnav_estimator_get_state(self.0, x.as_mut_ptr()) },
            OK
        );
        x
    }
    fn sigma(&self) -> [f64; 6] {
        let mut s = [0.0; 6];
        // SAFETY: live handle, 6 doubles.
        assert_eq!(
            unsafe { relnav_estimator_get_sigma(self.0, s.as_mut_ptr()) },
            OK
        );
        s
    }
    fn ess(&self) -> f64 {
        let mut e = -1.0;
        // SAFETY: live handle, writable double.
        assert_eq!(unsafe { relnav_estimator_get_ess(self.0, &mut e) }, OK);
        e
    }
    fn reset(&self) {
        // SAFETY: live handle.
        assert_eq!(unsafe { relnav_estimator_reset(self.0) }, OK);
    }
    fn acceptance(&self) -> f64 {
        let mut a = -1.0;
        // SAFETY: live handle, writable double.
        assert_eq!(
            unsafe { relnav_estimator_get_pf_acceptance(self.0, &mut a) },
            OK
        );
        a
    }
}

impl Drop for Est {
    fn drop(&mut self) {
        // SAFETY: freed once.
        unsafe { relnav_estimator_free(self.0) };
    }
}

/// Paper 000's measurements near t = k s (a smooth track; exact values do not matter).
fn z(k: usize) -> [f64; 3] {
    let t = k as f64;
    [670.8 - 0.002 * t, 0.8961 + 2e-6 * t, 0.3025 - 1e-6 * t]
}

fn pf_config(filter: relnav_filter, particles: i32, seed: u64) -> relnav_config {
    let mut c = relnav_config_default();
    c.filter = filter as i32;
    c.particles = particles;
    c.seed = seed;
    c
}

/// [`pf_config`] with the particle filter's `prior`.
fn prior_config(
    filter: relnav_filter,
    particles: i32,
    seed: u64,
    prior: relnav_pf_prior,
) -> relnav_config {
    relnav_config {
        pf_prior: prior as i32,
        ..pf_config(filter, particles, seed)
    }
}

/// [`pf_config`] with point particles (`pf_prior = gaussian`): the moves, their acceptance
/// and the failures a point set cannot undo.
fn points_config(filter: relnav_filter, particles: i32, seed: u64) -> relnav_config {
    prior_config(
        filter,
        particles,
        seed,
        relnav_pf_prior::RELNAV_PF_PRIOR_GAUSSIAN,
    )
}

/// The particle filters' two priors: points and a Gaussian per particle.
const PRIORS: [relnav_pf_prior; 2] = [
    relnav_pf_prior::RELNAV_PF_PRIOR_GAUSSIAN,
    relnav_pf_prior::RELNAV_PF_PRIOR_PARTICLE,
];

#[test]
fn defaults_of_the_new_fields() {
    let c = relnav_config_default();
    assert_eq!(c.particles, 1500);
    assert_eq!(c.resampler, relnav_resampler::RELNAV_RESAMPLER_AUTO as i32);
    assert_eq!(c.resample_threshold, 2.0 / 3.0);
    assert_eq!(
        c.noise_model,
        relnav_noise_model::RELNAV_NOISE_GAUSSIAN as i32
    );
    assert_eq!((c.noise_zeta, c.noise_scale, c.noise_dof), (0.2, 10.0, 4.0));
    assert_eq!(validate(&c), OK);
    // the AQUKF, every particle filter code and hinf are accepted with the defaults (9
    // needs the default `hinf` feature)
    assert_eq!((c.window, c.q_vv_floor, c.q_vv_ceiling), (10, 0.0, 1.0));
    // the H-infinity noise inputs are derived (0) and the design is the mixed one
    assert_eq!(
        (
            c.hinf_period,
            c.hinf_delta_bar,
            c.hinf_b_pos,
            c.hinf_b_vel,
            c.hinf_d
        ),
        (1.0, 0.05, 0.0, 0.0, 0.0)
    );
    assert_eq!(
        (c.hinf_design, c.hinf_gamma_factor, c.hinf_acquisition),
        (relnav_hinf_form::RELNAV_HINF_MIXED as i32, 1.5, 1)
    );
    // the gated adaptation law by default, the IMM's three modes
    assert_eq!(c.aq_law, relnav_adaptation::RELNAV_ADAPTATION_GATED as i32);
    assert_eq!((c.aq_gate_window, c.aq_gate_quantile), (10, 0.999));
    assert_eq!(c.imm_modes, 3);
    assert_eq!(c.imm_accel_psd, [0.0, 1e-6, 1e-3]);
    assert_eq!(c.imm_p_stay, [0.999999, 0.9, 0.9]);
    for f in (3..=8)
        .chain(cfg!(feature = "hinf").then_some(9))
        .chain([10])
    {
        let c = relnav_config {
            filter: f,
            ..relnav_config_default()
        };
        assert_eq!(validate(&c), OK, "filter {f}: {}", last_error());
    }
    #[cfg(not(feature = "hinf"))]
    {
        let c = relnav_config {
            filter: 9,
            ..relnav_config_default()
        };
        assert_eq!(
            validate(&c),
            relnav_status::RELNAV_ERROR_NOT_IMPLEMENTED,
            "filter 9"
        );
        assert!(last_error().contains("not implemented"), "{}", last_error());
    }
}

#[test]
fn bad_new_fields_are_refused_with_their_name() {
    type Mutator = fn(&mut relnav_config);
    let cases: &[(&str, Mutator)] = &[
        ("particles", |c| c.particles = 0),
        ("particles", |c| c.particles = -1),
        ("particles", |c| c.particles = 2_000_001),
        ("particles", |c| c.particles = i32::MIN),
        ("resampler", |c| c.resampler = 0),
        ("resampler", |c| c.resampler = 6),
        ("resampler", |c| c.resampler = 7),
        ("resample_threshold", |c| c.resample_threshold = 0.0),
        ("resample_threshold", |c| c.resample_threshold = -0.5),
        ("resample_threshold", |c| c.resample_threshold = 1.5),
        ("resample_threshold", |c| c.resample_threshold = f64::NAN),
        ("noise_model", |c| c.noise_model = 0),
        ("noise_model", |c| c.noise_model = 4),
        ("noise_zeta", |c| c.noise_zeta = 1.0),
        ("noise_zeta", |c| c.noise_zeta = -0.1),
        ("noise_zeta", |c| c.noise_zeta = f64::NAN),
        ("noise_scale", |c| c.noise_scale = 0.5),
        ("noise_scale", |c| c.noise_scale = f64::INFINITY),
        ("noise_dof", |c| c.noise_dof = 2.0),
        ("noise_dof", |c| c.noise_dof = f64::NAN),
        ("window", |c| c.window = 0),
        ("window", |c| c.window = -3),
        ("window", |c| c.window = 513),
        ("q_vv_floor", |c| c.q_vv_floor = -1e-9),
        ("q_vv_floor", |c| c.q_vv_floor = f64::NAN),
        ("q_vv_ceiling", |c| c.q_vv_ceiling = 0.0),
        ("q_vv_ceiling", |c| c.q_vv_ceiling = f64::INFINITY),
        ("q_vv_ceiling", |c| {
            c.q_vv_floor = 1e-3;
            c.q_vv_ceiling = 1e-4;
        }),
        ("aq_law", |c| c.aq_law = 0),
        ("aq_law", |c| c.aq_law = 3),
        ("aq_gate_window", |c| c.aq_gate_window = 0),
        ("aq_gate_window", |c| c.aq_gate_window = -1),
        ("aq_gate_window", |c| c.aq_gate_window = 129),
        ("aq_gate_quantile", |c| c.aq_gate_quantile = 0.0),
        ("aq_gate_quantile", |c| c.aq_gate_quantile = 1.0),
        ("aq_gate_quantile", |c| c.aq_gate_quantile = f64::NAN),
        ("imm_modes", |c| c.imm_modes = 1),
        ("imm_modes", |c| c.imm_modes = 4),
        ("imm_modes", |c| c.imm_modes = -2),
        ("imm_accel_psd_2", |c| c.imm_accel_psd[1] = -1e-6),
        ("imm_accel_psd_3", |c| c.imm_accel_psd[2] = f64::NAN),
        ("imm_p_stay_1", |c| c.imm_p_stay[0] = 1.0),
        ("imm_p_stay_3", |c| c.imm_p_stay[2] = 0.0),
    ];
    // refused for a particle filter and for a Kalman filter alike (no value hides until
    // the filter changes)
    for filter in [
        relnav_filter::RELNAV_FILTER_EKF,
        relnav_filter::RELNAV_FILTER_RPF,
    ] {
        for (name, m) in cases {
            let mut c = relnav_config {
                filter: filter as i32,
                ..relnav_config_default()
            };
            m(&mut c);
            assert_eq!(validate(&c), INVALID, "{name} accepted ({filter:?})");
            let msg = last_error();
            assert!(msg.contains(name), "{name}: {msg}");
            // and relnav_estimator_new refuses it the same way, leaving *out null
            let mut p = std::ptr::dangling_mut::<relnav_estimator>();
            // SAFETY: valid pointers.
            assert_eq!(unsafe { relnav_estimator_new(&c, &mut p) }, INVALID);
            assert!(p.is_null());
        }
    }
    // the variance of a heavy-tailed model must be finite for the Kalman filters
    let c = relnav_config {
        noise_model: relnav_noise_model::RELNAV_NOISE_MIXTURE as i32,
        noise_scale: 1e160,
        ..relnav_config_default()
    };
    assert_eq!(validate(&c), INVALID);
    assert!(last_error().contains("variance"), "{}", last_error());
    // valid edges
    let ok: &[Mutator] = &[
        |c| c.particles = 1,
        |c| c.particles = 2_000_000,
        |c| c.resample_threshold = 1.0,
        |c| c.resample_threshold = 1e-9,
        |c| c.noise_zeta = 0.0,
        |c| c.noise_scale = 1.0,
        |c| c.noise_dof = 2.000001,
        |c| c.resampler = 1,
        |c| c.resampler = 4,
        |c| c.noise_model = 3,
    ];
    for m in ok {
        let mut c = relnav_config {
            filter: relnav_filter::RELNAV_FILTER_CGAPF as i32,
            pf_prior: relnav_pf_prior::RELNAV_PF_PRIOR_GAUSSIAN as i32,
            ..relnav_config_default()
        };
        m(&mut c);
        assert_eq!(validate(&c), OK, "{}", last_error());
    }
}

#[test]
fn config_round_trip_keeps_the_new_fields() {
    let mut c = pf_config(relnav_filter::RELNAV_FILTER_GAPF, 77, 9);
    c.resampler = relnav_resampler::RELNAV_RESAMPLER_RESIDUAL as i32;
    c.resample_threshold = 0.5;
    c.noise_model = relnav_noise_model::RELNAV_NOISE_STUDENT_T as i32;
    c.noise_zeta = 0.1;
    c.noise_scale = 3.0;
    c.noise_dof = 5.0;
    let e = Est::new(&c);
    let mut back = relnav_config_default();
    // SAFETY: live handle, writable config.
    assert_eq!(unsafe { relnav_estimator_get_config(e.0, &mut back) }, OK);
    assert_eq!(
        (
            back.filter,
            back.particles,
            back.resampler,
            back.noise_model
        ),
        (c.filter, 77, 4, 3)
    );
    assert_eq!(
        (
            back.resample_threshold,
            back.noise_zeta,
            back.noise_scale,
            back.noise_dof,
            back.seed
        ),
        (0.5, 0.1, 3.0, 5.0, 9)
    );
}

/// A one-double getter refuses a null handle and a null output, naming each.
fn getter_checks_pointers(
    get: unsafe extern "C" fn(*const relnav_estimator, *mut f64) -> relnav_status,
) {
    let mut out = 0.0;
    // SAFETY: null handle and null output are the cases under test.
    unsafe {
        assert_eq!(
            get(std::ptr::null(), &mut out),
            relnav_status::RELNAV_ERROR_NULL_POINTER
        );
    }
    assert!(last_error().contains("estimator"), "{}", last_error());
    let kf = Est::new(&relnav_config_default());
    // SAFETY: null output under test.
    unsafe {
        assert_eq!(
            get(kf.0, std::ptr::null_mut()),
            relnav_status::RELNAV_ERROR_NULL_POINTER
        );
    }
    assert!(last_error().contains("out"), "{}", last_error());
}

#[test]
fn get_ess_checks_pointers_and_reports_particles() {
    getter_checks_pointers(relnav_estimator_get_ess);
    let kf = Est::new(&relnav_config_default());
    // Kalman filters: NaN (no particles), before and after steps
    assert!(kf.ess().is_nan());
    assert_eq!(kf.step(Some(&z(0))), OK);
    assert!(kf.ess().is_nan());
    for filter in [
        relnav_filter::RELNAV_FILTER_PF,
        relnav_filter::RELNAV_FILTER_RPF,
        relnav_filter::RELNAV_FILTER_UPF,
        relnav_filter::RELNAV_FILTER_GAPF,
        relnav_filter::RELNAV_FILTER_CGAPF,
    ] {
        let n = 400;
        let e = Est::new(&pf_config(filter, n, 1));
        assert_eq!(e.ess(), f64::from(n), "{filter:?} before any update");
        let mut below = false;
        for k in 0..30 {
            assert_eq!(e.step(Some(&z(k))), OK, "{filter:?}: {}", last_error());
            let ess = e.ess();
            assert!(
                (1.0..=f64::from(n)).contains(&ess),
                "{filter:?} step {k}: ess {ess}"
            );
            below |= ess < f64::from(n);
        }
        // the weights do become unequal: the output is not a constant
        assert!(
            below,
            "{filter:?}: ess never dropped below the particle count"
        );
        // a step without measurement does not change the ess
        let before = e.ess();
        assert_eq!(e.step(None), OK);
        assert_eq!(e.ess(), before);
    }
}

#[test]
fn get_pf_acceptance_checks_pointers_and_reports_each_steps_moves() {
    getter_checks_pointers(relnav_estimator_get_pf_acceptance);
    let kf = Est::new(&relnav_config_default());
    // a Kalman filter makes no moves
    assert_eq!(kf.step(Some(&z(0))), OK);
    assert!(kf.acceptance().is_nan());
    for filter in [
        relnav_filter::RELNAV_FILTER_PF,
        relnav_filter::RELNAV_FILTER_GAPF,
    ] {
        let e = Est::new(&points_config(filter, 400, 1));
        assert!(e.acceptance().is_nan(), "{filter:?} before any step");
        // the first update draws the particles from the measurement: no move
        assert_eq!(e.step(Some(&z(0))), OK, "{filter:?}: {}", last_error());
        assert!(e.acceptance().is_nan(), "{filter:?} first step");
        for k in 1..5 {
            assert_eq!(e.step(Some(&z(k))), OK, "{filter:?}: {}", last_error());
            let a = e.acceptance();
            assert!((0.0..=1.0).contains(&a), "{filter:?} step {k}: {a}");
        }
        // no reading, no move
        assert_eq!(e.step(None), OK);
        assert!(e.acceptance().is_nan(), "{filter:?}");
        e.reset();
        assert!(e.acceptance().is_nan(), "{filter:?} after a reset");
    }
}

#[test]
fn identical_seeds_reproduce_and_reset_reseeds() {
    for filter in [
        relnav_filter::RELNAV_FILTER_PF,
        relnav_filter::RELNAV_FILTER_RPF,
        relnav_filter::RELNAV_FILTER_UPF,
        relnav_filter::RELNAV_FILTER_GAPF,
        relnav_filter::RELNAV_FILTER_CGAPF,
    ] {
        let run = |e: &Est| -> Vec<[f64; 6]> {
            (0..25)
                .map(|k| {
                    assert_eq!(e.step(Some(&z(k))), OK);
                    e.state()
                })
                .collect()
        };
        for prior in PRIORS {
            let config = |seed| prior_config(filter, 250, seed, prior);
            let a = Est::new(&config(123));
            let b = Est::new(&config(123));
            let c = Est::new(&config(124));
            let ra = run(&a);
            assert_eq!(
                ra,
                run(&b),
                "{filter:?} {prior:?}: same seed, different outputs"
            );
            assert_ne!(
                ra,
                run(&c),
                "{filter:?} {prior:?}: different seeds, same outputs"
            );
            a.reset();
            assert_eq!(
                ra,
                run(&a),
                "{filter:?} {prior:?}: reset does not reproduce the run"
            );
        }
    }
}

/// The Kalman filters with a heavy-tailed noise model use its variance: an EKF with the
/// mixture model is the EKF with Gaussian sigmas `sigma sqrt(variance_factor)`, number for
/// number, and its reported uncertainty is wider than with the Gaussian model.
#[test]
fn kalman_filters_use_the_noise_model_variance() {
    let (zeta, scale, dof) = (0.2, 10.0, 4.0);
    for (code, model) in [
        (
            relnav_noise_model::RELNAV_NOISE_MIXTURE,
            NoiseModel::Mixture { zeta, scale },
        ),
        (
            relnav_noise_model::RELNAV_NOISE_STUDENT_T,
            NoiseModel::StudentT { dof },
        ),
    ] {
        for filter in [
            relnav_filter::RELNAV_FILTER_EKF,
            relnav_filter::RELNAV_FILTER_UKF,
        ] {
            let mut heavy = relnav_config_default();
            heavy.filter = filter as i32;
            heavy.noise_model = code as i32;
            let vf = model.variance_factor();
            let mut gauss = heavy;
            gauss.noise_model = relnav_noise_model::RELNAV_NOISE_GAUSSIAN as i32;
            gauss.sigma_range = heavy.sigma_range * vf.sqrt();
            gauss.sigma_angle = heavy.sigma_angle * vf.sqrt();
            let plain = relnav_config {
                filter: filter as i32,
                ..relnav_config_default()
            };
            let (h, g, p) = (Est::new(&heavy), Est::new(&gauss), Est::new(&plain));
            for k in 0..60 {
                for e in [&h, &g, &p] {
                    assert_eq!(e.step(Some(&z(k))), OK);
                }
                assert_eq!(h.state(), g.state(), "{code:?} {filter:?} step {k}");
                assert_eq!(h.sigma(), g.sigma());
            }
            assert!(vf > 1.9, "{code:?}: variance factor {vf}");
            assert!(
                h.sigma()[0] > p.sigma()[0],
                "{code:?} {filter:?}: {:?} vs {:?}",
                h.sigma(),
                p.sigma()
            );
        }
    }
}

/// A point particle filter whose update fails (here: a zero measured range at the first
/// update, which initialises the particles by inverting noisy copies of the measurement)
/// reports RELNAV_ERROR_NUMERICAL and changes nothing: it goes on bit for bit like one
/// that never saw the bad measurement. So does one whose prediction alone fails
/// (a thrust that overflows the state), with either prior.
#[test]
fn failed_particle_filter_step_changes_nothing() {
    for kind in [
        relnav_filter::RELNAV_FILTER_PF,
        relnav_filter::RELNAV_FILTER_RPF,
        relnav_filter::RELNAV_FILTER_UPF,
        relnav_filter::RELNAV_FILTER_GAPF,
        relnav_filter::RELNAV_FILTER_CGAPF,
    ] {
        for prior in PRIORS {
            let config = prior_config(kind, 200, 0, prior);
            let e = Est::new(&config);
            let fresh = Est::new(&config);
            if matches!(prior, relnav_pf_prior::RELNAV_PF_PRIOR_GAUSSIAN) {
                assert_eq!(
                    e.step(Some(&[0.0, 0.5, 0.1])),
                    relnav_status::RELNAV_ERROR_NUMERICAL
                );
                assert!(last_error().contains("inversion"), "{}", last_error());
                assert_eq!(e.state(), fresh.state(), "{kind:?}");
            }
            for k in 0..4 {
                assert_eq!(e.step(Some(&z(k))), OK, "{kind:?}: {}", last_error());
                assert_eq!(fresh.step(Some(&z(k))), OK);
                assert_eq!(e.state(), fresh.state(), "{kind:?} {prior:?} step {k}");
            }
            // prediction alone overflows: refused, nothing changed
            assert_eq!(
                e.step_with(&[1e308; 3], None, 1e4),
                relnav_status::RELNAV_ERROR_NUMERICAL,
                "{kind:?} {prior:?}"
            );
            assert!(last_error().contains("not finite"), "{}", last_error());
            assert_eq!(e.state(), fresh.state(), "{kind:?} {prior:?}");
            assert_eq!(e.step(Some(&z(4))), OK, "{kind:?}: {}", last_error());
            assert_eq!(fresh.step(Some(&z(4))), OK);
            assert_eq!(e.state(), fresh.state(), "{kind:?} {prior:?}");
        }
    }
}

/// The one failure a point particle filter cannot undo without copying its particle set:
/// the update of a step succeeded and the prediction after it overflowed. It is reported,
/// then every later step is refused until a reset. (The particle prior keeps an undo of
/// its terms: the same step is refused and leaves it as it was.)
#[test]
fn particle_filter_failing_after_its_update_refuses_until_reset() {
    let e = Est::new(&points_config(relnav_filter::RELNAV_FILTER_RPF, 200, 0));
    assert_eq!(e.step(Some(&z(0))), OK, "{}", last_error());
    assert_eq!(
        e.step_with(&[1e308; 3], Some(&z(1)), 1e4),
        relnav_status::RELNAV_ERROR_NUMERICAL
    );
    assert_eq!(e.step(Some(&z(1))), relnav_status::RELNAV_ERROR_NUMERICAL);
    assert!(last_error().contains("reset"), "{}", last_error());
    assert_eq!(e.step(None), relnav_status::RELNAV_ERROR_NUMERICAL);
    // invalid inputs are still reported as such
    assert_eq!(e.step(Some(&[f64::NAN, 0.0, 0.0])), INVALID);
    e.reset();
    let fresh = Est::new(&points_config(relnav_filter::RELNAV_FILTER_RPF, 200, 0));
    for k in 0..5 {
        assert_eq!(e.step(Some(&z(k))), OK, "{}", last_error());
        assert_eq!(fresh.step(Some(&z(k))), OK);
        assert_eq!(e.state(), fresh.state(), "step {k}");
    }
    // the particle prior: the same step refused, the filter as it was before it
    let config = prior_config(
        relnav_filter::RELNAV_FILTER_RPF,
        200,
        0,
        relnav_pf_prior::RELNAV_PF_PRIOR_PARTICLE,
    );
    let (e, fresh) = (Est::new(&config), Est::new(&config));
    for est in [&e, &fresh] {
        assert_eq!(est.step(Some(&z(0))), OK, "{}", last_error());
    }
    assert_eq!(
        e.step_with(&[1e308; 3], Some(&z(1)), 1e4),
        relnav_status::RELNAV_ERROR_NUMERICAL
    );
    assert_eq!(e.state(), fresh.state());
    for k in 1..5 {
        assert_eq!(e.step(Some(&z(k))), OK, "{}", last_error());
        assert_eq!(fresh.step(Some(&z(k))), OK);
        assert_eq!(e.state(), fresh.state(), "particle prior, step {k}");
    }
}

/// The H-infinity filter through the C ABI: the design on its own (paper form: gamma and
/// matrices; an infeasible request is a status and a message, `*out` untouched), the
/// navigator with code 9 (gamma, NaN sigma, a step of another length refused).
#[cfg(feature = "hinf")]
#[test]
fn hinf_design_and_estimator() {
    let spec = relnav_hinf_spec {
        form: relnav_hinf_form::RELNAV_HINF_PAPER as i32,
        mean_motion: 7.2722e-5,
        delta_bar: 0.05,
        period: 0.1,
        b_pos: 0.05,
        b_vel: 0.001,
        d: 0.1,
        gamma_factor: 1.5,
        b_matrix: [0.0; 36],
        d_matrix: [0.0; 9],
    };
    // SAFETY: all-zero bytes are a valid relnav_hinf_result (plain doubles and ints).
    let mut out: relnav_hinf_result = unsafe { std::mem::zeroed() };
    // SAFETY: valid pointers.
    let st = unsafe { relnav_hinf_design(&spec, &mut out) };
    assert_eq!(st, OK, "{}", last_error());
    assert!(out.gamma > 0.3 && out.gamma < 0.5, "gamma {}", out.gamma);
    assert!(out.lmi_max_eig < 0.0);
    assert!((out.matrices.period - 0.1).abs() < 1e-15);
    // positions are corrected by the measurement: B_F's position block is far from zero
    assert!(out.matrices.b_f[0].abs() > 0.1);
    let bad = relnav_hinf_spec {
        mean_motion: std::f64::consts::TAU / 5400.0,
        delta_bar: 50.0,
        ..spec
    };
    let before = out.gamma;
    // SAFETY: valid pointers.
    let st = unsafe { relnav_hinf_design(&bad, &mut out) };
    assert_eq!(st, relnav_status::RELNAV_ERROR_INFEASIBLE);
    assert!(last_error().contains("infeasible"), "{}", last_error());
    assert_eq!(out.gamma, before);

    let c = relnav_config {
        filter: relnav_filter::RELNAV_FILTER_HINF as i32,
        ..relnav_config_default()
    };
    let mut est = std::ptr::null_mut();
    // SAFETY: valid pointers.
    assert_eq!(
        unsafe { relnav_estimator_new(&c, &mut est) },
        OK,
        "{}",
        last_error()
    );
    let (mut gamma, mut sig) = (f64::NAN, [0.0; 6]);
    let z = [670.0, 0.9, 0.3];
    // SAFETY: live handle, arrays of the documented lengths.
    unsafe {
        assert_eq!(relnav_estimator_get_hinf_gamma(est, &mut gamma), OK);
        assert_eq!(
            relnav_estimator_step(est, [0.0; 3].as_ptr(), z.as_ptr(), 1.0),
            OK
        );
        assert_eq!(
            relnav_estimator_step(est, [0.0; 3].as_ptr(), z.as_ptr(), 0.5),
            relnav_status::RELNAV_ERROR_INVALID_ARGUMENT
        );
        assert!(last_error().contains("hinf_period"), "{}", last_error());
        assert_eq!(relnav_estimator_get_sigma(est, sig.as_mut_ptr()), OK);
        relnav_estimator_free(est);
    }
    assert!(gamma.is_finite() && gamma > 0.0);
    assert!(sig.iter().all(|s| s.is_nan()));
}

/// The mixed H2/H-infinity design through the C ABI: `relnav_config_hinf_spec` gives the
/// request filter 9 makes (derived noise matrices), `relnav_hinf_design` with it returns
/// the gamma and H2 norm the estimator reports; unknown codes and bad factors are refused.
#[cfg(feature = "hinf")]
/// `relnav_estimator_get_hinf_design`: the mixed design (filter 9's default) runs the SDP
/// from a gamma-optimal stage designed by the Riccati route; the gamma-optimal design is
/// the Riccati route alone (no interior-point iteration); other filters report no route.
#[test]
fn hinf_design_route_is_reported() {
    let info = |c: &relnav_config| {
        let mut est = std::ptr::null_mut();
        let mut i = relnav_hinf_design_info {
            route: -1,
            observer_route: -1,
            riccati_failure: -1,
            riccati_steps: -1,
            iterations: -1,
            solve_time: -1.0,
        };
        // SAFETY: valid pointers; the handle is freed after use.
        unsafe {
            assert_eq!(relnav_estimator_new(c, &mut est), OK, "{}", last_error());
            assert_eq!(relnav_estimator_get_hinf_design(est, &mut i), OK);
            assert_eq!(
                relnav_estimator_get_hinf_design(est, std::ptr::null_mut()),
                relnav_status::RELNAV_ERROR_NULL_POINTER
            );
            relnav_estimator_free(est);
        }
        i
    };
    let riccati = relnav_hinf_route::RELNAV_HINF_ROUTE_RICCATI as i32;
    let ok = relnav_hinf_riccati_failure::RELNAV_HINF_RICCATI_OK as i32;
    let base = relnav_config_default();
    let mixed = info(&relnav_config {
        filter: relnav_filter::RELNAV_FILTER_HINF as i32,
        ..base
    });
    assert_eq!(mixed.route, relnav_hinf_route::RELNAV_HINF_ROUTE_SDP as i32);
    assert_eq!((mixed.observer_route, mixed.riccati_failure), (riccati, ok));
    assert!(mixed.riccati_steps > 0 && mixed.iterations > 0, "{mixed:?}");
    assert!(mixed.solve_time > 0.0 && mixed.solve_time.is_finite());
    let optimal = info(&relnav_config {
        filter: relnav_filter::RELNAV_FILTER_HINF as i32,
        hinf_design: 1,
        ..base
    });
    assert_eq!((optimal.route, optimal.observer_route), (riccati, riccati));
    assert_eq!((optimal.riccati_failure, optimal.iterations), (ok, 0));
    assert!(optimal.riccati_steps > 0, "{optimal:?}");
    let ekf = info(&base);
    assert_eq!(ekf.route, relnav_hinf_route::RELNAV_HINF_ROUTE_NONE as i32);
    assert_eq!((ekf.riccati_steps, ekf.iterations), (0, 0));
    assert!(ekf.solve_time.is_nan());
    // SAFETY: a null handle is reported, not dereferenced.
    let st = unsafe {
        relnav_estimator_get_hinf_design(std::ptr::null(), &mut relnav_hinf_design_info { ..ekf })
    };
    assert_eq!(st, relnav_status::RELNAV_ERROR_NULL_POINTER);
    // the reasons: one distinct text per failure code, fixed texts otherwise
    // SAFETY: the function returns static NUL-terminated strings.
    let text = |c: i32| {
        unsafe { CStr::from_ptr(relnav_hinf_riccati_failure_string(c)) }
            .to_string_lossy()
            .into_owned()
    };
    let reasons: Vec<String> = (1..=4).map(text).collect();
    assert!(reasons
        .iter()
        .all(|r| !r.is_empty() && !r.contains("unknown")));
    for i in 0..4 {
        assert!(!reasons[i + 1..].contains(&reasons[i]), "{reasons:?}");
    }
    assert!(reasons[0].contains("singular"), "{}", reasons[0]);
    assert_eq!(text(ok), "none");
    for c in [5, -1, i32::MAX, i32::MIN] {
        assert_eq!(text(c), "unknown Riccati failure code");
    }
}

#[test]
fn hinf_mixed_design_matches_the_estimator() {
    let c = relnav_config {
        filter: relnav_filter::RELNAV_FILTER_EKF as i32,
        accel_psd: 1e-10,
        q_pos: [0.0; 3],
        q_vel: [0.0; 3],
        ..relnav_config_default()
    };
    // SAFETY: all-zero bytes are a valid relnav_hinf_spec (plain doubles and ints).
    let mut spec: relnav_hinf_spec = unsafe { std::mem::zeroed() };
    // SAFETY: valid pointers.
    assert_eq!(
        unsafe { relnav_config_hinf_spec(&c, &mut spec) },
        OK,
        "{}",
        last_error()
    );
    assert_eq!(spec.form, relnav_hinf_form::RELNAV_HINF_MIXED as i32);
    assert_eq!(
        (spec.b_pos, spec.b_vel, spec.d, spec.gamma_factor),
        (0.0, 0.0, 0.0, 1.5)
    );
    // B B^T: the position variance of a white acceleration of 1e-10 over 1 s is q/3
    let b = spec.b_matrix;
    let bbt00: f64 = (0..6).map(|k| b[k] * b[k]).sum();
    assert!((bbt00 - 1e-10 / 3.0).abs() < 1e-3 * 1e-10, "{bbt00}");
    // SAFETY: all-zero bytes are a valid relnav_hinf_result.
    let mut out: relnav_hinf_result = unsafe { std::mem::zeroed() };
    // SAFETY: valid pointers.
    assert_eq!(
        unsafe { relnav_hinf_design(&spec, &mut out) },
        OK,
        "{}",
        last_error()
    );
    assert!(out.lmi_max_eig < 0.0);
    assert!((out.gamma - 1.5 * out.gamma_opt).abs() < 1e-12 * out.gamma);
    assert!(out.h2_norm > 0.0 && out.h2_norm < 0.2, "{}", out.h2_norm);
    assert!(out.iterations > 0 && out.solve_time > 0.0);

    let c9 = relnav_config {
        filter: relnav_filter::RELNAV_FILTER_HINF as i32,
        ..c
    };
    let mut est = std::ptr::null_mut();
    // SAFETY: valid pointers.
    assert_eq!(
        unsafe { relnav_estimator_new(&c9, &mut est) },
        OK,
        "{}",
        last_error()
    );
    let (mut gamma, mut h2, mut certified) = (f64::NAN, f64::NAN, -2);
    // SAFETY: live handle, writable locals.
    unsafe {
        assert_eq!(relnav_estimator_get_hinf_gamma(est, &mut gamma), OK);
        assert_eq!(relnav_estimator_get_hinf_h2_norm(est, &mut h2), OK);
        assert_eq!(relnav_estimator_get_hinf_certified(est, &mut certified), OK);
        relnav_estimator_free(est);
    }
    assert!(
        (gamma - out.gamma).abs() < 1e-9 * gamma,
        "{gamma} vs {}",
        out.gamma
    );
    assert!(
        (h2 - out.h2_norm).abs() < 1e-9 * h2,
        "{h2} vs {}",
        out.h2_norm
    );
    assert_eq!(certified, 0, "track initiation first");
    // other filters: NaN and -1
    let mut ekf = std::ptr::null_mut();
    // SAFETY: valid pointers, live handle.
    unsafe {
        assert_eq!(relnav_estimator_new(&c, &mut ekf), OK);
        assert_eq!(relnav_estimator_get_hinf_h2_norm(ekf, &mut h2), OK);
        assert_eq!(relnav_estimator_get_hinf_certified(ekf, &mut certified), OK);
        relnav_estimator_free(ekf);
    }
    assert!(h2.is_nan());
    assert_eq!(certified, -1);

    for (field, bad) in [
        (
            "hinf_design",
            relnav_config {
                hinf_design: 2,
                ..c9
            },
        ),
        (
            "hinf_acquisition",
            relnav_config {
                hinf_acquisition: 2,
                ..c9
            },
        ),
        (
            "hinf_gamma_factor",
            relnav_config {
                hinf_gamma_factor: 0.5,
                ..c9
            },
        ),
    ] {
        // SAFETY: valid pointer.
        assert_eq!(
            unsafe { relnav_config_validate(&bad) },
            relnav_status::RELNAV_ERROR_INVALID_ARGUMENT
        );
        assert!(last_error().contains(field), "{field}: {}", last_error());
    }
    let bad = relnav_hinf_spec {
        gamma_factor: 1.0,
        ..spec
    };
    // SAFETY: valid pointers.
    assert_eq!(
        unsafe { relnav_hinf_design(&bad, &mut out) },
        relnav_status::RELNAV_ERROR_INVALID_ARGUMENT
    );
    assert!(last_error().contains("gamma_factor"), "{}", last_error());
}

/// The IMM (code 10) through the C ABI: its mode probabilities sum to 1 from creation on,
/// the unused third mode of a 2-mode IMM is NaN, every other filter reports NaN; the
/// getter checks its pointers; the configuration round-trips.
#[test]
fn imm_mode_probabilities() {
    let probs = |e: &Est| {
        let mut mu = [0.0; 3];
        // SAFETY: live handle, 3 doubles.
        assert_eq!(
            unsafe { relnav_estimator_get_mode_probabilities(e.0, mu.as_mut_ptr()) },
            OK
        );
        mu
    };
    let mut c = relnav_config_default();
    c.filter = relnav_filter::RELNAV_FILTER_IMM as i32;
    let e = Est::new(&c);
    // the stationary distribution of the chain, mu_j ~ 1 / (1 - p_j)
    let w = c.imm_p_stay.map(|p| 1.0 / (1.0 - p));
    let total: f64 = w.iter().sum();
    let mu0 = probs(&e);
    for j in 0..3 {
        assert!((mu0[j] - w[j] / total).abs() < 1e-12, "{mu0:?}");
    }
    for k in 0..50 {
        assert_eq!(e.step(Some(&z(k))), OK, "{}", last_error());
        let mu = probs(&e);
        assert!((mu.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{mu:?}");
        assert!(mu.iter().all(|m| (0.0..=1.0).contains(m)), "{mu:?}");
    }
    let mut back = relnav_config_default();
    // SAFETY: live handle, writable config.
    assert_eq!(unsafe { relnav_estimator_get_config(e.0, &mut back) }, OK);
    assert_eq!(
        (
            back.filter,
            back.imm_modes,
            back.imm_accel_psd,
            back.imm_p_stay
        ),
        (10, 3, c.imm_accel_psd, c.imm_p_stay)
    );
    // two modes: the third is NaN
    c.imm_modes = 2;
    c.imm_accel_psd[1] = 1e-4;
    let e2 = Est::new(&c);
    assert_eq!(e2.step(Some(&z(0))), OK);
    let mu = probs(&e2);
    assert!(
        (mu[0] + mu[1] - 1.0).abs() < 1e-12 && mu[2].is_nan(),
        "{mu:?}"
    );
    // other filters: NaN
    let ekf = Est::new(&relnav_config_default());
    assert!(probs(&ekf).iter().all(|m| m.is_nan()));
    // pointers are checked
    // SAFETY: null pointers are the cases under test.
    unsafe {
        assert_eq!(
            relnav_estimator_get_mode_probabilities(e.0, std::ptr::null_mut()),
            relnav_status::RELNAV_ERROR_NULL_POINTER
        );
        let mut mu = [0.0; 3];
        assert_eq!(
            relnav_estimator_get_mode_probabilities(std::ptr::null(), mu.as_mut_ptr()),
            relnav_status::RELNAV_ERROR_NULL_POINTER
        );
    }
}

/// `relnav_estimator_get_estimate` gives the bits of `relnav_estimator_get_state` then
/// `relnav_estimator_get_sigma` (Kalman filters, a particle filter, the H-infinity filter's
/// NaN sigma) and checks its pointers.
#[test]
fn get_estimate_is_state_then_sigma() {
    let mut out = [0.0; 12];
    // SAFETY: null handle and null output are the cases under test.
    unsafe {
        assert_eq!(
            relnav_estimator_get_estimate(std::ptr::null(), out.as_mut_ptr()),
            relnav_status::RELNAV_ERROR_NULL_POINTER
        );
        assert!(last_error().contains("estimator"), "{}", last_error());
    }
    let mut filters = vec![
        relnav_filter::RELNAV_FILTER_EKF,
        relnav_filter::RELNAV_FILTER_UKF,
        relnav_filter::RELNAV_FILTER_AQUKF,
        relnav_filter::RELNAV_FILTER_PF,
        relnav_filter::RELNAV_FILTER_IMM,
    ];
    if cfg!(feature = "hinf") {
        filters.push(relnav_filter::RELNAV_FILTER_HINF);
    }
    for filter in filters {
        let e = Est::new(&pf_config(filter, 200, 3));
        // SAFETY: null output under test.
        let st = unsafe { relnav_estimator_get_estimate(e.0, std::ptr::null_mut()) };
        assert_eq!(st, relnav_status::RELNAV_ERROR_NULL_POINTER);
        assert!(last_error().contains("out"), "{}", last_error());
        for k in 0..5 {
            if k > 0 {
                assert_eq!(e.step(Some(&z(k))), OK, "{filter:?}: {}", last_error());
            }
            // SAFETY: live handle, 12 doubles.
            let st = unsafe { relnav_estimator_get_estimate(e.0, out.as_mut_ptr()) };
            assert_eq!(st, OK);
            let want: Vec<u64> = e
                .state()
                .iter()
                .chain(e.sigma().iter())
                .map(|v| v.to_bits())
                .collect();
            let got: Vec<u64> = out.iter().map(|v| v.to_bits()).collect();
            assert_eq!(got, want, "{filter:?} step {k}");
        }
    }
}

/// An estimator in the caller's storage (`relnav_estimator_init`, the flight library's
/// only way): the storage query and its compile-time bound, the refusals (null, too small,
/// misaligned), and steps bit for bit those of a heap estimator, for each Kalman-type
/// filter; `relnav_estimator_deinit` accepts null.
#[test]
fn estimator_in_caller_storage_is_the_heap_estimator() {
    let (mut size, mut align) = (0usize, 0usize);
    // SAFETY: writable pointers.
    assert_eq!(
        unsafe { relnav_estimator_storage(&mut size, &mut align) },
        OK
    );
    assert!(size > 0 && size <= RELNAV_ESTIMATOR_STORAGE_SIZE, "{size}");
    assert!(align.is_power_of_two() && align <= RELNAV_ESTIMATOR_STORAGE_ALIGN);
    // SAFETY: null pointers are refused.
    assert_eq!(
        unsafe { relnav_estimator_storage(std::ptr::null_mut(), &mut align) },
        relnav_status::RELNAV_ERROR_NULL_POINTER
    );
    #[repr(C, align(16))]
    struct Storage([u8; RELNAV_ESTIMATOR_STORAGE_SIZE]);
    let mut storage = Box::new(Storage([0; RELNAV_ESTIMATOR_STORAGE_SIZE]));
    let base = storage.0.as_mut_ptr().cast::<std::ffi::c_void>();
    let c = relnav_config_default();
    let mut est = std::ptr::null_mut();
    // SAFETY: the storage is live and unused; the refusals write nothing into it.
    unsafe {
        assert_eq!(relnav_estimator_init(base, size - 1, &c, &mut est), INVALID);
        assert!(
            est.is_null() && last_error().contains("storage"),
            "{}",
            last_error()
        );
        assert_eq!(
            relnav_estimator_init(base.cast::<u8>().add(1).cast(), size, &c, &mut est),
            INVALID
        );
        assert_eq!(
            relnav_estimator_init(std::ptr::null_mut(), size, &c, &mut est),
            relnav_status::RELNAV_ERROR_NULL_POINTER
        );
        assert_eq!(relnav_estimator_deinit(std::ptr::null_mut()), OK);
    }
    for filter in [
        relnav_filter::RELNAV_FILTER_EKF,
        relnav_filter::RELNAV_FILTER_UKF,
        relnav_filter::RELNAV_FILTER_AQUKF,
        relnav_filter::RELNAV_FILTER_IMM,
        relnav_filter::RELNAV_FILTER_REKF,
    ] {
        let mut c = relnav_config_default();
        c.filter = filter as i32;
        let heap = Est::new(&c);
        // SAFETY: the storage is live, aligned, large enough and unused.
        assert_eq!(
            unsafe { relnav_estimator_init(base, size, &c, &mut est) },
            OK,
            "{}",
            last_error()
        );
        let placed = Est(est);
        for k in 0..50 {
            let zk = (k % 5 != 2).then(|| z(k));
            assert_eq!(heap.step(zk.as_ref()), OK);
            assert_eq!(placed.step(zk.as_ref()), OK);
        }
        let bits = |x: [f64; 6]| x.map(f64::to_bits);
        assert_eq!(bits(heap.state()), bits(placed.state()), "{filter:?}");
        assert_eq!(bits(heap.sigma()), bits(placed.sigma()), "{filter:?}");
        std::mem::forget(placed); // not freed: it lives in `storage`
                                  // SAFETY: made by relnav_estimator_init, ended once.
        assert_eq!(unsafe { relnav_estimator_deinit(est) }, OK);
    }
}

/// The runtime H-infinity filter in the caller's storage (`relnav_hinf_filter_init`, the
/// flight library's way to run gains designed elsewhere): the storage query, the refusals
/// (null, too small, misaligned, singular `C_F`: `*out` nulled), and, with paper 002's
/// published matrices (`C_F` not the identity), steps bit for bit those of the heap filter
/// and within rounding of the recursion computed here with nalgebra's own inverse.
#[test]
fn runtime_hinf_filter_in_caller_storage() {
    use relnav_core::hinf::{PAPER_A_F, PAPER_B_F, PAPER_C_F};
    use relnav_core::types::{Mat6, Mat63, State, Vec3};
    let (mut size, mut align) = (0usize, 0usize);
    // SAFETY: writable pointers.
    assert_eq!(
        unsafe { relnav_hinf_filter_storage(&mut size, &mut align) },
        OK
    );
    assert!(
        size > 0 && size <= RELNAV_HINF_FILTER_STORAGE_SIZE,
        "{size}"
    );
    assert!(align.is_power_of_two() && align <= RELNAV_HINF_FILTER_STORAGE_ALIGN);
    let m = relnav_hinf_matrices {
        a_f: std::array::from_fn(|k| PAPER_A_F[k / 6][k % 6]),
        b_f: std::array::from_fn(|k| PAPER_B_F[k / 3][k % 3]),
        c_f: std::array::from_fn(|k| PAPER_C_F[k / 6][k % 6]),
        e_f: std::array::from_fn(|k| 1e-3 * (k % 4) as f64),
        period: 0.1,
    };
    #[repr(C, align(16))]
    struct Storage([u8; RELNAV_HINF_FILTER_STORAGE_SIZE]);
    let mut storage = Box::new(Storage([0; RELNAV_HINF_FILTER_STORAGE_SIZE]));
    let base = storage.0.as_mut_ptr().cast::<std::ffi::c_void>();
    let x0 = [100.0, -50.0, 20.0, 0.1, -0.2, 0.05];
    let mut placed = std::ptr::null_mut();
    // SAFETY: the storage is live and unused; the refusals write nothing into it.
    unsafe {
        let st = relnav_hinf_filter_init(base, size - 1, &m, x0.as_ptr(), &mut placed);
        assert_eq!(st, INVALID);
        assert!(placed.is_null() && last_error().contains("storage"));
        let st = relnav_hinf_filter_init(
            base.cast::<u8>().add(1).cast(),
            size,
            &m,
            x0.as_ptr(),
            &mut placed,
        );
        assert_eq!(st, INVALID);
        let singular = relnav_hinf_matrices {
            c_f: [0.0; 36],
            ..m
        };
        let st = relnav_hinf_filter_init(base, size, &singular, x0.as_ptr(), &mut placed);
        assert_eq!(st, INVALID);
        assert!(last_error().contains("singular"), "{}", last_error());
        let st = relnav_hinf_filter_init(std::ptr::null_mut(), size, &m, x0.as_ptr(), &mut placed);
        assert_eq!(st, relnav_status::RELNAV_ERROR_NULL_POINTER);
        assert_eq!(relnav_hinf_filter_deinit(std::ptr::null_mut()), OK);
    }
    let mut heap = std::ptr::null_mut();
    // SAFETY: valid pointers; the storage is live, aligned, large enough and unused.
    unsafe {
        assert_eq!(relnav_hinf_filter_new(&m, x0.as_ptr(), &mut heap), OK);
        let st = relnav_hinf_filter_init(base, size, &m, x0.as_ptr(), &mut placed);
        assert_eq!(st, OK, "{}", last_error());
    }
    // the recursion x_f <- A_F x_f + B_F y + E_F a, estimate C_F x_f, computed here
    let a_f = Mat6::from_fn(|i, j| PAPER_A_F[i][j]);
    let b_f = Mat63::from_fn(|i, j| PAPER_B_F[i][j]);
    let c_f = Mat6::from_fn(|i, j| PAPER_C_F[i][j]);
    let e_f = Mat63::from_fn(|i, j| m.e_f[3 * i + j]);
    let mut x_f = c_f.try_inverse().unwrap() * State::from(x0);
    let accel = [0.0, 2e-3, -1e-3];
    for k in 0..300 {
        let y = [
            100.0 + 0.01 * k as f64,
            -50.0 - 0.02 * k as f64,
            20.0 + (0.1 * k as f64).sin(),
        ];
        let yp = if k % 6 == 4 {
            std::ptr::null()
        } else {
            y.as_ptr()
        };
        let yv = if yp.is_null() {
            (c_f * x_f).fixed_rows::<3>(0).into_owned()
        } else {
            Vec3::from(y)
        };
        x_f = a_f * x_f + b_f * yv + e_f * Vec3::from(accel);
        let (mut a, mut b) = ([0.0; 6], [0.0; 6]);
        // SAFETY: live handles, arrays of the documented lengths.
        unsafe {
            assert_eq!(relnav_hinf_filter_step(heap, yp, accel.as_ptr()), OK);
            assert_eq!(relnav_hinf_filter_step(placed, yp, accel.as_ptr()), OK);
            assert_eq!(relnav_hinf_filter_get_state(heap, a.as_mut_ptr()), OK);
            assert_eq!(relnav_hinf_filter_get_state(placed, b.as_mut_ptr()), OK);
        }
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "step {k}");
        let want = c_f * x_f;
        for i in 0..6 {
            assert!(
                (b[i] - want[i]).abs() <= 1e-9 * (1.0 + want[i].abs()),
                "step {k}, {i}: {} vs {}",
                b[i],
                want[i]
            );
        }
    }
    // SAFETY: each handle ended once, the way it was made.
    unsafe {
        relnav_hinf_filter_free(heap);
        assert_eq!(relnav_hinf_filter_deinit(placed), OK);
    }
}
