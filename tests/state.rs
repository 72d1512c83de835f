//! Saved state (`docs/state-format.md`) through the Rust API, the C ABI and the FMU entry
//! points. For every filter code (`FilterKind::ALL`: a new code without serialisation fails
//! here): a state saved at several points of a run with burns and dropouts, restored into
//! the same navigator / instance and into a fresh one, continues bit for bit as the
//! uninterrupted run. Every refusal (truncated at every length, flipped bytes, another kind,
//! format version, GUID or configuration, malformed fields under a valid checksum) is
//! refused with a reason and changes nothing. The FMU's state machine returns to the saved
//! state's rules. The sizes follow the documented layout.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use relnav::{self as ffi, relnav_status};
use relnav_core::dynamics::CwModel;
use relnav_core::estimators::pf::PfPrior;
use relnav_core::nav::{FilterKind, NavConfig, NavErrorKind, Navigator, STATE_FORMAT_VERSION};
use relnav_core::sensors::{MeasurementModel, RadioSensor};
use relnav_core::types::Vec3;
use relnav_fmi::fmi2::types::*;
use relnav_fmi::fmi2::Logger;
use relnav_fmi::machine::ModelState;
use relnav_fmi::state::FMU_STATE_FORMAT_VERSION;
use relnav_nav_model::{vr, N_VARS, VARIABLES};
use std::ffi::{CStr, CString};

// relnav.fmu's fmi2* functions in this binary, as the FMU's shared library exports them
relnav_fmi::export_fmi2!(relnav_nav_model::RelnavFmu);

/// relnav.fmu's GUID.
fn guid() -> &'static str {
    relnav_fmi::fmi2::description::guid_of(&relnav_nav_model::INFO)
}

/// What an `fmi2Component` of relnav.fmu points to.
type Instance = relnav_fmi::fmi2::Instance<relnav_nav_model::RelnavFmu>;

/// A fresh instance without a logger.
fn instance() -> Instance {
    Instance::new(
        c"t".into(),
        Logger::new(None, std::ptr::null_mut()),
        false,
        guid(),
    )
}

const STEPS: usize = 30;
/// Save points: before anything, after the first (initialising) update, mid-run, during a
/// burn, after a dropout.
const SAVE_AT: [usize; 5] = [0, 1, 7, 12, 19];

// ---------------------------------------------------------------- scenario

/// One step's inputs: thrust [N] (I/O frame) and the measurement taken at its start.
#[derive(Clone, Copy)]
struct Input {
    thrust: [f64; 3],
    z: Option<[f64; 3]>,
}

/// Paper 000's geometry: a CW truth from near the initial estimate, a burn over steps
/// 10..14, a dropout every fifth step, noisy range/azimuth/elevation.
fn scenario(cfg: &NavConfig) -> Vec<Input> {
    let cw = CwModel::new(cfg.mean_motion);
    let sensor = RadioSensor::new(cfg.frame, cfg.sigma_range, cfg.sigma_angle);
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut x = cfg.initial_state();
    x[0] += 3.0;
    x[1] -= 2.0;
    x[4] += 0.02;
    (0..STEPS)
        .map(|k| {
            let thrust = if (10..14).contains(&k) {
                [20.0, -10.0, 5.0]
            } else {
                [0.0; 3]
            };
            let z = (k % 5 != 4).then(|| {
                let h = sensor.predict(&x.fixed_rows::<3>(0).into_owned()).unwrap();
                let s = [cfg.sigma_range, cfg.sigma_angle, cfg.sigma_angle];
                std::array::from_fn(|i| h[i] + s[i] * rng.sample::<f64, _>(StandardNormal))
            });
            let a = cfg.frame.vec_to_canonical(&Vec3::from(thrust)) / cfg.chaser_mass;
            x = cw.propagate(&x, &a, 1.0);
            Input { thrust, z }
        })
        .collect()
}

/// `kind` with the defaults, the particle filters with point particles (their layout
/// below; [`configs`] adds the particle prior).
fn config(kind: FilterKind) -> NavConfig {
    NavConfig {
        filter: kind,
        pf_prior: relnav_core::estimators::pf::PfPrior::Gaussian,
        ..NavConfig::default()
    }
}

/// Every filter code alone, then the Kalman-type ones as range-parameterised banks, then
/// particle filters with the particle prior (EKF and UKF terms).
fn configs() -> Vec<(String, NavConfig)> {
    let mut out: Vec<(String, NavConfig)> = FilterKind::ALL
        .iter()
        .map(|k| (format!("{k:?}"), config(*k)))
        .collect();
    for (kind, n) in [
        (FilterKind::Ekf, 3),
        (FilterKind::Ukf, 4),
        (FilterKind::Aqukf, 2),
        (FilterKind::Imm, 3),
    ] {
        out.push((
            format!("{kind:?} bank of {n}"),
            NavConfig {
                range_bank: n,
                ..config(kind)
            },
        ));
    }
    for kind in [FilterKind::Rpf, FilterKind::Upf] {
        out.push((
            format!("{kind:?} particle prior"),
            NavConfig {
                pf_prior: PfPrior::Particle,
                particles: 40,
                ..config(kind)
            },
        ));
    }
    out
}

/// Every output of a navigator after a step, as bits (NaN-safe exact comparison).
fn outputs(nav: &Navigator) -> Vec<u64> {
    let mut o: Vec<f64> = nav.state().iter().copied().collect();
    o.extend(nav.covariance().iter());
    o.push(nav.ess().unwrap_or(-1.0));
    o.extend(nav.q_vv().unwrap_or([-1.0; 3]));
    o.push(nav.hinf_gamma().unwrap_or(-1.0));
    o.extend(nav.mode_probabilities().unwrap_or([-1.0; 3]));
    match nav.last_update() {
        Some(u) => {
            o.extend(u.innovation.iter());
            o.push(u.nis);
            o.push(f64::from(u8::from(u.azimuth_used)));
        }
        None => o.push(-2.0),
    }
    o.into_iter().map(f64::to_bits).collect()
}

fn step(nav: &mut Navigator, i: &Input) {
    nav.step(&i.thrust, i.z.as_ref(), 1.0).unwrap();
}

// ---------------------------------------------------------------- Rust API

/// Save at each point, continue; restore into the same navigator and into a fresh one;
/// the continuation is bit-identical, and a restored navigator saves the same bytes.
#[test]
fn every_filter_continues_bit_for_bit_after_a_restore() {
    for (kind, cfg) in configs() {
        let inputs = scenario(&cfg);
        let mut nav = Navigator::new(&cfg).unwrap();
        let mut saved = Vec::new();
        let mut trace = vec![outputs(&nav)];
        for (k, i) in inputs.iter().enumerate() {
            if SAVE_AT.contains(&k) {
                let mut b = Vec::new();
                nav.save_state(&mut b);
                assert_eq!(b.len(), nav.state_len(), "{kind:?}: counted size");
                saved.push((k, b));
            }
            step(&mut nav, i);
            trace.push(outputs(&nav));
        }
        let mut fresh = Navigator::new(&cfg).unwrap();
        for (k, b) in &saved {
            for (which, target) in [("same", &mut nav), ("fresh", &mut fresh)] {
                target.restore_state(b).unwrap();
                assert_eq!(outputs(target), trace[*k], "{kind:?} {which} at {k}");
                let mut again = Vec::new();
                target.save_state(&mut again);
                assert!(
                    again == *b,
                    "{kind:?} {which} at {k}: re-saved bytes differ"
                );
                for (j, i) in inputs.iter().enumerate().skip(*k) {
                    step(target, i);
                    assert_eq!(
                        outputs(target),
                        trace[j + 1],
                        "{kind:?} restored ({which}) at step {k}: outputs differ at step {}",
                        j + 1
                    );
                }
            }
        }
    }
}

/// The parallel path (from `PARALLEL_MIN_PARTICLES` = 32768 particles on): its per-chunk
/// generators are state. Saved mid-run on one thread, restored into a navigator that runs
/// the particle loops on two: the continuation is bit-identical (the thread count is not
/// part of the configuration fingerprint; the results do not depend on it).
#[test]
fn the_parallel_path_continues_bit_for_bit_on_another_thread_count() {
    for kind in [FilterKind::Pf, FilterKind::Rpf] {
        let cfg = NavConfig {
            particles: 40_000,
            pf_threads: 1,
            ..config(kind)
        };
        let inputs = scenario(&cfg);
        let mut nav = Navigator::new(&cfg).unwrap();
        for i in &inputs[..8] {
            step(&mut nav, i);
        }
        let mut b = Vec::new();
        nav.save_state(&mut b);
        // 10 chunk generators of 4 words beside the filter's own
        assert_eq!(b.len(), nav.state_len());
        let mut trace = Vec::new();
        for i in &inputs[8..14] {
            step(&mut nav, i);
            trace.push(outputs(&nav));
        }
        let mut other = Navigator::new(&NavConfig {
            pf_threads: 2,
            ..cfg
        })
        .unwrap();
        other.restore_state(&b).unwrap();
        for (i, want) in inputs[8..14].iter().zip(&trace) {
            step(&mut other, i);
            assert_eq!(outputs(&other), *want, "{kind:?}");
        }
    }
}

/// A state saved between a separate update and prediction (the H-infinity filter holds
/// the measurement until its step) continues bit for bit too.
#[test]
fn a_state_between_update_and_predict_continues_bit_for_bit() {
    // and the literal particle filters (the SIR's index-only resampling is pending there)
    let literal = [FilterKind::Pf, FilterKind::Rpf].map(|k| NavConfig {
        pf_move: false,
        pf_prior: relnav_core::estimators::pf::PfPrior::Gaussian,
        ..config(k)
    });
    for cfg in FilterKind::ALL.map(config).into_iter().chain(literal) {
        let kind = cfg.filter;
        let inputs = scenario(&cfg);
        let mut nav = Navigator::new(&cfg).unwrap();
        for i in &inputs[..6] {
            step(&mut nav, i);
        }
        nav.update(inputs[6].z.as_ref().unwrap()).unwrap();
        let mut b = Vec::new();
        nav.save_state(&mut b);
        let mut trace = Vec::new();
        nav.predict(&inputs[6].thrust, 1.0).unwrap();
        trace.push(outputs(&nav));
        for i in &inputs[7..12] {
            step(&mut nav, i);
            trace.push(outputs(&nav));
        }
        let mut fresh = Navigator::new(&cfg).unwrap();
        fresh.restore_state(&b).unwrap();
        fresh.predict(&inputs[6].thrust, 1.0).unwrap();
        assert_eq!(outputs(&fresh), trace[0], "{kind:?}");
        for (i, want) in inputs[7..12].iter().zip(&trace[1..]) {
            step(&mut fresh, i);
            assert_eq!(outputs(&fresh), *want, "{kind:?}");
        }
    }
}

/// A particle filter marked failed stays failed after a restore of that state, and a
/// state saved before the failure works again.
#[test]
fn the_failure_flag_is_part_of_the_state() {
    let cfg = NavConfig {
        particles: 200,
        ..config(FilterKind::Rpf)
    };
    let inputs = scenario(&cfg);
    let mut nav = Navigator::new(&cfg).unwrap();
    for i in &inputs[..3] {
        step(&mut nav, i);
    }
    let mut good = Vec::new();
    nav.save_state(&mut good);
    // an update that succeeds, then a prediction that overflows: marked failed
    let z = inputs[3].z.unwrap();
    let e = nav.step(&[1e308; 3], Some(&z), 1e4);
    assert_eq!(e.unwrap_err().kind, NavErrorKind::Numerical);
    let mut failed = Vec::new();
    nav.save_state(&mut failed);
    assert!(failed != good);
    let mut other = Navigator::new(&cfg).unwrap();
    other.restore_state(&failed).unwrap();
    let e = other.step(&inputs[3].thrust, inputs[3].z.as_ref(), 1.0);
    assert_eq!(e.unwrap_err().kind, NavErrorKind::Numerical);
    other.restore_state(&good).unwrap();
    step(&mut other, &inputs[3]);
}

fn refusal(nav: &mut Navigator, bytes: &[u8], want: &str, what: &str) {
    let before = {
        let mut b = Vec::new();
        nav.save_state(&mut b);
        b
    };
    let e = nav.restore_state(bytes).expect_err(what);
    assert_eq!(e.kind, NavErrorKind::InvalidState, "{what}");
    assert!(
        e.message.contains(want),
        "{what}: message {:?} lacks {want:?}",
        e.message
    );
    let mut after = Vec::new();
    nav.save_state(&mut after);
    assert!(
        after == before,
        "{what}: a refused state changed the navigator"
    );
}

/// Recompute an envelope's CRC-32 after an edit (header of `hl` bytes, CRC in its last 4).
fn reseal(b: &mut [u8], hl: usize) {
    let mut h = crc32fast::Hasher::new();
    h.update(&b[..hl - 4]);
    h.update(&b[hl..]);
    let c = h.finalize();
    b[hl - 4..hl].copy_from_slice(&c.to_le_bytes());
}

const EST_HEADER: usize = 32;

/// Truncations at every length, flipped bytes, other versions, kinds, configurations,
/// tampered headers and malformed fields under a valid checksum: each refused with its
/// reason, the navigator unchanged.
#[test]
fn bad_states_are_refused_and_change_nothing() {
    for kind in FilterKind::ALL {
        let cfg = config(kind);
        let inputs = scenario(&cfg);
        let mut nav = Navigator::new(&cfg).unwrap();
        for i in &inputs[..8] {
            step(&mut nav, i);
        }
        let mut good = Vec::new();
        nav.save_state(&mut good);
        let mut target = Navigator::new(&cfg).unwrap();
        step(&mut target, &inputs[0]);
        // every truncation (the length check comes before the checksum: cheap)
        for len in 0..good.len() {
            assert!(
                target.restore_state(&good[..len]).is_err(),
                "{kind:?}: truncated to {len}"
            );
        }
        refusal(
            &mut target,
            &good[..good.len() - 1],
            "truncated",
            "truncated",
        );
        let mut long = good.clone();
        long.push(0);
        refusal(&mut target, &long, "unexpected bytes", "trailing byte");
        // flipped bytes: every header byte, then a sample of the payload
        let mut rng = ChaCha8Rng::seed_from_u64(kind as u64);
        let positions: Vec<usize> = (0..EST_HEADER)
            .chain((0..200).map(|_| rng.random_range(EST_HEADER..good.len())))
            .collect();
        for p in positions {
            let mut c = good.clone();
            c[p] ^= 1 << rng.random_range(0..8);
            assert!(
                target.restore_state(&c).is_err(),
                "{kind:?}: byte {p} flipped"
            );
        }
        let mut c = good.clone();
        c[good.len() / 2] ^= 0x10;
        refusal(&mut target, &c, "checksum mismatch", "corrupted payload");
        // another format version (checksum recomputed: only the version differs)
        let mut c = good.clone();
        c[8..12].copy_from_slice(&(STATE_FORMAT_VERSION + 1).to_le_bytes());
        reseal(&mut c, EST_HEADER);
        refusal(&mut target, &c, "format version 7", "version");
        // another magic
        let mut c = good.clone();
        c[0] = b'X';
        refusal(&mut target, &c, "not a relnav estimator state", "magic");
        // another configuration: named in the message
        let other = NavConfig {
            sigma_range: 0.6,
            ..cfg
        };
        let mut o = Navigator::new(&other).unwrap();
        let mut ob = Vec::new();
        o.save_state(&mut ob);
        refusal(
            &mut target,
            &ob,
            "sigma_range = 0.6 in the state, 0.5 in this estimator",
            "other configuration",
        );
        o.restore_state(&ob).unwrap();
        // another filter
        let k2 = if kind == FilterKind::Ekf {
            FilterKind::Ukf
        } else {
            FilterKind::Ekf
        };
        let o = Navigator::new(&config(k2)).unwrap();
        let mut ob = Vec::new();
        o.save_state(&mut ob);
        refusal(
            &mut target,
            &ob,
            &format!("the state is for filter {}", k2 as i32),
            "other filter",
        );
        // a header whose filter code was edited (checksum recomputed)
        let mut c = good.clone();
        c[12..16].copy_from_slice(&(k2 as i32).to_le_bytes());
        reseal(&mut c, EST_HEADER);
        refusal(
            &mut target,
            &c,
            "the state is for filter",
            "tampered filter code",
        );
        // a header whose fingerprint was edited (checksum recomputed)
        let mut c = good.clone();
        c[16] ^= 1;
        reseal(&mut c, EST_HEADER);
        refusal(&mut target, &c, "fingerprint", "tampered fingerprint");
        // the same state still restores and continues
        target.restore_state(&good).unwrap();
    }
}

/// Bytes of the CONF section: tag, count, 8 bytes per setting.
fn conf_len() -> usize {
    4 + 4 + 8 * NavConfig::default().settings().len()
}

/// Malformed fields under a valid checksum (a crafted state): refused, no panic.
#[test]
fn malformed_fields_are_refused() {
    // AQUKF: the window position past the window
    let cfg = config(FilterKind::Aqukf);
    let mut nav = Navigator::new(&cfg).unwrap();
    let mut b = Vec::new();
    nav.save_state(&mut b);
    // payload: CONF (4 + 4 + 8 per setting), NAVG (4 + 1 + 8 + 1 + 33), tag (4),
    // UKF (48 + 288), q (24)
    let head = EST_HEADER + conf_len() + 47 + 4 + 336 + 24;
    assert_eq!(&b[head - 24 - 336 - 4..head - 24 - 336], b"AQUK");
    b[head..head + 8].copy_from_slice(&10u64.to_le_bytes());
    reseal(&mut b, EST_HEADER);
    refusal(&mut nav, &b, "window position 10", "head out of range");
    // a particle filter whose pairing permutation repeats an index
    let cfg = NavConfig {
        particles: 10,
        ..config(FilterKind::Gapf)
    };
    let mut nav = Navigator::new(&cfg).unwrap();
    let mut b = Vec::new();
    nav.save_state(&mut b);
    let n = 10;
    // PART: n, m, x0, P0, x (n*48), logw, w, loglik (n*8 each), perm (n*4)
    let perm = EST_HEADER + conf_len() + 47 + 4 + 16 + 48 + 288 + n * 48 + 3 * n * 8;
    assert_eq!(
        u32::from_le_bytes(b[perm + 4..perm + 8].try_into().unwrap()),
        1
    );
    b[perm + 4..perm + 8].copy_from_slice(&0u32.to_le_bytes());
    reseal(&mut b, EST_HEADER);
    refusal(
        &mut nav,
        &b,
        "not a permutation",
        "duplicate in permutation",
    );
    // a non-finite particle
    let mut b = Vec::new();
    nav.save_state(&mut b);
    let x = EST_HEADER + conf_len() + 47 + 4 + 16 + 48 + 288;
    b[x..x + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    reseal(&mut b, EST_HEADER);
    refusal(&mut nav, &b, "particle must be finite", "NaN particle");
    // an all-zero generator state
    let mut b = Vec::new();
    nav.save_state(&mut b);
    // then: mean, cached covariance (flag and 36), ESS, flags, prior mean, covariance,
    // factor, predictive mean, covariance and factor
    let rng_at = perm + n * 4 + 48 + 1 + 288 + 8 + 3 + 48 + 288 + 288 + 48 + 288 + 288;
    b[rng_at..rng_at + 32].fill(0);
    reseal(&mut b, EST_HEADER);
    refusal(&mut nav, &b, "all zero", "zero generator");
    // a bool that is neither 0 nor 1 (the navigator's failure flag)
    let mut b = Vec::new();
    nav.save_state(&mut b);
    let failed = EST_HEADER + conf_len() + 4;
    assert_eq!(&b[failed - 4..failed], b"NAVG");
    b[failed] = 7;
    reseal(&mut b, EST_HEADER);
    refusal(&mut nav, &b, "must be 0 or 1", "bad bool");
}

/// The sizes follow `docs/state-format.md` (a field added without updating the layout
/// and [`STATE_FORMAT_VERSION`] fails here).
#[test]
fn sizes_follow_the_documented_layout() {
    assert_eq!(
        STATE_FORMAT_VERSION, 6,
        "update docs/state-format.md and this table"
    );
    let conf = conf_len();
    // failure flag, step start time, last-update flag, innovation, NIS, azimuth flag
    // (zeros when absent)
    let navg = 4 + 1 + 8 + 1 + 3 * 8 + 8 + 1;
    let m6 = 36 * 8;
    let v6 = 6 * 8;
    let kalman = v6 + m6;
    for (label, cfg) in configs() {
        let kind = cfg.filter;
        let n = cfg.particles;
        // the particle prior: term count, each term's log-weight and estimate, the sum,
        // the generator, the resampling count and the last ESS
        let gaussian_sum = 8 + n * (8 + kalman) + kalman + 32 + 8 + 8;
        let single = match kind {
            _ if cfg.pf_prior == PfPrior::Particle => gaussian_sum,
            FilterKind::Ekf | FilterKind::Ukf | FilterKind::Rekf => kalman,
            // q_vv, window position/fill/width and entries, then the gated law's NIS ring
            // (position/fill/width and (NIS, dof) entries), gate flag and inflation
            FilterKind::Aqukf => {
                kalman + 24 + 3 * 8 + cfg.window * 24 + 3 * 8 + cfg.aq_gate_window * 16 + 1 + 8 + 8
            }
            FilterKind::Pf | FilterKind::Rpf | FilterKind::Gapf => pf_len(n, 0),
            FilterKind::Upf | FilterKind::Cgapf => pf_len(n, n),
            // matrices (B_V too), period, C_F^-1, x_f, estimate; the step's gathered
            // measurements (two counts, opt fix, information, information innovation);
            // gamma, H2 norm, track-initiation flag, its covariance and hand-over flag (on by
            // default)
            FilterKind::Hinf => {
                m6 + 144
                    + m6
                    + 144
                    + 144
                    + 8
                    + m6
                    + v6
                    + v6
                    + (2 + 1 + 24 + m6 + v6)
                    + 8
                    + 8
                    + 1
                    + m6
                    + 1
            }
            // mode count, each mode's EKF, the mode probabilities, the combined estimate
            FilterKind::Imm => 8 + cfg.imm_modes * (kalman + 8) + kalman,
        };
        // a bank: member count, each member's log-weight and tagged section, the mixture
        let filter = 4 + if cfg.range_bank > 1 {
            8 + cfg.range_bank * (8 + 4 + single) + kalman
        } else {
            single
        };
        let mut nav = Navigator::new(&cfg).unwrap();
        println!("{label:18}: {} bytes", nav.state_len());
        assert_eq!(
            nav.state_len(),
            EST_HEADER + conf + navg + filter,
            "{kind:?}"
        );
        // the size is fixed by the configuration: the same after updates (a last update,
        // a particle filter's cached covariance, a held H-infinity measurement)
        let inputs = scenario(&cfg);
        for i in &inputs[..4] {
            step(&mut nav, i);
            assert_eq!(
                nav.state_len(),
                EST_HEADER + conf + navg + filter,
                "{kind:?}"
            );
        }
        assert!(nav.last_update().is_some());
    }
}

/// Particle-filter section without its tag: counts, prior, per-particle arrays, the rest
/// (below 32768 particles no chunk generators).
fn pf_len(n: usize, m: usize) -> usize {
    let m6 = 288;
    let chunk_generators = if n >= 32_768 {
        n.div_ceil(4096) * 32
    } else {
        0
    };
    16 + 48
        + m6
        + n * 48
        + m * 48
        + m * m6
        + 3 * n * 8
        + n * 4
        + 48
        + 1
        + m6
        + 8
        + 3
        + 48
        + m6
        + m6
        + 48
        + m6
        + m6
        + 32
        + chunk_generators
        + m6
        + m6
        + 1
        + 24
}

// ---------------------------------------------------------------- C ABI

const OK: relnav_status = relnav_status::RELNAV_OK;

fn last_error() -> String {
    // SAFETY: relnav_last_error returns a valid NUL-terminated string.
    unsafe { CStr::from_ptr(ffi::relnav_last_error()) }
        .to_string_lossy()
        .into_owned()
}

struct Est(*mut ffi::relnav_estimator);

impl Est {
    fn new(filter: i32) -> Self {
        let mut c = ffi::relnav_config_default();
        c.filter = filter;
        let mut p = std::ptr::null_mut();
        // SAFETY: valid pointers.
        assert_eq!(unsafe { ffi::relnav_estimator_new(&c, &mut p) }, OK);
        Est(p)
    }
    fn step(&self, i: &Input) {
        let zp = i.z.as_ref().map_or(std::ptr::null(), |z| z.as_ptr());
        // SAFETY: live handle, 3 doubles each.
        let st = unsafe { ffi::relnav_estimator_step(self.0, i.thrust.as_ptr(), zp, 1.0) };
        assert_eq!(st, OK, "{}", last_error());
    }
    fn state(&self) -> [u64; 12] {
        let mut x = [0.0; 6];
        let mut s = [0.0; 6];
        // SAFETY: live handle, 6 doubles each.
        unsafe {
            ffi::relnav_estimator_get_state(self.0, x.as_mut_ptr());
            ffi::relnav_estimator_get_sigma(self.0, s.as_mut_ptr());
        }
        std::array::from_fn(|i| if i < 6 { x[i] } else { s[i - 6] }.to_bits())
    }
    fn save(&self) -> Vec<u8> {
        let mut need = 0;
        // SAFETY: size query with a null buffer.
        let st = unsafe { ffi::relnav_estimator_save(self.0, std::ptr::null_mut(), 0, &mut need) };
        assert_eq!(st, OK);
        let mut b = vec![0u8; need];
        let mut len = 0;
        // SAFETY: `b` holds `need` bytes.
        let st = unsafe { ffi::relnav_estimator_save(self.0, b.as_mut_ptr(), b.len(), &mut len) };
        assert_eq!(st, OK);
        assert_eq!(len, need);
        b
    }
    fn restore(&self, b: &[u8]) -> relnav_status {
        // SAFETY: live handle; `b` readable.
        unsafe { ffi::relnav_estimator_restore(self.0, b.as_ptr(), b.len()) }
    }
}

impl Drop for Est {
    fn drop(&mut self) {
        // SAFETY: freed once.
        unsafe { ffi::relnav_estimator_free(self.0) };
    }
}

/// Through the C ABI: size query, a buffer one byte short, the round trip into the same
/// and a fresh handle for every filter code, refusals with a readable last error.
#[test]
fn c_abi_save_and_restore() {
    for kind in FilterKind::ALL {
        let code = kind as i32;
        let inputs = scenario(&config(kind));
        let a = Est::new(code);
        for i in &inputs[..9] {
            a.step(i);
        }
        let saved = a.save();
        let mut trace = Vec::new();
        for i in &inputs[9..] {
            a.step(i);
            trace.push(a.state());
        }
        let fresh = Est::new(code);
        for e in [&a, &fresh] {
            assert_eq!(e.restore(&saved), OK, "{}", last_error());
            for (i, want) in inputs[9..].iter().zip(&trace) {
                e.step(i);
                assert_eq!(e.state(), *want, "filter {code}");
            }
        }
        // a buffer one byte short: status, the needed size, nothing written
        let mut small = vec![0xAAu8; saved.len() - 1];
        let mut len = 0;
        // SAFETY: `small` holds its length in bytes.
        let st =
            unsafe { ffi::relnav_estimator_save(a.0, small.as_mut_ptr(), small.len(), &mut len) };
        assert_eq!(st, relnav_status::RELNAV_ERROR_BUFFER_TOO_SMALL);
        assert_eq!(len, saved.len());
        assert!(small.iter().all(|b| *b == 0xAA));
        assert!(last_error().contains(&format!("needs {} bytes", saved.len())));
        // refusals: the estimator keeps its state
        let before = a.state();
        assert_eq!(
            a.restore(&saved[..100]),
            relnav_status::RELNAV_ERROR_INVALID_STATE
        );
        assert!(
            last_error().starts_with("relnav_estimator_restore: state refused: truncated"),
            "{}",
            last_error()
        );
        let mut c = saved.clone();
        c[saved.len() - 3] ^= 4;
        assert_eq!(a.restore(&c), relnav_status::RELNAV_ERROR_INVALID_STATE);
        assert!(last_error().contains("checksum mismatch"));
        let other = Est::new(if code == 1 { 2 } else { 1 });
        assert_eq!(
            other.restore(&saved),
            relnav_status::RELNAV_ERROR_INVALID_STATE
        );
        assert!(last_error().contains(&format!("the state is for filter {code}")));
        assert_eq!(a.state(), before);
    }
    // null pointers
    let a = Est::new(1);
    let mut len = 0;
    // SAFETY: null arguments are checked.
    unsafe {
        assert_eq!(
            ffi::relnav_estimator_save(std::ptr::null(), std::ptr::null_mut(), 0, &mut len),
            relnav_status::RELNAV_ERROR_NULL_POINTER
        );
        assert_eq!(
            ffi::relnav_estimator_save(a.0, std::ptr::null_mut(), 0, std::ptr::null_mut()),
            relnav_status::RELNAV_ERROR_NULL_POINTER
        );
        assert_eq!(
            ffi::relnav_estimator_restore(a.0, std::ptr::null(), 10),
            relnav_status::RELNAV_ERROR_NULL_POINTER
        );
        assert_eq!(
            ffi::relnav_estimator_restore(std::ptr::null_mut(), [0u8].as_ptr(), 1),
            relnav_status::RELNAV_ERROR_NULL_POINTER
        );
    }
}

// ---------------------------------------------------------------- FMU

const FOK: fmi2Status = fmi2Status::fmi2OK;
const FERR: fmi2Status = fmi2Status::fmi2Error;
const FMU_HEADER: usize = 70;

fn callbacks() -> fmi2CallbackFunctions {
    fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    }
}

struct Fmu(fmi2Component);

impl Fmu {
    fn new() -> Self {
        let g = CString::new(guid()).unwrap();
        let cb = callbacks();
        // SAFETY: valid strings and callbacks for the duration of the call.
        let c = unsafe {
            fmi2Instantiate(
                c"s".as_ptr(),
                fmi2CoSimulation,
                g.as_ptr(),
                std::ptr::null(),
                &cb,
                0,
                0,
            )
        };
        assert!(!c.is_null());
        Fmu(c)
    }
    fn set_int(&self, r: u32, v: i32) -> fmi2Status {
        // SAFETY: live instance, one element.
        unsafe { fmi2SetInteger(self.0, &r, 1, &v) }
    }
    fn set_real(&self, r: u32, v: f64) -> fmi2Status {
        // SAFETY: live instance, one element.
        unsafe { fmi2SetReal(self.0, &r, 1, &v) }
    }
    fn init(&self) {
        // SAFETY: live instance.
        unsafe {
            assert_eq!(fmi2SetupExperiment(self.0, 0, 0.0, 0.0, 0, 0.0), FOK);
            assert_eq!(fmi2EnterInitializationMode(self.0), FOK);
            assert_eq!(fmi2ExitInitializationMode(self.0), FOK);
        }
    }
    fn step(&self, k: usize, i: &Input) -> fmi2Status {
        let ins = [vr::THRUST_X, vr::THRUST_Y, vr::THRUST_Z];
        let zs = [vr::RANGE, vr::AZIMUTH, vr::ELEVATION];
        // SAFETY: live instance, matching lengths.
        unsafe {
            assert_eq!(fmi2SetReal(self.0, ins.as_ptr(), 3, i.thrust.as_ptr()), FOK);
            if let Some(z) = &i.z {
                assert_eq!(fmi2SetReal(self.0, zs.as_ptr(), 3, z.as_ptr()), FOK);
            }
            let valid = i32::from(i.z.is_some());
            assert_eq!(
                fmi2SetBoolean(self.0, &vr::MEASUREMENT_VALID, 1, &valid),
                FOK
            );
            fmi2DoStep(self.0, k as f64, 1.0, 0)
        }
    }
    /// Every Real variable (parameters, inputs, outputs), as bits.
    fn reals(&self) -> Vec<u64> {
        let refs: Vec<u32> = VARIABLES
            .iter()
            .filter(|v| matches!(v.ty, relnav_fmi::variables::VarType::Real(_)))
            .map(|v| v.vr)
            .collect();
        let mut y = vec![0.0; refs.len()];
        // SAFETY: live instance, matching lengths.
        let st = unsafe { fmi2GetReal(self.0, refs.as_ptr(), refs.len(), y.as_mut_ptr()) };
        assert_eq!(st, FOK);
        let mut t = 0.0;
        // SAFETY: live instance, one double.
        let st = unsafe { fmi2GetRealStatus(self.0, status_kind::LAST_SUCCESSFUL_TIME, &mut t) };
        assert_eq!(st, FOK);
        y.push(t);
        y.into_iter().map(f64::to_bits).collect()
    }
    fn get_state(&self) -> fmi2FMUstate {
        let mut s: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: live instance, writable pointer.
        assert_eq!(unsafe { fmi2GetFMUstate(self.0, &mut s) }, FOK);
        assert!(!s.is_null());
        s
    }
    fn set_state(&self, s: fmi2FMUstate) -> fmi2Status {
        // SAFETY: live instance; the state pointer is only compared.
        unsafe { fmi2SetFMUstate(self.0, s) }
    }
    fn serialize(&self, s: fmi2FMUstate) -> Vec<u8> {
        let mut n = 0;
        // SAFETY: live instance, writable size.
        assert_eq!(
            unsafe { fmi2SerializedFMUstateSize(self.0, s, &mut n) },
            FOK
        );
        let mut b = vec![0u8; n];
        // SAFETY: `b` holds `n` bytes.
        let st = unsafe { fmi2SerializeFMUstate(self.0, s, b.as_mut_ptr().cast(), n) };
        assert_eq!(st, FOK);
        b
    }
    fn deserialize(&self, b: &[u8]) -> Result<fmi2FMUstate, fmi2Status> {
        let mut s: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: `b` readable; writable state pointer.
        let st = unsafe { fmi2DeSerializeFMUstate(self.0, b.as_ptr().cast(), b.len(), &mut s) };
        if st == FOK {
            Ok(s)
        } else {
            Err(st)
        }
    }
    fn free_state(&self, s: &mut fmi2FMUstate) -> fmi2Status {
        // SAFETY: live instance, writable pointer.
        unsafe { fmi2FreeFMUstate(self.0, s) }
    }
    fn do_step_only(&self, t: f64) -> fmi2Status {
        // SAFETY: live instance.
        unsafe { fmi2DoStep(self.0, t, 1.0, 0) }
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: freed once.
        unsafe { fmi2FreeInstance(self.0) };
    }
}

/// For every filter code through the fmi2 functions: get a state mid-run, continue; set
/// it back in the same instance; serialise it, deserialise and set it in a freshly
/// instantiated instance (parameters come with the state) and in one initialised with the
/// same parameters: every continuation is bit-identical (every Real variable and the time).
#[test]
fn fmu_state_round_trip_for_every_filter() {
    for (kind, cfg) in configs() {
        let inputs = scenario(&cfg);
        let a = Fmu::new();
        assert_eq!(a.set_int(vr::FILTER, cfg.filter as i32), FOK);
        assert_eq!(a.set_int(vr::RANGE_BANK, cfg.range_bank as i32), FOK);
        a.init();
        let k0 = 9;
        for (k, i) in inputs[..k0].iter().enumerate() {
            assert_eq!(a.step(k, i), FOK);
        }
        let s = a.get_state();
        let at_save = a.reals();
        let mut trace = Vec::new();
        for (k, i) in inputs.iter().enumerate().skip(k0) {
            assert_eq!(a.step(k, i), FOK);
            trace.push(a.reals());
        }
        let bytes = a.serialize(s);
        let replay = |f: &Fmu, which: &str| {
            assert_eq!(f.reals(), at_save, "{kind:?} {which}: restored values");
            for ((k, i), want) in inputs.iter().enumerate().skip(k0).zip(&trace) {
                assert_eq!(f.step(k, i), FOK);
                assert_eq!(f.reals(), *want, "{kind:?} {which} at step {k}");
            }
        };
        assert_eq!(a.set_state(s), FOK);
        replay(&a, "same instance");
        // the state object survives a set and can be set again
        assert_eq!(a.set_state(s), FOK);
        replay(&a, "same instance, twice");
        // a fresh instance, parameters from the state
        let b = Fmu::new();
        let sb = b.deserialize(&bytes).unwrap();
        assert_eq!(b.set_state(sb), FOK);
        replay(&b, "fresh instance");
        assert_eq!(b.serialize(b.get_state()), a.serialize(a.get_state()));
        // an instance initialised with the same parameters
        let c = Fmu::new();
        assert_eq!(c.set_int(vr::FILTER, cfg.filter as i32), FOK);
        assert_eq!(c.set_int(vr::RANGE_BANK, cfg.range_bank as i32), FOK);
        c.init();
        assert_eq!(c.step(0, &inputs[0]), FOK);
        let sc = c.deserialize(&bytes).unwrap();
        assert_eq!(c.set_state(sc), FOK);
        replay(&c, "initialised instance");
        let mut s = s;
        assert_eq!(a.free_state(&mut s), FOK);
        assert!(s.is_null());
    }
}

fn mode(f: &Fmu) -> ModelState {
    // SAFETY: a live instance made by fmi2Instantiate is an `Instance`.
    unsafe { (*(f.0 as *const Instance)).state }
}

/// A state taken in instantiated, initialisation, stepping and terminated mode restores
/// that mode's rules (what may be set, whether `fmi2DoStep` is allowed) and its time.
#[test]
fn fmu_state_restores_the_state_machine() {
    let inputs = scenario(&config(FilterKind::Ekf));
    let f = Fmu::new();
    assert_eq!(f.set_real(vr::SIGMA_RANGE, 0.7), FOK);
    let s_inst = f.get_state();
    // SAFETY: live instance.
    unsafe {
        assert_eq!(fmi2SetupExperiment(f.0, 0, 0.0, 0.0, 0, 0.0), FOK);
        assert_eq!(fmi2EnterInitializationMode(f.0), FOK);
    }
    let s_init = f.get_state();
    // SAFETY: live instance.
    assert_eq!(unsafe { fmi2ExitInitializationMode(f.0) }, FOK);
    for (k, i) in inputs[..5].iter().enumerate() {
        assert_eq!(f.step(k, i), FOK);
    }
    let s_step = f.get_state();
    let at_step = f.reals();
    // SAFETY: live instance.
    assert_eq!(unsafe { fmi2Terminate(f.0) }, FOK);
    let s_term = f.get_state();

    // terminated: no step, outputs readable
    assert_eq!(f.set_state(s_step), FOK);
    assert_eq!(f.set_state(s_term), FOK);
    assert_eq!(mode(&f), ModelState::Terminated);
    assert_eq!(f.reals(), at_step);
    assert_eq!(f.do_step_only(5.0), FERR);
    // from the error state a good state brings the instance back (FMI 2.0 sec. 2.1.3)
    assert_eq!(mode(&f), ModelState::Error);
    assert_eq!(f.set_state(s_step), FOK);
    assert_eq!(mode(&f), ModelState::StepComplete);
    assert_eq!(f.step(5, &inputs[5]), FOK);
    // stepping at the restored time only
    assert_eq!(f.set_state(s_step), FOK);
    assert_eq!(f.do_step_only(0.0), FERR);
    assert_eq!(f.set_state(s_step), FOK);
    // initialisation mode: parameters settable, no step, exit builds the estimator
    assert_eq!(f.set_state(s_init), FOK);
    assert_eq!(mode(&f), ModelState::InitializationMode);
    assert_eq!(f.do_step_only(0.0), FERR);
    assert_eq!(f.set_state(s_init), FOK);
    assert_eq!(f.set_real(vr::CHASER_MASS, 900.0), FOK);
    // SAFETY: live instance.
    assert_eq!(unsafe { fmi2ExitInitializationMode(f.0) }, FOK);
    assert_eq!(f.step(0, &inputs[0]), FOK);
    // stepping with chaser_mass 900: a state of sigma_range 0.7, chaser_mass 1000 is refused
    let before = f.reals();
    assert_eq!(f.set_state(s_step), FERR);
    assert_eq!(mode(&f), ModelState::Error);
    assert_eq!(f.reals(), before, "a refused state changes no value");
    // SAFETY: live instance.
    assert_eq!(unsafe { fmi2Reset(f.0) }, FOK);
    // after reset the parameters are free: the stepping state brings its own
    assert_eq!(f.set_state(s_step), FOK);
    assert_eq!(f.reals(), at_step);
    // instantiated: setupExperiment allowed again, the parameter set before kept
    assert_eq!(f.set_state(s_inst), FOK);
    assert_eq!(mode(&f), ModelState::Instantiated);
    let mut v = 0.0;
    // SAFETY: live instance; GetReal is illegal in the instantiated state.
    assert_eq!(
        unsafe { fmi2GetReal(f.0, &vr::SIGMA_RANGE, 1, &mut v) },
        FERR
    );
    assert_eq!(f.set_state(s_inst), FOK);
    f.init();
    // SAFETY: live instance.
    assert_eq!(
        unsafe { fmi2GetReal(f.0, &vr::SIGMA_RANGE, 1, &mut v) },
        FOK
    );
    assert_eq!(v, 0.7);
    for mut s in [s_inst, s_init, s_step, s_term] {
        assert_eq!(f.free_state(&mut s), FOK);
    }
}

/// Refusals through fmi2DeSerializeFMUstate / fmi2SetFMUstate: every truncation, flipped
/// bytes, another GUID, version or kind, a tampered header; unknown and freed state
/// pointers. Reasons checked on the instance API (the fmi2 logger is C-variadic).
#[test]
fn fmu_refuses_bad_states() {
    let inputs = scenario(&config(FilterKind::Cgapf));
    let a = Fmu::new();
    assert_eq!(a.set_int(vr::FILTER, FilterKind::Cgapf as i32), FOK);
    assert_eq!(a.set_int(vr::PARTICLES, 100), FOK);
    a.init();
    for (k, i) in inputs[..6].iter().enumerate() {
        assert_eq!(a.step(k, i), FOK);
    }
    let s = a.get_state();
    let good = a.serialize(s);
    let b = Fmu::new();
    for len in 0..good.len() {
        assert_eq!(b.deserialize(&good[..len]), Err(FERR), "truncated to {len}");
    }
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let positions: Vec<usize> = (0..FMU_HEADER)
        .chain((0..300).map(|_| rng.random_range(FMU_HEADER..good.len())))
        .collect();
    for p in positions {
        let mut c = good.clone();
        c[p] ^= 1 << rng.random_range(0..8);
        assert_eq!(b.deserialize(&c), Err(FERR), "byte {p} flipped");
    }
    assert!(b.deserialize(&good).is_ok());

    let reason =
        |bytes: &[u8]| -> String { instance().check_state(bytes, "test").unwrap_err().message };
    let mut c = good.clone();
    c[12 + 5] ^= 1; // a GUID character
    reseal(&mut c, FMU_HEADER);
    assert!(reason(&c).contains("another FMU: GUID"), "{}", reason(&c));
    let mut c = good.clone();
    c[8..12].copy_from_slice(&(FMU_STATE_FORMAT_VERSION + 1).to_le_bytes());
    reseal(&mut c, FMU_HEADER);
    assert!(reason(&c).contains("format version 2"));
    let mut c = good.clone();
    c[50..54].copy_from_slice(&1i32.to_le_bytes()); // the filter code
    reseal(&mut c, FMU_HEADER);
    assert!(reason(&c).contains("disagrees with the parameters"));
    assert!(reason(&good[..good.len() - 7]).contains("truncated"));
    let mut c = good.clone();
    c[FMU_HEADER + 100] ^= 1;
    assert!(reason(&c).contains("checksum mismatch"));
    // an estimator state is not an FMU state
    let e = Est::new(1);
    assert!(reason(&e.save()).contains("this is a relnav estimator state"));

    // the estimator inside: a corrupted estimator blob under a valid outer checksum is
    // refused by the C ABI at fmi2SetFMUstate, the instance unchanged
    let est_at = FMU_HEADER + 4 + 4 + 8 + 8 + 1 + 8 + 8 + N_VARS * 8 + 1 + 8;
    assert_eq!(&good[est_at..est_at + 8], b"RELNAVES");
    let mut c = good.clone();
    c[est_at + 40] ^= 1;
    reseal(&mut c, FMU_HEADER);
    let sc = b.deserialize(&c).unwrap();
    let mut inst = instance();
    let m = inst
        .restore_state(&c, "fmi2SetFMUstate")
        .unwrap_err()
        .message;
    assert!(m.contains("estimator state is corrupted"), "{m}");
    assert_eq!(inst.state, ModelState::Instantiated);
    assert_eq!(b.set_state(sc), FERR);
    // other parameters while stepping: the reason names the parameter
    let mut inst = instance();
    inst.enter_initialization();
    inst.exit_initialization().unwrap();
    let m = inst
        .restore_state(&good, "fmi2SetFMUstate")
        .unwrap_err()
        .message;
    assert!(m.contains("it was taken with filter = 8"), "{m}");
    assert_eq!(inst.state, ModelState::StepComplete);

    // state pointers: unknown, another instance's, freed; freeing null is fine
    let mut bogus: fmi2FMUstate = 0x1234usize as fmi2FMUstate;
    assert_eq!(b.set_state(bogus), FERR);
    assert_eq!(b.set_state(s), FERR, "another instance's state");
    assert_eq!(b.free_state(&mut bogus), FERR);
    let mut s2 = a.get_state();
    let copy = s2;
    assert_eq!(a.free_state(&mut s2), FOK);
    assert_eq!(a.set_state(copy), FERR, "a freed state");
    let mut null: fmi2FMUstate = std::ptr::null_mut();
    assert_eq!(a.free_state(&mut null), FOK);
    // a serialisation buffer that is too small
    let s3 = a.get_state();
    let mut small = vec![0u8; 10];
    // SAFETY: `small` holds 10 bytes.
    let st = unsafe { fmi2SerializeFMUstate(a.0, s3, small.as_mut_ptr().cast(), 10) };
    assert_eq!(st, FERR);
}

/// The FMU state's size: 70-byte header, the instance block, the estimator's state.
#[test]
fn fmu_state_size_follows_the_documented_layout() {
    let f = Fmu::new();
    let s = f.get_state();
    let inst_block = 4 + 4 + 8 + 8 + 1 + 8 + 8 + N_VARS * 8 + 1;
    assert_eq!(f.serialize(s).len(), FMU_HEADER + inst_block);
    f.init();
    let s = f.get_state();
    let e = Est::new(1);
    assert_eq!(
        f.serialize(s).len(),
        FMU_HEADER + inst_block + 8 + e.save().len()
    );
}
