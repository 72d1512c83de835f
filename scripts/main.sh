#!/usr/bin/env bash
# relnav's main job: set up, build the FMU, print paper 000's accuracy table through the
# FMU (EKF and UKF with fmpy, 20 seeded runs; the five particle filters with their moves, 10 runs;
# every one must meet the paper's bar), then reproduce every paper's numerical
# example with the evaluation engine (`relnav reproduce --paper all`: Markdown tables,
# CSV time series and PNG plots under results/), and run the system kit's closed GNC loop
# (relnav_system.ssp: plant -> relnav -> guidance) in fmpy, libcosim and Ecos, with its
# plots results/relnav_system_<variant>.png.
# Extra arguments go to tools/paper000_fmu.py (e.g. --driver slave, --frame 3).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
fi

echo "== setup"
bash scripts/setup.sh </dev/null
echo "== build the FMUs and the SSP (target/fmu/: relnav.fmu, relnav_plant.fmu, relnav_guidance.fmu, relnav_system.ssp)"
# fmu/build.sh builds the libraries first (the packer copies them) and then packs
bash fmu/build.sh </dev/null
echo "== paper 000 through the FMU"
"$ROOT/.venv/bin/python" tools/paper000_fmu.py "$@"
echo "== relnav reproduce --paper all (evaluation engine; plots and CSV in results/)"
cargo run --release --bin relnav -- reproduce --paper all --runs 10 --out results </dev/null
echo "== system kit: the closed GNC loop of relnav_system.ssp in fmpy, libcosim and Ecos (plots in results/)"
"$ROOT/.venv/bin/python" tools/relnav_system.py --plot-dir results </dev/null
