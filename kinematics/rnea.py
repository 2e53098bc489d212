"""Inverse dynamics of a batch of states by the recursive Newton–Euler algorithm.

τ = M(q) q̈ + C(q, q̇) q̇ − τ_g(q) for every sample at once: numpy over the batch, a Python loop only
over the n links. The equations are Craig's (*Introduction to Robotics*, 3rd ed., §6.5, eqs. 6.45–6.53;
Featherstone, *Rigid Body Dynamics Algorithms*, Table 5.1, in 3-vector form), written in each link's
own frame. With ``R`` the rotation of frame {i} in {i−1}, ``P`` the origin of {i} in {i−1}, ẑ the joint
axis, c_i the link's centre of mass and I_i its inertia about it, m_i its mass:

outward, i = 1 … n, from ω_0 = ω̇_0 = 0 and v̇_0 = −g (gravity as an acceleration of the base):

    ω_i  = Rᵀω_{i−1} + q̇_i ẑ                                         (6.45; prismatic: Rᵀω_{i−1})
    ω̇_i  = Rᵀω̇_{i−1} + Rᵀω_{i−1} × q̇_i ẑ + q̈_i ẑ                       (6.46; prismatic: Rᵀω̇_{i−1})
    v̇_i  = Rᵀ(ω̇_{i−1} × P + ω_{i−1} × (ω_{i−1} × P) + v̇_{i−1})          (6.47)
           [+ 2 ω_i × q̇_i ẑ + q̈_i ẑ for a prismatic joint]               (6.35)
    v̇_ci = ω̇_i × c_i + ω_i × (ω_i × c_i) + v̇_i                          (6.48)
    F_i  = m_i v̇_ci,   N_i = I_i ω̇_i + ω_i × I_i ω_i                     (6.49–6.50)

inward, i = n … 1 (R, P of link i+1 in i; f_{n+1} = n_{n+1} = 0):

    f_i = R f_{i+1} + F_i                                                (6.51)
    n_i = N_i + R n_{i+1} + c_i × F_i + P × R f_{i+1}                     (6.52)
    τ_i = n_i · ẑ (revolute),  f_i · ẑ (prismatic)                       (6.53)

The link frames are the arm's chain (:meth:`armlab.kinematics.locating.LocatingTable.steps`, the URDF's
link frames), each turned so that its joint axis is z. The mass properties are those of the Drake plant
of the same URDF (:func:`armlab.diagrams.plant.make_plant`, with the payload as a point mass at the tool
frame's origin), each moving link together with every body welded to it by fixed joints.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import as_batch, blocks, cos_sin, cross

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["LinkInertias", "inverse_dynamics", "link_inertias"]

@dataclass(frozen=True)
class LinkInertias:
    """Mass properties of the n moving links (each with the bodies welded to it), in the link frames {i}.

    ``mass`` (kg) ``(n,)``, ``com`` (m) ``(n, 3)``: centre of mass in {i}; ``inertia`` (kg·m²) ``(n, 3, 3)``:
    about the centre of mass, in {i}'s axes.
    """

    mass: NDArray[np.float64]
    com: NDArray[np.float64]
    inertia: NDArray[np.float64]


#: Mass properties already extracted, by URDF text, base, tool, joints and payload.
_INERTIAS: dict[tuple, LinkInertias] = {}


def link_inertias(arm: Arm, payload: float = 0.0) -> LinkInertias:
    """Each moving link's mass properties from the arm's Drake plant, with a ``payload`` (kg) at the tool.

    Every body welded to a moving link (through fixed joints, the tool's and the payload's included) is
    re-expressed in the link's frame and added to it. Extracted once per URDF and payload.
    """
    from armlab.diagrams.plant import check_payload, make_plant

    payload = check_payload(payload)
    text = arm.urdf() if arm.urdf_file is None else arm.urdf_file.read_text()
    key = (text, arm.base_link, arm.tool_name, tuple(arm.joint_names), payload)
    if key not in _INERTIAS:
        plant = make_plant(arm, np.zeros(3), payload)
        context = plant.CreateDefaultContext()
        mass, com, inertia = np.zeros(arm.n), np.zeros((arm.n, 3)), np.zeros((arm.n, 3, 3))
        for i, name in enumerate(arm.joint_names):
            link = plant.GetJointByName(name).child_body()
            moment, about_origin = np.zeros(3), np.zeros((3, 3))
            for body in plant.GetBodiesWeldedTo(link):
                X = plant.CalcRelativeTransform(context, link.body_frame(), body.body_frame())  # X_LB
                M = body.CalcSpatialInertiaInBodyFrame(context).ReExpress(X.rotation()).Shift(-X.translation())
                mass[i] += M.get_mass()
                moment += M.CalcComMoment()
                about_origin += M.CalcRotationalInertia().CopyToFullMatrix3()
            com[i] = moment / mass[i] if mass[i] > 0 else 0.0
            c = com[i]
            inertia[i] = about_origin - mass[i] * (c @ c * np.eye(3) - np.outer(c, c))  # parallel axes
        _INERTIAS[key] = LinkInertias(mass, com, inertia)
    return _INERTIAS[key]


def _z_cross(x: NDArray, rate: NDArray) -> NDArray:
    """x × (rate ẑ) = rate (x_y, −x_x, 0)."""
    return np.stack([x[1] * rate, -x[0] * rate, np.zeros_like(rate)])


def _into(R: NDArray, c: NDArray | None, s: NDArray | None, x: NDArray) -> NDArray:
    """(R·R_z(q))ᵀ x: a vector of frame {i−1} in frame {i} (``c, s`` = cos q, sin q; ``None``: no turn)."""
    y = R.T @ x
    if c is None:
        return y
    return np.stack([c * y[0] + s * y[1], c * y[1] - s * y[0], y[2]])


def _out_of(R: NDArray, c: NDArray | None, s: NDArray | None, x: NDArray) -> NDArray:
    """R·R_z(q) x: a vector of frame {i} in frame {i−1}."""
    if c is not None:
        x = np.stack([c * x[0] - s * x[1], s * x[0] + c * x[1], x[2]])
    return R @ x


def _block(
    links: list[tuple[NDArray, NDArray, bool]], inertias: LinkInertias, g: NDArray,
    q: NDArray, qd: NDArray, qdd: NDArray,
) -> NDArray:
    """τ ``(n, N)`` for one block of states ``(n, N)`` (the module docstring's equations)."""
    n, N = q.shape
    w = np.zeros((3, N))
    wd = np.zeros((3, N))
    vd = np.broadcast_to(-g[:, None], (3, N))
    turns, forces, moments = [], [], []
    for i, (R, P, revolute) in enumerate(links):
        c, s = cos_sin(q[i]) if revolute else (None, None)
        P_i = P[:, None] if revolute else P[:, None] + R[:, 2:3] * q[i]  # origin of {i} in {i−1}
        vd = _into(R, c, s, cross(wd, P_i) + cross(w, cross(w, P_i)) + vd)  # (6.47)
        if revolute:
            w_in = _into(R, c, s, w)
            wd = _into(R, c, s, wd) + _z_cross(w_in, qd[i])  # (6.46)
            wd[2] += qdd[i]
            w = w_in
            w[2] += qd[i]  # (6.45)
        else:
            w, wd = _into(R, None, None, w), _into(R, None, None, wd)
            vd = vd + 2 * _z_cross(w, qd[i])  # (6.35)
            vd[2] += qdd[i]
        com = inertias.com[i][:, None]
        F = inertias.mass[i] * (cross(wd, com) + cross(w, cross(w, com)) + vd)  # (6.48)–(6.49)
        I = inertias.inertia[i]
        N_i = I @ wd + cross(w, I @ w)  # (6.50)
        turns.append((R, c, s, P_i))
        forces.append(F)
        moments.append(N_i + cross(com, F))
    tau = np.empty((n, N))
    f = n_ = None
    for i in range(n - 1, -1, -1):
        f_i, n_i = forces[i], moments[i]
        if f is not None:  # link i+1's force and moment, in frame {i}
            R, c, s, P_next = turns[i + 1]
            f_out = _out_of(R, c, s, f)
            f_i = f_i + f_out  # (6.51)
            n_i = n_i + _out_of(R, c, s, n_) + cross(P_next, f_out)  # (6.52)
        tau[i] = n_i[2] if links[i][2] else f_i[2]  # (6.53)
        f, n_ = f_i, n_i
    return tau


def inverse_dynamics(
    arm: Arm, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike, gravity: str | ArrayLike | None = None,
    payload: float = 0.0,
) -> NDArray[np.float64]:
    """Joint torques/forces τ = M(q) q̈ + C(q, q̇) q̇ − τ_g(q) (N·m or N), ``(n,)`` or ``(..., n)``.

    ``q, qd, qdd``: joint positions (rad or m), rates and accelerations, ``(n,)`` or ``(..., n)``,
    broadcast together. ``gravity``: as :func:`armlab.diagrams.plant.resolve_gravity` (default the arm's);
    ``payload``: a point mass (kg) at the tool frame's origin. Equal to Drake's ``CalcInverseDynamics``
    with gravity as the plant's force elements. ``ValueError`` for a kinematic arm (no mass data).
    """
    from armlab.diagrams.plant import resolve_gravity

    arm.require_dynamics("inverse dynamics")
    n = arm.n
    q, qd, qdd = np.broadcast_arrays(as_batch(q, n, "q"), as_batch(qd, n, "qd"), as_batch(qdd, n, "qdd"))
    g = resolve_gravity(arm, gravity)
    inertias = link_inertias(arm, payload)
    # link frames turned so each joint axis is z: {i}' = {i}·A_i, inertias re-expressed in them
    turned = [np.eye(4) if step.post is None else step.post for step in arm.table.steps]
    links = []
    for i, step in enumerate(arm.table.steps):
        C = (turned[i - 1] if i else np.eye(4)) @ step.pre  # {i}' (before its joint moves) in {i−1}'
        links.append((C[:3, :3].copy(), C[:3, 3].copy(), step.revolute))
    A_T = np.array([T[:3, :3] for T in turned])
    local = LinkInertias(inertias.mass, np.einsum("ijk,ik->ij", A_T, inertias.com),
                         A_T @ inertias.inertia @ np.swapaxes(A_T, -1, -2))
    shape = q.shape[:-1]
    q, qd, qdd = (np.ascontiguousarray(a.reshape(-1, n).T) for a in (q, qd, qdd))
    tau = np.empty_like(q)
    for block in blocks(q.shape[1]):
        tau[:, block] = _block(links, local, g, q[:, block], qd[:, block], qdd[:, block])
    return tau.T.reshape(shape + (n,))
