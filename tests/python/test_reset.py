"""fmi2Reset and reproducibility: one instance, run, reset, run again."""

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.simulation import instantiate_fmu

import cwtruth as cw
import relnav_fmu as rf


@pytest.fixture(scope="module")
def scenario():
    thrust = cw.burn_thrust(np.arange(601.0), 100.0, 160.0, [2.0, -1.0, 0.5])
    valid = ~((np.arange(600.0) >= 200) & (np.arange(600.0) < 230))
    return cw.paper000_scenario(2, thrust_io=thrust, valid=valid)


def run_on_instance(runner, params, sc, z, steps=None):
    runner.initialize(params)
    n = sc.steps if steps is None else steps
    return runner.simulate(sc.times[: n + 1], sc.thrust[:n], z[:n], sc.valid[:n])


@pytest.mark.parametrize("code", [1, 2])
def test_reset_then_rerun_gives_identical_outputs(runner, scenario, code):
    z = scenario.measurements(0)
    params = {**scenario.params, "filter": code}
    runner.instantiate()
    try:
        first = run_on_instance(runner, params, scenario, z)
        runner.fmu.reset()
        second = run_on_instance(runner, params, scenario, z)
        # reset in the middle of a run, then a full run
        runner.fmu.reset()
        run_on_instance(runner, params, scenario, z, steps=123)
        runner.fmu.reset()
        third = run_on_instance(runner, params, scenario, z)
        runner.fmu.terminate()
    finally:
        runner.free_instance()
    assert np.array_equal(first, second)
    assert np.array_equal(first, third)
    assert np.allclose(second[0, :6], cw.PAPER000_EST0)
    # and equal to a fresh instance
    assert np.array_equal(first, runner.run(params, scenario.times, scenario.thrust, z, scenario.valid))


def test_reset_restores_default_parameter_values(runner, scenario):
    """FMI 2.0: after fmi2Reset the FMU is as if just instantiated, 'all variables have
    their default values' - parameters set before the reset do not carry over."""
    z = scenario.measurements(1)
    default_run = runner.run({}, scenario.times, scenario.thrust, z, scenario.valid)
    runner.instantiate()
    try:
        run_on_instance(runner, {"filter": 2, "x0": 500.0, "sigma_pos0": 10.0}, scenario, z)
        runner.fmu.reset()
        after_reset = run_on_instance(runner, {}, scenario, z)
        runner.fmu.terminate()
    finally:
        runner.free_instance()
    assert np.array_equal(after_reset, default_run), "parameters set before fmi2Reset leaked into the next run"


def test_seed_parameter_accepted(runner, scenario):
    z = scenario.measurements(2)
    runner.instantiate()
    try:
        runner.fmu.setupExperiment(startTime=0.0)
        runner.set_params({"seed": 12345})
        runner.fmu.enterInitializationMode()
        assert runner.fmu.getInteger([runner.vr["seed"]]) == [12345]
        runner.fmu.exitInitializationMode()
        seeded = runner.simulate(scenario.times, scenario.thrust, z, scenario.valid)
        runner.fmu.terminate()
    finally:
        runner.free_instance()
    # the EKF draws no random numbers: the seed changes nothing, and repeated runs agree
    assert np.array_equal(seeded, runner.run({"seed": 0}, scenario.times, scenario.thrust, z, scenario.valid))
    assert np.array_equal(seeded, runner.run({"seed": 12345}, scenario.times, scenario.thrust, z, scenario.valid))


def test_simulate_fmu_reusing_an_instance_with_reset(unzipdir, scenario):
    """fmpy's documented pattern for repeated runs: one instance, fmu.reset() between
    simulate_fmu calls."""
    md = read_model_description(str(unzipdir))
    fmu = instantiate_fmu(str(unzipdir), md, "CoSimulation")
    z = scenario.measurements(5)
    sig = rf.input_table(scenario.times, scenario.thrust, z, scenario.valid)
    kw = dict(start_time=0.0, stop_time=600.0, output_interval=1.0, input=sig, output=rf.OUTPUTS, model_description=md, fmu_instance=fmu)
    try:
        a = simulate_fmu(str(unzipdir), start_values={"filter": 2}, **kw)
        fmu.reset()
        b = simulate_fmu(str(unzipdir), start_values={"filter": 2}, **kw)
    finally:
        fmu.freeInstance()
    for name in rf.OUTPUTS:
        assert np.array_equal(a[name], b[name]), name
    assert len(a) == 601
