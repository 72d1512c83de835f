#!/usr/bin/env bash
# Fuzz the C ABI, the FMU (FMI 2.0 and FMI 3.0 functions) and saved-state restores with
# cargo-fuzz (fuzz/README.md).
#
#   bash scripts/fuzz.sh smoke            # every target for RELNAV_FUZZ_SMOKE_SECONDS (20) s, side by side
#   bash scripts/fuzz.sh long RUNS        # each target for RUNS executions (10^7: hours)
#   bash scripts/fuzz.sh build            # only build the targets (scripts/test.sh starts this
#                                         # early, in the background, and runs `smoke` later)
#
# `smoke` and `build` use cargo-fuzz's dev build (fuzz/Cargo.toml: opt-level 1), which
# compiles far faster than its release build; `long` uses the release build.
#
# RELNAV_FUZZ_SANITIZER=none builds without AddressSanitizer (about three times the
# executions per second; separate target dir fuzz/target-nosan) for long campaigns; the
# default is address.
#
# Needs nightly Rust and cargo-fuzz (`cargo install cargo-fuzz`); without them `smoke`
# says so and exits 0 (scripts/test.sh runs it only when both are present). Runs under
# `nice`, one libFuzzer process per target (smoke: all at once; long: one at a time), 1 s per input
# (`-timeout=1`: a slower input is a hang and fails the run). New inputs go to a scratch
# corpus (the committed fuzz/corpus/<target> is read, never written); crashes go to
# fuzz/artifacts/<target>/.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
fi
mode="${1:-smoke}"
TARGETS=(capi fmi fmi3 state)

if ! rustup toolchain list 2>/dev/null | grep -q '^nightly' \
    || ! cargo +nightly --version >/dev/null 2>&1 \
    || ! cargo +nightly fuzz --version >/dev/null 2>&1; then
    echo "fuzz: SKIPPED: nightly Rust (rustup toolchain 'nightly') or cargo-fuzz is not installed"
    exit 0
fi
export CARGO_BUILD_JOBS="${RELNAV_JOBS:-2}"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

san="${RELNAV_FUZZ_SANITIZER:-address}"
build_args=(-s "$san")
if [ "$mode" = long ]; then
    build_args+=(--release)
else
    build_args+=(--dev)
fi
if [ "$san" = none ]; then
    build_args+=(--target-dir fuzz/target-nosan)
fi
nice -n 10 cargo +nightly fuzz build "${build_args[@]}"
if [ "$mode" = build ]; then
    exit 0
fi
case "$mode" in
    smoke) limit=(-max_total_time="${RELNAV_FUZZ_SMOKE_SECONDS:-20}") ;;
    long) limit=(-runs="${2:-10000000}") ;;
    *) echo "usage: $0 smoke|long [RUNS]" >&2; exit 2 ;;
esac
# one target's run into its log; its exit status into a file beside it
run_target() {
    local t="$1" status=0
    mkdir -p "$scratch/$t" "fuzz/corpus/$t"
    nice -n 10 cargo +nightly fuzz run "${build_args[@]}" "$t" "$scratch/$t" "fuzz/corpus/$t" -- \
        "${limit[@]}" -timeout=1 -max_len=1024 -rss_limit_mb=2048 -print_final_stats=1 \
        >"$scratch/$t.log" 2>&1 || status=$?
    echo "$status" >"$scratch/$t.status"
}
# the smoke run's targets side by side (each libFuzzer process is single-threaded: the
# run takes one time limit instead of one per target); the long run one after the other
if [ "$mode" = smoke ]; then
    pids=()
    for t in "${TARGETS[@]}"; do
        run_target "$t" &
        pids+=($!)
    done
    for p in "${pids[@]}"; do
        wait "$p" || true
    done
else
    for t in "${TARGETS[@]}"; do
        run_target "$t"
    done
fi
rc=0
for t in "${TARGETS[@]}"; do
    echo "== fuzz $t (${limit[*]})"
    status="$(cat "$scratch/$t.status" 2>/dev/null || echo 1)"
    grep -E '^(Done|stat::number_of_executed_units|==[0-9]+== ERROR|SUMMARY)|panicked at|INFO: seed corpus' \
        "$scratch/$t.log" || true
    if [ "$status" -ne 0 ]; then
        tail -n 60 "$scratch/$t.log"
        echo "!! fuzz $t failed (exit $status): see fuzz/artifacts/$t/"
        rc=1
    fi
done
exit "$rc"
