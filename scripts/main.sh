#!/usr/bin/env bash
# relnav's main job: set up, build the FMU, print paper 000's accuracy table through the
# FMU (EKF and UKF with fmpy, 20 seeded runs; the five particle filters with their moves, 10 runs;
# every one must meet the paper's bar), then reproduce every paper's numerical
# example with the evaluation engine (`relnav reproduce --paper all`: Markdown tables,
# CSV time series and PNG plots under results/).
# Extra arguments go to tools/paper000_fmu.py (e.g. --driver slave, --frame 3).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
fi

echo "== setup"
bash scripts/setup.sh </dev/null
echo "== build the FMU (target/fmu/relnav.fmu)"
# the packer copies target/release/librelnav.so: build the library first (`cargo run`
# builds only the packer's own binary and would otherwise pack a stale or missing library)
cargo build --release --lib </dev/null
cargo run --release --bin relnav-fmu </dev/null
echo "== paper 000 through the FMU"
"$ROOT/.venv/bin/python" tools/paper000_fmu.py "$@"
echo "== relnav reproduce --paper all (evaluation engine; plots and CSV in results/)"
cargo run --release --bin relnav -- reproduce --paper all --runs 10 --out results </dev/null
