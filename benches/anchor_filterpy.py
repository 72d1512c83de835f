"""Anchor for the filter benchmarks: filterpy's UnscentedKalmanFilter on the same model
(paper 000's example: exact CW transition over 1 s, range/azimuth/elevation in frame 2,
scaled sigma points alpha=1, beta=2, kappa=0) timed per predict+update, median of
repeated runs. Prints one JSON line: {"filterpy_ukf_step_ns": median, ...}.
"""
import json
import math
import statistics
import time

import numpy as np
from filterpy.kalman import MerweScaledSigmaPoints, UnscentedKalmanFilter

N = 2 * math.pi / 7200.0
T = 1.0


def cw_phi(n, t):
    """Closed-form CW transition (canonical frame: x radial, y along-track, z normal)."""
    th = n * t
    s, c = math.sin(th), math.cos(th)
    return np.array([
        [4 - 3 * c, 0, 0, s / n, 2 * (1 - c) / n, 0],
        [6 * (s - th), 1, 0, -2 * (1 - c) / n, (4 * s - 3 * th) / n, 0],
        [0, 0, c, 0, 0, s / n],
        [3 * n * s, 0, 0, c, 2 * s, 0],
        [-6 * n * (1 - c), 0, 0, -2 * s, 4 * c - 3, 0],
        [0, 0, -n * s, 0, 0, c],
    ])


# frame 2 (paper 000): x along-track, y radial, z minus normal
T2 = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1]], dtype=float)
T6 = np.block([[T2, np.zeros((3, 3))], [np.zeros((3, 3)), T2]])
PHI = T6 @ cw_phi(N, T) @ T6.T


def fx(x, dt):
    return PHI @ x


def hx(x):
    rho = math.sqrt(x[0] ** 2 + x[1] ** 2 + x[2] ** 2)
    return np.array([rho, math.atan2(x[1], x[0]) % (2 * math.pi), math.asin(x[2] / rho)])


def residual_z(a, b):
    d = a - b
    d[1] = (d[1] + math.pi) % (2 * math.pi) - math.pi
    return d


SIG_A = math.radians(0.01)


def measurements(steps=600):
    """Paper 000's truth (at rest at (400, 500, 200) m) measured with noise, seeded."""
    rng = np.random.default_rng(1)
    x_true = np.array([400.0, 500.0, 200.0, 0, 0, 0])
    zs = []
    for _ in range(steps):
        z = hx(x_true) + rng.normal(0, [0.5, SIG_A, SIG_A])
        z[1] %= 2 * math.pi
        zs.append(z)
        x_true = PHI @ x_true
    return zs


def make():
    """filterpy's UKF set up like relnav's defaults (paper 000)."""
    pts = MerweScaledSigmaPoints(6, alpha=1.0, beta=2.0, kappa=0.0)
    f = UnscentedKalmanFilter(dim_x=6, dim_z=3, dt=T, fx=fx, hx=hx, points=pts,
                              residual_z=residual_z)
    f.x = np.array([405.0, 505.0, 205.0, 0.1, 0.1, 0.1])
    f.P = np.diag([50.0**2] * 3 + [1.0] * 3)
    f.Q = np.diag([0.09, 0.000625, 0.0025, 1e-6, 1e-6, 1e-6])
    f.R = np.diag([0.25, SIG_A**2, SIG_A**2])
    return f


def main():
    zs = measurements()
    samples = []
    for rep in range(7):
        f = make()
        t0 = time.perf_counter_ns()
        for z in zs:  # filterpy's update reuses the sigma points of its predict
            f.predict()
            f.update(z)
        samples.append((time.perf_counter_ns() - t0) / len(zs))
    print(json.dumps({"filterpy_ukf_step_ns": statistics.median(samples),
                      "samples_ns": samples}))


if __name__ == "__main__":
    main()
