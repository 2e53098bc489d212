"""Duty cycles and load cases: what a drive has to do, over and over, with each payload it may carry.

A :class:`DutyCycle` is a sequence of steps, each a :class:`Move` (an armlab
:class:`~armlab.kinematics.quintic.Motion`) or a :class:`Dwell` (the arm held still where the previous step
left it, against gravity), each saying whether the payload is carried during it: a pick-and-place carries its
load one way only. The cycle repeats, so its RMS torque is the one that heats a motor (the RMS of many cycles
is the RMS of one). A :class:`LoadCase` is one payload: a point mass (kg) with an optional offset of its centre
of mass from the tool point and an inertia of its own (tool frame); every load case is evaluated.

:func:`sample` turns a cycle into weighted samples: each motion segment on a uniform grid with composite
Simpson weights (so ∫f dt of a smooth f is exact to O(h⁴), and a segment's midpoint is a node), each dwell
one sample weighted by its duration (its torque is constant). For what runs through time (a winding's
temperature, a drive's bus energy) the samples are also **knots** of a piecewise-linear time function: a
segment's nodes at their times, joined by straight lines; a dwell two knots (its start and end) of its one
sample, so the value holds through it; where one segment ends and the next begins, two knots at the same time
(a step of zero length: the acceleration may jump there).

Duty-cycle files are JSON, see :data:`DUTY_FILE_HELP`; load-case files likewise, :data:`LOAD_CASES_HELP`.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armlab.files import check_name, is_json_number, json_number, read_json
from armlab.kinematics.quintic import Motion
from armlab.limits import allowed, check_range, real_number
from armlab.models.write_urdf import check_inertia
from armlab.values import cut, shown

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = [
    "DEFAULT_RATE",
    "DUTY_FILE_HELP",
    "LOAD_CASES_HELP",
    "MAX_LOAD_CASES",
    "CycleSamples",
    "DutyCycle",
    "Dwell",
    "LoadCase",
    "Move",
    "check_count",
    "load_cases_of",
    "read_duty_cycle",
    "read_load_cases",
    "sample",
]

#: Samples per second of motion (each segment gets at least 16 intervals).
DEFAULT_RATE = 500.0

#: The most load cases a sizing evaluates (``--payload`` and ``--load-cases`` together), checked before any is
#: read: every candidate pair is checked at every sample of every case (the working arrays grow with their product).
MAX_LOAD_CASES = 100

DUTY_FILE_HELP = """\
A duty-cycle file is JSON: {"deg": false, "start": [q1, ...], "steps": [STEP, ...]}; the cycle repeats.
  A STEP is a move, {"segments": [SEGMENT, ...], "payload": true}, its segments as in a segments
  file (armlab simulate --help; a first segment without "from" starts where the cycle is), or a
  dwell, {"dwell": 0.5, "payload": false} (s, held still against gravity where the cycle is).
  "payload": whether the load is carried during the step (default false). "start": where a cycle
  that begins with a dwell is (default: the first move's start). "deg": revolute values in degrees."""

LOAD_CASES_HELP = """\
A load-case file is JSON: [{"name": "box", "mass": 2.0, "offset": [0, 0, 0.05],
  "inertia": [[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]]}, ...]: mass (kg); optional offset
  (m) of its centre of mass from the tool point and inertia (kg·m², symmetric, about that centre), tool
  frame. At most 100 load cases (MAX_LOAD_CASES)."""


@dataclass(frozen=True)
class LoadCase:
    """A payload: ``mass`` (kg) at ``offset`` (m, ``(3,)``, tool frame) from the tool point, with ``inertia``
    (kg·m², ``(3, 3)``, symmetric, about its centre of mass, tool-frame axes; default none: a point mass); ``name``
    at most 100 characters without control characters (:func:`~armlab.files.check_name`). Each in its range of
    :data:`~armlab.limits.LIMITS` (payload, coordinate, inertia); ``ValueError`` otherwise."""

    mass: float
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: tuple[tuple[float, float, float], ...] = ((0.0, 0.0, 0.0),) * 3
    name: str = ""

    def __post_init__(self) -> None:
        check_name(self.name, "load case name")
        try:
            mass = float(self.mass)
        except (TypeError, ValueError):
            raise ValueError(f"load case mass {shown(self.mass)} is not allowed: a mass, "
                             f"{allowed('payload')}") from None
        mass = float(check_range(mass, f"load case {self.label} mass", key="payload"))
        try:
            offset = np.asarray(self.offset, dtype=float)
            inertia = np.asarray(self.inertia, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"load case {self.label}: offset {shown(self.offset)} and inertia {shown(self.inertia)}"
                             " must be 3 and 3×3 numbers") from None
        if offset.shape != (3,) or not np.all(np.isfinite(offset)):
            raise ValueError(f"load case {self.label} offset {cut(str(np.ravel(offset).tolist()))} is not allowed: "
                             "3 finite numbers (m, tool frame)")
        check_range(offset, f"load case {self.label} offset", key="coordinate")
        if inertia.shape != (3, 3):
            raise ValueError(f"load case {self.label} inertia has shape {inertia.shape}; expected 3×3 (kg·m²)")
        if np.all(np.isfinite(inertia)):
            check_range(inertia, f"load case {self.label} inertia", np.abs(inertia).max(), key="inertia")
        if not np.array_equal(inertia, inertia.T):  # exact: the user's own numbers, Ixy given twice
            raise ValueError(f"load case {self.label} inertia {cut(str(inertia.tolist()))} is not symmetric: "
                             "its element (i, j) is its element (j, i)")
        check_inertia(mass, inertia, f"load case {self.label}")
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "offset", tuple(float(v) for v in offset))
        object.__setattr__(self, "inertia", tuple(tuple(float(v) for v in row) for row in inertia))

    @property
    def label(self) -> str:
        """Its name, or its mass (``"2 kg"``)."""
        return self.name or f"{float(self.mass):g} kg"


def load_cases_of(payloads: float | Sequence[float] | LoadCase | Sequence[LoadCase]) -> tuple[LoadCase, ...]:
    """Load cases of point masses (kg, a number or a sequence) or :class:`LoadCase` objects; ``ValueError`` if none."""
    if isinstance(payloads, LoadCase):
        return (payloads,)
    if isinstance(payloads, list | tuple) and payloads and all(isinstance(p, LoadCase) for p in payloads):
        return tuple(payloads)
    masses = np.atleast_1d(np.asarray(payloads, dtype=float))
    if masses.ndim != 1 or masses.size == 0:
        raise ValueError(f"payloads {cut(str(np.ravel(masses).tolist()))} are not allowed: give at least one mass "
                         "(kg)")
    check_count(masses.size)
    return tuple(LoadCase(float(m)) for m in masses)


def check_count(cases: int) -> None:
    """``ValueError`` for more than :data:`MAX_LOAD_CASES` load cases (``cases`` of them)."""
    if cases > MAX_LOAD_CASES:
        raise ValueError(f"{cases:,} load cases, more than the {MAX_LOAD_CASES} allowed (armlab.sizing.duty."
                         "MAX_LOAD_CASES)")


@dataclass(frozen=True)
class Move:
    """A step of a cycle: ``motion``; ``payload`` whether the load is carried during it."""

    motion: Motion
    payload: bool = False


@dataclass(frozen=True)
class Dwell:
    """A step of a cycle: held still for ``duration`` s (≥ 0) where the cycle is; ``payload`` as :class:`Move`."""

    duration: float
    payload: bool = False

    def __post_init__(self) -> None:
        d = float(self.duration)
        if not (math.isfinite(d) and d >= 0):
            raise ValueError(f"dwell {self.duration!r} s is not allowed: a dwell is a finite duration ≥ 0 s")
        object.__setattr__(self, "duration", float(check_range(d, "dwell", key="dwell")))


@dataclass(frozen=True)
class DutyCycle:
    """Steps (:class:`Move`, :class:`Dwell`) repeated; ``start`` (n,) is where a cycle opening with a dwell is
    (default: its first move's start). ``ValueError`` without a move, or for a move of another joint count."""

    steps: tuple[Move | Dwell, ...]
    start: NDArray[np.float64] | None = None
    description: str = ""
    _n: int = field(init=False, repr=False, default=0)

    def __post_init__(self) -> None:
        steps = tuple(self.steps)
        moves = [s for s in steps if isinstance(s, Move)]
        if not moves:
            raise ValueError("a duty cycle needs at least one move")
        n = moves[0].motion.n
        for k, s in enumerate(steps, start=1):
            if not isinstance(s, Move | Dwell):
                raise ValueError(f"duty cycle step {k} is {type(s).__name__}: a step is a Move or a Dwell")
            if isinstance(s, Move) and s.motion.n != n:
                raise ValueError(f"duty cycle step {k} moves {s.motion.n} joints; step 1 moves {n}")
        start = moves[0].motion.segments[0].q_start if self.start is None else np.asarray(self.start, dtype=float)
        if start.shape != (n,):
            raise ValueError(f"duty cycle start has shape {start.shape}; expected {n} joint values")
        object.__setattr__(self, "steps", steps)
        object.__setattr__(self, "start", start)
        object.__setattr__(self, "_n", n)

    @property
    def n(self) -> int:
        """Number of joints."""
        return self._n

    @property
    def duration(self) -> float:
        """One cycle (s)."""
        return float(sum(s.motion.duration if isinstance(s, Move) else s.duration for s in self.steps))

    @classmethod
    def of(cls, motion: Motion, payload: bool = True) -> DutyCycle:
        """One motion repeated, carrying the load (``payload``) throughout."""
        return cls((Move(motion, payload),), description=motion.description)


@dataclass(frozen=True)
class CycleSamples:
    """A cycle's samples: q, q̇, q̈ ``(T, n)``; ``weight`` (s, ``(T,)``, Σ = the cycle's duration): ∫f dt ≈ Σ w f;
    ``carrying`` ``(T,)`` whether the payload is held; ``step`` ``(T,)`` the step (0-based) of each sample;
    ``time`` ``(T,)`` when each sample is (s from the cycle's start; a dwell's: its start); the knots (module
    docstring): ``knot_sample`` ``(K,)`` the sample of each knot and ``knot_time`` ``(K,)`` its time (s,
    non-decreasing, from 0 to the cycle's duration)."""

    q: NDArray[np.float64]
    qd: NDArray[np.float64]
    qdd: NDArray[np.float64]
    weight: NDArray[np.float64]
    carrying: NDArray[np.bool_]
    step: NDArray[np.intp]
    time: NDArray[np.float64]
    knot_sample: NDArray[np.intp]
    knot_time: NDArray[np.float64]

    @property
    def duration(self) -> float:
        """The cycle's duration (s): Σ weight."""
        return float(self.weight.sum())


def _simpson(tf: float, rate: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Nodes (s) on [0, tf] and composite Simpson weights, 4k intervals (k ≥ 4; ≥ ``rate``·tf)."""
    intervals = 4 * max(4, math.ceil(tf * rate / 4))
    t = np.linspace(0.0, tf, intervals + 1)
    w = np.full(intervals + 1, 2.0)
    w[1::2] = 4.0
    w[0] = w[-1] = 1.0
    return t, w * (tf / intervals) / 3


def sample(cycle: DutyCycle, rate: float = DEFAULT_RATE) -> CycleSamples:
    """The weighted samples of one cycle (see the module docstring); ``rate`` samples per second of motion."""
    rate = float(check_range(real_number(rate, "rate"), "rate", key="sample_rate"))  # bounded: memory grows with it
    parts: list[tuple[Any, ...]] = []
    where = np.asarray(cycle.start, dtype=float)
    now = 0.0
    for k, step in enumerate(cycle.steps):
        if isinstance(step, Dwell):
            if step.duration > 0:
                zero = np.zeros((1, cycle.n))
                parts.append((where[None, :], zero, zero, np.array([step.duration]), k, step.payload,
                              np.array([now]), np.array([now, now + step.duration]), np.zeros(2, dtype=np.intp)))
                now += step.duration
            continue
        for segment in step.motion.segments:
            t, w = _simpson(segment.duration, rate)
            q, qd, qdd = Motion((segment,)).evaluate(t)  # in the segment's own time: its end node is its own
            parts.append((q, qd, qdd, w, k, step.payload, now + t, now + t, np.arange(t.size)))
            now += segment.duration
        where = step.motion.segments[-1].q_end
    q, qd, qdd, w, time = (np.concatenate([p[i] for p in parts]) for i in (0, 1, 2, 3, 6))
    sizes = [p[3].size for p in parts]
    first = np.cumsum([0, *sizes[:-1]])  # each part's first sample
    knots = np.concatenate([p[8] + s for p, s in zip(parts, first, strict=True)])
    knot_time = np.concatenate([p[7] for p in parts])
    return CycleSamples(q, qd, qdd, w, np.repeat([bool(p[5]) for p in parts], sizes),
                        np.repeat([int(p[4]) for p in parts], sizes), time, knots, knot_time)


def _flag(raw: Any, where: str) -> bool:
    if not isinstance(raw, bool):
        raise ValueError(f"{where} \"payload\" = {json.dumps(raw)} must be true or false")
    return raw


def read_duty_cycle(arm: Arm, path: str | Path) -> DutyCycle:
    """The duty cycle in a file (JSON, :data:`DUTY_FILE_HELP`), every move's ends checked against the limits."""
    # lazy: armlab --help loads armlab.sizing.duty but not the IK (start-up time)
    from armlab.planning.motions import MAX_SEGMENTS, parse_segments

    path = Path(path)
    name = f"--duty-cycle {path.name}"
    data = read_json(path, "--duty-cycle")
    if not isinstance(data, dict) or not isinstance(data.get("steps"), list) or not data["steps"]:
        raise ValueError(f"{name}: expected an object with a non-empty list \"steps\"")
    parts = sum(len(spec["segments"]) if isinstance(spec, dict) and isinstance(spec.get("segments"), list) else 1
                for spec in data["steps"])
    if parts > MAX_SEGMENTS:
        raise ValueError(f"{name}: {parts:,} segments and dwells, more than the {MAX_SEGMENTS} allowed "
                         "(armlab.planning.motions.MAX_SEGMENTS)")
    unknown = sorted(set(data) - {"deg", "start", "steps"})
    if unknown:
        raise ValueError(f"{name}: unknown key(s) {cut(', '.join(unknown))}; allowed: deg, start, steps")
    deg = data.get("deg", False)
    if not isinstance(deg, bool):
        raise ValueError(f"{name}: \"deg\" = {json.dumps(deg)} must be true or false")
    start = None
    if "start" in data:
        raw = data["start"]
        if not isinstance(raw, list) or len(raw) != arm.n or not all(is_json_number(v) for v in raw):
            raise ValueError(f"{name}: \"start\" = {json.dumps(raw)} must be a list of {arm.n} numbers")
        start = np.array(raw, dtype=float)
        start = np.where(arm.revolute, np.radians(start), start) if deg else start
        arm.check_q(start, "start", deg)
    steps: list[Move | Dwell] = []
    where_now = start
    for k, spec in enumerate(data["steps"], start=1):
        where = f"{name} step {k}"
        if not isinstance(spec, dict) or ("dwell" in spec) == ("segments" in spec):
            raise ValueError(f"{where}: expected an object with \"segments\" (a move) or \"dwell\" (s)")
        unknown = sorted(set(spec) - {"dwell", "segments", "payload", "label"})
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {cut(', '.join(unknown))}; allowed: dwell, segments, payload, "
                             "label")
        payload = _flag(spec.get("payload", False), where)
        if "dwell" in spec:
            steps.append(Dwell(json_number(spec["dwell"], f"{where} dwell"), payload))
            continue
        motion = parse_segments(arm, spec["segments"], deg, where, str(spec.get("label", f"step {k}")), where_now)
        steps.append(Move(motion, payload))
        where_now = motion.segments[-1].q_end
    if start is None and isinstance(steps[0], Dwell):
        raise ValueError(f"{name}: a cycle that begins with a dwell needs \"start\" (where the arm is held)")
    return DutyCycle(tuple(steps), start, f"duty cycle {path.name}")


def read_load_cases(path: str | Path) -> tuple[LoadCase, ...]:
    """The load cases in a file (JSON, :data:`LOAD_CASES_HELP`)."""
    path = Path(path)
    name = f"--load-cases {path.name}"
    data = read_json(path, "--load-cases")
    if not isinstance(data, list) or not data:
        raise ValueError(f"{name}: expected a non-empty list of load cases")
    try:
        check_count(len(data))
    except ValueError as error:
        raise ValueError(f"{name}: {error}") from None
    cases = []
    for k, spec in enumerate(data, start=1):
        where = f"{name} case {k}"
        if not isinstance(spec, dict) or "mass" not in spec:
            raise ValueError(f"{where}: expected an object with \"mass\" (kg)")
        unknown = sorted(set(spec) - {"name", "mass", "offset", "inertia"})
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {cut(', '.join(unknown))}; allowed: name, mass, offset, "
                             "inertia")
        offset = spec.get("offset", [0.0] * 3)
        if not (isinstance(offset, list) and len(offset) == 3 and all(is_json_number(v) for v in offset)):
            raise ValueError(f"{where}: \"offset\" = {cut(json.dumps(offset))} must be a list of 3 numbers (m)")
        inertia = spec.get("inertia", [[0.0] * 3] * 3)
        if not (isinstance(inertia, list) and len(inertia) == 3 and all(
                isinstance(row, list) and len(row) == 3 and all(is_json_number(v) for v in row) for row in inertia)):
            raise ValueError(f"{where}: \"inertia\" = {cut(json.dumps(inertia))} must be a list of 3 rows of 3 "
                             "numbers (kg·m²)")
        cases.append(LoadCase(json_number(spec["mass"], f"{where} mass"), tuple(offset),
                              tuple(tuple(row) for row in inertia), check_name(spec.get("name", ""), f"{where} name")))
    return tuple(cases)
