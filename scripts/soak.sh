#!/usr/bin/env bash
# Soak of every filter through the FMU (tests/soak.rs): 10^6 steps per Kalman-type filter
# (EKF, UKF, AQUKF, H-infinity), 10^5 per particle filter (point particles, and the default
# Gaussian per particle), against an independent truth, with random dropouts, burns and
# step sizes. Not part of scripts/test.sh (minutes on one core, the test build aside).
# Prints one table row per filter (lines "SOAK | ...") and keeps the log in
# target/soak/soak.log.
#
#   bash scripts/soak.sh                  # everything
#   bash scripts/soak.sh soak_ekf         # one filter (test name filter)
#   RELNAV_SOAK_SCALE=100 bash scripts/soak.sh   # 100 times fewer steps (a quick look)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
fi
mkdir -p target/soak
status=0
nice -n 10 cargo test -j"${RELNAV_JOBS:-2}" --test soak -- --ignored --nocapture --test-threads=1 "$@" \
    2>&1 | tee target/soak/soak.log || status=$?
echo
echo "== summary"
grep -m1 '^SOAK | filter' target/soak/soak.log || true
grep '^SOAK | ' target/soak/soak.log | grep -v '^SOAK | filter' || true
exit "$status"
