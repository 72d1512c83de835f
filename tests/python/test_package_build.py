"""How the Python package is built and installed: a wheel with its type information, and
one compiled relnav-core (and relnav-eval, relnav-fmi, relnav-nav-model) shared by the
CLI/FMU build and the extension's build: the features of every crate both depend on are the
same, and the extension's build holds the C ABI crate (whose rlib makes cargo emit object
code beside the LTO bitcode, as in `cargo build --release`), so cargo compiles those crates
once and the release build after setup compiles only the binaries and the FMU libraries
(measured: 53 s instead of about 115 s on 2 cores)."""

from __future__ import annotations

import importlib.resources
import re
import shutil
import subprocess

import pytest

import relnav
from conftest import REPO_ROOT

def crate_features(*packages: str) -> dict:
    cargo = shutil.which("cargo")
    if cargo is None:
        pytest.fail("cargo not found (scripts/test.sh puts ~/.cargo/bin on PATH)", pytrace=False)
    out = subprocess.run(
        [cargo, "tree", "--offline", "--locked", "-e", "features,no-dev", *(a for p in packages for a in ("-p", p)),
         "--prefix", "none", "-f", "{p} | {f}"],
        cwd=REPO_ROOT, capture_output=True, text=True, timeout=120, check=True,
    ).stdout
    feats: dict = {}
    for line in out.splitlines():
        m = re.match(r"^(\S+) v(\S+).*? \| (.*?)(?: \(\*\))?$", line)
        if m:
            feats[(m[1], m[2])] = m[3]
    return feats


def test_cli_and_extension_builds_share_relnavs_dependencies():
    # what `cargo build --release` builds (the workspace's default members) and the extension
    alone = crate_features(
        "relnav", "relnav-core", "relnav-eval", "relnav-fmi", "relnav-models", "relnav-nav-model", "relnav-fmu-pack"
    )
    ext = crate_features("relnav-python")
    differ = {k: (alone[k], ext[k]) for k in alone if k in ext and alone[k] != ext[k]}
    assert any(name == "relnav-core" for name, _ in ext) and len(alone) > 50
    # the C ABI crate in the extension's graph: without it its dependencies are LTO bitcode only
    assert any(name == "relnav" for name, _ in ext), "python/Cargo.toml must depend on relnav (see there)"
    assert not differ, (
        "these crates get other features in the Python extension's build than in `cargo build --release`, so "
        "relnav and its dependencies would be compiled twice; request the extension's features in the top-level "
        f"Cargo.toml (see the comment there): {differ}"
    )


def test_installed_package_has_its_type_information():
    files = importlib.resources.files("relnav")
    for name in ("py.typed", "_relnav.pyi", "errors.py", "_campaign.py"):
        assert files.joinpath(name).is_file(), name
    assert relnav.Estimator.__doc__ and "FMU" in relnav.Estimator.__doc__
    assert relnav.Estimator.run.__doc__ and "GIL" in relnav.Estimator.run.__doc__
    assert relnav.campaign.__doc__ and "bit-identical" in relnav.campaign.__doc__
