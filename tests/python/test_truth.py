"""Self-checks of the independent numpy truth model (tools/cwtruth.py); no FMU needed."""

import numpy as np
import pytest

import cwtruth as cw
import refekf

N = cw.PAPER000_N


def test_closed_form_satisfies_cw_equations():
    x0 = np.array([500.0, 400.0, -200.0, 0.1, -0.2, 0.05])
    t = np.linspace(0, 7200, 721)
    x = cw.cw_closed_form(N, x0, t)
    # derivative of the position is the velocity, and the velocity obeys CW (central differences)
    eps = 1e-3
    xp = cw.cw_closed_form(N, x0, t + eps)
    xm = cw.cw_closed_form(N, x0, t - eps)
    deriv = (xp - xm) / (2 * eps)
    expected = x @ cw.cw_a(N).T
    assert np.allclose(deriv, expected, rtol=0, atol=1e-8)
    assert np.allclose(x[0], x0, rtol=0, atol=1e-12)


def test_expm_matches_closed_form_and_rk4():
    x0 = np.array([500.0, 400.0, -200.0, 0.1, -0.2, 0.05])
    t = np.arange(0.0, 601.0)
    cf = cw.cw_closed_form(N, x0, t)
    e = cw.zoh_step_matrix(N, 600.0)
    assert np.allclose(e[:6, :6] @ x0, cf[-1], rtol=0, atol=1e-9)
    acc = cw.burn_thrust(t, 100, 160, [2e-3, -1e-3, 5e-4])
    ex = cw.truth_trajectory(N, x0, t, acc)
    rk = cw.rk4_trajectory(N, x0, t, acc, substeps=10)
    assert np.abs(ex - rk).max() < 1e-8
    # the burn matters: tens of metres by the end
    assert np.abs(ex - cf).max() > 10.0
    # one long step of a held acceleration = many short ones
    one = cw.zoh_step_matrix(N, 60.0)
    sixty = np.linalg.matrix_power(cw.zoh_step_matrix(N, 1.0), 60)
    assert np.allclose(one, sixty, rtol=1e-12, atol=1e-12)


def test_expm_against_series_definition():
    rng = np.random.default_rng(1)
    m = rng.standard_normal((5, 5)) * 0.3
    # exp(M) exp(-M) = I and exp(2M) = exp(M)^2
    assert np.allclose(cw.expm(m) @ cw.expm(-m), np.eye(5), atol=1e-13)
    assert np.allclose(cw.expm(2 * m), cw.expm(m) @ cw.expm(m), atol=1e-12)
    d = np.diag([0.1, -2.0, 3.0])
    assert np.allclose(cw.expm(d), np.diag(np.exp([0.1, -2.0, 3.0])), rtol=1e-14)


@pytest.mark.parametrize("frame", [1, 2, 3])
def test_frames_are_proper_rotations(frame):
    t = cw.FRAME_ROT[frame]
    assert np.allclose(t @ t.T, np.eye(3))
    assert np.isclose(np.linalg.det(t), 1.0)
    v = np.array([1.0, 2.0, 3.0])  # canonical radial, along, normal
    io = cw.vec_to_frame(v, frame)
    expected = {1: [1, 2, 3], 2: [2, 1, -3], 3: [2, -3, -1]}[frame]
    assert np.allclose(io, expected)
    assert np.allclose(cw.vec_to_canonical(io, frame), v)


def test_measure_roundtrip_and_ranges():
    rng = np.random.default_rng(2)
    p = rng.standard_normal((1000, 3)) * 300
    z = cw.measure(p)
    assert np.all((z[:, 1] >= 0) & (z[:, 1] < 2 * np.pi))
    assert np.all(np.abs(z[:, 2]) <= np.pi / 2)
    assert np.allclose(cw.meas_to_position(z), p, atol=1e-9)
    z0 = cw.measure(np.array([400.0, 500.0, 200.0]))
    assert np.isclose(z0[0], np.sqrt(400**2 + 500**2 + 200**2))
    assert np.isclose(np.rad2deg(z0[1]), 51.340191745909912)


def test_paper000_scenario_in_every_frame_is_one_physical_trajectory():
    ref = cw.paper000_scenario(2)
    for f in (1, 3):
        sc = cw.paper000_scenario(f)
        assert np.allclose(cw.state_to_canonical(sc.truth_io, f), cw.state_to_canonical(ref.truth_io, 2), atol=1e-9)
    # the truth at rest at (400, 500, 200) in frame 2 drifts by metres in 600 s
    assert np.allclose(ref.truth_io[0], cw.PAPER000_TRUTH0)
    assert np.abs(ref.truth_io[-1, :3] - ref.truth_io[0, :3]).max() > 10


def test_seeded_measurements_are_reproducible():
    sc = cw.paper000_scenario(2)
    a, b, c = sc.measurements(0), sc.measurements(0), sc.measurements(1)
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    resid = a - cw.measure(sc.truth_io[:-1, :3])
    assert abs(np.std(resid[:, 0]) - cw.PAPER000_SIGMA_RANGE) < 0.05


def test_reference_ekf_meets_the_bar_by_itself():
    """The numpy reference EKF (tools/refekf.py) is sound on its own: paper 000's bar."""
    sc = cw.paper000_scenario(2)
    est = np.array([refekf.run_ekf(sc.params, sc.times, sc.thrust, sc.measurements(s), sc.valid)[:, :6] for s in range(5)])
    acc = cw.accuracy(est, sc.truth_io, sc.times)
    assert acc.worst_axis[:3].max() < 0.6 and acc.pos_rmse < 0.4, acc.describe()
