"""Bench of the relnav Python package (called by scripts/bench.sh after the criterion
benches, whose medians it reads from target/criterion when present):

1. ``Estimator.step`` (UKF and EKF) per step against filterpy's UKF predict+update on the
   same model and measurements (benches/anchor_filterpy.py), and the Python overhead per
   step over the Rust navigator step (criterion ``navigator_step_*``);
2. a 600-step ``Estimator.run`` (one call, GIL released): time per call and per step;
3. campaign throughput on paper 003 (runs per second) with 1 and 2 Dask workers
   (LocalCluster, one thread per worker process), on 2 local threads, and the CLI's
   `relnav simulate` with 1 and 2 threads for reference.

Usage: bench_python.py [--runs R] [--skip-campaign] [--instructions]. Prints Markdown tables;
--instructions adds instructions per step counted by callgrind (stable on a loaded machine).
"""

from __future__ import annotations

import argparse
import json
import logging
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import relnav

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benches"))
import anchor_filterpy as anchor  # noqa: E402

REPS = 15


def criterion_ns(name: str):
    p = ROOT / "target" / "criterion" / name / "new" / "estimates.json"
    return json.loads(p.read_text())["median"]["point_estimate"] if p.is_file() else None


def median_per_step(fn, steps: int) -> float:
    """Median over REPS repetitions of the time per step [ns] (the minimum is kept in
    MINIMA: on a loaded machine it is the better estimate of the unloaded time)."""
    samples = []
    for _ in range(REPS):
        t0 = time.perf_counter_ns()
        fn()
        samples.append((time.perf_counter_ns() - t0) / steps)
    MINIMA[fn] = min(samples)
    return statistics.median(samples)


MINIMA: dict = {}


def step_benches() -> list:
    zs = np.array(anchor.measurements())
    k = len(zs)
    thrust = np.zeros((k, 3))
    rows = []
    # filterpy's UKF: predict + update per measurement (its update reuses the predict's points)
    def filterpy_loop():
        f = anchor.make()
        for z in zs:
            f.predict()
            f.update(z)

    fp = median_per_step(filterpy_loop, k)
    fp_min = MINIMA[filterpy_loop]
    for name in ("ukf", "ekf"):
        def step_loop(name=name):
            est = relnav.Estimator(filter=name)
            step = est.step
            for i in range(k):
                step(thrust[i], zs[i], 1.0)

        def step_loop_lists(name=name):
            est = relnav.Estimator(filter=name)
            step = est.step
            u, zl = [0.0, 0.0, 0.0], zs.tolist()
            for i in range(k):
                step(u, zl[i], 1.0)

        def batch(name=name):
            relnav.Estimator(filter=name).run(thrust, zs)

        s_np = median_per_step(step_loop, k)
        s_list = median_per_step(step_loop_lists, k)
        run_step = median_per_step(batch, k)
        rust = criterion_ns(f"navigator_step_{name}")
        mins = (MINIMA[step_loop], MINIMA[step_loop_lists], MINIMA[batch])
        rows.append((name, s_np, s_list, run_step, rust, mins))
    return (fp, fp_min), rows


def cli_times(runs: int) -> list:
    """`relnav simulate` on the same scenario and runs, 1 and 2 threads (reference)."""
    import subprocess
    import tempfile

    cli = ROOT / "target" / "release" / "relnav"
    if not cli.is_file():
        return []
    out = []
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "paper003.toml"
        path.write_text(relnav.scenario_text("paper003"))
        for threads in (1, 2):
            t0 = time.perf_counter()
            subprocess.run([str(cli), "simulate", str(path), "--runs", str(runs), "--out", d, "--no-plots",
                            "--threads", str(threads)], check=True, capture_output=True)
            out.append((f"`relnav simulate` (CLI, rayon), {threads} thread{'s' if threads > 1 else ''}", runs,
                        time.perf_counter() - t0, None))
    return out


def campaign_benches(runs: int) -> list:
    from distributed import Client, LocalCluster

    out = []
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                          dashboard_address=None, silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
            # warm up: the workers import relnav and prepare the scenario once
            client.run(lambda: __import__("relnav").__version__)
            t0 = time.perf_counter()
            r = relnav.campaign("paper003", runs=runs, client=client, progress=False)
            dt = time.perf_counter() - t0
        out.append((f"relnav.campaign on Dask, {workers} worker process{'es' if workers > 1 else ''} x 1 thread",
                    runs, dt, r))
    t0 = time.perf_counter()
    r = relnav.campaign("paper003", runs=runs, threads=2, progress=False)
    out.append(("relnav.campaign on local threads (no client), 2 threads", runs, time.perf_counter() - t0, r))
    out.extend(cli_times(runs))
    # bit-identical whatever ran it (us_per_step is wall-clock, left out)
    ref = [{k: v for k, v in row.items() if k != "us_per_step"} for row in out[0][3].summary]
    for _, _, _, r in out[1:]:
        if r is None:
            continue
        got = [{k: v for k, v in row.items() if k != "us_per_step"} for row in r.summary]
        assert repr(got) == repr(ref), "campaign results differ between schedulers"
    return out


def cg_worker(mode: str, n: int, name: str, total: int) -> None:
    """What --instructions runs under callgrind: n steps of one kind. The `total`
    measurements are generated whatever n is (also for the baseline with n = 0), so that
    their generation (a Python loop in the anchor) cancels in the difference."""
    zs = np.array(anchor.measurements(max(total, n, 1)))
    u = np.zeros((max(total, n, 1), 3))
    est = relnav.Estimator(filter=name)
    if mode == "run" and n:
        est.run(u[:n], zs[:n])
    elif mode == "steps_np":
        for k in range(n):
            est.step(u[k], zs[k], 1.0)
    elif mode == "steps_list":
        ul, zl = [0.0, 0.0, 0.0], zs.tolist()
        for k in range(n):
            est.step(ul, zl[k], 1.0)


def instruction_counts(n: int = 6000) -> None:
    """Instructions per step (valgrind --tool=callgrind, stable under load): the same
    script with n steps minus with none, over n."""
    import os
    import platform
    import shutil
    import subprocess

    if shutil.which("valgrind") is None:
        print("(valgrind not found: no instruction counts)")
        return

    # The 0-step baseline (~4.7 G instructions: Python, numpy, relnav's imports) must be the
    # same in every run for the difference to mean anything. It was not: numpy's OpenBLAS
    # starts worker threads that spin for as long as the scheduler lets them (+-15 M between
    # runs, 2 500 per step at n = 6000: the EKF's difference came out negative), and
    # address-space randomisation moves id()-hashed objects (+-1 M). With one BLAS thread and
    # ASLR off (setarch -R) two baselines differ by ~3 000 instructions.
    norand = ["setarch", platform.machine(), "-R"] if shutil.which("setarch") else []

    def count(mode, steps, name):
        env = {**os.environ, "PYTHONHASHSEED": "0", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
        p = subprocess.run(norand + ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null",
                                     sys.executable, __file__, "--cg-worker", mode, str(steps), name, str(n)],
                           capture_output=True, text=True, env=env, check=True)
        return int(p.stderr.split("Collected : ")[1].split()[0])

    print()
    print(f"| instructions per step (callgrind, {n} steps minus none) | UKF | EKF |")
    print("|---|---:|---:|")
    res = {}
    for name in ("ukf", "ekf"):
        base = count("run", 0, name)
        res[name] = {m: (count(m, n, name) - base) / n for m in ("run", "steps_list", "steps_np")}
    labels = {"run": "Estimator.run (the Rust step + 12 copies)", "steps_list": "Estimator.step, lists",
              "steps_np": "Estimator.step, numpy rows"}
    for m, label in labels.items():
        print(f"| {label} | {res['ukf'][m]:.0f} | {res['ekf'][m]:.0f} |")
    for m in ("steps_list", "steps_np"):
        print(f"| overhead of {labels[m]} over run | {res['ukf'][m] - res['ukf']['run']:.0f} | "
              f"{res['ekf'][m] - res['ekf']['run']:.0f} |")


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--cg-worker":
        cg_worker(sys.argv[2], int(sys.argv[3]), sys.argv[4], int(sys.argv[5]))
        return
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=16, help="paper 003 runs per campaign (default 16: four chunks)")
    ap.add_argument("--skip-campaign", action="store_true")
    ap.add_argument("--instructions", action="store_true", help="also count instructions per step (callgrind)")
    ap.add_argument("--instructions-only", action="store_true", help="only the callgrind counts")
    args = ap.parse_args()
    if args.instructions_only:
        instruction_counts()
        return

    (fp, fp_min), rows = step_benches()
    print("| Python package, paper 000 (600 steps, 1 s, radio) | per step, median (min) "
          "| filterpy UKF / this | overhead over the Rust step |")
    print("|---|---:|---:|---:|")
    print(f"| filterpy UnscentedKalmanFilter predict+update (same run) | {fp / 1000:.1f} us ({fp_min / 1000:.1f}) | 1 | |")
    for name, s_np, s_list, run_step, rust, mins in rows:
        over = (lambda v: f"{(v - rust) / 1000:.2f} us") if rust else (lambda v: "n/a (no criterion run)")
        ratio = (lambda v: f"{fp / v:.0f}x") if name == "ukf" else (lambda v: "")
        for label, v, m in [(f"relnav Estimator.step, {name.upper()} (numpy rows)", s_np, mins[0]),
                            (f"relnav Estimator.step, {name.upper()} (lists)", s_list, mins[1]),
                            (f"relnav Estimator.run, {name.upper()} (600 steps in one call: "
                             f"{run_step * 600 / 1e6:.3f} ms)", run_step, mins[2])]:
            print(f"| {label} | {v / 1000:.2f} us ({m / 1000:.2f}) | {ratio(v)} | {over(v)} |")
        if rust:
            print(f"| Rust navigator_step_{name} (criterion median, same bench.sh run) | {rust / 1000:.2f} us | | |")
    if args.instructions:
        instruction_counts()
    if args.skip_campaign:
        return
    print()
    print(f"| campaign, paper 003 ({args.runs} runs, 9 filters, 101 steps) | wall time | runs / s |")
    print("|---|---:|---:|")
    for label, runs, dt, _ in campaign_benches(args.runs):
        print(f"| {label} | {dt:.1f} s | {runs / dt:.3f} |")


if __name__ == "__main__":
    main()
