"""relnav.Estimator gives the C ABI's and the FMU's estimates bit for bit on paper 000's
example (with a reported burn and a measurement dropout): step by step, through the batch
``run``, through ``librelnav.so`` via ctypes and through the FMU via fmpy.

The ctypes view of ``relnav_config`` is read from include/relnav.h (the checked-in
cbindgen header), so fields appended there need no change here."""

from __future__ import annotations

import ctypes

import numpy as np
import pytest

import cwtruth as cw
import relnav
from conftest import REPO_ROOT, header_struct

LIBRARY = REPO_ROOT / "target" / "release" / "librelnav.so"


def config_struct() -> type:
    """ctypes.Structure of ``relnav_config``, field by field from the header."""
    cfg_t = header_struct("relnav_config")
    assert len(cfg_t._fields_) > 20
    return cfg_t


@pytest.fixture(scope="module")
def capi():
    if not LIBRARY.is_file():
        pytest.fail(f"{LIBRARY} missing: build it with `cargo build --release`", pytrace=False)
    lib = ctypes.CDLL(str(LIBRARY))
    cfg_t = config_struct()
    dp = ctypes.POINTER(ctypes.c_double)
    lib.relnav_config_default.restype = cfg_t
    lib.relnav_estimator_new.argtypes = [ctypes.POINTER(cfg_t), ctypes.POINTER(ctypes.c_void_p)]
    lib.relnav_estimator_step.argtypes = [ctypes.c_void_p, dp, dp, ctypes.c_double]
    lib.relnav_estimator_get_state.argtypes = [ctypes.c_void_p, dp]
    lib.relnav_estimator_get_sigma.argtypes = [ctypes.c_void_p, dp]
    lib.relnav_estimator_free.argtypes = [ctypes.c_void_p]
    lib.relnav_last_error.restype = ctypes.c_char_p
    return lib


def run_capi(lib, params: dict, sc: cw.Scenario, z: np.ndarray) -> np.ndarray:
    """(N, 12) state and sigma after each step through the C ABI."""
    cfg = lib.relnav_config_default()
    for name in C_PARAMS:  # the fields named like the FMU parameters they hold
        if name in params:
            setattr(cfg, name, params[name])
    est = ctypes.c_void_p()
    assert lib.relnav_estimator_new(ctypes.byref(cfg), ctypes.byref(est)) == 0, lib.relnav_last_error()
    out = np.empty((sc.steps, 12))
    x, s = (ctypes.c_double * 6)(), (ctypes.c_double * 6)()
    try:
        for k in range(sc.steps):
            u = (ctypes.c_double * 3)(*sc.thrust[k])
            zk = (ctypes.c_double * 3)(*z[k]) if sc.valid[k] else None
            h = sc.times[k + 1] - sc.times[k]
            assert lib.relnav_estimator_step(est, u, zk, h) == 0, lib.relnav_last_error()
            lib.relnav_estimator_get_state(est, x)
            lib.relnav_estimator_get_sigma(est, s)
            out[k] = list(x) + list(s)
    finally:
        lib.relnav_estimator_free(est)
    return out


# the parameters these tests change (the others keep paper 000's defaults, checked below)
C_PARAMS = ("filter", "frame", "chaser_mass", "seed", "particles")


def run_steps(params: dict, sc: cw.Scenario, z: np.ndarray) -> np.ndarray:
    est = relnav.Estimator(**params)
    out = np.empty((sc.steps, 12))
    for k in range(sc.steps):
        est.step(sc.thrust[k], z[k] if sc.valid[k] else None, dt=sc.times[k + 1] - sc.times[k])
        out[k, :6], out[k, 6:] = est.state, est.sigma
    return out


def run_batch(params: dict, sc: cw.Scenario, z: np.ndarray) -> np.ndarray:
    x, s = relnav.Estimator(**params).run(sc.thrust, z, sc.valid, np.diff(sc.times))
    return np.hstack([x, s])


def bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def scenario(steps: int) -> cw.Scenario:
    times = np.arange(steps + 1, dtype=float)
    # a reported 2 N along-track burn over 20..40 s, and no measurements over 50..59 s
    thrust = cw.burn_thrust(times, 20.0, 40.0, [2.0, 0.0, 0.0])
    valid = np.ones(steps, dtype=bool)
    valid[50:60] = False
    return cw.paper000_scenario(frame=2, times=times, thrust_io=thrust, valid=valid)


CASES = [
    ("ekf", {}, 600),
    ("ukf", {}, 600),
    ("aqukf", {}, 600),
    ("hinf", {}, 600),
    ("imm", {}, 600),
    ("pf", {"particles": 500, "seed": 11}, 120),
    ("cgapf", {"particles": 300, "seed": -5}, 80),
]


@pytest.mark.parametrize("name,extra,steps", CASES, ids=[c[0] for c in CASES])
def test_python_equals_c_abi_and_fmu_bit_for_bit(name, extra, steps, capi, runner):
    sc = scenario(steps)
    z = sc.measurements(seed=3)
    code = {"ekf": 1, "ukf": 2, "aqukf": 3, "pf": 4, "cgapf": 8, "hinf": 9, "imm": 10}[name]
    params = {**sc.params, "filter": code, **extra}
    changed = {k: v for k, v in params.items() if k in C_PARAMS}
    assert relnav.Estimator(**params).params == relnav.Estimator(**changed).params
    fmu = runner.run(params, sc.times, sc.thrust, z, sc.valid)[1:]
    c = run_capi(capi, {**params, "seed": extra.get("seed", 0) & 0xFFFFFFFF}, sc, z)
    py_steps = run_steps({**params, "filter": name}, sc, z)
    py_batch = run_batch(params, sc, z)
    assert np.isfinite(fmu[:, :6]).all()
    for label, got in [("C ABI", c), ("Estimator.step", py_steps), ("Estimator.run", py_batch)]:
        diff = np.flatnonzero((bits(got) != bits(fmu)).any(axis=1))
        assert diff.size == 0, f"{name}: {label} differs from the FMU from step {diff[:1]}: {got[diff[:1]]} vs {fmu[diff[:1]]}"
