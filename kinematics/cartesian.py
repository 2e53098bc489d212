"""Task-space paths of the tool: a straight line and a circular arc, orientation held or slerped, timed by a profile.

A :class:`ToolPath` is the tool point p(s) and (optionally) the tool rotation R(s) for s ∈ [0, 1], with their
first and second derivatives in s (closed forms):

* :func:`line_path` — p = p0 + s (p1 − p0) (RTB ``ctraj``, MATLAB ``transformtraj``);
* :func:`arc_path` — p = c + Rot(u, sθ)(p0 − c), about the centre c and unit axis u by the angle θ
  (centre–axis–angle), or :func:`arc_through` the circle through three points, from the first to the third
  by the second;
* the rotation held (R(s) = R0) or slerped, R(s) = exp(s [φ]×) R0 with φ = log(R1 R0ᵀ) (world frame: angular
  rate φ per unit s, constant).

:func:`tool_motion_along` gives the joint motion: IK along the path at ``samples`` values of s on one branch
(:func:`armlab.kinematics.ik_path.solve_path`), the joint path q(s) the quintic Hermite interpolant of q, q',
q'' at the samples (a Drake ``PiecewisePolynomial`` in s), timed by a :class:`~armlab.kinematics.profiles.Profile`
s(t) — a Drake ``PathParameterizedTrajectory`` q(s(t)), one :class:`~armlab.kinematics.quintic.TrajectorySegment`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.ik import solve, solve_branch
from armlab.kinematics.ik_path import PathJoints, solve_path
from armlab.kinematics.ik_target import check_pose, rotation_log
from armlab.kinematics.locating import homogeneous, rotation_about
from armlab.kinematics.profiles import (
    Profile,
    cubic_profile,
    hermite_coefficients,
    minimum_jerk_profile,
    trapezoid_profile,
)
from armlab.kinematics.quintic import Motion, TrajectorySegment, polynomial_matrix
from armlab.limits import check_count, check_positive, check_range

if TYPE_CHECKING:
    from pydrake.trajectories import PiecewisePolynomial

    from armlab.models.arm import Arm

__all__ = ["DEFAULT_SAMPLES", "PROFILES", "ToolPath", "arc_path", "arc_through", "joint_path", "line_path",
           "path_profile", "tool_joint_path", "tool_motion_along", "tool_path_text"]

#: The time profiles a tool path takes by name.
PROFILES = ("minimum-jerk", "cubic", "trapezoid")

#: Samples of s along a path by default (the IK is exact at each; between them the quintic Hermite interpolant).
DEFAULT_SAMPLES = 201
#: Shortest line and smallest arc radius or angle taken (m, rad): shorter is a zero-length path.
MIN_LENGTH = 1e-9


@dataclass(frozen=True)
class ToolPath:
    """A tool path for s ∈ [0, 1]: ``kind`` ("line", "arc"), the point's function of s and the rotation's.

    ``centre``, ``axis``, ``angle`` (an arc's; ``None`` for a line), ``start``/``end`` points (m) and rotations
    ``R0``/``R1`` (``None``: position only; R1 = R0: held).
    """

    kind: str
    start: NDArray[np.float64]
    end: NDArray[np.float64]
    R0: NDArray[np.float64] | None = None
    R1: NDArray[np.float64] | None = None
    centre: NDArray[np.float64] | None = None
    axis: NDArray[np.float64] | None = None
    angle: float = 0.0

    @property
    def length(self) -> float:
        """The path's length (m)."""
        if self.centre is None:
            return float(np.linalg.norm(self.end - self.start))
        return float(abs(self.angle) * np.linalg.norm(self.start - self.centre))

    def points(self, s: NDArray) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """p, dp/ds, d²p/ds² at ``s`` ``(m,)``, each ``(m, 3)`` (m)."""
        if self.centre is None or self.axis is None:
            d = self.end - self.start
            return self.start + s[:, None] * d, np.broadcast_to(d, (s.size, 3)).copy(), np.zeros((s.size, 3))
        r = np.einsum("mij,j->mi", rotation_about(self.axis, s * self.angle), self.start - self.centre)
        dp = self.angle * np.cross(self.axis, r)
        ddp = self.angle**2 * np.cross(self.axis, np.cross(self.axis, r))
        return self.centre + r, dp, ddp

    def rotations(self, s: NDArray) -> tuple[NDArray, NDArray, NDArray] | None:
        """R ``(m, 3, 3)``, its angular rate and that rate's derivative per unit s ``(m, 3)``; ``None``: no rotation."""
        if self.R0 is None or self.R1 is None:
            return None
        phi = rotation_log(self.R1 @ self.R0.T)
        angle = float(np.linalg.norm(phi))
        if angle == 0.0:  # exact: held, R1 = R0
            R = np.broadcast_to(self.R0, (s.size, 3, 3)).copy()
        else:
            R = rotation_about(phi / angle, s * angle) @ self.R0
        return R, np.broadcast_to(phi, (s.size, 3)).copy(), np.zeros((s.size, 3))


def _position(point: ArrayLike, name: str) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """A point (3,) (a planar arm's (2,) gets z = 0) or a 4×4 pose: (position, rotation or None)."""
    a = np.asarray(point, dtype=float)
    if a.shape == (4, 4):
        return check_pose(a)
    if a.shape == (2,):
        a = np.append(a, 0.0)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} = {np.ravel(a).tolist()} must be a point (x, y, z) in m or a 4×4 pose")
    return check_range(a, name, key="coordinate"), None  # a point at 1e308 m would overflow the IK


def line_path(start: ArrayLike, end: ArrayLike) -> ToolPath:
    """The straight line from ``start`` to ``end`` (points (3,) m, or 4×4 poses: the rotation is slerped between
    them; a pose and a point: the rotation is held). ``ValueError`` for a zero-length line."""
    p0, R0 = _position(start, "line start")
    p1, R1 = _position(end, "line end")
    if np.linalg.norm(p1 - p0) < MIN_LENGTH:
        raise ValueError(f"the line from {p0.tolist()} to {p1.tolist()} has zero length: give two different points")
    return ToolPath("line", p0, p1, R0, R1 if R1 is not None else R0)


def arc_path(centre: ArrayLike, axis: ArrayLike, start: ArrayLike, angle: float,
             end_rotation: ArrayLike | None = None) -> ToolPath:
    """The arc about ``centre`` (3,) m and ``axis`` (3,) by ``angle`` (rad, right-handed) from ``start`` (a point or
    a pose; with a pose the rotation is held, or slerped to ``end_rotation`` (3, 3)). ``ValueError`` for a zero
    axis, a start on the axis, a start not square to the axis, or a zero angle."""
    c, _ = _position(centre, "arc centre")
    p0, R0 = _position(start, "arc start")
    u = np.asarray(axis, dtype=float)
    if u.shape != (3,) or not np.all(np.isfinite(u)) or np.linalg.norm(u) < MIN_LENGTH:
        raise ValueError(f"arc axis = {np.ravel(u).tolist()} must be a nonzero vector (x, y, z)")
    u = u / np.linalg.norm(u)
    if not np.isfinite(angle) or abs(angle) < MIN_LENGTH:
        raise ValueError(f"arc angle = {angle} rad is not allowed: a finite nonzero angle")
    angle = float(check_range(angle, "arc angle", key="angle"))  # 1e308 rad would overflow the timing
    r = p0 - c
    if np.linalg.norm(r) < MIN_LENGTH:
        raise ValueError(f"the arc's start {p0.tolist()} is its centre: the radius is zero")
    if abs(r @ u) > 1e-9 * np.linalg.norm(r):
        raise ValueError(f"the arc's start {p0.tolist()} is not square to its axis {u.tolist()} about "
                         f"{c.tolist()} (by {r @ u:.3g} m)")
    end = c + rotation_about(u, angle) @ r
    R1 = R0 if end_rotation is None else check_pose(homogeneous(end_rotation, end))[1]
    return ToolPath("arc", p0, end, R0, R1, c, u, float(angle))


def arc_through(a: ArrayLike, b: ArrayLike, c: ArrayLike) -> ToolPath:
    """The arc of the circle through ``a``, ``b``, ``c`` (points (3,) m, or (2,) in z = 0), from ``a`` by ``b`` to
    ``c``; ``a`` may be a pose (its rotation held). ``ValueError`` for collinear (or coincident) points."""
    pa, Ra = _position(a, "arc point 1")
    pb, _ = _position(b, "arc point 2")
    pc, _ = _position(c, "arc point 3")
    ab, ac = pb - pa, pc - pa
    normal = np.cross(ab, ac)
    if np.linalg.norm(normal) <= 1e-12 * max(np.linalg.norm(ab) * np.linalg.norm(ac), 1e-300):
        raise ValueError(f"the arc points {pa.tolist()}, {pb.tolist()}, {pc.tolist()} are collinear: no circle "
                         "passes through them")
    # the circumcentre: a + (|ac|² (ab × n) × ... ) in the standard closed form
    n2 = normal @ normal
    centre = pa + (np.cross(normal, ab) * (ac @ ac) + np.cross(ac, normal) * (ab @ ab)) / (2 * n2)
    u = normal / np.sqrt(n2)
    ra, rc = pa - centre, pc - centre
    angle = float(np.arctan2(u @ np.cross(ra, rc), ra @ rc)) % (2 * np.pi)  # a → c counter-clockwise about u
    start = pa if Ra is None else homogeneous(Ra, pa)
    return arc_path(centre, u, start, angle)


def joint_path(joints: PathJoints) -> PiecewisePolynomial:
    """The joint path q(s) ``(n, 1)``: per interval of s the quintic with the samples' q, q', q'' at both ends
    (:func:`~armlab.kinematics.profiles.hermite_coefficients`), as Drake's ``PiecewisePolynomial``."""
    from pydrake.trajectories import PiecewisePolynomial

    s, q, dq, ddq = joints.s, joints.q, joints.dq, joints.ddq
    c = hermite_coefficients(q[:-1], dq[:-1], ddq[:-1], q[1:], dq[1:], ddq[1:], np.diff(s))  # (m − 1, n, 6)
    return PiecewisePolynomial([polynomial_matrix(piece) for piece in c], s.tolist())


def path_profile(path: ToolPath, kind: str = "minimum-jerk", duration: float | None = None,
                 speed: float | None = None, acceleration: float | None = None) -> Profile:
    """The time profile of a tool path by name (:data:`PROFILES`): minimum jerk or cubic over ``duration`` s, or a
    trapezoid of the tool's peak ``speed`` (m/s) and ``acceleration`` (m/s²) along the path, or of a duration."""
    if kind not in PROFILES:
        raise ValueError(f"profile {kind!r} is not allowed: one of {', '.join(PROFILES)}")
    if kind == "trapezoid":
        L = path.length
        return trapezoid_profile(None if speed is None else _tool_rate(speed, "peak speed", "m/s") / L,
                                 None if acceleration is None else _tool_rate(acceleration, "peak acceleration",
                                                                              "m/s²") / L, duration)
    if speed is not None or acceleration is not None:
        raise ValueError(f"a peak speed or acceleration applies to the trapezoid profile, not {kind!r}")
    if duration is None:
        raise ValueError(f"the {kind} profile needs a duration (s)")
    return minimum_jerk_profile(duration) if kind == "minimum-jerk" else cubic_profile(duration)


def _tool_rate(value: float, what: str, unit: str) -> float:
    return check_positive(value, what, unit, f"a {what} must be a positive finite number")


def start_joints(arm: Arm, path: ToolPath, q0: ArrayLike | None, branch: int | None) -> NDArray[np.float64]:
    """The joints at the path's start: ``q0`` (checked), IK ``branch`` of a closed form, or the IK solution nearest
    zero (:func:`armlab.kinematics.ik.solve`)."""
    if q0 is not None:
        return arm.check_q(q0, "q0")
    if branch is not None:
        return solve_branch(arm, path.start, branch)
    target = path.start if path.R0 is None else homogeneous(path.R0, path.start)
    return solve(arm, target)[0]


def tool_motion_along(arm: Arm, path: ToolPath, duration: float | None = None, profile: Profile | None = None,
                      q0: ArrayLike | None = None, branch: int | None = None, samples: int = DEFAULT_SAMPLES,
                      label: str = "") -> Motion:
    """``arm``'s tool along ``path``, timed by ``profile`` (default: minimum jerk over ``duration`` s).

    The joints start at ``q0``, or IK ``branch``, or the IK solution nearest zero; IK at ``samples`` values of s
    (≥ 2) on that branch (:func:`~armlab.kinematics.ik_path.solve_path`: ``ValueError`` with s and the point
    where the path leaves the reach, a joint limit, or passes a singularity). Orientation is followed only for
    a 6-joint arm (or more) and when the path has one; other arms take the position.
    """
    if profile is None:
        if duration is None:
            raise ValueError(f"give the {path.kind} a duration (s) or a time profile")
        profile = minimum_jerk_profile(duration)
    from pydrake.trajectories import PathParameterizedTrajectory

    trajectory = PathParameterizedTrajectory(tool_joint_path(arm, path, q0, branch, samples), profile.piecewise())
    motion = Motion((TrajectorySegment(trajectory, label or path.kind),),
                    f"{tool_path_text(arm, path)}, {profile.name} timing")
    motion.check_limits(arm)
    return motion


def tool_joint_path(arm: Arm, path: ToolPath, q0: ArrayLike | None = None, branch: int | None = None,
                    samples: int = DEFAULT_SAMPLES) -> PiecewisePolynomial:
    """The joint path q(s) ``(n, 1)``, s in [0, 1], that puts ``arm``'s tool on ``path``, untimed (what
    :func:`tool_motion_along` times, and what :func:`armlab.planning.timing.fastest` takes): IK at ``samples``
    values of s on one branch from ``q0``, IK ``branch`` or the solution nearest zero, as there.

    A 6-joint arm (or more) on a path of points (no rotation given) holds the tool's rotation at the start
    configuration (RTB ``ctraj``'s rule). The tool is on the path at the samples to
    :data:`~armlab.kinematics.ik_path.PATH_TOL`; between them, the quintic Hermite interpolant's error (the
    Panda's 0.45 m line from its ready pose: 4.2e-8 m and 1.6e-7 rad at 201 samples, 3.4e-9 m and 1.3e-8 rad
    at 801; ``tests/test_plan.py`` holds it to 2e-7 and 2e-8)."""
    samples = check_count(samples, "samples")  # bounded: the IK's work and memory grow with it
    start = start_joints(arm, path, q0, branch)
    if arm.n >= 6 and path.R0 is None:
        held = arm.fk(start)[:3, :3]
        path = replace(path, R0=held, R1=held)
    s = np.linspace(0.0, 1.0, samples)
    p, dp, ddp = path.points(s)
    rotations = path.rotations(s) if arm.n >= 6 else None
    return joint_path(solve_path(arm, f"the {path.kind}", s, p, dp, ddp, start, *(rotations or (None, None, None))))


def tool_path_text(arm: Arm, path: ToolPath) -> str:
    """"the tool along a 0.2828 m line (position)": what a motion of ``arm`` along ``path`` is."""
    if arm.n < 6:
        what = "position"
    elif path.R0 is None or path.R1 is None or not np.linalg.norm(rotation_log(path.R1 @ path.R0.T)):
        what = "orientation held"
    else:
        what = "orientation slerped"
    return f"the tool along a {path.length:.4g} m {path.kind} ({what})"
