//! Orbit propagation for the nonlinear truths of the evaluation engine and of the plant FMU
//! (`relnav_plant`): a hand-written high-order integrator (Gragg–Bulirsch–Stoer
//! extrapolation), classical RK4, the accelerations of the two-body problem with J2 (Earth),
//! and [`TwoBodyJ2`], the target and the chaser propagated together with the relative state
//! read in the target's Hill frame. (The Mars approach of `eval::mars` uses the integrators
//! with its own accelerations.)
//!
//! No crate was added: `ode_solvers` (the usual choice) pins its own nalgebra version and
//! adaptive stepping is not wanted here (the truth is sampled on a fixed 1 s grid). The GBS
//! step (modified midpoint with `n_j = 2, 4, 6, 8, 10` substeps, Aitken–Neville
//! extrapolation in `h^2`; Hairer, Nørsett & Wanner, *Solving ODEs I*, sec. II.9) is of
//! order 10; a test checks its order and energy/angular-momentum conservation.

use crate::types::{State, Vec3};
use nalgebra::SVector;

/// Standard gravitational parameter of the Earth [m^3/s^2] (EGM-96).
pub const MU_EARTH: f64 = 3.986_004_418e14;
/// Equatorial radius of the Earth [m].
pub const R_EARTH: f64 = 6_378_137.0;
/// Second zonal harmonic of the Earth (EGM-96, unnormalised).
pub const J2_EARTH: f64 = 1.082_626_68e-3;

/// One classical RK4 step of `y' = f(t, y)` over `h`.
pub fn rk4_step<F: Fn(f64, &State) -> State>(f: &F, t: f64, y: &State, h: f64) -> State {
    let k1 = f(t, y);
    let k2 = f(t + 0.5 * h, &(y + k1 * (0.5 * h)));
    let k3 = f(t + 0.5 * h, &(y + k2 * (0.5 * h)));
    let k4 = f(t + h, &(y + k3 * h));
    y + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
}

/// Substep counts of the GBS extrapolation (order `2 * len` = 10).
const GBS_SEQ: [usize; 5] = [2, 4, 6, 8, 10];

/// One Gragg–Bulirsch–Stoer step of `y' = f(t, y)` over `h` (order 10; see the module
/// documentation), for a state of any dimension `D`.
pub fn gbs_step<const D: usize, F: Fn(f64, &SVector<f64, D>) -> SVector<f64, D>>(
    f: &F,
    t: f64,
    y: &SVector<f64, D>,
    h: f64,
) -> SVector<f64, D> {
    let f0 = f(t, y);
    let mut table = [SVector::<f64, D>::zeros(); 5];
    for (j, &n) in GBS_SEQ.iter().enumerate() {
        // modified midpoint with n substeps
        let hs = h / n as f64;
        let mut z0 = *y;
        let mut z1 = y + f0 * hs;
        for m in 1..n {
            let z2 = z0 + f(t + m as f64 * hs, &z1) * (2.0 * hs);
            z0 = z1;
            z1 = z2;
        }
        let mut tj = (z1 + z0 + f(t + h, &z1) * hs) * 0.5;
        // Aitken–Neville: extrapolate to h -> 0 along the row
        for k in 1..=j {
            let ratio = (n as f64 / GBS_SEQ[j - k] as f64).powi(2);
            let prev = table[k - 1];
            let new = tj + (tj - prev) / (ratio - 1.0);
            table[k - 1] = tj;
            tj = new;
        }
        table[j] = tj;
    }
    table[GBS_SEQ.len() - 1]
}

/// Two-body acceleration plus the J2 zonal term (z = the Earth's pole):
/// `a = -mu r / r^3 - (3/2) J2 mu R^2 / r^5 (x (1 - 5 z^2/r^2), y (1 - 5 z^2/r^2), z (3 - 5 z^2/r^2))`.
pub fn accel_j2(r: &Vec3) -> Vec3 {
    let r2 = r.norm_squared();
    let rn = r2.sqrt();
    let k = 1.5 * J2_EARTH * MU_EARTH * R_EARTH * R_EARTH / (r2 * r2 * rn);
    let z2 = r.z * r.z / r2;
    -r * (MU_EARTH / (r2 * rn))
        - Vec3::new(
            r.x * (1.0 - 5.0 * z2),
            r.y * (1.0 - 5.0 * z2),
            r.z * (3.0 - 5.0 * z2),
        ) * k
}

/// `(r, v)' = (v, accel_j2(r) + a_extra)`.
pub fn j2_rhs(x: &State, a_extra: &Vec3) -> State {
    let r = x.fixed_rows::<3>(0).into_owned();
    let a = accel_j2(&r) + a_extra;
    State::from_row_slice(&[x[3], x[4], x[5], a.x, a.y, a.z])
}

/// `(r, v)' = (v, -mu r / r^3 + a_extra)` (point-mass gravity).
pub fn point_mass_rhs(x: &State, a_extra: &Vec3) -> State {
    let r = x.fixed_rows::<3>(0).into_owned();
    let a = -r * (MU_EARTH / r.norm().powi(3)) + a_extra;
    State::from_row_slice(&[x[3], x[4], x[5], a.x, a.y, a.z])
}

/// The local-vertical frame of a target `(r, v)`: rows are the canonical Hill axes (x
/// radial, y along-track = h x r, z orbit normal), and the frame's rotation rate
/// `|r x v| / r^2` about its z axis.
pub fn hill_frame(target: &State) -> (nalgebra::Matrix3<f64>, f64) {
    let r = target.fixed_rows::<3>(0).into_owned();
    let v = target.fixed_rows::<3>(3).into_owned();
    let h = r.cross(&v);
    let xr = r.normalize();
    let zn = h.normalize();
    let ya = zn.cross(&xr);
    let rot = nalgebra::Matrix3::from_rows(&[xr.transpose(), ya.transpose(), zn.transpose()]);
    (rot, h.norm() / r.norm_squared())
}

/// Canonical relative state (Hill frame of `target`, rotating-frame velocity) of `chaser`.
pub fn relative_state(target: &State, chaser: &State) -> State {
    let (rot, w) = hill_frame(target);
    let dr = rot * (chaser.fixed_rows::<3>(0) - target.fixed_rows::<3>(0));
    let dv = rot * (chaser.fixed_rows::<3>(3) - target.fixed_rows::<3>(3));
    let omega = Vec3::new(0.0, 0.0, w);
    let rel_v = dv - omega.cross(&dr);
    State::from_row_slice(&[dr.x, dr.y, dr.z, rel_v.x, rel_v.y, rel_v.z])
}

/// Inverse of [`relative_state`]: the chaser's inertial state from the relative one.
pub fn chaser_from_relative(target: &State, rel: &State) -> State {
    let (rot, w) = hill_frame(target);
    let dr = rel.fixed_rows::<3>(0).into_owned();
    let omega = Vec3::new(0.0, 0.0, w);
    let dv = rel.fixed_rows::<3>(3) + omega.cross(&dr);
    let r = target.fixed_rows::<3>(0) + rot.transpose() * dr;
    let v = target.fixed_rows::<3>(3) + rot.transpose() * dv;
    State::from_row_slice(&[r.x, r.y, r.z, v.x, v.y, v.z])
}

/// A circular orbit of mean motion `n` [rad/s] at inclination `incl` [rad], at the
/// ascending node at t = 0 (Earth-centred inertial).
pub fn circular_target(n: f64, incl: f64) -> State {
    let a = (MU_EARTH / (n * n)).cbrt();
    let v = (MU_EARTH / a).sqrt();
    State::from_row_slice(&[a, 0.0, 0.0, 0.0, v * incl.cos(), v * incl.sin()])
}

/// A Keplerian orbit of mean motion `n` [rad/s] and eccentricity `e` at inclination `incl`
/// [rad], perigee at the ascending node (argument of perigee and node 0), at true anomaly
/// `nu` (Earth-centred inertial): `r = p / (1 + e cos nu)` along `(cos nu, sin nu)` and
/// `v = sqrt(mu / p) (-sin nu, e + cos nu)` in the orbit plane, `p = a (1 - e^2)`.
pub fn keplerian_target(n: f64, e: f64, nu: f64, incl: f64) -> State {
    let a = (MU_EARTH / (n * n)).cbrt();
    let p = a * (1.0 - e * e);
    let (sn, cn) = nu.sin_cos();
    let r = p / (1.0 + e * cn);
    let v = (MU_EARTH / p).sqrt();
    let (si, ci) = incl.sin_cos();
    let (px, py) = (r * cn, r * sn);
    let (vx, vy) = (-v * sn, v * (e + cn));
    State::from_row_slice(&[px, py * ci, py * si, vx, vy * ci, vy * si])
}

/// The two-body + J2 truth of both spacecraft: a target on a circular
/// ([`TwoBodyJ2::new`]) or Keplerian ([`TwoBodyJ2::keplerian`]) orbit and the chaser,
/// both around the Earth (point mass + J2, [`gbs_step`] substeps), thrust acting on the
/// chaser along the target's (rotating) Hill axes.
/// The relative state is read in the target's Hill frame ([`relative_state`]). Used by the
/// evaluation engine's `two_body_j2` scenarios and by the plant FMU's `truth_model` 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoBodyJ2 {
    /// Target (ECI position and velocity).
    pub target: State,
    /// Chaser (ECI position and velocity).
    pub chaser: State,
    /// Longest integration substep [s]: a step `dt` takes `round(dt / substep)` (at least
    /// one) equal substeps.
    pub substep: f64,
    /// Whether J2 acts (true from the constructors); false: point-mass gravity alone.
    pub j2: bool,
}

impl TwoBodyJ2 {
    /// Target on the circular orbit of mean motion `n` [rad/s] at inclination `incl` [rad]
    /// ([`circular_target`]), chaser at the canonical relative state `rel0`.
    pub fn new(n: f64, incl: f64, rel0: &State, substep: f64) -> Self {
        let target = circular_target(n, incl);
        let chaser = chaser_from_relative(&target, rel0);
        Self {
            target,
            chaser,
            substep,
            j2: true,
        }
    }

    /// Target on the Keplerian orbit of mean motion `n`, eccentricity `e` and inclination
    /// `incl` at true anomaly `nu0` ([`keplerian_target`]), chaser at the canonical relative
    /// state `rel0`. At `e = 0` this is [`TwoBodyJ2::new`] (the circular orbit from its
    /// ascending node; `nu0` unused).
    pub fn keplerian(n: f64, e: f64, nu0: f64, incl: f64, rel0: &State, substep: f64) -> Self {
        if e == 0.0 {
            return Self::new(n, incl, rel0, substep);
        }
        let target = keplerian_target(n, e, nu0, incl);
        Self {
            target,
            chaser: chaser_from_relative(&target, rel0),
            substep,
            j2: true,
        }
    }

    /// Canonical relative state now (Hill frame of the target, rotating-frame velocity).
    pub fn relative(&self) -> State {
        relative_state(&self.target, &self.chaser)
    }

    /// Propagate both over `[t0, t0 + dt)` with the chaser's thrust acceleration `accel`
    /// held along the target's Hill axes as they rotate (what the linear models' zero-order
    /// hold assumes): target and chaser are one 12-dimensional system for the integrator,
    /// the axes taken from the target's state at every evaluation.
    pub fn step(&mut self, accel: &Vec3, t0: f64, dt: f64) {
        let sub = (dt / self.substep).round().max(1.0) as usize;
        let h = dt / sub as f64;
        let j2 = self.j2;
        let gravity = move |y: &State, a: &Vec3| {
            if j2 {
                j2_rhs(y, a)
            } else {
                point_mass_rhs(y, a)
            }
        };
        let thrust = *accel != Vec3::zeros();
        let rhs = |_: f64, y: &SVector<f64, 12>| {
            let target = y.fixed_rows::<6>(0).into_owned();
            let chaser = y.fixed_rows::<6>(6).into_owned();
            let a_in = if thrust {
                hill_frame(&target).0.transpose() * accel
            } else {
                Vec3::zeros()
            };
            let (dt_, dc) = (gravity(&target, &Vec3::zeros()), gravity(&chaser, &a_in));
            SVector::<f64, 12>::from_fn(|i, _| if i < 6 { dt_[i] } else { dc[i - 6] })
        };
        let mut y = SVector::<f64, 12>::from_fn(|i, _| {
            if i < 6 {
                self.target[i]
            } else {
                self.chaser[i - 6]
            }
        });
        for j in 0..sub {
            y = gbs_step(&rhs, t0 + j as f64 * h, &y, h);
        }
        self.target = y.fixed_rows::<6>(0).into_owned();
        self.chaser = y.fixed_rows::<6>(6).into_owned();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kepler(x: &State) -> State {
        let r = x.fixed_rows::<3>(0).into_owned();
        let a = -r * (MU_EARTH / r.norm().powi(3));
        State::from_row_slice(&[x[3], x[4], x[5], a.x, a.y, a.z])
    }

    fn energy(x: &State) -> f64 {
        0.5 * x.fixed_rows::<3>(3).norm_squared() - MU_EARTH / x.fixed_rows::<3>(0).norm()
    }

    /// An eccentric Kepler orbit closes after one period (the analytic solution), and the
    /// error falls like h^10 (order check by halving the step).
    #[test]
    fn gbs_closes_a_kepler_orbit_with_order_ten() {
        let (rp, e) = (7.0e6, 0.3);
        let a = rp / (1.0 - e);
        let vp = (MU_EARTH * (1.0 + e) / rp).sqrt();
        let x0 = State::from_row_slice(&[rp, 0.0, 0.0, 0.0, vp, 0.0]);
        let period = 2.0 * core::f64::consts::PI * (a.powi(3) / MU_EARTH).sqrt();
        let err = |steps: usize| {
            let h = period / steps as f64;
            let mut x = x0;
            for k in 0..steps {
                x = gbs_step(&|_, y: &State| kepler(y), k as f64 * h, &x, h);
            }
            (x - x0).fixed_rows::<3>(0).norm()
        };
        assert!(
            err(100) < 1e-3,
            "position error after one period {} m",
            err(100)
        );
        // truncation-dominated regime (h = T/16 .. T/32): order 10 gives a ratio of 1024
        let (e1, e2) = (err(16), err(32));
        eprintln!("GBS error after one period: {e1:e} m (16 steps), {e2:e} m (32 steps)");
        assert!(e1 / e2 > 300.0, "ratio {e1} / {e2}");
        // RK4 with the same number of evaluations (32 GBS steps ~ 1100 evaluations)
        let h = period / 280.0;
        let mut x = x0;
        for k in 0..280 {
            x = rk4_step(&|_, y: &State| kepler(y), k as f64 * h, &x, h);
        }
        assert!((x - x0).fixed_rows::<3>(0).norm() > 10.0 * e2);
    }

    /// With J2 the energy `v^2/2 - mu/r + U_J2` and the polar angular momentum are conserved.
    #[test]
    fn j2_motion_conserves_energy_and_polar_angular_momentum() {
        let x0 = circular_target(0.0011, 0.9);
        let u_j2 = |x: &State| {
            let r = x.fixed_rows::<3>(0).norm();
            let s = x[2] / r;
            MU_EARTH * J2_EARTH * R_EARTH * R_EARTH / (2.0 * r.powi(3)) * (3.0 * s * s - 1.0)
        };
        let en = |x: &State| energy(x) + u_j2(x);
        let hz = |x: &State| x[0] * x[4] - x[1] * x[3];
        let mut x = x0;
        for k in 0..6000 {
            x = gbs_step(&|_, y: &State| j2_rhs(y, &Vec3::zeros()), k as f64, &x, 1.0);
        }
        assert!((en(&x) - en(&x0)).abs() < 1e-9 * en(&x0).abs());
        assert!((hz(&x) - hz(&x0)).abs() < 1e-10 * hz(&x0).abs());
        // and J2 does act: the orbit plane precesses
        let h0 = x0.fixed_rows::<3>(0).cross(&x0.fixed_rows::<3>(3));
        let h1 = x.fixed_rows::<3>(0).cross(&x.fixed_rows::<3>(3));
        assert!(h0.normalize().dot(&h1.normalize()) < 1.0 - 1e-9);
    }

    #[test]
    fn relative_state_round_trip() {
        let t = circular_target(0.0011, 0.5);
        let rel = State::from_row_slice(&[-3000.0, 50_000.0, 200.0, 0.1, 5.0, -0.2]);
        let c = chaser_from_relative(&t, &rel);
        assert!((relative_state(&t, &c) - rel).norm() < 1e-6);
    }
}
