#!/usr/bin/env python3
"""Issue 10 item 4: every particle filter's efficiency (RMSE over the square root of the
PCRLB) against the particle count, through the evaluation engine (`relnav simulate`).

Scenarios (derived from the built-in files, written to a temporary directory):
* `paper000`: scenarios/paper000.toml (radio, paper 000's Q drives the truth and is the
  filters' Q);
* `paper003`: scenarios/paper003.toml (lidar, contaminated Gaussian zeta 0.2, scale 10);
* `quiet`: paper 000's geometry and sensor with honest small process noise: the truth is
  driven by a white acceleration of 1e-10 m^2/s^3 and every filter assumes exactly that
  (`accel_psd` 1e-10, `process_noise` zero); the truth's initial state is drawn from the
  filters' prior (50 m, 1 m/s), so the bound's initial information is the true one.

Each scenario file gets the EKF and every particle filter (`pf`, `rpf`, `upf`, `gapf`,
`cgapf`; point particles, `prior = "gaussian"`, with their moves on, the default of
`move`: the filters of issue 10; `--prior particle` for a Gaussian per particle, the
navigator's default since 7 December 2026) at each particle count; one campaign per scenario, so
every filter sees the same truths and measurements (the engine's seed: the scenario's
`simulation.seed`, run `i` from SplitMix64(seed, i); each filter its own particle seed
from the same stream). The engine reports `efficiency_pos` / `efficiency_vel`, the
time-averaged RMSE over the time-averaged root PCRLB after `convergence_time`.

    .venv/bin/python tools/pf_efficiency.py [--runs 5] [--particles 100,300,1000,3000,10000]
        [--scenarios paper000,quiet,paper003] [--prior gaussian] [--threads 2] [--keep DIR]

Needs `target/release/relnav` (`cargo build --release --bin relnav`). Prints one Markdown
table per scenario: efficiency pos / vel at each N, and the smallest N whose position and
velocity efficiency are both within `--within` (1.2) — '> N_max' when none is.
"""

from __future__ import annotations

import argparse
import csv
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
KINDS = [("pf", "SIR PF"), ("rpf", "RPF"), ("upf", "UPF"), ("gapf", "GA-PF"), ("cgapf", "CGA-PF")]
FILTER_KEYS = ["initial_state", "sigma_pos0", "sigma_vel0", "accel_psd", "process_noise"]


def fmt(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(fmt(x) for x in v) + "]"
    raise TypeError(v)


def base_text(path: Path) -> tuple[str, dict]:
    """The file up to its first [[filter]] (scenario, truth, sensor, simulation) and the
    first filter's keys (the EKF's: the prior and noise every filter here shares)."""
    text = path.read_text()
    head = text.split("[[filter]]", 1)[0]
    doc = tomllib.loads(text)
    first = doc["filter"][0]
    assert first["kind"] == "ekf", path
    return head, {k: first[k] for k in FILTER_KEYS if k in first}


def quiet_from(head: str, ekf: dict) -> tuple[str, dict]:
    """paper 000 with honest small process noise (see the module docs)."""
    lines = []
    section = ""
    for line in head.splitlines():
        s = line.strip()
        if s.startswith("["):
            section = s
        if s.startswith("name ="):
            line = 'name = "pf_efficiency_quiet"'
        elif s.startswith("title ="):
            line = 'title = "Paper 000 geometry, honest small process noise (1e-10 m^2/s^3)"'
        elif section == "[truth]" and s.startswith("process_noise"):
            line = "accel_psd = 1e-10"
        elif section == "[truth]" and s.startswith("initial_state"):
            # the truth drawn from the filters' prior, so that the bound's P0 is the
            # actual initial spread (paper 000's file starts the truth at a fixed offset)
            sd = [ekf["sigma_pos0"]] * 3 + [ekf["sigma_vel0"]] * 3
            line = f"initial_state = {fmt(ekf['initial_state'])}\ninitial_sigma = {fmt(sd)}"
        lines.append(line)
    f = dict(ekf)
    f["process_noise"] = [0.0] * 6
    f["accel_psd"] = 1e-10
    return "\n".join(lines) + "\n", f


def filter_block(label: str, kind: str, common: dict, particles: int | None, prior: str | None = None) -> str:
    out = ["[[filter]]", f"label = {fmt(label)}", f"kind = {fmt(kind)}"]
    out += [f"{k} = {fmt(v)}" for k, v in common.items()]
    if particles is not None:
        out.append(f"particles = {particles}")
    if prior is not None:
        out.append(f"prior = {fmt(prior)}")
    return "\n".join(out) + "\n\n"


def scenario_file(name: str, counts: list[int], tmp: Path, prior: str = "gaussian") -> Path:
    base = {"paper000": "paper000", "quiet": "paper000", "paper003": "paper003"}[name]
    head, common = base_text(ROOT / "scenarios" / f"{base}.toml")
    if name == "quiet":
        head, common = quiet_from(head, common)
    body = filter_block("EKF", "ekf", common, None)
    for kind, label in KINDS:
        for n in counts:
            body += filter_block(f"{label} N={n}", kind, common, n, prior)
    path = tmp / f"{name}.toml"
    path.write_text(head + "\n" + body)
    return path


def run(name: str, counts: list[int], runs: int, threads: int, tmp: Path, prior: str = "gaussian") -> list[dict]:
    path = scenario_file(name, counts, tmp, prior)
    out = tmp / "out"
    exe = ROOT / "target" / "release" / "relnav"
    cmd = [str(exe), "simulate", str(path), "--runs", str(runs), "--out", str(out),
           "--threads", str(threads), "--no-plots"]
    t0 = time.time()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    print(f"<!-- {name}: {runs} runs in {time.time() - t0:.0f} s -->", flush=True)
    scen = tomllib.loads(path.read_text())["name"]
    with open(out / scen / "summary.csv", newline="") as fh:
        return list(csv.DictReader(fh))


def table(name: str, rows: list[dict], counts: list[int], within: float) -> str:
    by = {r["label"]: r for r in rows}
    ekf = by["EKF"]
    pcrlb = f"PCRLB {float(ekf['pcrlb_pos_m']):.3g} m / {float(ekf['pcrlb_vel_mps']):.3g} m/s"
    lines = [
        f"**{name}** ({pcrlb}; runs {ekf['runs_used']}; EKF efficiency "
        f"{float(ekf['efficiency_pos']):.2f} / {float(ekf['efficiency_vel']):.2f})",
        "",
        "| filter | " + " | ".join(f"N = {n}" for n in counts) + f" | N within {within}x |",
        "|---|" + "---|" * len(counts) + "---|",
    ]
    for kind, label in KINDS:
        cells, need = [], None
        for n in counts:
            r = by[f"{label} N={n}"]
            ep, ev = float(r["efficiency_pos"]), float(r["efficiency_vel"])
            failed = int(r["failed_runs"])
            cells.append(f"{ep:.2f} / {ev:.2f}" + (f" ({failed} failed)" if failed else ""))
            if need is None and ep <= within and ev <= within and not failed:
                need = n
        lines.append(f"| {label} | " + " | ".join(cells) + f" | {need if need else f'> {counts[-1]}'} |")
    return "\n".join(lines) + "\n"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--particles", default="100,300,1000,3000,10000")
    ap.add_argument("--scenarios", default="paper000,quiet,paper003")
    ap.add_argument("--prior", choices=["gaussian", "particle"], default="gaussian",
                    help="the particle filters' prior: gaussian (point particles, the tables of docs/results.md) or particle")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--within", type=float, default=1.2)
    ap.add_argument("--keep", type=Path, help="keep the scenario files and results here")
    a = ap.parse_args()
    counts = [int(x) for x in a.particles.split(",")]
    with tempfile.TemporaryDirectory() as d:
        tmp = a.keep or Path(d)
        tmp.mkdir(parents=True, exist_ok=True)
        for name in a.scenarios.split(","):
            rows = run(name, counts, a.runs, a.threads, tmp, a.prior)
            print(table(name, rows, counts, a.within), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
