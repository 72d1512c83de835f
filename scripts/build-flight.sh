#!/usr/bin/env bash
# The flight library: relnav without std (no heap, no threads, no I/O, no SDP solver, no
# BLAS), panics aborting, built into target/flight/librelnav.a, then checked on programs
# linked against it (docs/c-abi.md#the-flight-library). Its code is first linted
# (`cargo clippy` without std, warnings as errors). Then:
#
#   * cpp-harness/examples/quickstart.c links with `-lm` alone (the C library and the math
#     library: nothing else is on the link line) and prints the estimate the
#     full library prints (target/release/librelnav.a, when it exists: the CI's release
#     stage builds it before this one);
#   * cpp-harness/flight/bits.c runs every filter of the flight library over the same
#     inputs against both libraries: the outputs (each estimate's bits in hexadecimal and
#     a checksum of every state and covariance) must be identical;
#   * cpp-harness/flight/every.c takes the address of every function of include/relnav.h
#     (the table every_fns.h is written from the header here), so every exported path is
#     linked, and checks that what the flight library leaves out answers "not in this
#     build";
#   * cpp-harness/flight/stack.c measures the stack depth of each call (every function of
#     the header, checked) over nominal and adversarial inputs (every filter, frames 1-3,
#     circular and eccentric orbits); the deepest must stay under FLIGHT_STACK_BOUND bytes
#     (the measured depth rounded up: it may only fall);
#   * cpp-harness/flight/work.c, run under callgrind, counts the instructions of single
#     steps of every filter, nominal and adversarial (burn, dropout, every sensor at once,
#     an outlier, the pole, zero range, huge thrust, 10 s and 3000 s steps; circular and
#     e = 0.5 orbits), and work_table.py prints each kind's worst step over the nominal
#     median; the nominal steps (one length, one sensor set) must stay within 1.5x of
#     their median, the other kinds are reported (more work by design: docs/c-abi.md);
#   * the stripped quickstart is at most 1 MiB; it and every.c reference no allocator
#     (malloc, free) and no symbol of Rust's std, and no `core::panicking` symbol (a panic
#     path the optimiser could not remove) is left in them. They are linked with
#     `--gc-sections`, as flight software is: without it the linker keeps every function of
#     the precompiled `core` objects it pulls in, unreferenced ones included;
#   * the library calls nothing of the platform but C math functions (sin, atan2, ...) and
#     memcpy/memset: the symbols every.c's program needs beyond every.c's own.
#
# Usage: bash scripts/build-flight.sh [-jN]. Prints the sizes and symbol counts.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
JOBS="${1:--j${RELNAV_JOBS:-2}}"
TARGET="${CARGO_TARGET_DIR:-$ROOT/target}"
OUT="$TARGET/flight"
CC="${CC:-cc}"
MAX_STRIPPED_BYTES=$((1024 * 1024))
FLIGHT_STACK_BOUND=$((32 * 1024))

# the build without std is a product of its own: its lints too
cargo clippy -p relnav --no-default-features --lib --profile flight "$JOBS" -- -D warnings
cargo build -p relnav --no-default-features --lib --profile flight "$JOBS"
LIB="$OUT/librelnav.a"
test -f "$LIB"

fail=0
check() {
    if "$@"; then return 0; fi
    echo "build-flight: FAILED: $*" >&2
    fail=1
}

cflags=(-O2 -std=c11 -D_DEFAULT_SOURCE -Iinclude -Wall -Wextra -Werror)
"$CC" "${cflags[@]}" cpp-harness/examples/quickstart.c "$LIB" -lm -Wl,--gc-sections -o "$OUT/quickstart"
"$CC" "${cflags[@]}" cpp-harness/flight/bits.c "$LIB" -lm -Wl,--gc-sections -o "$OUT/bits"
# the functions a C file calls or declares, one per line, sorted
functions() { grep -oE '\b(relnav_[a-z0-9_]+)\(' "$1" | tr -d '(' | sort -u; }
functions include/relnav.h | sed 's/.*/    (void *)\&&,/' > "$OUT/every_fns.h"
"$CC" "${cflags[@]}" -I"$OUT" cpp-harness/flight/every.c "$LIB" -lm -Wl,--gc-sections -o "$OUT/every"
# a measuring program: its threads are its own (the library starts none)
"$CC" "${cflags[@]}" cpp-harness/flight/stack.c "$LIB" -lm -lpthread -o "$OUT/stack"
"$CC" "${cflags[@]}" cpp-harness/flight/work.c "$LIB" -lm -o "$OUT/work"
strip -o "$OUT/quickstart.stripped" "$OUT/quickstart"

"$OUT/quickstart" > "$OUT/quickstart.out"
"$OUT/bits" > "$OUT/bits.out"
cat "$OUT/quickstart.out"
check "$OUT/every"
check "$OUT/stack" "$FLIGHT_STACK_BOUND"
# stack.c calls every function of the header
unmeasured=$(comm -23 <(functions include/relnav.h) <(functions cpp-harness/flight/stack.c))
[ -z "$unmeasured" ] || echo "build-flight: stack.c does not call: $unmeasured" >&2
check test -z "$unmeasured"
if command -v valgrind >/dev/null 2>&1; then
    rm -rf "$OUT/work.cg" && mkdir -p "$OUT/work.cg"
    # without address-space randomisation where setarch can switch it off (counts that
    # depend on addresses would move by a few instructions between runs)
    norand=()
    if command -v setarch >/dev/null 2>&1; then norand=(setarch "$(uname -m)" -R); fi
    "${norand[@]}" valgrind --tool=callgrind --collect-atstart=no --dump-instr=no \
        --callgrind-out-file="$OUT/work.cg/cg.out" "$OUT/work" 2> "$OUT/work.cg/valgrind.log"
    echo "instructions per step (worst of each kind / median of the nominal steps):"
    check python3 cpp-harness/flight/work_table.py "$OUT/work.cg" 1.5
else
    echo "build-flight: no valgrind: instruction counts per step skipped"
fi

size_lib=$(stat -c %s "$LIB")
size_exe=$(stat -c %s "$OUT/quickstart")
size_stripped=$(stat -c %s "$OUT/quickstart.stripped")
symbols=$(nm -C "$OUT/quickstart" "$OUT/every")
panics=$(grep -c 'core::panicking' <<<"$symbols" || true)
std_syms=$(grep -c ' std::' <<<"$symbols" || true)
allocs=$( { nm -u "$OUT/quickstart"; nm -u "$OUT/every"; } | grep -cE ' (malloc|calloc|realloc|free|posix_memalign|aligned_alloc)(@|$)' || true)
size_every=$(stat -c %s "$OUT/every")
echo "flight library: $LIB $size_lib bytes"
echo "quickstart linked against it: $size_exe bytes, $size_stripped stripped (limit $MAX_STRIPPED_BYTES)"
echo "every.c (all $(wc -l < "$OUT/every_fns.h") functions) linked against it: $size_every bytes"
echo "symbols in both: core::panicking $panics, std:: $std_syms, allocator $allocs"
# what the library asks of the platform: the symbols every.c's program needs that every.c
# itself does not call (a bare-metal port supplies these and nothing else)
"$CC" "${cflags[@]}" -I"$OUT" -c cpp-harness/flight/every.c -o "$OUT/every.o"
platform=$(comm -23 <(nm -u "$OUT/every" | awk '{print $2}' | sed 's/@.*//' | sort -u) \
    <(nm -u "$OUT/every.o" | awk '{print $2}' | sort -u) |
    grep -vE '^(_ITM_.*|__cxa_finalize|__gmon_start__|__libc_start_main)$' | tr '\n' ' ')
echo "the library's calls into the platform: $platform"
allowed='^(memcpy|memmove|memset|memcmp|bcmp|sin|cos|tan|asin|acos|atan|atan2|sinh|cosh|tanh|asinh|acosh|atanh|exp|exp2|expm1|log|log2|log10|log1p|pow|sqrt|cbrt|hypot|fma|fmod|floor|ceil|round|trunc)$'
check test -z "$(tr ' ' '\n' <<<"$platform" | grep -v '^$' | grep -vE "$allowed")"
check test "$size_stripped" -le "$MAX_STRIPPED_BYTES"
check test "$std_syms" -eq 0
check test "$allocs" -eq 0
check test "$panics" -eq 0

FULL="$TARGET/release/librelnav.a"
if [ -f "$FULL" ]; then
    full_libs=(-lpthread -ldl -lm)
    "$CC" "${cflags[@]}" cpp-harness/examples/quickstart.c "$FULL" "${full_libs[@]}" -o "$OUT/quickstart.full"
    "$CC" "${cflags[@]}" cpp-harness/flight/bits.c "$FULL" "${full_libs[@]}" -o "$OUT/bits.full"
    "$OUT/quickstart.full" > "$OUT/quickstart.full.out"
    "$OUT/bits.full" > "$OUT/bits.full.out"
    check cmp "$OUT/quickstart.out" "$OUT/quickstart.full.out"
    check cmp "$OUT/bits.out" "$OUT/bits.full.out"
    echo "flight and full library: quickstart and bits.c outputs $( [ $fail -eq 0 ] && echo identical || echo DIFFER)" \
        "($(wc -l < "$OUT/bits.out") filter runs)"
else
    echo "build-flight: $FULL not built: no comparison with the full library (cargo build --release first)"
fi
exit $fail
