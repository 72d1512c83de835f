"""The FMU's log as a master receives it (fmpy formats the printf-style message with its
native proxy): `logCalls` carries every call's arguments, `%` and `#` are escaped per the
FMI logger rules (the message is a format: `%%`; `#` is FMI's escape: `##`)."""

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException


def calls(runner):
    return [m for _, c, m in runner.log.records if c == "logCalls"]


def test_log_calls_carry_the_arguments(runner):
    runner.log.records.clear()
    runner.instantiate(logging_on=True)
    try:
        vr = runner.vr
        runner.fmu.setupExperiment(startTime=0.0, stopTime=10.0)
        runner.fmu.setReal([vr["chaser_mass"], vr["x0"]], [500.0, 401.5])
        runner.fmu.setInteger([vr["filter"], vr["particles"]], [2, 300])
        runner.fmu.enterInitializationMode()
        runner.fmu.exitInitializationMode()
        runner.fmu.setBoolean([vr["measurement_valid"]], [False])
        runner.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.5, noSetFMUStatePriorToCurrentPoint=False)
        x = runner.fmu.getReal([vr["x"], vr["sigma_vz"]])
        status = runner.fmu.getInteger([vr["fmi_status"]])
        runner.fmu.terminate()
    finally:
        runner.free_instance()
    log = calls(runner)
    text = "\n".join(log)
    assert log[0].startswith('fmi2Instantiate(instanceName = "relnav_test", fmuType = 1, fmuGUID = "{'), log[0]
    assert "loggingOn = true" in log[0]
    expected = [
        "fmi2SetupExperiment(toleranceDefined = false, tolerance = 0, startTime = 0, stopTimeDefined = true, stopTime = 10)",
        "fmi2SetReal(nvr = 2: chaser_mass (vr 4) = 500, x0 (vr 7) = 401.5)",
        "fmi2SetInteger(nvr = 2: filter (vr 0) = 2, particles (vr 45) = 300)",
        "fmi2EnterInitializationMode()",
        "fmi2ExitInitializationMode()",
        "fmi2SetBoolean(nvr = 1: measurement_valid (vr 32) = false)",
        "fmi2DoStep(currentCommunicationPoint = 0, communicationStepSize = 0.5, noSetFMUStatePriorToCurrentPoint = false)",
        f"fmi2GetReal(nvr = 2: x (vr 33) = {x[0]!r}, sigma_vz (vr 44) = {x[1]!r})",
        f"fmi2GetInteger(nvr = 1: fmi_status (vr {vr['fmi_status']}) = {status[0]})",
        "fmi2Terminate()",
        "fmi2FreeInstance()",
    ]
    for e in expected:
        assert e in log, f"missing {e!r} in\n{text}"
    assert log.index(expected[0]) < log.index(expected[6]) < log.index(expected[-1])
    assert status == [0]


def test_log_calls_off_by_category(runner):
    runner.log.records.clear()
    runner.instantiate(logging_on=True)
    try:
        runner.fmu.setDebugLogging(False, ["logCalls"])
        runner.initialize({})
        runner.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=1.0)
    finally:
        runner.free_instance()
    # the calls before logCalls was switched off, and no other
    assert [m.split("(")[0] for m in calls(runner)] == ["fmi2Instantiate", "fmi2SetDebugLogging"]
    assert any(c == "logInfo" for _, c, _ in runner.log.records)


def test_percent_and_hash_are_escaped(runner):
    """A message with % and # reaches the master as written (% survives printf
    formatting) with # doubled, FMI's escape for a literal #."""
    runner.log.records.clear()
    runner.instantiate(logging_on=True)
    try:
        with pytest.raises(FMICallException):
            runner.fmu.setDebugLogging(True, ["50%s #r0# %d"])
    finally:
        runner.free_instance()
    errors = [m for s, c, m in runner.log.records if c == "logStatusError"]
    assert any('unknown log category "50%s ##r0## %d"' in m for m in errors), runner.log.text()
    calls_ = calls(runner)
    assert any('categories = ["50%s ##r0## %d"]' in m for m in calls_), calls_


def test_long_messages_are_cut(runner):
    """A call with many values is logged, cut at 1500 characters with ' ...'."""
    runner.log.records.clear()
    runner.instantiate(logging_on=True)
    try:
        runner.initialize({})
        refs = [runner.vr[n] for n in ['x', 'y', 'z', 'vx', 'vy', 'vz', 'sigma_x', 'sigma_y', 'sigma_z', 'sigma_vx', 'sigma_vy', 'sigma_vz']] * 10
        values = runner.fmu.getReal(refs)
    finally:
        runner.free_instance()
    get = [m for m in calls(runner) if m.startswith("fmi2GetReal(nvr = 120:")]
    assert len(get) == 1 and get[0].endswith(" ...") and len(get[0]) <= 1504, get
    assert np.isfinite(values[0])
