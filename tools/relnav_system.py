"""relnav's system kit: the closed GNC loop of ``relnav_system.ssp`` (truth plant ->
relnav -> guidance -> plant) in three FMI masters, from the same file:

* **fmpy** — this module's own master over ``fmpy.fmi2.FMU2Slave``: it reads the SSD
  itself (components, connections, the parameter set, start time, the OSP step size) and
  runs the fixed-step scheme the two engines use (below);
* **libcosim** (``libcosimpy``) — ``CosimExecution.from_ssp_file`` on the archive (the
  default variant) or on a variant's ``.ssd`` in the unpacked archive; the step size comes
  from the OSP annotation;
* **Ecos** (``ecospy``) — ``EcosSimulation(ssp_path=...)`` on the archive (the default
  variant) or on a folder holding a variant as its ``SystemStructure.ssd`` (Ecos reads no
  other SSD), ``init(parameter_set=<the set's name>)``, ``step(1)``.

**Data transfer** (measured, ``ssp-notes.md`` sec. 5 and ``docs/kit.md``): both engines run
a Jacobi scheme — before the first step every connected input receives its source's
initial output; each communication step steps every FMU from ``t_k`` with the inputs set
at ``t_k``, then copies every connected output (now at ``t_(k+1)``) to its inputs. No
FMU of the kit has direct feedthrough (``dependencies=""``), so there is no algebraic
loop and nothing to iterate. The fmpy master does exactly that, so the three give the
same numbers, bit for bit, at every communication point.

Run ``python tools/relnav_system.py --help``; ``scripts/main.sh`` runs every master on both
variants and writes the plots ``results/relnav_system_<set>.png``.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

REPO_ROOT = Path(__file__).resolve().parent.parent
DEFAULT_SSP = REPO_ROOT / "target" / "fmu" / "relnav_system.ssp"

NS = {
    "ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
    "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
    "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
    "osp": "http://opensimulationplatform.com/SSP/OSPAnnotations",
}

# variant name -> SSD file in the archive
VARIANTS = {
    "paper000": "SystemStructure.ssd",
    "lidar": "LidarHeavyTail.ssd",
    "proba3": "EccentricProba3.ssd",
    "sensors": "MultiSensorHandover.ssd",
}

# what every master records after each step: (component, variable)
TRUTH = ["true_x", "true_y", "true_z", "true_vx", "true_vy", "true_vz"]
ESTIMATE = ["x", "y", "z", "vx", "vy", "vz"]
SIGMA = ["sigma_x", "sigma_y", "sigma_z", "sigma_vx", "sigma_vy", "sigma_vz"]
THRUST = ["thrust_x", "thrust_y", "thrust_z"]
RECORD = (
    [("plant", v) for v in TRUTH + ["range", "azimuth", "elevation"]]
    + [("relnav", v) for v in ESTIMATE + SIGMA]
    + [("guidance", v) for v in THRUST + ["delta_v"]]
)
RECORD_BOOL = [("plant", "measurement_valid")]
RECORD_INT = [("plant", "fmi_status"), ("relnav", "fmi_status"), ("guidance", "fmi_status")]


@dataclass
class Component:
    name: str
    source: str  # path in the archive, e.g. resources/relnav.fmu
    connectors: dict[str, tuple[str, str]]  # name -> (kind, type)
    params: dict[str, tuple[str, object]]  # name -> (ssv type, value)
    set_name: str


@dataclass
class System:
    """An SSD as this module reads it."""

    name: str
    ssd: str
    components: dict[str, Component]
    connections: list[tuple[str, str, str, str]]  # (start element, connector, end element, connector)
    start: float
    stop: float
    step: float
    set_name: str

    @property
    def steps(self) -> int:
        return int(round((self.stop - self.start) / self.step))


def _value(kind: str, text: str):
    if kind == "Real":
        return float(text)
    if kind == "Integer":
        return int(text)
    if kind == "Boolean":
        if text not in ("true", "false", "1", "0"):
            raise ValueError(f"Boolean value {text!r}")
        return text in ("true", "1")
    return text


def parse_ssd(text: str, name: str = "SystemStructure.ssd") -> System:
    """Read an SSD (SSP 1.0) the way the kit writes it: one system of FMU components,
    element-to-element connections, at most one inline ParameterBinding per component
    (all with one set name), ``DefaultExperiment`` with the OSP fixed-step annotation."""
    root = ET.fromstring(text)
    if root.tag != f"{{{NS['ssd']}}}SystemStructureDescription" or root.get("version") != "1.0":
        raise ValueError(f"{name}: not an SSP 1.0 SystemStructureDescription")
    system = root.find("ssd:System", NS)
    if system is None:
        raise ValueError(f"{name}: no ssd:System")
    comps: dict[str, Component] = {}
    set_names = set()
    for el in system.find("ssd:Elements", NS):
        if el.tag != f"{{{NS['ssd']}}}Component":
            raise ValueError(f"{name}: only FMU components are supported (got {el.tag})")
        conns = {}
        for c in el.findall("ssd:Connectors/ssd:Connector", NS):
            types = [t.tag.split("}")[1] for t in c]
            conns[c.get("name")] = (c.get("kind"), types[0] if types else "Real")
        params: dict = {}
        set_name = ""
        bindings = el.findall("ssd:ParameterBindings/ssd:ParameterBinding", NS)
        if len(bindings) > 1:
            raise ValueError(f"{name}: component {el.get('name')} has {len(bindings)} parameter bindings")
        for b in bindings:
            ps = b.find("ssd:ParameterValues/ssv:ParameterSet", NS)
            if ps is None:
                raise ValueError(f"{name}: only inline parameter sets are supported")
            set_name = ps.get("name", "")
            set_names.add(set_name)
            for p in ps.findall("ssv:Parameters/ssv:Parameter", NS):
                (v,) = list(p)
                kind = v.tag.split("}")[1]
                params[p.get("name")] = (kind, _value(kind, v.get("value")))
        comps[el.get("name")] = Component(el.get("name"), el.get("source"), conns, params, set_name)
    if len(set_names) > 1:
        raise ValueError(f"{name}: several parameter set names {sorted(set_names)}")
    connections = []
    for c in system.findall("ssd:Connections/ssd:Connection", NS):
        a, ac, b, bc = (c.get(k) for k in ("startElement", "startConnector", "endElement", "endConnector"))
        for el, conn in ((a, ac), (b, bc)):
            if el not in comps or conn not in comps[el].connectors:
                raise ValueError(f"{name}: connection to undeclared connector {el}.{conn}")
        connections.append((a, ac, b, bc))
    exp = root.find("ssd:DefaultExperiment", NS)
    start = float(exp.get("startTime", "0")) if exp is not None else 0.0
    stop = float(exp.get("stopTime")) if exp is not None and exp.get("stopTime") else float("nan")
    algo = root.find("ssd:DefaultExperiment/ssd:Annotations/ssc:Annotation/osp:Algorithm/osp:FixedStepAlgorithm", NS)
    if algo is None:
        raise ValueError(f"{name}: no OSP FixedStepAlgorithm (the step size)")
    return System(
        name=root.get("name"),
        ssd=name,
        components=comps,
        connections=connections,
        start=start,
        stop=stop,
        step=float(algo.get("baseStepSize")),
        set_name=set_names.pop() if set_names else "",
    )


def read_system(ssp: Path, variant: str = "paper000") -> System:
    """The system of ``variant`` (see :data:`VARIANTS`) in the archive ``ssp``."""
    with zipfile.ZipFile(ssp) as z:
        return parse_ssd(z.read(VARIANTS[variant]).decode("utf-8"), VARIANTS[variant])


@dataclass
class Run:
    """One closed-loop run: ``values[(component, variable)]`` at the communication points
    ``times`` (N+1 for fmpy and Ecos, which can be read at the start; libcosim's
    observer only after the first step: its row 0 is NaN), the wall time of the stepping
    loop and of the whole run (loading included)."""

    master: str
    variant: str
    times: np.ndarray
    values: dict[tuple[str, str], np.ndarray]
    loop_seconds: float
    total_seconds: float
    system: System = field(repr=False, default=None)

    def series(self, comp: str, names: list[str]) -> np.ndarray:
        return np.stack([self.values[(comp, n)] for n in names], axis=1)


def _empty(n: int) -> dict:
    out = {k: np.full(n + 1, np.nan) for k in RECORD + RECORD_BOOL + RECORD_INT}
    return out


def _release(slaves: dict, tmp: str) -> None:
    """Free every instance (best effort, on the way out) and the unpacked files."""
    for s in slaves.values():
        try:
            s.freeInstance()
        except Exception:  # noqa: BLE001 - best effort on the way out
            pass
    shutil.rmtree(tmp, ignore_errors=True)


def _jacobi(sysm: System, slaves: dict, n: int, getv, transfer, enter) -> tuple[dict, float]:
    """The fixed-step Jacobi scheme every master here runs (module documentation), once the
    parameters are set: ``enter`` each slave into initialisation, transfer, exit, transfer;
    record row 0; then per step every slave steps, the outputs go to the inputs and the
    recorded variables (``getv(component, name)``) are read. Returns the records and the
    stepping loop's wall time."""
    h, t0 = sysm.step, sysm.start
    for s in slaves.values():
        enter(s)
    transfer()
    for s in slaves.values():
        s.exitInitializationMode()
    transfer()
    values = _empty(n)

    def record(k: int) -> None:
        for key in values:
            values[key][k] = getv(*key)

    record(0)
    t_loop = time.perf_counter()
    for k in range(n):
        tc = t0 + k * h
        for s in slaves.values():
            s.doStep(currentCommunicationPoint=tc, communicationStepSize=h)
        transfer()
        record(k + 1)
    loop = time.perf_counter() - t_loop
    for s in slaves.values():
        s.terminate()
    return values, loop


# ------------------------------------------------------------------------ fmpy, FMI 3.0
# The FMI 2.0 scalars each FMI 3.0 FMU of the kit publishes as one array, in order, by
# model identifier (declared in the models' `ArrayDef`s; written here independently, and
# checked against the FMUs by tests/python/test_fmi3.py).
FMI3_ARRAYS = {
    "relnav": {
        "thrust": THRUST,
        "measurement": ["range", "azimuth", "elevation"],
        "camera": ["camera_azimuth", "camera_elevation"],
        "gnss_position": ["gnss_x", "gnss_y", "gnss_z"],
        "gnss_velocity": ["gnss_vx", "gnss_vy", "gnss_vz"],
        "position": ESTIMATE[:3],
        "velocity": ESTIMATE[3:],
        "sigma": SIGMA,
    },
    "relnav_plant": {
        "thrust": THRUST,
        "measurement": ["range", "azimuth", "elevation"],
        "camera": ["camera_azimuth", "camera_elevation"],
        "gnss_position": ["gnss_x", "gnss_y", "gnss_z"],
        "gnss_velocity": ["gnss_vx", "gnss_vy", "gnss_vz"],
        "true_position": TRUTH[:3],
        "true_velocity": TRUTH[3:],
    },
    "relnav_guidance": {
        "position": ESTIMATE[:3],
        "velocity": ESTIMATE[3:],
        "thrust": THRUST,
    },
}


def run_fmpy3(fmu_dir: Path, ssp: Path, variant: str = "paper000", steps: int | None = None) -> Run:
    """The system of ``ssp``'s ``variant`` with the kit's FMI 3.0 FMUs
    (``<fmu_dir>/<id>3.fmu``), over fmpy's ``FMU3Slave``, by the same Jacobi scheme as
    :func:`run_fmpy`: the SSD's parameters and scalar connections, each scalar that FMI 3.0
    publishes in an array (:data:`FMI3_ARRAYS`) read and written through its array."""
    from fmpy import extract, read_model_description
    from fmpy.fmi3 import FMU3Slave

    t_all = time.perf_counter()
    sysm = read_system(ssp, variant)
    n = sysm.steps if steps is None else steps
    h, t0 = sysm.step, sysm.start
    tmp = tempfile.mkdtemp(prefix="relnav-system-fmpy3-")
    slaves, vars3, where = {}, {}, {}
    try:
        for c in sysm.components.values():
            ident = Path(c.source).stem
            unzip = extract(str(Path(fmu_dir) / f"{ident}3.fmu"), unzipdir=str(Path(tmp) / c.name))
            md = read_model_description(unzip)
            vars3[c.name] = {v.name: v for v in md.modelVariables}
            # scalar name -> (FMI 3.0 variable, element index or None)
            where[c.name] = {name: (name, None) for name in vars3[c.name]}
            for array, elements in FMI3_ARRAYS[ident].items():
                for i, e in enumerate(elements):
                    where[c.name][e] = (array, i)
            s = FMU3Slave(
                guid=md.guid,
                unzipDirectory=unzip,
                modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName=c.name,
            )
            s.instantiate()
            slaves[c.name] = s

        def length(comp: str, var: str) -> int:
            return int(np.prod([int(d.start) for d in vars3[comp][var].dimensions])) if vars3[comp][var].dimensions else 1

        def get_var(comp: str, var: str) -> list:
            v, s = vars3[comp][var], slaves[comp]
            k = length(comp, var)
            if v.type == "Float64":
                return s.getFloat64([v.valueReference], nValues=k)
            if v.type == "Int32":
                return s.getInt32([v.valueReference], nValues=k)
            return s.getBoolean([v.valueReference], nValues=k)

        def set_var(comp: str, var: str, values: list) -> None:
            v, s = vars3[comp][var], slaves[comp]
            if v.type == "Float64":
                s.setFloat64([v.valueReference], [float(x) for x in values])
            elif v.type == "Int32":
                s.setInt32([v.valueReference], [int(x) for x in values])
            else:
                s.setBoolean([v.valueReference], [bool(x) for x in values])

        def getv(comp: str, name: str):
            var, i = where[comp][name]
            vals = get_var(comp, var)
            return vals[0 if i is None else i]

        for c in sysm.components.values():
            for name, (_, value) in c.params.items():
                set_var(c.name, name, [value])

        def transfer() -> None:
            # outputs first, then inputs, a whole array at a time
            vals = [getv(a, ac) for a, ac, _, _ in sysm.connections]
            pending: dict = {}
            for (_, _, b, bc), v in zip(sysm.connections, vals):
                var, i = where[b][bc]
                if (b, var) not in pending:
                    pending[(b, var)] = list(get_var(b, var))
                pending[(b, var)][0 if i is None else i] = v
            for (b, var), values in pending.items():
                set_var(b, var, values)

        values, loop = _jacobi(sysm, slaves, n, getv, transfer, lambda s: s.enterInitializationMode(startTime=t0))
    finally:
        _release(slaves, tmp)
    times = t0 + h * np.arange(n + 1)
    return Run("fmpy (FMI 3.0)", variant, times, values, loop, time.perf_counter() - t_all, sysm)


# ------------------------------------------------------------------------------- fmpy
def run_fmpy(ssp: Path, variant: str = "paper000", steps: int | None = None, overrides: dict | None = None) -> Run:
    """The system run by this module's master over fmpy's ``FMU2Slave`` (Jacobi, as the
    engines: see the module documentation). ``overrides`` maps ``(component, variable)``
    to a value set after the SSD's parameter set (e.g. ``{("relnav", "filter"): 1}`` to
    run the same loop with the EKF)."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    t_all = time.perf_counter()
    sysm = read_system(ssp, variant)
    n = sysm.steps if steps is None else steps
    h, t0 = sysm.step, sysm.start
    tmp = tempfile.mkdtemp(prefix="relnav-system-fmpy-")
    slaves, refs, types = {}, {}, {}
    try:
        with zipfile.ZipFile(ssp) as z:
            z.extractall(tmp)
        for c in sysm.components.values():
            unzip = extract(str(Path(tmp) / c.source), unzipdir=str(Path(tmp) / "fmu" / c.name))
            md = read_model_description(unzip)
            refs[c.name] = {v.name: v.valueReference for v in md.modelVariables}
            types[c.name] = {v.name: v.type for v in md.modelVariables}
            s = FMU2Slave(
                guid=md.guid,
                unzipDirectory=unzip,
                modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName=c.name,
            )
            s.instantiate()
            s.setupExperiment(startTime=t0)
            slaves[c.name] = s

        def setv(comp: str, name: str, value) -> None:
            s, r, ty = slaves[comp], [refs[comp][name]], types[comp][name]
            if ty == "Real":
                s.setReal(r, [float(value)])
            elif ty == "Integer":
                s.setInteger(r, [int(value)])
            elif ty == "Boolean":
                s.setBoolean(r, [bool(value)])
            else:
                raise ValueError(f"{comp}.{name}: type {ty}")

        def getv(comp: str, name: str):
            s, r, ty = slaves[comp], [refs[comp][name]], types[comp][name]
            if ty == "Real":
                return s.getReal(r)[0]
            if ty == "Integer":
                return s.getInteger(r)[0]
            return s.getBoolean(r)[0]

        for c in sysm.components.values():
            for name, (_, value) in c.params.items():
                setv(c.name, name, value)
        for (comp, name), value in (overrides or {}).items():
            setv(comp, name, value)

        def transfer() -> None:
            # outputs first, then inputs: every input gets its source's current output
            vals = [getv(a, ac) for a, ac, _, _ in sysm.connections]
            for (_, _, b, bc), v in zip(sysm.connections, vals):
                setv(b, bc, v)

        values, loop = _jacobi(sysm, slaves, n, getv, transfer, lambda s: s.enterInitializationMode())
    finally:
        _release(slaves, tmp)
    times = t0 + h * np.arange(n + 1)
    return Run("fmpy", variant, times, values, loop, time.perf_counter() - t_all, sysm)


# --------------------------------------------------------------------------- libcosim
def run_libcosim(ssp: Path, variant: str = "paper000", steps: int | None = None) -> Run:
    """The system in libcosim: the archive itself for the default variant, else the
    variant's ``.ssd`` in the unpacked archive (libcosim reads any SSD file by path). The
    step size comes from the SSD's OSP annotation; parameters from its binding."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    t_all = time.perf_counter()
    sysm = read_system(ssp, variant)
    n = sysm.steps if steps is None else steps
    log_output_level(CosimLogLevel.ERROR)
    tmp = None
    try:
        if VARIANTS[variant] == "SystemStructure.ssd":
            path = Path(ssp)
        else:
            tmp = tempfile.mkdtemp(prefix="relnav-system-libcosim-")
            with zipfile.ZipFile(ssp) as z:
                z.extractall(tmp)
            path = Path(tmp) / VARIANTS[variant]
        ex = CosimExecution.from_ssp_file(str(path))
        idx = {c: ex.slave_index_from_instance_name(c) for c in sysm.components}
        refs = {c: {v.name.decode(): v.reference for v in ex.slave_variables(i)} for c, i in idx.items()}
        obs = CosimObserver.create_last_value()
        ex.add_observer(obs)
        values = _empty(n)
        t_loop = time.perf_counter()
        for k in range(n):
            if not ex.step():
                raise RuntimeError(f"libcosim step {k} failed: {_cosim_error()}")
            for key in RECORD:
                pass
            for comp in sysm.components:
                reals = [key for key in RECORD if key[0] == comp]
                got = obs.last_real_values(idx[comp], [refs[comp][v] for _, v in reals])
                for key, v in zip(reals, got):
                    values[key][k + 1] = v
                bools = [key for key in RECORD_BOOL if key[0] == comp]
                if bools:
                    got = obs.last_boolean_values(idx[comp], [refs[comp][v] for _, v in bools])
                    for key, v in zip(bools, got):
                        values[key][k + 1] = v
                ints = [key for key in RECORD_INT if key[0] == comp]
                got = obs.last_integer_values(idx[comp], [refs[comp][v] for _, v in ints])
                for key, v in zip(ints, got):
                    values[key][k + 1] = v
        loop = time.perf_counter() - t_loop
        t_end = ex.status().current_time
        if t_end != round((sysm.start + n * sysm.step) * 1e9):
            raise RuntimeError(f"libcosim ended at {t_end} ns")
        del obs, ex
    finally:
        if tmp:
            shutil.rmtree(tmp, ignore_errors=True)
    times = sysm.start + sysm.step * np.arange(n + 1)
    return Run("libcosim", variant, times, values, loop, time.perf_counter() - t_all, sysm)


def _cosim_error() -> str:
    from libcosimpy._internal import get_last_error_message

    return get_last_error_message()


# ------------------------------------------------------------------------------- Ecos
def run_ecos(ssp: Path, variant: str = "paper000", steps: int | None = None) -> Run:
    """The system in Ecos: the archive itself for the default variant, else a folder
    holding the variant as its ``SystemStructure.ssd`` (Ecos reads no other SSD). Ecos
    takes the step size as an argument (it ignores the OSP annotation) and applies the
    parameter set only when named in ``init``. Its copy of an unpacked archive goes to a
    temporary folder of ours (``TMPDIR``), removed afterwards."""
    from ecospy import EcosLib, EcosSimulation

    t_all = time.perf_counter()
    sysm = read_system(ssp, variant)
    if sysm.start != 0.0:
        raise ValueError("Ecos starts its clock at 0: the SSD's startTime must be 0")
    n = sysm.steps if steps is None else steps
    EcosLib.set_log_level("warn")
    tmp = tempfile.mkdtemp(prefix="relnav-system-ecos-")
    old_tmpdir = os.environ.get("TMPDIR")
    os.environ["TMPDIR"] = tmp  # Ecos unpacks an archive into the temp folder and leaves it
    sim = None
    try:
        if VARIANTS[variant] == "SystemStructure.ssd":
            path = Path(ssp)
        else:
            path = Path(tmp) / "variant"
            with zipfile.ZipFile(ssp) as z:
                z.extractall(path)
            (path / "SystemStructure.ssd").write_bytes((path / VARIANTS[variant]).read_bytes())
        sim = EcosSimulation(step_size=sysm.step, ssp_path=str(path))
        if not sim.init(parameter_set=sysm.set_name):
            raise RuntimeError(f"Ecos init failed: {EcosLib.get_last_error()}")
        values = _empty(n)

        def record(k: int) -> None:
            for comp, v in RECORD:
                values[(comp, v)][k] = sim.get_real(f"{comp}::{v}")
            for comp, v in RECORD_BOOL:
                values[(comp, v)][k] = sim.get_bool(f"{comp}::{v}")
            for comp, v in RECORD_INT:
                values[(comp, v)][k] = sim.get_integer(f"{comp}::{v}")

        record(0)
        t_loop = time.perf_counter()
        for k in range(n):
            sim.step(1)
            record(k + 1)
        loop = time.perf_counter() - t_loop
        if sim.get_time() != sysm.start + n * sysm.step:
            raise RuntimeError(f"Ecos ended at {sim.get_time()} s")
        sim.terminate()
    finally:
        if sim is not None:
            sim.free()
        if old_tmpdir is None:
            os.environ.pop("TMPDIR", None)
        else:
            os.environ["TMPDIR"] = old_tmpdir
        shutil.rmtree(tmp, ignore_errors=True)
    times = sysm.start + sysm.step * np.arange(n + 1)
    return Run("Ecos", variant, times, values, loop, time.perf_counter() - t_all, sysm)


MASTERS = {"fmpy": run_fmpy, "libcosim": run_libcosim, "Ecos": run_ecos}


# ---------------------------------------------------------------------------- results
def hold_point(run: Run) -> np.ndarray:
    p = run.system.components["guidance"].params
    return np.array([p.get(f"hold_{a}", ("Real", 0.0))[1] for a in "xyz"], dtype=float)


@dataclass
class Metrics:
    final_hold_error: float  # |true position - hold point| at the end [m]
    hold_error_last: float  # largest |true position - hold point| over the last tenth [m]
    rmse_pos: float  # estimation RMSE of the position over the run (after the first step) [m]
    rmse_vel: float  # [m/s]
    rmse_pos_last: float  # over the last half [m]
    final_sigma_pos: float  # the filter's own 1-sigma position uncertainty at the end, RSS [m]
    delta_v: float  # [m/s]
    measurements: int  # valid measurements
    loop_seconds: float
    total_seconds: float


def metrics(run: Run) -> Metrics:
    truth = run.series("plant", TRUTH)
    est = run.series("relnav", ESTIMATE)
    sig = run.series("relnav", SIGMA)
    err = est - truth
    rows = slice(1, None)  # libcosim has no row 0
    n = len(run.times) - 1
    half = slice(1 + n // 2, None)
    last = slice(n - n // 10, None)
    hold = hold_point(run)
    dist = np.linalg.norm(truth[:, :3] - hold, axis=1)
    return Metrics(
        final_hold_error=float(dist[-1]),
        hold_error_last=float(np.max(dist[last])),
        rmse_pos=float(np.sqrt(np.mean(np.sum(err[rows, :3] ** 2, axis=1)))),
        rmse_vel=float(np.sqrt(np.mean(np.sum(err[rows, 3:] ** 2, axis=1)))),
        rmse_pos_last=float(np.sqrt(np.mean(np.sum(err[half, :3] ** 2, axis=1)))),
        final_sigma_pos=float(np.sqrt(np.sum(sig[-1, :3] ** 2))),
        delta_v=float(run.values[("guidance", "delta_v")][-1]),
        measurements=int(np.nansum(run.values[("plant", "measurement_valid")][1:])),
        loop_seconds=run.loop_seconds,
        total_seconds=run.total_seconds,
    )


def first_difference(a: Run, b: Run) -> str | None:
    """``None`` when ``a`` and ``b`` hold the same bits at every communication point both
    recorded (rows 1..N), else where they first differ."""
    for key in RECORD + RECORD_BOOL + RECORD_INT:
        x, y = a.values[key][1:], b.values[key][1:]
        if not np.array_equal(x.view(np.uint64), y.view(np.uint64)):
            k = int(np.argwhere(x.view(np.uint64) != y.view(np.uint64))[0][0]) + 1
            return f"{key[0]}.{key[1]} at t = {a.times[k]}: {a.master} {x[k - 1]!r}, {b.master} {y[k - 1]!r}"
    return None


def plot(run: Run, path: Path) -> Path:
    """True and estimated trajectory, estimation error per axis with its 3-sigma band,
    thrust."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = run.times
    truth = run.series("plant", TRUTH)
    est = run.series("relnav", ESTIMATE)
    sig = run.series("relnav", SIGMA)
    thrust = run.series("guidance", THRUST)
    hold = hold_point(run)
    frame = run.system.components["relnav"].params.get("frame", ("Integer", 2))[1]
    axes_names = {1: ("x radial", "y along-track", "z normal"), 2: ("x along-track", "y radial", "z -normal"), 3: ("x along-track", "y -normal", "z nadir")}[frame]
    # the orbital plane as GNC engineers draw it: along-track (V-bar) across, radial (R-bar) up
    along, radial = {1: ((1, 1.0), (0, 1.0)), 2: ((0, 1.0), (1, 1.0)), 3: ((0, 1.0), (2, -1.0))}[frame]
    ax_of = lambda p: (along[1] * p[..., along[0]], radial[1] * p[..., radial[0]])  # noqa: E731
    fig = plt.figure(figsize=(13, 9), layout="constrained")
    gs = fig.add_gridspec(4, 2, width_ratios=[1.1, 1])
    ax = fig.add_subplot(gs[:3, 0])
    ax.plot(*ax_of(truth), "k-", lw=1.2, label="true")
    ax.plot(*ax_of(est[1:]), "C0--", lw=0.9, label="estimated (relnav)")
    ax.plot(*ax_of(truth[0]), "ko", label="start")
    ax.plot(*ax_of(hold), "r*", ms=14, label="hold point")
    ax.set_xlabel("along-track (V-bar) [m]")
    ax.set_ylabel("radial (R-bar, up) [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right")
    ax.set_title(f"relnav_system.ssp, {run.variant} ({run.master}): orbital plane (I/O frame {frame})")
    m = metrics(run)
    ax.text(
        0.02,
        0.98,
        f"final |r - r_hold| = {m.final_hold_error:.3f} m\nposition RMSE = {m.rmse_pos:.3f} m "
        f"(last half {m.rmse_pos_last:.3f} m)\ndelta-v = {m.delta_v:.3f} m/s",
        transform=ax.transAxes,
        fontsize=9,
        va="top",
        bbox=dict(boxstyle="round", fc="white", alpha=0.8),
    )
    for i in range(3):
        a = fig.add_subplot(gs[i, 1])
        e = est[1:, i] - truth[1:, i]
        a.fill_between(t[1:], -3 * sig[1:, i], 3 * sig[1:, i], color="C1", alpha=0.25, label="±3 sigma (relnav)")
        a.plot(t[1:], e, "C0-", lw=0.7, label="estimate - truth")
        lim = 4 * np.nanpercentile(np.abs(sig[len(t) // 10 :, i]), 90)
        a.set_ylim(-lim, lim)
        a.set_ylabel(f"error {axes_names[i].split()[0]} [m]")
        a.grid(alpha=0.3)
        if i == 0:
            a.legend(loc="upper right", fontsize=8)
            a.set_title("estimation error per axis")
    a = fig.add_subplot(gs[3, :])
    for i in range(3):
        a.step(t[:-1], thrust[:-1, i], where="post", lw=0.8, label=f"thrust {axes_names[i].split()[0]}")
    a.set_xlabel("time [s]")
    a.set_ylabel("thrust [N]")
    a.grid(alpha=0.3)
    a.legend(loc="upper right", fontsize=8)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ssp", type=Path, default=DEFAULT_SSP, help="relnav_system.ssp (default: target/fmu/)")
    ap.add_argument("--variant", choices=[*VARIANTS, "all"], default="all")
    ap.add_argument("--master", choices=[*MASTERS, "all"], default="all")
    ap.add_argument("--steps", type=int, default=None, help="communication steps (default: the SSD's stop time)")
    ap.add_argument("--plot-dir", type=Path, default=REPO_ROOT / "results", help="where relnav_system_<variant>.png goes")
    ap.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="COMPONENT.VARIABLE=VALUE",
        help="fmpy only: override a parameter after the SSD's set (e.g. relnav.filter=1); no plot is written",
    )
    args = ap.parse_args(argv)
    overrides = {}
    for item in args.set:
        key, _, value = item.partition("=")
        comp, _, name = key.partition(".")
        if not (comp and name and value):
            ap.error(f"--set {item!r}: expected COMPONENT.VARIABLE=VALUE")
        overrides[(comp, name)] = float(value)
    if overrides and args.master != "fmpy":
        ap.error("--set needs --master fmpy (libcosim and Ecos run the SSD as it is)")
    if not args.ssp.is_file():
        print(f"error: {args.ssp} not found; build it with fmu/build.sh", file=sys.stderr)
        return 2
    variants = list(VARIANTS) if args.variant == "all" else [args.variant]
    masters = list(MASTERS) if args.master == "all" else [args.master]
    status = 0
    for variant in variants:
        if overrides:
            runs = [run_fmpy(args.ssp, variant, args.steps, overrides)]
        else:
            runs = [MASTERS[m](args.ssp, variant, args.steps) for m in masters]
        sysm = runs[0].system
        print(f"\n### relnav_system.ssp, variant {variant} ({sysm.ssd}, parameter set \"{sysm.set_name}\"): "
              f"{len(runs[0].times) - 1} steps of {sysm.step} s")
        print("\n| master | final hold-point error [m] | max over last 10 % [m] | position RMSE [m] | "
              "(last half) [m] | velocity RMSE [m/s] | final 1-sigma [m] | delta-v [m/s] | measurements | loop [s] | total [s] |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for r in runs:
            m = metrics(r)
            print(f"| {r.master} | {m.final_hold_error:.4f} | {m.hold_error_last:.4f} | {m.rmse_pos:.4f} | "
                  f"{m.rmse_pos_last:.4f} | {m.rmse_vel:.5f} | {m.final_sigma_pos:.4f} | {m.delta_v:.4f} | "
                  f"{m.measurements} | {m.loop_seconds:.2f} | {m.total_seconds:.2f} |")
        for r in runs[1:]:
            d = first_difference(runs[0], r)
            if d is None:
                print(f"\n{r.master} = {runs[0].master}: every recorded value identical, bit for bit, at every communication point")
            else:
                status = 1
                print(f"\n{r.master} differs from {runs[0].master}: {d}")
        if overrides:
            print(f"\n(fmpy with overrides {overrides}: no plot)")
            continue
        ref = next((r for r in runs if r.master != "libcosim"), runs[0])
        out = plot(ref, args.plot_dir / f"relnav_system_{variant}.png")
        print(f"\nplot: {out}")
    return status


if __name__ == "__main__":
    sys.exit(main())
