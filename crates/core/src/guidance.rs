//! The guidance law of the system kit (`relnav_guidance.fmu`): a hold-point controller in
//! the Hill frame that turns the navigation estimate into thrust, so that a closed GNC loop
//! (plant -> relnav -> guidance -> plant) can be assembled from FMUs and estimation errors
//! really move the chaser.
//!
//! **Law** (canonical Hill frame, state `X = (r, v)`, hold point `r_h` at rest in the
//! rotating frame): the accelerations of the linearised relative motion are cancelled and a
//! PD law with natural frequency `w` (`bandwidth`) and damping ratio `zeta` acts on the
//! error,
//!
//! ```text
//! a = -w^2 (r - r_h) - 2 zeta w v - f(X, t),   f_cw(X) = (3 n^2 x + 2 n vy, -2 n vx, -n^2 z)
//! ```
//!
//! with `f = f_cw` on a circular orbit and, at `eccentricity > 0`, the velocity rows of the
//! elliptic model's `A(t) X` ([`crate::dynamics::EllipticModel::continuous_a`]),
//!
//! so that the closed loop is `e'' + 2 zeta w e' + w^2 e = 0` on every axis (a V-bar hold,
//! `x_h = z_h = 0`, costs no thrust at rest; elsewhere `f_cw(r_h)` is held by thrust). The
//! force `F = m a` is limited per axis to `thrust_max` (axis-aligned thrusters).
//!
//! **Sampled data** (one step of computational delay, compensated): at `fmi2DoStep(t, h)`
//! the input is the estimate at `t`; the thrust `F_k` applied over `[t, t + h)` is this law's
//! previous output, so the estimate is predicted to `t + h` with the exact transition of the
//! same model, `X+ = Phi X + Gamma F_k / m` and the law evaluated there gives `F_(k+1)`, published
//! at `t + h` and applied over `[t + h, t + 2h)`. The output does not depend on the inputs
//! of the same communication point (no direct feedthrough), so the loop has no algebraic
//! loop in any master.
//!
//! **Minimum impulse bit** `I_min`: thrusters cannot deliver less than `I_min` [N s] per
//! firing. The commanded impulse `F h` is accumulated per axis; an axis fires when its
//! accumulated impulse reaches `I_min` (delivering it, at most `thrust_max`), and stays off
//! otherwise — the average impulse is kept, the chaser dithers within about `I_min / m` of
//! velocity around the hold point.

use crate::dynamics::{Discretization, Dynamics, RelativeDynamics};
use crate::frames::Frame;
use crate::nav::config::ECCENTRICITY_RULE;
use crate::numerics::state::{Reader, StateError, Writer};
use crate::params::{closed, Rule};
use crate::types::{Mat3, Mat6, Mat63, State, Vec3};

crate::config! {
    /// Everything that defines the guidance law: relnav_guidance.fmu's parameters (value
    /// references in the declarations). [`Default`]: frame 2, a 7200 s orbit, 1000 kg, the
    /// hold point (300, 0, 0) m, bandwidth 0.01 rad/s, damping 0.9, 10 N per axis.
    pub struct GuidanceConfig, GUIDANCE_PARAMS;
    frame: Frame {
        elements: [("frame", 0, "", 2, "")],
        rule: Rule::Any, c: false, scenario: None, slot: None,
        description: "Hill-frame convention of the estimate, the hold point and the thrust (as relnav's frame)",
    },
    mean_motion: f64 {
        elements: [("mean_motion", 1, "rad/s", 2.0 * core::f64::consts::PI / 7200.0, "")],
        rule: Rule::Interval { lo: closed(1e-9), hi: closed(0.1), why: " rad/s" },
        c: false, scenario: None, slot: None,
        description: "Mean motion of the target's orbit, 2 pi / period (1e-9..0.1)",
    },
    chaser_mass: f64 {
        elements: [("chaser_mass", 2, "kg", 1000.0, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Chaser mass: thrust = mass * commanded acceleration (> 0)",
    },
    hold: [f64; 3] {
        elements: [
            ("hold_x", 3, "m", 300.0, "Hold point x (at rest in the Hill frame)"),
            ("hold_y", 4, "m", 0.0, "Hold point y"),
            ("hold_z", 5, "m", 0.0, "Hold point z"),
        ],
        rule: Rule::Finite, c: false, scenario: None, slot: None,
        description: "Hold point in the I/O frame",
    },
    bandwidth: f64 {
        elements: [("bandwidth", 6, "rad/s", 0.01, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Natural frequency w of the closed loop e'' + 2 zeta w e' + w^2 e = 0 (> 0; w * step <= 0.5)",
    },
    damping: f64 {
        elements: [("damping", 7, "", 0.9, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Damping ratio zeta of the closed loop (> 0)",
    },
    thrust_max: f64 {
        elements: [("thrust_max", 8, "N", 10.0, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Largest thrust per axis (> 0)",
    },
    min_impulse_bit: f64 {
        elements: [("min_impulse_bit", 9, "N.s", 0.0, "")],
        rule: Rule::NonNegative, c: false, scenario: None, slot: None,
        description: "Smallest impulse a thruster delivers: the commanded impulse is accumulated per axis and fired once it reaches this bit (0: none)",
    },
    engage_time: f64 {
        elements: [("engage_time", 10, "s", 0.0, "")],
        rule: Rule::Finite, c: false, scenario: None, slot: None,
        description: "Time from which thrust is commanded (zero thrust before)",
    },
    eccentricity: f64 {
        elements: [("eccentricity", 22, "", 0.0, "")],
        rule: ECCENTRICITY_RULE,
        c: false, scenario: None, slot: None,
        description: "Eccentricity of the target's orbit (0 <= e <= 0.99): the law cancels and predicts with the linearised elliptic model (Yamanaka-Ankersen) when > 0, with CW at 0",
    },
    true_anomaly0: f64 {
        elements: [("true_anomaly0", 23, "rad", 0.0, "")],
        rule: Rule::Finite, c: false, scenario: None, slot: None,
        description: "True anomaly of the target at the start time (unused at eccentricity 0)",
    },
}

/// Largest `bandwidth * h` a step may have: the sampled PD loop (with the one-step delay
/// compensated by prediction) is well damped below it; a longer step is refused.
pub const MAX_BANDWIDTH_STEP: f64 = 0.5;

impl GuidanceConfig {
    /// Check every setting; the message names the first bad one.
    pub fn validate(&self) -> Result<(), String> {
        for p in GUIDANCE_PARAMS {
            p.check(self)?;
        }
        Ok(())
    }
}

/// The guidance law with its memory: the thrust being applied, the impulse accumulators,
/// the velocity increment spent.
#[derive(Debug, Clone, Copy)]
pub struct Guidance {
    cfg: GuidanceConfig,
    model: Dynamics,
    /// start time: the elliptic model's epoch (true anomaly `true_anomaly0`)
    t0: f64,
    hold: Vec3,
    cache: Option<(f64, Mat6, Mat63)>,
    /// Thrust applied over the current step [N, canonical].
    thrust: Vec3,
    /// Commanded impulse not yet delivered [N s, canonical].
    pending: Vec3,
    delta_v: f64,
}

impl Guidance {
    /// The law at rest (zero thrust until its first step).
    pub fn new(cfg: GuidanceConfig) -> Result<Self, String> {
        cfg.validate()?;
        Ok(Self {
            cfg,
            model: Dynamics::of_orbit(cfg.mean_motion, cfg.eccentricity, cfg.true_anomaly0),
            t0: 0.0,
            hold: cfg.frame.vec_to_canonical(&Vec3::from_row_slice(&cfg.hold)),
            cache: None,
            thrust: Vec3::zeros(),
            pending: Vec3::zeros(),
            delta_v: 0.0,
        })
    }

    /// The same law started at time `t0` (the instant the target is at `true_anomaly0`;
    /// [`Guidance::new`] starts at 0).
    pub fn starting_at(mut self, t0: f64) -> Self {
        self.t0 = t0;
        self
    }

    /// Thrust commanded for the current step [N, I/O frame].
    pub fn thrust(&self) -> Vec3 {
        self.cfg.frame.vec_from_canonical(&self.thrust)
    }

    /// Velocity increment delivered so far [m/s]: `sum |F|_1 h / m` (the sum over the three
    /// axis-aligned thrusters, which is what they burn).
    pub fn delta_v(&self) -> f64 {
        self.delta_v
    }

    /// The law's acceleration for the canonical state `x` at time `t` (before the thrust
    /// limit).
    pub fn acceleration(&self, x: &State, t: f64) -> Vec3 {
        let (w, zeta) = (self.cfg.bandwidth, self.cfg.damping);
        let r = x.fixed_rows::<3>(0).into_owned();
        let v = x.fixed_rows::<3>(3).into_owned();
        let f = (self.model.system_matrix(t - self.t0) * x)
            .fixed_rows::<3>(3)
            .into_owned();
        -(r - self.hold) * (w * w) - v * (2.0 * zeta * w) - f
    }

    /// One step from `t` over `h` with the estimate `estimate` [I/O frame] at `t`: account
    /// for the thrust applied over `[t, t + h)`, then command the thrust for the next step
    /// (see the module documentation).
    pub fn step(&mut self, estimate: &State, t: f64, h: f64) -> Result<(), String> {
        if !(h.is_finite() && h > 0.0) {
            return Err(format!("step must be finite and > 0 (got {h})"));
        }
        if self.cfg.bandwidth * h > MAX_BANDWIDTH_STEP {
            return Err(format!(
                "a step of {h} s is too long for bandwidth {} rad/s: bandwidth * step must be \
                 <= {MAX_BANDWIDTH_STEP} for the sampled loop to stay well damped",
                self.cfg.bandwidth
            ));
        }
        if let Some(i) = estimate.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "estimate {} must be finite (got {})",
                ["x", "y", "z", "vx", "vy", "vz"][i],
                estimate[i]
            ));
        }
        let m = self.cfg.chaser_mass;
        self.delta_v += self.thrust.abs().sum() * h / m;
        let (phi, gamma) = match self.cache {
            Some((hc, p, g)) if hc.to_bits() == h.to_bits() => (p, g),
            _ => {
                let d = self
                    .model
                    .step(t - self.t0, h, &Mat3::zeros(), Discretization::Exact);
                if self.model.time_invariant() {
                    self.cache = Some((h, d.phi, d.gamma));
                }
                (d.phi, d.gamma)
            }
        };
        let x = self.cfg.frame.state_to_canonical(estimate);
        let predicted = phi * x + gamma * (self.thrust / m);
        let tol = 1e-9 * (t + h).abs().max(1.0);
        let fmax = self.cfg.thrust_max;
        let command = if t + h >= self.cfg.engage_time - tol {
            (self.acceleration(&predicted, t + h) * m).map(|f| f.clamp(-fmax, fmax))
        } else {
            Vec3::zeros()
        };
        let bit = self.cfg.min_impulse_bit;
        self.thrust = if bit > 0.0 {
            self.pending += command * h;
            let mut fire = Vec3::zeros();
            for i in 0..3 {
                if self.pending[i].abs() >= bit {
                    fire[i] = (self.pending[i] / h).clamp(-fmax, fmax);
                    self.pending[i] -= fire[i] * h;
                }
            }
            fire
        } else {
            command
        };
        Ok(())
    }

    /// Bytes of the law's memory (thrust, accumulators, velocity increment).
    pub fn save(&self, w: &mut Writer<'_>) {
        w.tag(b"GDNC");
        w.matrix(&self.thrust);
        w.matrix(&self.pending);
        w.f64(self.delta_v);
    }

    /// Read what [`Guidance::save`] wrote; on error nothing changes.
    pub fn load(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        r.tag(b"GDNC")?;
        let thrust = r.finite_matrix("thrust")?;
        let pending = r.finite_matrix("impulse accumulator")?;
        let dv = r.finite("delta_v")?;
        self.thrust = thrust;
        self.pending = pending;
        self.delta_v = dv;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::CwModel;

    /// On the exact CW truth the closed loop reaches the hold point from paper 000's
    /// start (with the estimate equal to the truth), and a V-bar hold costs nothing once
    /// there.
    #[test]
    fn closed_loop_on_the_truth_reaches_the_hold_point() {
        let cfg = GuidanceConfig::default();
        let mut g = Guidance::new(cfg).unwrap();
        let m = CwModel::new(cfg.mean_motion);
        let f = cfg.frame;
        let mut x = f.state_to_canonical(&State::from_row_slice(&[
            400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
        ]));
        for k in 0..3000 {
            let a = f.vec_to_canonical(&g.thrust()) / cfg.chaser_mass;
            g.step(&f.state_from_canonical(&x), k as f64, 1.0).unwrap();
            x = m.phi(1.0) * x + m.gamma(1.0) * a;
        }
        let hold = f.vec_to_canonical(&Vec3::from_row_slice(&cfg.hold));
        assert!((x.fixed_rows::<3>(0) - hold).norm() < 1e-6, "{x}");
        assert!(g.thrust().norm() < 1e-6);
    }

    /// With a minimum impulse bit every firing delivers at least the bit, and the loop
    /// still holds within a small ripple.
    #[test]
    fn minimum_impulse_bit() {
        let cfg = GuidanceConfig {
            min_impulse_bit: 0.5,
            ..GuidanceConfig::default()
        };
        let mut g = Guidance::new(cfg).unwrap();
        let m = CwModel::new(cfg.mean_motion);
        let f = cfg.frame;
        let mut x = f.state_to_canonical(&State::from_row_slice(&[
            400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
        ]));
        let hold = f.vec_to_canonical(&Vec3::from_row_slice(&cfg.hold));
        let mut worst = 0.0f64;
        for k in 0..4000 {
            let th = g.thrust();
            assert!(th.iter().all(|v| *v == 0.0 || v.abs() >= 0.5), "{th}");
            let a = f.vec_to_canonical(&th) / cfg.chaser_mass;
            g.step(&f.state_from_canonical(&x), k as f64, 1.0).unwrap();
            x = m.phi(1.0) * x + m.gamma(1.0) * a;
            if k > 3000 {
                worst = worst.max((x.fixed_rows::<3>(0) - hold).norm());
            }
        }
        assert!(worst < 0.5, "ripple {worst} m");
    }
}
