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
//! geometrically and then overshoots. The fading factor responds to the innovation itself
//! within one step, and the corrections that follow feed the window with the level the
//! manoeuvre needs (the figures: `docs/results.md`, "Model error (a): unreported burns").
//! Once the
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

mod adaptive_q;
mod params;
#[cfg(test)]
mod tests;

pub use adaptive_q::{chi2_quantile_wh, AdaptiveQ};
pub use params::{AdaptationLaw, AqParams, MAX_GATE_WINDOW, MAX_WINDOW};

use super::{Estimator, FilterError, SensorUpdate, Ukf, UkfParams, UpdateInfo};
use crate::dynamics::{DiscreteModel, Dynamics, RelativeDynamics};
use crate::numerics::state::{Persist, Reader, StateError, Writer};
use crate::sensors::{MeasurementModel, Sensor};
use crate::types::{Mat3, Mat6, State, Vec3};
use nalgebra::{SMatrix, SVector};

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
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveUkf {
    ukf: Ukf,
    adapt: AdaptiveQ,
    /// time predicted since the last update [s]
    elapsed: f64,
}

impl AdaptiveUkf {
    /// From the initial estimate, the sigma-point parameters and the adaptive settings
    /// (validated by the caller). Inlined: as a function of its own (Thumb's code) it
    /// builds its window in its frame and copies it out (`docs/c-abi.md`).
    #[inline(always)]
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

    /// Unscented update with any sensor ([`Ukf::sensor_update`]), then the adaptation on
    /// its innovation (the NIS with the sensor's used components as degrees of freedom).
    /// The window's term is per prediction interval, so only the first update after a
    /// prediction feeds it ([`AdaptiveQ::observe`] ignores an interval of zero).
    pub fn update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        let (x0, p0) = (*self.ukf.state(), *self.ukf.covariance());
        let info = self.ukf.update_sensor(sensor, z)?;
        self.observe(&x0, &p0, info.nis, info.dof as f64);
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
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aqukf {
    core: AdaptiveUkf,
    dynamics: Dynamics,
    basis_dt: f64,
    basis: [Mat6; 3],
}

impl Aqukf {
    /// A filter from `x0`, `p0` (canonical) on `dynamics` (whose Van Loan noise the
    /// adapted density is discretised with), with validated sigma-point and adaptive
    /// settings (`aq.q_vv0` canonical).
    pub fn new(
        x0: State,
        p0: Mat6,
        ukf: UkfParams,
        aq: AqParams,
        dynamics: impl Into<Dynamics>,
    ) -> Self {
        Self {
            core: AdaptiveUkf::new(x0, p0, ukf, aq),
            dynamics: dynamics.into(),
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
            ukf: self.core.ukf,
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

    fn refresh_basis(&mut self, t: f64, dt: f64) {
        if self.basis_dt != dt || !self.dynamics.time_invariant() {
            for (i, b) in self.basis.iter_mut().enumerate() {
                let mut qc = Mat3::zeros();
                qc[(i, i)] = 1.0;
                *b = self.dynamics.step_noise(t, dt, &qc);
            }
            self.basis_dt = dt;
        }
    }
}

impl Estimator for Aqukf {
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        self.refresh_basis(model.t, model.dt);
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

    fn update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        self.core.update_sensor(sensor, z)
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
            dynamics: _,
            basis_dt: _,
            basis: _,
        } = self;
        core.save_state(w);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self {
            core,
            dynamics: _,
            basis_dt: _,
            basis: _,
        } = self;
        core.load_state(r)
    }
}
