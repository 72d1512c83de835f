#!/usr/bin/env bash
# Builds and packs every FMU of relnav and the system kit, in target/fmu/:
#
#   relnav.fmu           the navigation estimator (librelnav.so: the C ABI and its fmi2* exports)
#   relnav_plant.fmu     the truth plant (fmu/plant: relnav without default features)
#   relnav_guidance.fmu  the hold-point guidance law (fmu/guidance: likewise)
#   relnav_system.ssp    the closed GNC loop of the three (fmu/ssp/*.ssd)
#
# (and each FMU unpacked in target/fmu/<id>/). The kit's cdylibs are built in their own
# cargo invocation and profile (`kit`, Cargo.toml: release without LTO; output target/kit/):
# cargo unifies a package's features within one invocation, and relnav's default features
# (its own fmi2* exports, the H-infinity design, the evaluation engine) must stay out of
# them. Extra arguments go to cargo (e.g. -j2). Set CARGO_TARGET_DIR as usual.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
fi

# the library and the packer in one invocation: built with `--lib` alone, the library is
# compiled with other LTO settings than when a binary of the package links it, and the
# packer's build (or `cargo build --release` before this script) would compile it again
cargo build --release --lib --bin relnav-fmu "$@"
# The kit's crates in a profile of their own: relnav is a cdylib of this workspace, and
# cargo writes its cdylib to one path per profile whatever its features, so the kit's
# relnav (no default features) must not share the release directory with relnav.fmu's.
TARGET="${CARGO_TARGET_DIR:-$ROOT/target}"
cargo build --profile kit -p relnav_plant -p relnav_guidance "$@"
# beside librelnav.so, where the packer looks
cp "$TARGET/kit/librelnav_plant.so" "$TARGET/kit/librelnav_guidance.so" "$TARGET/release/"
cargo run --release "$@" --bin relnav-fmu -- --all
