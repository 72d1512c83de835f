//! The adaptive estimate of the velocity process-noise density ([`AdaptiveQ`]): the
//! sliding window of Maybeck's observations, the windowed-NIS gate of the gated law and
//! the fading factor (see the [module documentation](super) for the equations), and its
//! saved state.

use super::params::{AdaptationLaw, AqParams, MAX_GATE_WINDOW, MAX_WINDOW};
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::numerics::clamp;
use crate::numerics::state::{refuse, Persist, Reader, StateError, Writer};
use crate::types::{Mat6, State, Vec3};

/// Wilson–Hilferty approximation of the chi-square quantile with `dof` degrees of freedom
/// at the standard normal quantile `z`: `dof (1 - 2/(9 dof) + z sqrt(2/(9 dof)))^3`.
pub fn chi2_quantile_wh(dof: f64, z: f64) -> f64 {
    let c = 2.0 / (9.0 * dof);
    let b = 1.0 - c + z * c.sqrt();
    dof * b * b * b
}

/// The standard normal quantile at `p` in (0, 1) (NaN outside): Wichura's algorithm AS 241
/// (PPND16, 1988), relative error about 1e-16, as R's `qnorm` computes it. Written here
/// rather than taken from statrs because the core also builds without `std`, which statrs
/// needs; a unit test holds it to statrs's quantile.
#[allow(clippy::excessive_precision)] // the published coefficients, as printed
pub(super) fn normal_quantile(p: f64) -> f64 {
    fn horner(c: &[f64; 8], r: f64) -> f64 {
        c.iter().rev().fold(0.0, |acc, &k| acc * r + k)
    }
    const A: [f64; 8] = [
        3.387132872796366608,
        133.14166789178437745,
        1971.5909503065514427,
        13731.693765509461125,
        45921.953931549871457,
        67265.770927008700853,
        33430.575583588128105,
        2509.0809287301226727,
    ];
    const B: [f64; 8] = [
        1.0,
        42.313330701600911252,
        687.1870074920579083,
        5394.1960214247511077,
        21213.794301586595867,
        39307.89580009271061,
        28729.085735721942674,
        5226.495278852545925,
    ];
    const C: [f64; 8] = [
        1.42343711074968357734,
        4.6303378461565452959,
        5.7694972214606914055,
        3.64784832476320460504,
        1.27045825245236838258,
        0.24178072517745061177,
        0.0227238449892691845833,
        7.7454501427834140764e-4,
    ];
    const D: [f64; 8] = [
        1.0,
        2.05319162663775882187,
        1.6763848301838038494,
        0.68976733498510000455,
        0.14810397642748007459,
        0.0151986665636164571966,
        5.475938084995344946e-4,
        1.05075007164441684324e-9,
    ];
    const E: [f64; 8] = [
        6.6579046435011037772,
        5.4637849111641143699,
        1.7848265399172913358,
        0.29656057182850489123,
        0.026532189526576123093,
        0.0012426609473880784386,
        2.71155556874348757815e-5,
        2.01033439929228813265e-7,
    ];
    const F: [f64; 8] = [
        1.0,
        0.59983220655588793769,
        0.13692988092273580531,
        0.0148753612908506148525,
        7.868691311456132591e-4,
        1.8463183175100546818e-5,
        1.4215117583164458887e-7,
        2.04426310338993978564e-15,
    ];
    if !(p > 0.0 && p < 1.0) {
        return f64::NAN;
    }
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180625 - q * q;
        return q * horner(&A, r) / horner(&B, r);
    }
    let r = (-(if q < 0.0 { p } else { 1.0 - p }).ln()).sqrt();
    let v = if r <= 5.0 {
        horner(&C, r - 1.6) / horner(&D, r - 1.6)
    } else {
        horner(&E, r - 5.0) / horner(&F, r - 5.0)
    };
    if q < 0.0 {
        -v
    } else {
        v
    }
}

/// [`AdaptiveQ::nominal`] of `params`.
fn nominal(params: &AqParams) -> Vec3 {
    let (lo, hi) = (params.floor, params.ceiling.max(params.floor));
    params.q_vv0.map(|v| clamp(v, lo, hi))
}

/// The sliding-window estimate of the velocity process-noise density (see the [module
/// documentation](super) for the equations).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveQ {
    pub(super) params: AqParams,
    pub(super) q: Vec3,
    pub(super) ring: [[f64; 3]; MAX_WINDOW],
    pub(super) head: usize,
    pub(super) len: usize,
    /// gated law: (NIS, degrees of freedom) of the last `gate_window` updates
    pub(super) gate: [[f64; 2]; MAX_GATE_WINDOW],
    pub(super) gate_head: usize,
    pub(super) gate_len: usize,
    /// normal quantile of `gate_quantile`
    pub(super) gate_z: f64,
    /// gated law: the last test rejected consistency
    pub(super) open: bool,
    /// covariance inflation for the next prediction
    pub(super) inflation: f64,
}

impl AdaptiveQ {
    /// A fresh estimate at `params.q_vv0` (clipped), with an empty window.
    #[inline(always)]
    pub fn new(params: AqParams) -> Self {
        // one literal, every field computed first: the value is built where it is returned
        // (a local copied out would hold the window twice on the stack)
        let q = nominal(&params);
        Self {
            params,
            q,
            ring: [[0.0; 3]; MAX_WINDOW],
            head: 0,
            len: 0,
            gate: [[0.0; 2]; MAX_GATE_WINDOW],
            gate_head: 0,
            gate_len: 0,
            gate_z: normal_quantile(params.gate_quantile),
            open: false,
            inflation: 1.0,
        }
    }

    /// Back to the initial value, empty window.
    pub fn reset(&mut self) {
        self.q = self.nominal();
        self.head = 0;
        self.len = 0;
        self.gate_head = 0;
        self.gate_len = 0;
        self.open = false;
        self.inflation = 1.0;
    }

    /// The nominal `q_vv0` clipped into `[floor, ceiling]`: the start value, and the value
    /// of the gated law while its gate is closed.
    pub fn nominal(&self) -> Vec3 {
        nominal(&self.params)
    }

    /// Gated law: whether the last test found the innovations inconsistent (the estimate
    /// is adapting). Always false for the window law.
    pub fn gate_open(&self) -> bool {
        self.open
    }

    /// Gated law: the factor `lambda >= 1` by which the next prediction inflates the
    /// prior covariance (1 while the gate is closed, and always for the window law).
    pub fn inflation(&self) -> f64 {
        self.inflation
    }

    /// Gated law: the windowed NIS and its degrees of freedom over the last
    /// `gate_window` updates.
    pub fn windowed_nis(&self) -> (f64, f64) {
        let (mut s, mut d) = (0.0, 0.0);
        for e in self.gate.iter().take(self.gate_len) {
            s += e[0];
            d += e[1];
        }
        (s, d)
    }

    /// The settings.
    pub fn params(&self) -> &AqParams {
        &self.params
    }

    /// Current `q_vv` [m^2/s^3] per axis of the filter's frame.
    pub fn q_vv(&self) -> Vec3 {
        self.q
    }

    /// Number of observations in the window (at most `window`).
    pub fn filled(&self) -> usize {
        self.len
    }

    /// Observe one update: `dx = x+ - x-`, `p_post = P+`, `p_prior = P-`, `t` [s] the time
    /// since the previous update (> 0), `nis` the update's normalised innovation squared
    /// with `dof` degrees of freedom (used by the gated law only). Non-finite observations
    /// are ignored (the estimate keeps its value).
    pub fn observe(
        &mut self,
        dx: &State,
        p_post: &Mat6,
        p_prior: &Mat6,
        t: f64,
        nis: f64,
        dof: f64,
    ) {
        if !(t > 0.0 && t.is_finite()) {
            return;
        }
        let mut d = [0.0; 3];
        for (i, di) in d.iter_mut().enumerate() {
            let v = 3 + i;
            // diag_v(Q*_k - Qhat_k-1) / T = diag_v(dX dX^T + P_k - P_k|k-1) / T
            *di = (dx[v] * dx[v] + p_post[(v, v)] - p_prior[(v, v)]) / t;
        }
        if !d.iter().all(|v| v.is_finite()) {
            return;
        }
        let n = self.params.window.clamp(1, MAX_WINDOW);
        if let Some(slot) = self.ring.get_mut(self.head) {
            *slot = d;
        }
        self.head = (self.head + 1) % n;
        self.len = (self.len + 1).min(n);
        let mut sum = [0.0; 3];
        for e in self.ring.iter().take(self.len) {
            for i in 0..3 {
                sum[i] += e[i];
            }
        }
        let (lo, hi) = (
            self.params.floor,
            self.params.ceiling.max(self.params.floor),
        );
        match self.params.law {
            AdaptationLaw::Window => {
                for (q, s) in self.q.iter_mut().zip(sum) {
                    *q = clamp(*q + s / n as f64, lo, hi);
                }
            }
            AdaptationLaw::Gated => {
                if nis.is_finite() && nis >= 0.0 && dof > 0.0 {
                    let m = self.params.gate_window.clamp(1, MAX_GATE_WINDOW);
                    if let Some(slot) = self.gate.get_mut(self.gate_head) {
                        *slot = [nis, dof];
                    }
                    self.gate_head = (self.gate_head + 1) % m;
                    self.gate_len = (self.gate_len + 1).min(m);
                }
                let (s_nis, d) = self.windowed_nis();
                self.open = d > 0.0 && s_nis > chi2_quantile_wh(d, self.gate_z);
                let q0 = self.nominal();
                // the fading factor of the next prediction: the current NIS per degree
                // of freedom (finite and >= 0: checked where the gate was fed)
                self.inflation = if self.open && nis.is_finite() && dof > 0.0 {
                    (nis / dof).max(1.0)
                } else {
                    1.0
                };
                if self.open {
                    for ((q, s), q0) in self.q.iter_mut().zip(sum).zip(q0.iter()) {
                        *q = clamp(*q + s / n as f64, *q0, hi);
                    }
                } else {
                    self.q = q0;
                }
            }
        }
    }
}

/// Saved state: `q_vv` (3), the ring's write position `head` and fill `len`, the window
/// width `N` (u64 each; `N` must equal the configuration's), then the `N` slots of the ring
/// (3 each). The settings are configuration.
impl Persist for AdaptiveQ {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            params,
            q,
            ring,
            head,
            len,
            gate,
            gate_head,
            gate_len,
            gate_z: _,
            open,
            inflation,
        } = self;
        let n = params.window.clamp(1, MAX_WINDOW);
        w.matrix(q);
        w.usize(*head);
        w.usize(*len);
        w.usize(n);
        for slot in ring.iter().take(n) {
            for v in slot {
                w.f64(*v);
            }
        }
        let m = params.gate_window.clamp(1, MAX_GATE_WINDOW);
        w.usize(*gate_head);
        w.usize(*gate_len);
        w.usize(m);
        for slot in gate.iter().take(m) {
            for v in slot {
                w.f64(*v);
            }
        }
        w.bool(*open);
        w.f64(*inflation);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self {
            params,
            q,
            ring,
            head,
            len,
            gate,
            gate_head,
            gate_len,
            gate_z: _,
            open,
            inflation,
        } = self;
        let n = params.window.clamp(1, MAX_WINDOW);
        *q = r.finite_matrix("AQUKF q_vv")?;
        *head = r.usize("AQUKF window position")?;
        *len = r.usize("AQUKF window fill")?;
        if *head >= n || *len > n {
            return Err(refuse(crate::msg!(
                "AQUKF window position {head} / fill {len} out of range for window {n}"
            )));
        }
        r.count("AQUKF window width", n)?;
        for slot in ring.iter_mut().take(n) {
            for v in slot.iter_mut() {
                *v = r.finite("AQUKF window entry")?;
            }
        }
        let m = params.gate_window.clamp(1, MAX_GATE_WINDOW);
        *gate_head = r.usize("AQUKF gate position")?;
        *gate_len = r.usize("AQUKF gate fill")?;
        if *gate_head >= m || *gate_len > m {
            return Err(refuse(crate::msg!(
                "AQUKF gate position {gate_head} / fill {gate_len} out of range for gate window {m}"
            )));
        }
        r.count("AQUKF gate window width", m)?;
        for slot in gate.iter_mut().take(m) {
            for v in slot.iter_mut() {
                *v = r.finite("AQUKF gate entry")?;
            }
        }
        *open = r.bool("AQUKF gate state")?;
        let f = r.finite("AQUKF covariance inflation")?;
        if f < 1.0 {
            return Err(refuse(crate::msg!(
                "AQUKF covariance inflation {f} below 1"
            )));
        }
        *inflation = f;
        Ok(())
    }
}
