"""The papers' closed-form inverse kinematics, each a function of its paper's parameters.

* :func:`rr_ik` — paper 000, the planar two-link arm of Fig. 1/Fig. 2, by the law of
  cosines applied to eqs. (1)–(2) in its half-angle form; both elbow branches.
* :func:`arm4r_ik` — paper 001, the analytical ("inverse transform") method, eqs. (9)–(21).
* :func:`r2t_ik` — paper 003, the tool position p4 of eq. (21) (as corrected in
  :mod:`armlab.models.r2t`) solved for q1, q2, q3.

Each arm's module hands its own to the dispatcher (:attr:`armlab.models.arm.Arm.closed_form`);
:func:`armlab.kinematics.ik.solve` fits the branches into the joint limits and orders them.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import below, outside
from armlab.kinematics.batch import as_batch
from armlab.kinematics.ik_target import fmt, single
from armlab.values import shown

__all__ = ["ClosedForm", "arm4r_ik", "planar_target", "r2t_ik", "rr_ik"]


@dataclass(frozen=True)
class ClosedForm:
    """A paper's closed-form inverse kinematics of one arm, its parameters bound.

    ``solve(position, rotation, near, **options)`` gives every branch reaching the tool position
    ``position`` (3,) m, shape ``(len(branches), n)``, in the order of ``branches``, not fitted into the
    joint limits; ``rotation`` (3, 3) (a pose target) or ``None`` and ``near`` (n,) are there for a
    closed form that uses them (arm4r reads θ1 and its pitch off the rotation; on the z0 axis its θ1 is
    ``near``'s); ``ValueError`` for an unreachable position. The dispatcher keeps the branches whose
    orientation matches a pose target.
    """

    solve: Callable[..., NDArray[np.float64]]
    #: What each branch is, in ``solve``'s order (their number is the branch count): rr ("θ2 ≥ 0", "θ2 ≤ 0").
    branches: tuple[str, ...]
    #: Extra keyword arguments ``solve`` takes, and what each is: arm4r {"pitch": "its tool pitch θ2+θ3+θ4"}.
    options: Mapping[str, str] = field(default_factory=dict)
    #: A position target as the user gives it → the coordinates the closed form takes, the rest of the tool
    #: position being 0 (rr: x,y or x,y,0 → (x, y)); ``None``: x, y, z.
    coordinates: Callable[[NDArray], NDArray[np.float64]] | None = None
    #: Whether a user may choose a branch by its number (rr: paper 000's Table 2 names the elbow of each point).
    selectable: bool = False
    #: Whether it solves a full pose only (a six-axis arm's: ``rotation`` must be given); a position target is then
    #: solved as :func:`armlab.kinematics.ik.solve` says for a continuum.
    needs_pose: bool = False

#: A target this close to arm4r's z0 axis, relative to the arm's size (m/m), with |d2| as small, has no azimuth
#: of its own: θ1 is free there (a switch between two formulas; the reach is decided by :mod:`armlab.bounds`).
ON_AXIS_RTOL = 1e-12


def _positive_lengths(**lengths: float) -> None:
    for name, value in lengths.items():
        if not np.isfinite(value) or value <= 0:
            raise ValueError(f"{name} = {value} must be a positive finite length")


def planar_target(target: ArrayLike) -> NDArray[np.float64]:
    """The rr arm's target as (x, y): given as x,y or as x,y,0 (the arm moves in the plane z = 0)."""
    p = np.asarray(target, dtype=float)
    if p.shape == (3,):
        if p[2] != 0.0:
            raise ValueError(f"target z = {p[2]:g} is not allowed: the rr arm moves in the plane z = 0")
        p = p[:2]
    if p.shape != (2,):
        raise ValueError(f"target {shown(np.ravel(p).tolist())} has {p.size} values; rr takes x,y (or x,y,0) in m")
    return single(p, 2)


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
    unreachable = outside(distance, inner, outer)
    _unreachable(unreachable, p, strict, lambda xy: (
        f"target {fmt(xy)} is out of reach of the RR arm: |target| = {np.hypot(*xy):.6g} m, "
        f"reachable annulus {inner:.6g} m ≤ |target| ≤ {outer:.6g} m"))
    r = np.clip(distance, inner, outer)  # round-off beyond a rim: onto it (beyond that: NaN below)
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
    the joint limits (see :func:`armlab.kinematics.ik.solve`). A position out of reach raises ``ValueError``; only
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
    rho = np.hypot(px, py)
    in_plane = np.sqrt(np.maximum(px**2 + py**2 + pz**2 - d2**2, 0.0))  # |(r, pz)|: shoulder → wrist in the plane
    too_close = below(rho, abs(d2))
    too_far = outside(in_plane, abs(a2 - a3), a2 + a3)
    _unreachable(too_close, p, strict, lambda x: (
        f"target {fmt(x)} is out of reach of arm4r: its distance from the z0 axis, {np.hypot(x[0], x[1]):.6g} m, "
        f"is less than the offset |d2| = {abs(d2):.6g} m (eq. 9 has no solution)"))
    _unreachable(too_far, p, strict, lambda x: (
        f"target {fmt(x)} is out of reach of arm4r: √(px²+py²+pz²−d2²) = {np.sqrt(max(x @ x - d2**2, 0)):.6g} m "
        f"must lie in [|a2 − a3|, a2 + a3] = [{abs(a2 - a3):.6g}, {a2 + a3:.6g}] m (eq. 13 has no solution)"))
    h = np.sqrt(np.maximum(rho**2 - d2**2, 0.0))
    axis = ON_AXIS_RTOL * (a2 + a3 + abs(d2))
    azimuth = np.where((rho <= axis) & (abs(d2) <= axis), theta1_free, np.arctan2(py, px))
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
    out), row 1 u ≤ 0. Strokes are not checked here (see :func:`armlab.kinematics.ik.solve`). A point closer than
    |l3| to the column axis raises ``ValueError``; only for a batch with ``strict=False`` are
    such entries NaN instead.
    """
    for name, value in {"l1": l1, "l2": l2, "l3": l3, "l4": l4, "l5": l5}.items():
        if not np.isfinite(value):
            raise ValueError(f"{name} = {value} must be a finite length")
    p = as_batch(position, 3, "target")
    px, py, pz = p[..., 0], p[..., 1], p[..., 2]
    rho = np.hypot(px, py)
    too_close = below(rho, abs(l3))
    _unreachable(too_close, p, strict, lambda x: (
        f"target {fmt(x)} is out of reach of r2t: its distance from the column axis, {np.hypot(x[0], x[1]):.6g} m, "
        f"is less than the arm offset |l3| = {abs(l3):.6g} m"))
    u = np.sqrt(np.maximum(rho**2 - l3**2, 0.0))[..., None] * np.array([1.0, -1.0])
    q1 = np.arctan2(py, px)[..., None] - np.arctan2(u, l3)
    q2 = np.broadcast_to((pz - l1 - l2 + l5)[..., None], u.shape)
    out = np.stack([q1, q2, u - l4], axis=-1)
    out[too_close] = np.nan
    return out
