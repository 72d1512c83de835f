"""Anchor for the H-infinity design bench: the same SDP (paper 002, Theorem 1 / Corollary 1,
with the same conditioning as crates/core/src/hinf/design.rs: balanced uncertainty scaling, R <= 1e4 I,
margins 1e-5) posed in cvxpy and solved by Clarabel. Timed per solve with the problem
assembly included (variables, constraints, canonicalisation), median of repeated runs.
Prints one JSON line: {"cvxpy_hinf_design_ns": median, "gamma": ..., "status": ...}.
Needs benches/requirements-bench.txt (cvxpy, clarabel).
"""
import json
import statistics
import time

import cvxpy as cp
import numpy as np

W0, T, M, DB = 7.2722e-5, 0.1, 1000.0, 0.05
K = np.array([
    [-2.2541, -0.0071, -0.0072, -22.3975, 2.3256, 1.9369],
    [-0.0104, -2.2493, -0.0055, 2.3259, -23.7456, 1.4544],
    [-0.0072, -0.0055, -2.2471, 1.9357, 1.4552, -24.2818],
])
BOUND, EPS = 1e4, 1e-5


def plant():
    a1 = np.zeros((6, 6))
    a1[0:3, 3:6] = np.eye(3)
    a1[3, 0], a1[3, 4], a1[4, 3], a1[5, 2] = 3 * W0**2, 2 * W0, -2 * W0, -W0**2
    g0 = np.vstack([np.zeros((3, 3)), np.eye(3) / M])
    a = np.eye(6) + T * (a1 + g0 @ K)
    ha = np.zeros((6, 6))
    ha[3, 0], ha[3, 4], ha[4, 3], ha[5, 2] = 3 * W0, 2.0, -2.0, -W0
    ha *= T
    e1, e2 = W0 * (2 * DB + DB**2), W0 * DB
    ea = np.diag([e1, 0, e1, e2, e2, 0])
    s = np.sqrt(np.linalg.norm(ha) / np.linalg.norm(ea))
    b = np.diag([0.05] * 3 + [0.001] * 3)
    c = np.hstack([np.eye(3), np.zeros((3, 3))])
    d = 0.1 * np.eye(3)
    return a, b, c, d, np.eye(6), ha / s, ea * s


def solve():
    a, b, c, d, l, ha, ea = plant()
    r = cp.Variable((6, 6), symmetric=True)
    s = cp.Variable((6, 6), symmetric=True)
    ab = cp.Variable((6, 6))
    bb = cp.Variable((6, 3))
    cb = cp.Variable((6, 6))
    lam = cp.Variable()
    g2 = cp.Variable()
    z = lambda m, n: np.zeros((m, n))  # noqa: E731
    i = np.eye
    rows = [
        [-r, -s, r @ a + bb @ c, ab, r @ b, bb @ d, z(6, 6), r @ ha],
        [-s, -s, s @ a + bb @ c, ab, s @ b, bb @ d, z(6, 6), s @ ha],
        [(r @ a + bb @ c).T, (s @ a + bb @ c).T, -r + lam * (ea.T @ ea), -s, z(6, 6), z(6, 3), l.T, z(6, 6)],
        [ab.T, ab.T, -s, -s, z(6, 6), z(6, 3), -cb.T, z(6, 6)],
        [(r @ b).T, (s @ b).T, z(6, 6), z(6, 6), -g2 * i(6), z(6, 3), z(6, 6), z(6, 6)],
        [(bb @ d).T, (bb @ d).T, z(3, 6), z(3, 6), z(3, 6), -g2 * i(3), z(3, 6), z(3, 6)],
        [z(6, 6), z(6, 6), l, -cb, z(6, 6), z(6, 3), -i(6), z(6, 6)],
        [(r @ ha).T, (s @ ha).T, z(6, 6), z(6, 6), z(6, 6), z(6, 3), z(6, 6), -lam * i(6)],
    ]
    big = cp.bmat(rows)
    big = (big + big.T) / 2
    cons = [big << -EPS * np.eye(45), r << BOUND * np.eye(6), s >> EPS * np.eye(6), lam >= EPS, g2 >= 0]
    prob = cp.Problem(cp.Minimize(g2), cons)
    prob.solve(solver=cp.CLARABEL)
    return prob.status, float(np.sqrt(g2.value))


def main():
    solve()  # warm-up (imports, first canonicalisation)
    times = []
    for _ in range(7):
        t0 = time.perf_counter()
        status, gamma = solve()
        times.append(time.perf_counter() - t0)
    print(json.dumps({"cvxpy_hinf_design_ns": statistics.median(times) * 1e9, "gamma": gamma, "status": status}))


if __name__ == "__main__":
    main()
