"""FMU state through fmpy's FMU2Slave: getFMUstate / setFMUstate / serializeFMUstate /
deSerializeFMUstate for every filter code, the continuation bit-identical to the
uninterrupted run in the same instance and in another one; refusals with fmi2Error and a
logged reason; the state machine's rules; and the bytes read independently of relnav
following docs/state-format.md (header, CRC-32 with zlib, the embedded estimator state).
"""

from __future__ import annotations

import struct
import zlib

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2Error

import cwtruth as cw
import relnav_fmu as rf

STEPS = 40
SAVE_AT = 15
CODES = list(range(1, 12))
# documented sizes with the default parameters (1500 particles, window 10); the particle
# filters (4-8) with the default particle prior (pf_prior = 2): docs/state-format.md's
# `GSPF` section of 396 + 344 n bytes (n = 1500 terms, each an EKF's or a UKF's x and P)
# in place of the EKF's 340-byte section, the rest of the FMU state as the EKF's
PARTICLES = 1500
GSPF_FMU_STATE_BYTES = 2067 - 340 + 396 + 344 * PARTICLES
FMU_STATE_BYTES = {1: 2067, 2: 2067, 3: 2556, **{c: GSPF_FMU_STATE_BYTES for c in range(4, 9)}, 9: 3800, 10: 3107, 11: 2067}
# the particle filters with point particles (pf_prior = 1): the `PART` section, 2585 + 76 n
# + 336 m bytes (m = n for the unscented UPF and CGA-PF, no chunk generators below 32768)
POINTS = {"pf_prior": 1}
POINT_FMU_STATE_BYTES = {c: 2067 - 340 + 2585 + 76 * PARTICLES + (336 * PARTICLES if c in (6, 8) else 0) for c in range(4, 9)}
CASES = [(c, {}) for c in CODES] + [(c, POINTS) for c in range(4, 9)]
FMU_HEADER = 70
EST_HEADER = 32


@pytest.fixture(scope="module")
def scenario():
    times = np.arange(STEPS + 1.0)
    thrust = cw.burn_thrust(times, 10.0, 14.0, [20.0, -10.0, 5.0])
    valid = (np.arange(STEPS) % 5) != 4
    return cw.paper000_scenario(2, times=times, thrust_io=thrust, valid=valid)


@pytest.fixture(scope="module")
def other(unzipdir):
    """A second FMU2Slave on the same FMU: 'another instance'."""
    r = rf.SlaveRunner(unzipdir)
    yield r
    r.close()


def real_outputs(runner) -> list[int]:
    return [v.valueReference for v in runner.md.modelVariables if v.causality == "output" and v.type == "Real"]


def step_all(runner, sc, z, start: int, stop: int) -> np.ndarray:
    """Steps start..stop-1; every Real output after each, as raw bytes-comparable array."""
    outs = real_outputs(runner)
    rows = []
    for k in range(start, stop):
        runner.fmu.setReal(runner._in_real, [*sc.thrust[k], *z[k]])
        runner.fmu.setBoolean(runner._in_bool, [bool(sc.valid[k])])
        runner.fmu.doStep(currentCommunicationPoint=sc.times[k], communicationStepSize=1.0)
        rows.append(runner.fmu.getReal(outs))
    return np.array(rows)


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and a.tobytes() == b.tobytes()


def parse_fmu_state(b: bytes, guid: str) -> dict:
    """Read an FMU state as docs/state-format.md describes it (independently of relnav)."""
    magic, version = b[:8], struct.unpack_from("<I", b, 8)[0]
    g = b[12:50].decode("ascii")
    code, fingerprint, length, crc = struct.unpack_from("<iIQI", b, 50)
    assert magic == b"RELNAVFM" and version == 1 and g == guid
    assert length == len(b) - FMU_HEADER
    assert crc == zlib.crc32(b[:66] + b[FMU_HEADER:])
    p = FMU_HEADER
    assert b[p : p + 4] == b"FMUI"
    mode, time, start, stop_defined, stop, nvars = struct.unpack_from("<IddBdQ", b, p + 4)
    p += 4 + 4 + 8 + 8 + 1 + 8 + 8
    values = np.frombuffer(b, dtype="<f8", count=nvars, offset=p)
    p += 8 * nvars
    est = None
    if b[p]:
        (n,) = struct.unpack_from("<Q", b, p + 1)
        est = b[p + 9 : p + 9 + n]
        assert p + 9 + n == len(b)
    else:
        assert p + 1 == len(b)
    return dict(mode=mode, time=time, code=code, fingerprint=fingerprint, values=values, est=est)


def parse_estimator_state(e: bytes) -> dict:
    magic, version, code, fingerprint, length, crc = struct.unpack_from("<8sIiIQI", e, 0)
    assert magic == b"RELNAVES" and version == 6
    assert length == len(e) - EST_HEADER
    assert crc == zlib.crc32(e[:28] + e[EST_HEADER:])
    assert e[32:36] == b"CONF"
    (count,) = struct.unpack_from("<I", e, 36)
    assert count == 72
    conf = e[36 : 40 + 8 * count]
    assert fingerprint == zlib.crc32(conf)
    settings = e[40 : 40 + 8 * count]
    assert e[40 + 8 * count : 44 + 8 * count] == b"NAVG"
    return dict(code=code, settings=settings)


@pytest.mark.parametrize("code,extra", CASES, ids=[f"{c}{'-points' if e else ''}" for c, e in CASES])
def test_state_round_trip_is_bit_identical(runner, other, scenario, code, extra):
    """Save at step 15 of 40, continue; restore in the same instance and, serialised, in
    another instance (just instantiated: the parameters come with the state): the
    remaining 25 steps give bit-identical outputs. Every filter code at the defaults, and
    the particle filters with point particles too."""
    sc, z = scenario, scenario.measurements(code)
    params = {**sc.params, "filter": code, **extra}
    runner.instantiate()
    other.instantiate()
    try:
        runner.initialize(params)
        step_all(runner, sc, z, 0, SAVE_AT)
        state = runner.fmu.getFMUstate()
        blob = runner.fmu.serializeFMUstate(state)
        tail = step_all(runner, sc, z, SAVE_AT, STEPS)
        assert len(blob) == (POINT_FMU_STATE_BYTES if extra else FMU_STATE_BYTES)[code]
        # the same instance
        runner.fmu.setFMUstate(state)
        assert same_bits(step_all(runner, sc, z, SAVE_AT, STEPS), tail)
        # another instance, from the bytes
        st2 = other.fmu.deSerializeFMUstate(blob)
        other.fmu.setFMUstate(st2)
        assert same_bits(step_all(other, sc, z, SAVE_AT, STEPS), tail)
        assert other.fmu.serializeFMUstate(other.fmu.getFMUstate()) == runner.fmu.serializeFMUstate(
            runner.fmu.getFMUstate()
        )
        # the bytes follow the documented layout
        s = parse_fmu_state(blob, runner.md.guid)
        assert s["code"] == code and s["mode"] == 4 and s["time"] == SAVE_AT
        assert s["values"][runner.vr["filter"]] == code
        e = parse_estimator_state(s["est"])
        assert e["code"] == code
        # setting 4 of the configuration section is sigma_range, as f64 bits
        assert struct.unpack_from("<d", e["settings"], 8 * 4)[0] == params.get("sigma_range", 0.5)
        runner.fmu.freeFMUstate(state)
        other.fmu.freeFMUstate(st2)
    finally:
        runner.free_instance()
        other.free_instance()


def refused(runner, call) -> str:
    """Run ``call``; it must raise fmi2Error; returns the log text it produced."""
    runner.log.activate()
    runner.log.records.clear()
    with pytest.raises(FMICallException) as info:
        call()
    assert info.value.status == fmi2Error
    return runner.log.text()


def reseal(b: bytearray) -> bytes:
    b[66:70] = struct.pack("<I", zlib.crc32(bytes(b[:66]) + bytes(b[FMU_HEADER:])))
    return bytes(b)


def test_bad_states_are_refused_with_a_reason(runner, other, scenario):
    sc, z = scenario, scenario.measurements(0)
    params = {**sc.params, "filter": 5, "particles": 300}
    runner.instantiate()
    other.instantiate()
    try:
        runner.initialize(params)
        step_all(runner, sc, z, 0, 8)
        good = runner.fmu.serializeFMUstate(runner.fmu.getFMUstate())
        before = step_all(runner, sc, z, 8, 9)
        log = refused(other, lambda: other.fmu.deSerializeFMUstate(good[:-1]))
        assert "truncated" in log, log
        bad = bytearray(good)
        bad[len(bad) // 2] ^= 0x40
        assert "checksum mismatch" in refused(other, lambda: other.fmu.deSerializeFMUstate(bytes(bad)))
        bad = bytearray(good)
        bad[8:12] = struct.pack("<I", 2)
        assert "format version 2" in refused(other, lambda: other.fmu.deSerializeFMUstate(reseal(bad)))
        bad = bytearray(good)
        bad[20] = ord("0") if bad[20] != ord("0") else ord("1")
        assert "another FMU" in refused(other, lambda: other.fmu.deSerializeFMUstate(reseal(bad)))
        # another configuration: an instance running with other parameters
        other.fmu.reset()
        other.initialize({**params, "sigma_range": 0.6})
        st = other.fmu.deSerializeFMUstate(good)
        log = refused(other, lambda: other.fmu.setFMUstate(st))
        assert "sigma_range" in log and "fmi2Reset" in log, log
        # after fmi2Reset its parameters are free again: the state restores and continues
        other.fmu.reset()
        other.fmu.setFMUstate(st)
        assert same_bits(step_all(other, sc, z, 8, 9), before)
    finally:
        runner.free_instance()
        other.free_instance()


def test_state_machine_rules_come_back(runner, scenario):
    """A state taken in initialisation mode, restored while stepping, refuses doStep; the
    stepping state restored from the error state steps again at its time."""
    sc, z = scenario, scenario.measurements(0)
    runner.instantiate()
    try:
        runner.fmu.setupExperiment(startTime=0.0)
        runner.fmu.enterInitializationMode()
        init_state = runner.fmu.getFMUstate()
        runner.fmu.exitInitializationMode()
        step_all(runner, sc, z, 0, 3)
        step_state = runner.fmu.getFMUstate()
        runner.fmu.setFMUstate(init_state)
        log = refused(runner, lambda: runner.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=1.0))
        assert "illegal call sequence" in log, log
        runner.fmu.setFMUstate(step_state)
        step_all(runner, sc, z, 3, 5)
        runner.fmu.terminate()
    finally:
        runner.free_instance()
