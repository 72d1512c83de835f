//! The navigator's sensors beside its configured radio: any [`Sensor`], of any dimension,
//! added through the Rust API ([`super::Navigator::add_sensor`]) and applied in a step
//! when its reading is given ([`super::Navigator::step_with`]). [`NavSensor`] is the
//! object-safe view the navigator holds, so that one navigator holds sensors of different
//! dimensions; [`Named`] makes any [`Sensor`] one.

use super::factory::AnyFilter;
use crate::dynamics::DiscreteModel;
use crate::estimators::{Estimator, FilterError, SensorUpdate};
use crate::sensors::Sensor;
use crate::types::Vec3;
use nalgebra::SVector;

/// What an update by one of the navigator's sensors reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorReport {
    /// Normalised innovation squared (NaN for point particles and the H-infinity filter).
    pub nis: f64,
    /// Components used (its degrees of freedom).
    pub dof: usize,
}

impl<const D: usize> From<SensorUpdate<D>> for SensorReport {
    fn from(u: SensorUpdate<D>) -> Self {
        Self {
            nis: u.nis,
            dof: u.dof,
        }
    }
}

/// `Debug`, with `std` (a navigator's added sensors print); without, nothing: a `Debug`
/// in every sensor's vtable would link float formatting, whose code can panic.
#[cfg(feature = "std")]
pub trait SensorDebug: core::fmt::Debug {}
#[cfg(feature = "std")]
impl<T: core::fmt::Debug + ?Sized> SensorDebug for T {}
/// `Debug`, with `std` (a navigator's added sensors print); without, nothing: a `Debug`
/// in every sensor's vtable would link float formatting, whose code can panic.
#[cfg(not(feature = "std"))]
pub trait SensorDebug {}
#[cfg(not(feature = "std"))]
impl<T: ?Sized> SensorDebug for T {}

/// A sensor as the navigator holds it: its name (in messages), its dimension, the check of
/// a reading and the update of a filter with it (in the sensor's frame and SI units).
pub trait NavSensor: Send + Sync + SensorDebug {
    /// Name, for messages.
    fn name(&self) -> &str;
    /// Number of components of a reading.
    fn dim(&self) -> usize;
    /// Whether `z` is a reading this sensor can produce (length, finiteness, domain).
    fn check(&self, z: &[f64]) -> Result<(), crate::message::Message>;
    /// The update of `filter` with the reading `z` (checked) through the generic path
    /// ([`Estimator::update_sensor`]).
    fn apply(&self, filter: &mut AnyFilter, z: &[f64]) -> Result<SensorReport, FilterError>;
    /// [`NavSensor::apply`] then the time update through `model` with `accel`, committed
    /// together, for the filters that have that fused step (the EKF and the UKF); `None`
    /// for the others (nothing done).
    fn apply_predict(
        &self,
        filter: &mut AnyFilter,
        z: &[f64],
        model: &DiscreteModel,
        accel: &Vec3,
    ) -> Option<Result<SensorReport, FilterError>>;
}

/// `z` as a vector of `D` components (NaN where `z` is shorter; every caller has checked
/// its length): nalgebra's `from_column_slice` would assert the length, a panic path.
fn reading<const D: usize>(z: &[f64]) -> SVector<f64, D> {
    SVector::from_fn(|i, _| z.get(i).copied().unwrap_or(f64::NAN))
}

/// A sensor's name: with `std` a static text or an owned one (a declared sensor's name
/// allocates nothing, so a navigator holds no heap until sensors are added), a static
/// text without.
#[cfg(feature = "std")]
pub type SensorName = std::borrow::Cow<'static, str>;
/// A sensor's name: a static text without `std`.
#[cfg(not(feature = "std"))]
pub type SensorName = &'static str;

/// The text of a [`SensorName`] in either build.
fn name_str(n: &SensorName) -> &str {
    n
}

/// A [`Sensor`] of `D` components with a name: a [`NavSensor`].
#[derive(Debug, Clone)]
pub struct Named<S, const D: usize> {
    /// Name, for messages.
    pub name: SensorName,
    /// The sensor.
    pub sensor: S,
}

impl<S, const D: usize> Named<S, D> {
    /// `sensor` named `name`.
    #[cfg(feature = "std")]
    pub fn new(name: impl Into<std::borrow::Cow<'static, str>>, sensor: S) -> Self {
        Self {
            name: name.into(),
            sensor,
        }
    }

    /// `sensor` named `name`.
    #[cfg(not(feature = "std"))]
    pub fn new(name: &'static str, sensor: S) -> Self {
        Self { name, sensor }
    }

    /// `text` after this sensor's name and a colon.
    fn named(&self, text: &str) -> crate::message::Message {
        crate::message::Message::concat(&[name_str(&self.name), ": ", text])
    }
}

impl<const D: usize, S: Sensor<D> + Send + core::fmt::Debug> NavSensor for Named<S, D> {
    fn name(&self) -> &str {
        name_str(&self.name)
    }
    fn dim(&self) -> usize {
        D
    }
    fn check(&self, z: &[f64]) -> Result<(), crate::message::Message> {
        if z.len() != D {
            return Err(self.named(&crate::msg!(
                "a reading has {D} components (got {})",
                z.len()
            )));
        }
        self.sensor
            .check(&reading::<D>(z))
            .map_err(|e| self.named(&e))
    }
    fn apply(&self, filter: &mut AnyFilter, z: &[f64]) -> Result<SensorReport, FilterError> {
        if z.len() != D {
            return Err(FilterError::Unsupported("reading of the wrong length"));
        }
        filter
            .update_sensor(&self.sensor, &reading::<D>(z))
            .map(SensorReport::from)
    }
    fn apply_predict(
        &self,
        filter: &mut AnyFilter,
        z: &[f64],
        model: &DiscreteModel,
        accel: &Vec3,
    ) -> Option<Result<SensorReport, FilterError>> {
        if z.len() != D {
            return Some(Err(FilterError::Unsupported("reading of the wrong length")));
        }
        let z = reading::<D>(z);
        let r = filter.update_sensor_predict(&self.sensor, &z, model, accel)?;
        Some(r.map(SensorReport::from))
    }
}
