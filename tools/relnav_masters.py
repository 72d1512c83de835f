"""Drive relnav.fmu through FMI masters that others wrote, each through its own API:

* **fmpy** (``fmpy.fmi2.FMU2Slave``): the reference;
* **libcosim** (``libcosimpy``, the Open Simulation Platform's engine): one execution
  from an SSP folder whose system holds one component per case, all from one copy of
  the FMU (``CosimExecution.from_ssp_file``; a ``CosimLocalSlave`` per case would unpack
  the FMU once per instance, ~0.5 s each), parameters as initial values
  (``real/integer/boolean_initial_value``), inputs through an override manipulator,
  outputs from a last-value observer;
* **Ecos** (``ecospy``): one ``EcosSimulationStructure`` with one model per case, the
  parameters as one parameter set applied by ``init(parameter_set=...)``, inputs with
  ``set_real``/``set_bool``, outputs with ``get_real``.

Every case of a batch runs in one simulation of the master (one instance each), so a
master loads the FMU once per batch. All return ``{case name: (N, K) array}``: the
outputs :data:`OUTPUTS` after each of the N steps.
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import relnav_fmu as rf

OUTPUTS = rf.OUTPUTS + ["ess", "q_vv_x", "q_vv_y", "q_vv_z", "hinf_gamma"]


@dataclass
class Case:
    """One FMU instance: parameters (by name; code parameters take codes or item names)
    and the inputs of each step of a regular grid ``times``.

    ``valid`` (N,) drives ``measurement_valid`` at every step; ``None`` leaves it at the
    value the parameters give it (a Boolean start value).
    """

    name: str
    params: dict
    times: np.ndarray  # (N+1,)
    thrust: np.ndarray  # (N, 3) [N]
    meas: np.ndarray  # (N, 3) range, azimuth, elevation
    valid: np.ndarray | None  # (N,) bool

    @property
    def step(self) -> float:
        return float(self.times[1] - self.times[0])


def typed_params(md, params: dict) -> dict:
    """Parameters with item names resolved and each value of the Python type of its FMI
    type (float / int / bool): Ecos picks the setter from the Python type."""
    types = {v.name: v.type for v in md.modelVariables}
    conv = {"Real": float, "Integer": int, "Boolean": bool}
    return {n: conv[types[n]](v) for n, v in rf.resolve(md, params).items()}


def _check_grid(cases: list[Case]) -> tuple[float, int]:
    h, n = cases[0].step, len(cases[0].times) - 1
    for c in cases:
        if c.step != h or len(c.times) != n + 1 or c.times[0] != 0.0:
            raise ValueError(f"case {c.name}: every case needs the same grid from 0 with step {h}")
        if not np.allclose(np.diff(c.times), h, rtol=0, atol=0):
            raise ValueError(f"case {c.name}: the grid is not regular")
    return h, n


# ---------------------------------------------------------------------------- fmpy
def run_fmpy(runner: rf.SlaveRunner, cases: list[Case]) -> dict[str, np.ndarray]:
    """The reference: each case on a fresh instance of ``runner``'s FMU2Slave."""
    out_vr = [runner.vr[n] for n in OUTPUTS]
    in_vr = [runner.vr[n] for n in rf.REAL_INPUTS]
    valid_vr = [runner.vr["measurement_valid"]]
    res = {}
    for c in cases:
        runner.instantiate()
        try:
            runner.initialize(c.params)
            rows = []
            for k in range(len(c.times) - 1):
                runner.fmu.setReal(in_vr, [*map(float, c.thrust[k]), *map(float, c.meas[k])])
                if c.valid is not None:
                    runner.fmu.setBoolean(valid_vr, [bool(c.valid[k])])
                runner.fmu.doStep(currentCommunicationPoint=float(c.times[k]), communicationStepSize=c.step)
                rows.append(runner.fmu.getReal(out_vr))
            runner.fmu.terminate()
        finally:
            runner.free_instance()
        res[c.name] = np.array(rows)
    return res


# ---------------------------------------------------------------------------- libcosim
def cosim_set_initial(ex, idx: int, refs: dict, types: dict, params: dict) -> list[str]:
    """Set parameters as libcosim initial values; returns the names libcosim refused."""
    refused = []
    for name, value in params.items():
        if name not in refs:  # a variable libcosim does not know (an FMI Enumeration)
            refused.append(name)
            continue
        setter = {
            "Real": ex.real_initial_value,
            "Integer": ex.integer_initial_value,
            "Boolean": ex.boolean_initial_value,
        }[types[name]]
        if not setter(idx, refs[name], value):
            refused.append(name)
    return refused


def write_ssp(folder: Path, fmu_path, names: list[str]) -> Path:
    """An unpacked SSP (``SystemStructure.ssd`` + ``resources/relnav.fmu``) whose system
    has one component per name, all of the one FMU, without connections or parameter
    bindings (the SSD form both libcosim and Ecos accept, ``ssp-notes.md``)."""
    folder = Path(folder)
    (folder / "resources").mkdir(parents=True, exist_ok=True)
    shutil.copyfile(fmu_path, folder / "resources" / "relnav.fmu")
    components = "\n".join(
        f'      <ssd:Component name="{n}" type="application/x-fmu-sharedlibrary" source="resources/relnav.fmu"/>'
        for n in names
    )
    (folder / "SystemStructure.ssd").write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" '
        'xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" name="relnav_cases" version="1.0">\n'
        '  <ssd:System name="cases">\n'
        "    <ssd:Elements>\n"
        f"{components}\n"
        "    </ssd:Elements>\n"
        "  </ssd:System>\n"
        "</ssd:SystemStructureDescription>\n"
    )
    return folder


def run_libcosim(fmu_path, md, cases: list[Case], workdir) -> dict[str, np.ndarray]:
    """All cases as components of one libcosim execution (an SSP folder in ``workdir``;
    fixed step in nanoseconds)."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver

    h, n = _check_grid(cases)
    log_output_level(CosimLogLevel.ERROR)
    ssp = write_ssp(Path(workdir) / "libcosim_cases", fmu_path, [c.name for c in cases])
    ex = CosimExecution.from_ssp_file(str(ssp), step_size=round(h * 1e9))
    if ex.num_slaves() != len(cases):
        raise RuntimeError(f"libcosim loaded {ex.num_slaves()} of {len(cases)} components: {_cosim_error()}")
    # the loader keeps components in an unordered map: look indices up by name
    idx = {c.name: ex.slave_index_from_instance_name(c.name) for c in cases}
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer)
    manipulator = CosimManipulator.create_override()
    ex.add_manipulator(manipulator)
    refs = {}
    for c in cases:
        refs[c.name] = {v.name.decode(): v.reference for v in ex.slave_variables(idx[c.name])}
    types = {v.name: v.type for v in md.modelVariables}
    for c in cases:
        refused = cosim_set_initial(ex, idx[c.name], refs[c.name], types, typed_params(md, c.params))
        if refused:
            raise RuntimeError(f"libcosim refused initial values of {refused} for {c.name}: {_cosim_error()}")
    res = {c.name: np.empty((n, len(OUTPUTS))) for c in cases}
    for k in range(n):
        for c in cases:
            r, i = refs[c.name], idx[c.name]
            inputs = [*map(float, c.thrust[k]), *map(float, c.meas[k])]
            manipulator.slave_real_values(i, [r[v] for v in rf.REAL_INPUTS], inputs)
            if c.valid is not None:
                manipulator.slave_boolean_values(i, [r["measurement_valid"]], [bool(c.valid[k])])
        if not ex.step():
            raise RuntimeError(f"libcosim step {k} failed: {_cosim_error()}")
        for c in cases:
            r = refs[c.name]
            res[c.name][k] = observer.last_real_values(idx[c.name], [r[v] for v in OUTPUTS])
    t_end = ex.status().current_time
    if t_end != round(n * h * 1e9):
        raise RuntimeError(f"libcosim ended at {t_end} ns, expected {n * h} s")
    del observer, manipulator, ex
    return res


def _cosim_error() -> str:
    from libcosimpy._internal import get_last_error_message

    return get_last_error_message()


# ---------------------------------------------------------------------------- Ecos
def run_ecos(fmu_path, md, cases: list[Case], log_level: str = "warn") -> dict[str, np.ndarray]:
    """All cases as models of one Ecos simulation; parameters in one parameter set."""
    from ecospy import EcosLib, EcosSimulation, EcosSimulationStructure

    h, n = _check_grid(cases)
    EcosLib.set_log_level(log_level)
    structure = EcosSimulationStructure()
    params = {}
    for c in cases:
        structure.add_model(c.name, str(fmu_path))
        params.update({f"{c.name}::{k}": v for k, v in typed_params(md, c.params).items()})
    structure.add_parameter_set("initial", params)
    sim = EcosSimulation(structure=structure, step_size=h)
    try:
        if not sim.init(parameter_set="initial"):
            raise RuntimeError(f"Ecos init failed: {EcosLib.get_last_error()}")
        res = {c.name: np.empty((n, len(OUTPUTS))) for c in cases}
        for k in range(n):
            for c in cases:
                for name, v in zip(rf.REAL_INPUTS, [*c.thrust[k], *c.meas[k]]):
                    sim.set_real(f"{c.name}::{name}", float(v))
                if c.valid is not None:
                    sim.set_bool(f"{c.name}::measurement_valid", bool(c.valid[k]))
            sim.step(1)
            for c in cases:
                res[c.name][k] = [sim.get_real(f"{c.name}::{v}") for v in OUTPUTS]
        if sim.get_time() != n * h:
            raise RuntimeError(f"Ecos ended at {sim.get_time()} s, expected {n * h} s")
        sim.terminate()
    finally:
        sim.free()
        structure.free()
    return res


# ------------------------------------------------------------------ one instance, errors
def cosim_single(fmu_path, md, params: dict, steps: int, workdir, step: float = 1.0) -> dict:
    """One relnav instance ``B`` in libcosim with ``params`` as initial values, stepped
    ``steps`` times without measurements. Returns what libcosim tells the user:
    ``{"set": [ok, ...], "steps": [ok, ...], "errors": [last error message after each
    step], "x": [...], "time_ns": int}`` (its observer keeps the values of the last
    successful step). A parameter the FMU refuses aborts the process (libcosim
    applies initial values in a worker thread and does not catch the exception): run it
    in a subprocess."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.WARNING)
    ssp = write_ssp(Path(workdir) / "libcosim_single", fmu_path, ["B"])
    ex = CosimExecution.from_ssp_file(str(ssp), step_size=round(step * 1e9))
    i = ex.slave_index_from_instance_name("B")
    refs = {v.name.decode(): v.reference for v in ex.slave_variables(i)}
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer)
    types = {v.name: v.type for v in md.modelVariables}
    out = {"set": [], "steps": [], "errors": [], "x": []}
    for name, value in typed_params(md, params).items():
        ok = cosim_set_initial(ex, i, refs, types, {name: value}) == []
        out["set"].append(ok)
    for _ in range(steps):
        ok = bool(ex.step())
        out["steps"].append(ok)
        out["errors"].append("" if ok else _cosim_error())
        out["x"].append(observer.last_real_values(i, [refs["x"]])[0])
    out["time_ns"] = ex.status().current_time
    del observer, ex
    return out


def ecos_single(fmu_path, md, params: dict, steps: int, step: float = 1.0) -> dict:
    """One relnav instance ``B`` in Ecos with ``params`` as its parameter set, stepped
    ``steps`` times without measurements: ``{"init": bool, "error": last error,
    "x": [...], "fmi_status": int}`` (Ecos logs the FMU's messages only at level debug)."""
    from ecospy import EcosLib, EcosSimulation, EcosSimulationStructure

    structure = EcosSimulationStructure()
    structure.add_model("B", str(fmu_path))
    structure.add_parameter_set("initial", {f"B::{k}": v for k, v in typed_params(md, params).items()})
    sim = EcosSimulation(structure=structure, step_size=step)
    try:
        out = {"init": bool(sim.init(parameter_set="initial")), "x": []}
        for _ in range(steps):
            sim.step(1)
            out["x"].append(sim.get_real("B::x"))
        out["error"] = EcosLib.get_last_error()
        out["fmi_status"] = sim.get_integer("B::fmi_status")
        sim.terminate()
    finally:
        sim.free()
        structure.free()
    return out
