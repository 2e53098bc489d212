"""The motions ``armlab simulate`` runs: each paper's own, a quintic between two configurations, or a file.

Paper motions (:func:`paper_motion`) are the arms' own: each paper arm's module gives its arm its
paper motion and named paths (``Arm.motion``, ``Arm.paths``; e.g. :func:`armlab.models.rr.fig3_motion`,
path ``abcd`` :func:`armlab.models.rr.abcd_motion`, :func:`armlab.models.arm4r.section3_motion`).

Segment files (:func:`read_segments`) are JSON, see :data:`SEGMENTS_FILE_HELP`.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.files import is_json_number, json_number, read_json
from armlab.kinematics.ik import solve, solve_branch
from armlab.kinematics.quintic import ConstantRate, Motion, QuinticSegment, Segment, check_duration
from armlab.models import paper_arms
from armlab.values import cut

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = [
    "SEGMENTS_FILE_HELP",
    "paper_motion",
    "point_to_joints",
    "quintic_motion",
    "read_segments",
]

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
    # the segment checks and converts q0, qf (its messages name a bad value): its fields are arrays once made
    start, end = cast(NDArray[np.float64], q0), cast(NDArray[np.float64], qf)
    motion = Motion((QuinticSegment(start, end, tf),), description or "rest-to-rest quintic")
    motion.check_limits(arm)
    return motion


def point_to_joints(
    arm: Arm,
    point: ArrayLike,
    branch: int | None = None,
    pitch: float | None = None,
    near: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """Joint values reaching ``point``: the closed form's IK ``branch`` if given (rr: 0 θ2 ≥ 0, 1 θ2 ≤ 0;
    :func:`armlab.kinematics.ik.solve_branch`), else the solution of :func:`armlab.kinematics.ik.solve`
    nearest ``near`` (arm4r: with tool ``pitch``)."""
    if branch is None:
        return solve(arm, point, pitch=pitch, near=near)[0]
    return solve_branch(arm, point, branch)


def paper_motion(arm: Arm, path: str | None = None, tf: float | None = None) -> Motion:
    """The motion ``armlab simulate ARM`` runs without motion options: the arm's own (``arm.motion``).

    ``path`` names a multi-segment path of the arm's (``arm.paths``; rr: ``"abcd"``); ``tf`` overrides
    the duration (per segment for a path; the whole run for rrrr's constant rates). ``ValueError`` for an
    arm without a paper motion (a user's) or a path it does not have.
    """
    if tf is not None:
        tf = check_duration(tf)
    if arm.motion is None:
        raise ValueError(f"{arm.name} has no paper motion; give --from and --to (and --tf), or --segments")
    if path is None:
        return arm.motion(arm, tf)
    if path not in arm.paths:
        allowed = ", ".join(f"{other.name}: {', '.join(other.paths)}" for other in paper_arms() if other.paths)
        raise ValueError(f"path {path!r} is not available for {arm.name}; paths: {allowed}")
    return arm.paths[path](arm, tf)


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
            raise ValueError(f"{where}: unknown key(s) {cut(', '.join(unknown))}; allowed: "
                             f"{', '.join(sorted(known))}")
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
        if qf is None:  # then "rate" is given (checked above)
            segments.append(ConstantRate(q0, _values(arm, rate, deg, f"{where} rate"), tf, label))
        else:
            segments.append(QuinticSegment(q0, qf, tf, label))
    motion = Motion(tuple(segments), f"segments from {path.name}")
    motion.check_limits(arm)
    return motion
