#!/usr/bin/env python3
"""Issue 10's table: every particle filter against the EKF run with the same parameters on
the same measurements, through the relnav FMU (fmpy FMU2Slave), truth from the independent
numpy CW model (tools/cwtruth.py).

Cases (cwtruth.family_scenario): paper 000's geometry and radio sensor in I/O frames 1-3,
a 60 s burn known through the thrust inputs, a 30 s dropout, 600 s at 1 Hz; filter process
noise the FMU defaults (paper 000's Q) or honest for the quiet truth (white acceleration
1e-10 m^2/s^3, q_pos = q_vel = 0); Gaussian noise or paper 003's contaminated Gaussian
(zeta 0.2, scale 10); and paper 000's own example at the FMU defaults. Errors over
t >= 80 s. Each run uses one seed for the measurement noise and the particle filter.

    .venv/bin/python tools/pf_family.py [--seeds 3] [--particles 1500] [--prior 1] [--workers 2]

Prints a Markdown table per case (RMSE, ratios to the EKF, worst ratio over the seeds)
and the wall-clock microseconds per FMU step (indicative: measured on a shared machine;
criterion benches, scripts/bench.sh, hold the speed figures).
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import cwtruth as cw  # noqa: E402
import relnav_fmu as rf  # noqa: E402

T_FROM = 80.0
NAMES = {"ekf": 1, **rf.PARTICLE_FILTERS}
CASES = [(f"gauss-f{f}-{q}", f, q == "small", False) for q in ("small", "fmu") for f in (1, 2, 3)]
CASES += [(f"mix-f{f}-{q}", f, q == "small", True) for q in ("small", "fmu") for f in (2,)]
CASES += [("paper000", 2, False, False)]
_worker: dict = {}


def _init(unzipdir: str) -> None:
    _worker["runner"] = rf.SlaveRunner(Path(unzipdir))


def _run(job):
    key, frame, small_q, mixture, seed, name, particles, prior = job
    sc = cw.paper000_scenario(2) if key == "paper000" else cw.family_scenario(frame, small_q, mixture)
    params = {**sc.params, "filter": NAMES[name], "seed": seed, "particles": particles}
    if name != "ekf":
        params["pf_prior"] = prior
    t0 = time.perf_counter()
    out = _worker["runner"].run(params, sc.times, sc.thrust, sc.measurements(seed), sc.valid)
    us = 1e6 * (time.perf_counter() - t0) / sc.steps
    sel = sc.times >= T_FROM
    err = out[:, :6] - sc.truth_io
    pos = float(np.sqrt(np.mean(np.sum(err[sel, :3] ** 2, axis=-1))))
    vel = float(np.sqrt(np.mean(np.sum(err[sel, 3:] ** 2, axis=-1))))
    return (key, seed, name), (pos, vel, us)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fmu", type=Path, default=rf.locate_fmu())
    ap.add_argument("--seeds", type=int, default=3, help="seeds per case (100 + case index * 10 + k)")
    ap.add_argument("--particles", type=int, default=1500)
    ap.add_argument("--prior", type=int, default=1, help="pf_prior: 1 gaussian (points), 2 particle (a Gaussian per particle)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--cases", default="", help="comma-separated case keys (default: all)")
    args = ap.parse_args(argv)
    cases = [c for c in CASES if not args.cases or c[0] in args.cases.split(",")]
    with tempfile.TemporaryDirectory(prefix="relnav-fmu-") as tmp:
        unzipdir = rf.unpack(args.fmu, Path(tmp) / "relnav")
        jobs = [
            (key, f, q, m, 100 + 10 * i + k, name, args.particles, args.prior)
            for i, (key, f, q, m) in enumerate(cases)
            for k in range(args.seeds)
            for name in NAMES
        ]
        jobs.sort(key=lambda j: j[5] not in ("upf", "cgapf"))
        with mp.get_context("fork").Pool(args.workers, initializer=_init, initargs=(str(unzipdir),)) as pool:
            res = dict(pool.map(_run, jobs, chunksize=1))
    prior = {1: "Gaussian prior", 2: "particle prior"}.get(args.prior, f"pf_prior {args.prior}")
    print(f"## Particle filters against the EKF ({args.particles} particles, {prior}, {args.seeds} seeds per case, t >= {T_FROM:g} s)")
    print()
    print("| case | filter | pos RMSE [m] | vel RMSE [m/s] | pos / EKF (worst seed) | vel / EKF (worst seed) | us per step |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for i, (key, *_rest) in enumerate(cases):
        seeds = [100 + 10 * i + k for k in range(args.seeds)]
        for name in NAMES:
            r = np.array([res[(key, s, name)] for s in seeds])
            e = np.array([res[(key, s, "ekf")] for s in seeds])
            pos, vel = np.sqrt(np.mean(r[:, 0] ** 2)), np.sqrt(np.mean(r[:, 1] ** 2))
            epos, evel = np.sqrt(np.mean(e[:, 0] ** 2)), np.sqrt(np.mean(e[:, 1] ** 2))
            wp, wv = np.max(r[:, 0] / e[:, 0]), np.max(r[:, 1] / e[:, 1])
            print(
                f"| {key} | {name} | {pos:.3f} | {vel:.4f} | {pos / epos:.2f} ({wp:.2f}) | "
                f"{vel / evel:.2f} ({wv:.2f}) | {np.median(r[:, 2]):.0f} |"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
