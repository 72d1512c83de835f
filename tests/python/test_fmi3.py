"""relnav3.fmu, the FMI 3.0 Co-Simulation FMU beside relnav.fmu: fmpy validates it, its
description publishes every FMI 2.0 parameter and the vectors as arrays, its outputs equal
relnav.fmu's bit for bit, and it refuses what it does not offer with a logged reason."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools"))

import cwtruth as cw  # noqa: E402
import relnav_fmu as rf  # noqa: E402
import relnav_fmu3 as rf3  # noqa: E402

ARRAYS = {
    "thrust": 3,
    "measurement": 3,
    "camera": 2,
    "gnss_position": 3,
    "gnss_velocity": 3,
    "position": 3,
    "velocity": 3,
    "sigma": 6,
}


@pytest.fixture(scope="module")
def runner3(unzip3):
    r = rf3.Slave3Runner(unzip3)
    yield r
    r.close()


@pytest.mark.parametrize("ident", ["relnav3", "relnav_plant3", "relnav_guidance3"])
def test_fmpy_validates_the_fmi3_fmus(fmu3_path, ident):
    path = fmu3_path.parent / f"{ident}.fmu"
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    assert md.fmiVersion == "3.0" and md.coSimulation is not None
    # relnav applies measurements in Event Mode; the plant and the guidance law have none
    assert md.coSimulation.hasEventMode == (ident == "relnav3")


def test_kit_arrays_are_the_tool_s(fmu3_path):
    # tools/relnav_system.py's independent list of which scalars each array holds: the
    # FMUs publish exactly those arrays, of those lengths, and hide those scalars
    import relnav_system as rs

    for ident, arrays in rs.FMI3_ARRAYS.items():
        v3 = {v.name: v for v in read_model_description(str(fmu3_path.parent / f"{ident}3.fmu")).modelVariables}
        v2 = {v.name for v in read_model_description(str(fmu3_path.parent / f"{ident}.fmu")).modelVariables}
        published = {name for name, v in v3.items() if v.dimensions and name != "covariance"}
        assert published == set(arrays), ident
        for name, elements in arrays.items():
            assert [int(d.start) for d in v3[name].dimensions] == [len(elements)], (ident, name)
            assert set(elements) <= v2 and not set(elements) & set(v3), (ident, name)


def test_every_fmi3_function_is_exported(unzip3):
    # fmpy declares a wrapper for every function of the standard's fmi3FunctionTypes.h
    import inspect

    from fmpy.fmi3 import FMU3Model, FMU3ScheduledExecution, FMU3Slave

    standard = {
        name
        for cls in (FMU3Model, FMU3Slave, FMU3ScheduledExecution)
        for name, _ in inspect.getmembers(cls, inspect.isfunction)
        if name.startswith("fmi3")
    }
    assert len(standard) >= 70
    so = unzip3 / "binaries" / "x86_64-linux" / "relnav.so"
    out = subprocess.run(["nm", "-D", "--defined-only", str(so)], check=True, capture_output=True, text=True).stdout
    exported = {line.split()[-1] for line in out.splitlines() if line.strip()}
    assert sorted(standard - exported) == []
    # the FMI 2.0 functions and the C ABI are in the same binary
    assert {"fmi2DoStep", "relnav_estimator_step"} <= exported


def test_description_keeps_every_fmi2_variable(fmu_path, fmu3_path):
    md2 = read_model_description(str(fmu_path))
    md3 = read_model_description(str(fmu3_path))
    assert md3.fmiVersion == "3.0"
    v3 = {v.name: v for v in md3.modelVariables}
    elements = set()
    for name, n in ARRAYS.items():
        a = v3[name]
        assert [int(d.start) for d in a.dimensions] == [n], name
        # FMI 3.0 value references of arrays sit above every scalar's
        assert a.valueReference >= 10_000
    for name in ("thrust", "measurement", "position", "velocity", "sigma"):
        elements |= {None}
    fmi2_arrays = {
        "thrust": ["thrust_x", "thrust_y", "thrust_z"],
        "measurement": ["range", "azimuth", "elevation"],
        "camera": ["camera_azimuth", "camera_elevation"],
        "gnss_position": ["gnss_x", "gnss_y", "gnss_z"],
        "gnss_velocity": ["gnss_vx", "gnss_vy", "gnss_vz"],
        "position": ["x", "y", "z"],
        "velocity": ["vx", "vy", "vz"],
        "sigma": ["sigma_x", "sigma_y", "sigma_z", "sigma_vx", "sigma_vy", "sigma_vz"],
    }
    elements = {e for es in fmi2_arrays.values() for e in es}
    types = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean"}
    for v in md2.modelVariables:
        if v.name in elements:
            assert v.name not in v3, v.name
            continue
        w = v3[v.name]
        assert (w.valueReference, w.causality, w.variability) == (v.valueReference, v.causality, v.variability), v.name
        assert w.type == types[v.type], v.name
        assert (w.unit, w.description) == (v.unit, v.description), v.name
        if v.causality != "output":
            assert str(w.start) == str(v.start), v.name
    # an array has its elements' causality and, where they agree, their unit
    for name, es in fmi2_arrays.items():
        src = [next(v for v in md2.modelVariables if v.name == e) for e in es]
        assert v3[name].causality == src[0].causality
        units = {s.unit for s in src}
        assert v3[name].unit == (units.pop() if len(units) == 1 else None), name
    assert v3["time"].causality == "independent"


@pytest.mark.parametrize("filter_code", range(1, 12))
def test_outputs_equal_relnav_fmu_bit_for_bit(runner, runner3, filter_code):
    sc = cw.paper000_scenario(frame=2, times=np.arange(0.0, 61.0))
    params = {**sc.params, "filter": filter_code}
    if filter_code == 9:
        params["hinf_period"] = 1.0
    if 4 <= filter_code <= 8:
        params["particles"] = 200
    z = sc.measurements(3)
    out2 = runner.run(params, sc.times, sc.thrust, z, sc.valid)
    out3 = runner3.run(params, sc.times, sc.thrust, z, sc.valid)
    # (the H-infinity filter publishes no covariance: its sigmas are NaN in both)
    assert np.isfinite(out3[:, :6]).all()
    assert np.array_equal(out2.view(np.uint64), out3.view(np.uint64))


def test_state_round_trip_continues_bit_for_bit(runner3):
    sc = cw.paper000_scenario(frame=2, times=np.arange(0.0, 41.0))
    z = sc.measurements(1)
    r = runner3
    r.instantiate()
    try:
        r.initialize({**sc.params, "filter": "ukf"})
        r.simulate(sc.times[:21], sc.thrust[:20], z[:20], sc.valid[:20])
        state = r.fmu.getFMUState()
        blob = r.fmu.serializeFMUState(state)
        first = r.simulate(sc.times[20:], sc.thrust[20:], z[20:], sc.valid[20:])
        restored = r.fmu.deserializeFMUState(blob)
        r.fmu.setFMUState(restored)
        again = r.simulate(sc.times[20:], sc.thrust[20:], z[20:], sc.valid[20:])
        r.fmu.freeFMUState(state)
        r.fmu.freeFMUState(restored)
    finally:
        r.free_instance()
    assert np.array_equal(first.view(np.uint64), again.view(np.uint64))


def test_refusals_are_logged(runner3):
    r = runner3
    r.log.records.clear()
    r.instantiate()
    try:
        from fmpy.fmi3 import fmi3ValueReference, fmi3Float64

        # a step before initialisation, an unknown value reference, a short value array
        with pytest.raises(Exception):
            r.fmu.doStep(0.0, 1.0)
        r.fmu.reset()
        r.initialize({"filter": "ekf"})
        with pytest.raises(Exception):
            r.fmu.getFloat64([12345])
        r.fmu.reset()
        r.initialize({"filter": "ekf"})
        vrs = (fmi3ValueReference * 1)(r.vr["position"])
        vals = (fmi3Float64 * 2)()
        with pytest.raises(Exception, match="status 3"):
            r.fmu.fmi3GetFloat64(r.fmu.component, vrs, 1, vals, 2)
        r.fmu.reset()
        r.initialize({"filter": "ekf"})
        # Event Mode only for an instance made with eventModeUsed
        with pytest.raises(Exception):
            r.fmu.enterEventMode()
        text = r.log.text()
        assert "illegal call sequence" in text
        assert "unknown value reference 12345" in text
        assert "the 1 value references hold 3 values" in text
        assert "fmi3EnterEventMode: the instance was made with eventModeUsed = false" in text
        # the time is readable
        r.fmu.reset()
        r.initialize({"filter": "ekf"}, start_time=5.0)
        assert r.fmu.getFloat64([9999]) == [5.0]
    finally:
        r.free_instance()


@pytest.mark.parametrize("filter_name", ["ekf", "ukf", "aqukf", "pf", "imm", "rekf", "hinf"])
def test_covariance_is_symmetric_positive_definite_with_sigma_squared_diagonal(runner3, filter_name):
    sc = cw.paper000_scenario(frame=3, times=np.arange(0.0, 31.0))
    z = sc.measurements(2)
    params = {**sc.params, "filter": filter_name}
    if filter_name == "hinf":
        params["hinf_period"] = 1.0
    if filter_name == "pf":
        params["particles"] = 300
    r = runner3
    cov_vr, sigma_vr = r.vr["covariance"], r.vr["sigma"]
    assert [int(d.start) for d in r.vars["covariance"].dimensions] == [6, 6]
    r.instantiate()
    try:
        r.fmu.enterInitializationMode(startTime=0.0)
        r.set_params(params)
        # in Initialization Mode: the initial sigmas' diagonal
        seen = [(np.array(r.fmu.getFloat64([cov_vr], nValues=36)), np.array(r.fmu.getFloat64([sigma_vr], nValues=6)))]
        r.fmu.exitInitializationMode()
        for k in range(len(sc.times) - 1):
            r.fmu.setFloat64([r.vr["thrust"], r.vr["measurement"]], list(sc.thrust[k]) + list(z[k]))
            r.fmu.setBoolean([r.vr["measurement_valid"]], [bool(sc.valid[k])])
            r.fmu.doStep(sc.times[k], sc.times[k + 1] - sc.times[k])
            # both in one call, as a master reads a step's outputs
            both = np.array(r.fmu.getFloat64([cov_vr, sigma_vr], nValues=42))
            seen.append((both[:36], both[36:]))
    finally:
        r.free_instance()
    for cov, sigma in seen:
        p = cov.reshape(6, 6)
        if filter_name == "hinf":
            # no covariance, as its sigmas say
            assert np.isnan(p).all() and np.isnan(sigma).all()
            continue
        assert np.array_equal(p, p.T)
        np.linalg.cholesky(p)
        assert np.array_equal(np.sqrt(np.diag(p)), sigma)


# ------------------------------------------------------- FMI 3.0 in the other masters
# What each FMI importer installed here does with relnav3.fmu, measured (docs/fmu.md's
# FMI 3.0 masters table). Each runs in a child process: a master that cannot handle the
# FMU may end the process.
ECOS_CHILD = """
import sys
from ecospy import EcosLib, EcosSimulation, EcosSimulationStructure
EcosLib.set_log_level("debug")
structure = EcosSimulationStructure()
structure.add_model("B", sys.argv[1])
structure.add_parameter_set("initial", {"B::filter": 2})
sim = EcosSimulation(structure=structure, step_size=1.0)
print("init", sim.init(parameter_set="initial"))
print("mean_motion", sim.get_real("B::mean_motion"))
print("filter", sim.get_integer("B::filter"))
print("position", sim.get_real("B::position"))
sim.step(1)
print("time", sim.get_time())
sim.terminate(); sim.free(); structure.free()
"""

LIBCOSIM_CHILD = """
import sys
sys.path.insert(0, sys.argv[2])
import relnav_masters as rm
from pathlib import Path
from libcosimpy.CosimExecution import CosimExecution
ssp = rm.write_ssp(Path(sys.argv[3]) / "fmi3", sys.argv[1], ["B"])
try:
    CosimExecution.from_ssp_file(str(ssp), step_size=10**9)
    print("loaded")
except Exception:
    print("refused:", rm._cosim_error())
"""


def _child(code: str, *args: str) -> str:
    r = subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True, text=True, timeout=120)
    return r.stdout + r.stderr


def test_ecos_loads_relnav3_but_reads_arrays_as_scalars(fmu3_path):
    """Ecos (ecospy) instantiates and initialises relnav3.fmu and reads and sets its scalars,
    but has no array variables: it reads `position` with nValues = 1, which relnav3 refuses
    (its three values do not fit), and the instance is in the error state from then on
    (Ecos does not notice: it steps on). In Ecos, use relnav.fmu."""
    out = _child(ECOS_CHILD, fmu3_path)
    assert "init True" in out, out
    assert "mean_motion 0.0008726646259971648" in out and "filter 2" in out, out
    assert "fmi3GetFloat64: nValues = 1, but the 1 value references hold 3 values" in out, out
    assert "fmi3DoStep: illegal call sequence (not allowed in state Error)" in out, out


def test_libcosim_refuses_fmi3(fmu3_path, tmp_path):
    out = _child(LIBCOSIM_CHILD, fmu3_path, Path(rf.__file__).parent, tmp_path)
    assert "refused:" in out and "Unsupported FMI version" in out, out


def test_fmutool_check_is_clean(fmu3_path):
    exe = Path(sys.executable).parent / "fmutool"
    out = subprocess.run([str(exe), "-input", str(fmu3_path), "-check"], capture_output=True, text=True, timeout=120)
    text = out.stdout + out.stderr
    assert "compliant with FMI-3.0" in text and "No semantic error against the FMI-3 standard" in text, text


# ------------------------------------------------------------------------ Event Mode
def _event_run(r, params, times, thrust, meas, arrival):
    """relnav3 with eventModeUsed: each measurement applied in Event Mode at its arrival
    time, `arrival` s after the communication point (0: at it), the flag cleared after; the
    outputs at every whole communication point."""
    r.instantiate(eventModeUsed=True)
    try:
        r.fmu.enterInitializationMode(startTime=float(times[0]))
        r.set_params(params)
        r.fmu.exitInitializationMode()  # into Event Mode
        out = [r.outputs()]
        tv, mv, vv = r.vr["thrust"], r.vr["measurement"], r.vr["measurement_valid"]
        for k in range(len(times) - 1):
            # the arrival time and the step lengths as relnav.fmu's master computes them
            t, tm = float(times[k]), float(times[k] + arrival)
            r.fmu.setFloat64([tv], list(thrust[k]))
            if arrival > 0.0:
                r.fmu.enterStepMode()
                r.fmu.doStep(t, tm - t)
                r.fmu.enterEventMode()
            r.fmu.setFloat64([mv], list(meas[k]))
            r.fmu.setBoolean([vv], [True])
            discrete = r.fmu.updateDiscreteStates()
            assert not any(discrete[:5])
            r.fmu.setBoolean([vv], [False])
            r.fmu.enterStepMode()
            r.fmu.doStep(tm, float(times[k + 1]) - tm)
            out.append(r.outputs())
            r.fmu.enterEventMode()
        r.fmu.terminate()
    finally:
        r.free_instance()
    return np.array(out)


def _fmi2_run(runner, params, times, thrust, meas, arrival):
    """The same measurements through relnav.fmu: with `arrival` > 0 a step to the arrival
    time without measurement, then one from it with the measurement (taken at its start)."""
    if arrival == 0.0:
        return runner.run(params, times, thrust, meas, np.ones(len(times) - 1, bool))
    fine = np.sort(np.concatenate([times, times[:-1] + arrival]))
    n = len(times) - 1
    th = np.repeat(np.asarray(thrust, float), 2, axis=0)
    z = np.zeros((2 * n, 3))
    z[1::2] = meas
    valid = np.tile([False, True], n)
    return runner.run(params, fine, th, z, valid)[::2]


@pytest.mark.parametrize("filter_name", ["ekf", "ukf", "imm", "pf"])
@pytest.mark.parametrize("arrival", [0.0, 0.4])
def test_event_mode_applies_a_measurement_at_its_arrival_time(runner, runner3, filter_name, arrival):
    """A measurement applied in Event Mode at its arrival time gives what relnav.fmu gives
    when a communication point is put at that time (the same update at the same time, then
    the same prediction), bit for bit: also for the EKF and UKF, whose step fuses the
    update and the prediction and whose Event Mode runs them one after the other."""
    sc = cw.paper000_scenario(frame=2, times=np.arange(0.0, 41.0))
    params = {**sc.params, "filter": filter_name}
    if filter_name == "pf":
        params["particles"] = 200
    z = sc.measurements(4)
    ev = _event_run(runner3, params, sc.times, sc.thrust, z, arrival)
    ref = _fmi2_run(runner, params, sc.times, sc.thrust, z, arrival)
    assert ev.shape == ref.shape
    assert np.array_equal(ev.view(np.uint64), ref.view(np.uint64))


def test_event_mode_call_sequence(runner3):
    r = runner3
    r.log.records.clear()
    r.instantiate(eventModeUsed=True)
    try:
        r.fmu.enterInitializationMode(startTime=0.0)
        r.fmu.exitInitializationMode()
        # in Event Mode: no step, no second Event Mode; out of it: no discrete update
        with pytest.raises(Exception):
            r.fmu.doStep(0.0, 1.0)
        r.fmu.reset()
        r.fmu.enterInitializationMode(startTime=0.0)
        r.fmu.exitInitializationMode()
        r.fmu.enterStepMode()
        with pytest.raises(Exception):
            r.fmu.updateDiscreteStates()
        r.fmu.reset()
        r.fmu.enterInitializationMode(startTime=0.0)
        r.fmu.exitInitializationMode()
        # a parameter cannot be set in Event Mode
        with pytest.raises(Exception):
            r.fmu.setInt32([r.vr["filter"]], [2])
    finally:
        r.free_instance()
    text = r.log.text()
    assert text.count("illegal call sequence") == 2, text
    assert "cannot be set in state EventMode" in text, text
