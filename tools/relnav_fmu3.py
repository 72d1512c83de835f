"""Drive relnav3.fmu (FMI 3.0 Co-Simulation) with fmpy's low-level ``FMU3Slave`` API.

:class:`Slave3Runner` mirrors :class:`relnav_fmu.SlaveRunner`: the same scenarios and
measurements, the inputs and outputs as FMI 3.0 arrays (``thrust[3]``,
``measurement[3]``, ``position[3]``, ``velocity[3]``, ``sigma[6]``); its ``run`` returns
the outputs at every communication point, shape (N+1, 12), in the order of
:data:`relnav_fmu.OUTPUTS`.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from fmpy import read_model_description
from fmpy.fmi3 import FMU3Slave

from relnav_fmu import REPO_ROOT, SlaveRunner, codes

DEFAULT_FMU3 = REPO_ROOT / "target" / "fmu" / "relnav3.fmu"


def locate_fmu3() -> Path:
    """The built FMI 3.0 FMU: $RELNAV_FMU3 if set, else target/fmu/relnav3.fmu."""
    env = os.environ.get("RELNAV_FMU3")
    return Path(env) if env else DEFAULT_FMU3

OUTPUT_ARRAYS = ["position", "velocity", "sigma"]


class LogCapture3:
    """An fmi3LogMessageCallback that records (status, category, message)."""

    def __init__(self) -> None:
        self.records: list[tuple[int, str, str]] = []

        def _log(env, status, category, message):  # noqa: ARG001
            dec = lambda b: b.decode("utf-8", "replace") if isinstance(b, bytes) else str(b)  # noqa: E731
            self.records.append((int(status), dec(category), dec(message)))

        self.callback = _log

    def text(self) -> str:
        return "\n".join(f"[{s}] {c}: {m}" for s, c, m in self.records)


class Slave3Runner(SlaveRunner):
    """Run scenarios through one loaded FMU3Slave; each run is a fresh instantiation
    (``run`` and ``close`` are :class:`relnav_fmu.SlaveRunner`'s)."""

    def __init__(self, unzipdir: Path, logging_on: bool = False) -> None:
        self.unzipdir = Path(unzipdir)
        self.md = read_model_description(str(self.unzipdir))
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.vr = {name: v.valueReference for name, v in self.vars.items()}
        self.codes = codes(self.md)
        self.log = LogCapture3()
        self.logging_on = logging_on
        self.fmu = FMU3Slave(
            guid=self.md.guid,
            unzipDirectory=str(self.unzipdir),
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName="relnav3_test",
        )
        self._out = [self.vr[n] for n in OUTPUT_ARRAYS]
        self.instantiated = False

    def instantiate(self, logging_on: bool | None = None, **kw) -> None:
        on = self.logging_on if logging_on is None else logging_on
        self.fmu.instantiate(loggingOn=on, logMessage=self.log.callback, **kw)
        self.instantiated = True

    def free_instance(self) -> None:
        # fmpy's FMU3Slave.freeInstance also unloads the library: free the instance alone
        if self.instantiated:
            self.fmu.fmi3FreeInstance(self.fmu.component)
            self.instantiated = False

    def set_params(self, params: dict) -> None:
        """Set parameters by name (code parameters also take their item names)."""
        for name, value in params.items():
            var = self.vars[name]
            if isinstance(value, str) and name in self.codes:
                value = self.codes[name][value]
            if var.type == "Float64":
                self.fmu.setFloat64([var.valueReference], [float(value)])
            elif var.type == "Int32":
                self.fmu.setInt32([var.valueReference], [int(value)])
            elif var.type == "Boolean":
                self.fmu.setBoolean([var.valueReference], [bool(value)])
            else:  # pragma: no cover
                raise TypeError(f"{name}: unsupported type {var.type}")

    def initialize(self, params: dict, start_time: float = 0.0) -> None:
        self.fmu.enterInitializationMode(startTime=start_time)
        self.set_params(params)
        self.fmu.exitInitializationMode()

    def outputs(self) -> np.ndarray:
        return np.array(self.fmu.getFloat64(self._out, nValues=12))

    def simulate(self, times, thrust, meas, valid) -> np.ndarray:
        times = np.asarray(times, dtype=float)
        n_steps = len(times) - 1
        out = np.empty((n_steps + 1, 12))
        out[0] = self.outputs()
        thrust_vr, meas_vr, valid_vr = self.vr["thrust"], self.vr["measurement"], self.vr["measurement_valid"]
        thrust = np.asarray(thrust, float)
        meas = np.asarray(meas, float)
        for k in range(n_steps):
            self.fmu.setFloat64([thrust_vr, meas_vr], thrust[k].tolist() + meas[k].tolist())
            self.fmu.setBoolean([valid_vr], [bool(valid[k])])
            self.fmu.doStep(currentCommunicationPoint=times[k], communicationStepSize=times[k + 1] - times[k])
            out[k + 1] = self.outputs()
        return out
