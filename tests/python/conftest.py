"""Shared fixtures for relnav's FMU test suite.

The FMU is found at ``target/fmu/relnav.fmu`` relative to the repository root (or at
$RELNAV_FMU). Build it first with ``bash fmu/build.sh`` (scripts/test.sh
does). The truth model and the FMU drivers live in ``tools/`` and are shared with
``tools/paper000_fmu.py``.
"""

from __future__ import annotations

import ctypes
import re
import sys
from pathlib import Path

import numpy as np
import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO_ROOT / "tools"))

import cwtruth as cw  # noqa: E402
import relnav_fmu as rf  # noqa: E402
import relnav_fmu3 as rf3  # noqa: E402

RUNS = cw.PAPER000_RUNS

HEADER = REPO_ROOT / "include" / "relnav.h"
C_TYPES = {"int32_t": ctypes.c_int32, "uint64_t": ctypes.c_uint64, "double": ctypes.c_double, "bool": ctypes.c_bool}


def header_struct(name: str) -> type:
    """ctypes.Structure of the C ABI's struct ``name``, field by field from
    include/relnav.h (the checked-in cbindgen header: fields appended there need no change
    in the tests)."""
    body = re.search(rf"typedef struct {name} \{{(.*?)\}} {name};", HEADER.read_text(), re.S)
    assert body, f"{HEADER}: {name} not found"
    fields = []
    for m in re.finditer(r"^\s*(\w+)\s+(\w+)(?:\[(\d+)\])?;", body[1], re.M):
        ty = C_TYPES[m[1]]
        fields.append((m[2], ty * int(m[3]) if m[3] else ty))
    assert fields, f"{HEADER}: {name} has no fields"
    return type(name, (ctypes.Structure,), {"_fields_": fields})


def header_status(name: str) -> int:
    """The value of the ``relnav_status`` code ``name`` in include/relnav.h."""
    m = re.search(rf"^\s*{name} = (-?\d+),", HEADER.read_text(), re.M)
    assert m, f"{HEADER}: {name} not found"
    return int(m[1])
SEEDS = list(range(RUNS))


def pytest_report_header(config):
    path = rf.locate_fmu()
    if path.is_file():
        import time

        stamp = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(path.stat().st_mtime))
        return f"relnav FMU: {path} (built {stamp})"
    return f"relnav FMU: {path} MISSING - build it with `bash fmu/build.sh`"


def _built(path: Path, env: str) -> Path:
    if not path.is_file():
        pytest.fail(
            f"FMU not found at {path}.\n"
            "Build it first: `bash fmu/build.sh` from the repository root "
            f"(scripts/test.sh does this), or point ${env} at an .fmu file.",
            pytrace=False,
        )
    return path


@pytest.fixture(scope="session")
def fmu_path() -> Path:
    return _built(rf.locate_fmu(), "RELNAV_FMU")


@pytest.fixture(scope="session")
def fmu3_path() -> Path:
    """relnav3.fmu, the FMI 3.0 FMU."""
    return _built(rf3.locate_fmu3(), "RELNAV_FMU3")


@pytest.fixture(scope="session")
def unzipdir(fmu_path, tmp_path_factory) -> Path:
    """The FMU extracted once for the whole session."""
    return rf.unpack(fmu_path, tmp_path_factory.mktemp("fmu") / "relnav")


@pytest.fixture(scope="session")
def unzip3(fmu3_path, tmp_path_factory) -> Path:
    """relnav3.fmu extracted once for the whole session."""
    return rf.unpack(fmu3_path, tmp_path_factory.mktemp("fmu3") / "relnav3")


@pytest.fixture(scope="session")
def runner(unzipdir):
    """One loaded FMU2Slave; every run is a fresh instance of it."""
    r = rf.SlaveRunner(unzipdir)
    yield r
    r.close()


@pytest.fixture(scope="session")
def runs(runner, unzipdir):
    """Run a scenario for all seeds through one driver, cached for the session.

    ``runs(key, scenario, filter_code, driver="slave")`` -> (RUNS, N+1, 12).
    """
    cache: dict = {}

    def _runs(key: str, sc: cw.Scenario, filter_code: int, driver: str = "slave", seeds=SEEDS) -> np.ndarray:
        k = (key, filter_code, driver, tuple(seeds))
        if k not in cache:
            params = {**sc.params, "filter": filter_code}
            outs = []
            for seed in seeds:
                z = sc.measurements(seed)
                if driver == "slave":
                    outs.append(runner.run(params, sc.times, sc.thrust, z, sc.valid))
                elif driver == "simulate_fmu":
                    outs.append(rf.run_simulate_fmu(unzipdir, params, sc.times, sc.thrust, z, sc.valid))
                else:  # pragma: no cover
                    raise ValueError(driver)
            cache[k] = np.array(outs)
        return cache[k]

    return _runs
