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
import math

import numpy as np
from numpy.typing import NDArray

from armlab.bounds import above, above_value, below, below_value
from armlab.kinematics.basic_movements import T_Z1, T_Z3, T_Z4
from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.ik_closed_form import ClosedForm
from armlab.kinematics.ik_target import made_once, target_text

__all__ = ["spherical_wrist_closed_form", "spherical_wrist_ik", "ur_branches", "ur_closed_form", "ur_ik"]

#: |sin θ5| below this is a wrist singularity: θ6 (UR) or θ4 (spherical wrist) is then taken from ``near``.
SINGULAR_SIN = 1e-12


def _shoulder(point: NDArray, offset: float, what: str) -> tuple[float, float]:
    """The two θ1 with ``point``·z1 = ``offset``, z1 = (sin θ1, −cos θ1, 0): r sin(θ1 − φ) = offset."""
    r = float(np.hypot(point[0], point[1]))
    if below(r, abs(offset)):
        raise ValueError(f"{what} is out of reach: the wrist point is {r:.6g} m from the base axis, closer than "
                         f"the shoulder offset {abs(offset):.6g} m")
    phi, s = float(np.arctan2(point[1], point[0])), float(np.arcsin(np.clip(offset / r, -1.0, 1.0)))
    return phi + s, phi + np.pi - s


def _offsets(table: DHTable) -> NDArray[np.float64]:
    return np.array([row.theta for row in table.rows])


#: Rz(θ) = cos θ·_COS + sin θ·_SIN + _ONE (4×4).
_COS, _SIN, _ONE = np.diag([1.0, 1.0, 0.0, 0.0]), np.zeros((4, 4)), np.diag([0.0, 0.0, 1.0, 1.0])
_SIN[0, 1], _SIN[1, 0] = -1.0, 1.0
#: The two signs of a branch pair: θ5 and −θ5, θ3 and −θ3.
_SIGNS = np.array([1.0, -1.0])


@functools.cache
def _dh_parts(row: DHRow, inverse: bool) -> NDArray[np.float64]:
    """``(3, 4, 4)``: the matrices whose combination cos θ·[0] + sin θ·[1] + [2] is the standard DH transform of
    ``row`` at the DH angle θ, Rz(θ)·C with C = Tz(d)·Tx(a)·Rx(α) (000 eq. (9)), or with
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
    position, rotation = np.asarray(position, dtype=float), np.asarray(rotation, dtype=float)
    if position.ndim == 1:  # one pose: in scalars (a few dozen numpy calls on tiny arrays cost more than the math)
        return _ur_pose(table, position, rotation, np.asarray(near, dtype=float))
    rows = table.rows
    a2, a3 = rows[1].a, rows[2].a
    offset, d6 = rows[1].d + rows[2].d + rows[3].d, rows[5].d
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


def _acos(c: float) -> float | None:
    """arccos of ``c`` clipped at ±1 within round-off, ``None`` beyond (that branch does not exist)."""
    if above_value(abs(c), 1.0):
        return None
    return math.acos(min(1.0, max(-1.0, c)))


def _ur_constants(table: DHTable) -> tuple[float, ...]:
    """What :func:`_ur_pose` reads off ``table``: a2, a3, the shoulder offset d2 + d3 + d4, d6, frame 4's origin in
    frame 5 (x, y, z: the inverse of row 5 applied to the origin, which no turn about z moves), cos α5, sin α5, and
    row 6's and row 1's a, d, cos α, sin α."""
    return made_once(table, "ur", _make_ur_constants)


def _make_ur_constants(table: DHTable) -> tuple[float, ...]:
    rows = table.rows
    r5, r6, r1 = rows[4], rows[5], rows[0]
    c5, s5 = math.cos(r5.alpha), math.sin(r5.alpha)
    made = (rows[1].a, rows[2].a, rows[1].d + rows[2].d + rows[3].d, r6.d, -r5.a, -s5 * r5.d, -c5 * r5.d, c5, s5,
            r6.a, r6.d, math.cos(r6.alpha), math.sin(r6.alpha), r1.a, r1.d, math.cos(r1.alpha), math.sin(r1.alpha))
    return made


def _ur_pose(table: DHTable, position: NDArray, rotation: NDArray, near: NDArray) -> NDArray[np.float64]:
    """:func:`ur_branches` of one pose ``(3,)``, ``(3, 3)`` → ``(8, 6)``, the same formulas in scalars: the origin of
    DH frame 4 and its x axis in frame 1 from the pose and θ1, θ5, θ6 (the inverse DH transforms, Rx(−α)·Tx(−a)·
    Tz(−d)·Rz(−θ), applied to a point and a direction instead of 4×4 products), then the planar 3R chain."""
    a2, a3, offset, d6, o5x, o5y, o5z, ca5, sa5, a6, d6_, ca6, sa6, a1, d1, ca1, sa1 = _ur_constants(table)
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = rotation.tolist()
    px, py, pz = position.tolist()
    theta_offsets = [row.theta for row in table.rows]
    out = [[math.nan] * 6 for _ in range(8)]
    wx, wy = px - d6 * r02, py - d6 * r12
    r = math.hypot(wx, wy)
    if r == 0.0 or below_value(r, abs(offset)):  # no shoulder: every branch NaN (as the batch's 0/0)
        return np.array(out)
    phi, shoulder = math.atan2(wy, wx), math.asin(min(1.0, max(-1.0, offset / r)))
    for i, t1 in enumerate((phi + shoulder, phi + math.pi - shoulder)):
        s1, c1 = math.sin(t1), math.cos(t1)
        c5 = _acos((px * s1 - py * c1 - offset) / d6)
        if c5 is None:
            continue
        v0 = r00 * s1 - r10 * c1  # z1 = (s1, −c1, 0) in frame 6: (s5 c6, −s5 s6, c5)
        v1 = r01 * s1 - r11 * c1
        for j, t5 in enumerate((c5, -c5)):
            s5, cos5 = math.sin(t5), math.cos(t5)
            if abs(s5) < SINGULAR_SIN:  # not a bound: a switch of formula where v/s5 has no digits
                t6 = float(near[5]) + table.rows[5].theta
            else:
                t6 = math.atan2(-v1 / s5, v0 / s5)
            s6, c6 = math.sin(t6), math.cos(t6)
            # frame 4's origin and x axis in frame 6 (row 6 undone from frame 5's), then in the world
            x, y = c6 * o5x + s6 * o5y - a6, c6 * o5y - s6 * o5x
            z = o5z - d6_
            ox, oy, oz = x, ca6 * y + sa6 * z, ca6 * z - sa6 * y
            x, y, z = cos5, -ca5 * s5, sa5 * s5
            x, y = c6 * x + s6 * y, c6 * y - s6 * x
            ex, ey, ez = x, ca6 * y + sa6 * z, ca6 * z - sa6 * y
            wx = r00 * ox + r01 * oy + r02 * oz + px
            wy = r10 * ox + r11 * oy + r12 * oz + py
            wz = r20 * ox + r21 * oy + r22 * oz + pz
            dx, dy, dz = r00 * ex + r01 * ey + r02 * ez, r10 * ex + r11 * ey + r12 * ez, r20 * ex + r21 * ey + r22 * ez
            # … then in frame 1 (row 1 undone): only the x, y entries are needed
            x, y = c1 * wx + s1 * wy - a1, (c1 * wy - s1 * wx) * ca1 + (wz - d1) * sa1
            ax, ay = c1 * dx + s1 * dy, (c1 * dy - s1 * dx) * ca1 + dz * sa1
            elbow = _acos((x * x + y * y - a2 * a2 - a3 * a3) / (2 * a2 * a3))
            if elbow is None:
                continue
            t234, direction = math.atan2(ay, ax), math.atan2(y, x)
            for k, t3 in enumerate((elbow, -elbow)):
                t2 = direction - math.atan2(a3 * math.sin(t3), a2 + a3 * math.cos(t3))
                out[4 * i + 2 * j + k] = [t - o for t, o in zip((t1, t2, t3, t234 - t2 - t3, t5, t6), theta_offsets,
                                                                 strict=True)]
    return np.array(out)


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


#: sin α of a right angle within this (a layout check of a DH table's exact 90° twists).
_RIGHT_ANGLE = 1e-12


def _spherical_layout(table: DHTable) -> str | None:
    """Why ``table`` is not of the spherical-wrist layout :func:`spherical_wrist_ik` solves, or ``None`` if it is:
    six joints in standard DH, all revolute but joint 3, which may slide (the Stanford arm's boom); α1 = ±90°;
    joint 3 revolute with axes 2 and 3 parallel (α2 = 0), or prismatic with α2 = ±90° and d4 = 0; a spherical wrist:
    α4 = ±90°, α5 = −α4, a4 = a5 = a6 = d5 = 0."""
    rows = table.rows
    if (len(rows) != 6 or table.convention != "standard"
            or any(row.kind != "R" for k, row in enumerate(rows) if k != 2)):
        return "it takes six joints in standard DH, all revolute but joint 3"
    right = [abs(abs(math.sin(row.alpha)) - 1.0) <= _RIGHT_ANGLE for row in rows]
    if not (right[0] and right[3]):
        return "α1 and α4 must be ±90°"
    if rows[2].kind == "R" and (abs(math.sin(rows[1].alpha)) > _RIGHT_ANGLE
                                or math.cos(rows[1].alpha) < 0):
        return "axes 2 and 3 must be parallel (α2 = 0)"
    if rows[2].kind == "T" and not (right[1] and rows[3].d == 0.0):
        return "a sliding joint 3 takes α2 = ±90° and d4 = 0"
    if abs(math.sin(rows[4].alpha) + math.sin(rows[3].alpha)) > _RIGHT_ANGLE:
        return "α5 must be −α4"
    if any(value != 0.0 for value in (rows[3].a, rows[4].a, rows[5].a, rows[4].d)):
        return "a spherical wrist has a4 = a5 = a6 = d5 = 0"
    return None


def spherical_wrist_ik(table: DHTable, position: NDArray, rotation: NDArray, near: NDArray) -> NDArray[np.float64]:
    """Every branch (k ≤ 8, 6) of a spherical-wrist arm (:func:`_spherical_layout`: Puma 560, IRB 140, KR 5, the
    Stanford arm) reaching the tool pose (``position`` m, ``rotation`` (3, 3)), the tool being DH frame 6; joint
    values q = DH angle − offset (rad; a sliding joint 3: d − offset, m), in the order shoulder × elbow (or boom
    sign) × wrist flip. In scalars (one pose: numpy's per-call cost would exceed the arithmetic).

    The wrist centre c = p − d6·z5 (z5 = R·(0, sin α6, cos α6)) is frame 4's origin; in frame 1 its z coordinate is a
    constant w (d2 + d3 + d4 cos α3; with a sliding joint 3, d2 + a3 sin α2 sin θ3), which gives θ1 (two roots), and
    its x, y are a planar chain turned by θ2: the links a2, (a3, −d4 sin α3) turned by θ3 (two elbows), or
    (a2 + a3 cos θ3, −sin α2 (d3 + q3)) (two signs of the boom). The wrist's M = R03ᵀ·R·Rx(−α6) = Rz(θ4)·Ry(σθ5)·Rz(θ6),
    σ = −sin α4, is read as ZYZ angles (two flips); at a wrist singularity (sin θ5 = 0) θ4 is ``near``'s. On the base
    axis with w = 0, θ1 is ``near``'s.
    """
    rows = table.rows
    a1, d1, ca1, sa1 = rows[0].a, rows[0].d, math.cos(rows[0].alpha), math.sin(rows[0].alpha)
    a2, a3, d4 = rows[1].a, rows[2].a, rows[3].d
    ca2, sa2 = math.cos(rows[1].alpha), math.sin(rows[1].alpha)
    ca3, sa3 = math.cos(rows[2].alpha), math.sin(rows[2].alpha)
    ca6, sa6, d6 = math.cos(rows[5].alpha), math.sin(rows[5].alpha), rows[5].d
    sigma = -math.sin(rows[3].alpha)
    sliding = rows[2].kind == "T"
    if sliding:  # θ3 fixed at its offset; the boom's length d3 + q3 the unknown
        boom = a2 + a3 * math.cos(rows[2].theta)
        w = rows[1].d + a3 * sa2 * math.sin(rows[2].theta)
    else:
        b = -d4 * sa3
        rho, beta = math.hypot(a3, b), math.atan2(b, a3)
        w = rows[1].d + rows[2].d + d4 * ca3
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = rotation.tolist()
    px, py, pz = position.tolist()
    g0 = (r00, r10, r20)  # R·Rx(−α6): its first column, and its third (z5)
    g2 = (sa6 * r01 + ca6 * r02, sa6 * r11 + ca6 * r12, sa6 * r21 + ca6 * r22)
    cx, cy, cz = px - d6 * g2[0], py - d6 * g2[1], pz - d6 * g2[2]
    r = math.hypot(cx, cy)
    if below_value(r, abs(w)):
        _shoulder(np.array([cx, cy]), w, target_text(position, rotation))  # its own message
    if r == 0.0:  # on the base axis, w = 0: θ1 is free
        phi, k = float(near[0]) + rows[0].theta, 0.0
    else:
        phi, k = math.atan2(cy, cx), math.asin(min(1.0, max(-1.0, -w * sa1 / r)))
    near4 = float(near[3]) + rows[3].theta
    solutions: list[list[float]] = []
    for t1 in (phi - k, phi + math.pi + k):
        s1, c1 = math.sin(t1), math.cos(t1)
        u, v = c1 * cx + s1 * cy - a1, ca1 * (c1 * cy - s1 * cx) + sa1 * (cz - d1)  # the wrist centre in frame 1
        chains: list[tuple[float, float, float]] = []  # (θ2, θ3, joint 3's value)
        if sliding:
            if below_value(math.hypot(u, v), abs(boom)):
                continue
            length = math.sqrt(max(u * u + v * v - boom * boom, 0.0))
            chains = [(math.atan2(v, u) - math.atan2(-sa2 * reach, boom), rows[2].theta, reach - rows[2].d)
                      for reach in (length, -length)]
        else:
            elbow = _acos((u * u + v * v - a2 * a2 - rho * rho) / (2 * a2 * rho))
            if elbow is None:
                continue
            for t3 in (-beta + elbow, -beta - elbow):
                s3, c3 = math.sin(t3), math.cos(t3)
                chains.append((math.atan2(v, u) - math.atan2(a3 * s3 + b * c3, a2 + a3 * c3 - b * s3), t3,
                               t3 - rows[2].theta))
        for t2, t3, joint3 in chains:
            s2, c2, s3, c3 = math.sin(t2), math.cos(t2), math.sin(t3), math.cos(t3)
            m = []
            for gx, gy, gz in (g0, g2):  # M's columns 0 and 2: Rx(−α3)·Rz(−θ3)·Rx(−α2)·Rz(−θ2)·Rx(−α1)·Rz(−θ1) of G's
                x, y = c1 * gx + s1 * gy, c1 * gy - s1 * gx
                y, z = ca1 * y + sa1 * gz, ca1 * gz - sa1 * y
                x, y = c2 * x + s2 * y, c2 * y - s2 * x
                y, z = ca2 * y + sa2 * z, ca2 * z - sa2 * y
                x, y = c3 * x + s3 * y, c3 * y - s3 * x
                m.append((x, ca3 * y + sa3 * z, ca3 * z - sa3 * y))
            (m00, m10, m20), (m02, m12, m22) = m
            bend = math.atan2(math.hypot(m02, m12), m22)
            for bs in (bend, -bend):
                sb, cb = math.sin(bs), math.cos(bs)
                t4 = near4 if abs(sb) < SINGULAR_SIN else math.atan2(m12 / sb, m02 / sb)  # not a bound: as ur_ik
                s4, c4 = math.sin(t4), math.cos(t4)
                t6 = math.atan2(c4 * m10 - s4 * m00, cb * (c4 * m00 + s4 * m10) - sb * m20)  # Ry(−b)·Rz(−θ4)·M
                solutions.append([t1 - rows[0].theta, t2 - rows[1].theta, joint3, t4 - rows[3].theta,
                                  sigma * bs - rows[4].theta, t6 - rows[5].theta])
    if not solutions:
        raise ValueError(f"{target_text(position, rotation)} is out of reach: no branch of the closed form reaches it")
    return np.array(solutions)


_BRANCHES = tuple(f"shoulder {s}, wrist {w}, elbow {e}" for s in ("right", "left") for w in ("+", "−")
                  for e in ("+", "−"))


def ur_closed_form(table: DHTable) -> ClosedForm:
    """:func:`ur_ik` of the arm's DH ``table`` as its ``ClosedForm`` (a pose target; 8 branches)."""
    def solve(position: NDArray, rotation: NDArray | None, near: NDArray) -> NDArray[np.float64]:
        return ur_ik(table, position, _pose_only(rotation), near)
    return ClosedForm(solve, _BRANCHES, needs_pose=True)


def spherical_wrist_closed_form(table: DHTable) -> ClosedForm:
    """:func:`spherical_wrist_ik` of the arm's DH ``table`` as its ``ClosedForm`` (a pose target; 8 branches);
    ``ValueError`` for a table not of its layout."""
    why = _spherical_layout(table)
    if why is not None:
        raise ValueError(f"no spherical-wrist closed form for this DH table: {why}")
    def solve(position: NDArray, rotation: NDArray | None, near: NDArray) -> NDArray[np.float64]:
        return spherical_wrist_ik(table, position, _pose_only(rotation), near)
    elbow = "boom" if table.rows[2].kind == "T" else "elbow"
    return ClosedForm(solve, tuple(f"shoulder {s}, {elbow} {e}, wrist {w}" for s in ("right", "left")
                                   for e in ("+", "−") for w in ("+", "−")), needs_pose=True)


def _pose_only(rotation: NDArray | None) -> NDArray:
    if rotation is None:  # the dispatcher turns a position target into a pose first (a continuum otherwise)
        raise ValueError("this closed form takes a full pose (a 4×4 target): a tool position alone is reached by a "
                         "continuum of joint values")
    return rotation
