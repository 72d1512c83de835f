"""Drive relnav's FMI 2.0 Co-Simulation FMU with fmpy, two ways:

* :class:`SlaveRunner` — the low-level ``fmpy.fmi2.FMU2Slave`` API, one doStep per step;
* :func:`run_simulate_fmu` — ``fmpy.simulate_fmu`` with a structured input array.

Both take a :class:`cwtruth.Scenario` and a noisy measurement array and return the
outputs at every communication point, shape (N+1, 12) in the order of :data:`OUTPUTS`
(row 0 is the initial estimate after initialisation).
"""

from __future__ import annotations

import os
import re
import shutil
from ctypes import byref
from pathlib import Path

import numpy as np
from fmpy import calloc, extract, free, read_model_description, simulate_fmu
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)

REPO_ROOT = Path(__file__).resolve().parent.parent
DEFAULT_FMU = REPO_ROOT / "target" / "fmu" / "relnav.fmu"

STATE_OUTPUTS = ["x", "y", "z", "vx", "vy", "vz"]
SIGMA_OUTPUTS = ["sigma_x", "sigma_y", "sigma_z", "sigma_vx", "sigma_vy", "sigma_vz"]
OUTPUTS = STATE_OUTPUTS + SIGMA_OUTPUTS
REAL_INPUTS = ["thrust_x", "thrust_y", "thrust_z", "range", "azimuth", "elevation"]
BOOL_INPUTS = ["measurement_valid"]
# the declared camera and relative-GNSS sensors' inputs: zero and unflagged unless a test
# drives them
SENSOR_REAL_INPUTS = ["camera_azimuth", "camera_elevation", "gnss_x", "gnss_y", "gnss_z", "gnss_vx", "gnss_vy", "gnss_vz"]
SENSOR_BOOL_INPUTS = ["camera_valid", "gnss_valid", "gnss_velocity_valid"]
INPUTS = REAL_INPUTS + BOOL_INPUTS + SENSOR_REAL_INPUTS + SENSOR_BOOL_INPUTS

FILTERS = {"ekf": 1, "ukf": 2}
# the particle filters (filter codes 4-8)
PARTICLE_FILTERS = {"pf": 4, "rpf": 5, "upf": 6, "gapf": 7, "cgapf": 8}


_CODES = re.compile(r"\. Codes: (\d+ \w+(?:, \d+ \w+)*)$")


def codes(md) -> dict[str, dict[str, int]]:
    """The Integer parameters that select a method, from a modelDescription read by
    fmpy: ``{"filter": {"ekf": 1, ...}, "frame": {...}, ...}``.

    relnav declares them as FMI Integers (libcosim and Ecos cannot set Enumerations; FMI
    3.0's Int32) whose description ends in ``Codes: 1 ekf, 2 ukf, ...``.
    """
    out = {}
    for v in md.modelVariables:
        m = _CODES.search(v.description or "")
        if v.type in ("Integer", "Int32") and m:
            out[v.name] = {name: int(code) for code, name in (item.split(" ") for item in m.group(1).split(", "))}
    return out


def resolve(md, params: dict) -> dict:
    """``params`` with item names (``{"filter": "ukf"}``) replaced by their codes
    (``{"filter": 2}``): fmpy converts every Integer start value with ``int()`` and
    knows no item names (neither did it for Enumerations), so names are mapped here."""
    table = codes(md)
    out = {}
    for name, value in params.items():
        if isinstance(value, str) and name in table:
            if value not in table[name]:
                raise ValueError(f"{name} = {value!r}: not one of {sorted(table[name], key=table[name].get)}")
            value = table[name][value]
        out[name] = value
    return out


def locate_fmu() -> Path:
    """The built FMU: $RELNAV_FMU if set, else target/fmu/relnav.fmu."""
    env = os.environ.get("RELNAV_FMU")
    return Path(env) if env else DEFAULT_FMU


def unpack(fmu_path: Path, dest: Path | None = None) -> Path:
    """Extract the FMU (once) and return the directory."""
    if dest is None:
        return Path(extract(str(fmu_path)))
    if dest.exists():
        shutil.rmtree(dest)
    return Path(extract(str(fmu_path), unzipdir=str(dest)))


class LogCapture:
    """An fmi2CallbackLogger that records (status, category, message).

    fmpy formats the FMU's printf-style messages with a native proxy
    (``fmpy.logging.addLoggerProxy``) that keeps the Python callback in ONE process-wide
    slot: the last registration wins for every FMU instance that uses the proxy. So the
    callback is re-registered before each instantiation (:meth:`activate`) and the ctypes
    objects live as long as this object; whoever registers another logger must keep it
    alive while FMU instances may still log.
    """

    def __init__(self) -> None:
        self.records: list[tuple[int, str, str]] = []

        def _log(env, instance, status, category, message):  # noqa: ARG001
            dec = lambda b: b.decode("utf-8", "replace") if isinstance(b, bytes) else str(b)  # noqa: E731
            self.records.append((int(status), dec(category), dec(message)))

        self.py_callback = _log
        self.c_callback = fmi2CallbackLoggerTYPE(_log)
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self.callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self.activate()

    def activate(self) -> None:
        """(Re-)point fmpy's process-wide logger proxy at this capture."""
        self.callbacks.logger = self.c_callback
        try:
            from fmpy.logging import addLoggerProxy

            addLoggerProxy(byref(self.callbacks))
        except Exception:  # pragma: no cover - only when fmpy's helper library is missing
            pass

    def text(self) -> str:
        return "\n".join(f"[{s}] {c}: {m}" for s, c, m in self.records)


class SlaveRunner:
    """Run scenarios through one loaded FMU2Slave; each run is a fresh fmi2Instantiate.

    ``outputs`` (default :data:`OUTPUTS`) are the Real variables read after each step."""

    def __init__(self, unzipdir: Path, logging_on: bool = False, outputs: list[str] | None = None) -> None:
        self.unzipdir = Path(unzipdir)
        self.md = read_model_description(str(self.unzipdir))
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.vr = {name: v.valueReference for name, v in self.vars.items()}
        self.log = LogCapture()
        self.logging_on = logging_on
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=str(self.unzipdir),
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName="relnav_test",
        )
        self._in_real = [self.vr[n] for n in REAL_INPUTS]
        self._in_bool = [self.vr[n] for n in BOOL_INPUTS]
        self.output_names = list(OUTPUTS if outputs is None else outputs)
        self._out = [self.vr[n] for n in self.output_names]
        self.instantiated = False

    # -- life cycle -----------------------------------------------------------------
    def instantiate(self, logging_on: bool | None = None) -> None:
        """fmi2Instantiate; the FMU's log goes to ``self.log`` (debug logging on if
        ``logging_on``, default: the runner's setting)."""
        on = self.logging_on if logging_on is None else logging_on
        self.log.activate()
        self.fmu.instantiate(callbacks=self.log.callbacks, loggingOn=on)
        self.instantiated = True

    def free_instance(self) -> None:
        if self.instantiated:
            self.fmu.fmi2FreeInstance(self.fmu.component)
            self.instantiated = False

    def close(self) -> None:
        self.free_instance()
        self.fmu.freeLibrary()

    def set_params(self, params: dict) -> None:
        """Set parameters (and input start values) by name; code parameters also take
        their item names (``{"filter": "ukf"}``)."""
        for name, value in resolve(self.md, params).items():
            var = self.vars[name]
            if var.type == "Real":
                self.fmu.setReal([var.valueReference], [float(value)])
            elif var.type in ("Integer", "Enumeration"):
                self.fmu.setInteger([var.valueReference], [int(value)])
            elif var.type == "Boolean":
                self.fmu.setBoolean([var.valueReference], [bool(value)])
            else:  # pragma: no cover
                raise TypeError(f"{name}: unsupported type {var.type}")

    def initialize(self, params: dict, start_time: float = 0.0) -> None:
        self.fmu.setupExperiment(startTime=start_time)
        self.set_params(params)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def outputs(self) -> np.ndarray:
        return np.array(self.fmu.getReal(self._out))

    def simulate(self, times, thrust, meas, valid) -> np.ndarray:
        """Step the initialised instance over ``times``; returns (N+1, len(outputs))."""
        times = np.asarray(times, dtype=float)
        n_steps = len(times) - 1
        out = np.empty((n_steps + 1, len(self._out)))
        out[0] = self.outputs()
        set_real, set_bool, do_step, get_real = (
            self.fmu.setReal,
            self.fmu.setBoolean,
            self.fmu.doStep,
            self.fmu.getReal,
        )
        inputs = np.concatenate([np.asarray(thrust, float), np.asarray(meas, float)], axis=1)
        for k in range(n_steps):
            set_real(self._in_real, inputs[k].tolist())
            set_bool(self._in_bool, [bool(valid[k])])
            do_step(currentCommunicationPoint=times[k], communicationStepSize=times[k + 1] - times[k])
            out[k + 1] = get_real(self._out)
        return out

    def run(self, params: dict, times, thrust, meas, valid) -> np.ndarray:
        """Fresh instance: instantiate, initialise with ``params``, simulate, free."""
        self.instantiate()
        try:
            self.initialize(params, start_time=float(times[0]))
            out = self.simulate(times, thrust, meas, valid)
            self.fmu.terminate()
        finally:
            self.free_instance()
        return out


def input_table(times, thrust, meas, valid) -> np.ndarray:
    """Structured input array for fmpy.simulate_fmu: one row per step start time."""
    times = np.asarray(times, dtype=float)
    dtype = (
        [("time", np.float64)]
        + [(n, np.float64) for n in REAL_INPUTS + SENSOR_REAL_INPUTS]
        + [(n, np.bool_) for n in BOOL_INPUTS + SENSOR_BOOL_INPUTS]
    )
    sig = np.zeros(len(times) - 1, dtype=dtype)
    sig["time"] = times[:-1]
    for i, name in enumerate(["thrust_x", "thrust_y", "thrust_z"]):
        sig[name] = np.asarray(thrust)[:, i]
    for i, name in enumerate(["range", "azimuth", "elevation"]):
        sig[name] = np.asarray(meas)[:, i]
    sig["measurement_valid"] = np.asarray(valid, dtype=bool)
    return sig


def run_simulate_fmu(fmu, params: dict, times, thrust, meas, valid, output_interval: float = 1.0, **kw) -> np.ndarray:
    """Run through fmpy.simulate_fmu; returns (N+1, 12) at ``times``.

    ``fmu`` is the .fmu or an extracted directory. fmpy steps to every output point and
    to every input change, so ``times`` must be the union of those (true for a regular
    grid at ``output_interval``, and for any grid whose points all carry new measurement
    values, with a coarser ``output_interval``).
    """
    times = np.asarray(times, dtype=float)
    res = simulate_fmu(
        str(fmu),
        start_time=float(times[0]),
        stop_time=float(times[-1]),
        output_interval=output_interval,
        input=input_table(times, thrust, meas, valid),
        start_values=resolve(read_model_description(str(fmu)), params) if any(isinstance(v, str) for v in params.values()) else dict(params),
        output=OUTPUTS,
        fmi_type="CoSimulation",
        **kw,
    )
    t = res["time"]
    if len(t) != len(times) or not np.allclose(t, times, rtol=0, atol=1e-9):
        raise AssertionError(f"simulate_fmu recorded times {t[:5]}...{t[-3:]} (len {len(t)}), expected {len(times)} points")
    return np.stack([res[name] for name in OUTPUTS], axis=1)
