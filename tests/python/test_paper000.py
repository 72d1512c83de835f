"""Paper 000's example through the FMU, with fmpy.simulate_fmu and with FMU2Slave.

Truth: tools/cwtruth.py (independent numpy CW model). 20 seeded runs (numpy
default_rng(seed)); error = output after the step at t (i.e. at t + 1) minus truth at t + 1.
The bar is the paper's published accuracy (see cwtruth.BAR_*).
"""

import numpy as np
import pytest

import cwtruth as cw
import refekf
import refukf
from conftest import RUNS

FILTERS = [("ekf", 1), ("ukf", 2)]


@pytest.fixture(scope="module")
def scenario():
    return cw.paper000_scenario(frame=2)


@pytest.mark.parametrize("name,code", FILTERS)
@pytest.mark.parametrize("driver", ["slave", "simulate_fmu"])
def test_meets_published_accuracy(runs, scenario, name, code, driver):
    out = runs("paper000", scenario, code, driver)
    assert out.shape == (RUNS, scenario.steps + 1, 12)
    assert np.all(np.isfinite(out))
    acc = cw.accuracy(out[:, :, :6], scenario.truth_io, scenario.times)
    assert not acc.bar_violations(), f"{name} via {driver}: {acc.bar_violations()}; {acc.describe()}"
    # converged well before the 80 s mark, and the uncertainty shrank from (50 m, 1 m/s)
    assert acc.converge_time <= 80.0, acc.describe()
    final_sigma = out[:, -1, 6:].mean(axis=0)
    assert np.all(final_sigma[:3] < 1.0) and np.all(final_sigma[3:] < 0.05), final_sigma


@pytest.mark.parametrize("name,code", FILTERS)
def test_drivers_give_identical_outputs(runs, scenario, name, code):
    a = runs("paper000", scenario, code, "slave")
    b = runs("paper000", scenario, code, "simulate_fmu")
    assert np.array_equal(a, b), f"{name}: max difference {np.abs(a - b).max()}"


def test_first_outputs_by_hand(runs, scenario):
    """fmpy.simulate_fmu applies the row of time t at the start of the step at t: the
    first outputs equal a hand-computed EKF update with z(0) followed by a 1 s prediction
    (and not, e.g., the prediction alone or an update with z(1))."""
    out = runs("paper000", scenario, 1, "simulate_fmu")[0]
    z = scenario.measurements(0)
    ref = refekf.run_ekf(scenario.params, scenario.times[:3], scenario.thrust[:2], z[:2], scenario.valid[:2])
    assert np.allclose(out[0], ref[0], rtol=0, atol=1e-12)  # the initial estimate, sigma 50 / 1
    assert np.allclose(out[1], ref[1], rtol=1e-12, atol=1e-9), (out[1], ref[1])
    assert np.allclose(out[2], ref[2], rtol=1e-12, atol=1e-9)
    late = refekf.run_ekf(scenario.params, scenario.times[:3], scenario.thrust[:2], z[1:3], scenario.valid[:2])
    no_meas = refekf.run_ekf(scenario.params, scenario.times[:3], scenario.thrust[:2], z[:2], [False, False])
    assert np.abs(out[1, :3] - late[1, :3]).max() > 1e-3  # a one-step shift is far outside 1e-9
    assert np.abs(out[1, :3] - no_meas[1, :3]).max() > 1.0


def test_ekf_matches_reference_ekf_every_step(runs, scenario):
    """The FMU's EKF is the textbook EKF (tools/refekf.py) number for number, in the
    estimate and in the sigma outputs."""
    out = runs("paper000", scenario, 1, "slave")
    for seed in (0, 7, 19):
        ref = refekf.run_ekf(scenario.params, scenario.times, scenario.thrust, scenario.measurements(seed), scenario.valid)
        assert np.allclose(out[seed], ref, rtol=1e-9, atol=1e-9), np.abs(out[seed] - ref).max()


def test_ukf_matches_filterpy_ukf(runs, scenario):
    """Third-party anchor: filterpy's UnscentedKalmanFilter (scaled sigma points, alpha 1,
    beta 2, kappa 0, circular azimuth mean) on the same measurements."""
    out = runs("paper000", scenario, 2, "slave")
    for seed in (0, 11):
        ref = refukf.run_ukf(scenario.params, scenario.times, scenario.thrust, scenario.measurements(seed), scenario.valid)
        assert np.allclose(out[seed], ref, rtol=1e-9, atol=1e-9), np.abs(out[seed] - ref).max()


def test_ekf_and_ukf_agree_closely(runs, scenario):
    ekf = runs("paper000", scenario, 1, "slave")
    ukf = runs("paper000", scenario, 2, "slave")
    sel = scenario.times >= 80
    assert np.abs(ekf[:, sel, :3] - ukf[:, sel, :3]).max() < 0.05
    assert not np.array_equal(ekf, ukf)  # the filter parameter is really used


def test_sigma_outputs_are_consistent_with_errors(runs, scenario):
    """The reported 1-sigma matches the spread of the error over the runs (not wildly
    optimistic or pessimistic) after convergence."""
    for code in (1, 2):
        out = runs("paper000", scenario, code, "slave")
        sel = scenario.times >= 80
        err = out[:, sel, :6] - scenario.truth_io[None, sel]
        ratio = np.sqrt(np.mean(err**2, axis=(0, 1))) / np.mean(out[:, sel, 6:], axis=(0, 1))
        assert np.all(ratio < 1.5) and np.all(ratio > 0.1), ratio


def test_euler_discretization_option_runs(runner, scenario):
    """discretization = 2 (paper 000's literal Euler) is accepted, differs from the exact
    model, and still tracks the truth."""
    z = scenario.measurements(0)
    exact = runner.run({**scenario.params}, scenario.times, scenario.thrust, z, scenario.valid)
    euler = runner.run({**scenario.params, "discretization": 2}, scenario.times, scenario.thrust, z, scenario.valid)
    assert not np.array_equal(exact, euler)
    err = euler[80:, :3] - scenario.truth_io[80:, :3]
    assert np.abs(err).max() < 2.0

