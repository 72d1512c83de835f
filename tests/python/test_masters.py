"""relnav.fmu in FMI masters that others wrote: libcosim (``libcosimpy``) and Ecos
(``ecospy``) set every kind of parameter (Real, Integer, Boolean, and every code of the
Integer parameters that select a method: filter, frame, discretization, resampler,
noise_model) through their own APIs and give the same outputs as fmpy, bit for bit. A
refused parameter surfaces in each master as an error the master reports.

One simulation per master holds every case (one instance each), so each master loads
the FMU once; 30 steps of 1 s with a burn and measurement dropouts.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description

import cwtruth as cw
import relnav_fmu as rf
import relnav_masters as rm

TOOLS = Path(__file__).resolve().parents[2] / "tools"
TIMES = np.arange(31, dtype=float)
DROPOUTS = [3, 4, 12, 22]
# non-default values of each parameter kind, in every case
COMMON = {"sigma_pos0": 60.0, "sigma_range": 0.55, "seed": 11, "particles": 200}


@pytest.fixture(scope="module")
def md(unzipdir):
    return read_model_description(str(unzipdir))


def scenario_inputs(frame: int):
    """Paper 000's geometry in ``frame``: a 10-s burn (the filter is told), noisy
    measurements with dropouts."""
    sc = cw.paper000_scenario(frame, times=TIMES, thrust_io=cw.burn_thrust(TIMES, 10, 20, [1.0, -2.0, 0.5]))
    valid = np.ones(len(TIMES) - 1, dtype=bool)
    valid[DROPOUTS] = False
    return sc, sc.measurements(seed=frame), valid


@pytest.fixture(scope="module")
def cases(md):
    """Every code of every code parameter (given by item name), plus a Boolean start
    value, over the parameter kinds in COMMON."""
    codes = rf.codes(md)
    # the camera's and GNSS's densities act only on their readings, which these radio
    # cases do not carry (test_sensors.py drives them through fmpy)
    sensor_codes = {"camera_noise_model", "gnss_noise_model"}
    assert set(codes) == {"filter", "frame", "discretization", "resampler", "noise_model", "hinf_design", "aq_law", "pf_prior"} | sensor_codes
    out = []

    def case(name, frame=2, valid=True, **params):
        sc, z, v = scenario_inputs(frame)
        p = {**sc.params, **COMMON, **params}
        out.append(rm.Case(name, p, sc.times, sc.thrust, z, v if valid else None))

    for name in codes["filter"]:
        extra = {"hinf_period": 1.0} if name == "hinf" else {}
        extra |= {"window": 5} if name == "aqukf" else {}
        case(f"filter_{name}", filter=name, **extra)
    for name, code in codes["frame"].items():
        case(f"frame_{name}", frame=code, filter="ukf")
    for name in codes["discretization"]:
        case(f"discretization_{name}", filter="ekf", discretization=name)
    for name in codes["resampler"]:
        case(f"resampler_{name}", filter="pf", resampler=name)
    for name in codes["noise_model"]:
        case(f"noise_{name}", filter="rpf", noise_model=name, noise_zeta=0.1, noise_scale=8.0, noise_dof=5.0)
    for name in codes["hinf_design"]:
        case(f"hinf_design_{name}", filter="hinf", hinf_period=1.0, hinf_design=name)
    for name in codes["aq_law"]:
        case(f"aq_law_{name}", filter="aqukf", window=5, aq_law=name, aq_gate_window=4)
    # Boolean: measurement_valid starts true and is never driven: every step updates
    case("boolean_start", filter="ekf", valid=False, measurement_valid=True)
    return out


@pytest.fixture(scope="module")
def reference(runner, cases):
    return rm.run_fmpy(runner, cases)


def assert_bit_identical(ref: dict, got: dict, master: str):
    assert set(got) == set(ref)
    bad = []
    for name, r in ref.items():
        g = got[name]
        assert g.shape == r.shape, (master, name)
        if not np.array_equal(r.view(np.uint64), g.view(np.uint64)):
            k = int(np.argwhere(r.view(np.uint64) != g.view(np.uint64))[0][0])
            bad.append(f"{name}: first difference after step {k + 1}: fmpy {r[k][:3]} vs {master} {g[k][:3]}")
    assert not bad, f"{master} differs from fmpy:\n" + "\n".join(bad)


def test_reference_cases_differ(reference, cases):
    """Each setting changes the outputs (so a master that dropped it would be caught)."""
    by_name = {c.name: reference[c.name] for c in cases}
    default_like = by_name["filter_ekf"]
    for name, out in by_name.items():
        assert np.all(np.isfinite(out[:, :6])), name
        if name not in ("filter_ekf", "discretization_exact", "frame_along_radial_antinormal"):
            assert not np.array_equal(out, default_like), f"{name} gives the EKF's outputs"
    assert not np.array_equal(by_name["frame_along_radial_antinormal"], by_name["frame_radial_along_normal"])


def test_libcosim_sets_every_parameter_and_matches_fmpy(fmu_path, md, cases, reference, tmp_path):
    got = rm.run_libcosim(fmu_path, md, cases, tmp_path)
    assert_bit_identical(reference, got, "libcosim")


def test_ecos_sets_every_parameter_and_matches_fmpy(fmu_path, md, cases, reference):
    got = rm.run_ecos(fmu_path, md, cases)
    assert_bit_identical(reference, got, "Ecos")


# ---------------------------------------------------------------------------- errors
# (parameters, what the FMU logs): refused when set (Real, Integer, code) or at
# fmi2ExitInitializationMode (a combination)
REFUSED = [
    ({"chaser_mass": 0.0}, "fmi2SetReal: chaser_mass = 0 refused: chaser_mass must be finite and > 0"),
    ({"particles": 0}, "fmi2SetInteger: particles = 0 refused: particles must lie in 1..="),
    ({"filter": 12}, "fmi2SetInteger: filter = 12 is not a Filter code (allowed: 1 ekf, 2 ukf"),
    ({"hinf_period": 1000.0}, "invalid parameters: hinf_*: w0 * period = "),
]
# refused at fmi2DoStep: the H-infinity filter designed for 2 s, stepped by 1 s
STEP_REFUSED = ({"filter": 9, "hinf_period": 2.0}, "fmi2DoStep at t = 0: the hinf filter was designed for hinf_period = 2 s")

LIBCOSIM_CHILD = """
import json, sys
sys.path.insert(0, {tools!r})
from fmpy import read_model_description
import relnav_masters as rm
md = read_model_description({unzipdir!r})
out = rm.cosim_single({fmu!r}, md, json.loads(sys.argv[1]), 3, {workdir!r})
print("RESULT " + json.dumps(out), flush=True)
"""


def libcosim_child(fmu_path, unzipdir, tmp_path, params):
    script = LIBCOSIM_CHILD.format(tools=str(TOOLS), unzipdir=str(unzipdir), fmu=str(fmu_path), workdir=str(tmp_path))
    import json

    return subprocess.run(
        [sys.executable, "-c", script, json.dumps(params)], capture_output=True, text=True, timeout=300
    )


@pytest.mark.parametrize("params,reason", REFUSED, ids=[next(iter(p)) for p, _ in REFUSED])
def test_libcosim_reports_a_refused_parameter_and_aborts(fmu_path, unzipdir, tmp_path, params, reason):
    """libcosim applies initial values and calls fmi2ExitInitializationMode in a worker
    thread at the first step and does not catch the error it raises: the process aborts
    (SIGABRT), and the user sees the FMU's reason on stderr in the uncaught cosim::error
    (libcosim's own error log line is lost when stderr is a pipe: it is not flushed
    before the abort)."""
    child = libcosim_child(fmu_path, unzipdir, tmp_path, params)
    assert child.returncode == -6, (child.returncode, child.stdout, child.stderr)
    assert "RESULT" not in child.stdout
    assert f"what():  Model error: {reason}" in child.stderr, child.stderr


def test_libcosim_reports_a_refused_step(fmu_path, unzipdir, tmp_path):
    """fmi2Error from fmi2DoStep: libcosim's step() returns false, time stays, and the
    last error message carries the FMU's reason; the process goes on."""
    import json

    params, reason = STEP_REFUSED
    child = libcosim_child(fmu_path, unzipdir, tmp_path, params)
    assert child.returncode == 0, child.stderr
    out = json.loads(child.stdout.split("RESULT ", 1)[1])
    assert out["set"] == [True, True]
    assert out["steps"] == [False, False, False] and out["time_ns"] == 0
    assert out["errors"][0].startswith(f"Simulation error: B: Model error: {reason}"), out
    assert "illegal call sequence" in out["errors"][1]
    assert out["x"] == [405.0] * 3


@pytest.mark.parametrize("params,reason", [*REFUSED, STEP_REFUSED], ids=[*(next(iter(p)) for p, _ in REFUSED), "step"])
def test_ecos_ignores_errors_and_logs_them_at_debug(fmu_path, md, capfd, params, reason):
    """Ecos ignores fmi2Error from every call (init() returns true, steps go on, the
    outputs stay at the initial estimate) and shows the FMU's reason only at log level
    debug; the FMU's fmi_status output says 3."""
    from ecospy import EcosLib

    EcosLib.set_log_level("debug")
    try:
        out = rm.ecos_single(fmu_path, md, params, 3)
    finally:
        EcosLib.set_log_level("warn")
    log = capfd.readouterr()
    assert out["init"] is True and out["error"] == ""
    assert out["x"] == [405.0] * 3, out
    assert out["fmi_status"] == 3
    assert "[debug]" in log.out and f"fmi2Error {reason}" in log.out, log.out[-2000:]
    if "particles" in params:  # and nothing at the default level (once is enough)
        out = rm.ecos_single(fmu_path, md, params, 1)
        assert "fmi2Error" not in capfd.readouterr().out and out["fmi_status"] == 3
