"""Errors of every filter over one phase of a run: the position and velocity RMSE and the
mean NEES over `from <= t < to`, from the `timeseries.csv` that `relnav simulate` writes
(per-time RMSE over the runs; the phase's RMSE is the root of their time average, as the
summary's figures after the convergence time are).

    python tools/phase_rmse.py results/sensors_angles_only/timeseries.csv --from 660 --to 1800

Prints a Markdown table. The standard library alone: it runs wherever the CSV is.
"""
import argparse
import csv
import math


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("timeseries")
    ap.add_argument("--from", dest="t0", type=float, default=float("-inf"))
    ap.add_argument("--to", dest="t1", type=float, default=float("inf"))
    a = ap.parse_args()
    with open(a.timeseries, newline="") as f:
        rows = [r for r in csv.DictReader(f) if a.t0 <= float(r["t"]) < a.t1]
    if not rows:
        raise SystemExit(f"no time in [{a.t0}, {a.t1})")
    labels = [k[: -len("_rmse_pos")] for k in rows[0] if k.endswith("_rmse_pos")]

    def rms(label, col):
        return math.sqrt(sum(float(r[f"{label}_{col}"]) ** 2 for r in rows) / len(rows))

    print(f"| filter ({len(rows)} times in [{a.t0:g}, {a.t1:g})) | pos RMSE [m] | vel RMSE [m/s] | NEES avg |")
    print("|---|---:|---:|---:|")
    for label in labels:
        nees = sum(float(r[f"{label}_nees"]) for r in rows) / len(rows)
        print(f"| {label} | {rms(label, 'rmse_pos'):.1f} | {rms(label, 'rmse_vel'):.5f} | {nees:.2f} |")


if __name__ == "__main__":
    main()
