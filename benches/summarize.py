"""Print the criterion medians of benches/filters.rs and benches/pf.rs beside the filterpy
and numpy-SIR anchors measured in the same run, with the ratios the issues ask for
(Markdown). Usage: summarize.py FILTERPY_JSON [NUMPY_SIR_JSON [CVXPY_HINF_JSON]]"""
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

numpy_sir = json.loads(sys.argv[2])["numpy_sir_step_ns"] if len(sys.argv) > 2 else None
pf_rows = [("sir_step_n1500", 1500, "<= 100 us"), ("rpf_step_n1500", 1500, ""),
           ("gapf_step_n1500", 1500, ""), ("upf_step_n1500", 1500, ""),
           ("cgapf_step_n1500", 1500, ""), ("sir_step_n100000", 100000, "")]
print()
print("| particle filter step (update + resampling when due + predict) | median | ns / particle | target |")
print("|---|---:|---:|---|")
pm = {}
for r, n, t in pf_rows:
    try:
        pm[r] = median_ns(r)
    except FileNotFoundError:
        continue
    print(f"| {r} | {pm[r] / 1000:.1f} us | {pm[r] / n:.1f} | {t} |")
if numpy_sir and "sir_step_n1500" in pm:
    print(f"| vectorised numpy SIR step, N = 1500 (same run) | {numpy_sir / 1000:.1f} us | {numpy_sir / 1500:.1f} | anchor |")
    print(f"| ratio numpy / relnav SIR step | {numpy_sir / pm['sir_step_n1500']:.1f}x | | |")

cvx = json.loads(sys.argv[3])["cvxpy_hinf_design_ns"] if len(sys.argv) > 3 and sys.argv[3] else None
print()
print("| H-infinity (paper 002) | median | target |")
print("|---|---:|---|")
hm = {}
for r, t in [("hinf_design/hinf_design_paper", "<= 0.5 s"), ("hinf_design/hinf_design_observer", ""),
             ("hinf_step", "<= 200 ns")]:
    try:
        hm[r] = median_ns(r)
    except FileNotFoundError:
        continue
    v = f"{hm[r] / 1e6:.1f} ms" if hm[r] > 1e5 else f"{hm[r]:.0f} ns"
    print(f"| {r} | {v} | {t} |")
if cvx and "hinf_design/hinf_design_paper" in hm:
    print(f"| cvxpy + Clarabel, same SDP, assembly included (same run) | {cvx / 1e6:.1f} ms | anchor |")
    print(f"| ratio cvxpy / relnav design | {cvx / hm['hinf_design/hinf_design_paper']:.2f}x | |")
