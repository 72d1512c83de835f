#!/usr/bin/env bash
# Builds and packs every FMU of relnav and the system kit, in target/fmu/:
#
#   relnav.fmu           the navigation estimator (fmu/relnav: its fmi2* exports and the C ABI)
#   relnav_plant.fmu     the truth plant (fmu/plant)
#   relnav_guidance.fmu  the hold-point guidance law (fmu/guidance)
#   relnav_system.ssp    the closed GNC loop of the three (fmu/ssp/*.ssd)
#   relnav3.fmu          the estimator as FMI 3.0 (the same library as relnav.fmu)
#   relnav_plant3.fmu, relnav_guidance3.fmu   the kit as FMI 3.0 (the same libraries)
#
# (and each FMU unpacked in target/fmu/<id>/). The three cdylibs and the packer
# `relnav-fmu` (fmu/pack) are default members of the workspace: the plain release build
# (`cargo build --release`, which scripts/test.sh has run just before) builds them with
# the rest in one feature resolution, so here it has nothing left to do. A build of the
# FMU packages alone (`-p ...`) would resolve other features for shared dependencies and
# compile them again. Only the cdylibs export fmi2* symbols, one model each. Extra
# arguments go to cargo (e.g. -j2). Set CARGO_TARGET_DIR as usual.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
fi

cargo build --release "$@"
TARGET="${CARGO_TARGET_DIR:-$ROOT/target}"
# the packer finds the cdylibs beside itself, in target/release/
"$TARGET/release/relnav-fmu" --all
