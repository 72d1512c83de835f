"""The Python package relnav (python/, PyO3): its parameters are the FMU's (one variable
table), bad arguments raise the library's errors with its message, the type stubs list
the current parameters, and the README example runs.

The package is installed into .venv by scripts/setup.sh (``pip install ./python``)."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import relnav
import relnav_fmu as rf
from conftest import REPO_ROOT
from fmpy import read_model_description

STUB = REPO_ROOT / "python" / "relnav" / "_relnav.pyi"
EXAMPLE = REPO_ROOT / "examples" / "relnav_python_quickstart.py"

# paper 000's first measurement (the C quick-start's): range, azimuth, elevation at t = 0
Z0 = [670.8204, 0.896055, 0.302746]


def model_parameters(unzipdir):
    """(name, type, start) of every parameter in modelDescription.xml, in order; a code
    parameter (an Integer with its code list in the description) by its item name."""
    root = ET.parse(unzipdir / "modelDescription.xml").getroot()
    codes = {k: {c: n for n, c in v.items()} for k, v in rf.codes(read_model_description(str(unzipdir))).items()}
    out = []
    for sv in root.find("ModelVariables"):
        if sv.get("causality") != "parameter":
            continue
        child = sv[0]
        kind = child.tag
        start = child.get("start")
        name = sv.get("name")
        if kind == "Integer" and name in codes:
            out.append((name, "Integer", codes[name][int(start)]))
        elif kind == "Integer":
            out.append((name, "Integer", int(start)))
        elif kind == "Boolean":
            out.append((name, "Boolean", start == "true"))
        else:
            out.append((name, "Real", float(start)))
    return out


def test_parameters_are_the_fmus_parameters(unzipdir):
    """Names, types and defaults come from the variable table that writes
    modelDescription.xml: the same list, in the same order."""
    ours = [(p["name"], p["type"], p["default"]) for p in relnav.parameters()]
    assert ours == model_parameters(unzipdir)
    est = relnav.Estimator()
    assert est.params == {p["name"]: p["default"] for p in relnav.parameters()}
    by_name = {p["name"]: p for p in relnav.parameters()}
    assert [i[0] for i in by_name["filter"]["items"]][:9] == [
        "ekf", "ukf", "aqukf", "pf", "rpf", "upf", "gapf", "cgapf", "hinf"]
    assert by_name["mean_motion"]["unit"] == "rad/s"
    assert relnav.__version__ == re.search(r'^version = "(.*)"', (REPO_ROOT / "Cargo.toml").read_text(), re.M)[1]


def test_defaults_are_paper_000s_example():
    est = relnav.Estimator()
    np.testing.assert_array_equal(est.state, [405, 505, 205, 0.1, 0.1, 0.1])
    np.testing.assert_array_equal(est.sigma, [50, 50, 50, 1, 1, 1])
    np.testing.assert_array_equal(est.covariance, np.diag([2500.0] * 3 + [1.0] * 3))
    assert math.isnan(est.ess) and math.isnan(est.hinf_gamma) and np.isnan(est.q_vv).all()
    assert math.isnan(est.pf_acceptance)
    assert est.params["filter"] == "ekf" and est.params["frame"] == "along_radial_antinormal"
    assert est.params["mean_motion"] == 2 * math.pi / 7200
    assert repr(est) == "Estimator(filter='ekf')"


@pytest.mark.parametrize("name,code", [("ukf", 2), ("UKF", 2), ("rpf", 5)])
def test_enumerations_by_name_or_code(name, code):
    a = relnav.Estimator(filter=name, particles=100, seed=3)
    b = relnav.Estimator(filter=code, particles=100, seed=3)
    for e in (a, b):
        e.step((0.0, 0.0, 0.0), Z0)
    assert a.params == b.params and a.params["filter"] == name.lower()
    assert a.state.tobytes() == b.state.tobytes()
    f = relnav.Estimator(frame="along_antinormal_nadir")
    assert f.params["frame"] == relnav.Estimator(frame=3).params["frame"] == "along_antinormal_nadir"


def test_library_outputs_of_each_filter_kind():
    # point particles: the moves (and their acceptance) are theirs
    pf = relnav.Estimator(filter="cgapf", particles=200, seed=1, pf_prior=1)
    assert pf.ess == 200
    pf.step([0, 0, 0], Z0)
    assert 1 <= pf.ess <= 200
    # the first update draws the particles from the measurement; the second moves them
    assert math.isnan(pf.pf_acceptance)
    pf.step([0, 0, 0], Z0)
    assert 0 <= pf.pf_acceptance <= 1
    aq = relnav.Estimator(filter="aqukf")
    np.testing.assert_array_equal(aq.q_vv, [1e-6] * 3)
    h = relnav.Estimator(filter="hinf")
    assert 0 < h.hinf_gamma < math.inf
    assert np.isnan(h.sigma).all() and np.isnan(h.covariance).all()
    assert h.hinf_certified is False  # track initiation first
    h.step([0, 0, 0], Z0, dt=1.0)
    assert np.isfinite(h.state).all()
    assert relnav.Estimator(filter="hinf", hinf_acquisition=False).hinf_certified is True
    assert aq.hinf_certified is None


def raises(exc, match, fn, *args, **kwargs):
    with pytest.raises(exc, match=match) as info:
        fn(*args, **kwargs)
    return info.value


@pytest.mark.parametrize(
    "kwargs,message",
    [
        ({"filtr": "ukf"}, r'unknown parameter "filtr"; did you mean filter\?'),
        ({"mean_motion": "fast"}, r"mean_motion must be a number \(got str\)"),
        ({"mean_motion": True}, r"mean_motion must be a number \(got bool\)"),
        ({"particles": 1500.0}, r"particles must be an integer \(got float\)"),
        ({"seed": 2**40}, r"seed = 1099511627776 does not fit a 32-bit FMI Integer"),
        ({"filter": "kalman"}, r'filter = "kalman" is not a Filter \(allowed: 1 ekf, 2 ukf'),
        ({"filter": 0}, r"filter = 0 is not a Filter code"),
        ({"frame": 2.0}, r"frame must be a Frame name or code \(got float"),
        ({"mean_motion": -1.0}, r"mean_motion must be finite and > 0 \(got -1\)"),
        ({"sigma_range": math.nan}, r"sigma_range must be finite and > 0"),
        ({"particles": 0}, r"particles must lie in 1\.\.=2000000 \(got 0\)"),
        ({"resample_threshold": 1.5}, r"resample_threshold must lie in \(0, 1\]"),
        ({"window": 0}, r"window"),
        ({"noise_dof": 2.0}, r"noise_dof must be finite and > 2"),
    ],
)
def test_bad_parameters_raise_with_the_librarys_message(kwargs, message):
    e = raises(relnav.InvalidArgumentError, message, relnav.Estimator, **kwargs)
    assert isinstance(e, relnav.Error) and isinstance(e, ValueError) and e.status == 2


def test_bad_inputs_raise_and_change_nothing():
    est = relnav.Estimator(filter="ukf")
    est.step([0, 0, 0], Z0)
    before = (est.state.tobytes(), est.covariance.tobytes())
    for args, kwargs, message in [
        (([0, 0],), {}, r"thrust must be 3 numbers"),
        (("abc",), {}, r"thrust must be 3 numbers"),
        (([0, 0, math.inf],), {}, r"thrust must be finite"),
        (([0, 0, 0], [1.0, 2.0]), {}, r"measurement must be 3 numbers"),
        (([0, 0, 0], [math.nan, 0, 0]), {}, r"measurement \(range, azimuth, elevation\) must be finite"),
        (([0, 0, 0], [-1.0, 0, 0]), {}, r"measured range must be >= 0 \(got -1\)"),
        (([0, 0, 0], [1.0, 0, 2.0]), {}, r"measured elevation must lie in \[-pi/2, pi/2\]"),
        (([0, 0, 0],), {"dt": 0.0}, r"step size h must be finite and > 0 \(got 0\)"),
    ]:
        raises(relnav.InvalidArgumentError, message, est.step, *args, **kwargs)
    assert (est.state.tobytes(), est.covariance.tobytes()) == before
    # numpy arrays and tuples work as vectors
    est.step(np.zeros(3), tuple(Z0))
    h = relnav.Estimator(filter="hinf", hinf_period=1.0)
    raises(relnav.InvalidArgumentError, r"designed for hinf_period = 1 s .* step h = 2 s refused", h.step, [0, 0, 0], dt=2.0)


def test_numerical_failure_is_a_numerical_error():
    # a measurement at zero range cannot be inverted at a point particle filter's first
    # update (which draws the particles from the measurement)
    pf = relnav.Estimator(filter="pf", particles=50, pf_prior=1)
    e = raises(relnav.NumericalError, r"filter step failed", pf.step, [0, 0, 0], [0.0, 0.0, 0.0])
    assert e.status == 4 and isinstance(e, ArithmeticError)


def test_run_checks_its_arrays():
    est = relnav.Estimator()
    k = 5
    u, z = np.zeros((k, 3)), np.tile(Z0, (k, 1))
    raises(relnav.InvalidArgumentError, r"thrust must have shape \(K, 3\) \(got \[5, 2\]\)", est.run, np.zeros((k, 2)))
    raises(relnav.InvalidArgumentError, r"measurements has 4 rows, thrust 5", est.run, u, z[:4])
    raises(relnav.InvalidArgumentError, r"valid has 3 entries for K = 5 steps", est.run, u, z, np.ones(3, bool))
    raises(relnav.InvalidArgumentError, r"dt has 2 entries", est.run, u, z, None, [1.0, 1.0])
    raises(relnav.InvalidArgumentError, r"valid marks measurements but measurements is None", est.run, u, None, np.ones(k, bool))
    raises(relnav.InvalidArgumentError, r"thrust must be a K x 3 array of numbers", est.run, [["a", "b", "c"]])
    # a failing step names itself, and the estimator stays after the previous step
    bad = z.copy()
    bad[3, 0] = -1.0
    ref = relnav.Estimator()
    ref.run(u[:3], z[:3])
    e = raises(relnav.InvalidArgumentError, r"step 3: measured range must be >= 0", est.run, u, bad)
    assert e.step == 3
    assert est.state.tobytes() == ref.state.tobytes()
    # lists work too, and dt may vary per step
    x, s = relnav.Estimator().run(u.tolist(), z.tolist(), [True, False] * 2 + [True], [1.0, 0.5, 1.0, 2.0, 1.0])
    assert x.shape == s.shape == (k, 6) and np.isfinite(x).all()


def test_run_releases_the_gil_and_an_estimator_refuses_a_second_thread():
    """Two estimators run in parallel threads; one estimator is never used by two
    threads at once (the second gets an error instead of a deadlock)."""
    import threading

    k = 20000
    u = np.zeros((k, 3))
    ests = [relnav.Estimator(filter="ukf") for _ in range(2)]
    out = [None, None]

    def work(i):
        out[i] = ests[i].run(u)[0][-1]

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert out[0].tobytes() == out[1].tobytes()
    shared = relnav.Estimator(filter="ukf")
    errors = []
    started = threading.Event()

    def long_run():
        started.set()
        shared.run(np.zeros((500000, 3)))

    t = threading.Thread(target=long_run)
    t.start()
    started.wait()
    while t.is_alive() and not errors:
        try:
            shared.state
        except RuntimeError as e:
            errors.append(str(e))
        time.sleep(0.001)  # lets the other thread take the GIL and start its run
    t.join()
    assert errors and "in use by another thread" in errors[0]


def stub_block() -> str:
    """The generated part of the stub: Estimator.__init__ with every parameter."""
    lines = ["    def __init__(", "        self,", "        *,"]
    doc = []
    for p in relnav.parameters():
        ty = "Union[int, str]" if "items" in p else {"Real": "float", "Integer": "int", "Boolean": "bool"}[p["type"]]
        lines.append(f"        {p['name']}: {ty} = {p['default']!r},")
        unit = f" [{p['unit']}]" if p["unit"] else ""
        items = ""
        if "items" in p:
            items = " One of: " + ", ".join(f"{c} {n}" for n, c, _ in p["items"]) + "."
        doc.append(f"            {p['name']}{unit}: {p['description']}.{items}")
    lines.append("    ) -> None:")
    lines.append('        """Keyword arguments are the FMU\'s parameters (names, types, defaults):')
    lines.append("")
    lines.extend(doc)
    lines.append('        """')
    return "\n".join(lines) + "\n"


def test_stub_lists_the_current_parameters():
    text = STUB.read_text()
    begin = re.search(r"^    # --- parameters: begin.*\n", text, re.M)
    end = re.search(r"^    # --- parameters: end ---\n", text, re.M)
    assert begin and end, f"{STUB}: markers missing"
    current = text[begin.end():end.start()]
    want = stub_block()
    if os.environ.get("RELNAV_BLESS_STUBS") == "1":
        STUB.write_text(text[: begin.end()] + want + text[end.start():])
        return
    assert current == want, (
        f"{STUB} is stale (the FMU's parameter table changed): regenerate with "
        "RELNAV_BLESS_STUBS=1 pytest tests/python/test_package_api.py -k stub"
    )


def test_readme_example_runs(tmp_path):
    """examples/relnav_python_quickstart.py (shown verbatim in README.md) runs and its
    UKF lands within a metre of the truth."""
    proc = subprocess.run([sys.executable, str(EXAMPLE)], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    m = re.search(r"position error after 100 s: ([\d.]+) m", proc.stdout)
    assert m and float(m[1]) < 1.0, proc.stdout
