#!/usr/bin/env bash
# Benchmarks: criterion (cargo bench) plus the filterpy and numpy-SIR anchors in the same run; prints
# medians and ratios as a Markdown table. Usage: scripts/bench.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo bench --bench filters -- --warm-up-time 2 --measurement-time 5
cargo bench --bench pf -- --warm-up-time 2 --measurement-time 5
anchor=$(.venv/bin/python benches/anchor_filterpy.py)
numpy_sir=$(.venv/bin/python benches/anchor_numpy_sir.py)
.venv/bin/python benches/summarize.py "$anchor" "$numpy_sir"
