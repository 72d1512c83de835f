"""The AQUKF (filter 3, paper 001) through fmpy.simulate_fmu on paper 000's example with a
burn the filter is NOT told about: (2, -1, 0.5) N in frame 2 from t = 100 s to 160 s on the
1000 kg chaser (a 0.14 m/s velocity change). Truth from the independent numpy model
(tools/cwtruth.py: matrix exponential of the augmented CW system).

Both filters are tuned for the quiet phase: no position noise, a velocity noise of
1e-8 m^2/s^3 (the truth has none). The UKF keeps it and learns the unmodelled velocity
change only slowly; the AQUKF starts from the same value (its q_vel is the initial adaptive
q_vv) and raises q_vv when the state corrections outgrow the covariance. Both adaptation
laws are run: paper 001's window (``aq_law`` 1) and the NIS-gated default (``aq_law`` 2),
which raises q_vv only once the windowed normalised innovations exceed their chi-square
bound. (With paper 000's own Q, 0.3 m per step along-track, the position noise absorbs the
burn and every filter does equally well.)
"""

import numpy as np
import pytest
from fmpy import simulate_fmu

import cwtruth as cw
import relnav_fmu as rf

SEEDS = [0, 1, 2, 3]
Q_VV = ["q_vv_x", "q_vv_y", "q_vv_z"]
OUTPUTS = rf.OUTPUTS + Q_VV
TIMES = np.arange(cw.PAPER000_STEPS + 1, dtype=float)
THRUST = cw.burn_thrust(TIMES, 100.0, 160.0, [2.0, -1.0, 0.5])


@pytest.fixture(scope="module")
def not_told():
    return cw.paper000_scenario(2, thrust_io=THRUST, thrust_known=False)


def simulate(unzipdir, sc, params: dict, seed: int) -> np.ndarray:
    """(N+1, 15): the 12 outputs of rf.OUTPUTS and q_vv_x, q_vv_y, q_vv_z."""
    res = simulate_fmu(
        str(unzipdir),
        start_time=0.0,
        stop_time=float(sc.times[-1]),
        output_interval=1.0,
        input=rf.input_table(sc.times, sc.thrust, sc.measurements(seed), sc.valid),
        start_values={**sc.params, **params},
        output=OUTPUTS,
        fmi_type="CoSimulation",
    )
    assert np.allclose(res["time"], sc.times, rtol=0, atol=1e-9)
    return np.stack([res[name] for name in OUTPUTS], axis=1)


QUIET = {**{f"q_pos_{a}": 0.0 for a in "xyz"}, **{f"q_vel_{a}": 1e-8 for a in "xyz"}}


# "ukf", and the AQUKF with each law (looked up by name: aq_law is an issue-12 variable)
CASES = {"ukf": {"filter": 2}, "window": {"filter": 3, "aq_law": 1}, "gated": {"filter": 3, "aq_law": 2}}


@pytest.fixture(scope="module")
def runs(unzipdir, not_told):
    return {
        name: np.array([simulate(unzipdir, not_told, {**QUIET, **p, "window": 10}, s) for s in SEEDS])
        for name, p in CASES.items()
    }


@pytest.mark.parametrize("law", ["window", "gated"])
def test_aqukf_recovers_from_the_unreported_burn_better_than_the_ukf(runs, not_told, law):
    ukf = cw.accuracy(runs["ukf"][:, :, :6], not_told.truth_io, not_told.times, t_from=160.0)
    aq = cw.accuracy(runs[law][:, :, :6], not_told.truth_io, not_told.times, t_from=160.0)
    msg = f"UKF: {ukf.describe()}\nAQUKF ({law}): {aq.describe()}"
    # measured (4 seeds, 160-600 s), window / gated: position RMSE 0.15 / 0.11 m against
    # 0.99 m, worst position axis 0.36 / 0.25 m against 2.1 m, velocity RMSE 0.015 /
    # 0.0054 m/s against 0.026 m/s
    assert aq.pos_rmse < 0.3 * ukf.pos_rmse, msg
    assert aq.worst_axis[:3].max() < 0.5 * ukf.worst_axis[:3].max(), msg
    assert aq.vel_rmse < 0.75 * ukf.vel_rmse, msg


@pytest.mark.parametrize("law", ["window", "gated"])
def test_q_vv_outputs(runs, law):
    q = runs[law][:, :, 12:]
    assert np.all(np.isfinite(q)) and np.all(q >= 0.0)
    # starts at q_vel (1e-8 per axis), rises with the burn
    assert np.allclose(q[:, 0, :], 1e-8, rtol=1e-12)
    assert q[:, 100:200, :].max() > 100 * 1e-8
    if law == "gated":
        # never below the nominal q_vel
        assert q.min() >= 1e-8 * (1 - 1e-12)
    # the other filters have no adaptive noise: NaN
    assert np.all(np.isnan(runs["ukf"][:, :, 12:]))
