"""The one URDF builder: an arm's matrix of nominal geometry plus its bodies → URDF text.

Joint ``i`` of the URDF is row ``i`` of paper 003's matrix of nominal geometry
(:class:`~armlab.kinematics.locating.LocatingTable`): ``origin`` is T_{i,i−1} (P_i and
R_i as xyz/rpy) and ``axis`` is k_i, so the URDF's link frames are the table's frames
{i} and its root link is the paper's base frame — no transform is added in code.

Each moving link of a paper arm is a uniform solid cylinder from its frame's origin to the
next frame's origin (mass and radius from the arm's parameters); a user's DH table gives
each link's mass, centre of mass and inertia instead (:class:`Body` ``com``/``inertia``), and
a link without mass data gets no ``<inertial>``. Named points and the tool are massless links
on fixed joints; an unknown effort or velocity limit is left out of ``<limit>``. Visuals only
(no mass): a base disc, a column from the base to joint 1, a dark drum on each revolute
axis, a dark block on each prismatic axis and the guide it slides on (over its stroke) on
the parent link, a red ball at the tool. Every joint is actuated through a ``SimpleTransmission``.

Collision geometry (a :class:`Body` with ``collides``): capsules of the link's radius along its axis, by default
from its frame's origin to the next frame's origin (``linkI_capsule``, ``linkI_capsule2`` … for an axis of several
pieces; a sphere where the axis has no length), and a column from the base to joint 1, where there is one, as a
capsule of link 1's radius (``base_link_column``). The base disc has none: the ground under the arm is a scene's floor.
Drake filters the pairs of adjacent links itself; the pairs that touch by construction (:func:`touching_pairs`:
the links of a wrist whose frames coincide) are filtered by Drake collision filter groups written here.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass
from html import escape

import numpy as np
from numpy.typing import NDArray

from armlab.bounds import above
from armlab.drives.train import DriveTrain
from armlab.kinematics.locating import LocatingTable, orientation_angles

__all__ = ["DRAKE_NAMESPACE", "Body", "JointLimits", "Point", "check_inertia", "cylinder_inertia", "link_axis",
           "link_inertials", "touching_pairs", "upright", "urdf_text"]

#: The namespace of Drake's URDF extensions (``<drake:rotor_inertia>``, …), declared as ``xmlns:drake``.
DRAKE_NAMESPACE = "http://drake.mit.edu"


@dataclass(frozen=True)
class Body:
    """Mass properties and look of one link (``radius`` sizes its drawing and, with ``collides``, its capsule).

    Without ``com`` and ``inertia`` the link is a uniform solid cylinder of ``mass`` and ``radius``
    from its frame's origin to the next frame's origin (the paper arms). With them, the link has
    that ``mass`` (kg), its centre of mass at ``com`` (m, in the link frame {i}) and the inertia
    ``inertia`` (kg·m², 3×3 about the centre of mass, axes of {i}). ``mass = 0`` with neither:
    a link without mass data (a kinematic arm's), written with no ``<inertial>``.

    ``collides``: the link has collision geometry, capsules of ``radius`` (m) joining the points of its ``axis``
    (in the link frame {i}, m; e.g. a DH link's offsets d and a, bent where they meet); no ``axis``: the segment
    from its frame's origin to the next frame's origin (a sphere of ``radius`` where the axis has no length);
    ``False``: the arm's file gives the link no geometry (it is drawn, never checked).
    """

    mass: float
    radius: float
    color: tuple[float, float, float, float] = (0.8, 0.45, 0.1, 1.0)
    com: tuple[float, float, float] | None = None
    inertia: tuple[tuple[float, float, float], ...] | None = None
    collides: bool = False
    axis: tuple[tuple[float, float, float], ...] = ()


@dataclass(frozen=True)
class JointLimits:
    """Position limits (``None`` = unlimited revolute), effort (N·m or N) and velocity (rad/s or m/s) limits.

    ``effort`` or ``velocity`` ``None``: the limit is unknown (the arm's file gives none).
    """

    lower: float | None
    upper: float | None
    effort: float | None = None
    velocity: float | None = None


@dataclass(frozen=True)
class Point:
    """A named point: a frame on link ``link`` (0 base, 1 … n links, n+1 tool) at ``xyz``."""

    name: str
    link: int
    xyz: tuple[float, float, float]


def _a(text: str) -> str:
    """``text`` as an XML attribute value between double quotes: ``&``, ``<``, ``>``, ``"`` and ``'`` escaped (html's
    escape, not xml.sax.saxutils': that imports urllib), tabs and line ends as character references (a parser reads
    them back as they were, not as spaces)."""
    return escape(text, quote=True).replace("\t", "&#9;").replace("\n", "&#10;").replace("\r", "&#13;")


def _comment(text: str) -> str:
    """``text`` as the content of an XML comment, which cannot hold ``--`` nor end in ``-``: each ``-`` of a run
    parted by a space."""
    text = re.sub(r"-(?=-)", "- ", text)
    return text + " " if text.endswith("-") else text


def _f(x: float) -> str:
    return repr(float(x)) if x != 0 else "0"


def _origin(T: NDArray) -> str:
    rpy = orientation_angles(T[:3, :3])
    return f'<origin xyz="{" ".join(map(_f, T[:3, 3]))}" rpy="{" ".join(map(_f, rpy))}"/>'


def _z_to(direction: NDArray) -> NDArray:
    """A rotation taking the z axis onto ``direction`` (unit)."""
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(z, direction)
    s, c = np.linalg.norm(axis), float(z @ direction)
    if s < 1e-12:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]]) / s
    return np.eye(3) + s * K + (1 - c) * K @ K


def upright(gravity: tuple[float, float, float]) -> NDArray[np.float64] | None:
    """The pose (4×4, no translation) of a base frame in which gravity is ``gravity`` (m/s², ``(3,)``) within a
    world frame in which it is −z: the smallest turn taking its direction to −z; ``None`` when it already is −z
    or there is none (zero gravity: nothing to turn)."""
    g = np.asarray(gravity, dtype=float)
    norm = float(np.linalg.norm(g))
    if norm == 0 or (g[0] == 0 and g[1] == 0 and g[2] < 0):  # exact: no turn at all
        return None
    d, down = g / norm, np.array([0.0, 0.0, -1.0])
    v, c = np.cross(d, down), float(d @ down)
    K = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    X = np.eye(4)
    X[:3, :3] = np.diag([1.0, -1.0, -1.0]) if not above(c, -1.0) else np.eye(3) + K + K @ K / (1 + c)
    return X


def cylinder_inertia(mass: float, radius: float, length: float) -> NDArray:
    """Inertia of a uniform solid cylinder about its centre, axis along z."""
    side = mass * (3 * radius**2 + length**2) / 12
    return np.diag([side, side, mass * radius**2 / 2])


def _segment(axis: NDArray, end: NDArray, radius: float) -> tuple[NDArray, NDArray, float]:
    """Frame (4×4, z along the cylinder, origin at its centre) and length of a link's cylinder."""
    length = float(np.linalg.norm(end))
    if length < 1e-9:  # no offset to the next frame: a short drum on the joint axis
        length = 2 * radius
        T = np.eye(4)
        T[:3, :3] = _z_to(axis)
        return T, np.zeros(3), length
    T = np.eye(4)
    T[:3, :3] = _z_to(end / length)
    T[:3, 3] = end / 2
    return T, end / 2, length


def check_inertia(mass: float, inertia: NDArray, what: str) -> None:
    """``ValueError`` naming ``what`` unless ``mass`` (kg) and ``inertia`` (3×3 about the centre of mass) are physical.

    Physical: a finite mass ≥ 0, a finite symmetric inertia whose principal moments are ≥ 0 and each at
    most the sum of the other two (the triangle inequality); a massless link has no inertia.
    """
    inertia = np.asarray(inertia, dtype=float)
    if not np.isfinite(mass) or mass < 0:
        raise ValueError(f"{what}: mass = {mass:g} kg is not allowed: a mass is a finite number ≥ 0 kg")
    if not np.all(np.isfinite(inertia)):
        raise ValueError(f"{what}: the inertia {inertia.tolist()} has a value that is not a finite number")
    for k, axis in enumerate("xyz"):
        if inertia[k, k] < 0:
            raise ValueError(f"{what}: I{axis}{axis} = {inertia[k, k]:g} kg·m² is negative: "
                             "a moment of inertia is ≥ 0")
    scale = max(1.0, float(np.abs(inertia).max())) * 1e-12
    if mass == 0 and np.abs(inertia).max() > scale:
        raise ValueError(f"{what}: mass 0 kg with a nonzero inertia is not physical: give the link's mass")
    moments = np.linalg.eigvalsh(inertia)  # ascending
    if moments[0] < -scale or moments[0] + moments[1] < moments[2] - scale:
        raise ValueError(f"{what}: the inertia is not physical: its principal moments "
                         f"({', '.join(f'{m:.6g}' for m in moments)}) kg·m² must be ≥ 0 and each at most "
                         "the sum of the other two (the triangle inequality)")


def link_inertials(table: LocatingTable, bodies: tuple[Body, ...]) -> list[tuple[float, NDArray, NDArray]]:
    """Each moving link's ``(mass, com, inertia)`` in its link frame {i} (kg, m (3,), kg·m² (3, 3) about the com).

    A body with an explicit ``com``/``inertia`` keeps them; otherwise it is the uniform cylinder from
    {i}'s origin to the next frame's origin (see :class:`Body`).
    """
    ends = [row.P for row in table.rows[1:]] + [tuple(table.tool[:3, 3])]
    out = []
    for row, body, end in zip(table.rows, bodies, ends, strict=True):
        if body.com is not None or body.inertia is not None:
            com = np.zeros(3) if body.com is None else np.asarray(body.com, dtype=float)
            inertia = np.zeros((3, 3)) if body.inertia is None else np.asarray(body.inertia, dtype=float)
        else:
            seg, com, length = _segment(np.asarray(row.k), np.asarray(end, dtype=float), body.radius)
            inertia = seg[:3, :3] @ cylinder_inertia(body.mass, body.radius, length) @ seg[:3, :3].T
        out.append((float(body.mass), com, inertia))
    return out


_JOINT_MATERIAL = '<material name="joint"><color rgba="0.15 0.15 0.15 1"/></material>'


def _cylinder_visual(T: NDArray, radius: float, length: float, material: str) -> str:
    return (f'<visual>{_origin(T)}<geometry><cylinder radius="{_f(radius)}" length="{_f(length)}"/></geometry>'
            f'<material name="{material}"/></visual>')


#: Pieces of a link's axis shorter than this (m) are no piece (a sphere where the whole axis is shorter).
_NO_LENGTH = 1e-9


def link_axis(body: Body, end: NDArray) -> list[NDArray[np.float64]]:
    """The points of a link's collision axis in its frame (m): its ``axis``, or its origin and ``end`` (the next
    frame's origin), pieces of no length dropped; one point where the axis has no length."""
    given = [np.asarray(point, dtype=float) for point in body.axis] or [np.zeros(3), np.asarray(end, dtype=float)]
    points = given[:1]
    for point in given[1:]:
        if np.linalg.norm(point - points[-1]) >= _NO_LENGTH:
            points.append(point)
    return points


def _capsule_collision(name: str, start: NDArray, end: NDArray, radius: float) -> str:
    """A collision capsule of ``radius`` (m) from ``start`` to ``end`` (m, in the link frame), or a sphere at
    ``start`` when they coincide."""
    length = float(np.linalg.norm(end - start))
    T = np.eye(4)
    if length < _NO_LENGTH:
        T[:3, 3] = start
        origin = _origin(T) if np.any(start) else ""
        return (f'<collision name="{name}">{origin}<geometry><sphere radius="{_f(radius)}"/></geometry>'
                "</collision>")
    T[:3, :3] = _z_to((end - start) / length)
    T[:3, 3] = (start + end) / 2
    return (f'<collision name="{name}">{_origin(T)}<geometry><capsule radius="{_f(radius)}" '
            f'length="{_f(length)}"/></geometry></collision>')


def _link_collisions(i: int, body: Body, end: NDArray) -> list[str]:
    """Link ``i``'s collision capsules along its axis (:func:`link_axis`): ``linkI_capsule``, ``linkI_capsule2`` …"""
    points = link_axis(body, end)
    pieces = list(itertools.pairwise(points)) or [(points[0], points[0])]
    return [_capsule_collision(f"link{i}_capsule{k + 1 if k else ''}", a, b, body.radius)
            for k, (a, b) in enumerate(pieces)]


def _to_axis(point: NDArray, axis: list[NDArray[np.float64]]) -> float:
    """The distance (m) of ``point`` to the polyline ``axis`` (its points, one or more)."""
    if len(axis) == 1:
        return float(np.linalg.norm(point - axis[0]))
    best = np.inf
    for a, b in itertools.pairwise(axis):
        s = float(np.clip((point - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0))
        best = min(best, float(np.linalg.norm(point - a - s * (b - a))))
    return best


def touching_pairs(table: LocatingTable, bodies: tuple[Body, ...], limits: tuple[JointLimits, ...]
                   ) -> list[tuple[str, str]]:
    """The pairs of links, not adjacent, whose collision shapes touch at every pose by construction.

    Links i and j > i + 1 are joined by the links between: joint i+1's origin A (fixed on link i) lies within
    d(A, axis i) of link i's axis, joint j's origin B within d(B, axis j) of link j's, and A and B are at most the
    distances between the joint origins of the links between apart (each constant on its link), plus the strokes
    of the prismatic joints between. When all that is within the two radii (a spherical wrist: its frames coincide,
    the links between have no length), the two shapes overlap whatever the joints do, and checking them says
    nothing. ``(link j, link i)`` names; the base's column (:func:`urdf_text`, of link 1's radius) is link 0.
    """
    n = table.n
    origins = [np.asarray(row.P, dtype=float) for row in table.rows] + [table.tool[:3, 3]]  # joint i+1 in frame {i}
    column = bool(np.linalg.norm(origins[0]) >= _NO_LENGTH and any(body.collides for body in bodies))
    axes = [[np.zeros(3), origins[0]]] + [link_axis(body, end) for body, end in zip(bodies, origins[1:], strict=True)]
    shaped = [column] + [body.collides for body in bodies]
    radius = [bodies[0].radius] + [body.radius for body in bodies]
    span = [float(np.linalg.norm(end)) for end in origins[1:]]  # link k's joint origins apart, k = 1 … n
    strokes = [max(abs(lim.lower or 0.0), abs(lim.upper or 0.0)) if row.kind == "T" else 0.0
               for row, lim in zip(table.rows, limits, strict=True)]
    names = ["base_link"] + [f"link{i}" for i in range(1, n + 1)]
    pairs = []
    for i in range(n + 1):
        for j in range(i + 2, n + 1):
            if not (shaped[i] and shaped[j]):
                continue
            apart = (_to_axis(origins[i], axes[i]) + sum(span[i:j - 1]) + sum(strokes[i:j])
                     + _to_axis(np.zeros(3), axes[j]))
            if not above(apart, radius[i] + radius[j]):
                pairs.append((names[j], names[i]))
    return pairs


def _rail_visual(T_fixed: NDArray, axis: NDArray, lower: float, upper: float, radius: float) -> str:
    """A prismatic joint's guide: a bar along its axis over the stroke [lower, upper] (m), in the parent's frame."""
    T = np.eye(4)
    T[:3, :3] = _z_to(axis)
    T[:3, 3] = axis * (lower + upper) / 2
    T = T_fixed @ T
    width = _f(radius * 0.8)
    return (f'<visual>{_origin(T)}<geometry><box size="{width} {width} {_f(upper - lower + 2 * radius)}"/>'
            '</geometry><material name="rail"/></visual>')


def urdf_text(
    name: str,
    table: LocatingTable,
    bodies: tuple[Body, ...],
    limits: tuple[JointLimits, ...],
    points: tuple[Point, ...],
    tool_name: str = "tool",
    comment: str = "",
    drives: DriveTrain | None = None,
    ros_limits: bool = False,
    collision_filters: tuple[tuple[str, str], ...] = (),
    gravity: tuple[float, float, float] | None = None,
) -> str:
    """URDF of the chain: links ``base_link``, ``link1`` … ``linkN``, ``tool_name`` and the points.
    ``bodies`` has one entry per moving link (``n``); ``limits`` one per joint; ``drives`` the drive train
    (module docstring), ``None`` for none. ``ros_limits``: an unknown effort or velocity limit is written as 0,
    ROS's "none" (urdfdom, and so Pinocchio, needs both attributes; armlab reads 0 as unknown), not left out.
    ``collision_filters``: pairs of link names never checked against each other (beyond the adjacent ones and
    :func:`touching_pairs`, always filtered), written as Drake's ``<drake:collision_filter_group>`` (a group of the
    two that ignores itself).
    ``gravity``: the arm's gravity (m/s², base frame) when it is not along −z, which every URDF reader assumes: the
    URDF's root is then a ``world`` link, its ``base_link`` welded to it turned so that gravity is −z in ``world``
    (:func:`upright`).
    """
    n = table.n
    if len(bodies) != n or len(limits) != n:
        raise ValueError(f"{name}: need {n} bodies and {n} joint limits, got {len(bodies)} and {len(limits)}")
    if drives is not None and drives.n != n:
        raise ValueError(f"{name}: the drive train has {drives.n} joints, the arm {n}")
    link_names = ["base_link"] + [f"link{i}" for i in range(1, n + 1)] + [tool_name]
    filters = list(dict.fromkeys((*collision_filters, *touching_pairs(table, bodies, limits))))
    out = ['<?xml version="1.0"?>']
    if comment:
        out.append(f"<!-- {_comment(comment)} -->")
    drake = f' xmlns:drake="{DRAKE_NAMESPACE}"' if drives is not None or filters else ""
    out.append(f'<robot name="{_a(name)}"{drake}>')
    out.append('  <material name="base"><color rgba="0.3 0.3 0.35 1"/></material>')
    out.append('  <material name="rail"><color rgba="0.7 0.72 0.75 1"/></material>')
    base_r = max(b.radius for b in bodies) * 2.5
    visuals: list[list[str]] = [[] for _ in range(n + 1)]  # per link 0 (base) … n, drawn in that link's frame
    visuals[0].append(f'<visual><origin xyz="0 0 {_f(-base_r / 4)}"/>'
                      f'<geometry><cylinder radius="{_f(base_r)}" length="{_f(base_r / 2)}"/></geometry>'
                      '<material name="base"/></visual>')
    pedestal = np.asarray(table.rows[0].P, dtype=float)
    if np.linalg.norm(pedestal) > 1e-9:  # a column from the base to joint 1
        seg, _, length = _segment(np.asarray(table.rows[0].k), pedestal, bodies[0].radius)
        visuals[0].append(_cylinder_visual(seg, bodies[0].radius, length, "base"))
        if any(body.collides for body in bodies):
            visuals[0].append(_capsule_collision("base_link_column", np.zeros(3), pedestal, bodies[0].radius))
    for i, (row, body, lim) in enumerate(zip(table.rows, bodies, limits, strict=True), start=1):
        if row.kind == "T" and lim.lower is not None and lim.upper is not None:  # the slider's guide, on the parent
            visuals[i - 1].append(_rail_visual(row.T_fixed, np.asarray(row.k, dtype=float), lim.lower, lim.upper,
                                               body.radius))
    ends = [row.P for row in table.rows[1:]] + [tuple(table.tool[:3, 3])]
    turn = None if gravity is None else upright(gravity)
    if turn is not None:
        out.append('  <link name="world"/>')
        out.append('  <joint name="world_base_link" type="fixed"><parent link="world"/><child link="base_link"/>'
                   f"{_origin(turn)}</joint>")
    out.append('  <link name="base_link">')
    out.extend(f"    {visual}" for visual in visuals[0])
    out.append("  </link>")
    inertials = link_inertials(table, bodies)
    for i, (row, body, lim, end, (mass, com, inertia)) in enumerate(
        zip(table.rows, bodies, limits, ends, inertials, strict=True), start=1
    ):
        seg, _, length = _segment(np.asarray(row.k), np.asarray(end, dtype=float), body.radius)
        joint_drum = np.eye(4)
        joint_drum[:3, :3] = _z_to(np.asarray(row.k))
        rgba = " ".join(map(_f, body.color))
        out.append(f'  <link name="link{i}">')
        if mass > 0:  # a link without mass data has no <inertial> (Drake needs none for kinematics)
            out.append(f'    <inertial><origin xyz="{" ".join(map(_f, com))}"/><mass value="{_f(mass)}"/>'
                       f'<inertia ixx="{_f(inertia[0, 0])}" ixy="{_f(inertia[0, 1])}" ixz="{_f(inertia[0, 2])}"'
                       f' iyy="{_f(inertia[1, 1])}" iyz="{_f(inertia[1, 2])}" izz="{_f(inertia[2, 2])}"/>'
                       "</inertial>")
        out.append(f'    <visual>{_origin(seg)}<geometry><cylinder radius="{_f(body.radius)}" '
                   f'length="{_f(length)}"/></geometry><material name="link{i}"><color rgba="{rgba}"/>'
                   "</material></visual>")
        if row.kind == "T":  # a slider block on the joint axis
            side = _f(body.radius * 2.2)
            out.append(f'    <visual>{_origin(joint_drum)}<geometry><box size="{side} {side} {side}"/></geometry>'
                       f'{_JOINT_MATERIAL}</visual>')
        else:  # a drum on the joint axis
            out.append(f'    <visual>{_origin(joint_drum)}<geometry><cylinder radius="{_f(body.radius * 1.3)}" '
                       f'length="{_f(body.radius * 2.4)}"/></geometry>{_JOINT_MATERIAL}</visual>')
        if body.collides:
            out.extend(f"    {element}" for element in _link_collisions(i, body, np.asarray(end, dtype=float)))
        out.extend(f"    {visual}" for visual in visuals[i])
        out.append("  </link>")
        kind = "prismatic" if row.kind == "T" else ("continuous" if lim.lower is None else "revolute")
        out.append(f'  <joint name="{_a(row.name)}" type="{kind}">')
        out.append(f'    <parent link="{_a(link_names[i - 1])}"/><child link="link{i}"/>')
        out.append(f"    {_origin(row.T_fixed)}")
        out.append(f'    <axis xyz="{" ".join(map(_f, row.k))}"/>')
        rates = [(key, 0.0 if value is None and ros_limits else value)
                 for key, value in (("effort", lim.effort), ("velocity", lim.velocity))]
        attributes = [f'{key}="{_f(value)}"' for key, value in (("lower", lim.lower), ("upper", lim.upper), *rates)
                      if value is not None]  # an unknown effort or velocity limit is left out (unlimited), or 0
        if attributes:
            out.append(f"    <limit {' '.join(attributes)}/>")
        if drives is not None:
            if drives.asymmetric:  # a URDF has one friction per joint: the mean, and the two in a comment
                out.append(f"    <!-- armlab: Coulomb friction T_c+ = {_f(drives.coulomb[i - 1])}, T_c- = "
                           f"{_f(drives.negative[i - 1])} N·m; friction= is their mean -->")
            friction = (drives.coulomb[i - 1] + drives.negative[i - 1]) / 2
            out.append(f'    <dynamics damping="{_f(drives.viscous[i - 1])}" friction="{_f(friction)}"/>')
        out.append("  </joint>")
    out.append(f'  <link name="{_a(tool_name)}"><visual><geometry><sphere radius="{_f(bodies[-1].radius * 1.2)}"/>'
               '</geometry><material name="tool"><color rgba="0.85 0.1 0.1 1"/></material></visual></link>')
    out.append(f'  <joint name="{_a(tool_name)}_weld" type="fixed"><parent link="link{n}"/>'
               f"<child link=\"{_a(tool_name)}\"/>{_origin(table.tool)}</joint>")
    for point in points:
        if point.name in link_names:
            continue  # the point is already a link (e.g. the tool)
        # a point of the tool frame hangs from link n (the tool link stays the end of the chain, what a reader takes)
        parent, xyz = ((link_names[n], (table.tool @ np.array([*point.xyz, 1.0]))[:3]) if point.link == n + 1
                       else (link_names[point.link], point.xyz))
        out.append(f'  <link name="{_a(point.name)}"/>')
        out.append(f'  <joint name="{_a(point.name)}_weld" type="fixed"><parent link="{_a(parent)}"/>'
                   f'<child link="{_a(point.name)}"/><origin xyz="{" ".join(map(_f, xyz))}"/></joint>')
    for i, row in enumerate(table.rows):
        ratio, motor = "1", ""
        if drives is not None:
            ratio = _f(drives.gear_ratio[i])
            motor = (f'<drake:gear_ratio value="{ratio}"/><drake:rotor_inertia value="{_f(drives.rotor_inertia[i])}"/>'
                     f"<!-- gearbox efficiency {_f(drives.efficiency[i])} (no URDF or Drake tag) -->")
        out.append(f'  <transmission name="{_a(row.name)}_transmission">'
                   "<type>transmission_interface/SimpleTransmission</type>"
                   f'<joint name="{_a(row.name)}"><hardwareInterface>hardware_interface/EffortJointInterface'
                   "</hardwareInterface></joint>"
                   f'<actuator name="{_a(row.name)}_motor"><mechanicalReduction>{ratio}</mechanicalReduction>{motor}'
                   "</actuator></transmission>")
    for a, b in filters:
        group = f"filter_{a}_{b}"
        out.append(f'  <drake:collision_filter_group name="{_a(group)}"><drake:member link="{_a(a)}"/>'
                   f'<drake:member link="{_a(b)}"/><drake:ignored_collision_filter_group name="{_a(group)}"/>'
                   "</drake:collision_filter_group>")
    out.append("</robot>")
    return "\n".join(out) + "\n"
