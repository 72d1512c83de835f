"""Variable communication step sizes (canHandleVariableCommunicationStepSize): a mix of
0.5 s and 1 s steps, with a measurement at the start of every step."""

import numpy as np
import pytest

import cwtruth as cw
import refekf
import refukf
import relnav_fmu as rf


def mixed_grid(stop=600.0):
    """Each 1 s block is one 1 s step or two 0.5 s steps (pseudo-random, fixed), so every
    whole second is a grid point (fmpy.simulate_fmu with output_interval=1 steps there)."""
    rng = np.random.default_rng(123)
    t = [0.0]
    for _ in range(int(stop)):
        if rng.random() < 0.5:
            t += [t[-1] + 0.5, t[-1] + 1.0]
        else:
            t += [t[-1] + 1.0]
    return np.array(t)


@pytest.fixture(scope="module")
def scenario():
    times = mixed_grid()
    steps = np.diff(times)
    assert set(np.round(steps, 12)) == {0.5, 1.0} and np.sum(steps == 0.5) > 200
    thrust = cw.burn_thrust(times, 100.0, 160.0, [2.0, -1.0, 0.5])
    return cw.paper000_scenario(2, times=times, thrust_io=thrust)


@pytest.mark.parametrize("name,code", [("ekf", 1), ("ukf", 2)])
def test_mixed_steps_meet_bar(runs, scenario, name, code):
    out = runs("mixed-steps", scenario, code)
    acc = cw.accuracy(out[:, :, :6], scenario.truth_io, scenario.times)
    assert not acc.bar_violations(), f"{name}: {acc.bar_violations()}; {acc.describe()}"


def test_mixed_steps_match_references(runs, scenario):
    z = scenario.measurements(0)
    ekf = runs("mixed-steps", scenario, 1)[0]
    ref = refekf.run_ekf(scenario.params, scenario.times, scenario.thrust, z, scenario.valid)
    assert np.allclose(ekf, ref, rtol=1e-9, atol=1e-9), np.abs(ekf - ref).max()
    ukf = runs("mixed-steps", scenario, 2)[0]
    ref = refukf.run_ukf(scenario.params, scenario.times, scenario.thrust, z, scenario.valid)
    assert np.allclose(ukf, ref, rtol=1e-9, atol=1e-9), np.abs(ukf - ref).max()


def test_simulate_fmu_with_mixed_steps_equals_slave(runs, unzipdir, scenario):
    """fmpy.simulate_fmu (output_interval 1 s) steps to every input change, i.e. to the
    half-second grid points too: the same step sequence, the same outputs."""
    z = scenario.measurements(3)
    slave = runs("mixed-steps", scenario, 1, seeds=[3])[0]
    sim = rf.run_simulate_fmu(unzipdir, {**scenario.params, "filter": 1}, scenario.times, scenario.thrust, z, scenario.valid, output_interval=1.0)
    assert np.array_equal(sim, slave)


def test_prediction_independent_of_step_partition(runner):
    """Without measurements the estimate is the exact CW propagation of the initial
    estimate, whatever the steps (0.5, 1, 7.5 and 20 s mixed, thrust held over steps)."""
    coarse = np.concatenate([np.arange(0.0, 100.0, 0.5), np.arange(100.0, 160.0, 7.5), np.arange(160.0, 601.0, 20.0)])
    fine = np.arange(0.0, 601.0, 0.5)
    results = {}
    for label, times in (("coarse", coarse), ("fine", fine)):
        thrust = cw.burn_thrust(times, 100.0, 160.0, [2.0, -1.0, 0.5])
        n = len(times) - 1
        out = runner.run({}, times, thrust, np.zeros((n, 3)), np.zeros(n, dtype=bool))
        results[label] = dict(zip(times.tolist(), out))
    common = sorted(set(results["coarse"]) & set(results["fine"]))
    assert len(common) > 50
    a = np.array([results["coarse"][t][:6] for t in common])
    b = np.array([results["fine"][t][:6] for t in common])
    assert np.allclose(a, b, rtol=1e-11, atol=1e-9), np.abs(a - b).max()
    est0_c = cw.state_to_canonical(cw.PAPER000_EST0, 2)
    truth = cw.state_to_frame(
        cw.truth_trajectory(cw.PAPER000_N, est0_c, coarse, cw.vec_to_canonical(cw.burn_thrust(coarse, 100.0, 160.0, [2.0, -1.0, 0.5]), 2) / 1000.0),
        2,
    )
    got = np.array([results["coarse"][t][:6] for t in coarse.tolist()])
    assert np.allclose(got, truth, rtol=1e-10, atol=1e-8), np.abs(got - truth).max()
