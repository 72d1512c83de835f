#!/usr/bin/env bash
# Idempotent machine set-up for relnav on Debian with the Rust toolchain already present.
#
#   * apt-get installs what is missing: cmake, g++, valgrind, binutils (readelf),
#     libopenblas-dev and libgfortran-12-dev (static BLAS/LAPACK for the H-infinity design),
#     fonts-dejavu-core (text in the plots), libtbb12 (the Ecos co-simulation engine that
#     the FMU tests drive needs libtbb.so.12) and
#     python3-venv (only if `python3 -m venv` does not work). `apt-get update` runs only
#     when something has to be installed. sudo is used when not root.
#   * for the bare-metal targets (scripts/build-bare.sh), apt-get also installs Debian's
#     Rust with its source (rustc-web, cargo-web, rust-web-src: /usr/bin/cargo and rustc,
#     which a rustup toolchain first on PATH leaves alone), the ARM and AArch64 cross
#     compilers (gcc-arm-none-eabi with libnewlib-arm-none-eabi, gcc-aarch64-linux-gnu) and
#     qemu-user; qemu-system-arm is unpacked from its package into .tools/qemu and its
#     libraries installed, not the package itself: it would replace a newer backported
#     qemu-utils where the machine has one.
#   * creates .venv at the repository root and installs scripts/requirements.txt into it
#     (skipped when the venv already matches the requirements file).
#   * installs cargo-fuzz with `cargo install` when nightly Rust is present and cargo-fuzz
#     is not (for the fuzz smoke run; RELNAV_NO_FUZZ=1 skips it), in the background while
#     the venv's packages download and install.
#   * builds the Python package relnav (python/, PyO3) as a wheel with maturin (release,
#     in the shared target/; a no-op for cargo when nothing changed) into target/wheels/
#     and installs it into .venv (RELNAV_SKIP_PYTHON_PACKAGE=1 skips this step).
#
# Non-interactive (DEBIAN_FRONTEND=noninteractive, no stdin needed); exports nothing
# beyond this process. Re-running it when everything is in place does nothing.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv"
REQ="$ROOT/scripts/requirements.txt"
PYTHON="${PYTHON:-python3}"

# each line with the seconds since the set-up started (where its time goes, for the CI budget)
log() { printf '[setup %4ds] %s\n' "$SECONDS" "$*"; }

# ---------------------------------------------------------------- system packages
SUDO=()
if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then
        SUDO=(sudo -n)
    else
        log "not root and no sudo: cannot install system packages"
    fi
fi

missing=()
command -v cmake >/dev/null 2>&1 || missing+=(cmake)
command -v ctest >/dev/null 2>&1 || missing+=(cmake)
command -v g++ >/dev/null 2>&1 || missing+=(g++)
command -v valgrind >/dev/null 2>&1 || missing+=(valgrind)
command -v readelf >/dev/null 2>&1 || missing+=(binutils)
# static BLAS/LAPACK and Fortran runtime for the H-infinity design (build.rs links them
# statically into the library, so the FMU stays self-contained)
ls /usr/lib/x86_64-linux-gnu/libopenblas.a /usr/lib/x86_64-linux-gnu/openblas-pthread/libopenblas.a \
    >/dev/null 2>&1 || [ -n "${RELNAV_OPENBLAS_DIR:-}" ] || missing+=(libopenblas-dev)
{ gcc -print-file-name=libgfortran.a 2>/dev/null | grep -q / \
    && gcc -print-file-name=libquadmath.a 2>/dev/null | grep -q /; } \
    || [ -n "${RELNAV_GFORTRAN_DIR:-}" ] || missing+=(libgfortran-12-dev)
# the font the evaluation engine's PNG plots use for their text
[ -f /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf ] || missing+=(fonts-dejavu-core)
# Intel TBB runtime: ecospy's libecosc.so needs libtbb.so.12 (OSError at import otherwise)
{ dpkg -s libtbb12 >/dev/null 2>&1 || /sbin/ldconfig -p 2>/dev/null | grep -q 'libtbb\.so\.12 '; } \
    || missing+=(libtbb12)

# the bare-metal targets (scripts/build-bare.sh)
dpkg -s rustc-web cargo-web rust-web-src >/dev/null 2>&1 || missing+=(rustc-web cargo-web rust-web-src)
command -v arm-none-eabi-gcc >/dev/null 2>&1 || missing+=(gcc-arm-none-eabi)
dpkg -s libnewlib-arm-none-eabi >/dev/null 2>&1 || missing+=(libnewlib-arm-none-eabi)
command -v aarch64-linux-gnu-gcc >/dev/null 2>&1 || missing+=(gcc-aarch64-linux-gnu libc6-dev-arm64-cross)
command -v qemu-aarch64 >/dev/null 2>&1 || missing+=(qemu-user)

venv_works() {
    local probe
    probe="$(mktemp -d)"
    if "$PYTHON" -m venv "$probe/v" >/dev/null 2>&1 && [ -x "$probe/v/bin/python" ]; then
        rm -rf "$probe"
        return 0
    fi
    rm -rf "$probe"
    return 1
}
if ! command -v "$PYTHON" >/dev/null 2>&1; then
    missing+=(python3 python3-venv python3-pip)
elif [ ! -x "$VENV/bin/python" ] && ! venv_works; then
    missing+=(python3-venv)
fi

if [ "${#missing[@]}" -gt 0 ]; then
    # de-duplicate, keep order
    mapfile -t missing < <(printf '%s\n' "${missing[@]}" | awk '!seen[$0]++')
    if [ "$(id -u)" -ne 0 ] && [ "${#SUDO[@]}" -eq 0 ]; then
        log "error: missing ${missing[*]} and cannot install them (not root, no sudo)"
        exit 1
    fi
    log "installing with apt-get: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    "${SUDO[@]}" apt-get update -qq </dev/null
    "${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" </dev/null
else
    log "system packages present: cmake g++ valgrind readelf fonts-dejavu-core libopenblas-dev libgfortran-12-dev libtbb12, and the bare-metal tools"
fi

# qemu-system-arm, for the Cortex-M4 board: unpacked, with the libraries it links
QEMU_DIR="$ROOT/.tools/qemu"
if ! command -v qemu-system-arm >/dev/null 2>&1 && [ ! -x "$QEMU_DIR/usr/bin/qemu-system-arm" ]; then
    log "unpacking qemu-system-arm into $QEMU_DIR"
    deb_dir="$(mktemp -d)"
    download=(apt-get download -q)
    # as root, apt would hand the download to its sandbox user, who cannot write there
    [ "$(id -u)" -ne 0 ] || download+=(-o APT::Sandbox::User=root)
    (cd "$deb_dir" && "${download[@]}" qemu-system-arm </dev/null)
    deb=("$deb_dir"/qemu-system-arm_*.deb)
    mapfile -t qemu_libs < <(dpkg-deb -f "${deb[0]}" Depends | tr ',' '\n' | sed 's/([^)]*)//; s/|.*//; s/ //g' |
        grep -vE '^(qemu-system-common|qemu-system-data|)$')
    need=()
    for pkg in "${qemu_libs[@]}"; do dpkg -s "$pkg" >/dev/null 2>&1 || need+=("$pkg"); done
    if [ "${#need[@]}" -gt 0 ]; then
        log "installing with apt-get: ${need[*]}"
        DEBIAN_FRONTEND=noninteractive "${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${need[@]}" </dev/null
    fi
    rm -rf "$QEMU_DIR" && mkdir -p "$QEMU_DIR"
    dpkg-deb -x "${deb[0]}" "$QEMU_DIR"
    rm -rf "$deb_dir"
fi

# ---------------------------------------------------------------- cargo-fuzz (optional)
# When a nightly toolchain is installed (the machine image ships one beside stable),
# install cargo-fuzz for the fuzz smoke run of scripts/test.sh (scripts/fuzz.sh). It is a
# crates.io build of ~1.5 min on 2 cores, done once; skipped when already installed, when
# there is no nightly, or with RELNAV_NO_FUZZ=1. A failed install only skips the smoke run.
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
fi
# (nightly is looked up in `rustup toolchain list` first, so that no rustup ever tries to
# download a missing toolchain)
if [ "${RELNAV_NO_FUZZ:-0}" != 1 ] && command -v cargo >/dev/null 2>&1 \
    && rustup toolchain list 2>/dev/null | grep -q '^nightly' \
    && cargo +nightly --version >/dev/null 2>&1 \
    && ! cargo +nightly fuzz --version >/dev/null 2>&1; then
    # in the background, beside the Python packages' download and install (network-bound);
    # waited for before the Python package's build below
    log "installing cargo-fuzz (nightly Rust is present), in the background"
    FUZZ_LOG="$(mktemp)"
    cargo install --locked -q -j "${RELNAV_JOBS:-2}" cargo-fuzz >"$FUZZ_LOG" 2>&1 </dev/null &
    FUZZ_PID=$!
fi
wait_cargo_fuzz() {
    if [ -n "${FUZZ_PID:-}" ]; then
        if wait "$FUZZ_PID"; then
            log "cargo-fuzz installed"
        else
            cat "$FUZZ_LOG"
            log "warning: cargo-fuzz did not install: the fuzz smoke run will be skipped"
        fi
        rm -f "$FUZZ_LOG"
        FUZZ_PID=""
    fi
}

# ---------------------------------------------------------------- Python venv
if [ -x "$VENV/bin/python" ] && ! "$VENV/bin/python" -c 'import sys' >/dev/null 2>&1; then
    log "existing .venv is broken: recreating"
    rm -rf "$VENV"
fi
if [ ! -x "$VENV/bin/python" ]; then
    log "creating $VENV"
    "$PYTHON" -m venv "$VENV"
fi

STAMP="$VENV/.relnav-requirements.sha256"
want="$(sha256sum "$REQ" | cut -d' ' -f1)"
have="$(cat "$STAMP" 2>/dev/null || true)"
if [ "$want" = "$have" ] && "$VENV/bin/python" -c 'import fmpy, numpy, pytest, xdist, filterpy, libcosimpy.CosimExecution, ecospy, fmu_manipulation_toolbox, maturin, tqdm, dask, distributed' >/dev/null 2>&1; then
    log "venv up to date ($(cd "$ROOT" && "$VENV/bin/python" -c 'import fmpy, numpy; print("fmpy", fmpy.__version__, "numpy", numpy.__version__)'))"
else
    log "installing Python packages from scripts/requirements.txt"
    # --no-compile: no bytecode for every module of every package now (a quarter of the
    # install's time); Python writes it for the modules it imports, when it imports them
    "$VENV/bin/python" -m pip install --disable-pip-version-check -q --no-input --no-compile -r "$REQ" </dev/null
    echo "$want" >"$STAMP"
    log "venv ready ($("$VENV/bin/python" -c 'import fmpy, numpy; print("fmpy", fmpy.__version__, "numpy", numpy.__version__)'))"
fi

wait_cargo_fuzz

# ---------------------------------------------------------------- Python package relnav
# maturin (from PyPI, in the venv) drives cargo on python/Cargo.toml, a member of the
# workspace: the wheel is built in target/ beside the CLI and the FMU and shares their
# compiled relnav. Rebuilt every time (cargo decides what changed), then installed.
if [ "${RELNAV_SKIP_PYTHON_PACKAGE:-0}" != 1 ]; then
    if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
        PATH="$HOME/.cargo/bin:$PATH"
    fi
    WHEELS="$ROOT/target/wheels"
    rm -rf "$WHEELS"
    log "building the Python package relnav (maturin build --release)"
    CARGO_BUILD_JOBS="${RELNAV_JOBS:-2}" "$VENV/bin/python" -m maturin build --release --quiet \
        -m "$ROOT/python/Cargo.toml" -i "$VENV/bin/python" -o "$WHEELS" </dev/null
    wheel=("$WHEELS"/relnav-*.whl)
    "$VENV/bin/python" -m pip install --disable-pip-version-check -q --no-input --no-deps \
        --force-reinstall "${wheel[0]}" </dev/null
    log "relnav $("$VENV/bin/python" -c 'import relnav; print(relnav.__version__)') installed from ${wheel[0]##*/}"
fi
