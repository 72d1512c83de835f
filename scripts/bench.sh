#!/usr/bin/env bash
# Benchmarks: criterion (cargo bench) plus the filterpy, numpy-SIR and cvxpy H-infinity anchors in the same run; prints
# medians and ratios as a Markdown table, callgrind instruction counts beside them, the FMU cycle's
# overhead timed interleaved (examples/kalman_profile time-json) and the campaign
# throughput (benches/instructions.py); then the Python package's bench (benches/bench_python.py). Usage: scripts/bench.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo bench --bench filters -- --warm-up-time 2 --measurement-time 5
cargo bench --bench pf -- --warm-up-time 2 --measurement-time 5
cargo bench --bench hinf -- --warm-up-time 1 --measurement-time 3
anchor=$(.venv/bin/python benches/anchor_filterpy.py)
numpy_sir=$(.venv/bin/python benches/anchor_numpy_sir.py)
# the H-infinity design anchor needs cvxpy + clarabel (bench only, not the test suite)
.venv/bin/python -m pip install --disable-pip-version-check -q --no-input -r benches/requirements-bench.txt </dev/null
cvxpy_hinf=$(.venv/bin/python benches/anchor_cvxpy_hinf.py 2>/dev/null)
# callgrind instruction counts (the stable figure) and campaign throughput (runs/s per scenario)
cargo build --release --example hinf_profile --example kalman_profile --example pf_steps --bin relnav
counts=$(.venv/bin/python benches/instructions.py)
# the FMU cycle's overhead over the bare step timed interleaved, batch by batch (the criterion
# medians' difference is biased by any drift of the host between the two benches)
paired=$(OPENBLAS_NUM_THREADS=1 target/release/examples/kalman_profile time-json 3000)
uptime
.venv/bin/python benches/summarize.py "$anchor" "$numpy_sir" "$cvxpy_hinf" "$counts" "$paired"
echo
# the Python package (relnav.Estimator against filterpy, Estimator.run, campaigns on Dask)
.venv/bin/python benches/bench_python.py --instructions
