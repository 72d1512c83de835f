#!/usr/bin/env bash
# The flight library on bare-metal targets (docs/c-abi.md#bare-metal-targets): built for
# a Cortex-M4F (thumbv7em-none-eabihf) and a 64-bit ARM (aarch64-unknown-none) and run on
# each under an emulator, and built only for the targets RELNAV_BARE_BUILD_ONLY names (for
# example riscv32imac-unknown-none-elf: no emulator of a bare RISC-V board is installed;
# not in CI, where that build would add half a minute and run nothing):
#
#   * no precompiled `core` for these targets can be downloaded here, so `core` is built
#     from Debian's source of its own Rust (packages rustc-web, cargo-web, rust-web-src:
#     the compiler and its source are one version) with cargo's `-Zbuild-std=core`, an
#     unstable flag that RUSTC_BOOTSTRAP=1 allows on that stable compiler. Only `core`:
#     the build fails if anything needs `alloc` or `std`;
#   * Cortex-M4F: cpp-harness/examples/quickstart.c, cpp-harness/flight/bits.c and
#     cpp-harness/flight/every.c are linked with arm-none-eabi-gcc and newlib (output by
#     semihosting; reset code and memory map in cpp-harness/bare/) and run on the emulated
#     MPS2 AN386 board (qemu-system-arm);
#   * AArch64: the same programs, linked statically with the library's AArch64 objects
#     into Linux programs, run under qemu-aarch64 (the library's code is the bare-metal
#     target's; only the C side and its start-up are Linux's);
#   * the checks: every.c passes on both (what the flight library leaves out answers "not
#     in this build"); no `core::panicking` symbol in any program; the quickstart prints
#     what it prints on the host; and bits.c prints the same bits on the Cortex-M4F, on
#     AArch64 and on the host. On these targets the library's archive carries Rust's
#     compiler_builtins, whose math functions (sin, atan2, ...; the `libm` crate) the
#     programs then use, where the host's use the C library's; so the host's bits.c is
#     linked here against those same functions (cpp-harness/bare/libm-shim) and must match
#     the targets' bit for bit. Against the C library's math the host differs in the last
#     bits: the final estimates must stay within 1e-6 m and 1e-9 m/s (they are 3e-13
#     apart, docs/c-abi.md).
#
# scripts/setup.sh installs the tools (qemu-system-arm unpacked into .tools/). Usage: bash
# scripts/build-bare.sh [-jN]. Prints the program sizes on the Cortex-M4F.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
JOBS="${1:--j${RELNAV_JOBS:-2}}"
TARGET="${CARGO_TARGET_DIR:-$ROOT/target}"
OUT="$TARGET/bare"
DEB_RUSTC=/usr/bin/rustc
DEB_CARGO=/usr/bin/cargo
QEMU_SYSTEM_ARM="${QEMU_SYSTEM_ARM:-$(command -v qemu-system-arm || echo "$ROOT/.tools/qemu/usr/bin/qemu-system-arm")}"
M4=thumbv7em-none-eabihf
A64=aarch64-unknown-none
read -r -a BUILD_ONLY <<<"${RELNAV_BARE_BUILD_ONLY:-}"

missing=()
for tool in "$DEB_RUSTC" "$DEB_CARGO" arm-none-eabi-gcc arm-none-eabi-nm aarch64-linux-gnu-gcc qemu-aarch64 "$QEMU_SYSTEM_ARM"; do
    command -v "$tool" >/dev/null 2>&1 || missing+=("$tool")
done
if [ "${#missing[@]}" -eq 0 ]; then
    CORE_SRC="$("$DEB_RUSTC" --print sysroot)/lib/rustlib/src/rust/library/core"
    [ -d "$CORE_SRC" ] || missing+=("$CORE_SRC (rust-web-src)")
fi
if [ "${#missing[@]}" -gt 0 ]; then
    echo "build-bare: missing ${missing[*]}: run scripts/setup.sh" >&2
    exit 1
fi
echo "build-bare: $("$DEB_RUSTC" --version), core from $CORE_SRC"

# the Debian compiler, cargo and build scripts alone: nothing of rustup's toolchain
mkdir -p "$OUT"
if ! env PATH=/usr/bin:/bin RUSTC="$DEB_RUSTC" RUSTC_BOOTSTRAP=1 CARGO_TARGET_DIR="$OUT/cargo" \
    "$DEB_CARGO" build --locked -p relnav --no-default-features --lib --profile flight \
    -Zbuild-std=core --target "$M4" --target "$A64" "${BUILD_ONLY[@]/#/--target=}" "$JOBS" > "$OUT/cargo.log" 2>&1; then
    cat "$OUT/cargo.log"
    echo "build-bare: the build failed" >&2
    exit 1
fi
# (the crate's cdylib has no meaning on these targets: cargo says so for each)
grep -v "dropping unsupported crate type \`cdylib\`\|generated 1 warning\|^$" "$OUT/cargo.log" || true
lib() { echo "$OUT/cargo/$1/flight/librelnav.a"; }

fail=0
check() {
    if "$@"; then return 0; fi
    echo "build-bare: FAILED: $*" >&2
    fail=1
}
# machine of each archive's objects, as readelf names it
for t in "$M4" "$A64" "${BUILD_ONLY[@]}"; do
    echo "$t: $(readelf -h "$(lib "$t")" | grep -m1 Machine: | sed 's/.*Machine: *//'), $(stat -c %s "$(lib "$t")") bytes"
done

# the host's flight library and the libm crate's math for it
cargo build -q -p relnav --no-default-features --lib --profile flight "$JOBS"
CARGO_TARGET_DIR="$OUT/shim" cargo build -q --locked --release "$JOBS" \
    --manifest-path cpp-harness/bare/libm-shim/Cargo.toml

mkdir -p "$OUT/m4" "$OUT/a64" "$OUT/host"
common=(-O2 -std=c11 -D_DEFAULT_SOURCE -ffp-contract=off -Iinclude -Wall -Wextra -Werror)
programs=(quickstart:cpp-harness/examples/quickstart.c bits:cpp-harness/flight/bits.c every:cpp-harness/flight/every.c)
# every.c's table of the header's functions, as build-flight.sh writes it
grep -oE '\b(relnav_[a-z0-9_]+)\(' include/relnav.h | tr -d '(' | sort -u |
    sed 's/.*/    (void *)\&&,/' > "$OUT/every_fns.h"

m4cc=(arm-none-eabi-gcc "${common[@]}" -I"$OUT" -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard)
a64cc=(aarch64-linux-gnu-gcc "${common[@]}" -I"$OUT" -static)
for p in "${programs[@]}"; do
    name="${p%%:*}" src="${p#*:}"
    "${m4cc[@]}" "$src" cpp-harness/bare/cortex-m4.c "$(lib "$M4")" --specs=rdimon.specs -nostartfiles \
        -T cpp-harness/bare/mps2-an386.ld -lm -Wl,--gc-sections -Wl,--no-warn-execstack -o "$OUT/m4/$name.elf"
    "${a64cc[@]}" "$src" "$(lib "$A64")" -lm -Wl,--gc-sections -o "$OUT/a64/$name"
    # a fault or a hang ends in a failed check, not a stuck run
    check timeout 600 "$QEMU_SYSTEM_ARM" -M mps2-an386 -nographic -monitor none -serial none \
        -semihosting -kernel "$OUT/m4/$name.elf" > "$OUT/m4/$name.raw"
    # the reset code's last line, the deepest stack (cpp-harness/bare/cortex-m4.c), apart
    grep '^#stack ' "$OUT/m4/$name.raw" | sed "s/^#stack /$name /" > "$OUT/m4/$name.stack" || true
    grep -v '^#stack ' "$OUT/m4/$name.raw" > "$OUT/m4/$name.out" || true
    check timeout 600 qemu-aarch64 "$OUT/a64/$name" > "$OUT/a64/$name.out"
done
cc "${common[@]}" cpp-harness/examples/quickstart.c "$TARGET/flight/librelnav.a" -lm -o "$OUT/host/quickstart"
cc "${common[@]}" cpp-harness/flight/bits.c "$TARGET/flight/librelnav.a" \
    -L"$OUT/shim/release" -lrelnav_libm -Wl,-rpath,"$OUT/shim/release" -lm -o "$OUT/host/bits.libm"
cc "${common[@]}" cpp-harness/flight/bits.c "$TARGET/flight/librelnav.a" -lm -o "$OUT/host/bits.c-math"
"$OUT/host/quickstart" > "$OUT/host/quickstart.out"
"$OUT/host/bits.libm" > "$OUT/host/bits.libm.out"
"$OUT/host/bits.c-math" > "$OUT/host/bits.c-math.out"

cat "$OUT/m4/quickstart.out"
check cmp "$OUT/m4/quickstart.out" "$OUT/host/quickstart.out"
check cmp "$OUT/a64/quickstart.out" "$OUT/host/quickstart.out"
check cmp "$OUT/m4/bits.out" "$OUT/a64/bits.out"
check cmp "$OUT/m4/bits.out" "$OUT/host/bits.libm.out"
echo "bits.c ($(wc -l < "$OUT/m4/bits.out") filter runs): Cortex-M4F, AArch64 and the host with the same math:" \
    "$( cmp -s "$OUT/m4/bits.out" "$OUT/a64/bits.out" && cmp -s "$OUT/m4/bits.out" "$OUT/host/bits.libm.out" \
        && echo identical || echo DIFFER); with the C library's math on the host:" \
    "$(cmp -s "$OUT/m4/bits.out" "$OUT/host/bits.c-math.out" && echo identical || echo "differs in the last bits")"
# the host with the C library's math: round-off apart
check python3 - "$OUT/m4/bits.out" "$OUT/host/bits.c-math.out" <<'PY'
import struct, sys
def finals(path):
    out = {}
    for line in open(path):
        key, rest = line.split(": checksum ")
        out[key] = [struct.unpack(">d", bytes.fromhex(v))[0] for v in rest.split("state")[1].split()]
    return out
a, b = finals(sys.argv[1]), finals(sys.argv[2])
assert a.keys() == b.keys(), "not the same runs"
pos = max(abs(u - v) for k in a for u, v in zip(a[k][:3], b[k][:3]))
vel = max(abs(u - v) for k in a for u, v in zip(a[k][3:], b[k][3:]))
print(f"  the final estimates: at most {pos:.2g} m and {vel:.2g} m/s apart")
# the math functions differ by an ulp or so; 400 steps do not make that a micrometre
sys.exit(0 if pos < 1e-6 and vel < 1e-9 else 1)
PY
tail -n 1 "$OUT/m4/every.out"
panics=$( { arm-none-eabi-nm -C "$OUT"/m4/*.elf; nm -C "$OUT"/a64/quickstart "$OUT"/a64/bits "$OUT"/a64/every; } |
    grep -c 'core::panicking' || true)
echo "core::panicking symbols in the programs: $panics"
check test "$panics" -eq 0
echo "Cortex-M4F programs (newlib's printf included):"
arm-none-eabi-size "$OUT"/m4/*.elf
echo "their deepest stack, main and all it calls, bytes: $(cat "$OUT"/m4/*.stack | tr '\n' ' ')"
# the host's bound on a call's stack (build-flight.sh), here for a whole program
while read -r name bytes; do
    check test "$bytes" -le $((32 * 1024))
done < <(cat "$OUT"/m4/*.stack)
check test "$(cat "$OUT"/m4/*.stack | wc -l)" -eq "${#programs[@]}"
exit $fail
