"""Input handling at fmi2DoStep: the azimuth cut at 0 / 2 pi, non-finite inputs, and the
communication-point bookkeeping."""

import math

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2Error

import cwtruth as cw
import refekf
import refukf
import relnav_fmu as rf


@pytest.fixture(scope="module")
def cut_scenario():
    """Frame 2, the chaser drifts through the radial = 0 plane ahead of the target, so the
    measured azimuth atan2(radial, along) jumps from just below 2 pi to just above 0."""
    times = np.arange(601.0)
    truth0_io = np.array([400.0, -20.0, 100.0, 0.0, 0.1, 0.0])
    truth_c = cw.cw_closed_form(cw.PAPER000_N, cw.state_to_canonical(truth0_io, 2), times)
    truth_io = cw.state_to_frame(truth_c, 2)
    est0 = truth0_io + np.array([5.0, 5.0, 5.0, 0.1, 0.1, 0.1])
    params = cw.frame_params(2)
    params.update(dict(zip(["x0", "y0", "z0", "vx0", "vy0", "vz0"], est0.tolist())))
    return cw.Scenario(frame=2, times=times, truth_io=truth_io, thrust=np.zeros((600, 3)), valid=np.ones(600, dtype=bool), params=params)


def test_truth_crosses_the_azimuth_cut(cut_scenario):
    az = cw.measure(cut_scenario.truth_io[:-1, :3])[:, 1]
    assert az[0] > 6.0 and az[-1] < 0.5
    assert np.any(np.abs(np.diff(az)) > 6.0)


@pytest.mark.parametrize("name,code", [("ekf", 1), ("ukf", 2)])
def test_filters_track_through_the_azimuth_cut(runs, cut_scenario, name, code):
    out = runs("azimuth-cut", cut_scenario, code, seeds=list(range(10)))
    acc = cw.accuracy(out[:, :, :6], cut_scenario.truth_io, cut_scenario.times)
    assert not acc.bar_violations(), f"{name}: {acc.bar_violations()}; {acc.describe()}"
    z = cut_scenario.measurements(0)
    ref = (refekf.run_ekf if code == 1 else refukf.run_ukf)(cut_scenario.params, cut_scenario.times, cut_scenario.thrust, z, cut_scenario.valid)
    assert np.allclose(out[0], ref, rtol=1e-9, atol=1e-9), np.abs(out[0] - ref).max()


def one_step(runner, thrust, meas, valid, t=0.0, h=1.0):
    """Fresh instance, one doStep; returns (exception or None, outputs before, after, log)."""
    runner.log.records.clear()
    runner.instantiate(logging_on=True)
    try:
        runner.initialize({})
        before = runner.outputs()
        exc = None
        try:
            runner.fmu.setReal([runner.vr[n] for n in rf.REAL_INPUTS], list(thrust) + list(meas))
            runner.fmu.setBoolean([runner.vr["measurement_valid"]], [valid])
            runner.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        except FMICallException as e:
            exc = e
        after = runner.outputs()
        return exc, before, after, runner.log.text()
    finally:
        runner.free_instance()


def test_invalid_measurement_values_are_ignored_when_not_valid(runner):
    exc, before, after, log = one_step(runner, [0.0, 0.0, 0.0], [math.nan, math.inf, -math.inf], False)
    assert exc is None, log
    assert np.all(np.isfinite(after))
    # a pure prediction: the estimate moved by about the velocity, the sigmas grew
    assert np.allclose(after[:3] - before[:3], before[3:6], atol=1e-3)
    assert np.all(after[6:9] > before[6:9])


def test_non_finite_measurement_is_an_error_and_leaves_the_estimate(runner):
    exc, before, after, log = one_step(runner, [0.0, 0.0, 0.0], [math.nan, 0.9, 0.3], True)
    assert exc is not None and exc.status == fmi2Error, log
    assert np.array_equal(before, after)
    assert "measurement" in log and "finite" in log, log


def test_non_finite_thrust_is_an_error(runner):
    exc, before, after, log = one_step(runner, [math.inf, 0.0, 0.0], [670.0, 0.9, 0.3], True)
    assert exc is not None and exc.status == fmi2Error, log
    assert np.array_equal(before, after)
    assert "thrust" in log, log


def test_communication_point_must_follow_on(runner):
    runner.log.records.clear()
    runner.instantiate(logging_on=True)
    try:
        runner.initialize({})
        runner.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=1.0)
        runner.fmu.doStep(currentCommunicationPoint=1.0, communicationStepSize=0.25)
        with pytest.raises(FMICallException):
            runner.fmu.doStep(currentCommunicationPoint=5.0, communicationStepSize=1.0)
    finally:
        runner.free_instance()
    assert "currentCommunicationPoint" in runner.log.text()


def test_start_time_other_than_zero(runner):
    """setupExperiment(startTime=1000): the same run shifted in time gives the same outputs
    (the dynamics are time-invariant)."""
    sc = cw.paper000_scenario(2)
    z = sc.measurements(0)
    a = runner.run({}, sc.times[:101], sc.thrust[:100], z[:100], sc.valid[:100])
    b = runner.run({}, sc.times[:101] + 1000.0, sc.thrust[:100], z[:100], sc.valid[:100])
    assert np.allclose(a, b, rtol=1e-12, atol=1e-9)
