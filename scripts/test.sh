#!/usr/bin/env bash
# relnav's single test command (CI runs it through .ci/run):
#
#   setup (scripts/setup.sh, also builds and installs the Python package relnav)
#   -> cargo fmt --check -> cargo clippy -D warnings (workspace, every target: benches and
#   examples are compiled and linted here) -> cargo test (libraries, binaries, tests/)
#   -> cargo build --release -> the flight library (scripts/build-flight.sh: relnav without
#   std, its programs checked against the release library) -> the bare-metal targets
#   (scripts/build-bare.sh: the flight library for a Cortex-M4F and AArch64, run on qemu) -> FMUs and SSP (fmu/build.sh: relnav.fmu, the system kit's
#   relnav_plant.fmu, relnav_guidance.fmu, relnav_system.ssp)
#   -> pytest tests/python (in .venv, two workers) -> C++ harness (cmake, build, ctest; valgrind)
#   -> C++ harness under ASan+UBSan (second build dir) -> fuzz smoke run (scripts/fuzz.sh
#   smoke, the targets side by side for 20 s, only when nightly Rust and cargo-fuzz are
#   installed)
#
# The fuzz targets' build (cargo-fuzz's dev profile with AddressSanitizer, its own target
# dir) starts in the background right after setup and runs beside the stages in front; the
# fuzz smoke stage waits for what is left of it. Its `nice 10` does not lower its share:
# `setsid` makes it a scheduler autogroup of its own (Linux), and autogroups share the CPUs
# equally (measured: 47 % of the CPU time while clippy and the test build ran). Giving its
# autogroup nice 19 instead was measured slower overall (1764 s against 1417 s: it then
# ran at the end, 263 s waited for, much of it on one core, as cargo-fuzz builds each
# crate as one codegen unit), so it keeps its equal share.
#
# Every stage is run and reported; a stage that later ones need (setup, release build,
# FMU) stops the run when it fails. Exits non-zero if any stage failed; the last line is
# the summary ("stages: N passed, N failed"). Non-interactive: works with CI=true and no
# stdin.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
fi
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"
# every build here is a full one from the clone's state: incremental compilation would only
# write caches (time and disk) that a one-shot run never reads
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
JOBS="${RELNAV_JOBS:-2}"
# the Python extension (python/, in the workspace) is checked against the venv's Python
export PYO3_PYTHON="${PYO3_PYTHON:-$ROOT/.venv/bin/python}"

declare -a STAGE_NAMES=() STAGE_RESULTS=()
T_START=$SECONDS

banner() {
    printf '\n'
    printf '==============================================================================\n'
    printf '== %s\n' "$*"
    printf '==============================================================================\n'
}

summary() {
    local passed=0 failed=0 i line=""
    for i in "${!STAGE_NAMES[@]}"; do
        line+="${STAGE_NAMES[$i]}: ${STAGE_RESULTS[$i]}; "
        case "${STAGE_RESULTS[$i]}" in
            ok*) passed=$((passed + 1)) ;;
            FAILED*) failed=$((failed + 1)) ;;
        esac
    done
    banner "summary ($((SECONDS - T_START)) s)"
    printf '%s\n' "${line%; }"
    printf 'stages: %d passed, %d failed\n' "$passed" "$failed"
}

# stage NAME required|optional CMD...: run CMD, record the result; a failed required
# stage ends the run (after the summary).
stage() {
    local name="$1" kind="$2" t0=$SECONDS rc=0
    shift 2
    banner "$name"
    printf '$ %s\n' "$*"
    if "$@" </dev/null; then
        STAGE_NAMES+=("$name")
        STAGE_RESULTS+=("ok ($((SECONDS - t0)) s)")
    else
        rc=$?
        STAGE_NAMES+=("$name")
        STAGE_RESULTS+=("FAILED (exit $rc)")
        printf '\n!! stage "%s" failed with exit code %d\n' "$name" "$rc"
        if [ "$kind" = required ]; then
            printf '!! later stages need it: stopping\n'
            summary
            exit 1
        fi
    fi
}

run_pytest() {
    local rc=0
    # two workers (pytest-xdist): most tests are single-threaded Python driving an FMU
    "$ROOT/.venv/bin/python" -m pytest -q -p no:cacheprovider -n "$JOBS" --durations=5 tests/python || rc=$?
    if [ "$rc" -eq 5 ]; then
        echo "pytest collected no tests (exit 5): counted as a failure"
    fi
    return "$rc"
}

run_cpp_harness() {
    cmake -S cpp-harness -B cpp-harness/build -DCMAKE_BUILD_TYPE=Debug -DRELNAV_REQUIRE_FLIGHT=ON &&
        cmake --build cpp-harness/build -j"$JOBS" &&
        ctest --test-dir cpp-harness/build --output-on-failure -j"$JOBS"
}

# The same harness under AddressSanitizer + UndefinedBehaviorSanitizer (a second build
# directory; the valgrind tests are not defined there). Any report fails the test.
run_cpp_harness_sanitized() {
    cmake -S cpp-harness -B cpp-harness/build-asan -DCMAKE_BUILD_TYPE=Debug -DRELNAV_SANITIZE=ON &&
        cmake --build cpp-harness/build-asan -j"$JOBS" &&
        ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:halt_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1" \
            UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
            ctest --test-dir cpp-harness/build-asan --output-on-failure -j"$JOBS"
}

# The fuzz targets' build in the background (see the header); its output goes to a log that
# the fuzz smoke stage prints.
FUZZ_BUILD_PID=""
FUZZ_BUILD_LOG=""
# (scripts/fuzz.sh checks for nightly Rust and cargo-fuzz itself: without them both the
# build and the smoke run say SKIPPED and succeed)
start_fuzz_build() {
    FUZZ_BUILD_LOG="$(mktemp)"
    # its own process group (setsid), so that an early exit stops cargo and rustc too
    setsid bash scripts/fuzz.sh build >"$FUZZ_BUILD_LOG" 2>&1 </dev/null &
    FUZZ_BUILD_PID=$!
    echo "fuzz targets: building in the background (pid $FUZZ_BUILD_PID, nice 10)"
}
stop_fuzz_build() {
    if [ -n "$FUZZ_BUILD_PID" ]; then
        kill -- "-$FUZZ_BUILD_PID" 2>/dev/null || kill "$FUZZ_BUILD_PID" 2>/dev/null || true
    fi
    if [ -n "$FUZZ_BUILD_LOG" ]; then
        rm -f "$FUZZ_BUILD_LOG"
    fi
}
trap stop_fuzz_build EXIT

# A short run of each cargo-fuzz target (fuzz/README.md), only when nightly Rust and
# cargo-fuzz are installed (scripts/setup.sh installs cargo-fuzz when nightly exists;
# scripts/fuzz.sh says SKIPPED otherwise).
run_fuzz_smoke() {
    if [ -n "$FUZZ_BUILD_PID" ]; then
        local rc=0 t0=$SECONDS
        wait "$FUZZ_BUILD_PID" || rc=$?
        FUZZ_BUILD_PID=""
        echo "fuzz targets' background build: exit $rc (waited $((SECONDS - t0)) s for it)"
        tail -n 40 "$FUZZ_BUILD_LOG"
        if [ "$rc" -ne 0 ]; then
            return "$rc"
        fi
    fi
    bash scripts/fuzz.sh smoke
}

stage "setup" required bash scripts/setup.sh
start_fuzz_build
stage "cargo fmt --check" optional cargo fmt --all -- --check
stage "cargo clippy" optional cargo clippy --workspace --all-targets -j"$JOBS" -- -D warnings
stage "cargo test" optional cargo test --workspace --exclude relnav-python --tests -j"$JOBS"
stage "cargo test --doc" optional cargo test --workspace --exclude relnav-python --doc -j"$JOBS"
stage "cargo build --release" required cargo build --release -j"$JOBS"
stage "flight library" optional bash scripts/build-flight.sh -j"$JOBS"
stage "bare-metal targets" optional bash scripts/build-bare.sh -j"$JOBS"
stage "build FMUs" required bash fmu/build.sh -j"$JOBS"
stage "pytest tests/python" optional run_pytest
stage "C++ harness" optional run_cpp_harness
stage "C++ harness (ASan+UBSan)" optional run_cpp_harness_sanitized
stage "fuzz smoke" optional run_fuzz_smoke

summary
for r in "${STAGE_RESULTS[@]}"; do
    case "$r" in FAILED*) exit 1 ;; esac
done
exit 0
