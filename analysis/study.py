"""Design studies: the study file, its candidates, and what one candidate evaluates to.

A study is a JSON object::

    {"arm": "urm6",
     "vary": {"theta3": {"from": 0, "to": 90, "steps": 7, "unit": "deg"},
              "theta5": {"values": [30, 60, 90], "unit": "deg"}},
     "evaluate": ["workspace_volume", "reach", "min_manipulability"],
     "samples": 200000}

``arm``: any arm :func:`~armlab.models.get_arm` takes (``armlab list``: a paper arm, a library arm, an example), or
a ``.urdf``, ``.sdf``, MJCF ``.xml`` or DH ``.csv`` file (relative to the study file).
``vary``: parameters of the arm's ``Parameters`` (``armlab show ARM``), ``payload`` (kg, a point mass
at the tool) and ``tf`` (the motion's duration, s), each ``{"from", "to", "steps"}`` (evenly spaced,
both ends included) or ``{"values": [...]}``, with an optional ``unit`` (:data:`UNITS`; default SI).
Every combination is a candidate. ``evaluate``: objectives from :data:`OBJECTIVES`. Optional:
``samples`` (workspace samples, default 200000), ``resolution`` (voxel edge, m; default: each
candidate's own, :func:`~armlab.analysis.workspace.default_resolution`), ``seed`` (0), ``payload``
(kg) and ``tf`` (s) when not varied,
``simulate`` (false: torques by batch inverse dynamics along the motion sampled every 1 ms; true: by
paper 000's Fig. 6 simulation), ``segments`` (a segments file, as ``armlab simulate --segments``,
instead of the arm's paper motion). The drive objectives (:data:`DRIVES`) choose every joint's motor and gearbox
for the motion, carrying the payload throughout (:func:`armlab.sizing.sizing.size`, with the mass iteration):
``drive_mass`` (kg, the chosen drives' total; NaN when infeasible), ``drives_feasible`` (1 or 0) and
``drive_margin`` (the chosen pairs' smallest margin; NaN when infeasible); optional ``safety_factor`` (≥ 1, default
1), ``motors`` and ``gearboxes`` (catalogue CSV files, relative to the study file; default armlab's examples).

The servo objectives (:data:`SERVO`: ``max_tracking_error`` and ``rms_tracking_error`` per joint, rad or m) simulate
each candidate through the servo loop of ``servo`` (an object of :class:`~armlab.diagrams.simulate.SimulationOptions`'
servo settings: ``{"controller": "pid", "bandwidth": 5, "rate": 1000, "encoder": 4096, …}``), and may vary the
controller's ``rate`` (Hz or kHz) and the ``encoder``'s counts per revolution; ``drives`` (a drive file, relative to
the study file) gives the arm its drive train (the encoder on the motor, the motors' electrics).
"""

from __future__ import annotations

import itertools
import json
import math
import os
import socket
import time
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from armlab.analysis.singular import JACOBIAN_SAMPLES, task_sigma
from armlab.analysis.workspace import (
    DEFAULT_SAMPLES,
    check_resolution,
    check_samples,
    check_seed,
    sample_joints,
    tool_positions,
    workspace,
    workspace_plane,
)
from armlab.arm_file import MAX_FILE_NUMBER
from armlab.diagrams.drives import torque_stats
from armlab.diagrams.simulate import DEFAULT_LOG_PERIOD, SimulationOptions, check_work, simulate
from armlab.drives.read import with_drives
from armlab.files import json_number, read_json
from armlab.kinematics.rnea import inverse_dynamics
from armlab.limits import check_range
from armlab.models import ARMS, get_arm
from armlab.models.plant import PlantOptions
from armlab.planning.motions import paper_motion, read_segments
from armlab.sizing.catalogue import read_gearboxes, read_motors
from armlab.sizing.duty import DutyCycle, LoadCase
from armlab.sizing.select import check_safety_factor
from armlab.sizing.sizing import size
from armlab.values import check_payload, cut, shown

if TYPE_CHECKING:
    from armlab.kinematics.quintic import Motion
    from armlab.models.arm import Arm

__all__ = ["COLLISION", "DRIVES", "DYNAMICS", "MAX_CANDIDATES", "OBJECTIVES", "PER_JOINT", "SERVO", "SERVO_SETTINGS",
           "SERVO_VARIABLES", "UNITS", "WORKSPACE", "Study", "Variable", "evaluate", "load_study", "parse_study"]

#: Objectives computed from the workspace (:func:`armlab.analysis.workspace.workspace`), with units.
WORKSPACE = {"workspace_volume": "m^dim", "reach": "m", "min_manipulability": "", "mean_manipulability": "",
             "collision_free_volume": "m^dim", "min_clearance": "m"}
#: Workspace objectives that check the samples for collisions (the arm against itself).
COLLISION = ("collision_free_volume", "min_clearance")
#: Objectives computed from the joint torques along the motion; the first two per joint.
DYNAMICS = {"peak_torque": "N·m or N", "rms_torque": "N·m or N", "peak_power": "W"}
#: Objectives of the drives chosen from the catalogues for the motion (see the module docstring).
DRIVES = {"drive_mass": "kg", "drives_feasible": "", "drive_margin": ""}
#: Objectives of the servo loop's simulation (see the module docstring), per joint.
SERVO = {"max_tracking_error": "rad or m", "rms_tracking_error": "rad or m"}
OBJECTIVES = {**WORKSPACE, **DYNAMICS, **DRIVES, **SERVO}
#: Per-joint objectives: a column each, ``NAME_1`` … ``NAME_n``.
PER_JOINT = ("peak_torque", "rms_torque", *SERVO)
#: The servo loop's variables a study may vary (with its servo objectives).
SERVO_VARIABLES = ("rate", "encoder")
#: Units a varied value may be given in, and their factor to SI.
UNITS = {"deg": np.pi / 180, "rad": 1.0, "m": 1.0, "cm": 1e-2, "mm": 1e-3, "kg": 1.0, "g": 1e-3, "s": 1.0,
         "ms": 1e-3, "Hz": 1.0, "kHz": 1e3}
#: Units allowed for the study's own variables.
_OWN_UNITS = {"payload": ("kg", "g"), "tf": ("s", "ms"), "rate": ("Hz", "kHz"), "encoder": ()}
_KEYS = ("arm", "vary", "evaluate", "samples", "resolution", "seed", "payload", "tf", "simulate", "segments",
         "safety_factor", "motors", "gearboxes", "servo", "drives")
#: The settings a study's ``servo`` object may give (SimulationOptions' servo fields).
SERVO_SETTINGS = ("controller", "rate", "bandwidth", "saturate", "anti_windup", "encoder", "encoder_side", "velocity",
                  "velocity_cutoff", "noise", "seed", "delay", "electrics", "current_rate", "current_bandwidth",
                  "elastic")
#: Period of the motion's samples for the batch inverse dynamics (s).
TORQUE_PERIOD = 1e-3
#: Most candidates of one study (each is built and checked before any work starts).
MAX_CANDIDATES = 10_000


@dataclass(frozen=True)
class Variable:
    """A varied parameter: its values as the study gives them (``unit``) and in SI."""

    name: str
    unit: str
    values: tuple[float, ...]

    @property
    def si(self) -> tuple[float, ...]:
        """The values in SI units (rad, m, kg, s)."""
        factor = UNITS.get(self.unit, 1.0)
        return tuple(v * factor for v in self.values)

    @property
    def column(self) -> str:
        """Its column in ``results.csv`` (the study's unit)."""
        return self.name


@dataclass(frozen=True)
class Study:
    """A checked study (see the module docstring). ``arm`` is an arm's name or a file's absolute path."""

    arm: str
    vary: tuple[Variable, ...]
    evaluate: tuple[str, ...]
    samples: int
    resolution: float | None
    seed: int
    payload: float
    tf: float | None
    simulate: bool
    segments: str | None
    n: int  # the arm's joint count
    dim: int  # dimension of its workspace (2: planar)
    safety_factor: float = 1.0  # the drive objectives' (DRIVES)
    motors: str | None = None  # their catalogues' absolute paths; None: armlab's examples
    gearboxes: str | None = None
    servo: tuple[tuple[str, Any], ...] = ()  # the servo objectives' settings (SERVO_SETTINGS), as (name, value)
    drives: str | None = None  # a drive file's absolute path: the arm's drive train

    @property
    def candidates(self) -> list[tuple[float, ...]]:
        """Every combination of the varied values (study units), the first variable slowest."""
        return list(itertools.product(*(v.values for v in self.vary)))

    @property
    def objective_columns(self) -> list[str]:
        """Objective columns of ``results.csv``: per-joint ones as ``peak_torque_1`` … ``peak_torque_n``."""
        cols = []
        for name in self.evaluate:
            cols += [f"{name}_{i}" for i in range(1, self.n + 1)] if name in PER_JOINT else [name]
        return cols

    @property
    def columns(self) -> list[str]:
        """The header of ``results.csv``."""
        return ["candidate", *(v.column for v in self.vary), *self.objective_columns, "wall_time_s", "worker"]

    def units(self) -> dict[str, str]:
        """Unit of every column."""
        units = {v.column: v.unit for v in self.vary}
        volume = {1: "m", 2: "m²", 3: "m³"}[self.dim]
        for col in self.objective_columns:
            base = next(name for name in OBJECTIVES if col == name or col.startswith(name + "_"))
            units[col] = volume if base in ("workspace_volume", "collision_free_volume") else OBJECTIVES[base]
        return units | {"wall_time_s": "s"}

    def settings(self, values: tuple[float, ...]) -> tuple[dict[str, float], float, float | None]:
        """Arm parameter overrides, payload and tf (SI) of the candidate ``values`` (study units)."""
        overrides: dict[str, float] = {}
        payload, tf = self.payload, self.tf
        for var, value in zip(self.vary, values, strict=True):
            si = value * UNITS.get(var.unit, 1.0)
            if var.name == "payload":
                payload = si
            elif var.name == "tf":
                tf = si
            elif var.name not in SERVO_VARIABLES:
                overrides[var.name] = si
        return overrides, payload, tf

    def servo_settings(self, values: tuple[float, ...]) -> dict[str, Any]:
        """The candidate's servo settings: the study's ``servo``, its varied rate (Hz) and encoder counts."""
        settings = dict(self.servo)
        for var, value in zip(self.vary, values, strict=True):
            if var.name == "rate":
                settings["rate"] = value * UNITS.get(var.unit, 1.0)
            elif var.name == "encoder":
                settings["encoder"] = int(value) if float(value).is_integer() else value
        return settings

    def to_json(self) -> dict[str, Any]:
        """The study as run: every setting explicit."""
        return {
            "arm": self.arm,
            "vary": {v.name: {"values": list(v.values), "unit": v.unit} for v in self.vary},
            "evaluate": list(self.evaluate),
            "samples": self.samples,
            "resolution": self.resolution,
            "seed": self.seed,
            "payload": self.payload,
            "tf": self.tf,
            "simulate": self.simulate,
            "segments": self.segments,
            "safety_factor": self.safety_factor,
            "motors": self.motors,
            "gearboxes": self.gearboxes,
            "servo": dict(self.servo),
            "drives": self.drives,
        }


# --------------------------------------------------------------------------------------------- parsing
def load_study(path: str | Path) -> Study:
    """Read and check a study file (:func:`parse_study`); ``ValueError`` with one line naming the problem."""
    path = Path(path)
    data = read_json(path, "study")
    try:
        return parse_study(data, path.parent)
    except ValueError as error:
        raise ValueError(f"{path}: {error}") from None


def _variable(name: str, spec: Any, known: list[str]) -> Variable:
    if name not in known:
        raise ValueError(f"vary: unknown parameter {shown(name)}; allowed: {', '.join(known)}")
    if not isinstance(spec, dict):
        raise ValueError(f"vary.{name} = {cut(json.dumps(spec))} must be an object {{\"from\", \"to\", \"steps\"}} or "
                         "{\"values\"}")
    unit = spec.get("unit", "")
    allowed_units = _OWN_UNITS.get(name, tuple(UNITS))
    if unit and unit not in allowed_units:
        raise ValueError(f"vary.{name}: unit {cut(json.dumps(unit))} is not allowed; allowed: "
                         f"{', '.join(allowed_units)}")
    extra = set(spec) - {"from", "to", "steps", "values", "unit"}
    if extra:
        raise ValueError(f"vary.{shown(name)}: unknown key {shown(sorted(extra)[0])}; allowed: from, to, steps, "
                         "values, unit")
    if "values" in spec:
        if {"from", "to", "steps"} & set(spec):
            raise ValueError(f"vary.{name}: give \"values\" or \"from\"/\"to\"/\"steps\", not both")
        raw = spec["values"]
        if not isinstance(raw, list) or not raw:
            raise ValueError(f"vary.{name}.values = {cut(json.dumps(raw))}: the range is empty; give a non-empty list")
        values = [json_number(v, f"vary.{name}.values[{i}]") for i, v in enumerate(raw)]
        if len(set(values)) != len(values):
            raise ValueError(f"vary.{name}.values = {cut(json.dumps(raw))} repeats a value")
    else:
        missing = [k for k in ("from", "to", "steps") if k not in spec]
        if missing:
            raise ValueError(f"vary.{name}: missing {', '.join(repr(k) for k in missing)} (or give \"values\")")
        lo, hi = json_number(spec["from"], f"vary.{name}.from"), json_number(spec["to"], f"vary.{name}.to")
        steps = spec["steps"]
        if isinstance(steps, bool) or not isinstance(steps, int):
            raise ValueError(f"vary.{name}.steps = {cut(json.dumps(steps))} must be a whole number 1 … "
                             f"{MAX_CANDIDATES:,}")
        if steps < 1:
            raise ValueError(f"vary.{name}.steps = {steps}: the range is empty; give a whole number ≥ 1")
        if steps == 1 and lo != hi:
            raise ValueError(f"vary.{name}: steps = 1 from {lo:g} to {hi:g}; give steps ≥ 2 or from = to")
        if steps > MAX_CANDIDATES:
            raise ValueError(f"vary.{name}.steps = {steps:,} is more than the {MAX_CANDIDATES:,} candidates a study "
                             "may have; give fewer steps")
        values = np.linspace(lo, hi, steps).tolist()
    if name not in _OWN_UNITS:  # an arm parameter: bounded like the numbers of an arm file

        big = next((v for v in values if abs(v * UNITS.get(unit, 1.0)) > MAX_FILE_NUMBER), None)
        if big is not None:
            raise ValueError(f"vary.{name}: {big:g}{' ' + unit if unit else ''} is out of range: allowed |{name}| ≤ "
                             f"{MAX_FILE_NUMBER:g} (m or rad; like the numbers of an arm file)")
    return Variable(name, unit, tuple(values))


def parse_study(data: Any, base: Path = Path()) -> Study:
    """Check a study (the decoded JSON) before any work; ``ValueError`` with one line naming the problem.

    Every candidate's arm (and, for torque objectives, its motion) is built here, so a value the arm
    does not allow is found before anything runs. ``base``: the folder file names are relative to.
    """
    if not isinstance(data, dict):
        raise ValueError("a study must be a JSON object with \"arm\", \"vary\" and \"evaluate\"")
    extra = [k for k in data if k not in _KEYS]
    if extra:
        raise ValueError(f"unknown key {shown(extra[0])}; allowed: {', '.join(_KEYS)}")
    for key in ("arm", "vary", "evaluate"):
        if key not in data:
            raise ValueError(f"missing {shown(key)}")
    name = data["arm"]
    if not isinstance(name, str):
        raise ValueError(f"arm = {cut(json.dumps(name))} must be a name or a file")
    if name not in ARMS and Path(name).suffix:  # a file: relative to the study's folder (get_arm says what it is)
        name = str((base / name).resolve())
    nominal = get_arm(name)
    known = [f.name for f in fields(ARMS[name].Parameters)] if name in ARMS else []
    known += ["payload", "tf", *SERVO_VARIABLES]
    if not isinstance(data["vary"], dict) or not data["vary"]:
        raise ValueError("vary must be a non-empty object {parameter: range}")
    vary = tuple(_variable(k, v, known) for k, v in data["vary"].items())
    count = math.prod(len(v.values) for v in vary)
    if count > MAX_CANDIDATES:
        raise ValueError(f"vary makes {count:,} candidates ({' × '.join(str(len(v.values)) for v in vary)}), more "
                         f"than the {MAX_CANDIDATES:,} a study may have; vary fewer values")
    evaluate = data["evaluate"]
    if not isinstance(evaluate, list) or not evaluate or not all(isinstance(e, str) for e in evaluate):
        raise ValueError(f"evaluate = {cut(json.dumps(evaluate))} must be a non-empty list of objectives")
    for objective in evaluate:
        if objective not in OBJECTIVES:
            raise ValueError(f"evaluate: unknown objective {shown(objective)}; allowed: {', '.join(OBJECTIVES)}")
    if len(set(evaluate)) != len(evaluate):
        raise ValueError(f"evaluate = {cut(json.dumps(evaluate))} repeats an objective")
    dynamics = any(e in DYNAMICS or e in DRIVES or e in SERVO for e in evaluate)
    if dynamics:
        nominal.require_dynamics("torque objectives")
    for key in ("payload", "tf", "simulate", "segments", "drives"):
        if not dynamics and (key in data or key in data["vary"]):
            where = f"vary.{key}" if key in data["vary"] else key
            raise ValueError(f"{where} changes only the torque objectives ({', '.join(DYNAMICS)}), the drive "
                             f"objectives ({', '.join(DRIVES)}) and the servo objectives ({', '.join(SERVO)}); "
                             "evaluate one of them")
    servo = _servo(data, any(e in SERVO for e in evaluate))
    drives = any(e in DRIVES for e in evaluate)
    for key in ("safety_factor", "motors", "gearboxes"):
        if key in data and not drives:
            raise ValueError(f"{key} changes only the drive objectives ({', '.join(DRIVES)}); evaluate one of them")
    safety_factor = check_safety_factor(json_number(data.get("safety_factor", 1.0), "safety_factor"))
    catalogues = []
    for key in ("motors", "gearboxes"):
        file = data.get(key)
        if file is not None and not isinstance(file, str):
            raise ValueError(f"{key} = {cut(json.dumps(file))} must be a file name")
        catalogues.append(None if file is None else str((base / file).resolve()))
    if drives:
        read_motors(catalogues[0]), read_gearboxes(catalogues[1])  # checked before any work
    samples = check_samples(data.get("samples", DEFAULT_SAMPLES // 5))
    seed = check_seed(data.get("seed", 0))
    payload = json_number(data.get("payload", 0.0), "payload")
    tf = None if data.get("tf") is None else json_number(data["tf"], "tf")
    simulate = data.get("simulate", False)
    if not isinstance(simulate, bool):
        raise ValueError(f"simulate = {cut(json.dumps(simulate))} must be true or false")
    segments = data.get("segments")
    if segments is not None:
        if not isinstance(segments, str):
            raise ValueError(f"segments = {cut(json.dumps(segments))} must be a file name")
        if tf is not None or any(v.name == "tf" for v in vary):
            raise ValueError("segments gives the motion's times: do not give or vary tf with it")
        segments = str((base / segments).resolve())
    q = sample_joints(nominal, 4096, 0)
    dim = workspace_plane(tool_positions(nominal, q))[1].shape[0]
    resolution = data.get("resolution")
    if resolution is not None:
        resolution = check_resolution(json_number(resolution, "resolution"))
    drive_file = data.get("drives")
    if drive_file is not None and not isinstance(drive_file, str):
        raise ValueError(f"drives = {cut(json.dumps(drive_file))} must be a file name")
    study = Study(name, vary, tuple(evaluate), samples, resolution, seed, payload, tf, simulate, segments,
                  nominal.n, dim, safety_factor, motors=catalogues[0], gearboxes=catalogues[1], servo=servo,
                  drives=None if drive_file is None else str((base / drive_file).resolve()))
    for values in study.candidates:
        try:
            build(study, values)
        except ValueError as error:
            text = ", ".join(f"{v.name} = {x:g} {v.unit}".rstrip() for v, x in zip(vary, values, strict=True))
            raise ValueError(f"candidate {text}: {error}") from None
    return study


def _servo(data: dict[str, Any], evaluated: bool) -> tuple[tuple[str, Any], ...]:
    """The study's ``servo`` settings as (name, value) pairs; ``ValueError`` for an unknown setting, or for servo
    settings or variables without a servo objective (the values themselves: checked with each candidate)."""
    settings = data.get("servo", {})
    if not isinstance(settings, dict):
        raise ValueError(f"servo = {cut(json.dumps(settings))} must be an object of servo settings")
    unknown = [k for k in settings if k not in SERVO_SETTINGS]
    if unknown:
        raise ValueError(f"servo: unknown setting {shown(unknown[0])}; allowed: {', '.join(SERVO_SETTINGS)}")
    varied = [k for k in SERVO_VARIABLES if k in data["vary"]]
    if (settings or varied) and not evaluated:
        where = "servo" if settings else f"vary.{varied[0]}"
        raise ValueError(f"{where} changes only the servo objectives ({', '.join(SERVO)}); evaluate one of them")
    return tuple(settings.items())


# ------------------------------------------------------------------------------------------ evaluation
def build(study: Study, values: tuple[float, ...]) -> tuple[Arm, Motion | None, float]:
    """The candidate's arm, its motion (``None`` without torque objectives) and payload; ``ValueError`` if bad
    (the servo settings too: :func:`servo_options`)."""
    overrides, payload, tf = study.settings(values)
    arm = with_drives(get_arm(study.arm, **overrides), study.drives)
    if not any(e in DYNAMICS or e in DRIVES or e in SERVO for e in study.evaluate):
        return arm, None, payload
    payload = check_payload(payload)
    if tf is not None:
        check_range(tf, "tf")
    motion = read_segments(arm, study.segments) if study.segments else paper_motion(arm, tf=tf)
    check_work(motion, DEFAULT_LOG_PERIOD if study.simulate or any(e in SERVO for e in study.evaluate)
               else TORQUE_PERIOD)
    if any(e in SERVO for e in study.evaluate):
        servo_options(study, values, payload)
    return arm, motion, payload


def servo_options(study: Study, values: tuple[float, ...], payload: float) -> SimulationOptions:
    """The simulation options of the candidate's servo run; ``ValueError`` naming a bad setting."""
    return SimulationOptions(PlantOptions(payload=payload, ideal_drives=True), **study.servo_settings(values))


def evaluate(study: Study, values: tuple[float, ...]) -> dict[str, float]:
    """The objectives of one candidate (``values`` in the study's units), by column of ``results.csv``."""
    arm, motion, payload = build(study, values)
    out: dict[str, float] = {}
    if any(e in WORKSPACE for e in study.evaluate):
        w = workspace(arm, study.samples, study.resolution, study.seed, jacobians=False,
                      collisions=any(e in COLLISION for e in study.evaluate))
        found: dict[str, float | None] = {"workspace_volume": w.volume, "reach": w.reach,
                                          "collision_free_volume": w.collision_free_volume,
                                          "min_clearance": w.min_clearance}
        if any(e.endswith("manipulability") for e in study.evaluate):  # on the workspace's kept configurations
            manipulability = task_sigma(arm, w.q[:JACOBIAN_SAMPLES])[0]
            found |= {"min_manipulability": float(manipulability.min()),
                      "mean_manipulability": float(manipulability.mean())}
        for e in (e for e in study.evaluate if e in WORKSPACE):
            value = found[e]
            if value is None:  # min_clearance of an arm with no pair to check
                raise ValueError(f"evaluate: {e}: {arm.name} has no pair of links to check (adjacent links never "
                                 "are)")
            out[e] = float(value)
    if motion is not None and any(e in DRIVES for e in study.evaluate):
        sizing = size(arm, DutyCycle.of(motion), (LoadCase(payload),), read_motors(study.motors),
                      read_gearboxes(study.gearboxes), study.safety_factor)
        drives = {"drive_mass": sizing.drive_mass, "drives_feasible": float(sizing.feasible),
                  "drive_margin": sizing.margin}
        out |= {e: drives[e] for e in study.evaluate if e in DRIVES}
    if motion is not None and any(e in SERVO for e in study.evaluate):
        log = simulate(arm, motion, servo_options(study, values, payload))
        error = np.abs(log.q - log.q_ref)
        tracking = {"max_tracking_error": error.max(axis=0), "rms_tracking_error": np.sqrt(np.mean(error**2, axis=0))}
        for e in (e for e in study.evaluate if e in SERVO):
            out |= {f"{e}_{i + 1}": float(v) for i, v in enumerate(tracking[e])}
    if motion is not None and any(e in DYNAMICS for e in study.evaluate):
        stats = torque_stats(*_torques(study, arm, motion, payload))
        drive = {"peak_torque": stats["max_abs_torque"], "rms_torque": stats["rms_torque"],
                 "peak_power": stats["peak_power"]}
        for e in study.evaluate:
            if e in ("peak_torque", "rms_torque"):
                out |= {f"{e}_{i + 1}": float(v) for i, v in enumerate(drive[e])}
            elif e == "peak_power":
                out[e] = drive[e]
    return out


def _torques(study: Study, arm: Arm, motion: Motion, payload: float) -> tuple[np.ndarray, np.ndarray]:
    """Joint torques and rates along ``motion``: Fig. 6's simulation, or batch inverse dynamics every 1 ms."""
    if study.simulate:
        log = simulate(arm, motion, SimulationOptions(PlantOptions(payload=payload, ideal_drives=True)))
        return log.tau, log.qd

    t = np.linspace(0.0, motion.duration, round(motion.duration / TORQUE_PERIOD) + 1)
    q, qd, qdd = motion.evaluate(t)
    return inverse_dynamics(arm, q, qd, qdd, payload=payload), qd


def timed_evaluate(study: Study, values: tuple[float, ...]) -> dict[str, Any]:
    """:func:`evaluate` on a Dask worker: ``{"objectives", "wall_time_s", "worker"}``, or ``{"error", …}``
    when the candidate raises (its message, one line), so that the other candidates go on."""
    try:
        from distributed import get_worker

        worker = get_worker().address
    except (ImportError, ValueError):
        worker = f"{socket.gethostname()}:{os.getpid()}"
    began = time.perf_counter()
    try:
        objectives = evaluate(study, values)
    except Exception as error:  # reported with the candidate's parameters; the sweep goes on
        message = str(error).strip().splitlines()[0] if str(error).strip() else ""
        return {"error": f"{type(error).__name__}: {message}", "worker": worker}
    return {"objectives": objectives, "wall_time_s": time.perf_counter() - began, "worker": worker}
