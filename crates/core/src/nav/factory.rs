//! The one filter factory ([`build_filter`]): a configuration's filter code becomes an
//! estimator here and nowhere else — for the navigator (and so the C ABI, the FMU and the
//! Python package) and for the evaluation engine. [`AnyFilter`] holds any of them by value
//! (enum dispatch: no boxing, no allocation per step).

use super::config::{FilterKind, NavConfig};
use super::error::{NavError, NavErrorKind};
use crate::dynamics::DiscreteModel;
use crate::estimators::aqukf::AqukfSnapshot;
use crate::estimators::pf::{Kernel, ParticleFilter, PfInit};
use crate::estimators::{Aqukf, Ekf, Estimator, FilterError, Imm, SensorUpdate, Ukf, UpdateInfo};
use crate::hinf::HinfEstimator;
use crate::numerics::state::{Persist, Reader, StateError, Writer};
use crate::sensors::{MeasurementModel, Sensor};
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
    Pf(ParticleFilter),
    /// Robust H-infinity filter (code 9).
    Hinf(HinfEstimator),
    /// Interacting multiple-model filter (code 10).
    Imm(Imm),
}

/// What a step of a Kalman-type filter can change, to restore after a failed step. Small
/// on purpose: `AnyFilter` itself is as large as its largest variant (the AQUKF's window),
/// and copying that on every step cost a quarter of an EKF step.
#[derive(Debug, Clone)]
pub(super) enum Snapshot {
    Ekf(Ekf),
    Ukf(Ukf),
    Aqukf(AqukfSnapshot),
    Hinf(HinfEstimator),
    Imm(Imm),
    /// particle filters are transactional themselves (see [`Navigator`])
    None,
}

impl AnyFilter {
    pub(super) fn snapshot(&self) -> Snapshot {
        match self {
            AnyFilter::Ekf(f) => Snapshot::Ekf(f.clone()),
            AnyFilter::Ukf(f) => Snapshot::Ukf(f.clone()),
            AnyFilter::Aqukf(f) => Snapshot::Aqukf(f.snapshot()),
            AnyFilter::Hinf(f) => Snapshot::Hinf(*f),
            AnyFilter::Imm(f) => Snapshot::Imm(f.clone()),
            AnyFilter::Pf(_) => Snapshot::None,
        }
    }

    /// Undo the step since `s` was taken (`s` from [`AnyFilter::snapshot`] of this filter).
    pub(super) fn restore(&mut self, s: &Snapshot) {
        match (self, s) {
            (AnyFilter::Ekf(f), Snapshot::Ekf(g)) => f.clone_from(g),
            (AnyFilter::Ukf(f), Snapshot::Ukf(g)) => f.clone_from(g),
            (AnyFilter::Aqukf(f), Snapshot::Aqukf(g)) => f.restore(g),
            (AnyFilter::Hinf(f), Snapshot::Hinf(g)) => *f = *g,
            (AnyFilter::Imm(f), Snapshot::Imm(g)) => f.clone_from(g),
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
            AnyFilter::Pf(_) => b"PART",
            AnyFilter::Hinf(_) => b"HINF",
            AnyFilter::Imm(_) => b"IMM ",
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
            AnyFilter::Pf(f) => f.save_state(w),
            AnyFilter::Hinf(f) => f.save_state(w),
            AnyFilter::Imm(f) => f.save_state(w),
        }
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        r.tag(self.state_tag())?;
        match self {
            AnyFilter::Ekf(f) => f.load_state(r),
            AnyFilter::Ukf(f) => f.load_state(r),
            AnyFilter::Aqukf(f) => f.load_state(r),
            AnyFilter::Pf(f) => f.load_state(r),
            AnyFilter::Hinf(f) => f.load_state(r),
            AnyFilter::Imm(f) => f.load_state(r),
        }
    }
}

impl Estimator for AnyFilter {
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        match self {
            AnyFilter::Ekf(f) => f.predict(model, accel),
            AnyFilter::Ukf(f) => f.predict(model, accel),
            AnyFilter::Aqukf(f) => f.predict(model, accel),
            AnyFilter::Pf(f) => f.predict(model, accel),
            AnyFilter::Hinf(f) => f.predict(model, accel),
            AnyFilter::Imm(f) => f.predict(model, accel),
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
            AnyFilter::Pf(f) => f.update(sensor, z),
            AnyFilter::Hinf(f) => f.update(sensor, z),
            AnyFilter::Imm(f) => f.update(sensor, z),
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
            AnyFilter::Pf(f) => f.update_sensor(sensor, z),
            AnyFilter::Hinf(f) => f.update_sensor(sensor, z),
            AnyFilter::Imm(f) => f.update_sensor(sensor, z),
        }
    }
    fn state(&self) -> &State {
        match self {
            AnyFilter::Ekf(f) => f.state(),
            AnyFilter::Ukf(f) => f.state(),
            AnyFilter::Aqukf(f) => f.state(),
            AnyFilter::Pf(f) => f.state(),
            AnyFilter::Hinf(f) => f.state(),
            AnyFilter::Imm(f) => f.state(),
        }
    }
    fn covariance(&self) -> &Mat6 {
        match self {
            AnyFilter::Ekf(f) => f.covariance(),
            AnyFilter::Ukf(f) => f.covariance(),
            AnyFilter::Aqukf(f) => f.covariance(),
            AnyFilter::Pf(f) => f.covariance(),
            AnyFilter::Hinf(f) => f.covariance(),
            AnyFilter::Imm(f) => f.covariance(),
        }
    }
    fn set_estimate(&mut self, x: State, p: Mat6) {
        match self {
            AnyFilter::Ekf(f) => f.set_estimate(x, p),
            AnyFilter::Ukf(f) => f.set_estimate(x, p),
            AnyFilter::Aqukf(f) => f.set_estimate(x, p),
            AnyFilter::Pf(f) => f.set_estimate(x, p),
            AnyFilter::Hinf(f) => f.set_estimate(x, p),
            AnyFilter::Imm(f) => f.set_estimate(x, p),
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
    let x0 = cfg.initial_state();
    let p0 = cfg.initial_covariance();
    if let Some(mut params) = cfg.pf_params() {
        params.init = opts.pf_init.unwrap_or(params.init);
        params.kernel = opts.pf_kernel;
        params.carry_covariance = opts.pf_carry_covariance;
        return Ok(AnyFilter::Pf(ParticleFilter::new(x0, p0, params)));
    }
    if let (FilterKind::Hinf, Some(h)) = (cfg.filter, &opts.hinf) {
        let mut h = *h;
        h.set_estimate(x0, p0);
        return Ok(AnyFilter::Hinf(h));
    }
    match cfg.filter {
        FilterKind::Ekf => Ok(AnyFilter::Ekf(Ekf::new(x0, p0))),
        FilterKind::Ukf => Ok(AnyFilter::Ukf(Ukf::new(x0, p0, cfg.ukf()))),
        FilterKind::Aqukf => Ok(AnyFilter::Aqukf(Aqukf::new(
            x0,
            p0,
            cfg.ukf(),
            cfg.aq_params(),
            cfg.dynamics(),
        ))),
        FilterKind::Imm => Ok(AnyFilter::Imm(Imm::new(
            x0,
            p0,
            cfg.imm_params(),
            cfg.dynamics(),
        ))),
        #[cfg(feature = "hinf")]
        FilterKind::Hinf => {
            use crate::hinf::design::{design_open_loop, design_open_loop_mixed, DesignOptions};
            let spec = cfg.hinf_spec()?;
            let opts = DesignOptions::default();
            let (d, info) = match cfg.hinf_design {
                super::config::HinfDesignKind::GammaOptimal => {
                    design_open_loop(&spec, &opts).map(|d| {
                        let info = d.info();
                        (d, info)
                    })
                }
                super::config::HinfDesignKind::Mixed => {
                    design_open_loop_mixed(&spec, cfg.hinf_gamma_factor, &opts).map(|m| {
                        let info = m.info();
                        (m.mixed, info)
                    })
                }
            }
            .map_err(|e| NavError {
                kind: NavErrorKind::InvalidArgument,
                message: format!("hinf design ({}) failed: {e}", cfg.hinf_design.name()),
            })?;
            let invalid = |e: crate::hinf::HinfError| NavError::invalid(format!("hinf: {e}"));
            let mut f = HinfEstimator::new(d.matrices, d.gamma, x0)
                .map_err(invalid)?
                .with_h2_norm(d.h2_norm)
                .with_design_info(info);
            if cfg.hinf_acquisition {
                let plant = crate::hinf::HinfPlant::open_loop(&spec);
                f = f.with_acquisition(&plant, p0).map_err(invalid)?;
            }
            Ok(AnyFilter::Hinf(f))
        }
        other => Err(NavError {
            kind: NavErrorKind::NotImplemented,
            message: format!("filter {} is not implemented", other.name()),
        }),
    }
}
