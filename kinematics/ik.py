"""Inverse kinematics: the papers' closed forms, a multi-start numerical solver, and one dispatcher.

* :func:`rr_ik` — paper 000, the planar two-link arm of Fig. 1/Fig. 2, by the law of
  cosines applied to eqs. (1)–(2) in its half-angle form; both elbow branches.
* :func:`arm4r_ik` — paper 001, the analytical ("inverse transform") method, eqs. (9)–(21).
* :func:`r2t_ik` — paper 003, the tool position p4 of eq. (21) (as corrected in
  :mod:`armlab.models.r2t`) solved for q1, q2, q3.
* :func:`numeric_ik` — any arm (urm6, rrrr, users' arms), a position or a full pose: damped
  least squares (Levenberg–Marquardt) on the tool pose error from many starts at once, each
  converged start polished by Newton steps and checked by the arm's own forward kinematics.
* :func:`solve` — what ``armlab ik`` and ``Arm.ik`` call: picks the method, fits every angle
  into the joint limits, drops, deduplicates (modulo 2π) and orders the solutions (nearest to
  ``near`` first).
* :func:`pose`, :func:`target_pose` make a 4×4 pose target from a position and roll, pitch,
  yaw; :func:`rotation_log` is the orientation error's rotation vector.

Unreachable targets and targets reachable only outside the joint limits raise
``ValueError`` naming the target (paper 001: "some of the possible solutions … can not be
realized because of the structure limitation … the nearest set of solution will be chosen");
an unreachable position's error gives the closest distance the tool gets to it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.basic_movements import T_Z4, T_Z5, T_Z6
from armlab.kinematics.batch import as_batch
from armlab.kinematics.locating import homogeneous, orientation_angles
from armlab.limits import check_range

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = [
    "ANALYTIC_ARMS",
    "arm4r_ik",
    "drake_arm",
    "fit_limits",
    "numeric_ik",
    "planar_target",
    "pose",
    "r2t_ik",
    "rotation_log",
    "rr_ik",
    "solve",
    "target_pose",
]

#: Relative tolerance on lengths when deciding reachability at a workspace boundary (round-off only).
REACH_RTOL = 1e-12
#: Forward kinematics of a returned solution must hit the target to this distance (m).
POSITION_TOL = 1e-9
#: Two solutions closer than this in every joint are the same solution.
SAME_SOLUTION_TOL = 1e-9


def _fmt(v: ArrayLike) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in np.ravel(v)) + ")"


def _positive_lengths(**lengths: float) -> None:
    for name, value in lengths.items():
        if not np.isfinite(value) or value <= 0:
            raise ValueError(f"{name} = {value} must be a positive finite length")


def _single(position: ArrayLike, n: int, name: str = "target") -> NDArray[np.float64]:
    p = as_batch(position, n, name)
    if p.ndim != 1:
        raise ValueError(f"{name} has shape {p.shape}; expected one point of {n} coordinates")
    return p


def planar_target(target: ArrayLike) -> NDArray[np.float64]:
    """The rr arm's target as (x, y): given as x,y or as x,y,0 (the arm moves in the plane z = 0)."""
    p = np.asarray(target, dtype=float)
    if p.shape == (3,):
        if p[2] != 0.0:
            raise ValueError(f"target z = {p[2]:g} is not allowed: the rr arm moves in the plane z = 0")
        p = p[:2]
    if p.shape != (2,):
        raise ValueError(f"target {np.ravel(p).tolist()} has {p.size} values; rr takes x,y (or x,y,0) in m")
    return _single(p, 2)


def _unreachable(bad: NDArray, p: NDArray, strict: bool, message: Callable[[NDArray], str]) -> None:
    """Raise ``message(first bad point)`` if a target is out of reach, unless a non-strict batch (NaN rows then)."""
    if np.any(bad) and (strict or p.ndim == 1):
        raise ValueError(message(p.reshape(-1, p.shape[-1])[np.argmax(np.ravel(bad))]))


# --------------------------------------------------------------------------- paper 000
def rr_ik(target: ArrayLike, L1: float, L2: float, strict: bool = True) -> NDArray[np.float64]:
    """Both inverse-kinematics branches of paper 000's planar RR arm (Fig. 2), shape ``(..., 2, 2)``.

    Eqs. (1)–(2), x = L1 c1 + L2 c12, y = L1 s1 + L2 s12, squared and added give the law of
    cosines r² = x² + y² = L1² + L2² + 2 L1 L2 cos θ2. Written with the half angle,
    tan²(θ2/2) = (1 − cos θ2)/(1 + cos θ2) = ((L1 + L2)² − r²)/(r² − (L1 − L2)²), so

        θ2 = ±2 atan2(√((L1 + L2 − r)(L1 + L2 + r)), √((r − |L1 − L2|)(r + |L1 − L2|))),
        θ1 = atan2(y, x) − atan2(L2 sin θ2, L1 + L2 cos θ2).

    Unlike arccos of the law of cosines (whose slope is infinite at cos θ2 = ±1), this stays
    accurate on the annulus' rims: at r = L1 + L2 it gives θ2 = 0 exactly, at r = |L1 − L2| ±π.

    ``out[..., b, :]`` is branch ``b`` = (θ1, θ2): branch 0 has θ2 ≥ 0, branch 1 has θ2 ≤ 0.
    Paper 000 draws both in Fig. 2 without naming them; with its y axis up (the vertical
    plane of Fig. 26), branch 0 puts the elbow below the line from the base to M ("elbow
    down"; the paper's start M0 ≈ FK(−38°, 98°) is on it) and branch 1 above ("elbow up").
    On the annulus' rims the two coincide (θ2 = 0) or differ only by θ2 = ±π.

    ``target`` is one point ``(2,)`` or a batch ``(..., 2)``. A target outside the reachable
    annulus |L1 − L2| ≤ |target| ≤ L1 + L2 raises ``ValueError``; only for a batch with
    ``strict=False`` are the unreachable entries NaN instead.
    """
    _positive_lengths(L1=L1, L2=L2)
    p = as_batch(target, 2, "target")
    x, y = p[..., 0], p[..., 1]
    distance = np.hypot(x, y)
    inner, outer = abs(L1 - L2), L1 + L2
    tol = REACH_RTOL * outer
    unreachable = (distance > outer + tol) | (distance < inner - tol)
    _unreachable(unreachable, p, strict, lambda xy: (
        f"target {_fmt(xy)} is out of reach of the RR arm: |target| = {np.hypot(*xy):.6g} m, "
        f"reachable annulus {inner:.6g} m ≤ |target| ≤ {outer:.6g} m"))
    r = np.clip(distance, inner, outer)  # round-off beyond a rim: onto it
    half = np.arctan2(np.sqrt((outer - r) * (outer + r)), np.sqrt((r - inner) * (r + inner)))  # θ2/2 ≥ 0
    theta2 = np.stack([2 * half, -2 * half], axis=-1)  # branch 0: θ2 ≥ 0, branch 1: θ2 ≤ 0
    theta1 = np.arctan2(y, x)[..., None] - np.arctan2(L2 * np.sin(theta2), L1 + L2 * np.cos(theta2))
    out = np.stack([theta1, theta2], axis=-1)
    out[unreachable] = np.nan
    return out


# --------------------------------------------------------------------------- paper 001
def arm4r_ik(
    position: ArrayLike, pitch: ArrayLike, a2: float, a3: float, d2: float, theta1_free: float = 0.0,
    strict: bool = True,
) -> NDArray[np.float64]:
    """Paper 001's analytical inverse kinematics of the 4R arm, eqs. (9)–(21): shape ``(..., 4, 4)``.

    With the modified DH of Table 1 the tool position is (eq. 5, checked against
    :func:`armlab.models.arm4r.forward`)

        p = Rz(θ1) · (r, d2, −(a2 s2 + a3 s23)),   r = a2 c2 + a3 c23,

    and its orientation R04 = Rz(θ1) Rx(−90°) Rz(θ2 + θ3 + θ4): a 4-DOF arm reaches only the
    orientations given by θ1 and the *pitch* θ2 + θ3 + θ4 (the angle of the tool x axis below
    the horizontal, in the arm's vertical plane). So the request is a position plus a pitch.

    * θ1, eq. (9) −s1 px + c1 py = d2, solved as eq. (11):
      θ1 = atan2(py, px) − atan2(d2, ±√(px² + py² − d2²)). The "−" root is written
      π − atan2(d2, √…), equal modulo 2π. On the z0 axis with d2 = 0 θ1 is free: ``theta1_free``
      and ``theta1_free − π`` are used there.
    * θ3, from px² + py² + pz² = d2² + a2² + a3² + 2 a2 a3 c3: θ3 = ±arccos(…), eq. (13).
    * θ23 = θ2 + θ3 = atan2(a2 s3 r − (a3 + a2 c3) pz, (a3 + a2 c3) r + a2 s3 pz), eq. (18),
      with r = c1 px + s1 py (eq. 12). (Eq. 17's printed denominator "px² + (c1 px + s1 py)²"
      should read pz² + (c1 px + s1 py)²; it cancels in the atan2.)
    * θ2 = θ23 − θ3, eq. (19). **Misprint:** the paper prints eq. (19) as "θ1 = θ23 − θ3",
      i.e. with θ1 for θ2; ``tests/test_ik.py`` shows that the printed form gives a wrong
      tool position.
    * θ4 = pitch − θ23: eq. (21) reads θ4 off the tool orientation (the o vector); for the
      orientations this arm can reach, that orientation is the pitch.

    ``position`` is one point ``(3,)`` or a batch ``(..., 3)`` (``pitch`` a scalar or one per
    point). Rows ``out[..., k, :]`` are the four sign combinations (θ1 root +, θ3 +), (+, −),
    (−, +), (−, −); at singular targets some coincide. Angles are not wrapped or checked against
    the joint limits (see :func:`solve`). A position out of reach raises ``ValueError``; only
    for a batch with ``strict=False`` are the unreachable entries NaN instead.
    """
    _positive_lengths(a2=a2, a3=a3)
    if not np.isfinite(d2):
        raise ValueError(f"d2 = {d2} must be a finite length")
    p = as_batch(position, 3, "target")
    pitch = np.asarray(pitch, dtype=float)
    if not np.all(np.isfinite(pitch)):
        raise ValueError(f"pitch = {pitch} is not a finite number")
    pitch = np.broadcast_to(pitch, p.shape[:-1])
    px, py, pz = p[..., 0], p[..., 1], p[..., 2]
    tol = REACH_RTOL * (a2 + a3 + abs(d2))
    rho = np.hypot(px, py)
    in_plane = np.sqrt(np.maximum(px**2 + py**2 + pz**2 - d2**2, 0.0))  # |(r, pz)|: shoulder → wrist in the plane
    too_close = rho < abs(d2) - tol
    too_far = (in_plane > a2 + a3 + tol) | (in_plane < abs(a2 - a3) - tol)
    _unreachable(too_close, p, strict, lambda x: (
        f"target {_fmt(x)} is out of reach of arm4r: its distance from the z0 axis, {np.hypot(x[0], x[1]):.6g} m, "
        f"is less than the offset |d2| = {abs(d2):.6g} m (eq. 9 has no solution)"))
    _unreachable(too_far, p, strict, lambda x: (
        f"target {_fmt(x)} is out of reach of arm4r: √(px²+py²+pz²−d2²) = {np.sqrt(max(x @ x - d2**2, 0)):.6g} m "
        f"must lie in [|a2 − a3|, a2 + a3] = [{abs(a2 - a3):.6g}, {a2 + a3:.6g}] m (eq. 13 has no solution)"))
    h = np.sqrt(np.maximum(rho**2 - d2**2, 0.0))
    azimuth = np.where((rho <= tol) & (abs(d2) <= tol), theta1_free, np.arctan2(py, px))
    offset = np.arctan2(d2, h)
    theta1 = np.stack([azimuth - offset, azimuth - (np.pi - offset)], axis=-1)  # eq. (11), the two roots
    c3 = np.clip((px**2 + py**2 + pz**2 - d2**2 - a2**2 - a3**2) / (2 * a2 * a3), -1.0, 1.0)
    theta3 = np.stack([np.arccos(c3), -np.arccos(c3)], axis=-1)  # eq. (13), the two roots
    t1, t3 = theta1[..., [0, 0, 1, 1]], theta3[..., [0, 1, 0, 1]]
    r = np.cos(t1) * px[..., None] + np.sin(t1) * py[..., None]  # eq. (12): c1 px + s1 py = a2 c2 + a3 c23
    A, B = a3 + a2 * np.cos(t3), a2 * np.sin(t3)
    theta23 = np.arctan2(B * r - A * pz[..., None], A * r + B * pz[..., None])  # eq. (18)
    theta2 = theta23 - t3  # eq. (19), corrected: the paper prints "θ1 = θ23 − θ3"
    theta4 = pitch[..., None] - theta23  # pitch = θ2 + θ3 + θ4 (eq. 21 for the reachable orientations)
    out = np.stack([t1, theta2, t3, theta4], axis=-1)
    out[too_close | too_far] = np.nan
    return out


# --------------------------------------------------------------------------- paper 003
def r2t_ik(
    position: ArrayLike, l1: float, l2: float, l3: float, l4: float, l5: float, strict: bool = True
) -> NDArray[np.float64]:
    """Closed-form inverse kinematics of paper 003's R-T-T robot, shape ``(..., 2, 3)``.

    Eq. (21), corrected (the printed one has stray "c q1"/"s q1" factors):

        p4 = (l3 c1 − (q3 + l4) s1,  l3 s1 + (q3 + l4) c1,  l1 + l2 + q2 − l5),

    so (px, py) = Rz(q1)·(l3, u) with u = q3 + l4 = ±√(px² + py² − l3²), hence

        q1 = atan2(py, px) − atan2(u, l3),   q3 = u − l4,   q2 = pz − l1 − l2 + l5.

    ``position`` is one point ``(3,)`` or a batch ``(..., 3)``. Row 0 takes u ≥ 0 (arm pointing
    out), row 1 u ≤ 0. Strokes are not checked here (see :func:`solve`). A point closer than
    |l3| to the column axis raises ``ValueError``; only for a batch with ``strict=False`` are
    such entries NaN instead.
    """
    for name, value in {"l1": l1, "l2": l2, "l3": l3, "l4": l4, "l5": l5}.items():
        if not np.isfinite(value):
            raise ValueError(f"{name} = {value} must be a finite length")
    p = as_batch(position, 3, "target")
    px, py, pz = p[..., 0], p[..., 1], p[..., 2]
    rho = np.hypot(px, py)
    too_close = rho < abs(l3) - REACH_RTOL * (abs(l3) + abs(l4))
    _unreachable(too_close, p, strict, lambda x: (
        f"target {_fmt(x)} is out of reach of r2t: its distance from the column axis, {np.hypot(x[0], x[1]):.6g} m, "
        f"is less than the arm offset |l3| = {abs(l3):.6g} m"))
    u = np.sqrt(np.maximum(rho**2 - l3**2, 0.0))[..., None] * np.array([1.0, -1.0])
    q1 = np.arctan2(py, px)[..., None] - np.arctan2(u, l3)
    q2 = np.broadcast_to((pz - l1 - l2 + l5)[..., None], u.shape)
    out = np.stack([q1, q2, u - l4], axis=-1)
    out[too_close] = np.nan
    return out


# --------------------------------------------------------------------------- Drake plant
#: Plants built by :func:`drake_arm`, by URDF file, base, tool and joints.
_PLANTS: dict[tuple[str, str, str, tuple[str, ...]], tuple[Any, Any, NDArray]] = {}


def drake_arm(arm: Arm) -> tuple[Any, Any, NDArray]:
    """``(plant, tool_frame, index)`` for ``arm`` (:meth:`Arm.make_plant`): ``q_plant[index] = q_arm``.

    Built once per URDF file and kept: the errata checks query it many times.
    """
    key = (arm.urdf_key, arm.base_link, arm.tool_name, tuple(arm.joint_names))
    if key not in _PLANTS:
        plant = arm.make_plant()
        index = np.array([plant.GetJointByName(name).position_start() for name in arm.joint_names])
        _PLANTS[key] = (plant, plant.GetFrameByName(arm.tool_name), index)
    return _PLANTS[key]


# --------------------------------------------------------------------------- numeric
def pose(position: ArrayLike, rpy: ArrayLike) -> NDArray[np.float64]:
    """The 4×4 pose with origin ``position`` (m, (3,)) and rotation R = Rz(y)·Ry(p)·Rx(r), ``rpy`` = (r, p, y) in rad.

    The URDF convention: roll about x, then pitch about y, then yaw about z, all about the fixed axes.
    """
    values = np.asarray(rpy, dtype=float)
    if values.shape != (3,) or not np.all(np.isfinite(values)):
        raise ValueError(f"rpy {np.ravel(values).tolist()} must be 3 finite angles (roll, pitch, yaw)")
    check_range(values, "rpy", key="angle")
    r, p, y = values
    return homogeneous((T_Z6(y) @ T_Z5(p) @ T_Z4(r))[:3, :3], _single(position, 3, "position"))


def rotation_log(R: ArrayLike) -> NDArray[np.float64]:
    """The rotation vector ω = θ·u (rad) with exp([ω]×) = R, |ω| ≤ π, shape ``(..., 3)`` for ``(..., 3, 3)``.

    With v = vee(R − Rᵀ)/2 = sin θ·u and cos θ = (tr R − 1)/2, θ = atan2(|v|, cos θ). For
    cos θ ≥ 0, ω = (θ / sin θ)·v; beyond π/2 (where v loses accuracy) u is read from
    R + Rᵀ = 2 cos θ·I + 2 (1 − cos θ) u uᵀ, its column of largest diagonal, signed like v.
    Accurate to round-off for every angle, including θ → 0 and θ → π.
    """
    R = np.asarray(R, dtype=float)
    v = 0.5 * np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]], -1)
    s = np.linalg.norm(v, axis=-1)
    c = np.clip((np.trace(R, axis1=-2, axis2=-1) - 1.0) / 2.0, -1.0, 1.0)
    theta = np.arctan2(s, c)
    regular = np.where(s > 0, theta / np.where(s > 0, s, 1.0), 1.0)[..., None] * v  # θ/sin θ → 1 as θ → 0
    obtuse = np.where(c < 0, c, -1.0)[..., None, None]  # only used where cos θ < 0, so 1 − cos θ ≥ 1
    M = (R + np.swapaxes(R, -1, -2) - 2.0 * obtuse * np.eye(3)) / (2.0 * (1.0 - obtuse))  # u uᵀ there
    k = np.argmax(np.diagonal(M, axis1=-2, axis2=-1), axis=-1)
    column = np.take_along_axis(M, k[..., None, None], axis=-1)[..., 0]
    u = column / np.sqrt(np.take_along_axis(np.diagonal(M, axis1=-2, axis2=-1), k[..., None], axis=-1))
    u = np.where((np.sum(u * v, axis=-1) < 0)[..., None], -u, u)
    return np.where((c < 0)[..., None], theta[..., None] * u, regular)


#: Starts of the numerical solver, solved as one batch: the first is ``near``, the rest random within limits.
SEEDS = 256
#: A returned solution's tool orientation must match a pose target to this angle (rad).
ORIENTATION_TOL = 1e-9
#: Numerical solutions closer than this (rad or m, revolute joints modulo 2π) are the same solution.
DISTINCT_TOL = 1e-6
#: Levenberg–Marquardt iterations at most, then Newton polishing steps at most.
LM_ITERATIONS, NEWTON_STEPS = 200, 8


def _pose_error(arm: Arm, position: NDArray, rotation: NDArray | None, q: NDArray) -> NDArray[np.float64]:
    """Tool pose error ``(..., 3)`` or ``(..., 6)`` by the arm's own FK: [target − p(q); log(R* R(q)ᵀ)], world frame."""
    T = arm.forward(q).tool
    error = position - T[..., :3, 3]
    if rotation is None:
        return error
    return np.concatenate([error, rotation_log(rotation @ np.swapaxes(T[..., :3, :3], -1, -2))], axis=-1)


def _project(arm: Arm, q: NDArray, lower: NDArray, upper: NDArray) -> NDArray[np.float64]:
    """``q`` moved into the limits: a revolute angle by a 2π shift when one fits, else clipped onto the limit."""
    base = np.where(np.isfinite(lower), lower, 0.0)
    shifted = base + np.mod(q - base, 2 * np.pi)  # in [lower, lower + 2π)
    shift = arm.revolute & ((q < lower) | (q > upper)) & (shifted <= upper)
    return np.clip(np.where(shift, shifted, q), lower, upper)


def _jacobian_rows(arm: Arm, q: NDArray, rows: int) -> NDArray[np.float64]:
    """The tool Jacobian's first ``rows`` rows (3: linear velocity; 6: [v; ω]), world frame, ``(..., rows, n)``."""
    from armlab.kinematics.differential import jacobian

    return jacobian(arm, q)[..., :rows, :]


def _levenberg_marquardt(
    arm: Arm, position: NDArray, rotation: NDArray | None, q: NDArray, lower: NDArray, upper: NDArray
) -> tuple[NDArray, NDArray]:
    """Damped least squares on the tool pose error, every start ``q`` ``(S, n)`` at once; returns (q, error).

    Each start takes the step (JᵀJ + λI) δ = Jᵀe, projected into the limits (:func:`_project`); a
    joint at a limit that the step would push beyond it is held (its column of J dropped). A step
    that lowers |e| is kept and λ divided by 3, else λ is multiplied by 4. A start stops when it
    reaches the target (|e|² < 1e-26), when it is stationary (|Jᵀe| ≤ 1e-6 |J| |e| over the joints
    not held: a local minimum of |e| within the limits, the closest the tool gets from there) or
    when no step lowers |e| (λ ≥ 1e10). Only the starts still running are computed.
    """
    rows = 3 if rotation is None else 6
    q = q.copy()
    error = _pose_error(arm, position, rotation, q)
    cost = np.einsum("...i,...i", error, error)
    damping = np.full(q.shape[0], 1e-3)
    running = np.arange(q.shape[0])
    for _ in range(LM_ITERATIONS):
        J = _jacobian_rows(arm, q[running], rows)
        Jt = np.swapaxes(J, -1, -2)
        gradient = (Jt @ error[running, :, None])[..., 0]
        held = ((q[running] <= lower) & (gradient < 0)) | ((q[running] >= upper) & (gradient > 0))  # by a limit
        gradient = np.where(held, 0.0, gradient)
        stationary = np.linalg.norm(gradient, axis=-1) <= 1e-6 * np.linalg.norm(J, axis=(-2, -1)) * np.sqrt(
            cost[running])
        J = np.where(held[:, None, :], 0.0, J)  # a joint held by its limit takes no part in the step
        Jt = np.swapaxes(J, -1, -2)
        if rows < arm.n:  # the same step as Jᵀ(JJᵀ + λI)⁻¹e: a rows × rows system instead of n × n
            A = J @ Jt + damping[running, None, None] * np.eye(rows)
            step = (Jt @ np.linalg.solve(A, error[running, :, None]))[..., 0]
        else:
            A = Jt @ J + damping[running, None, None] * np.eye(arm.n)
            step = np.linalg.solve(A, gradient[..., None])[..., 0]
        trial = _project(arm, q[running] + step, lower, upper)
        trial_error = _pose_error(arm, position, rotation, trial)
        trial_cost = np.einsum("...i,...i", trial_error, trial_error)
        better = trial_cost < cost[running]
        accepted = running[better]
        q[accepted], error[accepted], cost[accepted] = trial[better], trial_error[better], trial_cost[better]
        damping[running] = np.clip(np.where(better, damping[running] / 3, damping[running] * 4), 1e-12, 1e10)
        done = (cost[running] < 1e-26) | stationary | (damping[running] >= 1e10)
        running = running[~done]
        if running.size == 0:
            break
    return q, error


def _newton(
    arm: Arm, position: NDArray, rotation: NDArray | None, q: NDArray, lower: NDArray, upper: NDArray
) -> tuple[NDArray, NDArray]:
    """Newton steps q ← q + J⁺e (least-norm for a redundant request), kept within limits; returns (q, error)."""
    rows = 3 if rotation is None else 6
    error = _pose_error(arm, position, rotation, q)
    for _ in range(NEWTON_STEPS):
        if np.abs(error).max(initial=0.0) < 1e-15:
            break
        step = np.linalg.pinv(_jacobian_rows(arm, q, rows), rcond=1e-10) @ error[..., None]
        trial = _project(arm, q + step[..., 0], lower, upper)
        trial_error = _pose_error(arm, position, rotation, trial)
        better = np.linalg.norm(trial_error, axis=-1) < np.linalg.norm(error, axis=-1)
        q, error = np.where(better[:, None], trial, q), np.where(better[:, None], trial_error, error)
    return q, error


def _starts(arm: Arm, q0: NDArray, seeds: int) -> NDArray[np.float64]:
    """``q0`` and ``seeds − 1`` deterministic random starts within the limits (unlimited joints: (−π, π])."""
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    random = np.random.default_rng(0).uniform(lower, upper, size=(seeds - 1, arm.n))
    first = _project(arm, fit_limits(arm, q0[None, :], q0)[0][0], *arm.limit_arrays())  # unlimited: (−π, π]
    return np.vstack([first[None, :], random])


def _search(
    arm: Arm, position: NDArray, rotation: NDArray | None, starts: NDArray, limited: bool
) -> tuple[NDArray, NDArray]:
    """(solutions reaching the target to 1e-9 m and 1e-9 rad, error of every start) from ``starts``."""
    lower, upper = arm.limit_arrays() if limited else (np.full(arm.n, -np.inf), np.full(arm.n, np.inf))
    q, error = _levenberg_marquardt(arm, position, rotation, starts, lower, upper)
    close = np.linalg.norm(error, axis=-1) < 1e-5
    q, polished = _newton(arm, position, rotation, q[close], lower, upper)
    error[close] = polished
    reached = (np.linalg.norm(polished[:, :3], axis=-1) <= POSITION_TOL) & (
        np.linalg.norm(polished[:, 3:], axis=-1) <= ORIENTATION_TOL)
    return q[reached], error


def numeric_ik(
    arm: Arm, position: ArrayLike, rotation: ArrayLike | None = None, q0: ArrayLike | None = None,
    seeds: int = SEEDS,
) -> NDArray[np.float64]:
    """Joint values ``(k, n)`` putting ``arm``'s tool at ``position`` (and orientation ``rotation``), any arm.

    A multi-start damped least squares (Levenberg–Marquardt) on the tool pose error
    [target − p(q); log(R* R(q)ᵀ)] (m, rad; :func:`rotation_log`) with the arm's geometric
    Jacobian (:func:`armlab.kinematics.differential.jacobian`), from ``q0`` (default zeros)
    and ``seeds − 1`` deterministic random starts within the joint limits, all solved as one
    batch and kept within the limits (revolute angles shifted by 2π, else clipped). Each
    converged start is polished by Newton steps and kept only if the arm's own forward
    kinematics (``arm.forward``) reaches the target to 1e-9 m and 1e-9 rad. One row per
    start that succeeded, duplicates included (:func:`solve` removes them): every solution
    *found* — a redundant request (fewer constraints than joints) has infinitely many.

    ``ValueError`` naming the target if no start succeeds: "reachable only outside the joint
    limits" if the search without limits succeeds; else the closest distance the tool gets to
    the position (the minimum of |p(q) − target| over the limits, from the same starts), or,
    for a pose whose position is reachable, the closest pose found.
    """
    position = _single(position, 3)
    if rotation is not None:
        _, rotation = _check_pose(homogeneous(rotation, position))
    q0 = np.zeros(arm.n) if q0 is None else _single(q0, arm.n, "q0")
    if not (isinstance(seeds, int) and seeds >= 1):
        raise ValueError(f"seeds = {seeds!r} must be a positive whole number")
    starts = _starts(arm, q0, seeds)
    found, error = _search(arm, position, rotation, starts, limited=True)
    if found.shape[0]:
        return found
    what = _target_text(position, rotation)
    lower, upper = arm.limit_arrays()
    if np.isfinite(lower).any() or np.isfinite(upper).any():
        free, _ = _search(arm, position, rotation, starts, limited=False)
        if free.shape[0]:
            fitted, violations = fit_limits(arm, free, q0)
            inside = [v is None for v in violations]
            if any(inside):
                return fitted[inside]
            raise ValueError(_outside_limits_message(arm, what, violations))
    if rotation is not None:
        _, position_error = _search(arm, position, None, starts, limited=True)
        if np.linalg.norm(position_error, axis=-1).min() <= POSITION_TOL:
            best = error[np.argmin(np.linalg.norm(error, axis=-1))]
            raise ValueError(
                f"{what} is out of reach of {arm.name}: its position is reachable, but not with this "
                f"orientation (the closest pose found from {seeds} starts is {np.linalg.norm(best[:3]):.3g} m and "
                f"{np.linalg.norm(best[3:]):.3g} rad away)")
        error = position_error
    closest = float(np.linalg.norm(error[:, :3], axis=-1).min())
    raise ValueError(f"{what} is out of reach of {arm.name}: the tool gets no closer than {closest:.6g} m to it "
                     f"(the minimum of |p(q) − target| within the joint limits, from {seeds} starts)")


def _target_text(position: NDArray, rotation: NDArray | None) -> str:
    """``target (x, y, z)``, or for a pose ``target pose (x, y, z) m, rpy (r, p, y) rad``."""
    if rotation is None:
        return f"target {_fmt(position)}"
    return f"target pose {_fmt(position)} m, rpy {_fmt(orientation_angles(rotation) + 0.0)} rad"  # + 0.0: no −0


# --------------------------------------------------------------------------- limits
def fit_limits(arm: Arm, q: ArrayLike, near: ArrayLike | None = None) -> tuple[NDArray, list[tuple | None]]:
    """Fit solutions ``(k, n)`` into ``arm``'s joint limits by 2π shifts of revolute angles.

    A limited revolute angle becomes the q + 2πm within [lower, upper] nearest ``near``
    (ties keep the smaller shift); an unlimited one is wrapped to (−π, π]; a prismatic value
    is left as is. Values within round-off (1e-12) of a limit are clipped onto it.

    Returns the fitted array and, per solution, ``None`` if it is within limits or else
    ``(joint index, value, lower, upper)`` of its first joint that cannot be fitted.
    """
    q = np.array(q, dtype=float, ndmin=2)
    near = np.zeros(arm.n) if near is None else np.asarray(near, dtype=float)
    ok = np.ones(q.shape[:-1], dtype=bool)
    first: list[tuple | None] = [None] * q.shape[0]
    two_pi = 2 * np.pi
    for i, (lim, revolute) in enumerate(zip(arm.limits, arm.revolute, strict=True)):
        values = q[:, i]
        if lim.lower is None:
            if revolute:
                wrapped = values - two_pi * np.ceil((values - np.pi) / two_pi)  # (−π, π] up to round-off:
                q[:, i] = np.where(wrapped > np.pi, wrapped - two_pi, np.where(wrapped <= -np.pi, wrapped + two_pi,
                                                                               wrapped))  # exactly
            continue
        lo, hi = lim.lower - 1e-12, lim.upper + 1e-12
        if revolute:
            m_lo, m_hi = np.ceil((lo - values) / two_pi), np.floor((hi - values) / two_pi)
            m = np.clip(np.round((near[i] - values) / two_pi), m_lo, m_hi)
            fits = m_lo <= m_hi
            shifted = values + two_pi * np.where(fits, m, 0.0)
        else:
            fits = (values >= lo) & (values <= hi)
            shifted = values
        q[:, i] = np.where(fits, np.clip(shifted, lim.lower, lim.upper), values)
        for k in np.flatnonzero(~fits & ok):
            first[k] = (i, float(values[k]), lim.lower, lim.upper)
        ok &= fits
    return q, first


def _outside_limits_message(arm: Arm, target: str, violations: list[tuple | None]) -> str:
    parts = []
    for i, value, lo, hi in (v for v in violations if v is not None):
        if arm.revolute[i]:
            parts.append(f"{arm.joint_names[i]} = {np.degrees(value):.6g}° outside [{np.degrees(lo):.6g}°, "
                         f"{np.degrees(hi):.6g}°] even after 2π shifts")
        else:
            parts.append(f"{arm.joint_names[i]} = {value:.6g} m outside [{lo:.6g}, {hi:.6g}] m")
    return (f"{target} is reachable by {arm.name} only outside its joint limits: "
            + "; ".join(dict.fromkeys(parts)))


# --------------------------------------------------------------------------- dispatcher
#: Arms with a closed-form inverse kinematics in this module (by ``arm.name``).
ANALYTIC_ARMS = ("rr", "arm4r", "r2t")


def _analytic(arm: Arm) -> bool:
    """True for the paper arms rr, arm4r, r2t (a user arm merely named so is solved numerically)."""
    if arm.name not in ANALYTIC_ARMS:
        return False
    from armlab.models import ARMS

    return arm.paper == ARMS[arm.name].PAPER


def _check_pose(T: NDArray) -> tuple[NDArray, NDArray]:
    """(position, rotation) of a 4×4 pose; ``ValueError`` unless homogeneous with a proper rotation (to 1e-9)."""
    _single(T.ravel(), 16, "target")
    R = T[:3, :3]
    if np.abs(T[3] - [0.0, 0.0, 0.0, 1.0]).max() > 0:
        raise ValueError(f"target pose's last row {T[3].tolist()} must be [0, 0, 0, 1]")
    deviation = np.abs(R.T @ R - np.eye(3)).max()
    if deviation > 1e-9:
        raise ValueError(f"target pose's rotation {R.tolist()} is not orthonormal (|RᵀR − I| = {deviation:.3g} "
                         "> 1e-9): give it to full precision")
    if np.linalg.det(R) < 0:
        raise ValueError(f"target pose's rotation {R.tolist()} has determinant −1 (a reflection); a rotation has +1")
    return T[:3, 3], R


def _target(arm: Arm, target: ArrayLike) -> tuple[NDArray, NDArray | None]:
    """(position (3,), rotation (3, 3) or None) of a position or 4×4 pose target, checked."""
    t = np.asarray(target, dtype=float)
    position, rotation = _check_pose(t) if t.shape == (4, 4) else (t, None)
    if arm.name == "rr" and _analytic(arm):
        position = np.append(planar_target(position), 0.0)
    elif position.shape != (3,):
        raise ValueError(f"target {np.ravel(position).tolist()} has {position.size} values; {arm.name} takes "
                         "3 coordinates (x,y,z in m) or a 4×4 pose")
    position = _single(position, 3)
    for axis, value in zip("xyz", position, strict=True):
        check_range(value, f"target {axis}", key="coordinate")
    return position, rotation


def target_pose(arm: Arm, position: ArrayLike, rpy: ArrayLike) -> NDArray[np.float64]:
    """The 4×4 pose target of ``position`` as :func:`solve` takes it for ``arm`` (rr: x,y or x,y,0) and ``rpy``
    (rad, R = Rz(y)·Ry(p)·Rx(r), :func:`pose`)."""
    return pose(_target(arm, position)[0], rpy)


def _closed_form(arm: Arm, position: NDArray, rotation: NDArray | None, pitch: float | None,
                 near: NDArray) -> NDArray[np.float64]:
    """Every branch of the paper arm's closed form reaching ``position`` (and ``rotation``), shape ``(k, n)``.

    The closed forms take a position (arm4r: and the pitch). For a pose, arm4r's θ1 and pitch are read
    off the rotation R04 = Rz(θ1)·Rx(−90°)·Rz(pitch) (tool z axis (−s1, c1, 0)); the branches are then
    kept whose tool orientation (by ``arm.forward``) matches the target's to 1e-9 rad.
    """
    prm = arm.parameters
    if arm.name == "rr":
        candidates = rr_ik(position[:2], prm["L1"], prm["L2"])
    elif arm.name == "arm4r":
        theta1_free = float(near[0])
        if rotation is not None:
            if pitch is not None:
                raise ValueError(f"a pitch (here {pitch:.6g} rad) is not allowed with a pose target: the pose sets "
                                 "the tool pitch")
            theta1_free = float(np.arctan2(-rotation[0, 2], rotation[1, 2]))
            c1, s1 = np.cos(theta1_free), np.sin(theta1_free)
            pitch = float(np.arctan2(-rotation[2, 0], c1 * rotation[0, 0] + s1 * rotation[1, 0]))
        pitch = 0.0 if pitch is None else float(pitch)
        candidates = arm4r_ik(position, pitch, prm["a2"], prm["a3"], prm["d2"], theta1_free=theta1_free)
    else:
        candidates = r2t_ik(position, prm["l1"], prm["l2"], prm["l3"], prm["l4"], prm["l5"])
    if rotation is None:
        return candidates
    miss = np.linalg.norm(_pose_error(arm, position, rotation, candidates)[:, 3:], axis=-1)
    if not np.any(miss <= ORIENTATION_TOL):
        raise ValueError(f"{_target_text(position, rotation)} is out of reach of {arm.name}: its position is "
                         f"reachable, but not with this orientation (the {len(miss)} branches of the closed form "
                         f"reaching it miss the orientation by {miss.min():.3g} rad at least)")
    return candidates[miss <= ORIENTATION_TOL]


def _joint_difference(arm: Arm, q: NDArray, near: NDArray) -> NDArray[np.float64]:
    """``q − near``, for an unlimited revolute joint taken modulo 2π into [−π, π) (its angle is wrapped anyway)."""
    unlimited = arm.revolute & np.isinf(arm.limit_arrays()[0])
    d = q - near
    return np.where(unlimited, np.remainder(d + np.pi, 2 * np.pi) - np.pi, d)


def _distinct(arm: Arm, q: NDArray, tol: float) -> NDArray[np.float64]:
    """The rows of ``q`` ``(k, n)`` that differ from every earlier row by more than ``tol`` (revolute: modulo 2π)."""
    keep: list[int] = []
    for i in range(q.shape[0]):
        d = q[keep] - q[i]
        d = np.where(arm.revolute, np.remainder(d + np.pi, 2 * np.pi) - np.pi, d)
        if not keep or np.abs(d).max(axis=-1).min() > tol:
            keep.append(i)
    return q[keep]


def solve(
    arm: Arm,
    target: ArrayLike,
    pitch: float | None = None,
    near: ArrayLike | None = None,
    all_solutions: bool = False,
    seeds: int = SEEDS,
) -> list[NDArray[np.float64]]:
    """Joint values reaching ``target`` within ``arm``'s joint limits, nearest to ``near`` first.

    ``target`` is a tool position (3,) in m (rr: (x, y) or (x, y, 0)) or a full tool pose,
    a 4×4 homogeneous matrix (its rotation orthonormal with determinant +1, to 1e-9).

    * ``rr``: :func:`rr_ik`, 2 branches — the arm moves in z = 0.
    * ``arm4r``: :func:`arm4r_ik`, 4 branches, with ``pitch`` = θ2 + θ3 + θ4 (rad); **pitch = 0 if
      not given** (tool x axis horizontal, the "stretched" state of paper 001's simulation).
    * ``r2t``: :func:`r2t_ik`, 2 branches.
    * For a pose the paper arms' branches are kept whose orientation matches (:func:`_closed_form`).
    * any other arm (urm6, rrrr, users' arms): :func:`numeric_ik` from ``near`` and ``seeds − 1``
      random starts: every distinct solution *found* (a redundant request has infinitely many).

    Every solution is fitted into the joint limits by :func:`fit_limits`; those that do not fit
    are dropped, duplicates (revolute joints modulo 2π) removed, and the rest sorted by Euclidean
    joint distance to ``near`` (default zeros; an unlimited revolute joint's difference taken modulo
    2π). Each is checked by the arm's own FK to reach the target to 1e-9 m (and 1e-9 rad). Returns
    every solution if ``all_solutions``, else ``[best]``. ``ValueError`` (naming the bad value) for a
    wrong number of coordinates, NaN/inf, a coordinate beyond ±1e6 m or a pitch or ``near`` beyond
    ±1e6, a matrix that is not a pose, a pitch for an arm other than arm4r (or with a pose), an
    unreachable target (with the closest distance), or a target reachable only outside the joint
    limits (naming the joint and its limits).
    """
    position, rotation = _target(arm, target)
    near = np.zeros(arm.n) if near is None else _single(near, arm.n, "near")
    check_range(near, "near", key="q")
    if pitch is not None and not (arm.name == "arm4r" and _analytic(arm)):
        raise ValueError(f"pitch = {pitch} applies only to arm4r (its tool pitch θ2+θ3+θ4), not to {arm.name}")
    if pitch is not None:
        if np.isfinite(pitch):  # NaN/inf: arm4r_ik names them as such
            check_range(pitch, "pitch", key="angle")
    if _analytic(arm):
        candidates, tol = _closed_form(arm, position, rotation, pitch, near), SAME_SOLUTION_TOL
    else:
        candidates, tol = numeric_ik(arm, position, rotation, q0=near, seeds=seeds), DISTINCT_TOL
    fitted, violations = fit_limits(arm, candidates, near)
    kept = fitted[[v is None for v in violations]]
    if kept.shape[0] == 0:
        raise ValueError(_outside_limits_message(arm, _target_text(position, rotation), violations))
    error = _pose_error(arm, position, rotation, kept)  # the last word: the arm's own FK of what is returned
    miss = np.maximum(np.linalg.norm(error[:, :3], axis=-1) / POSITION_TOL,
                      np.linalg.norm(error[:, 3:], axis=-1) / ORIENTATION_TOL)
    if not np.any(miss <= 1.0):
        raise ValueError(f"{_target_text(position, rotation)}: no solution of {arm.name} reaches it to "
                         f"{POSITION_TOL:g} m and {ORIENTATION_TOL:g} rad (the closest misses by "
                         f"{np.linalg.norm(error[np.argmin(miss)]):.3g})")
    kept = kept[miss <= 1.0]
    unique = sorted(_distinct(arm, kept, tol), key=lambda q: float(np.linalg.norm(_joint_difference(arm, q, near))))
    return unique if all_solutions else unique[:1]
