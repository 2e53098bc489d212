"""The motions ``armlab simulate`` runs: each paper's own, a quintic between two configurations, or a file.

Paper motions (:func:`paper_motion`):

* ``rr`` — paper 000 Fig. 3/5/7: θ1 −38° → 62°, θ2 98° → 68°, rest to rest in t_f = 2 s (the t_f
  that reproduces the paper's coefficients a1 … b3).
* ``rr``, path ``abcd`` — paper 000 Figs. 8–10: A → B → C → D → A through the points of Table 1,
  each segment a rest-to-rest quintic between the exact inverse-kinematics angles on the branch
  Table 2 uses at each end (Table 2 rounds 73.7398° to 74°). The paper gives no segment time:
  2 s each is chosen (Fig. 3's t_f). Table 2 leaves C and A on another branch than it reaches
  them on, and D at θ2 = −180° after reaching it at +180° (the same pose, but the joint would
  have to unwind), so the motion is three runs: A–B–C, C–D, D–A (see :meth:`Motion.runs`).
* ``rrrr`` — paper 000 Figs. 18–19: constant rates ω = (7, 0.05, 0.05, 0.05) rad/s from q = 0
  for 15 s.
* ``arm4r`` — paper 001 §3: from (2, 0, 0) to (1, 1, 1.4) in 2 s, the tool pitch kept at the
  start's ("the state is the same with the original state"), both ends by the paper's inverse
  kinematics, the solution nearest the start (the paper's rule).
* ``r2t``, ``urm6`` — their papers are kinematic only; a demo motion each (documented below).

Segment files (:func:`read_segments`) are JSON, see :data:`SEGMENTS_FILE_HELP`.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.files import is_json_number, json_number, read_json
from armlab.kinematics.quintic import ConstantRate, Motion, QuinticSegment, Segment, check_duration

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = [
    "ABCD_POINTS",
    "ABCD_SEGMENTS",
    "PATHS",
    "SEGMENTS_FILE_HELP",
    "abcd_motion",
    "paper_motion",
    "point_to_joints",
    "quintic_motion",
    "read_segments",
]

#: Paper 000, Table 1: the points A, B, C, D (m).
ABCD_POINTS: dict[str, tuple[float, float]] = {"A": (0.4, -0.3), "B": (0.7, 0.0), "C": (0.4, 0.3), "D": (0.1, 0.0)}
#: Paper 000, Table 2's segments as (start point, its IK branch, end point, its IK branch); branch 0 has
#: θ2 ≥ 0, branch 1 θ2 ≤ 0 (:func:`armlab.kinematics.ik.rr_ik`). ``None``: start where the previous ends.
ABCD_SEGMENTS: tuple[tuple[str, int | None, str, int], ...] = (
    ("A", 0, "B", 0), ("B", None, "C", 1), ("C", 0, "D", 0), ("D", 1, "A", 1)
)
#: Named multi-segment paths (``--path``), by arm.
PATHS: dict[str, tuple[str, ...]] = {"rr": ("abcd",)}

SEGMENTS_FILE_HELP = """\
A segments file is JSON: {"deg": false, "segments": [SEGMENT, ...]}. Each SEGMENT has "tf" (s) and
  a start: "from": [q1, ...] or "from_point": [x, y(, z)], or neither to start where the previous
           segment ends (the first segment then needs one);
  an end:  "to": [q1, ...] or "to_point": [x, y(, z)] (a quintic, rest to rest), or "rate": [w1, ...]
           (constant rates, q = q0 + w t);
  options: "label"; for points "from_branch"/"to_branch" (rr only: 0 for θ2 ≥ 0, 1 for θ2 ≤ 0),
           "from_pitch"/"to_pitch" (arm4r: the tool pitch θ2+θ3+θ4). Without a branch the IK
           solution nearest the previous joints is taken.
With "deg": true, revolute joint values and rates are in degrees (prismatic ones stay m)."""


def quintic_motion(arm: Arm, q0: ArrayLike, qf: ArrayLike, tf: float, description: str = "") -> Motion:
    """One rest-to-rest quintic of ``arm`` from ``q0`` to ``qf`` in ``tf`` s, both ends checked against the limits."""
    motion = Motion((QuinticSegment(q0, qf, tf),), description or "rest-to-rest quintic")
    motion.check_limits(arm)
    return motion


def point_to_joints(
    arm: Arm,
    point: ArrayLike,
    branch: int | None = None,
    pitch: float | None = None,
    near: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """Joint values reaching ``point``: rr's IK ``branch`` (0: θ2 ≥ 0, 1: θ2 ≤ 0) if given, else the
    solution of :func:`armlab.kinematics.ik.solve` nearest ``near`` (arm4r: with tool ``pitch``)."""
    from armlab.kinematics.ik import fit_limits, planar_target, rr_ik, solve

    if branch is None:
        return solve(arm, point, pitch=pitch, near=near)[0]
    if arm.name != "rr" or branch not in (0, 1):
        raise ValueError(f"IK branch {branch!r} is not allowed: branches are 0 (θ2 ≥ 0) and 1 (θ2 ≤ 0) of the rr arm; "
                         "for other arms give no branch (the solution nearest the previous joints is taken)")
    p = planar_target(point)
    q = rr_ik(p, arm.parameters["L1"], arm.parameters["L2"])[branch]
    fitted, violations = fit_limits(arm, q, near=q)
    if violations[0] is not None:
        raise ValueError(f"point {p.tolist()} on IK branch {branch} is outside {arm.name}'s joint limits")
    return fitted[0]


def abcd_motion(arm: Arm, tf: float = 2.0) -> Motion:
    """Paper 000's A → B → C → D → A (Tables 1–2, Figs. 8–10), ``tf`` seconds per segment."""
    tf = check_duration(tf)
    segments: list[Segment] = []
    for start, start_branch, end, end_branch in ABCD_SEGMENTS:
        q0 = segments[-1].q_end if start_branch is None else point_to_joints(arm, ABCD_POINTS[start], start_branch)
        qf = point_to_joints(arm, ABCD_POINTS[end], end_branch)
        segments.append(QuinticSegment(q0, qf, tf, f"{start}-{end}"))
    motion = Motion(
        tuple(segments),
        f"paper 000 Figs. 8-10: A-B-C-D-A through Table 1's points, Table 2's IK branches, {tf:g} s per segment",
        {"joints": "000 Fig. 9", "torques": "000 Fig. 10", "path": "000 Fig. 8"},
    )
    motion.check_limits(arm)
    return motion


def _demo_r2t(arm: Arm, tf: float) -> Motion:
    lo, hi = arm.limit_arrays()
    q0 = np.array([-np.pi / 4, lo[1] + 0.2 * (hi[1] - lo[1]), lo[2] + 0.1 * (hi[2] - lo[2])])
    qf = np.array([np.pi / 4, lo[1] + 0.8 * (hi[1] - lo[1]), lo[2] + 0.9 * (hi[2] - lo[2])])
    return Motion((QuinticSegment(q0, qf, tf, "transfer"),),
                  f"demo (paper 003 has no motion): a part transfer, the column turning -45° → +45° while the "
                  f"carriage rises from 20 % to 80 % of its stroke and the arm extends from 10 % to 90 % of its "
                  f"stroke, rest to rest in {tf:g} s")


def _demo_urm6(arm: Arm, tf: float) -> Motion:
    from armlab.models.urm6 import TABLE1_PHI_DEG

    return Motion((QuinticSegment(np.zeros(arm.n), np.radians(TABLE1_PHI_DEG), tf, "home-Table1"),),
                  f"demo (paper 004 is kinematic only): from φ = 0 to Table 1's φ1…φ6 = "
                  f"{', '.join(f'{v:g}' for v in TABLE1_PHI_DEG)}°, rest to rest in {tf:g} s")


def paper_motion(arm: Arm, path: str | None = None, tf: float | None = None) -> Motion:
    """The motion ``armlab simulate ARM`` runs without motion options (see the module docstring).

    ``path`` names a multi-segment path (rr: ``"abcd"``); ``tf`` overrides the duration (per
    segment for a path; the whole run for rrrr's constant rates).
    """
    from armlab.models import ARMS

    if tf is not None:
        tf = check_duration(tf)
    if arm.name not in ARMS or arm.paper != ARMS[arm.name].PAPER:
        raise ValueError(f"{arm.name} has no paper motion; give --from and --to (and --tf), or --segments")
    if path is not None:
        if path not in PATHS.get(arm.name, ()):
            allowed = ", ".join(f"{a}: {', '.join(p)}" for a, p in PATHS.items())
            raise ValueError(f"path {path!r} is not available for {arm.name}; paths: {allowed}")
        return abcd_motion(arm, 2.0 if tf is None else tf)
    if arm.name == "rr":
        tf = 2.0 if tf is None else tf
        motion = Motion(
            (QuinticSegment(np.radians([-38.0, 98.0]), np.radians([62.0, 68.0]), tf, "Fig3"),),
            f"paper 000 Figs. 3, 5, 7: θ1 -38° → 62°, θ2 98° → 68°, rest to rest in {tf:g} s",
            {"joints": "000 Fig. 5", "torques": "000 Fig. 7", "path": "000 Fig. 3"},
        )
    elif arm.name == "rrrr":
        tf = 15.0 if tf is None else tf
        motion = Motion(
            (ConstantRate(np.zeros(4), np.array([7.0, 0.05, 0.05, 0.05]), tf, "constant-rate"),),
            f"paper 000 Figs. 18-19: q = ω t, ω = (7, 0.05, 0.05, 0.05) rad/s, for {tf:g} s",
            {"path": "000 Figs. 18-19"},
        )
    elif arm.name == "arm4r":
        tf = 2.0 if tf is None else tf
        q0 = point_to_joints(arm, (2.0, 0.0, 0.0), pitch=0.0)
        pitch = float(q0[1] + q0[2] + q0[3])
        qf = point_to_joints(arm, (1.0, 1.0, 1.4), pitch=pitch, near=q0)
        motion = Motion(
            (QuinticSegment(q0, qf, tf, "(2,0,0)-(1,1,1.4)"),),
            f"paper 001 §3: tool from (2, 0, 0) to (1, 1, 1.4) m with the start's pitch, IK solution nearest "
            f"the start, rest to rest in {tf:g} s",
            {"joints": "001 Figs. 4-6", "path": "001 Fig. 7"},
        )
    elif arm.name == "r2t":
        motion = _demo_r2t(arm, 3.0 if tf is None else tf)
    else:
        motion = _demo_urm6(arm, 4.0 if tf is None else tf)
    motion.check_limits(arm)
    return motion


def _numbers(raw: Any, name: str) -> NDArray[np.float64]:
    """A JSON list of finite numbers as an array; ``ValueError`` naming ``name`` otherwise."""
    if not isinstance(raw, list) or not raw or not all(is_json_number(v) for v in raw):
        raise ValueError(f"{name} = {json.dumps(raw)} must be a list of numbers")
    values = np.array(raw, dtype=float)
    if not np.all(np.isfinite(values)):
        raise ValueError(f"{name} = {json.dumps(raw)} has a value that is not a finite number")
    return values


def _values(arm: Arm, raw: Any, deg: bool, name: str) -> NDArray[np.float64]:
    values = _numbers(raw, name)
    if values.shape != (arm.n,):
        raise ValueError(f"{name} has {values.size} values; {arm.name} has {arm.n} joints")
    return np.where(arm.revolute, np.radians(values), values) if deg else values


def _end(arm: Arm, spec: Mapping[str, Any], which: str, deg: bool, near: NDArray | None, where: str) -> NDArray | None:
    joints, point = spec.get(which), spec.get(f"{which}_point")
    if joints is not None and point is not None:
        raise ValueError(f"{where}: give {which!r} or {which + '_point'!r}, not both")
    if joints is not None:
        return _values(arm, joints, deg, f"{where} {which}")
    if point is None:
        return None
    xyz = _numbers(point, f"{where} {which}_point")
    pitch = spec.get(f"{which}_pitch")
    if pitch is not None:
        pitch = json_number(pitch, f"{where} {which}_pitch")
        pitch = float(np.radians(pitch)) if deg else pitch
    branch = spec.get(f"{which}_branch")
    if branch is not None and not (is_json_number(branch) and isinstance(branch, int) and branch in (0, 1)):
        raise ValueError(f"{where} {which}_branch = {json.dumps(branch)} is not allowed: 0 (θ2 ≥ 0) or 1 (θ2 ≤ 0)")
    try:
        return point_to_joints(arm, xyz, branch, pitch, near)
    except ValueError as error:
        raise ValueError(f"{where} {which}_point: {error}") from None


def read_segments(arm: Arm, path: str | Path) -> Motion:
    """The motion in a segments file (JSON, :data:`SEGMENTS_FILE_HELP`), every end checked against the limits."""
    path = Path(path)
    data = read_json(path, "--segments")
    if not isinstance(data, dict) or not isinstance(data.get("segments"), list) or not data["segments"]:
        raise ValueError(f"--segments {path}: expected an object with a non-empty list \"segments\"")
    deg = data.get("deg", False)
    if not isinstance(deg, bool):
        raise ValueError(f"--segments {path}: \"deg\" = {json.dumps(deg)} must be true or false")
    segments: list[Segment] = []
    known = {"label", "tf", "from", "from_point", "from_branch", "from_pitch", "to", "to_point", "to_branch",
             "to_pitch", "rate"}
    for k, spec in enumerate(data["segments"], start=1):
        where = f"--segments {path.name} segment {k}"
        if not isinstance(spec, dict):
            raise ValueError(f"{where}: expected an object, got {spec!r}")
        unknown = sorted(set(spec) - known)
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {', '.join(unknown)}; allowed: {', '.join(sorted(known))}")
        if "tf" not in spec:
            raise ValueError(f"{where}: needs \"tf\" (s)")
        label = str(spec.get("label", k))
        previous = segments[-1].q_end if segments else None
        q0 = _end(arm, spec, "from", deg, previous, where)
        if q0 is None:
            if previous is None:
                raise ValueError(f"{where}: the first segment needs \"from\" or \"from_point\"")
            q0 = previous
        qf = _end(arm, spec, "to", deg, q0, where)
        rate = spec.get("rate")
        if (qf is None) == (rate is None):
            raise ValueError(f"{where}: give exactly one of \"to\", \"to_point\" or \"rate\"")
        json_number(spec["tf"], f"{where} tf")  # a JSON number: not "2", true or null
        tf = check_duration(spec["tf"], f"{where} tf")
        if rate is not None:
            segments.append(ConstantRate(q0, _values(arm, rate, deg, f"{where} rate"), tf, label))
        else:
            segments.append(QuinticSegment(q0, qf, tf, label))
    motion = Motion(tuple(segments), f"segments from {path.name}")
    motion.check_limits(arm)
    return motion
