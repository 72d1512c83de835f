"""A 60 s burn known through the thrust inputs: (2, -1, 0.5) N in frame 2 from t = 100 s
to 160 s on the 1000 kg chaser. Truth with the burn from the independent model
(matrix exponential of the augmented CW system)."""

import numpy as np
import pytest

import cwtruth as cw

TIMES = np.arange(cw.PAPER000_STEPS + 1, dtype=float)
THRUST = cw.burn_thrust(TIMES, 100.0, 160.0, [2.0, -1.0, 0.5])


@pytest.fixture(scope="module")
def told():
    return cw.paper000_scenario(2, thrust_io=THRUST, thrust_known=True)


@pytest.fixture(scope="module")
def not_told():
    return cw.paper000_scenario(2, thrust_io=THRUST, thrust_known=False)


def test_burn_changes_the_truth(told):
    coast = cw.paper000_scenario(2)
    assert np.abs(told.truth_io[-1, :3] - coast.truth_io[-1, :3]).max() > 20.0
    assert told.thrust[100].tolist() == [2.0, -1.0, 0.5] and not told.thrust[160].any() and not told.thrust[99].any()


@pytest.mark.parametrize("name,code", [("ekf", 1), ("ukf", 2)])
def test_bar_met_with_known_burn(runs, told, name, code):
    out = runs("burn-told", told, code)
    acc = cw.accuracy(out[:, :, :6], told.truth_io, told.times)
    assert not acc.bar_violations(), f"{name}: {acc.bar_violations()}; {acc.describe()}"


@pytest.mark.parametrize("name,code", [("ekf", 1), ("ukf", 2)])
def test_unknown_burn_gives_clearly_larger_error(runs, told, not_told, name, code):
    good = cw.accuracy(runs("burn-told", told, code)[:, :, :6], told.truth_io, told.times)
    bad = cw.accuracy(runs("burn-not-told", not_told, code)[:, :, :6], not_told.truth_io, not_told.times)
    msg = f"told: {good.describe()}\nnot told: {bad.describe()}"
    # precise range/angle measurements keep the position close either way; the velocity,
    # which the filter only learns through the dynamics, is where the unmodelled burn shows
    assert bad.vel_rmse > 5.0 * good.vel_rmse, msg
    assert bad.worst_axis[3:].max() > 5.0 * good.worst_axis[3:].max(), msg
    assert bad.worst_axis[:3].max() > 1.2 * good.worst_axis[:3].max(), msg
    assert bad.bar_violations(), "an unmodelled 2 mm/s^2 burn should break the bar\n" + msg


def test_thrust_acts_through_chaser_mass(runner, told):
    """Doubling thrust and mass gives the same acceleration: the same outputs."""
    z = told.measurements(0)
    a = runner.run({**told.params, "chaser_mass": 1000.0}, told.times, told.thrust, z, told.valid)
    b = runner.run({**told.params, "chaser_mass": 2000.0}, told.times, 2.0 * told.thrust, z, told.valid)
    assert np.allclose(a, b, rtol=1e-12, atol=1e-9)
    c = runner.run({**told.params, "chaser_mass": 2000.0}, told.times, told.thrust, z, told.valid)
    assert np.abs(a[160:, :3] - c[160:, :3]).max() > 0.1
