//! Runs `steps` Kalman filter steps (update + predict, the `ekf_step` / `ukf_step` of
//! `benches/filters.rs`: paper 000's model and seeded measurements) and prints the final
//! estimate's bits: the workload for `valgrind --tool=callgrind` instruction counts per step
//! (`(I(n2) - I(n1)) / (n2 - n1)` cancels the setup) and a check that a change left the
//! arithmetic bit for bit as it was (or by how much it moved).
//! `none` generates the measurements only (their count is subtracted from the filters').
//! `nav-ekf` / `capi-ekf` / `fmu-ekf` (and `-ukf`) run the same steps through the
//! navigator (`ecc-ekf`: the navigator on the elliptic model, e = 0.1), the C ABI (`relnav_estimator_step`) and one FMU master cycle (`fmi2SetReal` of
//! the three measurements, `fmi2DoStep`, `fmi2GetReal` of the 12 estimate outputs: the
//! `fmu_cycle_*` criterion bench; `fmu3-ekf` / `fmu3-ukf` the same cycle through the FMI 3.0
//! functions, arrays in and out: `fmu3_cycle_*`); their counts less the bare filter's are
//! the layers' overheads.
//! `sensor-<s>-ekf` (and `-ukf`, `-hinf`: the H-infinity filter designed for all four sensors,
//! `-hinffixed` the same without track initiation;
//! `s` = `radio`, `camera`, `gnss`, `velocity` or `none`)
//! run navigator steps (`Navigator::step_readings`) with that one sensor's reading at every
//! step, all four readings generated in every mode: less `sensor-none-*` (the prediction
//! alone), the count per step is that sensor's update (`benches/summarize.py` prints its
//! ratio to the radio's).
//! `time-ekf` / `time-ukf` (second argument: the number of batches) are the wall-clock
//! companion: the bare step, the navigator's step and the FMU cycle, 600 steps each, timed
//! **interleaved** batch by batch so that a busy machine slows all three alike; the minimum,
//! 10th percentile and median ns per step of each and the cycle's overhead over the bare step,
//! also paired: the median over the batches of each batch's cycle less the bare step timed
//! just before it, which a host whose speed drifts between two criterion benches minutes
//! apart does not bias (the minimum of many short batches is the uncontended figure on a
//! shared machine). `time-json` prints both filters' figures as one JSON line
//! (benches/instructions.py, for scripts/bench.sh's summary).
//! `cargo run --release --example kalman_profile -- ekf 600`,
//! `cargo run --release --example kalman_profile -- time-ukf 300`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use rand::SeedableRng;
use relnav as ffi;
use relnav_core::dynamics::{CwModel, Discretization};
use relnav_core::estimators::{Ekf, Estimator, Ukf, UkfParams};
use relnav_core::nav::{FilterKind, NavConfig, Navigator};
use relnav_core::sensors::RadioSensor;
use relnav_core::types::{Mat3, Mat6, State, Vec3};
use relnav_fmi::fmi2::types::*;
use relnav_nav_model::vr;
use std::hint::black_box;
use std::time::Instant;

// relnav.fmu's fmi2* functions in this binary, as the FMU's shared library exports them
relnav_fmi::export_fmi2!(relnav_nav_model::RelnavFmu);
// and its fmi3* functions (relnav3.fmu: the same library)
relnav_fmi::export_fmi3!(relnav_nav_model::RelnavFmu);

/// relnav.fmu's GUID.
fn guid() -> &'static str {
    relnav_fmi::fmi2::description::guid_of(&relnav_nav_model::INFO)
}

fn run<E: Estimator>(f: Option<E>, steps: usize) -> (State, Mat6) {
    let zs = measurement_vecs(steps);
    let (d, sensor) = paper000();
    let accel = Vec3::zeros();
    let Some(mut f) = f else {
        // the measurements alone: subtracted from the filters' counts
        return (black_box(State::zeros()), d.q);
    };
    for z in &zs {
        f.update(&sensor, black_box(z)).unwrap();
        f.predict(&d, black_box(&accel)).unwrap();
    }
    (*f.state(), *f.covariance())
}

/// Paper 000's discrete model over 1 s (the default process noise) and radio sensor.
fn paper000() -> (relnav_core::dynamics::DiscreteModel, RadioSensor) {
    let cfg = NavConfig::default();
    let fr = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let sensor = RadioSensor::new(fr, cfg.sigma_range, cfg.sigma_angle);
    let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    d.q += fr.cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&[
        cfg.q_pos[0],
        cfg.q_pos[1],
        cfg.q_pos[2],
        cfg.q_vel[0],
        cfg.q_vel[1],
        cfg.q_vel[2],
    ])));
    (d, sensor)
}

/// Paper 000's seeded measurements along the truth (frame 2, 1 s apart).
fn measurement_vecs(steps: usize) -> Vec<Vec3> {
    let cfg = NavConfig::default();
    let fr = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let sensor = RadioSensor::new(fr, cfg.sigma_range, cfg.sigma_angle);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let x0 = fr.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    (0..steps)
        .map(|k| {
            let x = model.phi(k as f64) * x0;
            sensor
                .measure(&x.fixed_rows::<3>(0).into_owned(), &mut rng)
                .unwrap()
        })
        .collect()
}

/// The same measurements as `[range, azimuth, elevation]` rows (the C ABI's and the FMU's
/// inputs).
fn measurements(steps: usize) -> Vec<[f64; 3]> {
    measurement_vecs(steps)
        .iter()
        .map(|z| [z.x, z.y, z.z])
        .collect()
}

/// `steps` navigator steps (measurement, no thrust, 1 s); the estimate in the user frame.
fn run_nav(kind: FilterKind, steps: usize, eccentricity: f64) -> Vec<f64> {
    let zs = measurements(steps);
    let cfg = NavConfig {
        filter: kind,
        eccentricity,
        ..Default::default()
    };
    let mut nav = Navigator::new(&cfg).unwrap();
    for z in &zs {
        nav.step(&[0.0; 3], Some(std::hint::black_box(z)), 1.0)
            .unwrap();
    }
    let x: [f64; 6] = nav.state().into();
    x.iter().chain(nav.sigma().iter()).copied().collect()
}

/// `steps` C ABI steps; the state and sigma (`relnav_estimator_get_state`, `_get_sigma`).
fn run_capi(kind: FilterKind, steps: usize) -> Vec<f64> {
    let zs = measurements(steps);
    let mut c_cfg = ffi::relnav_config_default();
    c_cfg.filter = kind as i32;
    let mut est = std::ptr::null_mut();
    let thrust = [0.0; 3];
    let mut out = [0.0; 12];
    // SAFETY: valid pointers, documented array lengths; the handle is freed once.
    unsafe {
        assert_eq!(
            ffi::relnav_estimator_new(&c_cfg, &mut est),
            ffi::relnav_status::RELNAV_OK
        );
        for z in &zs {
            ffi::relnav_estimator_step(est, thrust.as_ptr(), std::hint::black_box(z.as_ptr()), 1.0);
        }
        ffi::relnav_estimator_get_state(est, out.as_mut_ptr());
        ffi::relnav_estimator_get_sigma(est, out[6..].as_mut_ptr());
        ffi::relnav_estimator_free(est);
    }
    out.to_vec()
}

/// A Co-Simulation instance of the relnav FMU running `kind`, initialised, with the
/// measurement valid (the `fmu_cycle_*` bench's set-up); free it with `fmi2FreeInstance`.
fn fmu_instance(kind: FilterKind) -> fmi2Component {
    let g = std::ffi::CString::new(guid()).unwrap();
    let cb = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    // SAFETY: valid arguments (the callbacks are copied by the instance).
    let comp = unsafe {
        fmi2Instantiate(
            c"profile".as_ptr(),
            fmi2CoSimulation,
            g.as_ptr(),
            std::ptr::null(),
            &cb,
            0,
            0,
        )
    };
    assert!(!comp.is_null());
    fmu_initialise(comp, kind);
    comp
}

/// Set the filter, initialise, and mark the measurement valid (after instantiation or
/// `fmi2Reset`).
fn fmu_initialise(comp: fmi2Component, kind: FilterKind) {
    // SAFETY: a live instance, one value each.
    unsafe {
        fmi2SetInteger(comp, &vr::FILTER, 1, &(kind as i32));
        fmi2SetupExperiment(comp, 0, 0.0, 0.0, 0, 0.0);
        fmi2EnterInitializationMode(comp);
        fmi2ExitInitializationMode(comp);
        fmi2SetBoolean(comp, &vr::MEASUREMENT_VALID, 1, &1);
    }
}

/// One FMU master cycle per measurement (set 3 inputs, doStep, get 12 outputs); the last
/// outputs.
fn fmu_cycles(comp: fmi2Component, zs: &[[f64; 3]]) -> [f64; 12] {
    let ins = [vr::RANGE, vr::AZIMUTH, vr::ELEVATION];
    let outs: [u32; 12] = std::array::from_fn(|i| vr::X + i as u32);
    let mut y = [0.0; 12];
    for (k, z) in zs.iter().enumerate() {
        // SAFETY: a live instance, matching lengths.
        unsafe {
            fmi2SetReal(comp, ins.as_ptr(), 3, black_box(z.as_ptr()));
            let st = fmi2DoStep(comp, k as f64, 1.0, 1);
            assert_eq!(st, fmi2Status::fmi2OK);
            fmi2GetReal(comp, outs.as_ptr(), 12, y.as_mut_ptr());
        }
        black_box(&y);
    }
    y
}

/// `steps` FMU master cycles; the last outputs.
fn run_fmu(kind: FilterKind, steps: usize) -> Vec<f64> {
    // instantiated before the measurements are drawn: the one-time work (the description,
    // the GUID) then meets the same heap whatever `steps` is, and cancels in the difference
    // of two runs
    let comp = fmu_instance(kind);
    let zs = measurements(steps);
    let y = fmu_cycles(comp, &zs);
    // SAFETY: freed once.
    unsafe { fmi2FreeInstance(comp) };
    y.to_vec()
}

/// `steps` FMI 3.0 master cycles (`fmi3SetFloat64` of the `measurement` array,
/// `fmi3DoStep`, `fmi3GetFloat64` of `position`, `velocity` and `sigma`: the same 12
/// values); the last outputs.
fn run_fmu3(kind: FilterKind, steps: usize) -> Vec<f64> {
    use relnav_fmi::fmi3::description::vr_of;
    let info = &*relnav_nav_model::INFO;
    // instantiated first, as in `run_fmu`
    let comp =
        relnav_fmi::fmi3::functions::instantiate_plain::<relnav_nav_model::RelnavFmu>(c"profile");
    assert!(!comp.is_null());
    let zs = measurements(steps);
    let meas = [vr_of(info, "measurement").unwrap()];
    let outs = ["position", "velocity", "sigma"].map(|n| vr_of(info, n).unwrap());
    let mut y = [0.0; 12];
    let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
    // SAFETY: a live instance, matching lengths.
    unsafe {
        fmi3SetInt32(comp, &vr::FILTER, 1, &(kind as i32), 1);
        fmi3EnterInitializationMode(comp, false, 0.0, 0.0, false, 0.0);
        fmi3ExitInitializationMode(comp);
        fmi3SetBoolean(comp, &vr::MEASUREMENT_VALID, 1, &true, 1);
        for (k, z) in zs.iter().enumerate() {
            fmi3SetFloat64(comp, meas.as_ptr(), 1, black_box(z.as_ptr()), 3);
            let st = fmi3DoStep(
                comp,
                k as f64,
                1.0,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            );
            assert_eq!(st, relnav_fmi::fmi3::types::fmi3Status::fmi3OK);
            fmi3GetFloat64(comp, outs.as_ptr(), 3, y.as_mut_ptr(), 12);
            black_box(&y);
        }
        fmi3FreeInstance(comp);
    }
    y.to_vec()
}

/// Wall-clock figures of one filter from [`time_layers`], ns per step.
struct Timing {
    /// Minimum, 10th percentile and median of the bare step, the navigator's and the FMU cycle.
    layers: [[f64; 3]; 3],
    /// Median and minimum over the batches of the FMU cycle less the bare step of the same
    /// batch (paired: the two run back to back, so a slow phase of the host slows both).
    paired: [f64; 2],
}

/// `time-*`: the bare step, the navigator's and the FMU cycle timed interleaved, `batches`
/// batches of 600 steps each (see the module docs).
fn time_layers<E: Estimator>(kind: FilterKind, make: impl Fn() -> E, batches: usize) -> Timing {
    const STEPS: usize = 600;
    let (zs, zv) = (measurements(STEPS), measurement_vecs(STEPS));
    let (d, sensor) = paper000();
    let accel = Vec3::zeros();
    let mut nav = Navigator::new(&NavConfig {
        filter: kind,
        ..Default::default()
    })
    .unwrap();
    let comp = fmu_instance(kind);
    let per_step = |f: &mut dyn FnMut()| {
        let s = Instant::now();
        f();
        s.elapsed().as_nanos() as f64 / STEPS as f64
    };
    let mut t = [Vec::new(), Vec::new(), Vec::new()];
    for _ in 0..batches.max(1) {
        let mut f = make();
        t[0].push(per_step(&mut || {
            for z in &zv {
                f.update(&sensor, black_box(z)).unwrap();
                f.predict(&d, black_box(&accel)).unwrap();
            }
        }));
        nav.reset();
        t[1].push(per_step(&mut || {
            for z in &zs {
                nav.step(&[0.0; 3], Some(black_box(z)), 1.0).unwrap();
            }
        }));
        // SAFETY: a live instance.
        unsafe { fmi2Reset(comp) };
        fmu_initialise(comp, kind);
        t[2].push(per_step(&mut || {
            fmu_cycles(comp, &zs);
        }));
    }
    // SAFETY: freed once.
    unsafe { fmi2FreeInstance(comp) };
    let mut diff: Vec<f64> = t[2].iter().zip(&t[0]).map(|(c, b)| c - b).collect();
    diff.sort_by(f64::total_cmp);
    for v in t.iter_mut() {
        v.sort_by(f64::total_cmp);
    }
    let q = |v: &[f64], p: f64| v[((v.len() - 1) as f64 * p) as usize];
    Timing {
        layers: [0, 1, 2].map(|i| [q(&t[i], 0.0), q(&t[i], 0.1), q(&t[i], 0.5)]),
        paired: [q(&diff, 0.5), q(&diff, 0.0)],
    }
}

/// Print [`time_layers`]' figures as a table.
fn print_timing(kind: FilterKind, t: &Timing) {
    let k = kind.name();
    for (name, [min, p10, med]) in [
        format!("{k}_step"),
        format!("navigator_step_{k}"),
        format!("fmu_cycle_{k}"),
    ]
    .iter()
    .zip(&t.layers)
    {
        println!("{name:20} min {min:7.1}  p10 {p10:7.1}  median {med:7.1} ns");
    }
    println!(
        "{:20} min {:7.1}  p10 {:7.1} ns (of the minima / 10th percentiles)",
        "fmu - bare",
        t.layers[2][0] - t.layers[0][0],
        t.layers[2][1] - t.layers[0][1]
    );
    println!(
        "{:20} median {:7.1}  min {:7.1} ns (paired: batch by batch)",
        "fmu - bare", t.paired[0], t.paired[1]
    );
}

/// `steps` navigator steps with one sensor's reading per step (see the module docs); the
/// estimate and sigma in the user frame.
fn run_sensor(sensor: &str, kind: FilterKind, acquisition: bool, steps: usize) -> Option<Vec<f64>> {
    use relnav_core::nav::Readings;
    let cfg = NavConfig {
        filter: kind,
        // the H-infinity filter's design for all four sensors: each reading alone is a
        // subset of its measurement set
        hinf_sensors: 15,
        hinf_acquisition: acquisition,
        ..Default::default()
    };
    let fr = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let x0 = fr.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    let zs = measurement_vecs(steps);
    let mut nav = Navigator::new(&cfg).unwrap();
    for (k, z) in zs.iter().enumerate() {
        let x = fr.state_from_canonical(&(model.phi(k as f64) * x0));
        // the radio's noisy angles for the camera; GNSS a few sigma off the truth
        let (radio, camera) = ([z.x, z.y, z.z], [z.y, z.z]);
        let pos = [x[0] + 0.01, x[1] - 0.02, x[2] + 0.03];
        let vel = [x[3] + 1e-4, x[4], x[5] - 1e-4];
        let r = match sensor {
            "radio" => Readings {
                radio: Some(radio),
                ..Default::default()
            },
            "camera" => Readings {
                camera: Some(camera),
                ..Default::default()
            },
            "gnss" => Readings {
                gnss_position: Some(pos),
                ..Default::default()
            },
            "velocity" => Readings {
                gnss_velocity: Some(vel),
                ..Default::default()
            },
            "none" => Readings::default(),
            _ => return None,
        };
        nav.step_readings(&[0.0; 3], black_box(&r), 1.0).unwrap();
    }
    let x: [f64; 6] = nav.state().into();
    Some(x.iter().chain(nav.sigma().iter()).copied().collect())
}

fn layered(which: &str, steps: usize) -> Option<Vec<f64>> {
    if let Some(rest) = which.strip_prefix("sensor-") {
        let (sensor, f) = rest.rsplit_once('-')?;
        let (kind, acquisition) = match f {
            "ekf" => (FilterKind::Ekf, true),
            "ukf" => (FilterKind::Ukf, true),
            "hinf" => (FilterKind::Hinf, true),
            "hinffixed" => (FilterKind::Hinf, false),
            _ => return None,
        };
        return run_sensor(sensor, kind, acquisition, steps);
    }
    let (layer, f) = which.split_once('-')?;
    let kind = match f {
        "ekf" => FilterKind::Ekf,
        "ukf" => FilterKind::Ukf,
        _ => return None,
    };
    match layer {
        "nav" => Some(run_nav(kind, steps, 0.0)),
        // the same on the elliptic model (e = 0.1): a Kepler solve, the transition and the
        // quadrature of the input matrix and the noise at every step
        "ecc" => Some(run_nav(kind, steps, 0.1)),
        "capi" => Some(run_capi(kind, steps)),
        "fmu" => Some(run_fmu(kind, steps)),
        "fmu3" => Some(run_fmu3(kind, steps)),
        _ => None,
    }
}

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "ekf".to_string());
    let steps: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let cfg = NavConfig::default();
    let (x0, p0) = (cfg.initial_state(), cfg.initial_covariance());
    let make_ukf = || Ukf::new(x0, p0, UkfParams::default());
    match which.as_str() {
        "time-ekf" => {
            let t = time_layers(FilterKind::Ekf, || Ekf::new(x0, p0), steps);
            return print_timing(FilterKind::Ekf, &t);
        }
        "time-ukf" => {
            let t = time_layers(FilterKind::Ukf, make_ukf, steps);
            return print_timing(FilterKind::Ukf, &t);
        }
        "time-json" => {
            // both filters, for benches/instructions.py: one JSON line
            let e = time_layers(FilterKind::Ekf, || Ekf::new(x0, p0), steps);
            let u = time_layers(FilterKind::Ukf, make_ukf, steps);
            let one = |k: &str, t: &Timing| {
                format!(
                    "\"{k}\": {{\"step_min\": {:.1}, \"step_median\": {:.1}, \"fmu_min\": {:.1}, \
                     \"fmu_median\": {:.1}, \"overhead_paired_median\": {:.1}, \
                     \"overhead_paired_min\": {:.1}, \"batches\": {}}}",
                    t.layers[0][0],
                    t.layers[0][2],
                    t.layers[2][0],
                    t.layers[2][2],
                    t.paired[0],
                    t.paired[1],
                    steps.max(1)
                )
            };
            println!("{{{}, {}}}", one("ekf", &e), one("ukf", &u));
            return;
        }
        _ => {}
    }
    if let Some(y) = layered(&which, steps) {
        let h = y.iter().fold(0u64, |h, v| h.rotate_left(7) ^ v.to_bits());
        println!("{which} {steps} steps: outputs {y:?} bits-hash {h:016x}");
        return;
    }
    let (x, p) = match which.as_str() {
        "ekf" => run(Some(Ekf::new(x0, p0)), steps),
        "ukf" => run(Some(Ukf::new(x0, p0, UkfParams::default())), steps),
        "none" => run(None::<Ekf>, steps),
        other => panic!("unknown filter {other}"),
    };
    let h = x
        .iter()
        .chain(p.iter())
        .fold(0u64, |h, v| h.rotate_left(7) ^ v.to_bits());
    println!(
        "{which} {steps} steps: x {:?} P00 {:e} P55 {:e} bits-hash {h:016x}",
        x.as_slice(),
        p[(0, 0)],
        p[(5, 5)]
    );
}
