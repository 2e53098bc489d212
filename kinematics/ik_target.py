"""What an inverse-kinematics answer is checked against: its target, its tool pose error, the joint limits.

* :func:`pose` makes a 4×4 pose target from a position and roll, pitch, yaw; :func:`check_pose`
  checks one (homogeneous, a proper rotation).
* :func:`pose_error` is the tool pose error of joint values by the arm's own forward kinematics,
  [target − p(q); log(R* R(q)ᵀ)], with :func:`rotation_log` the orientation error's rotation vector;
  a solution must meet :data:`POSITION_TOL` and :data:`ORIENTATION_TOL` (:func:`on_target`).
* :func:`fit_limits` fits solutions into the joint limits by 2π shifts, :func:`project_into_limits` a solver's step;
  :func:`outside_limits_message` says which joint cannot be fitted.

Used by the closed forms (:mod:`armlab.kinematics.ik_closed_form`), the numerical solver
(:mod:`armlab.kinematics.ik_numeric`) and the dispatcher (:mod:`armlab.kinematics.ik`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import Interval, above, allowance, outside, tolerated
from armlab.kinematics.basic_movements import T_Z4, T_Z5, T_Z6
from armlab.kinematics.batch import as_batch
from armlab.kinematics.locating import homogeneous, orientation_angles
from armlab.limits import check_range

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = [
    "ORIENTATION_TOL",
    "POSITION_TOL",
    "JointConstants",
    "check_pose",
    "fit_limits",
    "fmt",
    "joint_constants",
    "made_once",
    "on_target",
    "outside_limits_message",
    "pose",
    "pose_error",
    "project_into_limits",
    "rotation_log",
    "single",
    "target_text",
]

#: Forward kinematics of a returned solution must hit the target to this distance (m).
POSITION_TOL = 1e-9
#: A returned solution's tool orientation must match a pose target to this angle (rad).
ORIENTATION_TOL = 1e-9
#: Indices of R's entries (2, 1), (0, 2), (1, 0) and their transposes: vee(R − Rᵀ) in two fancy-indexing reads.
_LOWER, _UPPER = np.array([2, 0, 1]), np.array([1, 2, 0])


def made_once[Made](owner: object, what: str, make: Callable[[Any], Made]) -> Made:
    """``make(owner)``, made once per frozen ``owner`` (an :class:`~armlab.models.arm.Arm`, a
    :class:`~armlab.kinematics.dh.DHTable`) and ``what``, kept in the owner's own ``__dict__`` as
    ``functools.cached_property`` keeps its value (and gone with it; a ``dataclasses.replace`` copy starts
    afresh): constants that cost more to make than a one-configuration solve spends on its arithmetic."""
    made: dict[str, Any] = owner.__dict__.setdefault("_made_once", {})
    if what not in made:
        made[what] = make(owner)
    return made[what]


class JointConstants(NamedTuple):
    """An arm's joint limits as :func:`fit_limits` uses them, each ``(n,)``."""

    lower: NDArray[np.float64]  #: ``arm.limit_arrays()``'s (rad or m; −inf: unlimited)
    upper: NDArray[np.float64]
    revolute: NDArray[np.bool_]
    limited: NDArray[np.bool_]  #: a URDF limits both ends or neither
    lowest: NDArray[np.float64]  #: what counts as within the limits: each widened by :func:`armlab.bounds.allowance`
    highest: NDArray[np.float64]
    interval: Interval  #: the limits, their allowances made once


def _joint_constants(arm: Arm) -> JointConstants:
    lower, upper = arm.limit_arrays()
    return JointConstants(lower, upper, arm.revolute, np.isfinite(lower) & np.isfinite(upper),
                          lower - allowance(lower), upper + allowance(upper), Interval(lower, upper))


def joint_constants(arm: Arm) -> JointConstants:
    """``arm``'s :class:`JointConstants` (made once per arm, :func:`made_once`)."""
    return made_once(arm, "joints", _joint_constants)


def fmt(v: ArrayLike) -> str:
    """Values as "(x, y, …)", 6 significant digits."""
    return "(" + ", ".join(f"{x:.6g}" for x in np.ravel(v)) + ")"


def single(position: ArrayLike, n: int, name: str = "target") -> NDArray[np.float64]:
    """``position`` as one point ``(n,)``; ``ValueError`` (naming ``name``) for a batch, a wrong count or NaN/inf."""
    p = as_batch(position, n, name)
    if p.ndim != 1:
        raise ValueError(f"{name} has shape {p.shape}; expected one point of {n} coordinates")
    return p


def pose(position: ArrayLike, rpy: ArrayLike) -> NDArray[np.float64]:
    """The 4×4 pose with origin ``position`` (m, (3,)) and rotation R = Rz(y)·Ry(p)·Rx(r), ``rpy`` = (r, p, y) in rad.

    The URDF convention: roll about x, then pitch about y, then yaw about z, all about the fixed axes.
    """
    values = np.asarray(rpy, dtype=float)
    if values.shape != (3,) or not np.all(np.isfinite(values)):
        raise ValueError(f"rpy {np.ravel(values).tolist()} must be 3 finite angles (roll, pitch, yaw)")
    check_range(values, "rpy", key="angle")
    r, p, y = values
    return homogeneous((T_Z6(y) @ T_Z5(p) @ T_Z4(r))[:3, :3], single(position, 3, "position"))


def rotation_log(R: ArrayLike) -> NDArray[np.float64]:
    """The rotation vector ω = θ·u (rad) with exp([ω]×) = R, |ω| ≤ π, shape ``(..., 3)`` for ``(..., 3, 3)``.

    With v = vee(R − Rᵀ)/2 = sin θ·u and cos θ = (tr R − 1)/2, θ = atan2(|v|, cos θ). For
    cos θ ≥ 0, ω = (θ / sin θ)·v; beyond π/2 (where v loses accuracy) u is read from
    R + Rᵀ = 2 cos θ·I + 2 (1 − cos θ) u uᵀ, its column of largest diagonal, signed like v.
    Accurate to round-off for every angle, including θ → 0 and θ → π.
    """
    R = np.asarray(R, dtype=float)
    if R.shape == (3, 3):  # one rotation: the same formulas in scalars (numpy's per-call cost exceeds them)
        return _rotation_log_one(R)
    v = 0.5 * (R[..., _LOWER, _UPPER] - R[..., _UPPER, _LOWER])  # (R21 − R12, R02 − R20, R10 − R01) / 2
    s = np.linalg.norm(v, axis=-1)
    c = np.clip((np.trace(R, axis1=-2, axis2=-1) - 1.0) / 2.0, -1.0, 1.0)
    theta = np.arctan2(s, c)
    regular = np.where(s > 0, theta / np.where(s > 0, s, 1.0), 1.0)[..., None] * v  # θ/sin θ → 1 as θ → 0
    if not np.any(c < 0):  # no angle beyond π/2 (a solver near its target): the second reading is not needed
        return regular
    obtuse = np.where(c < 0, c, -1.0)[..., None, None]  # only used where cos θ < 0, so 1 − cos θ ≥ 1
    M = (R + np.swapaxes(R, -1, -2) - 2.0 * obtuse * np.eye(3)) / (2.0 * (1.0 - obtuse))  # u uᵀ there
    k = np.argmax(np.diagonal(M, axis1=-2, axis2=-1), axis=-1)
    column = np.take_along_axis(M, k[..., None, None], axis=-1)[..., 0]
    u = column / np.sqrt(np.take_along_axis(np.diagonal(M, axis1=-2, axis2=-1), k[..., None], axis=-1))
    u = np.where((np.sum(u * v, axis=-1) < 0)[..., None], -u, u)
    return np.where((c < 0)[..., None], theta[..., None] * u, regular)


def _rotation_log_one(R: NDArray) -> NDArray[np.float64]:
    """:func:`rotation_log` of one rotation ``(3, 3)``, in scalars: ``(3,)``."""
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = R.tolist()
    v = (0.5 * (r21 - r12), 0.5 * (r02 - r20), 0.5 * (r10 - r01))
    s = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    c = min(1.0, max(-1.0, (r00 + r11 + r22 - 1.0) / 2.0))
    theta = math.atan2(s, c)
    if c >= 0:  # not beyond π/2: (θ / sin θ)·v, → v as θ → 0
        scale = theta / s if s > 0 else 1.0
        return np.array([scale * v[0], scale * v[1], scale * v[2]])
    M = np.array(R)  # beyond π/2: u from R + Rᵀ = 2 cos θ·I + 2 (1 − cos θ) u uᵀ, its column of largest diagonal
    M = (M + M.T - 2.0 * c * np.eye(3)) / (2.0 * (1.0 - c))
    k = int(np.argmax(np.diagonal(M)))
    u = M[:, k] / math.sqrt(M[k, k])
    if u[0] * v[0] + u[1] * v[1] + u[2] * v[2] < 0:
        u = -u
    return theta * u


def pose_error(arm: Arm, position: NDArray, rotation: NDArray | None, q: NDArray) -> NDArray[np.float64]:
    """Tool pose error ``(..., 3)`` or ``(..., 6)`` by the arm's own FK: [target − p(q); log(R* R(q)ᵀ)], world frame."""
    T = arm.forward(q).tool
    error = position - T[..., :3, 3]
    if rotation is None:
        return error
    return np.concatenate([error, rotation_log(rotation @ np.swapaxes(T[..., :3, :3], -1, -2))], axis=-1)


def on_target(error: NDArray) -> NDArray[np.bool_]:
    """Whether each tool pose error ``(..., 3)`` or ``(..., 6)`` (:func:`pose_error`: m, then rad) is within
    :data:`POSITION_TOL` in position and :data:`ORIENTATION_TOL` in orientation (:func:`armlab.bounds.tolerated`),
    ``(...)``: the test every IK solution passes before it is returned."""
    return (tolerated(np.linalg.norm(error[..., :3], axis=-1), POSITION_TOL)
            & tolerated(np.linalg.norm(error[..., 3:], axis=-1), ORIENTATION_TOL))


def project_into_limits(arm: Arm, q: NDArray, lower: NDArray, upper: NDArray,
                        interval: Interval | None = None) -> NDArray[np.float64]:
    """``q`` moved into the limits: a revolute angle by a 2π shift when one fits, else clipped onto the limit.
    ``interval``: ``lower`` and ``upper`` with their allowances made (:class:`armlab.bounds.Interval`), for a loop."""
    base = np.where(np.isfinite(lower), lower, 0.0)
    shifted = base + np.mod(q - base, 2 * np.pi)  # in [lower, lower + 2π)
    if interval is None:
        shift = arm.revolute & outside(q, lower, upper) & ~above(shifted, upper)
    else:
        shift = joint_constants(arm).revolute & interval.outside(q) & ~interval.above_upper(shifted)
    return np.minimum(np.maximum(np.where(shift, shifted, q), lower), upper)


def check_pose(T: NDArray) -> tuple[NDArray, NDArray]:
    """(position, rotation) of a 4×4 pose; ``ValueError`` unless homogeneous with a proper rotation (to 1e-9)."""
    single(T.ravel(), 16, "target")
    R = T[:3, :3]
    if np.abs(T[3] - [0.0, 0.0, 0.0, 1.0]).max() > 0:
        raise ValueError(f"target pose's last row {T[3].tolist()} must be [0, 0, 0, 1]")
    deviation = np.abs(R.T @ R - np.eye(3)).max()
    if not tolerated(deviation, 1e-9):
        raise ValueError(f"target pose's rotation {R.tolist()} is not orthonormal (|RᵀR − I| = {deviation:.3g} "
                         "> 1e-9): give it to full precision")
    if np.linalg.det(R) < 0:
        raise ValueError(f"target pose's rotation {R.tolist()} has determinant −1 (a reflection); a rotation has +1")
    return T[:3, 3], R


def target_text(position: NDArray, rotation: NDArray | None) -> str:
    """``target (x, y, z)``, or for a pose ``target pose (x, y, z) m, rpy (r, p, y) rad``."""
    if rotation is None:
        return f"target {fmt(position)}"
    return f"target pose {fmt(position)} m, rpy {fmt(orientation_angles(rotation) + 0.0)} rad"  # + 0.0: no −0


def fit_limits(arm: Arm, q: ArrayLike, near: ArrayLike | None = None) -> tuple[NDArray, list[tuple | None]]:
    """Fit solutions ``(k, n)`` into ``arm``'s joint limits by 2π shifts of revolute angles.

    A limited revolute angle becomes the q + 2πm within [lower, upper] nearest ``near``
    (ties keep the smaller shift); an unlimited one is wrapped to (−π, π]; a prismatic value
    is left as is. A value on a limit within the slack (:mod:`armlab.bounds`) fits, and is clipped onto it.

    Returns the fitted array and, per solution, ``None`` if it is within limits or else
    ``(joint index, value, lower, upper)`` of its first joint that cannot be fitted.
    """
    q = np.array(q, dtype=float, ndmin=2)
    near = np.zeros(arm.n) if near is None else np.asarray(near, dtype=float)
    lower, upper, revolute, limited, lo, hi, interval = joint_constants(arm)
    two_pi = 2 * np.pi
    m_lo, m_hi = np.ceil((lo - q) / two_pi), np.floor((hi - q) / two_pi)  # the 2π shifts that fit (±inf: unlimited)
    m = np.minimum(np.maximum(np.round((near - q) / two_pi), m_lo), m_hi)  # np.clip's, without its wrapper
    if interval.lower.size and limited.all() and revolute.all():  # every joint a limited revolute one (fewer calls)
        fits = m_lo <= m_hi  # not a bound: shift counts
        fitted = np.where(fits, np.minimum(np.maximum(q + two_pi * np.where(fits, m, 0.0), lower), upper), q)
    else:
        wrapped = q - two_pi * np.ceil((q - np.pi) / two_pi)  # (−π, π] up to round-off:
        wrapped = np.where(wrapped > np.pi, wrapped - two_pi, np.where(wrapped <= -np.pi, wrapped + two_pi, wrapped))
        fits = np.where(revolute, m_lo <= m_hi, ~interval.outside(q)) | ~limited  # not a bound: shift counts
        shifted = np.where(revolute, q + two_pi * np.where(fits, m, 0.0), q)
        inside = np.where(fits, np.minimum(np.maximum(shifted, lower), upper), q)
        fitted = np.where(limited, inside, np.where(revolute, wrapped, q))
    first: list[tuple | None] = [None] * q.shape[0]
    bad = ~fits
    for k in np.flatnonzero(bad.any(axis=-1)):
        i = int(np.argmax(bad[k]))
        first[k] = (i, float(q[k, i]), float(lower[i]), float(upper[i]))
    return fitted, first


def outside_limits_message(arm: Arm, target: str, violations: list[tuple | None]) -> str:
    """"``target`` is reachable by ARM only outside its joint limits: …", naming each joint that
    :func:`fit_limits` could not fit (its ``violations``)."""
    parts = []
    for i, value, lo, hi in (v for v in violations if v is not None):
        if arm.revolute[i]:
            parts.append(f"{arm.joint_names[i]} = {np.degrees(value):.6g}° outside [{np.degrees(lo):.6g}°, "
                         f"{np.degrees(hi):.6g}°] even after 2π shifts")
        else:
            parts.append(f"{arm.joint_names[i]} = {value:.6g} m outside [{lo:.6g}, {hi:.6g}] m")
    return (f"{target} is reachable by {arm.name} only outside its joint limits: "
            + "; ".join(dict.fromkeys(parts)))
