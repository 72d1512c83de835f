#!/usr/bin/env bash
# Builds and packs every FMU of relnav and the system kit, in target/fmu/:
#
#   relnav.fmu           the navigation estimator (fmu/relnav: its fmi2* exports and the C ABI)
#   relnav_plant.fmu     the truth plant (fmu/plant)
#   relnav_guidance.fmu  the hold-point guidance law (fmu/guidance)
#   relnav_system.ssp    the closed GNC loop of the three (fmu/ssp/*.ssd)
#
# (and each FMU unpacked in target/fmu/<id>/). The kit's cdylibs are built in their own
# cargo invocation and profile (`kit`, Cargo.toml: release without LTO; output target/kit/):
# cargo unifies a package's features within one invocation, and relnav-fmi's feature
# `fmi-exports` (relnav.fmu's fmi2* symbols) must stay out of them. Extra arguments go to
# cargo (e.g. -j2). Set CARGO_TARGET_DIR as usual.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
fi

cargo build --release -p relnav_fmu -p relnav-fmi --lib --bins "$@"
TARGET="${CARGO_TARGET_DIR:-$ROOT/target}"
cargo build --profile kit -p relnav_plant -p relnav_guidance "$@"
# beside librelnav_fmu.so, where the packer looks
cp "$TARGET/kit/librelnav_plant.so" "$TARGET/kit/librelnav_guidance.so" "$TARGET/release/"
"$TARGET/release/relnav-fmu" --all
