//! The one filter factory ([`build_filter`]): a configuration's filter code becomes an
//! estimator here and nowhere else — for the navigator (and so the C ABI, the FMU and the
//! Python package) and for the evaluation engine. [`AnyFilter`] holds any of them by value
//! (enum dispatch: no boxing, no allocation per step).

use super::config::{FilterKind, NavConfig};
use super::error::{NavError, NavErrorKind};
use crate::dynamics::DiscreteModel;
use crate::estimators::aqukf::AqukfSnapshot;
use crate::estimators::pf::{Kernel, PfInit};
#[cfg(feature = "std")]
use crate::estimators::pf::{ParticleFilter, PfPrior};
#[cfg(feature = "std")]
use crate::estimators::Bank;
#[cfg(feature = "std")]
use crate::estimators::GaussianSumPf;
use crate::estimators::{
    Aqukf, Ekf, Estimator, FilterError, Imm, Member, SensorUpdate, Ukf, UpdateInfo,
};
use crate::hinf::HinfEstimator;
use crate::numerics::state::{Persist, Reader, StateError, Writer};
use crate::sensors::{Geometry, Linearization, MeasurementModel, Sensor};
use crate::types::{Mat6, State, Vec3};
use nalgebra::SVector;

/// The estimators a navigator can run (enum dispatch: no boxing, no allocation per step).
#[derive(Debug, Clone)]
pub enum AnyFilter {
    /// Extended Kalman filter.
    Ekf(Ekf),
    /// Unscented Kalman filter.
    Ukf(Ukf),
    /// Sliding-window adaptive UKF (paper 001).
    Aqukf(Aqukf),
    /// Particle filter (codes 4-8: SIR, regularised, unscented, genetic, cloud-genetic).
    #[cfg(feature = "std")]
    Pf(ParticleFilter),
    /// Robust H-infinity filter (code 9; not yet in the build without std).
    #[cfg(feature = "std")]
    Hinf(HinfEstimator),
    /// Interacting multiple-model filter (code 10).
    Imm(Imm),
    /// A particle filter with the particle prior (`pf_prior = particle`, codes 4-8): a
    /// Gaussian per particle ([`crate::estimators::pf::gaussian_sum`]). Boxed: its terms are
    /// allocated at construction.
    #[cfg(feature = "std")]
    GaussianSum(Box<GaussianSumPf>),
    /// A range-parameterised bank of one of the Kalman-type filters above (`range_bank`
    /// members; [`crate::estimators::bank`]). Boxed: its members are allocated at
    /// construction.
    #[cfg(feature = "std")]
    Bank(Box<Bank<AnyFilter>>),
}

/// What a step of a Kalman-type filter can change, to restore after a failed step. Small
/// on purpose: `AnyFilter` itself is as large as its largest variant (the AQUKF's window),
/// and copying that on every step cost a quarter of an EKF step.
#[derive(Debug, Clone)]
#[doc(hidden)]
pub enum Snapshot {
    Ekf(Ekf),
    Ukf(Ukf),
    Aqukf(AqukfSnapshot),
    #[cfg(feature = "std")]
    Hinf(HinfEstimator),
    Imm(Imm),
    /// the bank keeps its checkpoint itself ([`Bank::checkpoint`]), and so does the
    /// Gaussian-sum particle filter
    #[cfg(feature = "std")]
    Bank,
    /// particle filters are transactional themselves (see [`Navigator`])
    None,
}

impl AnyFilter {
    /// The H-infinity filter, if this is one (never without std: not yet in that build).
    #[inline(always)]
    pub fn hinf(&self) -> Option<&HinfEstimator> {
        match self {
            #[cfg(feature = "std")]
            AnyFilter::Hinf(f) => Some(f),
            _ => None,
        }
    }

    /// A snapshot to [`AnyFilter::restore`] (a bank checkpoints itself, no allocation).
    pub(super) fn snapshot(&mut self) -> Snapshot {
        #[cfg(feature = "std")]
        if let AnyFilter::Bank(b) = self {
            b.checkpoint();
            return Snapshot::Bank;
        }
        #[cfg(feature = "std")]
        if let AnyFilter::GaussianSum(g) = self {
            g.checkpoint();
            return Snapshot::Bank;
        }
        self.member_snapshot()
    }

    fn member_snapshot(&self) -> Snapshot {
        match self {
            AnyFilter::Ekf(f) => Snapshot::Ekf(f.clone()),
            AnyFilter::Ukf(f) => Snapshot::Ukf(*f),
            AnyFilter::Aqukf(f) => Snapshot::Aqukf(f.snapshot()),
            #[cfg(feature = "std")]
            AnyFilter::Hinf(f) => Snapshot::Hinf(*f),
            AnyFilter::Imm(f) => Snapshot::Imm(f.clone()),
            #[cfg(feature = "std")]
            AnyFilter::Pf(_) | AnyFilter::Bank(_) | AnyFilter::GaussianSum(_) => Snapshot::None,
        }
    }

    /// Undo the step since `s` was taken (`s` from [`AnyFilter::snapshot`] of this filter).
    pub(super) fn restore(&mut self, s: &Snapshot) {
        match (self, s) {
            (AnyFilter::Ekf(f), Snapshot::Ekf(g)) => f.clone_from(g),
            (AnyFilter::Ukf(f), Snapshot::Ukf(g)) => f.clone_from(g),
            (AnyFilter::Aqukf(f), Snapshot::Aqukf(g)) => f.restore(g),
            #[cfg(feature = "std")]
            (AnyFilter::Hinf(f), Snapshot::Hinf(g)) => *f = *g,
            (AnyFilter::Imm(f), Snapshot::Imm(g)) => f.clone_from(g),
            #[cfg(feature = "std")]
            (AnyFilter::Bank(f), Snapshot::Bank) => f.rollback(),
            #[cfg(feature = "std")]
            (AnyFilter::GaussianSum(f), Snapshot::Bank) => f.rollback(),
            _ => {}
        }
    }
}

impl AnyFilter {
    /// The 4-byte tag of this filter's section in a saved state.
    pub(super) fn state_tag(&self) -> &'static [u8; 4] {
        match self {
            AnyFilter::Ekf(_) => b"EKF ",
            AnyFilter::Ukf(_) => b"UKF ",
            AnyFilter::Aqukf(_) => b"AQUK",
            #[cfg(feature = "std")]
            AnyFilter::Pf(_) => b"PART",
            #[cfg(feature = "std")]
            AnyFilter::Hinf(_) => b"HINF",
            AnyFilter::Imm(_) => b"IMM ",
            #[cfg(feature = "std")]
            AnyFilter::Bank(_) => b"BANK",
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(_) => b"GSPF",
        }
    }
}

/// The filter's section: its tag, then the filter's own [`Persist`] fields (each defined
/// beside the filter).
impl Persist for AnyFilter {
    fn save_state(&self, w: &mut Writer<'_>) {
        w.tag(self.state_tag());
        match self {
            AnyFilter::Ekf(f) => f.save_state(w),
            AnyFilter::Ukf(f) => f.save_state(w),
            AnyFilter::Aqukf(f) => f.save_state(w),
            #[cfg(feature = "std")]
            AnyFilter::Pf(f) => f.save_state(w),
            #[cfg(feature = "std")]
            AnyFilter::Hinf(f) => f.save_state(w),
            AnyFilter::Imm(f) => f.save_state(w),
            #[cfg(feature = "std")]
            AnyFilter::Bank(f) => f.save_state(w),
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(f) => f.save_state(w),
        }
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        r.tag(self.state_tag())?;
        match self {
            AnyFilter::Ekf(f) => f.load_state(r),
            AnyFilter::Ukf(f) => f.load_state(r),
            AnyFilter::Aqukf(f) => f.load_state(r),
            #[cfg(feature = "std")]
            AnyFilter::Pf(f) => f.load_state(r),
            #[cfg(feature = "std")]
            AnyFilter::Hinf(f) => f.load_state(r),
            AnyFilter::Imm(f) => f.load_state(r),
            #[cfg(feature = "std")]
            AnyFilter::Bank(f) => f.load_state(r),
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(f) => f.load_state(r),
        }
    }
}

impl AnyFilter {
    /// The update with `sensor`'s reading `z`, then the time update, committed together
    /// (the EKF and the UKF: `update_sensor_predict`, no snapshot); `None` for the other
    /// filters, whose callers take a snapshot and the two steps.
    #[inline(always)]
    pub(crate) fn update_sensor_predict<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
        model: &DiscreteModel,
        accel: &Vec3,
    ) -> Option<Result<SensorUpdate<D>, FilterError>> {
        match self {
            AnyFilter::Ekf(f) => Some(f.update_sensor_predict(sensor, z, model, accel)),
            AnyFilter::Ukf(f) => Some(f.update_sensor_predict(sensor, z, model, accel)),
            _ => None,
        }
    }
}

/// A bank's members: any Kalman-type filter (the factory never puts a particle, H-infinity
/// or bank filter in a bank).
impl Member for AnyFilter {
    type Saved = Snapshot;

    fn save(&self) -> Snapshot {
        self.member_snapshot()
    }

    fn restore(&mut self, s: &Snapshot) {
        AnyFilter::restore(self, s);
    }

    fn reset(&mut self, x: State, p: Mat6) {
        match self {
            #[cfg(feature = "std")]
            AnyFilter::Pf(pf) => *pf = ParticleFilter::new(x, p, *pf.params()),
            AnyFilter::Aqukf(f) => f.reset(x, p),
            AnyFilter::Imm(f) => f.reset(x, p),
            #[cfg(feature = "std")]
            AnyFilter::Bank(f) => f.reset(x, p),
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(f) => f.reset(x, p),
            other => other.set_estimate(x, p),
        }
    }

    fn update_at<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        g: &Geometry,
    ) -> Result<UpdateInfo, FilterError> {
        match self {
            AnyFilter::Ekf(f) => f.update_given(sensor, z, g),
            other => other.update(sensor, z),
        }
    }

    fn update_sensor_at<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
        lin: &Linearization<D>,
        nu: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        match self {
            AnyFilter::Ekf(f) => f.update_sensor_given(sensor, lin, nu),
            other => other.update_sensor(sensor, z),
        }
    }
}

impl Estimator for AnyFilter {
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        match self {
            AnyFilter::Ekf(f) => f.predict(model, accel),
            AnyFilter::Ukf(f) => f.predict(model, accel),
            AnyFilter::Aqukf(f) => f.predict(model, accel),
            #[cfg(feature = "std")]
            AnyFilter::Pf(f) => f.predict(model, accel),
            #[cfg(feature = "std")]
            AnyFilter::Hinf(f) => f.predict(model, accel),
            AnyFilter::Imm(f) => f.predict(model, accel),
            #[cfg(feature = "std")]
            AnyFilter::Bank(f) => f.predict(model, accel),
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(f) => f.predict(model, accel),
        }
    }
    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        match self {
            AnyFilter::Ekf(f) => f.update(sensor, z),
            AnyFilter::Ukf(f) => f.update(sensor, z),
            AnyFilter::Aqukf(f) => f.update(sensor, z),
            #[cfg(feature = "std")]
            AnyFilter::Pf(f) => f.update(sensor, z),
            #[cfg(feature = "std")]
            AnyFilter::Hinf(f) => f.update(sensor, z),
            AnyFilter::Imm(f) => f.update(sensor, z),
            #[cfg(feature = "std")]
            AnyFilter::Bank(f) => f.update(sensor, z),
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(f) => f.update(sensor, z),
        }
    }
    fn update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        match self {
            AnyFilter::Ekf(f) => f.update_sensor(sensor, z),
            AnyFilter::Ukf(f) => f.update_sensor(sensor, z),
            AnyFilter::Aqukf(f) => f.update_sensor(sensor, z),
            #[cfg(feature = "std")]
            AnyFilter::Pf(f) => f.update_sensor(sensor, z),
            #[cfg(feature = "std")]
            AnyFilter::Hinf(f) => f.update_sensor(sensor, z),
            AnyFilter::Imm(f) => f.update_sensor(sensor, z),
            #[cfg(feature = "std")]
            AnyFilter::Bank(f) => f.update_sensor(sensor, z),
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(f) => f.update_sensor(sensor, z),
        }
    }
    fn state(&self) -> &State {
        match self {
            AnyFilter::Ekf(f) => f.state(),
            AnyFilter::Ukf(f) => f.state(),
            AnyFilter::Aqukf(f) => f.state(),
            #[cfg(feature = "std")]
            AnyFilter::Pf(f) => f.state(),
            #[cfg(feature = "std")]
            AnyFilter::Hinf(f) => f.state(),
            AnyFilter::Imm(f) => f.state(),
            #[cfg(feature = "std")]
            AnyFilter::Bank(f) => f.state(),
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(f) => f.state(),
        }
    }
    fn covariance(&self) -> &Mat6 {
        match self {
            AnyFilter::Ekf(f) => f.covariance(),
            AnyFilter::Ukf(f) => f.covariance(),
            AnyFilter::Aqukf(f) => f.covariance(),
            #[cfg(feature = "std")]
            AnyFilter::Pf(f) => f.covariance(),
            #[cfg(feature = "std")]
            AnyFilter::Hinf(f) => f.covariance(),
            AnyFilter::Imm(f) => f.covariance(),
            #[cfg(feature = "std")]
            AnyFilter::Bank(f) => f.covariance(),
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(f) => f.covariance(),
        }
    }
    fn set_estimate(&mut self, x: State, p: Mat6) {
        match self {
            AnyFilter::Ekf(f) => f.set_estimate(x, p),
            AnyFilter::Ukf(f) => f.set_estimate(x, p),
            AnyFilter::Aqukf(f) => f.set_estimate(x, p),
            #[cfg(feature = "std")]
            AnyFilter::Pf(f) => f.set_estimate(x, p),
            #[cfg(feature = "std")]
            AnyFilter::Hinf(f) => f.set_estimate(x, p),
            AnyFilter::Imm(f) => f.set_estimate(x, p),
            #[cfg(feature = "std")]
            AnyFilter::Bank(f) => f.set_estimate(x, p),
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(f) => f.set_estimate(x, p),
        }
    }
}

/// Build the estimator of `cfg` at its initial estimate (the H-infinity filter designed
/// here, at construction: the only allocation). An unknown or unbuilt code is an error.
pub fn build_filter(cfg: &NavConfig) -> Result<AnyFilter, NavError> {
    build_filter_with(cfg, &FilterOptions::default())
}

/// What a configuration does not say about a filter: research settings of the evaluation
/// engine that no front end exposes (the particle filters' initialisation, kernel and
/// carried covariance) and an H-infinity filter designed elsewhere (the paper-form and
/// published filters of paper 002's reproduction, designed once per scenario).
#[derive(Debug, Clone, Default)]
pub struct FilterOptions {
    /// The particles' initialisation (`None`: [`PfInit::FirstMeasurement`], the default of
    /// every kind, [`crate::estimators::pf::PfKind::default_init`]).
    pub pf_init: Option<PfInit>,
    /// The regularised filter's kernel.
    pub pf_kernel: Kernel,
    /// The unscented kinds carry each particle's UKF covariance (van der Merwe literally)
    /// instead of restarting it from `Q` each step.
    pub pf_carry_covariance: bool,
    /// For filter code 9: this filter, set to the configuration's initial estimate,
    /// instead of a design from the configuration.
    pub hinf: Option<HinfEstimator>,
}

/// [`build_filter`] with the settings a configuration does not hold ([`FilterOptions`]).
pub fn build_filter_with(cfg: &NavConfig, opts: &FilterOptions) -> Result<AnyFilter, NavError> {
    let mut f = AnyFilter::Ekf(Ekf::new(State::zeros(), Mat6::identity()));
    build_filter_into(cfg, opts, &mut f)?;
    Ok(f)
}

/// [`build_filter_with`] into `out` (unchanged on error): the navigator builds its filter
/// where it keeps it, so that a filter as large as the AQUKF's (its window) is not also
/// held on the stack by every caller on the way.
pub(super) fn build_filter_into(
    cfg: &NavConfig,
    opts: &FilterOptions,
    out: &mut AnyFilter,
) -> Result<(), NavError> {
    if cfg.range_bank < 2 {
        return build_single_into(cfg, opts, out);
    }
    #[cfg(not(feature = "std"))]
    return Err(NavError {
        kind: NavErrorKind::NotImplemented,
        message: "range_bank > 1 is not in this build (the flight library)".into(),
    });
    #[cfg(feature = "std")]
    {
        let mut single = AnyFilter::Ekf(Ekf::new(State::zeros(), Mat6::identity()));
        build_single_into(cfg, opts, &mut single)?;
        let bank = Bank::new(
            single,
            cfg.initial_state(),
            cfg.initial_covariance(),
            cfg.range_bank,
        )
        .ok_or_else(|| {
            NavError::invalid(
                "range_bank > 1 splits the prior along its line of sight: x0's position must \
                 be away from the target and the initial covariance must spread it along it",
            )
        })?;
        *out = AnyFilter::Bank(Box::new(bank));
        Ok(())
    }
}

/// The filter of `cfg`'s code alone (no bank), into `out` (unchanged on error). Each arm
/// writes its filter into `out` directly: a `Result<AnyFilter, _>` returned through here
/// would be one more copy of the largest filter on the stack.
fn build_single_into(
    cfg: &NavConfig,
    opts: &FilterOptions,
    out: &mut AnyFilter,
) -> Result<(), NavError> {
    let x0 = cfg.initial_state();
    let p0 = cfg.initial_covariance();
    #[cfg(feature = "std")]
    if let Some(mut params) = cfg.pf_params() {
        params.init = opts.pf_init.unwrap_or(params.init);
        params.kernel = opts.pf_kernel;
        params.carry_covariance = opts.pf_carry_covariance;
        *out = match params.prior {
            PfPrior::Gaussian => AnyFilter::Pf(ParticleFilter::new(x0, p0, params)),
            PfPrior::Particle => {
                // the terms' radio update is the noise density's (the robust update)
                let noise = Some(cfg.noise());
                AnyFilter::GaussianSum(Box::new(GaussianSumPf::new(x0, p0, &params, noise)))
            }
        };
        return Ok(());
    }
    #[cfg(feature = "std")]
    if let (FilterKind::Hinf, Some(h)) = (cfg.filter, &opts.hinf) {
        let mut h = *h;
        h.set_estimate(x0, p0);
        *out = AnyFilter::Hinf(h);
        return Ok(());
    }
    #[cfg(not(feature = "std"))]
    let _ = opts;
    match cfg.filter {
        FilterKind::Ekf => *out = AnyFilter::Ekf(Ekf::new(x0, p0)),
        FilterKind::Rekf => *out = AnyFilter::Ekf(Ekf::new(x0, p0).robust(cfg.noise())),
        FilterKind::Ukf => *out = AnyFilter::Ukf(Ukf::new(x0, p0, cfg.ukf())),
        FilterKind::Aqukf => {
            *out = AnyFilter::Aqukf(Aqukf::new(
                x0,
                p0,
                cfg.ukf(),
                cfg.aq_params(),
                cfg.dynamics(),
            ))
        }
        FilterKind::Imm => {
            *out = AnyFilter::Imm(Imm::new(x0, p0, cfg.imm_params(), cfg.dynamics()))
        }
        #[cfg(feature = "hinf")]
        FilterKind::Hinf if cfg.eccentricity > 0.0 => *out = scheduled_hinf(cfg, x0)?,
        #[cfg(feature = "hinf")]
        FilterKind::Hinf => {
            let spec = cfg.hinf_spec()?;
            let plant = crate::hinf::HinfPlant::open_loop(&spec);
            *out = match cfg.hinf_velocity_noise() {
                None => open_loop_hinf(cfg, &plant, x0, p0)?,
                Some(r_vel) => {
                    let d_vel = crate::hinf::psd_sqrt(&r_vel);
                    open_loop_hinf(cfg, &plant.measuring_velocity(&d_vel), x0, p0)?
                }
            }
        }
        other => {
            return Err(NavError {
                kind: NavErrorKind::NotImplemented,
                message: crate::msg!("filter {} is not implemented", other.name()),
            })
        }
    }
    Ok(())
}

/// The H-infinity filter of a circular orbit: the observer design ([`NavConfig::hinf_design`])
/// for `plant` (the open-loop CW plant measuring the position, or the position and the
/// velocity, with the noise of the declared `hinf_sensors`), with track initiation when
/// `hinf_acquisition` is set.
#[cfg(feature = "hinf")]
fn open_loop_hinf<const M: usize>(
    cfg: &NavConfig,
    plant: &crate::hinf::HinfPlant<M>,
    x0: crate::types::State,
    p0: crate::types::Mat6,
) -> Result<AnyFilter, NavError> {
    use crate::hinf::design::{design_observer, design_plant_mixed, DesignOptions};
    let opts = DesignOptions::default();
    let period = cfg.hinf_period;
    let (d, info) = match cfg.hinf_design {
        super::config::HinfDesignKind::GammaOptimal => {
            design_observer(plant, period, &opts).map(|d| {
                let info = d.info();
                (d, info)
            })
        }
        super::config::HinfDesignKind::Mixed => {
            design_plant_mixed(plant, period, cfg.hinf_gamma_factor, &opts).map(|m| {
                let info = m.info();
                (m.mixed, info)
            })
        }
    }
    .map_err(|e| NavError {
        kind: NavErrorKind::InvalidArgument,
        message: crate::msg!("hinf design ({}) failed: {e}", cfg.hinf_design.name()),
    })?;
    let invalid = |e: crate::hinf::HinfError| NavError::invalid(crate::msg!("hinf: {e}"));
    // the design's information C^T (D D^T)^-1 C, block diagonal (position, velocity)
    let r = plant.d * plant.d.transpose();
    let ri = r
        .try_inverse()
        .ok_or_else(|| NavError::invalid("hinf: the design's measurement noise is singular"))?;
    let j_d = plant.c.transpose() * ri * plant.c;
    let mut f = HinfEstimator::new(d.matrices, d.gamma, x0)
        .map_err(invalid)?
        .with_h2_norm(d.h2_norm)
        .with_design_info(info)
        .with_measurement_information(&j_d, cfg.hinf_sensors.count_ones())
        .map_err(invalid)?;
    if cfg.hinf_acquisition {
        f = f.with_acquisition(plant, p0).map_err(invalid)?;
    }
    Ok(AnyFilter::Hinf(f))
}

/// The H-infinity filter of an eccentric orbit: an observer design ([`NavConfig::hinf_design`])
/// at each of the [`crate::hinf::SCHEDULE_POINTS`] instants of
/// [`crate::hinf::HinfSchedule`], each for the frozen plant of the step from there (the
/// elliptic transition and input matrix, the step's own process noise when it is derived,
/// the CW uncertainty structure at the local orbit rate), certified on its own LMI and
/// checked by the solver-independent frequency sweep
/// ([`crate::hinf::verify::observer_certified_norm`]); the reported `gamma` and H2 norm are
/// the largest over the instants.
/// The frozen plant of the step of `spec.period` from time `t` on an eccentric orbit, as a
/// scheduled H-infinity design sees it: the elliptic transition and input matrix, the CW
/// orbit-rate uncertainty structure at the local orbit rate, and (returned beside it) the
/// step's process noise `B B^T` when the noise inputs are derived (`hinf_b_pos =
/// hinf_b_vel = 0`; the spec's `B` is in the plant otherwise).
#[cfg(feature = "hinf")]
fn step_plant(
    cfg: &NavConfig,
    spec: &crate::hinf::HinfSpec,
    model: &crate::dynamics::EllipticModel,
    t: f64,
) -> (crate::hinf::HinfPlant, crate::types::Mat6) {
    use crate::dynamics::RelativeDynamics;
    use crate::hinf::{paper_ea, paper_ha, HinfPlant};
    let qc = crate::types::Mat3::identity() * cfg.accel_psd;
    let step = model.step(t, spec.period, &qc, crate::dynamics::Discretization::Exact);
    let w = model.angular_rate(t);
    let mut plant = HinfPlant::open_loop(spec);
    plant.a = step.phi;
    plant.g = step.gamma;
    plant.ha = paper_ha(w) * spec.period;
    plant.ea = paper_ea(w, spec.delta_bar);
    let q = if cfg.hinf_b_pos == 0.0 && cfg.hinf_b_vel == 0.0 {
        cfg.hinf_process_noise(step.q)
    } else {
        plant.b * plant.b.transpose()
    };
    (plant, q)
}

/// The error system of a scheduled H-infinity design over `steps` steps from time 0, as
/// it runs: `e(k+1) = (Phi_k - G(t_k) C) e(k) + [B_k, -G D, |Ea_k| Ha_k] d(k)`, each step
/// with its own transition, noise and uncertainty structure and the gain
/// [`crate::hinf::HinfSchedule::gain_at`] its start time picks
/// ([`crate::hinf::verify::varying_l2_gain`] bounds its gain: the certificate of the
/// schedule, switching and time variation included).
#[cfg(feature = "hinf")]
pub fn scheduled_error_steps(
    cfg: &NavConfig,
    schedule: &crate::hinf::HinfSchedule,
    steps: usize,
) -> Result<Vec<crate::hinf::verify::VaryingStep>, NavError> {
    let spec = cfg.hinf_spec()?;
    let model =
        crate::dynamics::EllipticModel::new(cfg.mean_motion, cfg.eccentricity, cfg.true_anomaly0);
    Ok((0..steps)
        .map(|k| {
            let t = k as f64 * spec.period;
            let (plant, q) = step_plant(cfg, &spec, &model, t);
            let g = schedule.gain_at(t);
            let gd = g * plant.d;
            let h = plant.ha * plant.ea.norm();
            crate::hinf::verify::VaryingStep {
                a: plant.a - g * plant.c,
                w: q + gd * gd.transpose() + h * h.transpose(),
            }
        })
        .collect())
}

/// The certificate of a scheduled design for the time-varying error system as it runs
/// ([`crate::hinf::HinfSchedule`]): over [`crate::hinf::SCHEDULE_CERTIFIED_ORBITS`] orbits
/// (at most [`crate::hinf::SCHEDULE_CERTIFIED_STEPS`] steps), the largest frozen-plant bound
/// if the time-varying Riccati recursion passes there, its bisection value (to 1e-4)
/// otherwise. When a whole number of steps makes an orbit the error system is periodic,
/// and a bound (that one, or 1 %, 5 % or 10 % above it) whose recursion closes a period
/// ([`crate::hinf::verify::closes_period`]) holds over every horizon.
#[cfg(feature = "hinf")]
fn certify_schedule(
    cfg: &NavConfig,
    schedule: &mut crate::hinf::HinfSchedule,
) -> Result<(), NavError> {
    use crate::hinf::verify::{
        closes_period, varying_gain_below, varying_l2_gain, varying_riccati,
    };
    use crate::hinf::{SCHEDULE_CERTIFIED_ORBITS, SCHEDULE_CERTIFIED_STEPS};
    use crate::types::Mat6;
    let per_orbit = schedule.orbit.period() / cfg.hinf_period;
    let whole = per_orbit.round();
    // a validated configuration has a finite, positive step; NaN casts to 0
    let periodic = whole >= 1.0
        && (per_orbit - whole).abs() <= 1e-9 * per_orbit
        && whole as usize <= SCHEDULE_CERTIFIED_STEPS;
    let steps = if periodic {
        let orbits = (SCHEDULE_CERTIFIED_STEPS as f64 / whole)
            .floor()
            .min(SCHEDULE_CERTIFIED_ORBITS);
        (orbits * whole) as usize
    } else {
        ((SCHEDULE_CERTIFIED_ORBITS * per_orbit).ceil() as usize).clamp(1, SCHEDULE_CERTIFIED_STEPS)
    };
    let error_steps = scheduled_error_steps(cfg, schedule, steps)?;
    let l = Mat6::identity();
    let frozen = schedule.frozen_gamma;
    let horizon = if varying_gain_below(&error_steps, &l, frozen) {
        frozen
    } else {
        varying_l2_gain(&error_steps, &l, 1e-4)
    };
    if !horizon.is_finite() {
        return Err(NavError {
            kind: NavErrorKind::Numerical,
            message: crate::msg!(
                "hinf: the scheduled gains do not keep the eccentric orbit's error system \
                 bounded over its first {steps} steps (the frozen designs' bound is {frozen})"
            ),
        });
    }
    schedule.certified_gamma = horizon;
    schedule.certified_steps = steps;
    if periodic {
        let period = &error_steps[..whole as usize];
        for factor in [1.0, 1.01, 1.05, 1.1] {
            let gamma = horizon * factor;
            let closed = varying_riccati(&error_steps, &l, gamma, &Mat6::zeros())
                .is_some_and(|y| closes_period(period, &l, gamma, &(y * 1.01)));
            if closed {
                schedule.certified_gamma = gamma;
                schedule.certified_steps = usize::MAX;
                break;
            }
        }
    }
    Ok(())
}

#[cfg(feature = "hinf")]
fn scheduled_hinf(cfg: &NavConfig, x0: crate::types::State) -> Result<AnyFilter, NavError> {
    use crate::dynamics::EllipticModel;
    use crate::hinf::design::{design_mixed, design_observer, DesignOptions};
    use crate::hinf::{psd_sqrt, HinfSchedule, SCHEDULE_POINTS};
    use crate::types::Mat63;
    let spec = cfg.hinf_spec()?;
    let model = EllipticModel::new(cfg.mean_motion, cfg.eccentricity, cfg.true_anomaly0);
    let t = spec.period;
    let opts = DesignOptions::default();
    let derived_b = cfg.hinf_b_pos == 0.0 && cfg.hinf_b_vel == 0.0;
    let failed = |k: usize, e: crate::hinf::HinfError| NavError {
        kind: NavErrorKind::InvalidArgument,
        message: crate::msg!(
            "hinf design ({}) failed at instant {k} of {SCHEDULE_POINTS} along the orbit: {e}",
            cfg.hinf_design.name()
        ),
    };
    let mut gains = [Mat63::zeros(); SCHEDULE_POINTS];
    let (mut gamma, mut h2) = (0.0f64, 0.0f64);
    let mut first = None;
    for (k, gain) in gains.iter_mut().enumerate() {
        let tk = model.time_at_true_anomaly(HinfSchedule::anomaly(k));
        let (mut plant, q) = step_plant(cfg, &spec, &model, tk);
        if derived_b {
            plant.b = psd_sqrt(&q);
        }
        let design = design_observer(&plant, t, &opts).map_err(|e| failed(k, e))?;
        let design = match cfg.hinf_design {
            super::config::HinfDesignKind::GammaOptimal => design,
            super::config::HinfDesignKind::Mixed => {
                let start =
                    crate::hinf::riccati::kalman_gain(&plant).unwrap_or(design.matrices.b_f);
                design_mixed(
                    &plant,
                    t,
                    cfg.hinf_gamma_factor * design.gamma,
                    &start,
                    &opts,
                )
                .map_err(|e| failed(k, e))?
            }
        };
        // the solver-independent check of each instant's certificate: the frequency sweep
        // of the channel the design bounds
        let norm = crate::hinf::verify::observer_certified_norm(&plant, &design.matrices.b_f);
        if !(norm <= design.gamma * (1.0 + 1e-6)) {
            return Err(NavError {
                kind: NavErrorKind::Numerical,
                message: crate::msg!(
                    "hinf design at instant {k} of {SCHEDULE_POINTS} along the orbit: its \
                     gain's H-infinity norm {norm} exceeds the certified gamma {}",
                    design.gamma
                ),
            });
        }
        *gain = design.matrices.b_f;
        gamma = gamma.max(design.gamma);
        h2 = h2.max(design.h2_norm);
        if first.is_none() {
            first = Some(design);
        }
    }
    let first = first.ok_or_else(|| NavError::invalid("no H-infinity design"))?;
    let invalid = |e: crate::hinf::HinfError| NavError::invalid(crate::msg!("hinf: {e}"));
    let mut schedule = HinfSchedule {
        gains,
        orbit: model,
        frozen_gamma: gamma,
        certified_gamma: f64::NAN,
        certified_steps: 0,
    };
    certify_schedule(cfg, &mut schedule)?;
    let f = HinfEstimator::new(first.matrices, schedule.certified_gamma, x0)
        .map_err(invalid)?
        .with_h2_norm(h2)
        .with_design_info(first.info())
        .with_schedule(schedule)
        .map_err(invalid)?;
    Ok(AnyFilter::Hinf(f))
}
