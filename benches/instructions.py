"""Instruction counts (valgrind --tool=callgrind) of the main cases, the stable figure on a
shared machine, and the campaign throughput of `relnav reproduce` per scenario (issue 15,
items 4 and 5). Needs the release builds of examples/hinf_profile, examples/kalman_profile,
examples/pf_steps and the relnav CLI (scripts/bench.sh builds them). Prints one JSON line:

  {"instructions": {case: count per design or per step}, "iterations": {design: "n"},
   "throughput": {scenario: runs per second}}

Per-step Kalman counts (the bare step, the navigator's, the C ABI's and the FMU cycle) are
(I(n2) - I(n1)) / (n2 - n1) less the same for the measurement generation alone
(`kalman_profile none`), which cancels the setup.
Usage: instructions.py [--no-callgrind] [--no-throughput] [--runs R]
"""
import argparse
import json
import pathlib
import platform
import re
import shutil
import subprocess
import tempfile

root = pathlib.Path(__file__).resolve().parent.parent
rel = root / "target" / "release"


# without address-space randomisation where setarch can switch it off: the instructions of
# memcpy and the allocator depend on the addresses they get, which would move a count by
# tens of instructions from one run to the next
NO_ASLR = ["setarch", platform.machine(), "-R"] if shutil.which("setarch") else []


def callgrind(args):
    p = subprocess.run([*NO_ASLR, "valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", *args],
                       capture_output=True, text=True, check=True)
    return int(p.stderr.split("Collected : ")[1].split()[0]), p.stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--no-callgrind", action="store_true")
    ap.add_argument("--no-throughput", action="store_true")
    ap.add_argument("--runs", type=int, default=20)
    a = ap.parse_args()
    out = {"instructions": {}, "iterations": {}, "throughput": {}}
    if not a.no_callgrind and shutil.which("valgrind"):
        hp = str(rel / "examples" / "hinf_profile")
        for d in ("paper", "observer", "mixed"):
            n, text = callgrind([hp, d])
            out["instructions"][f"hinf_design_{d}"] = n
            # "N", "N+M" (mixed: both stages) or "0 (Riccati, T Riccati trials, ...)"
            m = re.search(r"iterations (\S+)", text)
            out["iterations"][f"hinf_design_{d}"] = m.group(1) if m else "?"
            t = re.search(r"\((Riccati), (\d+) Riccati trials", text)
            if t:
                out["iterations"][f"hinf_design_{d}"] += f" (Riccati, {t.group(2)} trials)"
        kp = str(rel / "examples" / "kalman_profile")
        n1, n2 = 100, 1100
        gen = {n: callgrind([kp, "none", str(n)])[0] for n in (n1, n2)}  # the measurements alone
        for f in ("ekf", "ukf"):
            # the bare step and the same step through the navigator, the C ABI and the FMU cycle
            # (FMI 2.0 and FMI 3.0)
            for mode, name in ((f, f"{f}_step"), (f"nav-{f}", f"navigator_step_{f}"),
                               (f"capi-{f}", f"capi_step_{f}"), (f"fmu-{f}", f"fmu_cycle_{f}"),
                               (f"fmu3-{f}", f"fmu3_cycle_{f}")):
                i1, _ = callgrind([kp, mode, str(n1)])
                i2, _ = callgrind([kp, mode, str(n2)])
                out["instructions"][name] = ((i2 - gen[n2]) - (i1 - gen[n1])) / (n2 - n1)
        # one declared sensor's update per step through the navigator, less the prediction
        # alone (the camera's and GNSS's update against the radio's)
        for f in ("ekf", "ukf"):
            per = {}
            for s in ("none", "radio", "camera", "gnss", "velocity"):
                i1, _ = callgrind([kp, f"sensor-{s}-{f}", str(n1)])
                i2, _ = callgrind([kp, f"sensor-{s}-{f}", str(n2)])
                per[s] = (i2 - i1) / (n2 - n1)
            for s in ("radio", "camera", "gnss", "velocity"):
                out["instructions"][f"update_{s}_{f}"] = per[s] - per["none"]
        # the navigator's EKF on the elliptic model (e = 0.1)
        i1, _ = callgrind([kp, "ecc-ekf", str(n1)])
        i2, _ = callgrind([kp, "ecc-ekf", str(n2)])
        out["instructions"]["navigator_step_ekf_elliptic"] = ((i2 - gen[n2]) - (i1 - gen[n1])) / (n2 - n1)
        # particle steps at N = 1500 (examples/pf_steps): (I(20 + 10) - I(20 + 0)) / 10
        pf = str(rel / "examples" / "pf_steps")
        for name, kind, moves in (("sir_literal", "pf", "literal"), ("sir", "pf", "moves"),
                                  ("rpf_literal", "rpf", "literal"), ("rpf", "rpf", "moves"),
                                  ("gapf_literal", "gapf", "literal"), ("gapf", "gapf", "moves"),
                                  ("upf_literal", "upf", "literal"), ("upf", "upf", "moves"),
                                  ("cgapf_literal", "cgapf", "literal"), ("cgapf", "cgapf", "moves"),
                                  *((f"{k}_particle_prior", k if k != "sir" else "pf", "particle")
                                    for k in ("sir", "rpf", "upf", "gapf", "cgapf"))):
            i0, _ = callgrind([pf, "1500", "20", "0", "1", kind, moves])
            i1, _ = callgrind([pf, "1500", "20", "10", "1", kind, moves])
            out["instructions"][f"{name}_step_n1500"] = (i1 - i0) / 10
    if not a.no_throughput:
        with tempfile.TemporaryDirectory() as tmp:
            p = subprocess.run([str(rel / "relnav"), "reproduce", "--paper", "all", "--runs", str(a.runs),
                                "--no-plots", "--out", tmp], capture_output=True, text=True, check=True)
        for m in re.finditer(r"^throughput (\S+): (\d+) runs of (\d+) steps, (\d+) filters in \S+ s = (\S+) runs/s",
                             p.stderr, re.M):
            out["throughput"][m.group(1)] = {"runs_per_s": float(m.group(5)), "steps": int(m.group(3)),
                                             "filters": int(m.group(4))}
    print(json.dumps(out))


if __name__ == "__main__":
    main()
