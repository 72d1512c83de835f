"""Anchor for the particle-filter benchmark: one step of a vectorised numpy SIR filter on
paper 000's model (exact CW transition over 1 s, range/azimuth/elevation in frame 2,
Gaussian likelihood, N_eff < 2N/3 systematic resampling, weighted mean and covariance),
N = 1500, timed per update+predict in steady state like benches/pf.rs; median of
repeated runs. Prints one JSON line: {"numpy_sir_step_ns": median, "particles": 1500}.
"""
import json
import math
import statistics
import time

import numpy as np

N_MOTION = 2 * math.pi / 7200.0
NP = 1500
SIG = np.array([0.5, 0.01 * math.pi / 180, 0.01 * math.pi / 180])


# the same closed-form CW transition and frame-2 rotation as the filterpy anchor
from anchor_filterpy import T6, cw_phi  # noqa: E402

PHI = T6 @ cw_phi(N_MOTION, 1.0) @ T6.T  # frame 2 throughout
QL = np.linalg.cholesky(np.diag([0.09, 0.000625, 0.0025, 1e-6, 1e-6, 1e-6]))


def h(p):
    rho = np.sqrt(np.einsum("ij,ij->i", p[:, :3], p[:, :3]))
    az = np.mod(np.arctan2(p[:, 1], p[:, 0]), 2 * math.pi)
    el = np.arcsin(p[:, 2] / rho)
    return rho, az, el


def step(x, w, z, rng):
    rho, az, el = h(x)
    daz = np.mod(z[1] - az + math.pi, 2 * math.pi) - math.pi
    ll = -0.5 * (((z[0] - rho) / SIG[0]) ** 2 + (daz / SIG[1]) ** 2 + ((z[2] - el) / SIG[2]) ** 2)
    lw = np.log(w) + ll
    lw -= lw.max()
    w = np.exp(lw)
    w /= w.sum()
    mean = w @ x
    d = x - mean
    cov = (d * w[:, None]).T @ d
    if 1.0 / np.sum(w * w) < 2 * NP / 3:
        u = (rng.random() + np.arange(NP)) / NP
        idx = np.minimum(np.searchsorted(np.cumsum(w), u), NP - 1)
        x = x[idx]
        w = np.full(NP, 1.0 / NP)
    x = x @ PHI.T + rng.standard_normal((NP, 6)) @ QL.T
    return x, w, mean, cov


def main():
    rng = np.random.default_rng(1)
    x0 = np.array([400.0, 500.0, 200.0, 0.0, 0.0, 0.0])
    truth = [x0]
    for _ in range(3000):
        truth.append(PHI @ truth[-1])
    zs = []
    for t in truth:
        rho, az, el = h(t[None, :])
        zs.append(np.array([rho[0], az[0], el[0]]) + SIG * rng.standard_normal(3))
    # start near the truth (the benchmark times steady-state steps, not the start-up)
    x = x0 + rng.standard_normal((NP, 6)) * np.array([0.3, 0.3, 0.3, 0.01, 0.01, 0.01])
    w = np.full(NP, 1.0 / NP)
    k = 0
    for _ in range(50):
        x, w, _, _ = step(x, w, zs[k], rng)
        k += 1
    samples = []
    for _ in range(15):
        t0 = time.perf_counter_ns()
        reps = 100
        for _ in range(reps):
            x, w, _, _ = step(x, w, zs[k], rng)
            k += 1
        samples.append((time.perf_counter_ns() - t0) / reps)
    print(json.dumps({"numpy_sir_step_ns": statistics.median(samples), "particles": NP}))


if __name__ == "__main__":
    main()
