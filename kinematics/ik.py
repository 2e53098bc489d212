"""Inverse kinematics: the papers' closed forms, Drake's numeric IK, and one dispatcher.

* :func:`rr_ik` — paper 000, the planar two-link arm of Fig. 1/Fig. 2, by the law of
  cosines applied to eqs. (1)–(2); both elbow branches.
* :func:`arm4r_ik` — paper 001, the analytical ("inverse transform") method, eqs. (9)–(21).
* :func:`r2t_ik` — paper 003, the tool position p4 of eq. (21) (as corrected in
  :mod:`armlab.models.r2t`) solved for q1, q2, q3.
* :func:`numeric_ik` — any arm (urm6, users' arms): Drake's ``InverseKinematics`` with a
  position constraint on the tool frame, several seeds, a Newton polish and a check by
  the arm's own forward kinematics.
* :func:`solve` — what ``armlab ik`` calls: picks the method, fits every angle into the
  joint limits, drops, deduplicates and orders the solutions (nearest to ``near`` first).

Unreachable targets and targets reachable only outside the joint limits raise
``ValueError`` naming the target (paper 001: "some of the possible solutions … can not be
realized because of the structure limitation … the nearest set of solution will be chosen").
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import as_batch

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = [
    "ANALYTIC_ARMS",
    "arm4r_ik",
    "drake_arm",
    "fit_limits",
    "numeric_ik",
    "planar_target",
    "r2t_ik",
    "rr_ik",
    "solve",
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
    cosines x² + y² = L1² + L2² + 2 L1 L2 cos θ2, so

        θ2 = ±arccos((x² + y² − L1² − L2²) / (2 L1 L2)),
        θ1 = atan2(y, x) − atan2(L2 sin θ2, L1 + L2 cos θ2).

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
    c2 = np.clip((x**2 + y**2 - L1**2 - L2**2) / (2 * L1 * L2), -1.0, 1.0)  # law of cosines
    theta2 = np.stack([np.arccos(c2), -np.arccos(c2)], axis=-1)  # branch 0: θ2 ≥ 0, branch 1: θ2 ≤ 0
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


# --------------------------------------------------------------------------- numeric (Drake)
#: Plants built by :func:`drake_arm`, by URDF file, base, tool and joints.
_PLANTS: dict[tuple[str, str, str, tuple[str, ...]], tuple[Any, Any, NDArray]] = {}


def drake_arm(arm: Arm) -> tuple[Any, Any, NDArray]:
    """``(plant, tool_frame, index)`` for ``arm`` (:meth:`Arm.make_plant`): ``q_plant[index] = q_arm``.

    Built once per URDF file and kept: IK and the errata checks query it many times.
    """
    key = (arm.urdf_key, arm.base_link, arm.tool_name, tuple(arm.joint_names))
    if key not in _PLANTS:
        plant = arm.make_plant()
        index = np.array([plant.GetJointByName(name).position_start() for name in arm.joint_names])
        _PLANTS[key] = (plant, plant.GetFrameByName(arm.tool_name), index)
    return _PLANTS[key]


def numeric_ik(
    arm: Arm, position: ArrayLike, q0: ArrayLike | None = None, seeds: int = 12
) -> NDArray[np.float64]:
    """Joint values ``(n,)`` putting ``arm``'s tool frame origin at ``position``, by Drake.

    ``pydrake.multibody.inverse_kinematics.InverseKinematics`` with ``AddPositionConstraint``
    on the tool frame (bounds ±1e-10 m), the joint limits, and a quadratic cost ‖q − q0‖²
    (so that a redundant arm moves least from ``q0``), solved by ``pydrake.solvers.Solve``
    from ``q0`` (default zeros) and then ``seeds − 1`` deterministic random seeds within
    the limits (unlimited joints: (−π, π]). Each result is polished by Gauss–Newton steps
    on Drake's translational Jacobian and accepted only if the arm's own forward
    kinematics (``arm.forward``, independent of Drake) puts the tool within 1e-9 m of
    the target. If no seed succeeds, the search is repeated without joint limits: a
    success there raises "reachable only outside the joint limits", else the target is
    reported unreachable (``ValueError`` naming it in both cases).
    """
    target = _single(position, 3)
    q0 = np.zeros(arm.n) if q0 is None else _single(q0, arm.n, "q0")
    lower, upper = arm.limit_arrays()
    rng = np.random.default_rng(0)
    box_lo, box_hi = np.where(np.isfinite(lower), lower, -np.pi), np.where(np.isfinite(upper), upper, np.pi)
    starts = [np.clip(q0, lower, upper)] + [rng.uniform(box_lo, box_hi) for _ in range(seeds - 1)]
    q, miss = _drake_search(arm, target, q0, starts, with_limits=True)
    if q is not None:
        return q
    if np.all(np.isinf(lower)) and np.all(np.isinf(upper)):
        raise ValueError(f"target {_fmt(target)} is out of reach of {arm.name}: {_no_solution(seeds, miss)}")
    q_free, _ = _drake_search(arm, target, q0, starts, with_limits=False)
    if q_free is None:
        raise ValueError(f"target {_fmt(target)} is out of reach of {arm.name}: {_no_solution(seeds, miss)}")
    fitted, violation = fit_limits(arm, q_free[None, :], q0)
    if violation[0] is not None:
        raise ValueError(_outside_limits_message(arm, target, violation))
    return fitted[0]


def _no_solution(seeds: int, miss: float) -> str:
    return f"no solution from {seeds} seeds (closest miss {miss:.3g} m)"


def _drake_search(
    arm: Arm, target: NDArray, q0: NDArray, starts: list[NDArray], with_limits: bool
) -> tuple[NDArray | None, float]:
    """The first start from which Drake's IK plus polishing reaches ``target``; else the closest miss."""
    from pydrake.multibody.inverse_kinematics import InverseKinematics
    from pydrake.solvers import Solve

    plant, tool, index = drake_arm(arm)
    to_plant = np.zeros(plant.num_positions())
    ik = InverseKinematics(plant, with_joint_limits=with_limits)
    ik.AddPositionConstraint(tool, np.zeros(3), plant.world_frame(), target - 1e-10, target + 1e-10)
    prog = ik.prog()
    plant_q0 = to_plant.copy()
    plant_q0[index] = q0
    prog.AddQuadraticErrorCost(np.eye(plant.num_positions()), plant_q0, ik.q())
    lower, upper = arm.limit_arrays() if with_limits else (np.full(arm.n, -np.inf), np.full(arm.n, np.inf))
    best = np.inf
    for start in starts:
        guess = to_plant.copy()
        guess[index] = start
        result = Solve(prog, guess)
        q = _polish(arm, target, result.GetSolution(ik.q())[index], lower, upper)
        miss = float(np.linalg.norm(arm.forward(q).tool[:3, 3] - target))  # the paper's FK, not Drake's
        if miss <= POSITION_TOL:
            return q, miss
        best = min(best, miss)
    return None, best


def _polish(arm: Arm, target: NDArray, q: NDArray, lower: NDArray, upper: NDArray, steps: int = 8) -> NDArray:
    """Gauss–Newton steps q ← q + J⁺(target − p(q)) on Drake's tool Jacobian, kept within limits."""
    from pydrake.multibody.tree import JacobianWrtVariable

    plant, tool, index = drake_arm(arm)
    context = plant.CreateDefaultContext()
    world = plant.world_frame()
    full = np.zeros(plant.num_positions())
    for _ in range(steps):
        full[index] = q
        plant.SetPositions(context, full)
        error = target - plant.CalcPointsPositions(context, tool, np.zeros(3), world)[:, 0]
        if np.linalg.norm(error) < 1e-14:
            break
        J = plant.CalcJacobianTranslationalVelocity(
            context, JacobianWrtVariable.kQDot, tool, np.zeros(3), world, world
        )[:, index]
        q = np.clip(q + np.linalg.lstsq(J, error, rcond=1e-10)[0], lower, upper)
    return q


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
                q[:, i] = values - two_pi * np.ceil((values - np.pi) / two_pi)  # (−π, π]
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


def _outside_limits_message(arm: Arm, target: NDArray, violations: list[tuple | None]) -> str:
    parts = []
    for i, value, lo, hi in (v for v in violations if v is not None):
        if arm.revolute[i]:
            parts.append(f"{arm.joint_names[i]} = {np.degrees(value):.6g}° outside [{np.degrees(lo):.6g}°, "
                         f"{np.degrees(hi):.6g}°] even after 2π shifts")
        else:
            parts.append(f"{arm.joint_names[i]} = {value:.6g} m outside [{lo:.6g}, {hi:.6g}] m")
    return (f"target {_fmt(target)} is reachable by {arm.name} only outside its joint limits: "
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


def solve(
    arm: Arm,
    target: ArrayLike,
    pitch: float | None = None,
    near: ArrayLike | None = None,
    all_solutions: bool = False,
) -> list[NDArray[np.float64]]:
    """Joint values reaching ``target`` within ``arm``'s joint limits, nearest to ``near`` first.

    * ``rr``: :func:`rr_ik`; ``target`` is (x, y) or (x, y, 0) — the arm moves in z = 0.
    * ``arm4r``: :func:`arm4r_ik` with ``pitch`` = θ2 + θ3 + θ4 (rad); **pitch = 0 if not
      given** (tool x axis horizontal, the "stretched" state of paper 001's simulation).
    * ``r2t``: :func:`r2t_ik`.
    * any other arm (urm6, users' arms): :func:`numeric_ik` started from ``near``; it
      returns one solution (a redundant arm has infinitely many).

    Every solution is fitted into the joint limits by :func:`fit_limits`; those that do
    not fit are dropped, duplicates removed, and the rest sorted by Euclidean joint
    distance to ``near`` (default zeros). Returns every solution if ``all_solutions``,
    else ``[best]``. ``ValueError`` (naming the bad value) for a wrong number of
    coordinates, NaN/inf, a pitch for an arm other than arm4r, an unreachable target, or
    a target reachable only outside the joint limits (naming the joint and its limits).
    """
    name = arm.name
    if name == "rr" and _analytic(arm):
        p = planar_target(target)
    else:
        p = np.asarray(target, dtype=float)
        if p.shape != (3,):
            raise ValueError(f"target {np.ravel(p).tolist()} has {p.size} values; {name} takes 3 coordinates "
                             "(x,y,z in m)")
        p = _single(p, 3)
    near = np.zeros(arm.n) if near is None else _single(near, arm.n, "near")
    if pitch is not None and not (name == "arm4r" and _analytic(arm)):
        raise ValueError(f"pitch = {pitch} applies only to arm4r (its tool pitch θ2+θ3+θ4), not to {name}")
    prm = arm.parameters
    if not _analytic(arm):
        candidates = numeric_ik(arm, p, q0=near)[None, :]
    elif name == "rr":
        candidates = rr_ik(p, prm["L1"], prm["L2"])
    elif name == "arm4r":
        pitch = 0.0 if pitch is None else float(pitch)
        candidates = arm4r_ik(p, pitch, prm["a2"], prm["a3"], prm["d2"], theta1_free=float(near[0]))
    else:
        candidates = r2t_ik(p, prm["l1"], prm["l2"], prm["l3"], prm["l4"], prm["l5"])
    fitted, violations = fit_limits(arm, candidates, near)
    kept = fitted[[v is None for v in violations]]
    if kept.shape[0] == 0:
        raise ValueError(_outside_limits_message(arm, p, violations))
    unique: list[NDArray] = []
    for q in kept:
        if all(np.max(np.abs(q - u)) > SAME_SOLUTION_TOL for u in unique):
            unique.append(q)
    unique.sort(key=lambda q: float(np.linalg.norm(q - near)))
    return unique if all_solutions else unique[:1]
