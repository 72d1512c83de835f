"""A 30 s measurement dropout: measurement_valid is false for the steps starting at
t = 200 .. 229 s (outputs at 201 .. 230 s are pure predictions)."""

import numpy as np
import pytest

import cwtruth as cw

TIMES = np.arange(cw.PAPER000_STEPS + 1, dtype=float)
VALID = ~((TIMES[:-1] >= 200) & (TIMES[:-1] < 230))


@pytest.fixture(scope="module")
def scenario():
    return cw.paper000_scenario(2, valid=VALID)


@pytest.mark.parametrize("name,code", [("ekf", 1), ("ukf", 2)])
def test_covariance_grows_during_dropout_and_recovers(runs, scenario, name, code):
    out = runs("dropout", scenario, code)
    sig = out[:, :, 6:9]  # position sigmas, every run
    during = sig[:, 200:231]  # outputs at 200 (last with a measurement) .. 230
    assert np.all(np.diff(during, axis=1) > 0), f"{name}: position sigma must grow at every step without measurements"
    assert np.all(sig[:, 230] > 1.5 * sig[:, 200]), f"{name}: {sig[0, 200]} -> {sig[0, 230]}"
    # the first measurement after the gap (taken at 230) shrinks it at once ...
    assert np.all(sig[:, 231] < sig[:, 230])
    # ... and 30 s later it is back to the level before the gap
    assert np.allclose(sig[:, 260], sig[:, 199], rtol=0.1), (sig[0, 199], sig[0, 260])
    # velocity sigmas grow too, more gently
    assert np.all(out[:, 230, 10:12] > out[:, 200, 10:12])


@pytest.mark.parametrize("name,code", [("ekf", 1), ("ukf", 2)])
def test_error_consistent_with_sigma(runs, scenario, name, code):
    out = runs("dropout", scenario, code)
    err = out[:, :, :6] - scenario.truth_io[None]
    ratio = np.abs(err) / out[:, :, 6:]
    worst = ratio.max(axis=(0, 1))
    assert np.all(worst < 4.0), f"{name}: max |error| / sigma per axis {worst}"
    assert np.mean(ratio > 3.0) < 1e-3


@pytest.mark.parametrize("name,code", [("ekf", 1), ("ukf", 2)])
def test_bar_met_after_recovery(runs, scenario, name, code):
    out = runs("dropout", scenario, code)
    after = cw.accuracy(out[:, :, :6], scenario.truth_io, scenario.times, t_from=260.0)
    assert not after.bar_violations(), f"{name}: {after.bar_violations()}; {after.describe()}"
    # a 30 s gap at this geometry does not even break the bar from 80 s on
    whole = cw.accuracy(out[:, :, :6], scenario.truth_io, scenario.times)
    assert whole.worst_axis[:3].max() < cw.BAR_POS_AXIS, whole.describe()
