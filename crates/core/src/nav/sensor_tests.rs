//! The generic sensor path ([`Estimator::update_sensor`], [`Navigator::step_with`]) in
//! every filter, against independent references: the radio's specialised path on the same
//! measurement, the information form of the Kalman update for a linear sensor, and a
//! truth propagated here by RK4 from the CW equations with measurements formed here.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use super::*;
use crate::estimators::pf::PfPrior;
use crate::frames::Frame;
use crate::sensors::{
    CartesianSensor, GeometryError, Linearization, Modelled, Sensor, SensorNoise,
};
use core::f64::consts::{FRAC_PI_2, PI, TAU};
use nalgebra::{SMatrix, SVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// The relative velocity (canonical frame), as relative GNSS gives it.
#[derive(Debug, Clone, Copy)]
struct Velocity {
    sigma: f64,
}

impl Sensor<3> for Velocity {
    fn measure(&self, x: &State) -> Option<Vec3> {
        Some(Vec3::new(x[3], x[4], x[5]))
    }
    fn linearize(&self, x: &State) -> Result<Linearization<3>, GeometryError> {
        let mut h = SMatrix::<f64, 3, 6>::zeros();
        h.fixed_view_mut::<3, 3>(0, 3).fill_with_identity();
        Ok(Linearization {
            z: Vec3::new(x[3], x[4], x[5]),
            h,
            used: [true; 3],
        })
    }
    fn noise(&self) -> SensorNoise<3> {
        SensorNoise::gaussian([self.sigma; 3])
    }
}

/// The line of sight (azimuth `atan2(y, x)`, elevation `asin(z / rho)`, canonical frame):
/// an angles-only sensor of two components.
#[derive(Debug, Clone, Copy)]
struct LineOfSight {
    sigma: f64,
}

fn los(x: &State) -> Option<SVector<f64, 2>> {
    let rho = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
    (rho > 1e-6).then(|| SVector::<f64, 2>::new(x[1].atan2(x[0]), (x[2] / rho).asin()))
}

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(TAU) - PI
}

impl Sensor<2> for LineOfSight {
    fn measure(&self, x: &State) -> Option<SVector<f64, 2>> {
        los(x)
    }
    fn linearize(&self, x: &State) -> Result<Linearization<2>, GeometryError> {
        let z = los(x).ok_or(GeometryError::ZeroRange)?;
        let (px, py, pz) = (x[0], x[1], x[2]);
        let rxy2 = px * px + py * py;
        let rxy = rxy2.sqrt();
        let rho2 = rxy2 + pz * pz;
        let mut h = SMatrix::<f64, 2, 6>::zeros();
        h[(0, 0)] = -py / rxy2;
        h[(0, 1)] = px / rxy2;
        h[(1, 0)] = -px * pz / (rho2 * rxy);
        h[(1, 1)] = -py * pz / (rho2 * rxy);
        h[(1, 2)] = rxy / rho2;
        Ok(Linearization {
            z,
            h,
            used: [true; 2],
        })
    }
    fn residual(&self, z: &SVector<f64, 2>, zh: &SVector<f64, 2>) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(wrap(z[0] - zh[0]), z[1] - zh[1])
    }
    fn mean(&self, w: &[f64], zs: &[SVector<f64, 2>]) -> SVector<f64, 2> {
        let (mut s, mut c, mut e) = (0.0, 0.0, 0.0);
        for (wi, zi) in w.iter().zip(zs) {
            s += wi * zi[0].sin();
            c += wi * zi[0].cos();
            e += wi * zi[1];
        }
        SVector::<f64, 2>::new(s.atan2(c), e)
    }
    fn noise(&self) -> SensorNoise<2> {
        SensorNoise::gaussian([self.sigma; 2])
    }
}

/// Paper 000's example (the configuration's defaults, frame 2) with filter `code`, and the
/// truth's initial state in the canonical frame (5 m and 0.05 m/s off the estimate).
fn setup(code: i64) -> (NavConfig, State) {
    let cfg = NavConfig {
        filter: FilterKind::ALL
            .into_iter()
            .find(|k| *k as i64 == code)
            .unwrap(),
        particles: 1000,
        ..Default::default()
    };
    let io = [400.0, 500.0, 200.0, 0.05, 0.05, 0.05];
    (
        cfg,
        cfg.frame.state_to_canonical(&State::from_row_slice(&io)),
    )
}

/// The CW equations' right-hand side (canonical: x radial, y along-track, z normal).
fn cw_rhs(n: f64, s: &State) -> State {
    State::from_row_slice(&[
        s[3],
        s[4],
        s[5],
        3.0 * n * n * s[0] + 2.0 * n * s[4],
        -2.0 * n * s[3],
        -n * n * s[2],
    ])
}

/// The truth over `dt` by RK4 in 10 substeps (error far below the sensors' noise).
fn propagate(n: f64, s: &State, dt: f64) -> State {
    let h = dt / 10.0;
    let mut x = *s;
    for _ in 0..10 {
        let k1 = cw_rhs(n, &x);
        let k2 = cw_rhs(n, &(x + k1 * (h / 2.0)));
        let k3 = cw_rhs(n, &(x + k2 * (h / 2.0)));
        let k4 = cw_rhs(n, &(x + k3 * h));
        x += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
    }
    x
}

/// A noisy radio measurement of the canonical position `c` in frame 2 (x along-track,
/// y radial, z anti-normal), formed here.
fn radio(cfg: &NavConfig, c: &State, rng: &mut ChaCha8Rng) -> [f64; 3] {
    assert_eq!(cfg.frame, Frame::AlongRadialAntinormal);
    let p = [c[1], c[0], -c[2]];
    let rho = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    let g = |rng: &mut ChaCha8Rng| -> f64 { StandardNormal.sample(rng) };
    [
        rho + cfg.sigma_range * g(rng),
        (p[1].atan2(p[0]) + cfg.sigma_angle * g(rng)).rem_euclid(TAU),
        (p[2] / rho).asin() + cfg.sigma_angle * g(rng),
    ]
}

fn noisy<const D: usize>(z: SVector<f64, D>, sigma: f64, rng: &mut ChaCha8Rng) -> [f64; D] {
    core::array::from_fn(|k| {
        let g: f64 = StandardNormal.sample(rng);
        z[k] + sigma * g
    })
}

/// `|a - b| <= tol * scale` entry by entry, with the scale of each covariance entry
/// `sqrt(P_ii P_jj)` and of each state entry its standard deviation.
fn assert_close(a: &AnyFilter, b: &AnyFilter, tol: f64, what: &str) {
    let (pa, pb) = (a.covariance(), b.covariance());
    for i in 0..6 {
        let si = pa[(i, i)].sqrt();
        let dx = (a.state()[i] - b.state()[i]).abs();
        assert!(dx <= tol * si, "{what}: x[{i}] {dx:e} vs sigma {si:e}");
        for j in 0..6 {
            let s = (pa[(i, i)] * pa[(j, j)]).sqrt();
            let d = (pa[(i, j)] - pb[(i, j)]).abs();
            assert!(d <= tol * s, "{what}: P[{i},{j}] {d:e} vs {s:e}");
        }
    }
}

/// The radio as a generic sensor gives the radio path's update, to rounding, in every
/// Kalman-type filter (a different order of operations: the full Joseph form, all 13
/// sigma points), and to sampling agreement in the particle filters that weigh with the
/// transition as proposal (the same draws; likelihoods equal to rounding). The unscented
/// kinds' per-particle proposals are the radio path's only (see `pf::sensor_update`).
#[test]
fn the_radio_through_the_generic_path_is_the_radio_path() {
    for code in [1, 2, 3, 10, 4, 5, 7] {
        let (cfg, truth) = setup(code);
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut a = build_filter(&cfg).unwrap();
        let mut b = a.clone();
        let model = cfg
            .dynamics()
            .step(0.0, 1.0, &(Mat3::identity() * 1e-6), cfg.discretization);
        let sensor = RadioSensor::new(cfg.frame, cfg.sigma_range, cfg.sigma_angle);
        let generic = Modelled {
            model: sensor,
            noise: SensorNoise::gaussian([cfg.sigma_range, cfg.sigma_angle, cfg.sigma_angle]),
        };
        let mut x = truth;
        for _ in 0..5 {
            let z = Vec3::from(radio(&cfg, &x, &mut rng));
            a.update(&sensor, &z).unwrap();
            b.update_sensor(&generic, &z).unwrap();
            a.predict(&model, &Vec3::zeros()).unwrap();
            b.predict(&model, &Vec3::zeros()).unwrap();
            x = propagate(cfg.mean_motion, &x, 1.0);
        }
        // particle filters: the same particles as long as no weight rounds across a
        // resampling boundary (true here); Kalman filters: rounding only
        let tol = if (4..=8).contains(&code) { 1e-6 } else { 1e-9 };
        assert_close(&a, &b, tol, &format!("filter {code}"));
    }
}

/// A linear sensor (the velocity) through the EKF's and the UKF's generic paths is the
/// information form of the Kalman update, `P+ = (P^-1 + H^T R^-1 H)^-1`,
/// `x+ = P+ (P^-1 x + H^T R^-1 z)`, computed here.
#[test]
fn a_linear_sensor_gives_the_information_form() {
    let x = State::from_row_slice(&[500.0, 400.0, -200.0, 0.1, -0.2, 0.05]);
    let mut p = Mat6::from_diagonal(&State::from_row_slice(&[
        2500.0, 2500.0, 2500.0, 1.0, 1.0, 1.0,
    ]));
    p[(0, 3)] = 20.0;
    p[(3, 0)] = 20.0;
    p[(4, 1)] = -10.0;
    p[(1, 4)] = -10.0;
    let v = Velocity { sigma: 5e-4 };
    let z = Vec3::new(0.11, -0.19, 0.049);
    let mut h = SMatrix::<f64, 3, 6>::zeros();
    h.fixed_view_mut::<3, 3>(0, 3).fill_with_identity();
    let rinv = Mat3::identity() / (v.sigma * v.sigma);
    let pinv = p.try_inverse().unwrap();
    let p_post = (pinv + h.transpose() * rinv * h).try_inverse().unwrap();
    let x_post = p_post * (pinv * x + h.transpose() * rinv * z);
    let filters: [AnyFilter; 2] = [
        AnyFilter::Ekf(crate::estimators::Ekf::new(x, p)),
        AnyFilter::Ukf(crate::estimators::Ukf::new(x, p, Default::default())),
    ];
    for mut f in filters {
        let info = f.update_sensor(&v, &z).unwrap();
        assert_eq!(info.dof, 3);
        let r = (v.sigma * v.sigma) * Mat3::identity();
        let s = h * p * h.transpose() + r;
        let nu = z - Vec3::new(x[3], x[4], x[5]);
        let nis = nu.dot(&(s.try_inverse().unwrap() * nu));
        assert!(
            (info.nis - nis).abs() <= 1e-9 * nis,
            "{} vs {nis}",
            info.nis
        );
        for i in 0..6 {
            let si = p_post[(i, i)].sqrt();
            assert!((f.state()[i] - x_post[i]).abs() <= 1e-6 * si, "x[{i}]");
            for j in 0..6 {
                let sij = (p_post[(i, i)] * p_post[(j, j)]).sqrt();
                let d = (f.covariance()[(i, j)] - p_post[(i, j)]).abs();
                assert!(d <= 1e-6 * sij, "P[{i},{j}] {d:e} vs {sij:e}");
            }
        }
    }
}

/// RMS velocity error over the last half of a 200 s run (1 s steps, radio at every step)
/// and the velocity sensor's mean NIS, with the velocity sensor (every second step) and
/// the line of sight (every step) added when `extra`.
fn run(code: i64, extra: bool, quiet: bool, seed: u64) -> (f64, f64) {
    let (mut cfg, mut x) = setup(code);
    if quiet {
        // the truth's own process noise: none (a trace of white acceleration keeps P
        // positive definite)
        (cfg.q_pos, cfg.q_vel, cfg.accel_psd) = ([0.0; 3], [0.0; 3], 1e-14);
    }
    let mut nav = Navigator::new(&cfg).unwrap();
    let vel = Velocity { sigma: 5e-4 };
    let sight = LineOfSight { sigma: 1e-3 };
    if extra {
        assert_eq!(nav.add_sensor(Arc::new(Named::new("velocity", vel))), 0);
        assert_eq!(
            nav.add_sensor(Arc::new(Named::new("line of sight", sight))),
            1
        );
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut sq, mut count, mut nis, mut nis_n) = (0.0, 0, 0.0, 0);
    for k in 0..200 {
        let z = radio(&cfg, &x, &mut rng);
        let zv = noisy(vel.measure(&x).unwrap(), vel.sigma, &mut rng);
        let zs = noisy(los(&x).unwrap(), sight.sigma, &mut rng);
        let readings: Vec<Option<&[f64]>> = if extra {
            vec![(k % 2 == 0).then_some(&zv[..]), Some(&zs[..])]
        } else {
            vec![]
        };
        nav.step_with(&[0.0; 3], Some(&z), &readings, 1.0)
            .unwrap_or_else(|e| panic!("filter {code}, step {k}: {e}"));
        if extra && k % 2 == 0 {
            let r = nav.sensor_report(0).unwrap();
            if r.nis.is_finite() {
                nis += r.nis;
                nis_n += 1;
            }
        }
        x = propagate(cfg.mean_motion, &x, 1.0);
        if k >= 100 {
            let est = cfg.frame.state_to_canonical(&nav.state());
            sq += (est.fixed_rows::<3>(3) - x.fixed_rows::<3>(3)).norm_squared();
            count += 1;
        }
    }
    ((sq / count as f64).sqrt(), nis / nis_n.max(1) as f64)
}

/// Every filter but the H-infinity one takes a velocity sensor and an angles-only sensor
/// beside the radio: the velocity error falls to the velocity sensor's level (3-axis RMS
/// at most 4 sigma, where the radio alone leaves it at least 5 times above).
#[test]
fn every_filter_takes_any_sensor() {
    for code in [1, 2, 3, 10, 4, 5, 6, 7, 8] {
        let (alone, _) = run(code, false, false, 11);
        let (with, _) = run(code, true, false, 11);
        eprintln!("filter {code}: RMS velocity error {with:.3e} m/s with, {alone:.3e} without");
        assert!(
            with <= 4.0 * 5e-4 * 3f64.sqrt() && with <= 0.2 * alone,
            "filter {code}: RMS velocity error {with:e} with the sensors, {alone:e} without"
        );
    }
}

/// The library's camera ([`CameraSensor`], canonical frame) and relative-GNSS velocity
/// ([`VelocitySensor`], in the configuration's frame 2, its readings rotated here) give the
/// updates of this file's own line of sight and canonical velocity sensors on the same
/// readings, to rounding, in the Kalman filters and the IMM over 100 steps.
#[test]
fn the_library_camera_and_velocity_are_the_test_sensors() {
    use crate::sensors::{CameraSensor, VelocitySensor};
    for code in [1, 2, 3, 10] {
        let (cfg, mut x) = setup(code);
        let (mut own, mut lib) = (Navigator::new(&cfg).unwrap(), Navigator::new(&cfg).unwrap());
        own.add_sensor(Arc::new(Named::new("velocity", Velocity { sigma: 5e-4 })));
        own.add_sensor(Arc::new(Named::new(
            "line of sight",
            LineOfSight { sigma: 1e-3 },
        )));
        lib.add_sensor(Arc::new(Named::new(
            "gnss velocity",
            VelocitySensor::gaussian(cfg.frame, 5e-4),
        )));
        lib.add_sensor(Arc::new(Named::new(
            "camera",
            CameraSensor::gaussian(Frame::RadialAlongNormal, 1e-3),
        )));
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for k in 0..100 {
            let z = radio(&cfg, &x, &mut rng);
            let zv = noisy(Vec3::new(x[3], x[4], x[5]), 5e-4, &mut rng);
            // frame 2: x along-track, y radial, z anti-normal
            let zv_io = [zv[1], zv[0], -zv[2]];
            let zs = noisy(los(&x).unwrap(), 1e-3, &mut rng);
            let v = (k % 3 != 1).then_some(());
            own.step_with(
                &[0.0; 3],
                Some(&z),
                &[v.map(|_| &zv[..]), Some(&zs[..])],
                1.0,
            )
            .unwrap();
            lib.step_with(
                &[0.0; 3],
                Some(&z),
                &[v.map(|_| &zv_io[..]), Some(&zs[..])],
                1.0,
            )
            .unwrap();
            x = propagate(cfg.mean_motion, &x, 1.0);
        }
        assert_close(&own.filter, &lib.filter, 1e-7, &format!("filter {code}"));
        let (a, b) = (own.sensor_report(1).unwrap(), lib.sensor_report(1).unwrap());
        assert_eq!(a.dof, b.dof);
        assert!(
            (a.nis - b.nis).abs() <= 1e-7 * a.nis.max(1.0),
            "{a:?} {b:?}"
        );
    }
}

/// With the truth's process noise (none), the Kalman filters' velocity NIS averages its 3
/// degrees of freedom over the 100 velocity updates of a run (chi-square: the mean of 100
/// has standard deviation sqrt(6 / 100) = 0.24; bound 4 of those), on four seeds.
#[test]
fn the_generic_path_is_consistent() {
    for code in [1, 2, 10] {
        for seed in 0..4 {
            let (_, nis) = run(code, true, true, seed);
            eprintln!("filter {code}, seed {seed}: mean velocity NIS {nis:.3}");
            assert!(
                (nis - 3.0).abs() <= 4.0 * (6.0f64 / 100.0).sqrt(),
                "filter {code}, seed {seed}: mean NIS {nis}"
            );
        }
    }
}

/// The H-infinity filter takes a sensor that fixes the position (its design's
/// measurement) and refuses one of the position and the velocity together, naming why,
/// with the estimate unchanged.
#[cfg(feature = "hinf")]
#[test]
fn the_hinf_filter_takes_position_fixes_only() {
    let (cfg, x) = setup(9);
    let mut nav = Navigator::new(&cfg).unwrap();
    nav.add_sensor(Arc::new(Named::new("velocity", Velocity { sigma: 5e-4 })));
    let cart = CartesianSensor {
        frame: cfg.frame,
        sigma: 1.0,
    };
    let fix = Modelled {
        model: cart,
        noise: SensorNoise::gaussian([1.0; 3]),
    };
    nav.add_sensor(Arc::new(Named::new("position", fix)));
    let before = nav.state();
    let zv = [0.0; 3];
    let e = nav
        .step_with(&[0.0; 3], None, &[Some(&zv[..]), None], 1.0)
        .unwrap_err();
    assert_eq!(e.kind, NavErrorKind::NotImplemented, "{e}");
    assert!(e.message.contains("position"), "{e}");
    assert_eq!(nav.state(), before);
    let p = cfg
        .frame
        .vec_from_canonical(&x.fixed_rows::<3>(0).into_owned());
    nav.step_with(&[0.0; 3], None, &[None, Some(p.as_slice())], 1.0)
        .unwrap();
}

/// A design for the radio and relative GNSS position (`hinf_sensors` = 5): a GNSS reading
/// alone moves the estimate by `G J_D^-1 J_g (y - x)`, the design's observer with the
/// radio's reading replaced by its prediction, `J_D` computed here from this file's radio
/// (Jacobian by central differences at the initial estimate); a fix far more precise than
/// the design's, not declared, moves it by `G (y - x)` (its own weight, not amplified by
/// `J_D^-1`).
#[cfg(feature = "hinf")]
#[test]
fn the_hinf_filter_fuses_a_steps_position_fixes() {
    let (mut cfg, x) = setup(9);
    cfg.hinf_acquisition = false;
    cfg.hinf_sensors = 5;
    let sigma_g = 2.0;
    let fix = Modelled {
        model: CartesianSensor {
            frame: cfg.frame,
            sigma: sigma_g,
        },
        noise: SensorNoise::gaussian([sigma_g; 3]),
    };
    cfg.sigma_gnss = sigma_g;
    let precise = Modelled {
        model: CartesianSensor {
            frame: cfg.frame,
            sigma: 1e-4,
        },
        noise: SensorNoise::gaussian([1e-4; 3]),
    };
    let mut none = Navigator::new(&cfg).unwrap();
    none.add_sensor(Arc::new(Named::new("position", fix)));
    none.add_sensor(Arc::new(Named::new("precise", precise)));
    let (mut gnss_only, mut precise_only) = (none.clone(), none.clone());
    let g = Vec3::new(x[0] + 1.5, x[1] - 2.0, x[2] + 0.5);
    let g_io = cfg.frame.vec_from_canonical(&g);
    gnss_only
        .step_with(&[0.0; 3], None, &[Some(g_io.as_slice()), None], 1.0)
        .unwrap();
    precise_only
        .step_with(&[0.0; 3], None, &[None, Some(g_io.as_slice())], 1.0)
        .unwrap();
    none.step_with(&[0.0; 3], None, &[None, None], 1.0).unwrap();
    let x1 = none.state();
    // the design's information: the radio's at the initial estimate plus the GNSS's
    let x0 = cfg.initial_state();
    let mut cfg0 = cfg;
    cfg0.sigma_range = 0.0;
    cfg0.sigma_angle = 0.0;
    let noiseless = |r: &Vec3| {
        let mut s = x0;
        s.fixed_rows_mut::<3>(0).copy_from(r);
        Vec3::from(radio(&cfg0, &s, &mut ChaCha8Rng::seed_from_u64(0)))
    };
    let r0 = x0.fixed_rows::<3>(0).into_owned();
    let mut h = Mat3::zeros();
    for k in 0..3 {
        let mut d = Vec3::zeros();
        d[k] = 1e-4;
        h.set_column(k, &((noiseless(&(r0 + d)) - noiseless(&(r0 - d))) / 2e-4));
    }
    let ri = Mat3::from_diagonal(&Vec3::new(
        cfg.sigma_range.powi(-2),
        cfg.sigma_angle.powi(-2),
        cfg.sigma_angle.powi(-2),
    ));
    let j_g = Mat3::identity() / (sigma_g * sigma_g);
    let n = (h.transpose() * ri * h + j_g).try_inverse().unwrap();
    let AnyFilter::Hinf(f) = none.filter() else {
        panic!("not the H-infinity filter")
    };
    let b_f = f.filter().matrices().b_f;
    let want = b_f * (n * j_g * (g - r0));
    // the navigator's state is in the I/O frame
    let got = cfg.frame.state_to_canonical(&(gnss_only.state() - x1));
    assert!(
        (got - want).abs().max() <= 1e-6 * want.abs().max(),
        "{got} vs {want}"
    );
    let want = b_f * (g - r0);
    let got = cfg.frame.state_to_canonical(&(precise_only.state() - x1));
    assert!(
        (got - want).abs().max() <= 1e-3 * want.abs().max(),
        "{got} vs {want}"
    );
}

/// A design that measures the velocity (`hinf_sensors` 4 + 8, relative GNSS) takes a
/// velocity reading; one without refuses it, naming `hinf_sensors`.
#[cfg(feature = "hinf")]
#[test]
fn the_hinf_filter_takes_a_velocity_when_its_design_measures_one() {
    use crate::sensors::VelocitySensor;
    let (mut cfg, x) = setup(9);
    let vel = Named::new("GNSS velocity", VelocitySensor::gaussian(cfg.frame, 5e-4));
    let v_io = cfg
        .frame
        .vec_from_canonical(&x.fixed_rows::<3>(3).into_owned());
    let mut nav = Navigator::new(&cfg).unwrap();
    nav.add_sensor(Arc::new(vel.clone()));
    let e = nav
        .step_with(&[0.0; 3], None, &[Some(v_io.as_slice())], 1.0)
        .unwrap_err();
    assert!(e.message.contains("hinf_sensors"), "{e}");
    cfg.hinf_sensors = 12;
    let mut nav = Navigator::new(&cfg).unwrap();
    nav.add_sensor(Arc::new(vel));
    let before = nav.state();
    nav.step_with(&[0.0; 3], None, &[Some(v_io.as_slice())], 1.0)
        .unwrap();
    assert_ne!(nav.state(), before);
}

/// `step_with` checks every reading before anything changes, applies the radio then the
/// added sensors in their order, and leaves a Kalman filter as it was when a later update
/// fails.
#[test]
fn step_with_checks_orders_and_undoes() {
    let (cfg, x) = setup(1);
    let mut nav = Navigator::new(&cfg).unwrap();
    let vel = Velocity { sigma: 5e-4 };
    nav.add_sensor(Arc::new(Named::new("velocity", vel)));
    let z = radio(&cfg, &x, &mut ChaCha8Rng::seed_from_u64(2));
    let zv = [0.05, 0.05, 0.05];
    let before = nav.clone();
    let wrong = [1.0, 2.0];
    for (readings, what) in [
        (vec![Some(&wrong[..])], "3 components"),
        (vec![Some(&[f64::NAN, 0.0, 0.0][..])], "finite"),
        (vec![], "readings given"),
    ] {
        let e = nav
            .step_with(&[0.0; 3], Some(&z), &readings, 1.0)
            .unwrap_err();
        assert_eq!(e.kind, NavErrorKind::InvalidArgument);
        assert!(e.message.contains(what), "{e}");
        assert_eq!(nav.state(), before.state());
    }
    // the order: radio, then the velocity, then the prediction
    let mut other = before.clone();
    other.update(&z).unwrap();
    other
        .step_with(&[0.0; 3], None, &[Some(&zv[..])], 1.0)
        .unwrap();
    nav.step_with(&[0.0; 3], Some(&z), &[Some(&zv[..])], 1.0)
        .unwrap();
    assert_eq!(nav.filter().state(), other.filter().state());
    assert_eq!(nav.filter().covariance(), other.filter().covariance());
    assert!(nav.sensor_report(0).unwrap().nis.is_finite());
    // a failing later update undoes the radio's and the velocity's
    nav.add_sensor(Arc::new(Named::new("broken", Broken)));
    let kept = (nav.state(), nav.covariance(), nav.sensor_report(0));
    let e = nav
        .step_with(&[0.0; 3], Some(&z), &[Some(&zv[..]), Some(&[1.0][..])], 1.0)
        .unwrap_err();
    assert_eq!(e.kind, NavErrorKind::Numerical, "{e}");
    assert_eq!((nav.state(), nav.covariance(), nav.sensor_report(0)), kept);
    nav.reset();
    assert!(nav.sensor_report(0).is_none());
}

/// A sensor whose every linearisation fails.
#[derive(Debug, Clone, Copy)]
struct Broken;

impl Sensor<1> for Broken {
    fn measure(&self, _: &State) -> Option<SVector<f64, 1>> {
        None
    }
    fn linearize(&self, _: &State) -> Result<Linearization<1>, GeometryError> {
        Err(GeometryError::ZeroRange)
    }
    fn noise(&self) -> SensorNoise<1> {
        SensorNoise::gaussian([1.0])
    }
}

/// The AQUKF's adaptation takes the first update after a prediction only (its window's
/// term is per prediction interval): a velocity reading in the same step as the radio
/// changes the estimate, not the adapted density.
#[test]
fn the_aqukf_adapts_on_the_first_update_of_a_step() {
    let (cfg, x) = setup(3);
    // the window law adapts at every update it takes (the gated one only while its gate
    // is open)
    let cfg = NavConfig {
        aq_law: crate::estimators::AdaptationLaw::Window,
        ..cfg
    };
    let z = radio(&cfg, &x, &mut ChaCha8Rng::seed_from_u64(5));
    let zv = [0.3, -0.2, 0.1];
    let mut alone = Navigator::new(&cfg).unwrap();
    let mut with = alone.clone();
    with.add_sensor(Arc::new(Named::new("velocity", Velocity { sigma: 5e-4 })));
    // a first step (no interval before it) the same for both, then the radio with and
    // without the velocity after a prediction of 1 s
    alone.step(&[0.0; 3], Some(&z), 1.0).unwrap();
    with.step_with(&[0.0; 3], Some(&z), &[None], 1.0).unwrap();
    alone.step(&[0.0; 3], Some(&z), 1.0).unwrap();
    with.step_with(&[0.0; 3], Some(&z), &[Some(&zv[..])], 1.0)
        .unwrap();
    assert_ne!(alone.state(), with.state());
    assert_eq!(alone.q_vv(), with.q_vv());
    assert_ne!(alone.q_vv(), Some(cfg.q_vel), "the radio's update adapted");
}

/// A particle filter large enough for the chunked path weighs an added sensor's reading
/// there too, with results that do not depend on the thread count.
#[test]
fn the_generic_path_is_thread_count_independent() {
    use crate::estimators::pf::PARALLEL_MIN_PARTICLES;
    let (cfg, x) = setup(4);
    let run = |threads: usize| {
        let mut cfg = cfg;
        (cfg.particles, cfg.pf_threads) = (PARALLEL_MIN_PARTICLES, threads);
        let mut nav = Navigator::new(&cfg).unwrap();
        nav.add_sensor(Arc::new(Named::new("velocity", Velocity { sigma: 5e-4 })));
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut xt = x;
        for _ in 0..3 {
            let z = radio(&cfg, &xt, &mut rng);
            let zv = noisy(
                Velocity { sigma: 5e-4 }.measure(&xt).unwrap(),
                5e-4,
                &mut rng,
            );
            nav.step_with(&[0.0; 3], Some(&z), &[Some(&zv[..])], 1.0)
                .unwrap();
            xt = propagate(cfg.mean_motion, &xt, 1.0);
        }
        (nav.state(), nav.covariance())
    };
    assert_eq!(run(1), run(2));
}

/// The declared sensors (`Navigator::step_readings`): relative GNSS alone (position and
/// velocity, I/O frame 2, readings formed here) brings every filter but the H-infinity
/// one to the GNSS's level; the per-step NIS is reported for the sensors that gave a
/// reading (NaN for the others, and from point particles, which have no predictive
/// Gaussian; the particle prior's Gaussian sum has one); a bad camera reading is refused
/// naming the camera, with
/// the estimate unchanged; `range_sigma` is the covariance along the estimated line of
/// sight.
#[test]
fn declared_sensors_through_step_readings() {
    let priors = [PfPrior::Particle, PfPrior::Gaussian];
    let cases = [1, 2, 3, 10]
        .map(|c| (c, PfPrior::Particle))
        .into_iter()
        .chain(
            [4, 5, 6, 7, 8]
                .into_iter()
                .flat_map(|c| priors.map(|p| (c, p))),
        );
    for (code, pf_prior) in cases {
        let (cfg, mut x) = setup(code);
        let cfg = NavConfig { pf_prior, ..cfg };
        let mut nav = Navigator::new(&cfg).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (mut sq, mut n) = (0.0, 0);
        for k in 0..200 {
            let p = noisy(Vec3::new(x[1], x[0], -x[2]), cfg.sigma_gnss, &mut rng);
            let v = noisy(
                Vec3::new(x[4], x[3], -x[5]),
                cfg.sigma_gnss_velocity,
                &mut rng,
            );
            let r = Readings {
                gnss_position: Some(p),
                gnss_velocity: (k % 2 == 0).then_some(v),
                ..Default::default()
            };
            nav.step_readings(&[0.0; 3], &r, 1.0)
                .unwrap_or_else(|e| panic!("filter {code}, step {k}: {e}"));
            let nis = nav.step_nis();
            assert!(nis[0].is_nan() && nis[1].is_nan(), "{nis:?}");
            let kalman = matches!(code, 1 | 2 | 3 | 10) || pf_prior == PfPrior::Particle;
            assert_eq!(nis[2].is_finite(), kalman, "filter {code}: {nis:?}");
            assert_eq!(
                nis[3].is_finite(),
                kalman && k % 2 == 0,
                "filter {code}: {nis:?}"
            );
            x = propagate(cfg.mean_motion, &x, 1.0);
            if k >= 100 {
                let est = cfg.frame.state_to_canonical(&nav.state());
                sq += (est.fixed_rows::<3>(0) - x.fixed_rows::<3>(0)).norm_squared();
                n += 1;
            }
        }
        let rms = (sq / n as f64).sqrt();
        eprintln!("filter {code}: GNSS only, RMS position {rms:.4} m");
        // well inside the single fix's 3-axis error (sqrt(3) sigma_gnss): the filter
        // averages the fixes
        assert!(rms < 3f64.sqrt() * cfg.sigma_gnss, "filter {code}: {rms}");
        // a bad camera reading: refused, naming the camera, nothing changed
        let before = (nav.state(), nav.covariance());
        let bad = Readings {
            camera: Some([0.1, 2.0]),
            ..Default::default()
        };
        let e = nav.step_readings(&[0.0; 3], &bad, 1.0).unwrap_err();
        assert!(e.message.contains("camera"), "{}", e.message);
        assert_eq!((nav.state(), nav.covariance()), before);
        // the range's 1-sigma along the estimated line of sight
        let xs = nav.filter.state();
        let u = Vec3::new(xs[0], xs[1], xs[2]).normalize();
        let pr = nav
            .filter
            .covariance()
            .fixed_view::<3, 3>(0, 0)
            .into_owned();
        let want = (u.transpose() * pr * u)[0].sqrt();
        assert!((nav.range_sigma() - want).abs() <= 1e-12 * want);
    }
    // the radio and the camera in one step: both NIS reported
    let (cfg, x) = setup(1);
    let mut nav = Navigator::new(&cfg).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let z = radio(&cfg, &x, &mut rng);
    let r = Readings {
        radio: Some(z),
        camera: Some([z[1], z[2]]),
        ..Default::default()
    };
    nav.step_readings(&[0.0; 3], &r, 1.0).unwrap();
    let nis = nav.step_nis();
    assert!(nis[0].is_finite() && nis[1].is_finite() && nis[2].is_nan() && nis[3].is_nan());
    // a plain step reports the radio alone
    nav.step(&[0.0; 3], None, 1.0).unwrap();
    assert!(nav.step_nis().iter().all(|v| v.is_nan()));
}

/// `Navigator::update_readings` (FMI 3.0's Event Mode) then `Navigator::predict` is the
/// step: the same estimate, bit for bit, in every filter but the H-infinity one, with one
/// reading and with several (radio, camera and GNSS position together); a bad reading is
/// refused with nothing changed, and no reading is no update.
#[test]
fn update_readings_then_predict_is_the_step() {
    for code in [1, 2, 3, 10, 4, 5, 6, 7, 8] {
        let (cfg, x) = setup(code);
        let (mut stepped, mut split) =
            (Navigator::new(&cfg).unwrap(), Navigator::new(&cfg).unwrap());
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut x = x;
        for k in 0..40 {
            let z = radio(&cfg, &x, &mut rng);
            let p = noisy(Vec3::new(x[1], x[0], -x[2]), cfg.sigma_gnss, &mut rng);
            let r = if k % 3 == 0 {
                Readings {
                    radio: Some(z),
                    camera: Some([z[1], z[2]]),
                    gnss_position: Some(p),
                    ..Default::default()
                }
            } else {
                Readings {
                    radio: Some(z),
                    ..Default::default()
                }
            };
            let thrust = [0.5, -0.2, 0.1];
            stepped.step_readings(&thrust, &r, 1.0).unwrap();
            split.update_readings(&r).unwrap();
            split.predict(&thrust, 1.0).unwrap();
            assert_eq!(
                (stepped.state(), stepped.covariance()),
                (split.state(), split.covariance()),
                "filter {code}, step {k}"
            );
            x = propagate(cfg.mean_motion, &x, 1.0);
        }
        let before = (split.state(), split.covariance());
        let bad = Readings {
            radio: Some([1000.0, 0.1, 0.1]),
            camera: Some([0.1, 2.0]),
            ..Default::default()
        };
        let e = split.update_readings(&bad).unwrap_err();
        assert!(e.message.contains("camera"), "{}", e.message);
        split.update_readings(&Readings::default()).unwrap();
        assert_eq!((split.state(), split.covariance()), before);
    }
}

/// The declared sensors' own noise densities: a Kalman filter told a Student-t camera
/// (or a contaminated-Gaussian GNSS) takes the Gaussian of its variance, so its update
/// is the one told the Gaussian of that sigma; a particle filter weighs with the density
/// itself, so its estimate differs from the one told the Gaussian.
#[test]
fn declared_sensors_take_their_noise_models() {
    let base = NavConfig {
        frame: Frame::RadialAlongNormal,
        x0: [0.0, -1500.0, 20.0, 0.0, 0.0, 0.0],
        sigma_pos0: 30.0,
        sigma_vel0: 0.01,
        accel_psd: 1e-10,
        particles: 400,
        ..NavConfig::default()
    };
    let dof = 4.0;
    let zeta_scale = (0.2, 10.0);
    let gnss_var = 1.0 - zeta_scale.0 + zeta_scale.0 * zeta_scale.1 * zeta_scale.1;
    let told = NavConfig {
        camera_noise_model: NoiseKind::StudentT,
        camera_noise_dof: dof,
        gnss_noise_model: NoiseKind::Mixture,
        gnss_noise_zeta: zeta_scale.0,
        gnss_noise_scale: zeta_scale.1,
        ..base
    };
    let matched = NavConfig {
        sigma_camera: base.sigma_camera * (dof / (dof - 2.0)).sqrt(),
        sigma_gnss: base.sigma_gnss * gnss_var.sqrt(),
        sigma_gnss_velocity: base.sigma_gnss_velocity * gnss_var.sqrt(),
        ..base
    };
    let readings = |k: usize| Readings {
        camera: Some([-FRAC_PI_2 + 1e-4 * k as f64, 0.013]),
        gnss_position: Some([0.1, -1490.0 + 0.01 * k as f64, 19.0]),
        gnss_velocity: Some([0.0, 0.01, 0.0]),
        ..Readings::default()
    };
    // point particles weigh with the density; the Kalman filters (and the particle
    // prior's terms, for these sensors) take its variance
    for kind in [FilterKind::Ekf, FilterKind::Ukf, FilterKind::Pf] {
        let mut a = Navigator::new(&NavConfig {
            filter: kind,
            pf_prior: PfPrior::Gaussian,
            ..told
        })
        .unwrap();
        let mut b = Navigator::new(&NavConfig {
            filter: kind,
            pf_prior: PfPrior::Gaussian,
            ..matched
        })
        .unwrap();
        for k in 0..20 {
            a.step_readings(&[0.0; 3], &readings(k), 1.0).unwrap();
            b.step_readings(&[0.0; 3], &readings(k), 1.0).unwrap();
        }
        let d = (a.state() - b.state()).norm();
        if kind == FilterKind::Pf {
            assert!(d > 1e-6, "{kind:?}: the density made no difference ({d})");
        } else {
            assert!(d < 1e-9 * a.state().norm(), "{kind:?}: {d}");
        }
    }
}

/// A particle filter started from the first measurements draws its positions from the
/// first position fix and its velocities from a velocity reading of that same step, so a
/// GNSS velocity (Student-t, 0.5 mm/s) far more precise than the 1 m/s velocity prior
/// does not leave one particle: after the first step the cloud's velocity spread is the
/// reading's noise and every particle still counts.
#[test]
fn particle_filters_draw_their_velocities_from_the_first_velocity_reading() {
    let sigma_v = 5e-4;
    let cfg = NavConfig {
        filter: FilterKind::Pf,
        pf_prior: PfPrior::Gaussian,
        frame: Frame::RadialAlongNormal,
        particles: 1000,
        accel_psd: 1e-14,
        q_pos: [0.0; 3],
        q_vel: [0.0; 3],
        sigma_gnss_velocity: sigma_v,
        gnss_noise_model: NoiseKind::StudentT,
        gnss_noise_dof: 4.0,
        ..NavConfig::default()
    };
    let truth_v = [0.01, -0.02, 0.005];
    let mut nav = Navigator::new(&cfg).unwrap();
    let first = Readings {
        gnss_position: Some([400.0, 500.0, 200.0]),
        gnss_velocity: Some(truth_v),
        ..Readings::default()
    };
    // measured before the prediction: the update alone
    nav.step_readings(&[0.0; 3], &first, 1e-9).unwrap();
    let s = nav.sigma();
    let spread = sigma_v * (4.0f64 / 2.0).sqrt();
    for a in 3..6 {
        assert!(
            s[a] > 0.5 * spread && s[a] < 2.0 * spread,
            "axis {a}: {}",
            s[a]
        );
        assert!((nav.state()[a] - truth_v[a - 3]).abs() < spread);
    }
    assert!(nav.ess().unwrap() > 900.0);
}
