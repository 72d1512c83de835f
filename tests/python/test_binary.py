"""The FMU archive and its binary: layout, self-containment, exported FMI functions."""

from __future__ import annotations

import re
import shutil
import subprocess
import zipfile

import pytest

# Every FMI 2.0 common and co-simulation function (FMI 2.0.5, sections 2.1 and 4.2).
FMI2_FUNCTIONS = """
fmi2GetTypesPlatform fmi2GetVersion fmi2SetDebugLogging fmi2Instantiate fmi2FreeInstance
fmi2SetupExperiment fmi2EnterInitializationMode fmi2ExitInitializationMode fmi2Terminate
fmi2Reset fmi2GetReal fmi2GetInteger fmi2GetBoolean fmi2GetString fmi2SetReal
fmi2SetInteger fmi2SetBoolean fmi2SetString fmi2GetFMUstate fmi2SetFMUstate
fmi2FreeFMUstate fmi2SerializedFMUstateSize fmi2SerializeFMUstate fmi2DeSerializeFMUstate
fmi2GetDirectionalDerivative fmi2SetRealInputDerivatives fmi2GetRealOutputDerivatives
fmi2DoStep fmi2CancelStep fmi2GetStatus fmi2GetRealStatus fmi2GetIntegerStatus
fmi2GetBooleanStatus fmi2GetStringStatus
""".split()

# glibc (libc, libm, libpthread, libdl, the loader) and libgcc_s: present on every Linux.
ALLOWED_NEEDED = re.compile(
    r"^(libc\.so\.6|libm\.so\.6|libpthread\.so\.0|libdl\.so\.2|libgcc_s\.so\.1|ld-linux-x86-64\.so\.2)$"
)


def test_archive_layout(fmu_path):
    with zipfile.ZipFile(fmu_path) as z:
        names = sorted(z.namelist())
    assert names == ["binaries/linux64/relnav.so", "modelDescription.xml"], names
    assert all("\\" not in n and not n.startswith("./") for n in names)


@pytest.mark.skipif(shutil.which("readelf") is None, reason="readelf (binutils) not installed")
def test_binary_is_self_contained(unzipdir):
    so = unzipdir / "binaries" / "linux64" / "relnav.so"
    out = subprocess.run(["readelf", "-d", str(so)], check=True, capture_output=True, text=True).stdout
    needed = re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", out)
    assert needed, out
    extra = [n for n in needed if not ALLOWED_NEEDED.match(n)]
    assert not extra, f"relnav.so needs libraries beyond glibc/libgcc_s: {extra}"


@pytest.mark.skipif(shutil.which("nm") is None, reason="nm (binutils) not installed")
def test_every_fmi2_function_is_exported(unzipdir):
    so = unzipdir / "binaries" / "linux64" / "relnav.so"
    out = subprocess.run(["nm", "-D", "--defined-only", str(so)], check=True,
                         capture_output=True, text=True).stdout
    exported = {line.split()[-1] for line in out.splitlines() if line.strip()}
    missing = [f for f in FMI2_FUNCTIONS if f not in exported]
    assert not missing, f"missing exports: {missing}"
    assert "relnav_estimator_step" in exported  # the C ABI lives in the same binary
