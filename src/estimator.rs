//! The opaque estimator handle and every `relnav_estimator_*` call.

use crate::config::relnav_config;
use crate::error::{null, relnav_status, Failure};
use crate::panic::boundary;
use crate::ptr::{drop_placed, place_for, read_array, storage_of, write_array};
use relnav_core::nav::{NavConfig, Navigator};
#[cfg(feature = "std")]
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Opaque estimator handle.
pub struct relnav_estimator {
    nav: Navigator,
}

/// # Safety
/// `ptr` is null or a live handle (`relnav_estimator_new` or `relnav_estimator_init`).
pub(super) unsafe fn estimator_mut<'a>(
    ptr: *mut relnav_estimator,
    func: &str,
) -> Result<&'a mut Navigator, Failure> {
    // SAFETY: non-null handles come from relnav_estimator_new or relnav_estimator_init.
    unsafe { ptr.as_mut() }
        .map(|e| &mut e.nav)
        .ok_or_else(|| null("estimator", func))
}

/// # Safety
/// As [`estimator_mut`].
pub(super) unsafe fn estimator_ref<'a>(
    ptr: *const relnav_estimator,
    func: &str,
) -> Result<&'a Navigator, Failure> {
    // SAFETY: non-null handles come from relnav_estimator_new or relnav_estimator_init.
    unsafe { ptr.as_ref() }
        .map(|e| &e.nav)
        .ok_or_else(|| null("estimator", func))
}

/// The body of a getter that writes one value of the estimator to `*out`: the handle and
/// `out` checked for null, in that order, inside the panic boundary.
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or writable.
unsafe fn get_one<T>(
    estimator: *const relnav_estimator,
    out: *mut T,
    func: &str,
    value: impl FnOnce(&Navigator) -> T,
) -> relnav_status {
    boundary(func, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_ref(estimator, func) }?;
        // SAFETY: as above.
        let o = unsafe { out.as_mut() }.ok_or_else(|| null("out", func))?;
        *o = value(nav);
        Ok(())
    })
}

/// The start of [`relnav_estimator_new`] and [`relnav_estimator_init`]: `*out` set to null
/// (null `out` refused), then `config` read and converted.
///
/// # Safety
/// `out` is null or writable; `config` is null or points to a `relnav_config`.
unsafe fn creation(
    out: *mut *mut relnav_estimator,
    config: *const relnav_config,
    func: &str,
) -> Result<NavConfig, Failure> {
    if out.is_null() {
        return Err(null("out", func));
    }
    // SAFETY: `out` is non-null and writable by the caller's contract.
    unsafe { *out = core::ptr::null_mut() };
    // SAFETY: caller guarantees a valid or null pointer.
    let c = unsafe { config.as_ref() }.ok_or_else(|| null("config", func))?;
    Ok(NavConfig::try_from(c)?)
}

/// Create an estimator. On success `*out` holds a new handle (free it with
/// [`relnav_estimator_free`]); on error `*out` is set to null.
///
/// Flight library: not in this build (`RELNAV_ERROR_NOT_IMPLEMENTED`; no heap): use
/// [`relnav_estimator_init`].
///
/// # Safety
/// `config` is null or points to a `relnav_config`; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_new(
    config: *const relnav_config,
    out: *mut *mut relnav_estimator,
) -> relnav_status {
    const F: &str = "relnav_estimator_new";
    boundary(F, || {
        // SAFETY: the caller's pointer contracts, passed on.
        let cfg = unsafe { creation(out, config, F) }?;
        #[cfg(feature = "std")]
        {
            let nav = Navigator::new(&cfg)?;
            let handle = Box::into_raw(Box::new(relnav_estimator { nav }));
            // SAFETY: `out` is non-null (checked by `creation`) and writable by contract.
            unsafe { *out = handle };
            Ok(())
        }
        #[cfg(not(feature = "std"))]
        {
            let _ = cfg;
            Err(crate::error::not_in_this_build(
                F,
                Some("relnav_estimator_init"),
            ))
        }
    })
}

/// Bytes of storage that hold an estimator in every build: static storage for
/// [`relnav_estimator_init`] (`RELNAV_ESTIMATOR_STORAGE_SIZE` bytes aligned to
/// `RELNAV_ESTIMATOR_STORAGE_ALIGN`; [`relnav_estimator_storage`] gives the exact need).
pub const RELNAV_ESTIMATOR_STORAGE_SIZE: usize = 32768;
/// The alignment of `RELNAV_ESTIMATOR_STORAGE_SIZE`'s storage, at least the estimator's.
pub const RELNAV_ESTIMATOR_STORAGE_ALIGN: usize = 16;
const _: () = assert!(
    core::mem::size_of::<relnav_estimator>() <= RELNAV_ESTIMATOR_STORAGE_SIZE
        && core::mem::align_of::<relnav_estimator>() <= RELNAV_ESTIMATOR_STORAGE_ALIGN
);

/// The storage [`relnav_estimator_init`] needs: `*size` bytes aligned to `*align` (a power
/// of two).
///
/// # Safety
/// `size` and `align` are null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_storage(
    size: *mut usize,
    align: *mut usize,
) -> relnav_status {
    const F: &str = "relnav_estimator_storage";
    // SAFETY: the caller's pointer contracts, passed on.
    boundary(F, || unsafe {
        storage_of::<relnav_estimator>(size, align, F)
    })
}

/// Create an estimator in the caller's `storage` (`size` bytes, aligned as
/// [`relnav_estimator_storage`] says): no heap. On success `*out` holds the handle, which
/// points into `storage`; end it with [`relnav_estimator_deinit`] (not
/// [`relnav_estimator_free`]) before the storage is reused. On error `*out` is set to null
/// and the storage holds no estimator.
///
/// Flight library: the only way to make an estimator; filter codes 4-9 (the particle
/// filters, the H-infinity filter with its design at start-up) and `range_bank` > 1 are
/// refused with `RELNAV_ERROR_NOT_IMPLEMENTED`.
///
/// # Safety
/// `storage` is null or points to `size` writable bytes that nothing else uses while the
/// estimator lives; `config` is null or points to a `relnav_config`; `out` is null or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_init(
    storage: *mut core::ffi::c_void,
    size: usize,
    config: *const relnav_config,
    out: *mut *mut relnav_estimator,
) -> relnav_status {
    const F: &str = "relnav_estimator_init";
    boundary(F, || {
        // SAFETY: the caller's pointer contracts, passed on.
        let cfg = unsafe { creation(out, config, F) }?;
        let place = place_for::<relnav_estimator>(storage, size, F, "relnav_estimator_storage")?;
        // SAFETY: `place` is non-null, aligned and has room for one `relnav_estimator`
        // (checked above), writable and unused by the caller's contract; `MaybeUninit<T>`
        // has `T`'s layout, and `relnav_estimator` holds the navigator alone.
        let slot = unsafe {
            &mut *core::ptr::addr_of_mut!((*place).nav).cast::<core::mem::MaybeUninit<Navigator>>()
        };
        Navigator::new_in(&cfg, slot)?;
        // SAFETY: `out` is non-null (checked by `creation`) and writable by contract.
        unsafe { *out = place };
        Ok(())
    })
}

/// End an estimator made by [`relnav_estimator_init`]; its storage is the caller's again.
/// Null is accepted and ignored (`RELNAV_OK` either way).
///
/// # Safety
/// `estimator` is null or a handle from [`relnav_estimator_init`] not yet ended.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_deinit(
    estimator: *mut relnav_estimator,
) -> relnav_status {
    // SAFETY: the caller's contract, passed on.
    unsafe { drop_placed(estimator) };
    relnav_status::RELNAV_OK
}

/// Release an estimator. Null is accepted and ignored. Cannot fail, so returns nothing.
///
/// Flight library: does nothing (no handle comes from [`relnav_estimator_new`] there).
///
/// # Safety
/// `estimator` is null or a handle from [`relnav_estimator_new`] not yet freed.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_free(estimator: *mut relnav_estimator) {
    #[cfg(feature = "std")]
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if !estimator.is_null() {
            // SAFETY: the handle came from Box::into_raw and is freed exactly once.
            drop(unsafe { Box::from_raw(estimator) });
        }
    }));
    // without std no handle comes from relnav_estimator_new
    #[cfg(not(feature = "std"))]
    let _ = estimator;
}

/// Time update over `dt` seconds with `thrust` (3 doubles, [N], configured frame) held
/// constant. `dt` must be > 0 and at most 1000 orbital periods (`2 pi / mean_motion`);
/// a longer step is refused with `RELNAV_ERROR_INVALID_ARGUMENT`. Every call returns in
/// bounded time, whatever the numbers.
///
/// # Safety
/// `estimator` is a live handle or null; `thrust` is null or points to 3 doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_predict(
    estimator: *mut relnav_estimator,
    thrust: *const f64,
    dt: f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_predict";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_mut(estimator, F) }?;
        // SAFETY: as above.
        let u = unsafe { read_array::<3>(thrust, "thrust", F) }?;
        nav.predict(&u, dt)?;
        Ok(())
    })
}

/// Measurement update with `z` = (range [m], azimuth [rad], elevation [rad]).
///
/// # Safety
/// `estimator` is a live handle or null; `z` is null or points to 3 doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_update(
    estimator: *mut relnav_estimator,
    z: *const f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_update";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_mut(estimator, F) }?;
        // SAFETY: as above.
        let z = unsafe { read_array::<3>(z, "z", F) }?;
        nav.update(&z)?;
        Ok(())
    })
}

/// One step at time t: update with `z` (the measurement taken at t; pass null when there
/// is none), then predict over `dt` with `thrust` held. Afterwards the estimate is at
/// `t + dt`. On error nothing changes. `dt` as in [`relnav_estimator_predict`] (at most
/// 1000 orbital periods).
///
/// # Safety
/// `estimator` is a live handle or null; `thrust` is null or 3 doubles; `z` is null or 3
/// doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_step(
    estimator: *mut relnav_estimator,
    thrust: *const f64,
    z: *const f64,
    dt: f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_step";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_mut(estimator, F) }?;
        // SAFETY: as above.
        let u = unsafe { read_array::<3>(thrust, "thrust", F) }?;
        let zm = if z.is_null() {
            None
        } else {
            // SAFETY: non-null, 3 doubles by contract.
            Some(unsafe { read_array::<3>(z, "z", F) }?)
        };
        nav.step(&u, zm.as_ref(), dt)?;
        Ok(())
    })
}

/// One step with the declared sensors: at time t, update with each reading that is given
/// (null: none), in this order — `z` the radio's (range [m], azimuth, elevation [rad]),
/// `camera` the line of sight (azimuth, elevation [rad]; the radio's conventions),
/// `gnss_position` (x, y, z [m]) and `gnss_velocity` (vx, vy, vz [m/s]), all in the I/O
/// frame and taken at t, with the noise `sigma_camera`, `sigma_gnss`,
/// `sigma_gnss_velocity` of the configuration — then predict over `dt` with `thrust`
/// held. Every reading is checked first (a refusal names the sensor); on error nothing
/// changes. With only `z`, the same as [`relnav_estimator_step`].
///
/// # Safety
/// `estimator` is a live handle or null; `thrust` is null or 3 doubles; `z`,
/// `gnss_position`, `gnss_velocity` are null or 3 doubles each; `camera` is null or 2
/// doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_step_sensors(
    estimator: *mut relnav_estimator,
    thrust: *const f64,
    z: *const f64,
    camera: *const f64,
    gnss_position: *const f64,
    gnss_velocity: *const f64,
    dt: f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_step_sensors";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_mut(estimator, F) }?;
        // SAFETY: as above.
        let u = unsafe { read_array::<3>(thrust, "thrust", F) }?;
        // SAFETY (each): non-null pointers hold their documented number of doubles.
        let radio = (!z.is_null())
            .then(|| unsafe { read_array::<3>(z, "z", F) })
            .transpose()?;
        let camera = (!camera.is_null())
            .then(|| unsafe { read_array::<2>(camera, "camera", F) })
            .transpose()?;
        let gnss_position = (!gnss_position.is_null())
            .then(|| unsafe { read_array::<3>(gnss_position, "gnss_position", F) })
            .transpose()?;
        let gnss_velocity = (!gnss_velocity.is_null())
            .then(|| unsafe { read_array::<3>(gnss_velocity, "gnss_velocity", F) })
            .transpose()?;
        let readings = relnav_core::nav::Readings {
            radio,
            camera,
            gnss_position,
            gnss_velocity,
        };
        nav.step_readings(&u, &readings, dt)?;
        Ok(())
    })
}

/// Copy the last step's normalised innovation squared per declared sensor (4 doubles:
/// radio, camera, GNSS position, GNSS velocity; NaN for a sensor that gave no reading in
/// that step, for point particles and the H-infinity filter, and after a restore) to `out`, and
/// the estimated range's 1-sigma [m] (the covariance along the estimated line of sight;
/// NaN for the H-infinity filter) to `range_sigma`.
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or 4 writable doubles;
/// `range_sigma` is null or 1 writable double.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_sensor_diagnostics(
    estimator: *const relnav_estimator,
    out: *mut f64,
    range_sigma: *mut f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_get_sensor_diagnostics";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_ref(estimator, F) }?;
        // SAFETY: as above.
        unsafe { write_array(out, &nav.step_nis(), "out", F) }?;
        // SAFETY: as above.
        unsafe { write_array(range_sigma, &[nav.range_sigma()], "range_sigma", F) }
    })
}

/// Copy the state estimate (6 doubles: x, y, z [m], vx, vy, vz [m/s]) to `out`.
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or 6 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_state(
    estimator: *const relnav_estimator,
    out: *mut f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_get_state";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_ref(estimator, F) }?;
        let x: [f64; 6] = nav.state().into();
        // SAFETY: as above.
        unsafe { write_array(out, &x, "out", F) }
    })
}

/// Copy the 6x6 error covariance (36 doubles, row-major, configured frame) to `out`.
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or 36 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_covariance(
    estimator: *const relnav_estimator,
    out: *mut f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_get_covariance";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_ref(estimator, F) }?;
        let p = nav.covariance();
        let mut a = [0.0; 36];
        for i in 0..6 {
            for j in 0..6 {
                a[6 * i + j] = p[(i, j)];
            }
        }
        // SAFETY: as above.
        unsafe { write_array(out, &a, "out", F) }
    })
}

/// Copy the 1-sigma of each state component (square roots of the covariance diagonal,
/// 6 doubles) to `out`.
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or 6 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_sigma(
    estimator: *const relnav_estimator,
    out: *mut f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_get_sigma";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_ref(estimator, F) }?;
        // a NaN or negative variance (a failed filter) reports NaN, never a reassuring 0
        let s = nav.sigma();
        // SAFETY: as above.
        unsafe { write_array(out, &s, "out", F) }
    })
}

/// Copy the estimate and its 1-sigma in one call (12 doubles: x, y, z [m], vx, vy, vz
/// [m/s] as [`relnav_estimator_get_state`], then their 1-sigma as
/// [`relnav_estimator_get_sigma`], the same bits). One boundary instead of two for a
/// caller that reads both every step (the FMU publishes its 12 estimate outputs with it).
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or 12 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_estimate(
    estimator: *const relnav_estimator,
    out: *mut f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_get_estimate";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_ref(estimator, F) }?;
        let x = nav.state();
        let s = nav.sigma();
        let mut a = [0.0; 12];
        a[..6].copy_from_slice(x.as_slice());
        a[6..].copy_from_slice(&s);
        // SAFETY: as above.
        unsafe { write_array(out, &a, "out", F) }
    })
}

/// Return to the initial estimate of the configuration.
///
/// # Safety
/// `estimator` is a live handle or null.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_reset(estimator: *mut relnav_estimator) -> relnav_status {
    const F: &str = "relnav_estimator_reset";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        unsafe { estimator_mut(estimator, F) }?.reset();
        Ok(())
    })
}

/// Copy the configuration the estimator was created with to `out`.
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_config(
    estimator: *const relnav_estimator,
    out: *mut relnav_config,
) -> relnav_status {
    // SAFETY: the caller's pointer contracts, passed on.
    unsafe {
        get_one(estimator, out, "relnav_estimator_get_config", |nav| {
            relnav_config::from(nav.config())
        })
    }
}

/// Diagnostics of the last measurement update: innovation (3 doubles, azimuth wrapped) and
/// its normalised squared value NIS. Both are NaN before the first update. The particle
/// filters give the innovation of their weighted mean (zero at the first update, which
/// initialises the particles from the measurement) and no NIS (NaN).
///
/// # Safety
/// `estimator` is a live handle or null; `innovation` is null or 3 writable doubles;
/// `nis` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_innovation(
    estimator: *const relnav_estimator,
    innovation: *mut f64,
    nis: *mut f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_get_innovation";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_ref(estimator, F) }?;
        if innovation.is_null() {
            return Err(null("innovation", F));
        }
        // SAFETY: as above; checked before anything is written.
        let n = unsafe { nis.as_mut() }.ok_or_else(|| null("nis", F))?;
        let (nu, v) = match nav.last_update() {
            Some(u) => (u.innovation.into(), u.nis),
            None => ([f64::NAN; 3], f64::NAN),
        };
        // SAFETY: as above.
        unsafe { write_array(innovation, &nu, "innovation", F) }?;
        *n = v;
        Ok(())
    })
}

/// The effective sample size `1 / sum w_i^2` of a particle filter (codes 4-8) after its
/// last measurement update, before resampling (the particle count before the first
/// update); it lies in [1, particles]. The Kalman filters (codes 1, 2) carry no particles:
/// `*out` is NaN for them (and the status `RELNAV_OK`).
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_ess(
    estimator: *const relnav_estimator,
    out: *mut f64,
) -> relnav_status {
    // SAFETY: the caller's pointer contracts, passed on.
    unsafe {
        get_one(estimator, out, "relnav_estimator_get_ess", |nav| {
            nav.ess().unwrap_or(f64::NAN)
        })
    }
}

/// The fraction of a particle filter's (codes 4-8) Metropolis–Hastings moves (`pf_move`
/// rejuvenation, the RPF's jitter, the genetic operators) accepted in the last
/// `relnav_estimator_step` or update: how far its particles moved from their proposal.
/// `*out` is NaN when that step made no move (no measurement, the first update, which draws
/// the particles from the measurement), for the other filters, before the first step and
/// after a restore (the status `RELNAV_OK`).
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_pf_acceptance(
    estimator: *const relnav_estimator,
    out: *mut f64,
) -> relnav_status {
    // SAFETY: the caller's pointer contracts, passed on.
    unsafe {
        get_one(
            estimator,
            out,
            "relnav_estimator_get_pf_acceptance",
            |nav| nav.step_acceptance(),
        )
    }
}

/// The AQUKF's (code 3) current adaptive velocity process-noise density `q_vv`
/// [m^2/s^3], one value per axis of the configured frame (the diagonal of the rotated
/// matrix, exact because every frame rotation is a signed permutation; paper 001
/// sec. 2.2, `q_vv = diag(Q_vv) / T`). The other filters have none: `out` is filled with
/// NaN for them (and the status `RELNAV_OK`).
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or 3 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_q_vv(
    estimator: *const relnav_estimator,
    out: *mut f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_get_q_vv";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_ref(estimator, F) }?;
        let q = nav.q_vv().unwrap_or([f64::NAN; 3]);
        // SAFETY: as above; `write_array` checks `out` for null.
        unsafe { write_array(out, &q, "out", F) }
    })
}
/// The certified `gamma` of the H-infinity design of an estimator created with filter 9;
/// NaN for every other filter (status `RELNAV_OK`).
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_hinf_gamma(
    estimator: *const relnav_estimator,
    out: *mut f64,
) -> relnav_status {
    // SAFETY: the caller's pointer contracts, passed on.
    unsafe {
        get_one(estimator, out, "relnav_estimator_get_hinf_gamma", |nav| {
            nav.hinf_gamma().unwrap_or(f64::NAN)
        })
    }
}

/// The H2 norm of the H-infinity design of an estimator created with filter 9 (from the
/// unit white noises of its noise model to the prediction error; computed without the
/// solver — with the derived noise model its square is the steady-state mean-square error
/// [m^2 + m^2/s^2]); NaN for every other filter (status `RELNAV_OK`).
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_hinf_h2_norm(
    estimator: *const relnav_estimator,
    out: *mut f64,
) -> relnav_status {
    // SAFETY: the caller's pointer contracts, passed on.
    unsafe {
        get_one(estimator, out, "relnav_estimator_get_hinf_h2_norm", |nav| {
            nav.hinf_h2_norm().unwrap_or(f64::NAN)
        })
    }
}

/// Whether the H-infinity filter (filter 9) runs its designed, certified gain: 1 after
/// the hand-over of track initiation (`hinf_acquisition`) or always without it, 0 while it
/// still acquires with the Kalman gain, -1 for every other filter (status `RELNAV_OK`).
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_hinf_certified(
    estimator: *const relnav_estimator,
    out: *mut i32,
) -> relnav_status {
    // SAFETY: the caller's pointer contracts, passed on.
    unsafe {
        get_one(
            estimator,
            out,
            "relnav_estimator_get_hinf_certified",
            |nav| nav.hinf_certified().map_or(-1, i32::from),
        )
    }
}

/// The IMM's (code 10) mode probabilities after the last step, 3 doubles: mode 1 (the
/// configured process noise), mode 2, mode 3 (`imm_accel_psd` added); they sum to 1 over
/// the `imm_modes` modes, and an unused third mode is NaN. Every other filter has no modes:
/// `out` is filled with NaN (status `RELNAV_OK`).
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or 3 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_mode_probabilities(
    estimator: *const relnav_estimator,
    out: *mut f64,
) -> relnav_status {
    const F: &str = "relnav_estimator_get_mode_probabilities";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_ref(estimator, F) }?;
        let mu = nav.mode_probabilities().unwrap_or([f64::NAN; 3]);
        // SAFETY: as above; `write_array` checks `out` for null.
        unsafe { write_array(out, &mu, "out", F) }
    })
}

/// How the H-infinity filter of an estimator created with filter 9 was designed: the
/// route (Riccati bisection or SDP), the gamma-optimal stage's route and why its Riccati
/// route was not taken if it was not, the bisection's trials, Clarabel's iterations and
/// the design time. Every other filter gets `RELNAV_HINF_ROUTE_NONE`, zero counts and a NaN
/// time (status `RELNAV_OK`).
///
/// # Safety
/// `estimator` is a live handle or null; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_get_hinf_design(
    estimator: *const relnav_estimator,
    out: *mut crate::hinf::relnav_hinf_design_info,
) -> relnav_status {
    // SAFETY: the caller's pointer contracts, passed on.
    unsafe {
        get_one(
            estimator,
            out,
            "relnav_estimator_get_hinf_design",
            design_info_of,
        )
    }
}

fn design_info_of(nav: &Navigator) -> crate::hinf::relnav_hinf_design_info {
    nav.hinf_design_info()
        .map_or(crate::hinf::relnav_hinf_design_info::NONE, |i| {
            crate::hinf::relnav_hinf_design_info::of(&i)
        })
}
