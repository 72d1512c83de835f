"""The H-infinity filter's default (filter 9, issue 12) where nothing goes wrong, through
the FMU, against the EKF run on the same measurements.

Quiet Gaussian scenarios in frames 1-3 (different geometries, 0.7 to 5 km): 7200 s orbit,
radio 0.5 m / 0.01 deg at 1 Hz, 600 s, two burns the filter is told about, a 30 s dropout,
an initial error of 5 m / 0.1 m/s per axis. The truth (numpy, independent of relnav) has a
white acceleration of 1e-10 m^2/s^3 (exact discretisation: Van Loan with the matrix
exponential of tools/cwtruth.py) and the FMU's noise parameters match it (accel_psd =
1e-10, q_pos = q_vel = 0). Filter 9 runs with its defaults: the mixed H2/H-infinity
design, its noise model derived from those parameters, track initiation.

Then the same scenario with the true orbit rate 5 % off (the design's hinf_delta_bar),
where the robustness must show: the EKF, which trusts its nominal model, is several times
worse than the H-infinity filter.
"""

import numpy as np
import pytest

import cwtruth as cw

N = cw.PAPER000_N
PSD = 1e-10
STEPS = 600
SEEDS = [0, 1, 2, 3]
# canonical truth at t = 0 per I/O frame (frame 1: ~5 km; frame 2: paper 000's 670 m;
# frame 3: ~1.7 km)
GEOMETRY = {
    1: np.array([-2000.0, 4500.0, 1000.0, 0.0, 0.0, 0.0]),
    2: cw.state_to_canonical(np.array([400.0, 500.0, 200.0, 0.0, 0.0, 0.0]), 2),
    3: cw.state_to_canonical(np.array([1500.0, -300.0, 800.0, 0.0, 0.0, 0.0]), 3),
}
ERR0 = np.array([5.0, -5.0, 5.0, 0.1, -0.1, 0.1])
T_FROM = 100.0


def van_loan(n: float, h: float, q: float) -> np.ndarray:
    """Discrete covariance of a white acceleration of density q over h (Van Loan)."""
    a, g = cw.cw_a(n), cw.cw_b()
    m = np.zeros((12, 12))
    m[:6, :6] = -a
    m[:6, 6:] = q * g @ g.T
    m[6:, 6:] = a.T
    e = cw.expm(m * h)
    qd = e[6:, 6:].T @ e[:6, 6:]
    return 0.5 * (qd + qd.T)


def quiet_scenario(frame: int, seed: int, delta: float = 0.0):
    """(times, truth_io, thrust_io, meas, valid, params) of one seeded run."""
    rng = np.random.default_rng(1200 + seed)
    times = np.arange(STEPS + 1, dtype=float)
    thrust = cw.burn_thrust(times, 100.0, 120.0, [1.0, -0.5, 0.3]) + cw.burn_thrust(times, 400.0, 415.0, [-0.8, 0.6, -0.4])
    accel = cw.vec_to_canonical(thrust, frame) / 1000.0
    n_true = N * (1.0 + delta)
    step = cw.zoh_step_matrix(n_true, 1.0)
    chol = np.linalg.cholesky(van_loan(n_true, 1.0, PSD))
    x = np.empty((STEPS + 1, 6))
    x[0] = GEOMETRY[frame]
    z = np.zeros(9)
    for k in range(STEPS):
        z[:6], z[6:] = x[k], accel[k]
        x[k + 1] = (step @ z)[:6] + chol @ rng.standard_normal(6)
    truth = cw.state_to_frame(x, frame)
    meas = cw.add_noise(cw.measure(truth[:-1, :3]), cw.PAPER000_SIGMA_RANGE, cw.PAPER000_SIGMA_ANGLE, rng)
    valid = ~((times[:-1] >= 300.0) & (times[:-1] < 330.0))
    est0 = truth[0] + ERR0
    params = {"frame": frame, "mean_motion": N, "accel_psd": PSD}
    params.update({f"q_pos_{a}": 0.0 for a in "xyz"})
    params.update({f"q_vel_{a}": 0.0 for a in "xyz"})
    params.update({k: float(v) for k, v in zip(["x0", "y0", "z0", "vx0", "vy0", "vz0"], est0)})
    return times, truth, thrust, meas, valid, params


def rmse(runs: np.ndarray, truths: np.ndarray, times: np.ndarray, t_from: float = T_FROM):
    """Position and velocity RMSE over runs and t >= t_from."""
    sel = times >= t_from
    err = runs[:, sel, :6] - truths[:, sel]
    return (
        float(np.sqrt(np.mean(np.sum(err[..., :3] ** 2, axis=-1)))),
        float(np.sqrt(np.mean(np.sum(err[..., 3:] ** 2, axis=-1)))),
    )


@pytest.fixture(scope="module")
def quiet(runner):
    """frame -> (times, truths, {filter code: outputs}) over SEEDS, EKF (1) and filter 9
    with its defaults."""
    out = {}
    for frame in (1, 2, 3):
        runs = {1: [], 9: []}
        truths = []
        for seed in SEEDS:
            times, truth, thrust, meas, valid, params = quiet_scenario(frame, seed)
            truths.append(truth)
            for code in runs:
                runs[code].append(runner.run({**params, "filter": code}, times, thrust, meas, valid))
        out[frame] = (times, np.array(truths), {k: np.array(v) for k, v in runs.items()})
    return out


@pytest.mark.parametrize("frame", [1, 2, 3])
def test_default_hinf_costs_at_most_twice_the_ekf(quiet, frame):
    times, truths, runs = quiet[frame]
    ekf_p, ekf_v = rmse(runs[1], truths, times)
    hinf_p, hinf_v = rmse(runs[9], truths, times)
    msg = f"frame {frame}: EKF {ekf_p:.3f} m / {ekf_v:.2e} m/s, hinf {hinf_p:.3f} m / {hinf_v:.2e} m/s"
    # issue 12's target: within 2x the EKF's position RMSE (measured after 100 s: 1.12-1.53x;
    # the steady-state H2 norm of the certified gain is 1.65x the Kalman filter's, the price
    # of the 5 % orbit-rate robustness at hinf_gamma_factor 1.5)
    assert hinf_p < 2.0 * ekf_p, msg
    # velocity is not what the H2 criterion weighs (metres and m/s alike; the velocity error
    # is ~1e-4 m/s): measured 1.4-2.1x after 100 s
    assert hinf_v < 3.0 * ekf_v, msg
    # over the whole run, start and burns included, the track initiation keeps it at the EKF
    # (measured 1.00-1.02x)
    whole_p, _ = rmse(runs[9], truths, times, t_from=0.0)
    ekf_whole, _ = rmse(runs[1], truths, times, t_from=0.0)
    assert whole_p < 1.2 * ekf_whole, msg


def test_design_outputs(runner):
    times, truth, thrust, meas, valid, params = quiet_scenario(2, 0)
    runner.instantiate()
    try:
        runner.initialize({**params, "filter": 9})
        gamma, h2 = runner.fmu.getReal([runner.vr["hinf_gamma"], runner.vr["hinf_h2_norm"]])
        # the H2 norm with the derived noise model is the steady-state RMS prediction error:
        # a few centimetres here (measured 0.071 m); gamma is 1.5 times the optimum (~0.5)
        assert 0.02 < h2 < 0.2, h2
        assert 0.6 < gamma < 1.0, gamma
        certified = []
        for k in range(len(times) - 1):
            runner.fmu.setReal(runner._in_real, list(thrust[k]) + list(meas[k]))
            runner.fmu.setBoolean(runner._in_bool, [bool(valid[k])])
            runner.fmu.doStep(currentCommunicationPoint=times[k], communicationStepSize=1.0)
            certified.append(runner.fmu.getBoolean([runner.vr["hinf_certified"]])[0])
    finally:
        runner.free_instance()
    certified = np.array(certified)
    # track initiation first, the certified gain later (measured: from 244 s; it re-acquires
    # after the dropout at 300-330 s and hands over again)
    assert not certified[:50].any()
    assert certified[-50:].all()


def test_robust_to_the_orbit_rate_error(runner):
    """The truth's orbit rate 5 % above the nominal one the filters know."""
    ekf, hinf, truths = [], [], []
    for frame in (1, 2):
        for seed in SEEDS[:2]:
            times, truth, thrust, meas, valid, params = quiet_scenario(frame, seed, delta=0.05)
            truths.append(truth)
            ekf.append(runner.run({**params, "filter": 1}, times, thrust, meas, valid))
            hinf.append(runner.run({**params, "filter": 9}, times, thrust, meas, valid))
    truths = np.array(truths)
    for idx in ([0, 1], [2, 3]):
        e_p, _ = rmse(np.array(ekf)[idx], truths[idx], times, t_from=300.0)
        h_p, _ = rmse(np.array(hinf)[idx], truths[idx], times, t_from=300.0)
        # measured (t >= 300 s): EKF 8.1 m / hinf 2.0 m at 5 km, 1.4 m / 0.45 m at 670 m
        assert h_p < 0.5 * e_p, f"EKF {e_p:.2f} m, hinf {h_p:.2f} m"


@pytest.mark.parametrize(
    "params,name",
    [
        ({"hinf_gamma_factor": 1.0}, "hinf_gamma_factor"),
        ({"hinf_b_pos": 0.05}, "hinf_b_vel"),  # set together or derived together
        ({"accel_psd": 0.0, **{f"q_{k}_{a}": 0.0 for k in ("pos", "vel") for a in "xyz"}}, "accel_psd"),
    ],
)
def test_bad_mixed_design_parameters_are_refused(runner, params, name):
    from fmpy.fmi1 import FMICallException

    runner.log.records.clear()
    runner.instantiate(logging_on=True)
    try:
        with pytest.raises(FMICallException):
            runner.initialize({"filter": 9, **params})
        assert name in runner.log.text(), runner.log.text()
    finally:
        runner.free_instance()
