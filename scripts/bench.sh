#!/usr/bin/env bash
# Benchmarks: criterion (cargo bench) plus the filterpy anchor in the same run; prints
# medians and ratios as a Markdown table. Usage: scripts/bench.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo bench --bench filters -- --warm-up-time 2 --measurement-time 5
anchor=$(.venv/bin/python benches/anchor_filterpy.py)
.venv/bin/python benches/summarize.py "$anchor"
