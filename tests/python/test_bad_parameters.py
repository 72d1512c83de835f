"""Invalid parameters are rejected with fmi2Error and the logged reason names the
parameter: a value invalid whatever the other parameters are is refused when it is set
(fmi2Set*), a combination at fmi2ExitInitializationMode."""

import math

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2Error

BAD = [
    ("chaser_mass", 0.0),
    ("sigma_range", -1.0),
    ("mean_motion", math.nan),
    ("window", 0),
    ("frame", 5),
    # more of the same kind
    ("chaser_mass", -5.0),
    ("sigma_angle", 0.0),
    ("sigma_pos0", -1.0),
    ("sigma_vel0", math.inf),
    ("mean_motion", 0.0),
    ("q_pos_x", -1e-3),
    ("q_vel_z", math.nan),
    ("accel_psd", -1.0),
    ("x0", math.inf),
    ("filter", 0),
    ("frame", 0),
    ("discretization", 3),
    # particle filters and noise models
    ("particles", 0),
    ("particles", -5),
    ("resample_threshold", 0.0),
    ("resample_threshold", 1.5),
    ("noise_zeta", 1.0),
    ("noise_scale", 0.5),
    ("noise_dof", 2.0),
    ("resampler", 7),
    ("resampler", 0),
    ("noise_model", 4),
    # eccentric orbits (issue 34)
    ("eccentricity", -0.1),
    ("eccentricity", 1.0),
    ("eccentricity", 0.995),
    ("eccentricity", math.nan),
    ("true_anomaly0", math.inf),
]


def attempt(runner, params):
    """Instantiate with debug logging, set ``params``, initialise. Returns (exception or
    None, stage reached, log text)."""
    runner.log.records.clear()
    runner.instantiate(logging_on=True)
    stage = "set"
    try:
        runner.fmu.setupExperiment(startTime=0.0)
        runner.set_params(params)
        stage = "enter"
        runner.fmu.enterInitializationMode()
        stage = "exit"
        runner.fmu.exitInitializationMode()
        stage = "done"
        return None, stage, runner.log.text()
    except FMICallException as e:
        return e, stage, runner.log.text()
    finally:
        runner.free_instance()


@pytest.mark.parametrize("name,value", BAD, ids=[f"{n}={v}" for n, v in BAD])
def test_bad_parameter_rejected_with_reason(runner, name, value):
    exc, stage, log = attempt(runner, {name: value})
    assert exc is not None, f"{name}={value} was accepted (log: {log!r})"
    assert exc.status == fmi2Error, f"{name}={value}: status {exc.status} at {stage}"
    assert stage == "set", f"{name}={value}: refused at {stage}, not when set"
    assert name in log, f"{name}={value}: log does not name the parameter:\n{log}"
    # the same library still serves a good instance afterwards
    exc, stage, log = attempt(runner, {})
    assert exc is None, log


@pytest.mark.parametrize("name,value", [("hinf_period", 0.0), ("hinf_delta_bar", -0.1), ("hinf_period", 6e8)])
def test_bad_hinf_parameters_are_refused_when_set(runner, name, value):
    exc, stage, log = attempt(runner, {"filter": 9, name: value})
    assert exc is not None and stage == "set", (stage, log)
    assert name in log and name.removeprefix("hinf_") in log.split("refused:")[-1], log


def test_hinf_period_too_long_for_the_orbit_is_refused_at_exit_initialization(runner):
    """hinf_period = 1000 s is valid alone (for mean_motion <= 5e-4 rad/s): accepted when
    set, refused at fmi2ExitInitializationMode with the default orbit, accepted with a
    slow one."""
    exc, stage, log = attempt(runner, {"filter": 1, "hinf_period": 1000.0})
    assert exc is not None and stage == "exit" and "w0 * period" in log, (stage, log)
    exc, stage, log = attempt(runner, {"filter": 1, "hinf_period": 1000.0, "mean_motion": 7.3e-5})
    assert exc is None, log


@pytest.mark.parametrize("name,value", [("particles", 0), ("noise_zeta", 1.0)])
def test_particle_parameters_checked_whatever_the_filter(runner, name, value):
    """A bad particle-filter or noise parameter is refused with the EKF selected too, so it
    never hides until the filter changes."""
    exc, stage, log = attempt(runner, {"filter": 1, name: value})
    assert exc is not None and stage == "set" and name in log, (stage, log)


def test_hinf_track_initiation_on_an_eccentric_orbit_is_refused_at_exit_initialization(runner):
    """On an eccentric orbit the H-infinity design is scheduled over the orbit and runs
    without track initiation: filter 9 with eccentricity > 0 and hinf_acquisition on (each
    valid alone) is refused at fmi2ExitInitializationMode, the reason logged; with it off
    the instance initialises."""
    exc, stage, log = attempt(runner, {"filter": 9, "eccentricity": 0.1})
    assert exc is not None and exc.status == fmi2Error and stage == "exit", (stage, log)
    assert "eccentricity" in log and "hinf_acquisition" in log, log
    exc, stage, log = attempt(runner, {"filter": 9, "eccentricity": 0.1, "hinf_acquisition": False})
    assert exc is None, log


def test_unscented_particle_filters_need_process_noise(runner):
    """The literal UPF and CGA-PF (point particles, pf_move false) build their proposal on
    the transition density: no process noise at all is refused. With their moves (pf_move's
    default) it is not needed."""
    no_q = {f"q_{k}_{a}": 0.0 for k in ("pos", "vel") for a in "xyz"}
    points = {"pf_prior": 1}
    for code in (6, 8):
        exc, stage, log = attempt(runner, {"filter": code, "pf_move": False, **points, **no_q})
        assert exc is not None and stage == "exit" and "process noise" in log, (code, stage, log)
        exc, stage, log = attempt(runner, {"filter": code, **points, **no_q})
        assert exc is None, log
    exc, stage, log = attempt(runner, {"filter": 5, **points, **no_q})  # the RPF needs no density of Q
    assert exc is None, log


def test_valid_edge_values_accepted(runner):
    ok = {"q_pos_x": 0.0, "q_vel_y": 0.0, "accel_psd": 1e-9, "filter": 2, "frame": 3, "discretization": 2, "seed": -7}
    exc, stage, log = attempt(runner, ok)
    assert exc is None, log
    pf = {"filter": 8, "particles": 1, "resampler": 4, "resample_threshold": 1.0, "noise_model": 2,
          "noise_zeta": 0.0, "noise_scale": 1.0, "noise_dof": 2.001}
    exc, stage, log = attempt(runner, pf)
    assert exc is None, log


# fmpy's logger proxy is process-wide (see relnav_fmu.LogCapture) and simulate_fmu leaves
# the failed instance (with its ctypes logger) to the garbage collector: keep them alive.
_KEEP_ALIVE = []


def test_simulate_fmu_raises_and_logger_receives_reason(unzipdir):
    messages = []

    def logger(env, instance, status, category, message):  # noqa: ARG001
        messages.append((status, message.decode("utf-8", "replace") if isinstance(message, bytes) else str(message)))

    _KEEP_ALIVE.append(logger)
    with pytest.raises(Exception) as info:
        simulate_fmu(
            str(unzipdir),
            stop_time=10.0,
            output_interval=1.0,
            start_values={"chaser_mass": 0.0},
            debug_logging=True,
            logger=logger,
        )
    _KEEP_ALIVE.append(info)
    assert "fmi2" in str(info.value)
    assert any("chaser_mass" in m for _, m in messages), messages
    assert any(s == fmi2Error for s, m in messages if "chaser_mass" in m), messages


def test_bad_step_size_is_an_error(runner):
    """A non-positive communication step is refused with fmi2Error; a fresh instance works."""
    runner.log.records.clear()
    runner.instantiate(logging_on=True)
    try:
        runner.initialize({})
        before = runner.outputs()
        with pytest.raises(FMICallException) as info:
            runner.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.0)
        assert info.value.status >= fmi2Error
    finally:
        runner.free_instance()
    assert np.all(np.isfinite(before))
