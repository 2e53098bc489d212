"""The motions ``armlab simulate`` runs: each paper's own, a quintic between two configurations, or a file.

Paper motions (:func:`paper_motion`) are the arms' own: each paper arm's module gives its arm its
paper motion and named paths (``Arm.motion``, ``Arm.paths``; e.g. :func:`armlab.models.rr.fig3_motion`,
path ``abcd`` :func:`armlab.models.rr.abcd_motion`, :func:`armlab.models.arm4r.section3_motion`).

Segment files (:func:`read_segments`) are JSON, see :data:`SEGMENTS_FILE_HELP`.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.files import is_json_number, json_number, read_json
from armlab.kinematics.cartesian import (
    DEFAULT_SAMPLES,
    arc_path,
    arc_through,
    line_path,
    path_profile,
    tool_joint_path,
    tool_motion_along,
    tool_path_text,
)
from armlab.kinematics.ik import solve, solve_branch
from armlab.kinematics.profiles import spline, trapezoidal
from armlab.kinematics.quintic import ConstantRate, Motion, PolynomialSegment, QuinticSegment, Segment, check_duration
from armlab.limits import per_joint
from armlab.models import paper_arms
from armlab.values import cut

if TYPE_CHECKING:
    from pydrake.trajectories import Trajectory

    from armlab.kinematics.cartesian import ToolPath
    from armlab.models.arm import Arm

__all__ = [
    "MAX_SEGMENTS",
    "SEGMENTS_FILE_HELP",
    "paper_motion",
    "parse_segments",
    "point_to_joints",
    "quintic_motion",
    "read_segments",
]

#: The most segments a segments file (or a duty cycle, all its moves together) may list: checked before any is read.
#: The run's checks, summary and figures go through every segment (a label per segment on the figures), so their
#: time grows faster than the count; 200 segments run in seconds.
MAX_SEGMENTS = 200

SEGMENTS_FILE_HELP = """\
A segments file is JSON: {"deg": false, "segments": [SEGMENT, ...]}. Each SEGMENT has "tf" (s) and
  a start: "from": [q1, ...] or "from_point": [x, y(, z)], or neither to start where the previous
           segment ends (the first segment then needs one);
  an end:  "to": [q1, ...] or "to_point": [x, y(, z)] (a quintic, rest to rest), or "rate": [w1, ...]
           (constant rates, q = q0 + w t);
  or a tool path from the start's tool point: "line_to": [x, y(, z)] (a straight line),
           "arc_through": [[x, y(, z)], [x, y(, z)]] (the circle through the start, a via point and
           the end), or "arc_centre", "arc_axis" and "arc_angle" (rad; deg with "deg"), by IK along it
           ("samples", default 201) on the start's branch;
  options: "label"; for points "from_branch"/"to_branch" (rr only: 0 for θ2 ≥ 0, 1 for θ2 ≤ 0),
           "from_pitch"/"to_pitch" (arm4r: the tool pitch θ2+θ3+θ4). Without a branch the IK
           solution nearest the previous joints is taken. "profile": "trapezoid" makes a "to"
           segment a synchronised trapezoid (with "tf", or "velocity" and "acceleration" per joint
           instead), and times a tool path ("minimum-jerk" by default, "cubic", or "trapezoid" with
           "tf", or the tool's "speed" m/s and "acceleration" m/s² instead). "through": [[q1, ...],
           ...] passes those joint values without stopping (quintics, or "degree": 3 cubics; via
           velocities by Craig's rule; "tf" per piece or one for all). "profile": "fastest" times a
           "to" segment (the straight joint line) or a tool path as fast as the limits allow, rest to
           rest (Drake's Toppra, as armlab plan --fastest), without "tf": the joint limits are the
           arm's file's and its drive train's, or "velocity", "acceleration" and "effort" (one, or
           one per joint); the payload and gravity are the run's (--payload, --gravity).
  a planned motion: "to": [q1, ...] with "plan": {"scene": FILE, "clearance": m, "seed": 0, "budget": s}
           (every key optional; the scene file relative to the segments file): a collision-free path
           around the scene's obstacles and the arm itself, timed as fast as the limits allow (as
           armlab plan ARM to; "velocity", "acceleration", "effort" as for "fastest"), no "tf".
With "deg": true, revolute joint values and rates are in degrees (prismatic ones stay m).
At most 200 segments (MAX_SEGMENTS) in a file."""


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


#: The keys that make a segment a tool path.
_TOOL_PATH_KEYS = ("line_to", "arc_through", "arc_centre", "arc_axis", "arc_angle")


def _rates(arm: Arm, spec: Mapping[str, Any], key: str, deg: bool, where: str) -> NDArray[np.float64] | None:
    """A joint rate or limit ``key`` ("velocity", "acceleration", "effort"): one number or one per joint (deg with
    deg)."""
    raw = spec.get(key)
    if raw is None:
        return None
    values = per_joint(_numbers(raw if isinstance(raw, list) else [raw], f"{where} {key}"), arm.n, f"{where} {key}")
    return np.where(arm.revolute, np.radians(values), values) if deg else values


def _tool_path(arm: Arm, spec: Mapping[str, Any], q0: NDArray[np.float64], deg: bool, where: str) -> ToolPath:
    """The line or arc of a segment from the tool's point at ``q0`` (:mod:`armlab.kinematics.cartesian`; a 6-joint
    arm's tool pose, whose rotation a line to a point holds)."""
    start = arm.forward(q0).tool
    point = start[:3, 3] if arm.n < 6 else start
    kinds = [key for key in ("line_to", "arc_through", "arc_centre") if key in spec]
    if len(kinds) != 1 or any(key in spec for key in ("to", "to_point", "rate")):
        raise ValueError(f"{where}: give one tool path (\"line_to\", \"arc_through\" or \"arc_centre\" with "
                         "\"arc_axis\" and \"arc_angle\"), and no \"to\", \"to_point\" or \"rate\"")
    try:
        if kinds[0] == "line_to":
            return line_path(point, _numbers(spec["line_to"], f"{where} line_to"))
        if kinds[0] == "arc_through":
            raw = spec["arc_through"]
            if not isinstance(raw, list) or len(raw) != 2:
                raise ValueError(f"arc_through = {json.dumps(raw)} must be two points: a via point and the end")
            return arc_through(point, *(_numbers(p, f"{where} arc_through") for p in raw))
        if "arc_axis" not in spec or "arc_angle" not in spec:
            raise ValueError("an arc about a centre needs \"arc_axis\" and \"arc_angle\"")
        angle = json_number(spec["arc_angle"], f"{where} arc_angle")
        return arc_path(_numbers(spec["arc_centre"], f"{where} arc_centre"),
                        _numbers(spec["arc_axis"], f"{where} arc_axis"), point,
                        float(np.radians(angle)) if deg else angle)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None


def _along(arm: Arm, spec: Mapping[str, Any], path: ToolPath, q0: NDArray[np.float64], deg: bool, label: str,
           where: str, load: _Load) -> Motion:
    """The tool along ``path`` from ``q0``: IK along it, timed by the segment's profile, or as fast as the limits
    allow with ``load`` (``"profile": "fastest"``, :func:`_fastest` of the untimed joint path)."""
    samples = spec.get("samples", DEFAULT_SAMPLES)
    try:
        if spec.get("profile") == "fastest":
            joints = tool_joint_path(arm, path, q0, samples=samples)
        else:
            numbers = {key: None if spec.get(key) is None else json_number(spec[key], f"{where} {key}")
                       for key in ("tf", "speed", "acceleration")}
            profile = path_profile(path, str(spec.get("profile", "minimum-jerk")), numbers["tf"], numbers["speed"],
                                   numbers["acceleration"])
            return tool_motion_along(arm, path, profile=profile, q0=q0, samples=samples, label=label)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    return _fastest(arm, spec, joints, deg, label, where, tool_path_text(arm, path), load)


@dataclass(frozen=True)
class _Load:
    """What a run carries that a time-optimal segment is timed with, as the run's plant has it: the ``payload``
    (kg, at the tool) and ``gravity`` (``None``: the arm's; :class:`~armlab.models.plant.PlantOptions`)."""

    payload: float = 0.0
    gravity: str | ArrayLike | None = None


def _fastest(arm: Arm, spec: Mapping[str, Any], path: Trajectory, deg: bool, label: str, where: str,
             what: str, load: _Load) -> Motion:
    """The joint path ``path`` q(s) (``what`` it is, for the description) timed as fast as the limits allow
    (:func:`armlab.planning.timing.fastest`) with the ``load`` the run carries, the segment's own joint limits
    where it gives them."""
    # lazy: Drake's Toppra, only for a time-optimal segment
    from armlab.kinematics.quintic import TrajectorySegment
    from armlab.planning.timing import fastest

    if "tf" in spec:
        raise ValueError(f"{where}: a \"fastest\" segment takes no \"tf\": its duration is the least the limits "
                         "allow")
    velocity, acceleration, effort = (_rates(arm, spec, key, deg and key != "effort", where)
                                      for key in ("velocity", "acceleration", "effort"))
    try:
        best = fastest(arm, path, velocity, acceleration, effort, gravity=load.gravity, payload=load.payload)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    timing = cast(TrajectorySegment, best.motion.segments[0])  # fastest's motion: one trajectory segment
    return Motion((TrajectorySegment(timing.trajectory, label, timing.limits),),
                  f"{what}, time-optimal timing (Toppra)")


def _through(arm: Arm, spec: Mapping[str, Any], q0: NDArray[np.float64], deg: bool, label: str,
             where: str) -> Motion:
    """Splines from ``q0`` through the joint values ``"through"`` without stopping (:func:`armlab.kinematics.profiles
    .spline`: "degree" 5, quintics, or 3, cubics; "tf" one duration per piece or one for all)."""
    raw = spec["through"]
    if not isinstance(raw, list) or not raw:
        raise ValueError(f"{where} through = {json.dumps(raw)} must be a list of joint-value lists")
    points = [q0, *(_values(arm, q, deg, f"{where} through point {k + 1}") for k, q in enumerate(raw))]
    if "tf" not in spec:
        raise ValueError(f"{where}: needs \"tf\" (s): one duration per piece, or one for all")
    tf = spec["tf"]
    durations = ([json_number(t, f"{where} tf") for t in tf] if isinstance(tf, list)
                 else json_number(tf, f"{where} tf"))
    degree = spec.get("degree", 5)
    try:
        motion = spline(arm, np.array(points), durations, degree)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    return Motion(tuple(PolynomialSegment(c, s.duration, f"{label}.{k + 1}")
                        for k, (c, s) in enumerate(zip(motion.coefficients(), motion.segments, strict=True))),
                  motion.description)


def read_segments(arm: Arm, path: str | Path, payload: float = 0.0, gravity: str | ArrayLike | None = None) -> Motion:
    """The motion in a segments file (JSON, :data:`SEGMENTS_FILE_HELP`), every end checked against the limits; its
    ``"fastest"`` segments timed with the ``payload`` (kg) and ``gravity`` the run will have (as
    :class:`~armlab.models.plant.PlantOptions` takes them; ``None``: the arm's)."""
    path = Path(path)
    data = read_json(path, "--segments")
    if not isinstance(data, dict) or not isinstance(data.get("segments"), list) or not data["segments"]:
        raise ValueError(f"--segments {path}: expected an object with a non-empty list \"segments\"")
    unknown = sorted(set(data) - {"deg", "segments"})
    if unknown:
        raise ValueError(f"--segments {path}: unknown key(s) {cut(', '.join(unknown))}; allowed: deg, segments")
    deg = data.get("deg", False)
    if not isinstance(deg, bool):
        raise ValueError(f"--segments {path}: \"deg\" = {json.dumps(deg)} must be true or false")
    return parse_segments(arm, data["segments"], deg, f"--segments {path.name}", f"segments from {path.name}",
                          payload=payload, gravity=gravity, folder=path.parent)


#: The keys of a segment's "plan" object (:func:`_planned`).
_PLAN_KEYS = ("scene", "clearance", "seed", "budget")


def _planned(arm: Arm, spec: Mapping[str, Any], q0: NDArray[np.float64], qf: NDArray[np.float64], deg: bool,
             label: str, where: str, folder: Path | None) -> Motion:
    """A "plan" segment: :func:`armlab.planning.planner.plan_path` from ``q0`` to ``qf`` around its scene (a file
    relative to ``folder``, the segments file's), timed as fast as the limits allow."""
    # lazy: the planner loads Drake's SceneGraph and Toppra, only for a planned segment
    from armlab.kinematics.quintic import TrajectorySegment
    from armlab.planning.planner import plan_path

    options = spec["plan"]
    if options is True:
        options = {}
    if not isinstance(options, dict) or set(options) - set(_PLAN_KEYS):
        raise ValueError(f"{where}: \"plan\" = {cut(json.dumps(options))} is not allowed: true, or an object of "
                         f"{', '.join(_PLAN_KEYS)}")
    if "tf" in spec:
        raise ValueError(f"{where}: a \"plan\" segment takes no \"tf\": its duration is the least the limits allow")
    scene = options.get("scene")
    if scene is not None and not isinstance(scene, str):
        raise ValueError(f"{where}: plan scene = {json.dumps(scene)} must be a scene file's name")
    numbers = {key: json_number(options[key], f"{where} plan {key}") for key in ("clearance", "budget")
               if key in options}
    seed = options.get("seed", 0)
    if not (is_json_number(seed) and isinstance(seed, int)):
        raise ValueError(f"{where}: plan seed = {json.dumps(seed)} must be a whole number")
    velocity, acceleration, effort = (_rates(arm, spec, key, deg and key != "effort", where)
                                      for key in ("velocity", "acceleration", "effort"))
    try:
        plan = plan_path(arm, q0, qf, None if scene is None else (folder or Path()) / scene,
                         numbers.get("clearance", 0.0), seed, numbers.get("budget", 5.0), velocity=velocity,
                         acceleration=acceleration, effort=effort)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    timing = cast(TrajectorySegment, plan.motion.segments[0])  # fastest's motion: one trajectory segment
    return Motion((TrajectorySegment(timing.trajectory, label),),
                  f"a path planned around {scene or 'the arm itself'} (clearance {plan.min_clearance * 1e3:.4g} mm),"
                  " time-optimal timing (Toppra)")


def parse_segments(arm: Arm, specs: list[Any], deg: bool, where_file: str, description: str,
                   start: NDArray[np.float64] | None = None, payload: float = 0.0,
                   gravity: str | ArrayLike | None = None, folder: Path | None = None) -> Motion:
    """The motion of a list of SEGMENT objects (:data:`SEGMENTS_FILE_HELP`), read from JSON; ``where_file`` starts
    every message (``"--segments f.json"``); ``start`` (n,): where a first segment without a start begins (else it
    needs one); ``payload`` (kg), ``gravity``: what the run carries, the ``"fastest"`` segments' timing too;
    ``folder``: where a "plan" segment's scene file is (default the current folder). Every end is checked against
    the limits."""
    load = _Load(payload, gravity)
    if not isinstance(specs, list) or not specs:
        raise ValueError(f"{where_file}: expected a non-empty list of segments")
    if len(specs) > MAX_SEGMENTS:
        raise ValueError(f"{where_file}: {len(specs):,} segments, more than the {MAX_SEGMENTS} allowed "
                         "(armlab.planning.motions.MAX_SEGMENTS)")
    segments: list[Segment] = []
    known = {"label", "tf", "from", "from_point", "from_branch", "from_pitch", "to", "to_point", "to_branch",
             "to_pitch", "rate", "profile"}
    for k, spec in enumerate(specs, start=1):
        where = f"{where_file} segment {k}"
        if not isinstance(spec, dict):
            raise ValueError(f"{where}: expected an object, got {spec!r}")
        tool_path = any(key in spec for key in _TOOL_PATH_KEYS)
        timed = spec.get("profile") == "fastest" or "plan" in spec
        allowed = known | ({"plan"} if "plan" in spec else set()) | (
                           {"samples", *_TOOL_PATH_KEYS} if tool_path else {"through", "degree"} if "through" in spec
                           else set()) | ({"velocity", "acceleration", "effort"} if timed
                                          else {"speed", "acceleration"} if tool_path
                                          else {"velocity", "acceleration"} if spec.get("profile") == "trapezoid"
                                          else set())
        unknown = sorted(set(spec) - allowed)
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {cut(', '.join(unknown))}; allowed: "
                             f"{', '.join(sorted(allowed))} "
                             "(tool paths, trapezoids and \"fastest\" take more: armlab simulate --help)")
        label = str(spec.get("label", k))
        previous = segments[-1].q_end if segments else start
        q0 = _end(arm, spec, "from", deg, previous, where)
        if q0 is None:
            if previous is None:
                raise ValueError(f"{where}: the first segment needs \"from\" or \"from_point\"")
            q0 = previous
        if tool_path:
            segments.extend(_along(arm, spec, _tool_path(arm, spec, q0, deg, where), q0, deg, label, where,
                                   load).segments)
            continue
        if "through" in spec:
            if "profile" in spec:
                raise ValueError(f"{where}: \"profile\" is not allowed with \"through\": via points are splines "
                                 "(\"degree\" 5 or 3)")
            segments.extend(_through(arm, spec, q0, deg, label, where).segments)
            continue
        qf = _end(arm, spec, "to", deg, q0, where)
        rate = spec.get("rate")
        if (qf is None) == (rate is None):
            raise ValueError(f"{where}: give exactly one of \"to\", \"to_point\" or \"rate\" (or a tool path: "
                             "\"line_to\", \"arc_through\" or \"arc_centre\")")
        if "plan" in spec:
            if qf is None or "profile" in spec:
                raise ValueError(f"{where}: a \"plan\" segment needs \"to\" (or \"to_point\") and takes no "
                                 "\"rate\" or \"profile\"")
            segments.extend(_planned(arm, spec, q0, qf, deg, label, where, folder).segments)
            continue
        if timed and qf is not None:
            from pydrake.trajectories import PiecewisePolynomial  # lazy: Drake, only for a time-optimal segment

            # the straight joint line q(s) = q0 + s (qf − q0), s in [0, 1]
            line = PiecewisePolynomial.FirstOrderHold([0.0, 1.0], np.stack([q0, qf], axis=1).tolist())
            segments.extend(_fastest(arm, spec, line, deg, label, where, "the straight joint line", load).segments)
            continue
        if spec.get("profile") == "trapezoid" and qf is not None:
            try:
                segments.extend(trapezoidal(arm, q0, qf, _rates(arm, spec, "velocity", deg, where),
                                            _rates(arm, spec, "acceleration", deg, where),
                                            None if "tf" not in spec else json_number(spec["tf"], f"{where} tf"))
                                .segments)
            except ValueError as error:
                raise ValueError(f"{where}: {error}") from None
            continue
        if "profile" in spec:
            raise ValueError(f"{where}: \"profile\" = {json.dumps(spec['profile'])} is not allowed here: a joint "
                             "segment takes \"trapezoid\" or \"fastest\" (a tool path takes minimum-jerk, cubic, "
                             "trapezoid or fastest)")
        if "tf" not in spec:
            raise ValueError(f"{where}: needs \"tf\" (s)")
        json_number(spec["tf"], f"{where} tf")  # a JSON number: not "2", true or null
        tf = check_duration(spec["tf"], f"{where} tf")
        if qf is None:  # then "rate" is given (checked above)
            segments.append(ConstantRate(q0, _values(arm, rate, deg, f"{where} rate"), tf, label))
        else:
            segments.append(QuinticSegment(q0, qf, tf, label))
    motion = Motion(tuple(segments), description)
    motion.check_limits(arm)
    return motion
