//! Soak: long runs of every filter through the FMU (the exported `fmi2*` functions, called
//! as a master calls them), against an independent truth.
//!
//! Run with `bash scripts/soak.sh` (release-like test profile, one filter at a time;
//! `#[ignore]`d so that `cargo test` does not run it). Per Kalman-type filter (EKF, UKF,
//! AQUKF, H-infinity) 10^6 steps, per particle filter 10^5, each particle filter twice:
//! with point particles and their Gaussian-prior moves (`pf_prior = 1`) and with the
//! default particle prior, a Gaussian per particle (`pf_prior = 2`) (`RELNAV_SOAK_SCALE`
//! divides the steps, e.g. 100 for a quick look).
//!
//! **Truth** (written here, not relnav's model): the CW equations integrated by classical
//! RK4 in sub-steps of at most 0.5 s, with a white acceleration of spectral density
//! `ACCEL_PSD` per axis drawn as a constant acceleration of variance `ACCEL_PSD / dt` per
//! sub-step, the thrust held over the step. The chaser is kept on a bounded relative orbit
//! (radial amplitude 300 m, along-track centre 800 m, cross-track 100 m) by a PD controller
//! acting on the true state; on top, random burns of 0.5-3 N for 10-120 s. All thrust goes
//! to the FMU's thrust inputs (the burns are known to the filters).
//! **Measurements**: range/azimuth/elevation of the true position in the FMU's frame (code 2,
//! paper 000's; the rotation written here) with Gaussian noise of the configured sigmas;
//! 10 % random dropouts plus outages of 20-500 steps. **Steps**: random in
//! {0.5, 1, 2, 5, 10} s, changing at random (H-infinity: its design period, 1 s).
//!
//! **Checks per step**: the FMU's outputs equal, bit for bit, a C-ABI estimator fed the same
//! inputs (the FMU is a shell around it); that twin's full covariance gives the minimum
//! eigenvalue and asymmetry of `P`, and the NEES `e^T P^-1 e` of the FMU's estimate error
//! against the truth (6 dof: 95 % band [1.237, 14.449]); NaN outputs are counted. The
//! report is a table row per filter; figures over ten equal time segments show that the
//! NEES does not drift.
//!
//! One short test is not ignored: `sir_keeps_track_where_the_literal_sir_loses_it`, the
//! regression of the particle filters' loss of track in this soak (1 200 steps, seconds).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use relnav::*;
use relnav_core::types::{Mat6, State};
use relnav_fmi::fmi2::types::*;
use relnav_nav_model::VARIABLES;
use std::ffi::CString;
use std::time::Instant;

// relnav.fmu's fmi2* functions in this binary, as the FMU's shared library exports them
relnav_fmi::export_fmi2!(relnav_nav_model::RelnavFmu);

/// relnav.fmu's GUID.
fn guid() -> &'static str {
    relnav_fmi::fmi2::description::guid_of(&relnav_nav_model::INFO)
}

const N: f64 = 2.0 * std::f64::consts::PI / 5400.0;
const MASS: f64 = 1000.0;
const ACCEL_PSD: f64 = 1e-9;
const SIGMA_RANGE: f64 = 0.5;
const SIGMA_ANGLE: f64 = 2e-4;
const SIGMA_POS0: f64 = 5.0;
const SIGMA_VEL0: f64 = 0.02;
const STEPS: [f64; 5] = [0.5, 1.0, 2.0, 5.0, 10.0];
/// chi-square(6) 2.5 % and 97.5 % quantiles
const NEES_BAND: (f64, f64) = (1.237_344, 14.449_375);
const SEGMENTS: usize = 10;

fn scale() -> usize {
    std::env::var("RELNAV_SOAK_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1)
        .max(1)
}

// ------------------------------------------------------------------ truth (canonical)

/// `d/dt (r, v)` of the CW equations (x radial, y along-track, z normal).
fn cw(s: &[f64; 6], a: &[f64; 3]) -> [f64; 6] {
    [
        s[3],
        s[4],
        s[5],
        3.0 * N * N * s[0] + 2.0 * N * s[4] + a[0],
        -2.0 * N * s[3] + a[1],
        -N * N * s[2] + a[2],
    ]
}

fn rk4(s: &[f64; 6], a: &[f64; 3], h: f64) -> [f64; 6] {
    let add = |x: &[f64; 6], k: &[f64; 6], f: f64| -> [f64; 6] {
        std::array::from_fn(|i| x[i] + f * k[i])
    };
    let k1 = cw(s, a);
    let k2 = cw(&add(s, &k1, h / 2.0), a);
    let k3 = cw(&add(s, &k2, h / 2.0), a);
    let k4 = cw(&add(s, &k3, h), a);
    std::array::from_fn(|i| s[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// Advance the truth over `h` with the thrust acceleration `a` held and white noise.
fn propagate(s: &mut [f64; 6], a: &[f64; 3], h: f64, rng: &mut ChaCha8Rng) {
    let m = (h / 0.5).ceil().max(1.0) as usize;
    let dt = h / m as f64;
    let sd = (ACCEL_PSD / dt).sqrt();
    for _ in 0..m {
        let w: [f64; 3] = std::array::from_fn(|i| a[i] + sd * rng.sample::<f64, _>(StandardNormal));
        *s = rk4(s, &w, dt);
    }
}

/// The reference relative orbit (a natural CW motion) at time `t`.
fn reference(t: f64) -> [f64; 6] {
    let (a, yc, b) = (300.0, 800.0, 100.0);
    let (s, c) = (N * t).sin_cos();
    [
        a * c,
        yc - 2.0 * a * s,
        b * s,
        -a * N * s,
        -2.0 * a * N * c,
        b * N * c,
    ]
}

/// Canonical -> the FMU's frame 2 (x along-track, y radial, z anti-normal), written here.
fn to_io3(v: &[f64]) -> [f64; 3] {
    [v[1], v[0], -v[2]]
}

fn to_io6(s: &[f64; 6]) -> [f64; 6] {
    let (p, v) = (to_io3(&s[..3]), to_io3(&s[3..]));
    [p[0], p[1], p[2], v[0], v[1], v[2]]
}

// ------------------------------------------------------------------ FMU plumbing

fn vr(name: &str) -> u32 {
    VARIABLES.iter().find(|v| v.name == name).unwrap().vr
}

fn ok(st: fmi2Status, what: &str) {
    assert_eq!(st, fmi2Status::fmi2OK, "{what}");
}

/// What a particle filter's particles are (ignored by the other filters).
#[derive(Clone, Copy)]
enum Particles {
    /// `pf_prior = 1`: point particles, with the Gaussian-prior moves or without
    /// (`pf_move`, the papers' filters as written)
    Points { moves: bool },
    /// `pf_prior = 2`, the default: a Gaussian per particle
    Gaussians,
}

struct Fmu {
    c: fmi2Component,
    inputs: [u32; 3],
    meas: [u32; 3],
    valid: u32,
    outputs: [u32; 12],
}

impl Fmu {
    fn new(
        filter: i32,
        particles: i32,
        x0: &[f64; 6],
        hinf: bool,
        kind: Particles,
    ) -> (Self, relnav_config) {
        let g = CString::new(guid()).unwrap();
        let cb = fmi2CallbackFunctions {
            logger: None,
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: std::ptr::null_mut(),
        };
        // SAFETY: valid strings and callbacks for the call.
        let c = unsafe {
            fmi2Instantiate(
                c"soak".as_ptr(),
                fmi2CoSimulation,
                g.as_ptr(),
                std::ptr::null(),
                &cb,
                0,
                0,
            )
        };
        assert!(!c.is_null());
        let mut cfg = relnav_config_default();
        cfg.filter = filter;
        if particles > 0 {
            cfg.particles = particles;
        }
        cfg.mean_motion = N;
        cfg.chaser_mass = MASS;
        cfg.sigma_range = SIGMA_RANGE;
        cfg.sigma_angle = SIGMA_ANGLE;
        cfg.x0 = *x0;
        cfg.sigma_pos0 = SIGMA_POS0;
        cfg.sigma_vel0 = SIGMA_VEL0;
        cfg.accel_psd = ACCEL_PSD;
        cfg.q_pos = [0.0; 3];
        cfg.q_vel = [0.0; 3];
        if hinf {
            cfg.hinf_period = 1.0;
        }
        // pf_move applies to point particles only (and `false` only with them)
        let (prior, moves) = match kind {
            Particles::Points { moves } => (1, moves),
            Particles::Gaussians => (2, true),
        };
        cfg.pf_move = i32::from(moves);
        cfg.pf_prior = prior;
        let reals: Vec<(&str, f64)> = vec![
            ("mean_motion", cfg.mean_motion),
            ("chaser_mass", cfg.chaser_mass),
            ("sigma_range", cfg.sigma_range),
            ("sigma_angle", cfg.sigma_angle),
            ("x0", x0[0]),
            ("y0", x0[1]),
            ("z0", x0[2]),
            ("vx0", x0[3]),
            ("vy0", x0[4]),
            ("vz0", x0[5]),
            ("sigma_pos0", cfg.sigma_pos0),
            ("sigma_vel0", cfg.sigma_vel0),
            ("accel_psd", cfg.accel_psd),
            ("q_pos_x", 0.0),
            ("q_pos_y", 0.0),
            ("q_pos_z", 0.0),
            ("q_vel_x", 0.0),
            ("q_vel_y", 0.0),
            ("q_vel_z", 0.0),
            ("hinf_period", cfg.hinf_period),
        ];
        // SAFETY: live instance; one element per call.
        unsafe {
            for (name, v) in reals {
                let r = vr(name);
                ok(fmi2SetReal(c, &r, 1, &v), name);
            }
            let r = vr("filter");
            ok(fmi2SetInteger(c, &r, 1, &filter), "filter");
            let r = vr("pf_prior");
            ok(fmi2SetInteger(c, &r, 1, &prior), "pf_prior");
            let (r, m) = (vr("pf_move"), i32::from(moves));
            ok(fmi2SetBoolean(c, &r, 1, &m), "pf_move");
            if particles > 0 {
                let r = vr("particles");
                ok(fmi2SetInteger(c, &r, 1, &particles), "particles");
            }
            ok(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), "setup");
            ok(fmi2EnterInitializationMode(c), "enter init");
            ok(fmi2ExitInitializationMode(c), "exit init");
        }
        let outputs = [
            "x", "y", "z", "vx", "vy", "vz", "sigma_x", "sigma_y", "sigma_z", "sigma_vx",
            "sigma_vy", "sigma_vz",
        ]
        .map(vr);
        (
            Self {
                c,
                inputs: ["thrust_x", "thrust_y", "thrust_z"].map(vr),
                meas: ["range", "azimuth", "elevation"].map(vr),
                valid: vr("measurement_valid"),
                outputs,
            },
            cfg,
        )
    }

    fn step(&self, t: f64, thrust: &[f64; 3], z: Option<&[f64; 3]>, h: f64) -> fmi2Status {
        // SAFETY: live instance; arrays of 3 elements.
        unsafe {
            ok(
                fmi2SetReal(self.c, self.inputs.as_ptr(), 3, thrust.as_ptr()),
                "thrust",
            );
            let valid = i32::from(z.is_some());
            ok(fmi2SetBoolean(self.c, &self.valid, 1, &valid), "valid");
            if let Some(z) = z {
                ok(
                    fmi2SetReal(self.c, self.meas.as_ptr(), 3, z.as_ptr()),
                    "measurement",
                );
            }
            fmi2DoStep(self.c, t, h, 0)
        }
    }

    fn outputs(&self) -> [f64; 12] {
        let mut y = [0.0; 12];
        // SAFETY: live instance, 12 elements.
        ok(
            unsafe { fmi2GetReal(self.c, self.outputs.as_ptr(), 12, y.as_mut_ptr()) },
            "outputs",
        );
        y
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: from fmi2Instantiate, freed once.
        unsafe { fmi2FreeInstance(self.c) };
    }
}

struct Twin(*mut relnav_estimator);

impl Twin {
    fn new(cfg: &relnav_config) -> Self {
        let mut e = std::ptr::null_mut();
        // SAFETY: valid pointers.
        assert_eq!(
            unsafe { relnav_estimator_new(cfg, &mut e) },
            relnav_status::RELNAV_OK
        );
        Self(e)
    }
    fn step(&self, thrust: &[f64; 3], z: Option<&[f64; 3]>, h: f64) -> relnav_status {
        let zp = z.map_or(std::ptr::null(), |v| v.as_ptr());
        // SAFETY: live handle; arrays of 3 doubles or null.
        unsafe { relnav_estimator_step(self.0, thrust.as_ptr(), zp, h) }
    }
    fn state_cov(&self) -> ([f64; 6], Mat6) {
        let mut x = [0.0; 6];
        let mut p = [0.0; 36];
        // SAFETY: live handle; arrays of 6 and 36 doubles.
        unsafe {
            relnav_estimator_get_state(self.0, x.as_mut_ptr());
            relnav_estimator_get_covariance(self.0, p.as_mut_ptr());
        }
        (x, Mat6::from_row_slice(&p))
    }
}

impl Drop for Twin {
    fn drop(&mut self) {
        // SAFETY: from relnav_estimator_new, freed once.
        unsafe { relnav_estimator_free(self.0) };
    }
}

// ------------------------------------------------------------------ the soak

#[derive(Default)]
struct Segment {
    steps: usize,
    nees_sum: f64,
    in_band: usize,
}

struct Report {
    name: &'static str,
    steps: usize,
    particles: i32,
    measured: usize,
    burn_steps: usize,
    min_eig: f64,
    max_asym: f64,
    not_pd: usize,
    nan: usize,
    mismatches: usize,
    errors: usize,
    first_error: String,
    pos_sq: f64,
    max_pos_err: f64,
    /// step and time of the largest position error
    max_pos_at: (usize, f64),
    /// first step with a position error above 100 m, and the steps since the last
    /// measurement then (a lost filter)
    lost_at: Option<(usize, usize)>,
    segments: Vec<Segment>,
    seconds: f64,
}

/// [`soak_with`] with point particles and their moves.
fn soak(name: &'static str, filter: i32, steps: usize, particles: i32, seed: u64) -> Report {
    soak_with(
        name,
        filter,
        steps,
        particles,
        seed,
        Particles::Points { moves: true },
    )
}

/// A soak of `steps` steps of `filter` (a particle filter's particles as `kind` says).
fn soak_with(
    name: &'static str,
    filter: i32,
    steps: usize,
    particles: i32,
    seed: u64,
    kind: Particles,
) -> Report {
    let hinf = filter == 9;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // the truth starts at the reference orbit; the filter's initial estimate is off by a
    // draw from its own initial covariance
    let mut truth = reference(0.0);
    let guess = to_io6(&truth);
    let x0: [f64; 6] = std::array::from_fn(|i| {
        let s = if i < 3 { SIGMA_POS0 } else { SIGMA_VEL0 };
        guess[i] + s * rng.sample::<f64, _>(StandardNormal)
    });
    let (fmu, cfg) = Fmu::new(filter, particles, &x0, hinf, kind);
    let twin = Twin::new(&cfg);
    let mut r = Report {
        name,
        steps,
        particles,
        measured: 0,
        burn_steps: 0,
        min_eig: f64::INFINITY,
        max_asym: 0.0,
        not_pd: 0,
        nan: 0,
        mismatches: 0,
        errors: 0,
        first_error: String::new(),
        pos_sq: 0.0,
        max_pos_err: 0.0,
        max_pos_at: (0, 0.0),
        lost_at: None,
        segments: (0..SEGMENTS).map(|_| Segment::default()).collect(),
        seconds: 0.0,
    };
    let started = Instant::now();
    let (mut t, mut h) = (0.0, 1.0);
    let (mut burn_left, mut burn) = (0.0, [0.0; 3]);
    let mut outage = 0usize;
    let mut since_measured = 0usize;
    for k in 0..steps {
        if !hinf && rng.random::<f64>() < 0.02 {
            h = STEPS[rng.random_range(0..STEPS.len())];
        }
        // thrust: PD control towards the reference orbit (true state), plus random burns
        let rf = reference(t);
        let (wc, zeta) = (4.0 * N, 0.7);
        let mut u: [f64; 3] = std::array::from_fn(|i| {
            MASS * (-wc * wc * (truth[i] - rf[i]) - 2.0 * zeta * wc * (truth[3 + i] - rf[3 + i]))
        });
        if burn_left <= 0.0 && rng.random::<f64>() < 1e-3 {
            burn_left = rng.random_range(10.0..120.0);
            let d: [f64; 3] = std::array::from_fn(|_| rng.sample::<f64, _>(StandardNormal));
            let nd = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let f = rng.random_range(0.5..3.0);
            burn = d.map(|v| f * v / nd);
        }
        if burn_left > 0.0 {
            for i in 0..3 {
                u[i] += burn[i];
            }
            burn_left -= h;
            r.burn_steps += 1;
        }
        let un = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
        if un > 5.0 {
            u = u.map(|v| v * 5.0 / un);
        }
        // measurement at t
        if outage == 0 && rng.random::<f64>() < 5e-4 {
            outage = rng.random_range(20..500);
        }
        let z = if outage > 0 {
            outage -= 1;
            None
        } else if rng.random::<f64>() < 0.1 {
            None
        } else {
            let p = to_io3(&truth[..3]);
            let range = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            let az = p[1].atan2(p[0]) + SIGMA_ANGLE * rng.sample::<f64, _>(StandardNormal);
            let el = (p[2] / range).asin() + SIGMA_ANGLE * rng.sample::<f64, _>(StandardNormal);
            Some([
                range + SIGMA_RANGE * rng.sample::<f64, _>(StandardNormal),
                az.rem_euclid(std::f64::consts::TAU),
                el.clamp(-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2),
            ])
        };
        r.measured += usize::from(z.is_some());
        since_measured = if z.is_some() { 0 } else { since_measured + 1 };
        let u_io = to_io3(&u);
        let st = fmu.step(t, &u_io, z.as_ref(), h);
        let st2 = twin.step(&u_io, z.as_ref(), h);
        // the truth moves on over [t, t + h) with the thrust held
        let a = u.map(|v| v / MASS);
        propagate(&mut truth, &a, h, &mut rng);
        t += h;
        if st != fmi2Status::fmi2OK || st2 != relnav_status::RELNAV_OK {
            r.errors += 1;
            if r.first_error.is_empty() {
                r.first_error = format!("step {k}: FMU {st:?}, C ABI {st2:?}");
            }
            break; // the FMU is in its error state
        }
        let y = fmu.outputs();
        let (x, p) = twin.state_cov();
        let sigma: [f64; 6] = std::array::from_fn(|i| {
            let v = p[(i, i)];
            if v >= 0.0 {
                v.sqrt()
            } else {
                f64::NAN
            }
        });
        let same = (0..6)
            .all(|i| y[i].to_bits() == x[i].to_bits() && y[6 + i].to_bits() == sigma[i].to_bits());
        r.mismatches += usize::from(!same);
        let nan_out =
            y[..6].iter().any(|v| v.is_nan()) || (!hinf && y[6..].iter().any(|v| v.is_nan()));
        r.nan += usize::from(nan_out);
        let e = State::from_fn(|i, _| y[i] - to_io6(&truth)[i]);
        let pe = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        r.pos_sq += pe * pe;
        if pe > 100.0 && r.lost_at.is_none() {
            r.lost_at = Some((k, since_measured));
        }
        if pe > r.max_pos_err {
            r.max_pos_err = pe;
            r.max_pos_at = (k, t);
        }
        if hinf {
            continue; // no covariance: NEES and P checks do not apply
        }
        r.max_asym = r.max_asym.max((p - p.transpose()).abs().max());
        match relnav_core::numerics::eigen::symmetric_eigenvalues(p) {
            Some(ev) => r.min_eig = r.min_eig.min(ev.min()),
            None => r.not_pd += 1,
        }
        let seg = &mut r.segments[k * SEGMENTS / steps];
        seg.steps += 1;
        match p.cholesky() {
            Some(ch) => {
                let nees = e.dot(&ch.solve(&e));
                seg.nees_sum += nees;
                seg.in_band += usize::from((NEES_BAND.0..=NEES_BAND.1).contains(&nees));
            }
            None => r.not_pd += 1,
        }
    }
    r.seconds = started.elapsed().as_secs_f64();
    r
}

fn print(r: &Report) {
    let hinf = r.name == "hinf";
    let done: usize = r.segments.iter().map(|s| s.steps).sum();
    let nees_mean = r.segments.iter().map(|s| s.nees_sum).sum::<f64>() / done as f64;
    let frac = r.segments.iter().map(|s| s.in_band).sum::<usize>() as f64 / done as f64;
    let seg_frac: Vec<f64> = r
        .segments
        .iter()
        .map(|s| s.in_band as f64 / s.steps.max(1) as f64)
        .collect();
    let seg_mean: Vec<f64> = r
        .segments
        .iter()
        .map(|s| s.nees_sum / s.steps.max(1) as f64)
        .collect();
    let mn = |v: &[f64]| v.iter().fold(f64::INFINITY, |a, b| a.min(*b));
    let mx = |v: &[f64]| v.iter().fold(f64::NEG_INFINITY, |a, b| a.max(*b));
    let (eig, asym, nees, band) = if hinf {
        // no covariance exists for the H-infinity filter (its sigma outputs are NaN)
        (
            "-".to_string(),
            "-".to_string(),
            "-".to_string(),
            "-".to_string(),
        )
    } else {
        (
            format!("{:.3e}", r.min_eig),
            format!("{:.1e}", r.max_asym),
            format!(
                "{nees_mean:.3} [{:.2}, {:.2}]",
                mn(&seg_mean),
                mx(&seg_mean)
            ),
            format!("{frac:.3} [{:.3}, {:.3}]", mn(&seg_frac), mx(&seg_frac)),
        )
    };
    println!(
        "SOAK | {} | {} | {} | {:.3} | {} | {eig} | {asym} | {} | {} | {} | {} | {nees} | {band} | {:.3} | {:.2} (step {}) | {} | {:.0} s {}",
        r.name,
        r.steps,
        if r.particles > 0 {
            r.particles.to_string()
        } else {
            "-".into()
        },
        r.measured as f64 / r.steps as f64,
        r.burn_steps,
        r.not_pd,
        r.nan,
        r.mismatches,
        r.errors,
        (r.pos_sq / r.steps as f64).sqrt(),
        r.max_pos_err,
        r.max_pos_at.0,
        r.lost_at.map_or("-".to_string(), |(k, g)| format!(
            "step {k} ({g} steps after the last measurement)"
        )),
        r.seconds,
        r.first_error,
    );
}

fn header() {
    println!(
        "SOAK | filter | steps | particles | measured | random-burn steps | min eig P | max |P-P^T| | not PD | NaN | FMU != C ABI | errors | NEES mean [segment min, max] | in 95 % band [segment min, max] | pos RMS [m] | pos max [m] | first error > 100 m | time"
    );
}

fn run(name: &'static str, filter: i32, steps: usize, particles: i32) {
    run_with(
        name,
        filter,
        steps,
        particles,
        Particles::Points { moves: true },
    );
}

fn run_with(name: &'static str, filter: i32, steps: usize, particles: i32, kind: Particles) {
    header();
    let r = soak_with(name, filter, steps / scale(), particles, 11, kind);
    print(&r);
    assert_eq!(r.errors, 0, "{}", r.first_error);
    assert_eq!(r.nan, 0);
    assert_eq!(r.mismatches, 0);
    if filter != 9 {
        assert_eq!(r.not_pd, 0);
        assert!(r.min_eig > 0.0);
    }
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_ekf() {
    run("ekf", 1, 1_000_000, 0);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_ukf() {
    run("ukf", 2, 1_000_000, 0);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_aqukf() {
    run("aqukf", 3, 1_000_000, 0);
}

#[cfg(feature = "hinf")]
#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_hinf() {
    run("hinf", 9, 1_000_000, 0);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_pf() {
    run("pf", 4, 100_000, 500);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_rpf() {
    run("rpf", 5, 100_000, 500);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_upf() {
    run("upf", 6, 100_000, 200);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_gapf() {
    run("gapf", 7, 100_000, 500);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_cgapf() {
    run("cgapf", 8, 100_000, 200);
}

// The default particle prior (a Gaussian per particle, each with its own EKF or UKF step):
// as many terms as the point filters have particles.

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_pf_gaussians() {
    run_with("pf (Gaussians)", 4, 100_000, 500, Particles::Gaussians);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_rpf_gaussians() {
    run_with("rpf (Gaussians)", 5, 100_000, 500, Particles::Gaussians);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_upf_gaussians() {
    run_with("upf (Gaussians)", 6, 100_000, 200, Particles::Gaussians);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_gapf_gaussians() {
    run_with("gapf (Gaussians)", 7, 100_000, 500, Particles::Gaussians);
}

#[test]
#[ignore = "soak: minutes; run scripts/soak.sh"]
fn soak_cgapf_gaussians() {
    run_with("cgapf (Gaussians)", 8, 100_000, 200, Particles::Gaussians);
}

/// Regression of the soak's loss of track (docs/filters.md, "`pf_move`: Gaussian-prior
/// moves"): the soak's first 1 200 steps (seed 11, 500 particles). Without its moves
/// (`pf_move = false`) the SIR collapses: the likelihood (0.5 m, 2e-4 rad) is narrower
/// than the spread of the predicted particles after a long step, the weights fall onto a
/// few particles, resampling copies them and the transition cannot separate the copies
/// again (white acceleration 1e-9 m^2/s^3). Where the collapse shows depends on the random
/// stream: with one stream it loses the target (error above 100 m) within these steps,
/// with another it drifts tens of metres away with a huge mean NEES. The control below
/// therefore checks the collapse, not the crossing of 100 m: lost, or a mean NEES a
/// hundred times above the chi-square(6) band's upper end (the filter's covariance no
/// longer describes its error). With the moves (the default) the same filter follows the
/// EKF: no error above 100 m, position RMS within 1.3 times the EKF's on the same steps
/// (the particle filters' bar against the EKF), and a mean NEES inside the chi-square(6)
/// 95 % band of one step.
#[test]
fn sir_keeps_track_where_the_literal_sir_loses_it() {
    const STEPS: usize = 1_200;
    let rms = |r: &Report| (r.pos_sq / r.steps as f64).sqrt();
    let nees = |r: &Report| {
        let done: usize = r.segments.iter().map(|s| s.steps).sum();
        r.segments.iter().map(|s| s.nees_sum).sum::<f64>() / done as f64
    };
    header();
    let ekf = soak("ekf", 1, STEPS, 0, 11);
    print(&ekf);
    let literal = soak_with(
        "pf (literal)",
        4,
        STEPS,
        500,
        11,
        Particles::Points { moves: false },
    );
    print(&literal);
    let moved = soak("pf", 4, STEPS, 500, 11);
    print(&moved);
    assert!(
        ekf.lost_at.is_none() && rms(&ekf) < 1.0,
        "EKF {}",
        rms(&ekf)
    );
    // the mechanism is still there without the moves (so the check below can fail)
    assert!(
        literal.lost_at.is_some() || nees(&literal) > 100.0 * NEES_BAND.1,
        "the literal SIR kept track (RMS {} m, mean NEES {})",
        rms(&literal),
        nees(&literal)
    );
    assert_eq!(
        moved.errors + moved.nan + moved.mismatches + moved.not_pd,
        0
    );
    assert!(moved.lost_at.is_none(), "{:?}", moved.lost_at);
    assert!(
        rms(&moved) <= 1.3 * rms(&ekf),
        "SIR {} m against the EKF's {} m",
        rms(&moved),
        rms(&ekf)
    );
    assert!(
        (NEES_BAND.0..=NEES_BAND.1).contains(&nees(&moved)),
        "NEES {}",
        nees(&moved)
    );
}
