"""Closed-form inverse kinematics of the two classic six-axis layouts, read off the arm's own standard DH table.

* :func:`ur_ik` — the Universal Robots layout (three parallel axes 2, 3, 4; α = 90°, 0, 0, 90°, −90°, 0;
  a1 = a4 = a5 = a6 = 0), after Hawkins, "Analytic inverse kinematics for the Universal Robots UR-5/UR-10 arms"
  (2013): θ1 from the wrist-2 origin's offset d2 + d3 + d4 from the base axis, θ5 from the tool position along
  z1, θ6 from the tool orientation, then θ2, θ3, θ4 as a planar 3R chain. 8 branches (shoulder ×
  wrist ± × elbow).
  :func:`ur_branches` solves a whole batch of poses in one pass (numpy over the poses and the 8 branches at once,
  each DH transform linear in cos θ and sin θ); :func:`ur_ik` is its one pose.
* :func:`spherical_wrist_ik` — the Puma 560 layout (a spherical wrist: α4 = 90°, α5 = −90°, a4 = a5 = a6 =
  d5 = 0; α1 = 90°, α2 = 0, α3 = −90°, a1 = 0), after Paul, Shimano & Mayer (1981): θ1 from the wrist centre's
  offset d2 + d3 from the base axis, θ2, θ3 from its distance in the arm's plane, and the wrist's
  R36 = Rz(θ4)·Ry(−θ5)·Rz(θ6) (ZYZ). 8 branches (shoulder × elbow × wrist flip).

Both take a full pose: a position-only target of a six-axis arm is a continuum (:func:`armlab.kinematics.ik.solve`
says what it returns then). Each returns the branches that exist, ``(k, 6)``, k ≤ 8, not fitted into the joint
limits; at a wrist singularity (θ5 = 0) the free angle is ``near``'s. ``ValueError`` for an unreachable target.
"""

from __future__ import annotations

import functools

import numpy as np
from numpy.typing import NDArray

from armlab.bounds import above, below
from armlab.kinematics.basic_movements import T_Z1, T_Z3, T_Z4, T_Z5, T_Z6
from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.ik_closed_form import ClosedForm
from armlab.kinematics.ik_target import target_text

__all__ = ["spherical_wrist_closed_form", "spherical_wrist_ik", "ur_branches", "ur_closed_form", "ur_ik"]

#: |sin θ5| below this is a wrist singularity: θ6 (UR) or θ4 (spherical wrist) is then taken from ``near``.
SINGULAR_SIN = 1e-12


def _row(table: DHTable, i: int, theta: float) -> NDArray[np.float64]:
    """T_{i,i+1} of standard DH row ``i`` (0-based) at the DH angle ``theta`` (rad), 000 eq. (9): R_z(θ − offset)
    times the row at q = 0 (:attr:`DHTable.steps`; the joint's turn comes first in a standard row)."""
    post = table.steps[i].post
    turn = T_Z6(theta - table.rows[i].theta)
    return turn if post is None else turn @ post


def _shoulder(point: NDArray, offset: float, what: str) -> tuple[float, float]:
    """The two θ1 with ``point``·z1 = ``offset``, z1 = (sin θ1, −cos θ1, 0): r sin(θ1 − φ) = offset."""
    r = float(np.hypot(point[0], point[1]))
    if below(r, abs(offset)):
        raise ValueError(f"{what} is out of reach: the wrist point is {r:.6g} m from the base axis, closer than "
                         f"the shoulder offset {abs(offset):.6g} m")
    phi, s = float(np.arctan2(point[1], point[0])), float(np.arcsin(np.clip(offset / r, -1.0, 1.0)))
    return phi + s, phi + np.pi - s


def _acos(c: float) -> float | None:
    """arccos of ``c`` clipped at ±1 within round-off; ``None`` beyond (that branch does not exist)."""
    if above(abs(c), 1.0):
        return None
    return float(np.arccos(np.clip(c, -1.0, 1.0)))


def _offsets(table: DHTable) -> NDArray[np.float64]:
    return np.array([row.theta for row in table.rows])


def _rows_or_raise(solutions: list[list[float]], table: DHTable, what: str) -> NDArray[np.float64]:
    if not solutions:
        raise ValueError(f"{what} is out of reach: no branch of the closed form reaches it")
    return np.array(solutions) - _offsets(table)  # DH angles θ = q + offset


#: Rz(θ) = cos θ·_COS + sin θ·_SIN + _ONE (4×4).
_COS, _SIN, _ONE = np.diag([1.0, 1.0, 0.0, 0.0]), np.zeros((4, 4)), np.diag([0.0, 0.0, 1.0, 1.0])
_SIN[0, 1], _SIN[1, 0] = -1.0, 1.0
#: The two signs of a branch pair: θ5 and −θ5, θ3 and −θ3.
_SIGNS = np.array([1.0, -1.0])


@functools.cache
def _dh_parts(row: DHRow, inverse: bool) -> NDArray[np.float64]:
    """``(3, 4, 4)``: the matrices whose combination cos θ·[0] + sin θ·[1] + [2] is the standard DH transform of
    ``row`` at the DH angle θ, Rz(θ)·C with C = Tz(d)·Tx(a)·Rx(α) (000 eq. (9), as :func:`_row`), or with
    ``inverse`` its inverse C⁻¹·Rz(−θ)."""
    C = T_Z3(row.d) @ T_Z1(row.a) @ T_Z4(row.alpha)
    if inverse:
        Ci = np.linalg.inv(C)
        return np.stack([Ci @ _COS, -(Ci @ _SIN), Ci @ _ONE])
    return np.stack([_COS @ C, _SIN @ C, _ONE @ C])


def _dh(row: DHRow, theta: NDArray, inverse: bool = False) -> NDArray[np.float64]:
    """The standard DH transform of ``row`` (or with ``inverse`` its inverse) at the DH angles ``theta`` (any
    shape ``S``), ``S + (4, 4)``."""
    cos, sin, one = _dh_parts(row, inverse)
    return np.cos(theta)[..., None, None] * cos + np.sin(theta)[..., None, None] * sin + one


def _arccos(c: NDArray) -> NDArray[np.float64]:
    """arccos of ``c`` clipped at ±1 within round-off; NaN beyond (that branch does not exist), as :func:`_acos`."""
    return np.where(above(np.abs(c), 1.0), np.nan, np.arccos(np.clip(c, -1.0, 1.0)))


def ur_branches(table: DHTable, position: NDArray, rotation: NDArray, near: NDArray) -> NDArray[np.float64]:
    """The 8 branches of a UR-layout arm for a batch of tool poses at once: ``position`` ``(..., 3)`` m,
    ``rotation`` ``(..., 3, 3)``, ``near`` ``(..., 6)`` (θ6 at a wrist singularity) → q ``(..., 8, 6)`` (rad, DH
    angle − offset), in the order of :data:`_BRANCHES` (shoulder × wrist ± × elbow); a branch that does not exist
    (the wrist point closer to the base axis than the shoulder offset, |cos θ5| or |cos θ3| beyond 1) is NaN."""
    rows = table.rows
    a2, a3 = rows[1].a, rows[2].a
    offset, d6 = rows[1].d + rows[2].d + rows[3].d, rows[5].d
    position, rotation = np.asarray(position, dtype=float), np.asarray(rotation, dtype=float)
    batch = position.shape[:-1]
    target = np.zeros(batch + (4, 4))
    target[..., :3, :3], target[..., :3, 3], target[..., 3, 3] = rotation, position, 1.0
    wrist = position - d6 * rotation[..., :, 2]  # the origin of DH frame 5
    r = np.hypot(wrist[..., 0], wrist[..., 1])
    phi = np.arctan2(wrist[..., 1], wrist[..., 0])
    with np.errstate(divide="ignore", invalid="ignore"):  # r = 0: that pose's branches are NaN (no shoulder)
        shoulder = np.where(below(r, abs(offset)), np.nan, np.arcsin(np.clip(offset / r, -1.0, 1.0)))
    t1 = np.empty(batch + (2,))  # the two shoulders
    t1[..., 0], t1[..., 1] = phi + shoulder, phi + np.pi - shoulder
    z1 = np.zeros(t1.shape + (3,))  # (..., 2, 3)
    z1[..., 0], z1[..., 1] = np.sin(t1), -np.cos(t1)
    t5 = _arccos((np.einsum("...j,...kj->...k", position, z1) - offset) / d6)
    t5 = t5[..., None] * _SIGNS  # (..., 2 shoulders, 2 wrists)
    v = np.einsum("...ji,...kj->...ki", rotation, z1)  # z1 in frame 6: (s5 c6, −s5 s6, c5), (..., 2, 3)
    s5 = np.sin(t5)
    singular = np.abs(s5) < SINGULAR_SIN  # not a bound: a switch of formula where v/s5 has no digits
    safe = np.where(singular, 1.0, s5)
    t6 = np.where(singular, (near[..., 5] + rows[5].theta)[..., None, None],
                  np.arctan2(-v[..., None, 1] / safe, v[..., None, 0] / safe))
    T14 = (_dh(rows[0], t1, inverse=True)[..., None, :, :] @ target[..., None, None, :, :]
           @ _dh(rows[5], t6, inverse=True) @ _dh(rows[4], t5, inverse=True))  # (..., 2, 2, 4, 4)
    x, y = T14[..., 0, 3], T14[..., 1, 3]
    t234 = np.arctan2(T14[..., 1, 0], T14[..., 0, 0])
    t3 = _arccos((x * x + y * y - a2 * a2 - a3 * a3) / (2 * a2 * a3))
    t3 = t3[..., None] * _SIGNS  # (..., 2, 2, 2 elbows)
    t2 = np.arctan2(y, x)[..., None] - np.arctan2(a3 * np.sin(t3), a2 + a3 * np.cos(t3))
    theta = np.empty(t3.shape + (6,))
    theta[..., 0], theta[..., 1], theta[..., 2] = t1[..., :, None, None], t2, t3
    theta[..., 3], theta[..., 4], theta[..., 5] = t234[..., None] - t2 - t3, t5[..., None], t6[..., None]
    q = theta.reshape(batch + (8, 6)) - _offsets(table)  # DH angles θ = q + offset
    return np.where(np.isnan(q).any(axis=-1, keepdims=True), np.nan, q)


def ur_ik(table: DHTable, position: NDArray, rotation: NDArray, near: NDArray) -> NDArray[np.float64]:
    """Every branch (k ≤ 8, 6) of a UR-layout arm reaching the tool pose (``position`` m, ``rotation`` (3, 3)),
    the tool being DH frame 6; joint values q (rad) = DH angle − offset (:func:`ur_branches` of the one pose, the
    branches that exist). ``ValueError`` for an unreachable pose."""
    q = ur_branches(table, position, rotation, near)
    exists = ~np.isnan(q[:, 0])
    if not exists.any():
        what = target_text(position, rotation)
        wrist = position - table.rows[5].d * rotation[:, 2]
        _shoulder(wrist, table.rows[1].d + table.rows[2].d + table.rows[3].d, what)  # its own message, if that
        raise ValueError(f"{what} is out of reach: no branch of the closed form reaches it")
    return q[exists]


def spherical_wrist_ik(table: DHTable, position: NDArray, rotation: NDArray, near: NDArray) -> NDArray[np.float64]:
    """Every branch (k ≤ 8, 6) of a Puma-layout arm reaching the tool pose (``position`` m, ``rotation`` (3, 3)),
    the tool being DH frame 6; joint values q (rad) = DH angle − offset."""
    what = target_text(position, rotation)
    a2, a3, d4 = table.rows[1].a, table.rows[2].a, table.rows[3].d
    offset = table.rows[1].d + table.rows[2].d
    wrist = position - table.rows[5].d * rotation[:, 2]  # the wrist centre
    rho, beta = float(np.hypot(a3, d4)), float(np.arctan2(d4, a3))
    theta_near = near + _offsets(table)
    solutions: list[list[float]] = []
    for t1 in _shoulder(wrist, offset, what):
        u, v, _ = np.linalg.solve(_row(table, 0, t1), np.append(wrist, 1.0))[:3]
        elbow = _acos((u * u + v * v - a2 * a2 - a3 * a3 - d4 * d4) / (2 * a2 * rho))
        if elbow is None:
            continue
        for t3 in (-beta + elbow, -beta - elbow):
            s3, c3 = np.sin(t3), np.cos(t3)
            t2 = float(np.arctan2(v, u) - np.arctan2(a3 * s3 + d4 * c3, a2 + a3 * c3 - d4 * s3))
            R03 = (_row(table, 0, t1) @ _row(table, 1, t2) @ _row(table, 2, t3))[:3, :3]
            R36 = R03.T @ rotation  # Rz(θ4)·Ry(−θ5)·Rz(θ6)
            b = float(np.arctan2(np.hypot(R36[0, 2], R36[1, 2]), R36[2, 2]))
            for bs in (b, -b):
                sb = np.sin(bs)
                t4 = (theta_near[3] if abs(sb) < SINGULAR_SIN  # not a bound: a switch of formula (as in ur_ik)
                      else float(np.arctan2(R36[1, 2] / sb, R36[0, 2] / sb)))
                M = T_Z5(-bs)[:3, :3] @ T_Z6(-t4)[:3, :3] @ R36  # = Rz(θ6)
                solutions.append([t1, t2, float(t3), t4, -bs, float(np.arctan2(M[1, 0], M[0, 0]))])
    return _rows_or_raise(solutions, table, what)


_BRANCHES = tuple(f"shoulder {s}, wrist {w}, elbow {e}" for s in ("right", "left") for w in ("+", "−")
                  for e in ("+", "−"))


def ur_closed_form(table: DHTable) -> ClosedForm:
    """:func:`ur_ik` of the arm's DH ``table`` as its ``ClosedForm`` (a pose target; 8 branches)."""
    def solve(position: NDArray, rotation: NDArray | None, near: NDArray) -> NDArray[np.float64]:
        return ur_ik(table, position, _pose_only(rotation), near)
    return ClosedForm(solve, _BRANCHES, needs_pose=True)


def spherical_wrist_closed_form(table: DHTable) -> ClosedForm:
    """:func:`spherical_wrist_ik` of the arm's DH ``table`` as its ``ClosedForm`` (a pose target; 8 branches)."""
    def solve(position: NDArray, rotation: NDArray | None, near: NDArray) -> NDArray[np.float64]:
        return spherical_wrist_ik(table, position, _pose_only(rotation), near)
    return ClosedForm(solve, tuple(f"shoulder {s}, elbow {e}, wrist {w}" for s in ("right", "left")
                                   for e in ("+", "−") for w in ("+", "−")), needs_pose=True)


def _pose_only(rotation: NDArray | None) -> NDArray:
    if rotation is None:  # the dispatcher turns a position target into a pose first (a continuum otherwise)
        raise ValueError("this closed form takes a full pose (a 4×4 target): a tool position alone is reached by a "
                         "continuum of joint values")
    return rotation
