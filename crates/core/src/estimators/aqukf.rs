//! Sliding-window adaptive UKF, AQUKF (paper 001, sec. 2.2): a UKF whose velocity process
//! noise is estimated online from the state corrections of the last `N` updates.
//!
//! **Maybeck's observation** of the process noise at update `k` (P. S. Maybeck, *Stochastic
//! models, estimation and control*, vol. 2, 1982, eq. 10-43; paper 001 eq. 27):
//!
//! ```text
//! Q*_k = dX_k dX_k^T + P_k - (P_k|k-1 - Qhat_k-1),     dX_k = Xhat_k - Xhat_k|k-1
//! ```
//!
//! **Erratum.** Paper 001 (eq. 27, also the digest) prints `dX dX^T - [P_k - (P_k|k-1 -
//! Qhat)]`. With that sign `E[Q*] = 2 (P_k|k-1 - P_k) - Qhat` (because `E[dX dX^T] =
//! P_k|k-1 - P_k` for a consistent filter), which is not an estimate of `Q` at all; Maybeck's
//! `+ P_k - P_k|k-1 + Qhat` gives `E[Q*] = Q`. We implement Maybeck's sign.
//!
//! **Sliding window** of width `N` (paper 001 eq. 29):
//! `Qhat_k = Qhat_k-1 + (1/N) sum_{j=k-N+1..k} (Q*_j - Qhat_j-1)` (missing terms before the
//! first update count as zero). Note that `Q*_j - Qhat_j-1 = dX_j dX_j^T + P_j - P_j|j-1`
//! does not depend on `Qhat`: the recursion integrates the window mean of the filter's
//! inconsistency. `N = 1` is the undamped Maybeck update `Qhat_k = Q*_k` (weight
//! `omega_Q = 1` in eq. 28).
//!
//! **Velocity-only form** (eqs. 30-32): only the diagonal of the velocity block is kept, as
//! a rate `q_vv = diag(Qhat_vv) / T` with `T` the time since the previous update (the filter
//! period). We read the paper's "continuous form" literally: `q_vv` [m^2/s^3] is the
//! spectral density of a white acceleration per axis, and the next prediction adds its
//! exact discretisation over the step (Van Loan for CW; for the orbit model of the Mars
//! problem the double-integrator form `[[T^3/3, T^2/2], [T^2/2, T]] q`), on top of any fixed
//! process noise the caller adds. The rate recursion stored here is therefore
//!
//! ```text
//! d_j = diag_v(dX_j dX_j^T + P_j - P_j|j-1) / T_j                (3 numbers per update)
//! q_k = clamp(q_k-1 + (1/N) sum_{j=k-N+1..k} d_j, floor, ceiling)
//! ```
//!
//! **Positive semidefiniteness** (the projection): `Qhat_k = blockdiag(0, diag(q_k))` with
//! every `q_k,i` clipped into `[floor, ceiling]`, `0 <= floor <= ceiling`. Clipping the
//! diagonal is the Frobenius-nearest point of the raw velocity diagonal in the box of
//! diagonal matrices with eigenvalues in `[floor, ceiling]`; the off-diagonal terms and the
//! position block of `Q*` are dropped (as the paper does), so the estimate is PSD by
//! construction and bounded. The window entries `d_j` themselves are not clipped.
//!
//! **Adaptation laws** ([`AdaptationLaw`]). `Window` is the recursion above, applied at
//! every update: paper 001 literally. Its estimate random-walks around the truth when the
//! model is right (each `d_j` scatters by about `q` itself), and the filter pays for that
//! scatter in every quiet minute. `Gated` (the default) leaves `Q` alone while the
//! innovations are consistent with it and adapts only when they are not:
//!
//! ```text
//! S_k = sum_{j=k-M+1..k} nu_j^T S_j^-1 nu_j          (windowed NIS, M = gate_window)
//! D_k = sum_{j=k-M+1..k} m_j                          (its degrees of freedom, m_j = 3 or 2)
//! open_k = S_k > chi2inv(gate_quantile, D_k)
//! if open_k:  q_k = clamp(q_k-1 + (1/N) sum_{j=k-N+1..k} d_j, max(floor, q_0), ceiling)
//!             lambda_k = max(1, nu_k^T S_k^-1 nu_k / m_k)
//! otherwise:  q_k = q_0,  lambda_k = 1
//! next prediction:  P- = f(lambda_k P+) + Q(q_k)      (sigma points of lambda_k P+)
//! ```
//!
//! *The gate.* The innovations of a consistent filter are white with covariance `S`
//! (Bar-Shalom, Li & Kirubarajan 2001, sec. 5.4), so the windowed NIS is chi-square with
//! `D_k` degrees of freedom and the gate opens by chance with probability
//! `1 - gate_quantile` per test; while it is closed the filter is the fixed-`Q` UKF, bit
//! for bit. The quantile is the Wilson–Hilferty approximation
//! `D (1 - 2/(9D) + z sqrt(2/(9D)))^3` with the normal quantile `z` of `gate_quantile`
//! computed once (relative error at 0.999: 1.7 % for `D = 3`, 0.17 % for `D = 30`, the
//! default window of 10 updates; far inside the gate's own statistical width).
//!
//! *While it is open*, two things happen. (1) The sliding window above adapts `q` from
//! the nominal `q_0` (its ring keeps the `d_j` of every update, open or not); it never
//! lowers `q` below `q_0`: the gate tests for too little process noise, the failure that
//! costs accuracy without bound. (2) The next prediction inflates the prior covariance by
//! the current NIS per degree of freedom, the fading factor of the adaptive fading Kalman
//! filter (Xia, Rao, Ying & Shen 1994; the strong tracking filter of Zhou & Frank 1996;
//! gated by a chi-square test as in the robust adaptive UKF of Hajiyev & Soken 2014). (1)
//! alone is slow when `q_0` is small: `d_j` measures the filter's *correction*
//! `dX = K nu`, and with a small `Q` the velocity gain is small, so `q` grows only
//! geometrically and then overshoots (measured on `model_error_burns`: 29 s to recover from
//! the first burn, velocity errors up to 1.6 m/s while `q` overshoots to 0.6 m^2/s^3). The
//! fading factor responds to the innovation itself within one step, and the corrections
//! that follow feed the window with the level the manoeuvre needs (0.10 m position RMSE
//! after the burns, against 0.26 m for the window law and 3.5 m for the UKF). Once the
//! windowed NIS is consistent again, `q` returns to `q_0` and `lambda` to 1.
//!
//! **No allocation**: the window is a fixed-capacity ring buffer of [`MAX_WINDOW`] entries
//! inside the filter. An update with no prediction since the previous one (`T = 0`, e.g.
//! the very first measurement at `t = 0`) carries no information on `Q` and is not
//! observed.
//!
//! The adaptive core ([`AdaptiveQ`], [`AdaptiveUkf`]) is generic over the process model
//! (a closure for the mean and one for the noise discretisation): [`Aqukf`] uses it with the
//! CW model behind the [`Estimator`] trait (navigator, C ABI, FMU); the Mars approach of the
//! evaluation engine (`eval::mars`) uses it with an RK4 step of a nonlinear orbit.

use super::{Estimator, FilterError, Ukf, UkfParams, UpdateInfo};
use crate::dynamics::{CwModel, DiscreteModel};
use crate::numerics::state::{refuse, Persist, Reader, StateError, Writer};
use crate::sensors::MeasurementModel;
use crate::types::{Mat3, Mat6, State, Vec3};
use nalgebra::{SMatrix, SVector};

/// Largest sliding-window width (capacity of the ring buffer).
pub const MAX_WINDOW: usize = 512;

/// Largest NIS-gate window (capacity of its ring buffer).
pub const MAX_GATE_WINDOW: usize = 128;

/// How the AQUKF adapts its velocity process noise (codes shared by the C ABI's
/// `relnav_adaptation` and the FMU's `aq_law` parameter).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(i32)]
pub enum AdaptationLaw {
    /// Paper 001 literally: the sliding-window recursion at every update.
    Window = 1,
    /// The same recursion, applied only while the windowed NIS exceeds its chi-square
    /// bound; `q_vv = q_vv0` otherwise (see the module documentation).
    Gated = 2,
}

impl AdaptationLaw {
    /// All codes, in order.
    pub const ALL: [AdaptationLaw; 2] = [AdaptationLaw::Window, AdaptationLaw::Gated];

    /// From the stable code 1..=2.
    pub fn from_code(code: i32) -> Option<Self> {
        Self::ALL.into_iter().find(|k| *k as i32 == code)
    }

    /// Short name (`window`, `gated`).
    pub fn name(self) -> &'static str {
        match self {
            AdaptationLaw::Window => "window",
            AdaptationLaw::Gated => "gated",
        }
    }
}

/// Wilson–Hilferty approximation of the chi-square quantile with `dof` degrees of freedom
/// at the standard normal quantile `z`: `dof (1 - 2/(9 dof) + z sqrt(2/(9 dof)))^3`.
pub fn chi2_quantile_wh(dof: f64, z: f64) -> f64 {
    let c = 2.0 / (9.0 * dof);
    let b = 1.0 - c + z * c.sqrt();
    dof * b * b * b
}

/// The standard normal quantile at `p` in (0, 1) (NaN outside).
fn normal_quantile(p: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, Normal};
    if !(p > 0.0 && p < 1.0) {
        return f64::NAN;
    }
    match Normal::new(0.0, 1.0) {
        Ok(n) => n.inverse_cdf(p),
        Err(_) => f64::NAN,
    }
}

/// Settings of the adaptive process noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AqParams {
    /// Window width `N`, `1..=MAX_WINDOW` (paper 001: 10).
    pub window: usize,
    /// Initial velocity spectral density `q_vv` per axis [m^2/s^3] (clipped into
    /// `[floor, ceiling]`).
    pub q_vv0: Vec3,
    /// Lower bound on each `q_vv` entry [m^2/s^3], `>= 0`.
    pub floor: f64,
    /// Upper bound on each `q_vv` entry [m^2/s^3], `>= floor`, finite.
    pub ceiling: f64,
    /// Adaptation law (default [`AdaptationLaw::Gated`]).
    pub law: AdaptationLaw,
    /// Gated law: number `M` of updates in the windowed NIS, `1..=MAX_GATE_WINDOW`
    /// (default 10).
    pub gate_window: usize,
    /// Gated law: the gate opens when the windowed NIS exceeds its chi-square quantile at
    /// this probability, in (0, 1) (default 0.999: a false alarm in one test of 1000).
    pub gate_quantile: f64,
}

impl Default for AqParams {
    fn default() -> Self {
        Self {
            window: 10,
            q_vv0: Vec3::zeros(),
            floor: 0.0,
            ceiling: 1.0,
            law: AdaptationLaw::Gated,
            gate_window: 10,
            gate_quantile: 0.999,
        }
    }
}

impl AqParams {
    /// Check the settings; the message names the offending one.
    pub fn validate(&self) -> Result<(), String> {
        if !(1..=MAX_WINDOW).contains(&self.window) {
            return Err(format!(
                "window must lie in 1..={MAX_WINDOW} (got {})",
                self.window
            ));
        }
        if !(self.floor.is_finite() && self.floor >= 0.0) {
            return Err(format!(
                "q_vv_floor must be finite and >= 0 (got {})",
                crate::numerics::num(self.floor)
            ));
        }
        if !(self.ceiling.is_finite() && self.ceiling >= self.floor && self.ceiling > 0.0) {
            return Err(format!(
                "q_vv_ceiling must be finite, > 0 and >= q_vv_floor (got {}, floor {})",
                crate::numerics::num(self.ceiling),
                crate::numerics::num(self.floor)
            ));
        }
        if !self.q_vv0.iter().all(|q| q.is_finite() && *q >= 0.0) {
            return Err(format!(
                "the initial q_vv must be finite and >= 0 (got {:?})",
                self.q_vv0.as_slice()
            ));
        }
        if !(1..=MAX_GATE_WINDOW).contains(&self.gate_window) {
            return Err(format!(
                "aq_gate_window must lie in 1..={MAX_GATE_WINDOW} (got {})",
                self.gate_window
            ));
        }
        if !(self.gate_quantile > 0.0 && self.gate_quantile < 1.0) {
            return Err(format!(
                "aq_gate_quantile must lie in (0, 1) (got {}): the chi-square probability \
                 of the NIS gate",
                crate::numerics::num(self.gate_quantile)
            ));
        }
        Ok(())
    }
}

/// The sliding-window estimate of the velocity process-noise density (see the module
/// documentation for the equations).
#[derive(Debug, Clone, PartialEq)]
pub struct AdaptiveQ {
    params: AqParams,
    q: Vec3,
    ring: [[f64; 3]; MAX_WINDOW],
    head: usize,
    len: usize,
    /// gated law: (NIS, degrees of freedom) of the last `gate_window` updates
    gate: [[f64; 2]; MAX_GATE_WINDOW],
    gate_head: usize,
    gate_len: usize,
    /// normal quantile of `gate_quantile`
    gate_z: f64,
    /// gated law: the last test rejected consistency
    open: bool,
    /// covariance inflation for the next prediction
    inflation: f64,
}

impl AdaptiveQ {
    /// A fresh estimate at `params.q_vv0` (clipped), with an empty window.
    pub fn new(params: AqParams) -> Self {
        let mut a = Self {
            params,
            q: Vec3::zeros(),
            ring: [[0.0; 3]; MAX_WINDOW],
            head: 0,
            len: 0,
            gate: [[0.0; 2]; MAX_GATE_WINDOW],
            gate_head: 0,
            gate_len: 0,
            gate_z: normal_quantile(params.gate_quantile),
            open: false,
            inflation: 1.0,
        };
        a.reset();
        a
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
        let (lo, hi) = (
            self.params.floor,
            self.params.ceiling.max(self.params.floor),
        );
        self.params.q_vv0.map(|v| v.clamp(lo, hi))
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
                    *q = (*q + s / n as f64).clamp(lo, hi);
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
                        *q = (*q + s / n as f64).clamp(*q0, hi);
                    }
                } else {
                    self.q = q0;
                }
            }
        }
    }
}

/// What one AQUKF update and prediction can change, kept to undo a failed step without
/// copying the window: the UKF, the adaptive estimate, the window's write position and
/// the one slot the next update overwrites (so it undoes at most one update).
#[derive(Debug, Clone, PartialEq)]
pub struct AqukfSnapshot {
    ukf: Ukf,
    q: Vec3,
    head: usize,
    len: usize,
    slot: [f64; 3],
    gate_head: usize,
    gate_len: usize,
    gate_slot: [f64; 2],
    open: bool,
    inflation: f64,
    elapsed: f64,
}

/// Discrete covariance of a white acceleration of density `diag(q)` for the double
/// integrator `r' = v, v' = a` over `t`: `[[t^3/3, t^2/2], [t^2/2, t]] (x) diag(q)` (exact
/// Van Loan for that model). The noise model of the Mars approach filters.
pub fn double_integrator_q(q: &Vec3, t: f64) -> Mat6 {
    let mut m = Mat6::zeros();
    for i in 0..3 {
        m[(i, i)] = q[i] * t * t * t / 3.0;
        m[(i, i + 3)] = q[i] * t * t / 2.0;
        m[(i + 3, i)] = q[i] * t * t / 2.0;
        m[(i + 3, i + 3)] = q[i] * t;
    }
    m
}

/// A UKF with the sliding-window adaptive velocity noise, generic over the process model:
/// [`AdaptiveUkf::predict_with`] takes the mean propagation and the discretisation of the
/// adaptive density as closures.
#[derive(Debug, Clone, PartialEq)]
pub struct AdaptiveUkf {
    ukf: Ukf,
    adapt: AdaptiveQ,
    /// time predicted since the last update [s]
    elapsed: f64,
}

impl AdaptiveUkf {
    /// From the initial estimate, the sigma-point parameters and the adaptive settings
    /// (validated by the caller).
    pub fn new(x0: State, p0: Mat6, ukf: UkfParams, aq: AqParams) -> Self {
        Self {
            ukf: Ukf::new(x0, p0, ukf),
            adapt: AdaptiveQ::new(aq),
            elapsed: 0.0,
        }
    }

    /// The adaptive estimate.
    pub fn adaptive(&self) -> &AdaptiveQ {
        &self.adapt
    }

    /// Current `q_vv` [m^2/s^3] (filter frame).
    pub fn q_vv(&self) -> Vec3 {
        self.adapt.q_vv()
    }

    /// Back to `(x, p)` with the initial `q_vv` and an empty window.
    pub fn reset(&mut self, x: State, p: Mat6) {
        self.ukf.set_estimate(x, p);
        self.adapt.reset();
        self.elapsed = 0.0;
    }

    /// Time update over `dt`: `Q = q_fixed + noise(q_vv, dt)`, each sigma point through `f`
    /// ([`Ukf::predict_with`]).
    pub fn predict_with<F, G>(
        &mut self,
        dt: f64,
        q_fixed: &Mat6,
        noise: G,
        f: F,
    ) -> Result<(), FilterError>
    where
        F: FnMut(&State) -> Result<State, FilterError>,
        G: FnOnce(&Vec3, f64) -> Mat6,
    {
        let q = q_fixed + noise(&self.adapt.q_vv(), dt);
        let lam = self.adapt.inflation;
        if lam > 1.0 {
            let (x, p) = (*self.ukf.state(), *self.ukf.covariance());
            self.ukf.set_estimate(x, p * lam);
            if let Err(e) = self.ukf.predict_with(&q, f) {
                self.ukf.set_estimate(x, p);
                return Err(e);
            }
            self.adapt.inflation = 1.0;
        } else {
            self.ukf.predict_with(&q, f)?;
        }
        self.elapsed += dt;
        Ok(())
    }

    /// Feed the adaptive estimate with one update's prior and posterior and its NIS.
    fn observe(&mut self, x_prior: &State, p_prior: &Mat6, nis: f64, dof: f64) {
        let dx = self.ukf.state() - x_prior;
        let p_post = *self.ukf.covariance();
        self.adapt
            .observe(&dx, &p_post, p_prior, self.elapsed, nis, dof);
        self.elapsed = 0.0;
    }

    /// Unscented update with a range/azimuth/elevation (or Cartesian) sensor, then the
    /// adaptation.
    pub fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        let (x0, p0) = (*self.ukf.state(), *self.ukf.covariance());
        let info = self.ukf.update(sensor, z)?;
        let dof = if info.azimuth_used { 3.0 } else { 2.0 };
        self.observe(&x0, &p0, info.nis, dof);
        Ok(info)
    }

    /// Generic unscented update ([`Ukf::update_generic`]), then the adaptation. Returns the
    /// NIS.
    pub fn update_generic<const M: usize, H>(
        &mut self,
        h: H,
        z: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
    ) -> Result<f64, FilterError>
    where
        H: Fn(&State) -> Option<SVector<f64, M>>,
    {
        let (x0, p0) = (*self.ukf.state(), *self.ukf.covariance());
        let nis = self.ukf.update_generic(h, z, r)?;
        self.observe(&x0, &p0, nis, M as f64);
        Ok(nis)
    }

    /// Current estimate.
    pub fn state(&self) -> &State {
        self.ukf.state()
    }

    /// Current covariance.
    pub fn covariance(&self) -> &Mat6 {
        self.ukf.covariance()
    }
}

/// The AQUKF on the CW model (filter code 3): [`AdaptiveUkf`] whose adaptive density is
/// discretised exactly by Van Loan for the CW model of mean motion `n`,
/// `Qd(q_vv) = sum_i q_vv,i Qd_VanLoan(e_i e_i^T)` (linear in `q_vv`; the three unit
/// matrices are cached per step size, on the stack). The step's fixed noise is the model's
/// `q` ([`DiscreteModel::q`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Aqukf {
    core: AdaptiveUkf,
    cw: CwModel,
    basis_dt: f64,
    basis: [Mat6; 3],
}

impl Aqukf {
    /// A filter from `x0`, `p0` (canonical) for the CW model of mean motion `mean_motion`
    /// (rad/s), with validated sigma-point and adaptive settings (`aq.q_vv0` canonical).
    pub fn new(x0: State, p0: Mat6, ukf: UkfParams, aq: AqParams, mean_motion: f64) -> Self {
        Self {
            core: AdaptiveUkf::new(x0, p0, ukf, aq),
            cw: CwModel::new(mean_motion),
            basis_dt: f64::NAN,
            basis: [Mat6::zeros(); 3],
        }
    }

    /// Current adaptive `q_vv` [m^2/s^3] per canonical axis.
    pub fn q_vv(&self) -> Vec3 {
        self.core.q_vv()
    }

    /// The generic core.
    pub fn core(&self) -> &AdaptiveUkf {
        &self.core
    }

    /// Back to `(x, p)` with the initial `q_vv` and an empty window.
    pub fn reset(&mut self, x: State, p: Mat6) {
        self.core.reset(x, p);
    }

    /// A snapshot of the state one step can change ([`AqukfSnapshot`]).
    pub fn snapshot(&self) -> AqukfSnapshot {
        let a = &self.core.adapt;
        AqukfSnapshot {
            ukf: self.core.ukf.clone(),
            q: a.q,
            head: a.head,
            len: a.len,
            slot: a.ring.get(a.head).copied().unwrap_or_default(),
            gate_head: a.gate_head,
            gate_len: a.gate_len,
            gate_slot: a.gate.get(a.gate_head).copied().unwrap_or_default(),
            open: a.open,
            inflation: a.inflation,
            elapsed: self.core.elapsed,
        }
    }

    /// Undo everything since `s` was taken, provided at most one update happened since.
    pub fn restore(&mut self, s: &AqukfSnapshot) {
        let a = &mut self.core.adapt;
        if let Some(slot) = a.ring.get_mut(s.head) {
            *slot = s.slot;
        }
        (a.q, a.head, a.len) = (s.q, s.head, s.len);
        if let Some(slot) = a.gate.get_mut(s.gate_head) {
            *slot = s.gate_slot;
        }
        (a.gate_head, a.gate_len, a.open, a.inflation) =
            (s.gate_head, s.gate_len, s.open, s.inflation);
        self.core.ukf.clone_from(&s.ukf);
        self.core.elapsed = s.elapsed;
    }

    fn refresh_basis(&mut self, dt: f64) {
        if self.basis_dt != dt {
            for (i, b) in self.basis.iter_mut().enumerate() {
                let mut qc = Mat3::zeros();
                qc[(i, i)] = 1.0;
                *b = self.cw.van_loan_q(&qc, dt);
            }
            self.basis_dt = dt;
        }
    }
}

impl Estimator for Aqukf {
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        self.refresh_basis(model.dt);
        let basis = self.basis;
        self.core.predict_with(
            model.dt,
            &model.q,
            |q, _| basis[0] * q[0] + basis[1] * q[1] + basis[2] * q[2],
            |x| Ok(model.apply(x, accel)),
        )
    }

    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        self.core.update(sensor, z)
    }

    fn state(&self) -> &State {
        self.core.state()
    }

    fn covariance(&self) -> &Mat6 {
        self.core.covariance()
    }

    fn set_estimate(&mut self, x: State, p: Mat6) {
        self.core.ukf.set_estimate(x, p);
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
            return Err(refuse(format!(
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
            return Err(refuse(format!(
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
            return Err(refuse(format!("AQUKF covariance inflation {f} below 1")));
        }
        *inflation = f;
        Ok(())
    }
}

/// Saved state: the UKF's, the adaptive estimate's, and the time predicted since the last
/// update (8).
impl Persist for AdaptiveUkf {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            ukf,
            adapt,
            elapsed,
        } = self;
        ukf.save_state(w);
        adapt.save_state(w);
        w.f64(*elapsed);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self {
            ukf,
            adapt,
            elapsed,
        } = self;
        ukf.load_state(r)?;
        adapt.load_state(r)?;
        *elapsed = r.finite("AQUKF time since the last update")?;
        Ok(())
    }
}

/// Saved state: the adaptive UKF's. The CW model is configuration; the Van Loan basis is a
/// cache recomputed from it for the next step size (bit-identical: same inputs).
impl Persist for Aqukf {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            core,
            cw: _,
            basis_dt: _,
            basis: _,
        } = self;
        core.save_state(w);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self {
            core,
            cw: _,
            basis_dt: _,
            basis: _,
        } = self;
        core.load_state(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use rand_distr::StandardNormal;

    fn random_spd(rng: &mut ChaCha8Rng, scale: f64) -> Mat6 {
        let a = Mat6::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal));
        a * a.transpose() * scale + Mat6::identity() * scale
    }

    /// Window 1 is the undamped Maybeck update `Qhat_k = Q*_k` (projected): computed here
    /// from eq. 27 with Maybeck's sign, independently of the ring buffer.
    #[test]
    fn window_one_is_the_undamped_maybeck_update() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let t = 20.0;
        let params = AqParams {
            window: 1,
            q_vv0: Vec3::new(1e-6, 2e-6, 3e-6),
            floor: 0.0,
            ceiling: 1e3,
            law: AdaptationLaw::Window,
            ..Default::default()
        };
        let mut a = AdaptiveQ::new(params);
        for _ in 0..50 {
            let q_prev = a.q_vv();
            let qhat_prev = double_integrator_q(&q_prev, t); // the Q of the last prediction
            let p_post = random_spd(&mut rng, 1e-3);
            let p_prior = p_post + qhat_prev + random_spd(&mut rng, 1e-4);
            let dx = State::from_fn(|_, _| 0.05 * rng.sample::<f64, _>(StandardNormal));
            let q_star = dx * dx.transpose() + p_post - (p_prior - qhat_prev);
            a.observe(&dx, &p_post, &p_prior, t, f64::NAN, 3.0);
            for i in 0..3 {
                let want = (q_star[(3 + i, 3 + i)] / t).clamp(0.0, 1e3);
                let got = a.q_vv()[i];
                assert!(
                    (got - want).abs() <= 1e-12 * want.abs().max(1e-12),
                    "axis {i}: {got} vs {want}"
                );
            }
        }
    }

    /// The window recursion against a direct evaluation of eq. 29 over a stored history.
    #[test]
    fn window_sum_matches_eq_29() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let n = 7;
        let params = AqParams {
            window: n,
            q_vv0: Vec3::repeat(5e-3),
            floor: 0.0,
            ceiling: 1e9,
            law: AdaptationLaw::Window,
            ..Default::default()
        };
        let mut a = AdaptiveQ::new(params);
        let mut hist: Vec<[f64; 3]> = Vec::new();
        let mut q = [5e-3; 3];
        for _ in 0..40 {
            let p_post = random_spd(&mut rng, 1e-3);
            let p_prior = p_post + random_spd(&mut rng, 1e-3);
            let dx = State::from_fn(|_, _| 0.1 * rng.sample::<f64, _>(StandardNormal));
            let t = 1.0 + rng.random::<f64>();
            a.observe(&dx, &p_post, &p_prior, t, f64::NAN, 3.0);
            let d: [f64; 3] = std::array::from_fn(|i| {
                let v = 3 + i;
                (dx[v] * dx[v] + p_post[(v, v)] - p_prior[(v, v)]) / t
            });
            hist.push(d);
            let start = hist.len().saturating_sub(n);
            for i in 0..3 {
                let s: f64 = hist[start..].iter().map(|e| e[i]).sum();
                q[i] = (q[i] + s / n as f64).max(0.0);
                assert!((a.q_vv()[i] - q[i]).abs() <= 1e-12 * q[i].abs().max(1e-9));
            }
        }
        assert_eq!(a.filled(), n);
    }

    /// The Wilson–Hilferty quantile against the exact chi-square quantile (statrs) at the
    /// gate's probabilities, from one update (3 dof) to a full window of 128: within 5 %
    /// below 30 dof (measured 3.5 % at 3 dof and 0.9999), within 0.5 % from 30 dof on (the
    /// default window; measured 0.33 % at 0.9999).
    #[test]
    fn wilson_hilferty_matches_the_chi_square_quantile() {
        use statrs::distribution::{ChiSquared, ContinuousCDF};
        for p in [0.99, 0.999, 0.9999] {
            let z = normal_quantile(p);
            for dof in [3.0, 6.0, 9.0, 30.0, 90.0, 384.0] {
                let exact = ChiSquared::new(dof).unwrap().inverse_cdf(p);
                let wh = chi2_quantile_wh(dof, z);
                let tol = if dof < 30.0 { 0.05 } else { 0.005 };
                assert!(
                    (wh - exact).abs() <= tol * exact,
                    "p {p}, dof {dof}: {wh} vs {exact}"
                );
            }
        }
    }

    /// The gated law: while the windowed NIS stays below its bound, `q` is `q_0` whatever
    /// the corrections say; once it exceeds the bound, `q` follows the window recursion
    /// from `q_0` (never below it) and the fading factor is the last NIS per degree of
    /// freedom; back below the bound, `q = q_0` again.
    #[test]
    fn gated_law_adapts_only_while_the_gate_is_open() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let q0 = Vec3::new(1e-6, 2e-6, 3e-6);
        let params = AqParams {
            window: 4,
            q_vv0: q0,
            floor: 0.0,
            ceiling: 1e3,
            law: AdaptationLaw::Gated,
            gate_window: 5,
            gate_quantile: 0.999,
        };
        let mut gated = AdaptiveQ::new(params);
        let mut window = AdaptiveQ::new(AqParams {
            law: AdaptationLaw::Window,
            ..params
        });
        // bound of 5 updates x 3 dof at 0.999: 37.7; NIS 3 per update is consistent
        let bound = chi2_quantile_wh(15.0, normal_quantile(0.999));
        assert!((bound - 37.7).abs() < 0.4, "{bound}");
        let obs = |a: &mut AdaptiveQ, b: &mut AdaptiveQ, nis: f64, rng: &mut ChaCha8Rng| {
            let p_post = random_spd(rng, 1e-3);
            let p_prior = p_post + random_spd(rng, 1e-4);
            let dx = State::from_fn(|_, _| 0.5 * rng.sample::<f64, _>(StandardNormal));
            a.observe(&dx, &p_post, &p_prior, 1.0, nis, 3.0);
            b.observe(&dx, &p_post, &p_prior, 1.0, nis, 3.0);
        };
        for _ in 0..20 {
            obs(&mut gated, &mut window, 3.0, &mut rng);
            assert!(!gated.gate_open());
            assert_eq!(gated.q_vv(), q0);
            assert_eq!(gated.inflation(), 1.0);
        }
        // the window law has moved away (large corrections), the gated one has not
        assert!((window.q_vv() - q0).norm() > 1e-3);
        // a burst of inconsistent innovations opens the gate
        obs(&mut gated, &mut window, 40.0, &mut rng);
        assert!(gated.gate_open());
        assert!((gated.inflation() - 40.0 / 3.0).abs() < 1e-12);
        // q: q_0 plus the window mean of the last 4 observations, clipped at q_0
        let mut want = q0;
        for i in 0..3 {
            let s: f64 = window.ring.iter().take(window.filled()).map(|e| e[i]).sum();
            want[i] = (q0[i] + s / 4.0).max(q0[i]);
        }
        assert!((gated.q_vv() - want).norm() <= 1e-12 * want.norm());
        // consistent again once the burst has left the 5-update window
        for k in 0..5 {
            obs(&mut gated, &mut window, 3.0, &mut rng);
            assert_eq!(gated.gate_open(), k < 4, "k = {k}");
        }
        assert_eq!(gated.q_vv(), q0);
        assert_eq!(gated.inflation(), 1.0);
    }

    /// The double-integrator noise is Van Loan's for that model.
    #[test]
    fn double_integrator_noise_is_van_loan() {
        // CW with a tiny mean motion is the double integrator up to O(n t) coupling terms
        // (here n t = 6e-7)
        let cw = CwModel::new(1e-9);
        let q = Vec3::new(1e-4, 2e-4, 3e-4);
        let t = 600.0;
        let vl = cw.van_loan_q(&Mat3::from_diagonal(&q), t);
        let di = double_integrator_q(&q, t);
        assert!((vl - di).norm() <= 1e-6 * di.norm(), "{vl} vs {di}");
    }
}
