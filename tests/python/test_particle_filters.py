"""The particle filters (filter codes 4-8) through the FMU against the independent numpy
truth (tools/cwtruth.py), judged against the EKF run with the same parameters on the same
measurements (issue 10).

Scenario family (cwtruth.family_scenario): paper 000's geometry and radio sensor in each
of the three frames, a 60 s burn known through the thrust inputs, a 30 s dropout, 600 s
at 1 Hz; the filters' process noise either the FMU defaults (paper 000's Q) or honest for
the quiet truth (a white acceleration of 1e-10 m^2/s^3, nothing else); 500 particles (a
third of the FMU's default count: the particle prior needs tens, docs/results.md).
Error statistics over t >= 80 s (the outputs are the FMU's predictions at t + 1).

The margins are issue 10's: every particle filter, in every run, within 1.3 times the
EKF's position RMSE and 2 times its velocity RMSE on Gaussian noise, and at least 15 %
below the EKF's position RMSE with paper 003's contaminated Gaussian (which the EKF can
only model by its variance); on paper 000's own example the paper's < 0.4 m and
< 0.02 m/s. Each run is one seed (measurement noise and particle-filter seed); the cases
use different seeds. The particle filters run at the FMU's defaults but for the count
(since 7 December 2026 the particle prior, ``pf_prior`` = 2: a Gaussian per particle). The literal SIR (point
particles, ``pf_prior`` = 1, with ``pf_move`` = false) is run on one honest-noise case to
show what the margins catch.

The runs go through fmpy's FMU2Slave on two worker processes (the whole module: about
two minutes of CPU).
"""

from __future__ import annotations

import multiprocessing as mp

import numpy as np
import pytest
from fmpy import simulate_fmu

import cwtruth as cw
import relnav_fmu as rf

PARTICLES = 500
T_FROM = 80.0
PF = {"pf": 4, "rpf": 5, "upf": 6, "gapf": 7, "cgapf": 8}
CODES = {"ekf": 1, **PF}
REKF = 11
# (key, frame, small_q, mixture, seed): the Gaussian family in three frames with both
# process-noise settings, the heavy-tailed family in two frames, paper 000's example
GAUSSIAN = [(f"gauss-f{f}-{'small' if q else 'fmu'}", f, q, False, s) for s, (f, q) in enumerate([(1, True), (2, True), (3, True), (1, False), (2, False), (3, False)])]
HEAVY = [("mix-f2-small", 2, True, True, 6), ("mix-f3-fmu", 3, False, True, 7)]
PAPER000 = [("paper000", 2, False, False, s) for s in (8, 9)]
LITERAL = ("gauss-f1-small", "pf-literal")

_worker = {}


def _init(unzipdir):
    _worker["runner"] = rf.SlaveRunner(unzipdir)


def _run(job):
    try:
        return _run_job(job)
    except Exception as e:  # noqa: BLE001
        # re-raised as an exception the pool can send back: fmpy's FMICallException does
        # not unpickle (its constructor takes two arguments), which kills the pool's
        # result thread and leaves map() waiting forever
        raise RuntimeError(f"{job[:6]}: {type(e).__name__}: {e}") from None


def _run_job(job):
    key, frame, small_q, mixture, seed, name, extra = job
    sc = cw.paper000_scenario(2) if key == "paper000" else cw.family_scenario(frame, small_q, mixture)
    params = {**sc.params, "filter": REKF if name == "rekf" else CODES[name], "seed": seed, "particles": PARTICLES, **extra}
    out = _worker["runner"].run(params, sc.times, sc.thrust, sc.measurements(seed), sc.valid)
    sel = sc.times >= T_FROM
    err = out[:, :6] - sc.truth_io
    finite = bool(np.all(np.isfinite(out[:, :12])))
    pos = float(np.sqrt(np.mean(np.sum(err[sel, :3] ** 2, axis=-1))))
    vel = float(np.sqrt(np.mean(np.sum(err[sel, 3:] ** 2, axis=-1))))
    return (key, name if not extra else f"{name}-literal"), (pos, vel, finite)


@pytest.fixture(scope="module")
def rmse(unzipdir):
    """(case, filter) -> (position RMSE, velocity RMSE, all outputs finite)."""
    jobs = [(k, f, q, m, s, name, {}) for (k, f, q, m, s) in GAUSSIAN + HEAVY + PAPER000 for name in CODES]
    # the robust EKF (filter 11) on the heavy-tailed cases
    jobs += [(k, f, q, m, s, "rekf", {}) for (k, f, q, m, s) in HEAVY]
    k, f, q, m, s = GAUSSIAN[0]
    assert k == LITERAL[0]
    jobs.append((k, f, q, m, s, "pf", {"pf_prior": 1, "pf_move": False}))
    # the slow unscented runs first, so the two workers finish together
    jobs.sort(key=lambda j: j[5] not in ("upf", "cgapf"))
    with mp.get_context("fork").Pool(2, initializer=_init, initargs=(str(unzipdir),)) as pool:
        return dict(pool.map(_run, jobs, chunksize=1))


def _ratios(rmse, key):
    ekf_p, ekf_v, _ = rmse[(key, "ekf")]
    return {n: (rmse[(key, n)][0] / ekf_p, rmse[(key, n)][1] / ekf_v) for n in PF}


@pytest.mark.parametrize("case", GAUSSIAN, ids=[c[0] for c in GAUSSIAN])
def test_gaussian_noise_every_particle_filter_matches_the_ekf(rmse, case):
    key = case[0]
    report = {n: f"{p:.2f} / {v:.2f}" for n, (p, v) in _ratios(rmse, key).items()}
    for name in PF:
        pos, vel, finite = rmse[(key, name)]
        ekf_p, ekf_v, _ = rmse[(key, "ekf")]
        assert finite, f"{key} {name}: non-finite outputs"
        assert pos < 1.3 * ekf_p and vel < 2.0 * ekf_v, (
            f"{key} {name}: position {pos:.4f} m, velocity {vel:.6f} m/s; EKF {ekf_p:.4f} m, "
            f"{ekf_v:.6f} m/s; ratios (pos / vel) to the EKF: {report}"
        )


def test_literal_sir_degenerates_with_honest_noise(rmse):
    """Without its moves the SIR of point particles degenerates with small process noise (measured 190-375
    times the EKF's position error, issue 10): the margins above catch it."""
    pos, _, _ = rmse[LITERAL]
    ekf_p, _, _ = rmse[(LITERAL[0], "ekf")]
    assert pos > 3.0 * ekf_p, f"literal SIR {pos:.3f} m vs EKF {ekf_p:.3f} m"


@pytest.mark.parametrize("case", HEAVY, ids=[c[0] for c in HEAVY])
def test_heavy_tails_every_particle_filter_beats_the_ekf(rmse, case):
    key = case[0]
    ekf_p, _, _ = rmse[(key, "ekf")]
    for name in PF:
        pos, _, finite = rmse[(key, name)]
        assert finite, f"{key} {name}: non-finite outputs"
        assert pos < 0.85 * ekf_p, f"{key} {name}: position {pos:.4f} m vs EKF {ekf_p:.4f} m"


@pytest.mark.parametrize("case", HEAVY, ids=[c[0] for c in HEAVY])
def test_heavy_tails_robust_ekf_beats_the_ekf_and_matches_the_particle_filters(rmse, case):
    """The robust EKF (filter 11, the mixture's Gaussian-sum update) through the FMU: at
    least 15 % below the EKF's position RMSE and within 1.15 times every particle
    filter's."""
    key = case[0]
    ekf_p, _, _ = rmse[(key, "ekf")]
    pos, _, finite = rmse[(key, "rekf")]
    assert finite and pos < 0.85 * ekf_p, f"{key}: REKF {pos:.4f} m vs EKF {ekf_p:.4f} m"
    for name in PF:
        assert pos < 1.15 * rmse[(key, name)][0], f"{key}: REKF {pos:.4f} m vs {name} {rmse[(key, name)][0]:.4f} m"


@pytest.mark.parametrize("name", list(PF))
def test_paper000_bar_met(rmse, name):
    """Paper 000's example at the FMU defaults: < 0.4 m and < 0.02 m/s after 80 s, in every
    run (tools/paper000_fmu.py prints the 10-run table)."""
    for key, *_, seed in PAPER000:
        pos, vel, finite = rmse[(key, name)]
        assert finite and pos < cw.BAR_POS_RMSE and vel < cw.BAR_VEL_RMSE, (key, seed, name, pos, vel)


def test_same_seed_reproduces_and_ess_is_output(unzipdir):
    """Identical seed: bit-identical outputs (ess and pf_acceptance included) from two
    simulate_fmu runs; a different seed: different outputs. ess is the effective sample
    size of the particle filter, in [1, particles], and NaN for the EKF; pf_acceptance the
    fraction of the step's moves accepted, in [0, 1] once the particles move (NaN before,
    with the first update drawing them from the measurement) and NaN for the EKF."""
    sc = cw.paper000_scenario(2, times=np.arange(151.0))
    outputs = rf.OUTPUTS + ["ess", "pf_acceptance"]

    def simulate(params):
        res = simulate_fmu(
            str(unzipdir),
            start_time=0.0,
            stop_time=150.0,
            output_interval=1.0,
            input=rf.input_table(sc.times, sc.thrust, sc.measurements(0), sc.valid),
            start_values={**sc.params, **params},
            output=outputs,
            fmi_type="CoSimulation",
        )
        return np.stack([res[n] for n in outputs], axis=1)

    # point particles (pf_prior = 1): pf_acceptance is their moves'
    params = {"filter": 5, "pf_prior": 1, "particles": 500, "seed": 7}
    a, b, c = simulate(params), simulate(params), simulate({**params, "seed": 8})
    assert np.array_equal(a, b, equal_nan=True)
    assert not np.array_equal(a[:, :6], c[:, :6])
    ess = a[:, 12]
    assert np.all((ess >= 1.0) & (ess <= 500.0)) and len(np.unique(ess)) > 10, ess
    assert ess[0] == 500.0  # equal weights before the first update
    acc = a[3:, 13]
    assert np.all((acc >= 0.0) & (acc <= 1.0)) and len(np.unique(acc)) > 10, a[:, 13]
    ekf = simulate({"filter": 1})
    assert np.all(np.isnan(ekf[:, 12])) and np.all(np.isnan(ekf[:, 13]))
    assert np.all(np.isfinite(ekf[:, :12]))
