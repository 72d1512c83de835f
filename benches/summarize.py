"""Print the criterion medians of benches/filters.rs beside the filterpy anchor measured in
the same run, with the ratios the issue asks for (Markdown)."""
import json
import pathlib
import sys

root = pathlib.Path(__file__).resolve().parent.parent
crit = root / "target" / "criterion"


def median_ns(name):
    p = crit / name / "new" / "estimates.json"
    return json.loads(p.read_text())["median"]["point_estimate"]


anchor = json.loads(sys.argv[1])["filterpy_ukf_step_ns"] if len(sys.argv) > 1 else None
rows = ["ekf_step", "ukf_step", "navigator_step_ekf", "navigator_step_ukf",
        "capi_step_ekf", "capi_step_ukf", "fmu_cycle_ekf", "fmu_cycle_ukf"]
m = {r: median_ns(r) for r in rows}
print("| benchmark | median | target |")
print("|---|---:|---|")
targets = {"ekf_step": "<= 1000 ns", "ukf_step": "<= 2000 ns"}
for r in rows:
    print(f"| {r} | {m[r]:.0f} ns | {targets.get(r, '')} |")
for k in ("ekf", "ukf"):
    print(f"| fmu_cycle_{k} - {k}_step (FMI overhead: set 3 inputs, doStep, get 12 outputs) "
          f"| {m['fmu_cycle_' + k] - m[k + '_step']:.0f} ns | <= 500 ns |")
if anchor:
    print(f"| filterpy UnscentedKalmanFilter predict+update (same model, same run) | {anchor:.0f} ns | anchor |")
    print(f"| ratio filterpy / relnav UKF step | {anchor / m['ukf_step']:.0f}x | |")
    print(f"| ratio filterpy / relnav FMU UKF cycle | {anchor / m['fmu_cycle_ukf']:.0f}x | |")
