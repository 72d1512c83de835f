"""A third-party anchor for relnav's UKF: filterpy's UnscentedKalmanFilter with van der
Merwe's scaled sigma points, set up with relnav's documented model and step semantics
(update with the measurement taken at t_k, then predict over h_k with the thrust held).

The CW model and the sensor come from tools/cwtruth.py. Like relnav, the filter state is
kept in the canonical Hill frame (x radial, y along-track, z normal) whatever the I/O frame:
the sigma points come from a Cholesky factor of the covariance, and a Cholesky factor of a
permuted matrix is not the permuted factor, so a UKF run in another frame is a slightly
different (equally valid) filter. The azimuth is averaged on the circle and its residuals
wrapped to (-pi, pi].
"""

from __future__ import annotations

import numpy as np
from filterpy.kalman import MerweScaledSigmaPoints, UnscentedKalmanFilter

import cwtruth as cw
import refekf


def _wrap_pi(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def run_ukf(params: dict, times, thrust, meas, valid, alpha=1.0, beta=2.0, kappa=0.0) -> np.ndarray:
    """filterpy UKF on one run; returns (N+1, 12) like the FMU's outputs."""
    p = refekf.defaults()
    p.update(params)
    frame = int(p["frame"])
    n = float(p["mean_motion"])
    r6 = cw.rot6(frame)
    t3 = cw.FRAME_ROT[frame]
    q_rate = np.array([p[f"q_pos_{a}"] for a in "xyz"] + [p[f"q_vel_{a}"] for a in "xyz"])

    cache: dict[float, tuple[np.ndarray, np.ndarray]] = {}

    def model(h):  # canonical Phi and Gamma
        if h not in cache:
            e = cw.zoh_step_matrix(n, h)
            cache[h] = (e[:6, :6], e[:6, 6:])
        return cache[h]

    def fx(x, dt, accel):
        phi, gamma = model(dt)
        return phi @ x + gamma @ accel

    def hx(x):
        return cw.measure(t3 @ x[:3])

    def z_mean(sigmas, wm):
        z = np.empty(3)
        z[0] = wm @ sigmas[:, 0]
        z[1] = np.mod(np.arctan2(wm @ np.sin(sigmas[:, 1]), wm @ np.cos(sigmas[:, 1])), 2 * np.pi)
        z[2] = wm @ sigmas[:, 2]
        return z

    def residual_z(a, b):
        d = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
        d[1] = _wrap_pi(d[1])
        return d

    points = MerweScaledSigmaPoints(6, alpha=alpha, beta=beta, kappa=kappa)
    ukf = UnscentedKalmanFilter(dim_x=6, dim_z=3, dt=1.0, hx=hx, fx=fx, points=points, z_mean_fn=z_mean, residual_z=residual_z)
    ukf.x = r6.T @ np.array([p[k] for k in ["x0", "y0", "z0", "vx0", "vy0", "vz0"]], dtype=float)
    ukf.P = np.diag([p["sigma_pos0"] ** 2] * 3 + [p["sigma_vel0"] ** 2] * 3)
    ukf.R = np.diag([p["sigma_range"] ** 2, p["sigma_angle"] ** 2, p["sigma_angle"] ** 2])
    ukf.sigmas_f = points.sigma_points(ukf.x, ukf.P)

    times = np.asarray(times, dtype=float)
    out = np.empty((len(times), 12))
    def record(k):
        out[k, :6] = r6 @ ukf.x
        out[k, 6:] = np.sqrt(np.diag(r6 @ ukf.P @ r6.T))

    record(0)
    for k in range(len(times) - 1):
        h = float(times[k + 1] - times[k])
        if valid[k]:
            ukf.update(np.asarray(meas[k], dtype=float))
        else:
            ukf.sigmas_f = points.sigma_points(ukf.x, ukf.P)
        ukf.Q = r6.T @ np.diag(q_rate * h) @ r6
        ukf.predict(dt=h, accel=t3.T @ np.asarray(thrust[k], dtype=float) / p["chaser_mass"])
        record(k + 1)
    return out
