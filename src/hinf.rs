//! The H-infinity design on its own (`relnav_hinf_design`) and the runtime filter without
//! solver (`relnav_hinf_filter_*`).

#[cfg(not(feature = "std"))]
use crate::error::not_in_this_build;
use crate::error::{null, relnav_status, Failure};
use crate::panic::boundary;
use crate::ptr::{drop_placed, place_for, read_array, storage_of, write_array};
#[cfg(feature = "std")]
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Which H-infinity design `relnav_hinf_design` solves.
#[repr(i32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum relnav_hinf_form {
    /// Observer (error-dynamics) form for the open-loop CW plant, the known thrust as
    /// feed-forward (the form filter code 9 runs).
    RELNAV_HINF_OBSERVER = 1,
    /// Paper 002's Theorem 1 / Corollary 1 on its closed loop `u = K x` (its `K` and
    /// 1000 kg chaser; Euler `A = I + T (A1 + G0 K)`).
    RELNAV_HINF_PAPER = 2,
    /// Mixed H2/H-infinity observer for the open-loop CW plant (the default of filter code
    /// 9): first the gamma-optimal observer, then the least H2 norm under `gamma <=
    /// gamma_factor * gamma_opt`.
    RELNAV_HINF_MIXED = 3,
}

/// Inputs of an H-infinity design (canonical frame = paper 002's, SI units).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct relnav_hinf_spec {
    /// A `relnav_hinf_form` code.
    pub form: i32,
    /// Nominal mean motion `w0` [rad/s].
    pub mean_motion: f64,
    /// Orbit-rate uncertainty bound `delta_bar`, >= 0.
    pub delta_bar: f64,
    /// Sampling period [s].
    pub period: f64,
    /// Process-noise scaling on positions [m] (> 0, or 0 with `b_vel = 0`: `b_matrix`).
    pub b_pos: f64,
    /// Process-noise scaling on velocities [m/s] (> 0, or 0 with `b_pos = 0`).
    pub b_vel: f64,
    /// Measurement-noise scaling [m] (> 0, or 0: `d_matrix`).
    pub d: f64,
    /// `RELNAV_HINF_MIXED`: the bound on gamma as a multiple of the gamma-optimal
    /// observer's, finite and > 1 (filter 9's default: 1.5); ignored by the other forms.
    pub gamma_factor: f64,
    /// The process-noise input `B` (6x6, row-major, canonical frame) used when `b_pos =
    /// b_vel = 0`, e.g. the square root of a process covariance (`relnav_config_hinf_spec`
    /// fills it as filter 9 derives it).
    pub b_matrix: [f64; 36],
    /// The measurement-noise input `D` (3x3, row-major, canonical, invertible) used when
    /// `d = 0`.
    pub d_matrix: [f64; 9],
}

/// A designed H-infinity filter: `x_f(k+1) = A_F x_f + B_F y + E_F a`, `z_f = C_F x_f`
/// (row-major matrices; `y` the canonical position [m], `a` the known thrust
/// acceleration [m/s^2], canonical frame).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct relnav_hinf_matrices {
    /// `A_F`, 6x6.
    pub a_f: [f64; 36],
    /// `B_F`, 6x3.
    pub b_f: [f64; 18],
    /// `C_F`, 6x6.
    pub c_f: [f64; 36],
    /// `E_F`, 6x3 (zero for the paper form).
    pub e_f: [f64; 18],
    /// The period the matrices hold for [s].
    pub period: f64,
}

/// Design report.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct relnav_hinf_result {
    /// The filter.
    pub matrices: relnav_hinf_matrices,
    /// Certified bound `gamma` on the worst-case gain from the scaled noises to the error.
    pub gamma: f64,
    /// Largest eigenvalue of the LMI assembled from the solution (nalgebra; < 0).
    pub lmi_max_eig: f64,
    /// Clarabel iterations (0 when the gamma-optimal observer was designed by the Riccati
    /// route, which needs no interior-point solver; the SDP runs only as its fallback).
    pub iterations: i32,
    /// Wall time of assembly and solve [s].
    pub solve_time: f64,
    /// H2 norm of the filter's nominal error system from the unit white noises `(w, v)`
    /// (computed without the solver; with `B`, `D` square roots of the noise covariances,
    /// its square is the steady-state mean-square error).
    pub h2_norm: f64,
    /// `RELNAV_HINF_MIXED`: the gamma of the gamma-optimal observer the bound is relative
    /// to (its design's iterations and time are included above); NaN for the other forms.
    pub gamma_opt: f64,
}

#[cfg(feature = "hinf")]
fn to_c_matrices(m: &relnav_core::hinf::HinfMatrices) -> relnav_hinf_matrices {
    let mut o = relnav_hinf_matrices {
        a_f: [0.0; 36],
        b_f: [0.0; 18],
        c_f: [0.0; 36],
        e_f: [0.0; 18],
        period: m.period,
    };
    for i in 0..6 {
        for j in 0..6 {
            o.a_f[6 * i + j] = m.a_f[(i, j)];
            o.c_f[6 * i + j] = m.c_f[(i, j)];
        }
        for j in 0..3 {
            o.b_f[3 * i + j] = m.b_f[(i, j)];
            o.e_f[3 * i + j] = m.e_f[(i, j)];
        }
    }
    o
}

fn from_c_matrices(m: &relnav_hinf_matrices) -> relnav_core::hinf::HinfMatrices {
    use relnav_core::types::{Mat6, Mat63};
    relnav_core::hinf::HinfMatrices {
        a_f: Mat6::from_fn(|i, j| m.a_f[6 * i + j]),
        b_f: Mat63::from_fn(|i, j| m.b_f[3 * i + j]),
        c_f: Mat6::from_fn(|i, j| m.c_f[6 * i + j]),
        e_f: Mat63::from_fn(|i, j| m.e_f[3 * i + j]),
        // the C ABI's runtime filter takes the position alone
        b_v: Mat63::zeros(),
        period: m.period,
    }
}

impl From<relnav_core::hinf::HinfError> for Failure {
    fn from(e: relnav_core::hinf::HinfError) -> Self {
        use relnav_core::hinf::HinfErrorKind as K;
        let status = match e.kind {
            K::InvalidArgument => relnav_status::RELNAV_ERROR_INVALID_ARGUMENT,
            K::Infeasible => relnav_status::RELNAV_ERROR_INFEASIBLE,
            K::SolverFailed => relnav_status::RELNAV_ERROR_NUMERICAL,
        };
        Failure(status, e.message)
    }
}

/// Design an H-infinity filter (LMI solved with Clarabel; see `relnav::hinf`). On
/// success `*out` holds the matrices and the report; an infeasible request returns
/// `RELNAV_ERROR_INFEASIBLE` with a readable reason (`relnav_last_error`) and leaves `*out`
/// untouched. Without the `hinf` cargo feature it returns `RELNAV_ERROR_NOT_IMPLEMENTED`.
///
/// Flight library: not in this build (`RELNAV_ERROR_NOT_IMPLEMENTED`; no solver): design in
/// the full library (this call) or Python (`Estimator.hinf_matrices`) and load the matrices
/// with [`relnav_hinf_filter_init`].
///
/// # Safety
/// `spec` is null or readable; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_hinf_design(
    spec: *const relnav_hinf_spec,
    out: *mut relnav_hinf_result,
) -> relnav_status {
    const F: &str = "relnav_hinf_design";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let s = *unsafe { spec.as_ref() }.ok_or_else(|| null("spec", F))?;
        // SAFETY: as above.
        let o = unsafe { out.as_mut() }.ok_or_else(|| null("out", F))?;
        hinf_design(&s, o)
    })
}

#[cfg(feature = "hinf")]
/// The Rust spec of a C spec: the scalings, or the full matrices where they are zero.
fn spec_from_c(s: &relnav_hinf_spec) -> Result<relnav_core::hinf::HinfSpec, Failure> {
    use relnav_core::types::{Mat3, Mat6};
    let invalid = |m: String| Failure(relnav_status::RELNAV_ERROR_INVALID_ARGUMENT, m.into());
    if (s.b_pos == 0.0) != (s.b_vel == 0.0) {
        return Err(invalid(format!(
            "b_pos and b_vel are both > 0 (diagonal B) or both 0 (b_matrix) (got {} and {})",
            s.b_pos, s.b_vel
        )));
    }
    Ok(relnav_core::hinf::HinfSpec {
        w0: s.mean_motion,
        delta_bar: s.delta_bar,
        period: s.period,
        b_pos: s.b_pos,
        b_vel: s.b_vel,
        d: s.d,
        b_matrix: (s.b_pos == 0.0).then(|| Mat6::from_fn(|i, j| s.b_matrix[6 * i + j])),
        d_matrix: (s.d == 0.0).then(|| Mat3::from_fn(|i, j| s.d_matrix[3 * i + j])),
    })
}

#[cfg(feature = "hinf")]
fn hinf_design(s: &relnav_hinf_spec, o: &mut relnav_hinf_result) -> Result<(), Failure> {
    use relnav_core::hinf::design::{
        design_open_loop, design_open_loop_mixed, design_paper_spec, DesignOptions,
    };
    let spec = spec_from_c(s)?;
    let opts = DesignOptions::default();
    let (d, gamma_opt, extra) = match s.form {
        1 => (design_open_loop(&spec, &opts)?, f64::NAN, (0, 0.0)),
        2 => (design_paper_spec(&spec, &opts)?, f64::NAN, (0, 0.0)),
        3 => {
            let m = design_open_loop_mixed(&spec, s.gamma_factor, &opts)?;
            (
                m.mixed,
                m.pure.gamma,
                (m.pure.iterations, m.pure.solve_time),
            )
        }
        other => {
            return Err(Failure(
                relnav_status::RELNAV_ERROR_INVALID_ARGUMENT,
                format!("unknown hinf form code {other} (allowed: 1 observer, 2 paper, 3 mixed)")
                    .into(),
            ))
        }
    };
    *o = relnav_hinf_result {
        matrices: to_c_matrices(&d.matrices),
        gamma: d.gamma,
        lmi_max_eig: d.lmi_max_eig,
        iterations: i32::try_from(d.iterations + extra.0).unwrap_or(i32::MAX),
        solve_time: d.solve_time + extra.1,
        h2_norm: d.h2_norm,
        gamma_opt,
    };
    Ok(())
}

/// Fill `*out` with the H-infinity design request that filter 9 makes for `config`: the
/// form from `hinf_design`, its `gamma_factor`, and the noise inputs — the scalings where
/// `hinf_b_*`/`hinf_d` are set, else the matrices derived from the configuration's own
/// noise (process covariance square root for `hinf_period`, indirect-position covariance
/// square root at the initial estimate; see `relnav_config`), in the canonical frame.
/// `relnav_hinf_design(out, ...)` then returns the filter the estimator runs (before its
/// track initiation, `hinf_acquisition`). Works whatever `config.filter` is.
///
/// Flight library: not in this build (`RELNAV_ERROR_NOT_IMPLEMENTED`).
///
/// # Safety
/// `config` is null or readable; `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_config_hinf_spec(
    config: *const crate::config::relnav_config,
    out: *mut relnav_hinf_spec,
) -> relnav_status {
    const F: &str = "relnav_config_hinf_spec";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let c = unsafe { config.as_ref() }.ok_or_else(|| null("config", F))?;
        // SAFETY: as above.
        let o = unsafe { out.as_mut() }.ok_or_else(|| null("out", F))?;
        #[cfg(not(feature = "std"))]
        {
            let _ = (c, o);
            Err(not_in_this_build(F, None))
        }
        #[cfg(feature = "std")]
        config_hinf_spec(c, o)
    })
}

/// [`relnav_config_hinf_spec`] once its pointers are checked.
#[cfg(feature = "std")]
fn config_hinf_spec(
    c: &crate::config::relnav_config,
    o: &mut relnav_hinf_spec,
) -> Result<(), Failure> {
    {
        // validate as filter 9, whatever the configured filter
        let mut c9 = *c;
        c9.filter = relnav_core::nav::FilterKind::Hinf as i32;
        let cfg = relnav_core::nav::NavConfig::try_from(&c9)?;
        let spec = cfg.hinf_spec()?;
        let mut b_matrix = [0.0; 36];
        let mut d_matrix = [0.0; 9];
        let (b, d) = (spec.b(), spec.d());
        for i in 0..6 {
            for j in 0..6 {
                b_matrix[6 * i + j] = b[(i, j)];
            }
        }
        for i in 0..3 {
            for j in 0..3 {
                d_matrix[3 * i + j] = d[(i, j)];
            }
        }
        *o = relnav_hinf_spec {
            form: cfg.hinf_design as i32,
            mean_motion: spec.w0,
            delta_bar: spec.delta_bar,
            period: spec.period,
            b_pos: if spec.b_matrix.is_some() {
                0.0
            } else {
                spec.b_pos
            },
            b_vel: if spec.b_matrix.is_some() {
                0.0
            } else {
                spec.b_vel
            },
            d: if spec.d_matrix.is_some() { 0.0 } else { spec.d },
            gamma_factor: cfg.hinf_gamma_factor,
            b_matrix,
            d_matrix,
        };
        Ok(())
    }
}

#[cfg(not(feature = "hinf"))]
fn hinf_design(_s: &relnav_hinf_spec, _o: &mut relnav_hinf_result) -> Result<(), Failure> {
    Err(Failure(
        relnav_status::RELNAV_ERROR_NOT_IMPLEMENTED,
        "relnav_hinf_design: not in this build (no `hinf` feature: no LMI solver)".into(),
    ))
}

/// Opaque runtime H-infinity filter (no solver, no allocation in a step).
pub struct relnav_hinf_filter {
    f: relnav_core::hinf::HinfFilter,
}

/// Create a runtime filter from designed matrices; its estimate `C_F x_f` starts at `x0`
/// (6 doubles, canonical frame). Free with `relnav_hinf_filter_free`.
///
/// Flight library: not in this build (`RELNAV_ERROR_NOT_IMPLEMENTED`; no heap): use
/// [`relnav_hinf_filter_init`].
///
/// # Safety
/// `matrices` is null or readable; `x0` is null or 6 readable doubles; `out` is null or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_hinf_filter_new(
    matrices: *const relnav_hinf_matrices,
    x0: *const f64,
    out: *mut *mut relnav_hinf_filter,
) -> relnav_status {
    const F: &str = "relnav_hinf_filter_new";
    boundary(F, || {
        #[cfg(feature = "std")]
        {
            // SAFETY: the caller's pointer contracts, passed on.
            let f = unsafe { runtime_filter(matrices, x0, F) }?;
            // SAFETY: pointer contracts are the caller's, checked for null.
            let o = unsafe { out.as_mut() }.ok_or_else(|| null("out", F))?;
            *o = Box::into_raw(Box::new(relnav_hinf_filter { f }));
            Ok(())
        }
        #[cfg(not(feature = "std"))]
        {
            let _ = (matrices, x0, out);
            Err(not_in_this_build(F, Some("relnav_hinf_filter_init")))
        }
    })
}

/// The start of [`relnav_hinf_filter_new`] and [`relnav_hinf_filter_init`]: the filter of
/// `matrices`, its estimate starting at `x0`.
///
/// # Safety
/// `matrices` is null or readable; `x0` is null or 6 readable doubles.
unsafe fn runtime_filter(
    matrices: *const relnav_hinf_matrices,
    x0: *const f64,
    func: &str,
) -> Result<relnav_core::hinf::HinfFilter, Failure> {
    // SAFETY: the caller's contract, checked for null.
    let m = unsafe { matrices.as_ref() }.ok_or_else(|| null("matrices", func))?;
    // SAFETY: as above.
    let x = unsafe { read_array::<6>(x0, "x0", func) }?;
    Ok(relnav_core::hinf::HinfFilter::new(
        from_c_matrices(m),
        relnav_core::types::State::from(x),
    )?)
}

/// Bytes of storage that hold a runtime filter in every build: static storage for
/// [`relnav_hinf_filter_init`] (`RELNAV_HINF_FILTER_STORAGE_SIZE` bytes aligned to
/// `RELNAV_HINF_FILTER_STORAGE_ALIGN`; [`relnav_hinf_filter_storage`] gives the exact need).
pub const RELNAV_HINF_FILTER_STORAGE_SIZE: usize = 2048;
/// The alignment of `RELNAV_HINF_FILTER_STORAGE_SIZE`'s storage, at least the filter's.
pub const RELNAV_HINF_FILTER_STORAGE_ALIGN: usize = 16;
const _: () = assert!(
    core::mem::size_of::<relnav_hinf_filter>() <= RELNAV_HINF_FILTER_STORAGE_SIZE
        && core::mem::align_of::<relnav_hinf_filter>() <= RELNAV_HINF_FILTER_STORAGE_ALIGN
);

/// The storage [`relnav_hinf_filter_init`] needs: `*size` bytes aligned to `*align` (a
/// power of two).
///
/// # Safety
/// `size` and `align` are null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_hinf_filter_storage(
    size: *mut usize,
    align: *mut usize,
) -> relnav_status {
    const F: &str = "relnav_hinf_filter_storage";
    // SAFETY: the caller's pointer contracts, passed on.
    boundary(F, || unsafe {
        storage_of::<relnav_hinf_filter>(size, align, F)
    })
}

/// Create a runtime filter in the caller's `storage` (`size` bytes, aligned as
/// [`relnav_hinf_filter_storage`] says) from designed matrices: no heap, the flight
/// library's way to run gains designed elsewhere (`relnav_hinf_design` in the full library,
/// `Estimator.hinf_matrices` in Python) and loaded as data. Its estimate `C_F x_f` starts at `x0` (6 doubles,
/// canonical frame). On success `*out` points into `storage`; end it with
/// [`relnav_hinf_filter_deinit`] (not [`relnav_hinf_filter_free`]). On error `*out` is set
/// to null.
///
/// # Safety
/// `storage` is null or points to `size` writable bytes that nothing else uses while the
/// filter lives; `matrices` is null or readable; `x0` is null or 6 readable doubles; `out`
/// is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_hinf_filter_init(
    storage: *mut core::ffi::c_void,
    size: usize,
    matrices: *const relnav_hinf_matrices,
    x0: *const f64,
    out: *mut *mut relnav_hinf_filter,
) -> relnav_status {
    const F: &str = "relnav_hinf_filter_init";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let o = unsafe { out.as_mut() }.ok_or_else(|| null("out", F))?;
        *o = core::ptr::null_mut();
        let place =
            place_for::<relnav_hinf_filter>(storage, size, F, "relnav_hinf_filter_storage")?;
        // SAFETY: the caller's pointer contracts, passed on.
        let f = unsafe { runtime_filter(matrices, x0, F) }?;
        // SAFETY: `place` is non-null, aligned and has room for one filter (checked
        // above), writable and unused by the caller's contract.
        unsafe { place.write(relnav_hinf_filter { f }) };
        *o = place;
        Ok(())
    })
}

/// End a runtime filter made by [`relnav_hinf_filter_init`]; its storage is the caller's
/// again. Null is accepted and ignored (`RELNAV_OK` either way).
///
/// # Safety
/// `filter` is null or a handle from [`relnav_hinf_filter_init`] not yet ended.
#[no_mangle]
pub unsafe extern "C" fn relnav_hinf_filter_deinit(
    filter: *mut relnav_hinf_filter,
) -> relnav_status {
    // SAFETY: the caller's contract, passed on.
    unsafe { drop_placed(filter) };
    relnav_status::RELNAV_OK
}

/// One filter step: `x_f <- A_F x_f + B_F y + E_F a`. `y` is the canonical position
/// measurement [m] (3 doubles, or null: replaced by its prediction), `accel` the known
/// acceleration [m/s^2] (3 doubles). Non-finite inputs are refused before anything changes.
///
/// # Safety
/// `filter` is a live handle or null; `y` is null or 3 readable doubles; `accel` is null or
/// 3 readable doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_hinf_filter_step(
    filter: *mut relnav_hinf_filter,
    y: *const f64,
    accel: *const f64,
) -> relnav_status {
    const F: &str = "relnav_hinf_filter_step";
    boundary(F, || {
        // SAFETY: non-null handles come from Box::into_raw in relnav_hinf_filter_new.
        let h = unsafe { filter.as_mut() }.ok_or_else(|| null("filter", F))?;
        // SAFETY: as above.
        let a = unsafe { read_array::<3>(accel, "accel", F) }?;
        let yv = if y.is_null() {
            None
        } else {
            // SAFETY: as above.
            Some(unsafe { read_array::<3>(y, "y", F) }?)
        };
        if !a.iter().chain(yv.iter().flatten()).all(|v| v.is_finite()) {
            return Err(Failure(
                relnav_status::RELNAV_ERROR_INVALID_ARGUMENT,
                relnav_core::msg!("{F}: y and accel must be finite"),
            ));
        }
        let yv = yv.map(relnav_core::types::Vec3::from);
        h.f.step(yv.as_ref(), &relnav_core::types::Vec3::from(a));
        Ok(())
    })
}

/// Copy the estimate `C_F x_f` (6 doubles, canonical frame) to `out`.
///
/// # Safety
/// `filter` is a live handle or null; `out` is null or 6 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn relnav_hinf_filter_get_state(
    filter: *const relnav_hinf_filter,
    out: *mut f64,
) -> relnav_status {
    const F: &str = "relnav_hinf_filter_get_state";
    boundary(F, || {
        // SAFETY: non-null handles come from Box::into_raw in relnav_hinf_filter_new.
        let h = unsafe { filter.as_ref() }.ok_or_else(|| null("filter", F))?;
        let x: [f64; 6] = (*h.f.state()).into();
        // SAFETY: as above.
        unsafe { write_array(out, &x, "out", F) }
    })
}

/// Release a runtime filter (null is accepted). Cannot fail, so returns nothing.
///
/// Flight library: does nothing (no handle comes from [`relnav_hinf_filter_new`] there).
///
/// # Safety
/// `filter` is null or a handle from `relnav_hinf_filter_new` not yet freed.
#[no_mangle]
pub unsafe extern "C" fn relnav_hinf_filter_free(filter: *mut relnav_hinf_filter) {
    // without std no handle comes from relnav_hinf_filter_new
    #[cfg(not(feature = "std"))]
    let _ = filter;
    #[cfg(feature = "std")]
    if !filter.is_null() {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: the handle came from Box::into_raw and is freed once.
            drop(unsafe { Box::from_raw(filter) });
        }));
    }
}

/// Which computation designed an H-infinity filter (`relnav_hinf_design_info`).
#[repr(i32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum relnav_hinf_route {
    /// Not an H-infinity estimator (filter code other than 9).
    RELNAV_HINF_ROUTE_NONE = 0,
    /// Bisection on the H-infinity filtering Riccati equation, certified on the observer
    /// LMI (the gamma-optimal observer; no interior-point solver).
    RELNAV_HINF_ROUTE_RICCATI = 1,
    /// The SDP (Clarabel) with the filter matrices eliminated: the mixed design, and the
    /// gamma-optimal observer's fallback when the Riccati route fails.
    RELNAV_HINF_ROUTE_SDP = 2,
    /// The SDP posed literally (not used by filter 9).
    RELNAV_HINF_ROUTE_SDP_LITERAL = 3,
}

/// Why the gamma-optimal observer's Riccati route was not taken
/// (`relnav_hinf_design_info::riccati_failure`).
#[repr(i32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum relnav_hinf_riccati_failure {
    /// The route was taken (or the estimator is not an H-infinity filter).
    RELNAV_HINF_RICCATI_OK = 0,
    /// `D D^T` is singular (a noise-free measurement axis): the Riccati equation needs its
    /// inverse.
    RELNAV_HINF_RICCATI_SINGULAR_MEASUREMENT_NOISE = 1,
    /// The Kalman Riccati equation has no stabilising solution (no lower end for the
    /// bisection).
    RELNAV_HINF_RICCATI_NO_KALMAN_SOLUTION = 2,
    /// No gamma in the bisection's bracket admits a stabilising solution.
    RELNAV_HINF_RICCATI_NO_FEASIBLE_GAMMA = 3,
    /// The constructed observer failed the literal LMI check.
    RELNAV_HINF_RICCATI_CERTIFICATION_FAILED = 4,
}

/// How the H-infinity filter of an estimator (filter code 9) was designed
/// (`relnav_estimator_get_hinf_design`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct relnav_hinf_design_info {
    /// A `relnav_hinf_route` code: the route that designed the filter that runs
    /// (`RELNAV_HINF_ROUTE_NONE` for the other filters).
    pub route: i32,
    /// A `relnav_hinf_route` code: the route of the gamma-optimal observer (for the mixed
    /// design, its first stage; the same as `route` for the gamma-optimal design).
    pub observer_route: i32,
    /// A `relnav_hinf_riccati_failure` code for the gamma-optimal observer's Riccati route.
    pub riccati_failure: i32,
    /// Trials of the Riccati bisection (0 when the route was not taken).
    pub riccati_steps: i32,
    /// Interior-point (Clarabel) iterations, both stages of the mixed design together.
    pub iterations: i32,
    /// Wall time of the design [s] (NaN for the other filters).
    pub solve_time: f64,
}

impl relnav_hinf_design_info {
    /// The record of a filter that is not an H-infinity filter.
    pub(super) const NONE: Self = Self {
        route: relnav_hinf_route::RELNAV_HINF_ROUTE_NONE as i32,
        observer_route: relnav_hinf_route::RELNAV_HINF_ROUTE_NONE as i32,
        riccati_failure: relnav_hinf_riccati_failure::RELNAV_HINF_RICCATI_OK as i32,
        riccati_steps: 0,
        iterations: 0,
        solve_time: f64::NAN,
    };

    /// The C record of a design record.
    pub(super) fn of(info: &relnav_core::hinf::HinfDesignInfo) -> Self {
        use relnav_core::hinf::DesignRoute;
        let route = |r: DesignRoute| match r {
            DesignRoute::Riccati => relnav_hinf_route::RELNAV_HINF_ROUTE_RICCATI,
            DesignRoute::Sdp => relnav_hinf_route::RELNAV_HINF_ROUTE_SDP,
            DesignRoute::SdpLiteral => relnav_hinf_route::RELNAV_HINF_ROUTE_SDP_LITERAL,
        } as i32;
        let failure = info.riccati_failure.map_or(0, failure_code);
        Self {
            route: route(info.route),
            observer_route: route(info.observer_route),
            riccati_failure: failure,
            riccati_steps: i32::try_from(info.riccati_steps).unwrap_or(i32::MAX),
            iterations: i32::try_from(info.iterations).unwrap_or(i32::MAX),
            solve_time: info.solve_time,
        }
    }
}

/// The Riccati route's failures in the order of their `relnav_hinf_riccati_failure` codes
/// (code = position + 1).
const RICCATI_FAILURES: [relnav_core::hinf::riccati::RiccatiFailure; 4] = {
    use relnav_core::hinf::riccati::RiccatiFailure as R;
    [
        R::SingularMeasurementNoise,
        R::NoKalmanSolution,
        R::NoFeasibleGamma,
        R::CertificationFailed,
    ]
};
const _: () = assert!(
    relnav_hinf_riccati_failure::RELNAV_HINF_RICCATI_CERTIFICATION_FAILED as usize
        == RICCATI_FAILURES.len()
);

/// The `relnav_hinf_riccati_failure` code of a failure.
fn failure_code(f: relnav_core::hinf::riccati::RiccatiFailure) -> i32 {
    RICCATI_FAILURES
        .iter()
        .position(|&x| x == f)
        .map_or(0, |i| i32::try_from(i + 1).unwrap_or(0))
}

/// A static, readable reason for a `relnav_hinf_riccati_failure` code (why the
/// gamma-optimal observer's Riccati route fell back to the SDP): the text of
/// `relnav::hinf::riccati::RiccatiFailure`; `"none"` for `RELNAV_HINF_RICCATI_OK`,
/// `"unknown Riccati failure code"` for other codes. Cannot fail, so returns the text
/// itself.
#[no_mangle]
pub extern "C" fn relnav_hinf_riccati_failure_string(code: i32) -> *const core::ffi::c_char {
    #[cfg(not(feature = "std"))]
    return match code {
        0 => c"none",
        1..=4 => c"a Riccati failure (its text is not in this build: the flight library)",
        _ => c"unknown Riccati failure code",
    }
    .as_ptr();
    #[cfg(feature = "std")]
    riccati_failure_text(code)
}

#[cfg(feature = "std")]
fn riccati_failure_text(code: i32) -> *const core::ffi::c_char {
    use std::ffi::CString;
    use std::sync::OnceLock;
    static TEXT: OnceLock<Vec<CString>> = OnceLock::new();
    let unknown = c"unknown Riccati failure code".as_ptr();
    if code == relnav_hinf_riccati_failure::RELNAV_HINF_RICCATI_OK as i32 {
        return c"none".as_ptr();
    }
    catch_unwind(|| {
        let text = TEXT.get_or_init(|| {
            RICCATI_FAILURES
                .iter()
                .map(|f| CString::new(f.to_string()).unwrap_or_default())
                .collect()
        });
        usize::try_from(code)
            .ok()
            .and_then(|c| c.checked_sub(1))
            .and_then(|i| text.get(i))
            .map_or(unknown, |t| t.as_ptr())
    })
    .unwrap_or(unknown)
}
