"""Gains designed in Python, run by the flight library: the H-infinity filter of paper
002's example designed by ``relnav.Estimator`` (the full library, with its solver), its
matrices (``Estimator.hinf_matrices``) loaded as data into the flight library's runtime
filter (``target/flight/librelnav.so``, built by ``scripts/build-flight.sh``: no solver,
no heap) through its C ABI (``relnav_hinf_filter_init`` in storage this test allocates).

Checked against numpy: the design's structure (``A_F + B_F C = Phi(T)``, ``E_F = Gamma(T)``,
``C_F = I``: the observer of the exact ZOH CW step), the flight library's estimates against
the same recursion in numpy, and paper 002's accuracy bar on its example against the numpy
truth of ``test_hinf.py`` (the feedback u = K x as a known thrust, 0.1 m position fixes).
"""

import ctypes
import os
from pathlib import Path

import numpy as np
import pytest

import cwtruth as cw
import relnav
from conftest import REPO_ROOT, header_status, header_struct
from test_hinf import BAR_POS, BAR_VEL, MASS, PARAMS, PERIOD, T_FROM, W0, scenario

RELNAV_OK = header_status("RELNAV_OK")
RELNAV_ERROR_NOT_IMPLEMENTED = header_status("RELNAV_ERROR_NOT_IMPLEMENTED")
HinfMatrices = header_struct("relnav_hinf_matrices")


@pytest.fixture(scope="module")
def flight():
    path = Path(os.environ.get("RELNAV_FLIGHT_LIB", REPO_ROOT / "target/flight/librelnav.so"))
    if not path.is_file():
        pytest.fail(
            f"the flight library is not at {path}: build it with `bash scripts/build-flight.sh` "
            "(scripts/test.sh does), or point $RELNAV_FLIGHT_LIB at it",
            pytrace=False,
        )
    lib = ctypes.CDLL(str(path))
    lib.relnav_last_error.restype = ctypes.c_char_p
    return lib


@pytest.fixture(scope="module")
def designed():
    est = relnav.Estimator(**PARAMS, hinf_acquisition=False)
    m = est.hinf_matrices
    assert m is not None
    return m


def test_the_design_is_the_observer_of_the_exact_step(designed):
    step = cw.zoh_step_matrix(W0, PERIOD)
    phi, gamma = step[:6, :6], step[:6, 6:]
    c = np.hstack([np.eye(3), np.zeros((3, 3))])
    np.testing.assert_allclose(designed["a_f"] + designed["b_f"] @ c, phi, rtol=0, atol=1e-12)
    np.testing.assert_allclose(designed["e_f"], gamma, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(designed["c_f"], np.eye(6))
    np.testing.assert_array_equal(designed["b_v"], np.zeros((6, 3)))
    assert designed["period"] == PERIOD
    # a gain that corrects: the position block is far from zero
    assert np.abs(designed["b_f"][:3]).max() > 0.1
    # no matrices for a filter without them
    assert relnav.Estimator(filter="ekf").hinf_matrices is None


def run_flight(lib, m, y, accel, x0):
    size, align = ctypes.c_size_t(), ctypes.c_size_t()
    assert lib.relnav_hinf_filter_storage(ctypes.byref(size), ctypes.byref(align)) == RELNAV_OK
    assert align.value <= ctypes.alignment(ctypes.c_double)
    storage = (ctypes.c_double * (size.value // 8 + 1))()
    cm = HinfMatrices()
    cm.a_f[:] = m["a_f"].ravel()
    cm.b_f[:] = m["b_f"].ravel()
    cm.c_f[:] = m["c_f"].ravel()
    cm.e_f[:] = m["e_f"].ravel()
    cm.period = m["period"]
    handle = ctypes.c_void_p()
    x0c = (ctypes.c_double * 6)(*x0)
    st = lib.relnav_hinf_filter_init(
        storage, ctypes.c_size_t(size.value), ctypes.byref(cm), x0c, ctypes.byref(handle)
    )
    assert st == RELNAV_OK, lib.relnav_last_error()
    out = np.empty((len(y) + 1, 6))
    x = (ctypes.c_double * 6)()
    assert lib.relnav_hinf_filter_get_state(handle, x) == RELNAV_OK
    out[0] = x[:]
    for k in range(len(y)):
        yk = (ctypes.c_double * 3)(*y[k])
        ak = (ctypes.c_double * 3)(*accel[k])
        assert lib.relnav_hinf_filter_step(handle, yk, ak) == RELNAV_OK
        assert lib.relnav_hinf_filter_get_state(handle, x) == RELNAV_OK
        out[k + 1] = x[:]
    assert lib.relnav_hinf_filter_deinit(handle) == RELNAV_OK
    # the heap path is not in the flight library
    h = ctypes.c_void_p()
    assert lib.relnav_hinf_filter_new(ctypes.byref(cm), x0c, ctypes.byref(h)) == (
        RELNAV_ERROR_NOT_IMPLEMENTED
    )
    assert b"not in this build" in lib.relnav_last_error()
    return out


@pytest.mark.parametrize("manoeuvre", [False, True])
def test_flight_library_runs_the_python_design_on_paper002(flight, designed, manoeuvre):
    times, x, thrust, _, _ = scenario(manoeuvre)
    rng = np.random.default_rng(7)
    y = x[:-1, :3] + 0.1 * rng.standard_normal((len(times) - 1, 3))
    accel = thrust / MASS
    x0 = np.array([PARAMS[k] for k in ("x0", "y0", "z0", "vx0", "vy0", "vz0")])
    est = run_flight(flight, designed, y, accel, x0)
    # the same recursion in numpy
    ref = np.empty_like(est)
    xf = np.linalg.solve(designed["c_f"], x0)
    ref[0] = designed["c_f"] @ xf
    for k in range(len(y)):
        xf = designed["a_f"] @ xf + designed["b_f"] @ y[k] + designed["e_f"] @ accel[k]
        ref[k + 1] = designed["c_f"] @ xf
    np.testing.assert_allclose(est, ref, rtol=1e-10, atol=1e-9)
    # paper 002's bar after convergence, against the numpy truth
    m = times >= T_FROM
    rms = np.sqrt(np.mean((est[m] - x[m]) ** 2, axis=0))
    assert np.all(rms[:3] < BAR_POS), rms
    assert np.all(rms[3:] < BAR_VEL), rms
