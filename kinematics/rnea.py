"""Inverse dynamics of a batch of states by the recursive Newton–Euler algorithm.

τ = M(q) q̈ + C(q, q̇) q̇ − τ_g(q) for every sample at once: numpy over the batch, a Python loop only
over the n links. The equations are Craig's (*Introduction to Robotics*, 3rd ed., §6.5, eqs. 6.45–6.53;
Featherstone, *Rigid Body Dynamics Algorithms*, Table 5.1, in 3-vector form), written in each link's
own frame. With ``R`` the rotation of frame {i} in {i−1}, ``P`` the origin of {i} in {i−1}, ẑ the joint
axis, c_i the link's centre of mass and I_i its inertia about it, m_i its mass:

outward, i = 1 … n, from ω_0 = ω̇_0 = 0 and v̇_0 = −g (gravity as an acceleration of the base)::

    ω_i  = Rᵀω_{i−1} + q̇_i ẑ                                         (6.45; prismatic: Rᵀω_{i−1})
    ω̇_i  = Rᵀω̇_{i−1} + Rᵀω_{i−1} × q̇_i ẑ + q̈_i ẑ                       (6.46; prismatic: Rᵀω̇_{i−1})
    v̇_i  = Rᵀ(ω̇_{i−1} × P + ω_{i−1} × (ω_{i−1} × P) + v̇_{i−1})          (6.47)
           [+ 2 ω_i × q̇_i ẑ + q̈_i ẑ for a prismatic joint]               (§6.5)
    v̇_ci = ω̇_i × c_i + ω_i × (ω_i × c_i) + v̇_i                          (6.48)
    F_i  = m_i v̇_ci,   N_i = I_i ω̇_i + ω_i × I_i ω_i                     (6.49–6.50)

inward, i = n … 1 (R, P of link i+1 in i; f_{n+1} = n_{n+1} = 0)::

    f_i = R f_{i+1} + F_i                                                (6.51)
    n_i = N_i + R n_{i+1} + c_i × F_i + P × R f_{i+1}                     (6.52)
    τ_i = n_i · ẑ (revolute),  f_i · ẑ (prismatic)                       (6.53)

The link frames are the arm's chain (:meth:`armlab.kinematics.locating.LocatingTable.steps`, the URDF's
link frames), each turned so that its joint axis is z. The mass properties are the arm's own
(:meth:`armlab.models.arm.Arm.mass_properties`: each moving link with every body welded to it by fixed
joints, as the Drake plant of its URDF has them), with the payload as a point mass at the tool frame's
origin; the tests check the torques against Drake's ``CalcInverseDynamics``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import as_batch, blocks, cos_sin, cross, turn_z
from armlab.values import check_payload, resolve_gravity

if TYPE_CHECKING:
    from armlab.drives.train import DriveTrain
    from armlab.models.arm import Arm

__all__ = ["LinkInertias", "inverse_dynamics", "inverse_dynamics_and_tool_point", "link_inertias", "merge_inertials"]


@dataclass(frozen=True)
class LinkInertias:
    """Mass properties of the n moving links (each with the bodies welded to it), in the link frames {i}.

    ``mass`` (kg) ``(n,)``, ``com`` (m) ``(n, 3)``: centre of mass in {i}; ``inertia`` (kg·m²) ``(n, 3, 3)``:
    about the centre of mass, in {i}'s axes.
    """

    mass: NDArray[np.float64]
    com: NDArray[np.float64]
    inertia: NDArray[np.float64]


def merge_inertials(parts: list[tuple[float, NDArray, NDArray]]) -> tuple[float, NDArray, NDArray]:
    """One rigid body of ``parts`` welded together: ``(mass, com, inertia)`` from each part's (kg, m (3,), kg·m² (3, 3)
    about its own centre of mass, all in one frame); the inertia is about the joint centre of mass (parallel axes)."""
    total = float(sum(m for m, _, _ in parts))
    if total == 0:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    com = np.sum([m * np.asarray(c, dtype=float) for m, c, _ in parts], axis=0) / total
    inertia = np.zeros((3, 3))
    for m, c, I in parts:
        d = np.asarray(c, dtype=float) - com
        inertia = inertia + np.asarray(I, dtype=float) + m * (d @ d * np.eye(3) - np.outer(d, d))
    return total, com, inertia


def link_inertias(arm: Arm, payload: float = 0.0) -> LinkInertias:
    """Each moving link's mass properties (:meth:`Arm.mass_properties`, the numbers its URDF and so its
    Drake plant are built from), with a ``payload`` (kg) as a point mass at the tool frame's origin added to
    link n, as :func:`armlab.models.plant.make_plant` welds it there."""
    payload = check_payload(payload)
    mass, com, inertia = arm.mass_properties()
    if payload > 0:
        r = arm.table.tool[:3, 3]  # the tool frame's origin in link frame {n}
        mass[-1], com[-1], inertia[-1] = merge_inertials([(mass[-1], com[-1], inertia[-1]),
                                                          (payload, r, np.zeros((3, 3)))])
    return LinkInertias(mass, com, inertia)


def _skew(v: NDArray) -> NDArray:
    """[v]×, the matrix with [v]× x = v × x."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


@dataclass(frozen=True)
class _Link:
    """The constants of one link in its turned frame {i}' (joint axis z): ``C``, ``P`` the rotation and
    origin of {i}' in {i−1}' at q_i = 0; its mass m, ``K`` = [−[m c]×; I_o] (6×3) with c its centre of mass
    and I_o its inertia about the origin, ``mc`` = [m c]×.
    """

    C: NDArray
    P: NDArray
    revolute: bool
    mass: float
    K: NDArray
    mc: NDArray


def _block(links: list[_Link], g: NDArray, q: NDArray, qd: NDArray, qdd: NDArray,
           velocity: bool = False) -> tuple[NDArray, NDArray]:
    """τ ``(n, B)`` for one block of states ``(n, B)`` (the module docstring's equations), and the last link's
    ω, ω̇, v̇ (and with ``velocity`` its origin's velocity v) ``(3 or 4, 3, B)`` in its frame {n}'.

    The three vectors ω, ω̇ and v̇ of a link (and v: v_i = Rᵀ(v_{i−1} + ω_{i−1} × P) [+ q̇_i ẑ prismatic]) are one
    array ``(3 or 4, 3, B)`` rotated together; the force and moment ``(2, 3, B)`` likewise. Moments are taken
    about the link's origin, n_i = I_o ω̇_i + ω_i × I_o ω_i + m c_i × v̇_i (= N_i + c_i × F_i of 6.50–6.52).
    """
    n, B = q.shape
    W = np.zeros((4 if velocity else 3, 3, B))  # ω, ω̇, v̇ (, v) of the base
    W[2] = -g[:, None]
    turns, wrenches = [], []
    for i, link in enumerate(links):
        w, wd = W[0], W[1]
        P = link.P[:, None] if link.revolute else link.P[:, None] + link.C[:, 2:3] * q[i]  # origin of {i} in {i−1}
        A = np.matmul(-_skew(link.P), W[:2]) if link.revolute else cross(W[:2], P)  # ω × P, ω̇ × P
        W[2] += A[1] + cross(w, A[0])  # v̇ + ω̇ × P + ω × (ω × P), then rotated: (6.47)
        if velocity:
            W[3] += A[0]  # v + ω × P
        W = np.matmul(link.C.T, W)  # Cᵀ, then R_z(q)ᵀ: into frame {i}
        turn = cos_sin(q[i]) if link.revolute else None  # (cos q_i, sin q_i) of a revolute joint
        if turn is not None:
            turn_z(W, *turn)
            w, wd = W[0], W[1]
            wd[0] += qd[i] * w[1]  # Rᵀω × q̇ ẑ = q̇ (ω_y, −ω_x, 0): (6.46)
            wd[1] -= qd[i] * w[0]
            wd[2] += qdd[i]
            w[2] += qd[i]  # (6.45)
        else:
            w, vd = W[0], W[2]
            vd[0] += 2 * qd[i] * w[1]  # 2 ω × q̇ ẑ + q̈ ẑ (prismatic, §6.5)
            vd[1] -= 2 * qd[i] * w[0]
            vd[2] += qdd[i]
            if velocity:
                W[3, 2] += qd[i]
        X = np.matmul(link.K, W[:2])  # [ω × m c; I_o ω], [ω̇ × m c; I_o ω̇]
        wrench = X[1].reshape(2, 3, B) + cross(w, X[0].reshape(2, 3, B))
        wrench[0] += link.mass * W[2]  # F = m (v̇ + ω̇ × c + ω × (ω × c)): (6.48)–(6.49)
        wrench[1] += link.mc @ W[2]  # n = I_o ω̇ + ω × I_o ω + m c × v̇
        turns.append((turn, P))
        wrenches.append(wrench)
    tau = np.empty((n, B))
    for i in range(n - 1, -1, -1):
        wrench = wrenches[i]
        if i < n - 1:  # link i+1's force and moment, R (f, n), in frame {i}: (6.51)–(6.52)
            turn, P = turns[i + 1]
            child = wrenches[i + 1]
            if turn is not None:
                turn_z(child, turn[0], -turn[1])  # R_z(q)
            child = np.matmul(links[i + 1].C, child)
            wrench += child
            wrench[1] += cross(P, child[0])
        tau[i] = wrench[1, 2] if links[i].revolute else wrench[0, 2]  # (6.53)
    return tau, W


def inverse_dynamics(
    arm: Arm, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike, gravity: str | ArrayLike | None = None,
    payload: float = 0.0, drives: DriveTrain | None = None,
) -> NDArray[np.float64]:
    """Joint torques/forces τ = M(q) q̈ + C(q, q̇) q̇ − τ_g(q) + the drive train's (N·m or N), ``(n,)`` or ``(..., n)``.

    ``q, qd, qdd``: joint positions (rad or m), rates and accelerations, ``(n,)`` or ``(..., n)``,
    broadcast together. ``gravity``: as :func:`armlab.models.plant.resolve_gravity` (default the arm's);
    ``payload``: a point mass (kg) at the tool frame's origin; ``drives``: the drive train whose
    G²·J_m·q̈ + B·q̇ + T_c±·tanh(q̇/v_s) (:meth:`~armlab.drives.train.DriveTrain.torque`; T_c+ for q̇ ≥ 0, T_c−
    below) is added, ``None``: the arm's own (``arm.drives``; none: ideal drives, the rigid arm alone). Equal to
    Drake's ``CalcInverseDynamics``
    with gravity and the joints' damping as the plant's force elements and the actuators' reflected inertia, plus
    the Coulomb friction. ``ValueError`` for a kinematic arm (no mass data).
    """
    return _newton_euler(arm, q, qd, qdd, gravity, payload, tool=False, drives=drives)[0]


def inverse_dynamics_and_tool_point(
    arm: Arm, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike, gravity: str | ArrayLike | None = None,
    payload: float = 0.0, drives: DriveTrain | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(τ, [p v a] of the tool point): :func:`inverse_dynamics` and, from the same outward recursion, the tool
    point's position (m), velocity (m/s) and acceleration (m/s²) in the world frame, ``(..., n)`` and ``(..., 9)``.

    The recursion also carries each link origin's velocity; with ω, ω̇, v̇, v of the last link in its frame and r
    the tool point there, the tool point moves at v + ω × r and accelerates at v̇ + ω̇ × r + ω × (ω × r) (+ g:
    the recursion's v̇ starts from −g), turned into the world by the tool pose of ``arm.forward``. The same
    numbers as :func:`armlab.kinematics.differential.tool_motion`'s [v], [a] and the forward kinematics, for one
    pass instead of three.
    """
    return _newton_euler(arm, q, qd, qdd, gravity, payload, tool=True, drives=drives)


def _newton_euler(arm: Arm, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike, gravity: str | ArrayLike | None,
                  payload: float, tool: bool,
                  drives: DriveTrain | None) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """τ ``(..., n)`` (with the drive train ``drives``, ``None``: the arm's) and, if ``tool``, the tool point's
    [p v a] ``(..., 9)`` (else an empty array)."""
    arm.require_dynamics("inverse dynamics")
    n = arm.n
    arrays = (as_batch(q, n, "q"), as_batch(qd, n, "qd"), as_batch(qdd, n, "qdd"))
    try:
        q, qd, qdd = np.broadcast_arrays(*arrays)
    except ValueError:
        shapes = ", ".join(f"{name} {a.shape}" for name, a in zip(("q", "qd", "qdd"), arrays, strict=True))
        raise ValueError(f"q, qd and qdd have shapes that do not fit together ({shapes}): give each (n,) or the "
                         "same (..., n) batch (an (n,) one applies to every row)") from None
    g = resolve_gravity(arm, gravity)
    links = _links(arm, link_inertias(arm, payload))
    shape = q.shape[:-1]
    q, qd, qdd = (np.ascontiguousarray(a.reshape(-1, n).T) for a in (q, qd, qdd))
    tau = np.empty_like(q)
    last = np.empty((4, 3, q.shape[1])) if tool else np.empty((0, 3, 0))  # ω, ω̇, v̇, v of link n in {n}'
    for block in blocks(q.shape[1]):
        tau[:, block], W = _block(links, g, q[:, block], qd[:, block], qdd[:, block], velocity=tool)
        if tool:
            last[..., block] = W
    train = arm.drives if drives is None else drives
    if train is not None:
        if train.n != n:
            raise ValueError(f"{arm.name}: the drive train has {train.n} joint(s); the arm has {n}")
        tau += train.torque(qd.T, qdd.T).T
    if not tool:
        return tau.T.reshape(shape + (n,)), last
    step = arm.table.steps[-1]
    M = arm.table.tool if step.post is None else step.post @ arm.table.tool  # the tool frame in {n}'
    r = M[:3, 3, None]
    w, wd, vd, v = last
    v_tool = v + cross(w, r)
    a_tool = vd + cross(wd, r) + cross(w, cross(w, r))
    pose = arm.forward(q.T).tool  # (N, 4, 4): the tool frame in the world, R_0t = R_0n'·M_Rᵀ
    pva = np.empty((q.shape[1], 9))
    pva[:, :3] = pose[:, :3, 3]
    for k, vector in ((1, v_tool), (2, a_tool)):
        in_tool = M[:3, :3].T @ vector  # in the tool frame's axes, then R_0t column by column
        pva[:, 3 * k:3 * k + 3] = sum(pose[:, :3, j] * in_tool[j][:, None] for j in range(3))
    pva[:, 6:] += g
    return tau.T.reshape(shape + (n,)), pva.reshape(shape + (9,))


def _links(arm: Arm, inertias: LinkInertias) -> list[_Link]:
    """The constants of each link (:class:`_Link`) of ``arm``'s chain with mass properties ``inertias``."""
    # link frames turned so each joint axis is z: {i}' = {i}·A_i, mass properties re-expressed in them
    turned = [np.eye(4) if step.post is None else step.post for step in arm.table.steps]
    links = []
    for i, step in enumerate(arm.table.steps):
        pre = np.eye(4) if step.pre is None else step.pre
        C = (turned[i - 1] if i else np.eye(4)) @ pre  # {i}' (before its joint moves) in {i−1}'
        A_T = turned[i][:3, :3]
        m, c = inertias.mass[i], A_T @ inertias.com[i]
        I_o = A_T @ inertias.inertia[i] @ A_T.T + m * (c @ c * np.eye(3) - np.outer(c, c))  # about the origin
        links.append(_Link(C[:3, :3].copy(), C[:3, 3].copy(), step.revolute, m, np.vstack([-_skew(m * c), I_o]),
                           _skew(m * c)))
    return links
