"""Issue 12: the adaptive filters through the FMU, against the independent numpy truth
(tools/cwtruth.py), with the process noise every filter is told equal to what the truth
really has: a white acceleration of 1e-8 m^2/s^3 (exact Van Loan noise in the truth,
``accel_psd`` in the filters, no ``q_pos``/``q_vel``). Paper 000's geometry and radio
sensor (0.5 m, 0.01 deg at 1 Hz), 600 s, six seeded runs per case.

* Quiet (nothing the filters are not told), frames 1-3, and frame 2 with a known burn
  ((2, -1, 0.5) N, 100-160 s, in the thrust inputs) and a measurement dropout (300-360 s):
  the NIS-gated AQUKF (filter 3, ``aq_law`` 2, the default) and the IMM (filter 10) cost at
  most 1.2x the UKF's position and velocity RMSE over t >= 100 s (issue 12's bar; the UKF
  and EKF run in the same test). Paper 001's window
  law (``aq_law`` 1) is measured beside them and reported, not held to the bar: it pays for
  the scatter of its estimate (docs/filters.md, "AQUKF").
* Unreported burns (the filters are told no thrust): a 60 s burn of (2, -1, 0.5) N on the
  1000 kg chaser in frame 2, and two burns of (0.5, -1, 0.3) N (30 s) and (-1, 0, 0.5) N
  (10 s) on a 100 kg chaser in frame 3. Every adaptive filter's position RMSE from the first
  burn on is at most half the UKF's (issue 12's bar), and it is back below 1 m (twice the
  range noise) after each burn no later than the UKF.
* Honest small noise (the quiet truth's 1e-10 m^2/s^3): paper 000's geometry with a known
  burn, with and without a 30 s dropout, frames 1-3: the gated AQUKF and the IMM at most
  1.25x the UKF's position and velocity RMSE. A third unreported-burn case: 2 N for 60 s,
  then 1.4 N for 30 s, on 400 kg in frame 1.
* The outputs: ``imm_mu_*`` sum to one and follow the burn; ``q_vv_*`` of the gated AQUKF
  stay at their nominal value while nothing happens. New variables are looked up by name.

Run with ``pytest -s`` to see the measured table.
"""

import numpy as np
import pytest

import cwtruth as cw
import relnav_fmu as rf

PSD = 1e-8
SEEDS = list(range(6))
T_FROM = 100.0
EXTRA = ["q_vv_x", "q_vv_y", "q_vv_z", "imm_mu_1", "imm_mu_2", "imm_mu_3"]
OUT = rf.OUTPUTS + EXTRA
Q_VV = slice(12, 15)
MU = slice(15, 18)
FILTERS = {
    "ekf": {"filter": 1},
    "ukf": {"filter": 2},
    "aqukf_gated": {"filter": 3, "aq_law": 2},
    "aqukf_window": {"filter": 3, "aq_law": 1},
    "imm": {"filter": 10},
}
ADAPTIVE = ["aqukf_gated", "aqukf_window", "imm"]
TIMES = np.arange(cw.PAPER000_STEPS + 1, dtype=float)


@pytest.fixture(scope="module")
def mrunner(unzipdir):
    r = rf.SlaveRunner(unzipdir, outputs=OUT)
    yield r
    r.close()


def campaign(runner, scenarios, params: dict) -> np.ndarray:
    """(runs, N+1, len(OUT)) for one filter over the seeded scenarios."""
    outs = []
    for seed, sc in zip(SEEDS, scenarios):
        outs.append(runner.run({**sc.params, **params}, sc.times, sc.thrust, sc.measurements(seed), sc.valid))
    return np.array(outs)


def test_van_loan_noise_is_the_double_integrators_at_small_rate():
    """The truth's discrete noise: Van Loan for CW tends to the double integrator's
    [[h^3/3, h^2/2], [h^2/2, h]] psd as n h -> 0."""
    h, psd = 2.0, 3e-8
    q = cw.van_loan_q(1e-9, psd, h)
    want = np.zeros((6, 6))
    for i in range(3):
        want[i, i] = psd * h**3 / 3
        want[i, i + 3] = want[i + 3, i] = psd * h**2 / 2
        want[i + 3, i + 3] = psd * h
    # coupling terms are O(n h) relative (2e-9 here)
    assert np.allclose(q, want, rtol=1e-6, atol=1e-8 * psd)


# --------------------------------------------------------------------------- quiet


QUIET = [1, 2, 3, "2+burn+dropout"]


def quiet_scenario(case, seed: int) -> cw.Scenario:
    if case == "2+burn+dropout":
        thrust = cw.burn_thrust(TIMES, 100.0, 160.0, [2.0, -1.0, 0.5])
        sc = cw.noisy_scenario(2, PSD, seed, thrust_io=thrust, thrust_known=True)
        sc.valid = ~((TIMES[:-1] >= 300.0) & (TIMES[:-1] < 360.0))
        return sc
    return cw.noisy_scenario(case, PSD, seed)


@pytest.fixture(scope="module")
def quiet(mrunner):
    """case -> (truths (runs, N+1, 6), {filter: outputs})."""
    out = {}
    for case in QUIET:
        scs = [quiet_scenario(case, s) for s in SEEDS]
        truth = np.array([sc.truth_io for sc in scs])
        out[case] = (truth, {name: campaign(mrunner, scs, p) for name, p in FILTERS.items()})
    return out


def quiet_ratios(quiet, frame, name):
    truth, res = quiet[frame]
    up, uv = cw.rmse_between(res["ukf"], truth, TIMES, T_FROM)
    p, v = cw.rmse_between(res[name], truth, TIMES, T_FROM)
    return p / up, v / uv, p, v


def test_quiet_table(quiet):
    """Print the issue's quiet table (ratios to the UKF); the EKF and UKF agree (the
    dynamics are linear, the measurement nearly so at 0.01 deg)."""
    lines = ["quiet, t >= 100 s: position / velocity RMSE over the UKF's"]
    for frame in QUIET:
        row = [f"frame {frame}:"]
        for name in ["ekf"] + ADAPTIVE:
            rp, rv, p, v = quiet_ratios(quiet, frame, name)
            row.append(f"{name} {rp:.3f} / {rv:.3f} ({p:.4f} m, {v:.5f} m/s)")
        lines.append("  ".join(row))
    print("\n" + "\n".join(lines))
    for frame in QUIET:
        rp, rv, _, _ = quiet_ratios(quiet, frame, "ekf")
        assert abs(rp - 1.0) < 0.02 and abs(rv - 1.0) < 0.02, f"frame {frame}: EKF/UKF {rp}, {rv}"


@pytest.mark.parametrize("frame", QUIET)
@pytest.mark.parametrize("name", ["aqukf_gated", "imm"])
def test_quiet_cost_within_1_2_of_the_ukf(quiet, frame, name):
    rp, rv, p, v = quiet_ratios(quiet, frame, name)
    msg = f"frame {frame}, {name}: {p:.4f} m, {v:.5f} m/s = {rp:.3f} / {rv:.3f} of the UKF"
    assert rp <= 1.2, msg
    assert rv <= 1.2, msg


def test_gated_q_vv_stays_nominal_while_quiet(quiet):
    """q_vel is 0 here (the noise is all in accel_psd): the gated law's q_vv is 0 unless its
    gate opens, which a consistent filter does in about one test of 1000."""
    for frame in QUIET:
        q = quiet[frame][1]["aqukf_gated"][:, 1:, Q_VV]
        assert np.all(np.isfinite(q)) and np.all(q >= 0.0)
        assert np.mean(np.all(q == 0.0, axis=-1)) > 0.98, f"frame {frame}"
        # the window law's q_vv wanders (the scatter it pays for)
        assert np.mean(np.all(quiet[frame][1]["aqukf_window"][:, 1:, Q_VV] == 0.0, axis=-1)) < 0.5


# --------------------------------------------------------------------------- burns

BURNS = {
    # frame, chaser mass, [(start, stop, force)]
    "frame2_1000kg": (2, 1000.0, [(100.0, 160.0, [2.0, -1.0, 0.5])]),
    "frame3_100kg": (3, 100.0, [(200.0, 230.0, [0.5, -1.0, 0.3]), (400.0, 410.0, [-1.0, 0.0, 0.5])]),
    # 2 N for 60 s, then 1.4 N for 30 s, on 400 kg
    "frame1_400kg": (1, 400.0, [(100.0, 160.0, [1.75, -0.87, 0.44]), (300.0, 330.0, [-1.25, 0.0, 0.63])]),
}


# ------------------------------------------------------------- honest small noise

# the quiet family with the honest noise of a quiet truth (1e-10 m^2/s^3, tools/cwtruth.py
# SMALL_Q): paper 000's geometry, a known 60 s burn, with and without a 30 s dropout
SMALL_FAMILY = [(frame, drop) for frame in (1, 2, 3) for drop in (False, True)]


@pytest.fixture(scope="module")
def small_family(mrunner):
    out = {}
    for frame, drop in SMALL_FAMILY:
        sc = cw.family_scenario(frame, small_q=True)
        if not drop:
            sc.valid = np.ones_like(sc.valid)
        res = {n: campaign(mrunner, [sc] * len(SEEDS), FILTERS[n]) for n in ["ukf", "aqukf_gated", "imm"]}
        out[(frame, drop)] = (sc, res)
    return out


@pytest.mark.parametrize("case", SMALL_FAMILY)
@pytest.mark.parametrize("name", ["aqukf_gated", "imm"])
def test_imm_quiet_family_with_honest_small_noise(small_family, case, name):
    """With a known burn, a dropout or neither, and the honest 1e-10 m^2/s^3 of a quiet
    truth, the adaptive filters cost at most 1.25x the UKF's position and velocity RMSE
    over t >= 80 s. The IMM's quiet mode must be sticky enough that the burn mode's
    covariance, mixed in, does not act as added process noise (docs/filters.md, "IMM")."""
    sc, res = small_family[case]
    up, uv = cw.rmse_between(res["ukf"], sc.truth_io, sc.times, cw.BAR_T_FROM)
    p, v = cw.rmse_between(res[name], sc.truth_io, sc.times, cw.BAR_T_FROM)
    msg = f"{case}, {name}: {p:.4f} m, {v:.6f} m/s = {p / up:.3f} / {v / uv:.3f} of the UKF"
    print(msg)
    assert p <= 1.25 * up, msg
    assert v <= 1.25 * uv, msg


@pytest.fixture(scope="module")
def burns(mrunner):
    """case -> (truths, {filter: outputs}) with the filters told no thrust."""
    out = {}
    for case, (frame, mass, windows) in BURNS.items():
        thrust = sum(cw.burn_thrust(TIMES, a, b, f) for a, b, f in windows)
        scs = [cw.noisy_scenario(frame, PSD, s, thrust_io=thrust, thrust_known=False, chaser_mass=mass) for s in SEEDS]
        truth = np.array([sc.truth_io for sc in scs])
        out[case] = (truth, {n: campaign(mrunner, scs, FILTERS[n]) for n in ["ukf"] + ADAPTIVE})
    return out


def burn_figures(burns, case, name):
    truth, res = burns[case]
    windows = BURNS[case][2]
    p, v = cw.rmse_between(res[name], truth, TIMES, windows[0][0])
    rec = []
    for i, (_, stop, _) in enumerate(windows):
        until = windows[i + 1][0] if i + 1 < len(windows) else np.inf
        rec.append(cw.recovery_time(res[name], truth, TIMES, stop, 1.0, until))
    return p, v, rec


def test_burn_table(burns):
    lines = ["unreported burns: position RMSE from the first burn on over the UKF's; recovery below 1 m [s]"]
    for case in BURNS:
        up, uv, urec = burn_figures(burns, case, "ukf")
        row = [f"{case}: ukf {up:.3f} m {uv:.4f} m/s rec {urec}"]
        for name in ADAPTIVE:
            p, v, rec = burn_figures(burns, case, name)
            row.append(f"{name} {p / up:.3f} / {v / uv:.3f} ({p:.3f} m) rec {rec}")
        lines.append("  ".join(row))
    print("\n" + "\n".join(lines))


@pytest.mark.parametrize("case", list(BURNS))
@pytest.mark.parametrize("name", ADAPTIVE)
def test_unreported_burns_at_least_twice_better_than_the_ukf(burns, case, name):
    up, _, urec = burn_figures(burns, case, "ukf")
    p, _, rec = burn_figures(burns, case, name)
    msg = f"{case}, {name}: {p:.3f} m against the UKF's {up:.3f} m; recovery {rec} against {urec}"
    assert p <= 0.5 * up, msg
    for r, u in zip(rec, urec):
        # back below 1 m, and no later than the UKF (NaN: never)
        assert np.isfinite(r), msg
        assert np.isnan(u) or r <= u, msg


def test_imm_mode_probabilities_follow_the_burns(burns):
    """imm_mu_* sum to one; the quiet mode holds before the first burn, the manoeuvring
    modes take over during it; every other filter reports NaN."""
    truth, res = burns["frame3_100kg"]
    mu = res["imm"][:, :, MU]
    assert np.allclose(mu.sum(axis=-1), 1.0, atol=1e-12)
    assert np.all((mu >= 0.0) & (mu <= 1.0))
    quiet = (TIMES >= 100.0) & (TIMES < 200.0)
    during = (TIMES >= 205.0) & (TIMES < 230.0)
    assert mu[:, quiet, 0].mean() > 0.9, mu[:, quiet].mean(axis=(0, 1))
    assert (mu[:, during, 1] + mu[:, during, 2]).mean() > 0.5, mu[:, during].mean(axis=(0, 1))
    for name in ["ukf", "aqukf_gated"]:
        assert np.all(np.isnan(res[name][:, :, MU])), name
    q = res["aqukf_gated"][:, :, Q_VV]
    assert q[:, (TIMES >= 200.0) & (TIMES < 240.0)].max() > 0.0
