"""A reference extended Kalman filter in plain numpy, written from the textbook
equations and relnav's documented step semantics (not from relnav's code), to check the
FMU's EKF number for number.

Per step k (time t_k, step h_k): if a measurement z_k (taken at t_k) is valid, update

    nu = z - h(x)  (azimuth wrapped to (-pi, pi]),  S = H P H^T + R,  K = P H^T S^-1
    x += K nu,  P = (I - K H) P (I - K H)^T + K R K^T

then predict over h_k with the thrust held: x = Phi x + Gamma a, P = Phi P Phi^T + Q with
Q = diag(q_pos h, q_vel h) given per I/O axis (accel_psd = 0). Everything is done in the
I/O frame (the CW matrices rotated into it), so no frame conversion is needed.
"""

from __future__ import annotations

import numpy as np

import cwtruth as cw


def _h_and_jacobian(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    px, py, pz = p
    rho2 = px * px + py * py + pz * pz
    rho = np.sqrt(rho2)
    rxy2 = px * px + py * py
    rxy = np.sqrt(rxy2)
    z = np.array([rho, np.mod(np.arctan2(py, px), 2 * np.pi), np.arcsin(pz / rho)])
    h = np.zeros((3, 6))
    h[0, :3] = p / rho
    h[1, :3] = [-py / rxy2, px / rxy2, 0.0]
    h[2, :3] = [-px * pz / (rho2 * rxy), -py * pz / (rho2 * rxy), rxy / rho2]
    return z, h


def _wrap_pi(a: float) -> float:
    w = np.mod(a, 2 * np.pi)
    return w - 2 * np.pi if w > np.pi else w


def defaults() -> dict:
    """The FMU's parameter defaults (paper 000's example), by the FMU's names."""
    p = dict(
        frame=2,
        mean_motion=cw.PAPER000_N,
        chaser_mass=1000.0,
        sigma_range=cw.PAPER000_SIGMA_RANGE,
        sigma_angle=cw.PAPER000_SIGMA_ANGLE,
        sigma_pos0=50.0,
        sigma_vel0=1.0,
    )
    for name, v in zip(["x0", "y0", "z0", "vx0", "vy0", "vz0"], cw.PAPER000_EST0):
        p[name] = v
    for axis, qp, qv in zip("xyz", cw.PAPER000_Q_POS, cw.PAPER000_Q_VEL):
        p[f"q_pos_{axis}"] = qp
        p[f"q_vel_{axis}"] = qv
    return p


def run_ekf(params: dict, times, thrust, meas, valid) -> np.ndarray:
    """Reference EKF. ``params`` uses the FMU's names (missing ones take the FMU defaults of
    paper 000). Returns (N+1, 12): state and 1-sigma per axis, as the FMU's outputs."""
    p = defaults()
    p.update(params)
    frame = int(p["frame"])
    n = float(p["mean_motion"])
    r6 = cw.rot6(frame)
    t3 = cw.FRAME_ROT[frame]
    q_rate = np.array([p[f"q_pos_{a}"] for a in "xyz"] + [p[f"q_vel_{a}"] for a in "xyz"])
    r_mat = np.diag([p["sigma_range"] ** 2, p["sigma_angle"] ** 2, p["sigma_angle"] ** 2])

    x = np.array([p[k] for k in ["x0", "y0", "z0", "vx0", "vy0", "vz0"]], dtype=float)
    pc = np.diag([p["sigma_pos0"] ** 2] * 3 + [p["sigma_vel0"] ** 2] * 3)

    times = np.asarray(times, dtype=float)
    out = np.empty((len(times), 12))
    out[0, :6] = x
    out[0, 6:] = np.sqrt(np.diag(pc))
    cache: dict[float, tuple[np.ndarray, np.ndarray]] = {}
    for k in range(len(times) - 1):
        if valid[k]:
            zp, hm = _h_and_jacobian(x[:3])
            nu = np.asarray(meas[k], dtype=float) - zp
            nu[1] = _wrap_pi(nu[1])
            s = hm @ pc @ hm.T + r_mat
            gain = np.linalg.solve(s, hm @ pc).T
            x = x + gain @ nu
            ikh = np.eye(6) - gain @ hm
            pc = ikh @ pc @ ikh.T + gain @ r_mat @ gain.T
            pc = 0.5 * (pc + pc.T)
        h = float(times[k + 1] - times[k])
        if h not in cache:
            e = cw.zoh_step_matrix(n, h)
            phi_io = r6 @ e[:6, :6] @ r6.T
            gamma_io = r6 @ e[:6, 6:] @ t3.T  # I/O acceleration -> I/O state
            cache[h] = (phi_io, gamma_io)
        phi_io, gamma_io = cache[h]
        x = phi_io @ x + gamma_io @ (np.asarray(thrust[k], dtype=float) / p["chaser_mass"])
        pc = phi_io @ pc @ phi_io.T + np.diag(q_rate * h)
        pc = 0.5 * (pc + pc.T)
        out[k + 1, :6] = x
        out[k + 1, 6:] = np.sqrt(np.diag(pc))
    return out
