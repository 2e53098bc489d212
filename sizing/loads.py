"""What each joint's drive carries: the arm with a payload or with the drives' own masses, and the load along a cycle.

An arm that carries more (a load case's payload at its tool, the chosen motors and gearboxes on its links) is
the same :class:`~armlab.models.arm.Arm` with its links' mass properties changed: each changed link's body
becomes an explicit one (mass, centre of mass, inertia in the link frame {i},
:class:`~armlab.models.write_urdf.Body`) merged from its own and the added part
(:func:`~armlab.kinematics.rnea.merge_inertials`). So its URDF, its Drake plant (the one builder) and its
Newton–Euler inverse dynamics all see the added mass; nothing else builds a model.

:func:`joint_loads` gives per load case and sample the joint-side load torque τ_L (N·m: the arm's inverse
dynamics, payload held where the cycle says), the load inertia J_load = M_kk(q) (kg·m², the mass
matrix's diagonal, from the inverse dynamics of a unit acceleration of joint k with gravity off) and the static
torque τ_g(q) (N·m: the inverse dynamics at rest, what a holding brake must hold).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.drives.train import DriveTrain
from armlab.kinematics.rnea import merge_inertials
from armlab.models.write_urdf import Body, link_inertials

if TYPE_CHECKING:
    from armlab.models.arm import Arm
    from armlab.sizing.duty import CycleSamples, LoadCase

__all__ = ["Loads", "joint_loads", "with_link_masses", "with_payload"]


def _with_parts(arm: Arm, parts: dict[int, list[tuple[float, NDArray, NDArray]]]) -> Arm:
    """``arm`` with rigid parts ``(mass, com, inertia)`` (link frame {i+1}, inertia about its com) welded to link
    ``i`` (0-based) for each key; its URDF is generated from the changed bodies."""
    arm.require_dynamics("adding mass to its links")
    inertials = link_inertials(arm.table, arm.bodies)
    bodies = list(arm.bodies)
    for i, extra in parts.items():
        if not extra or all(m == 0 for m, _, _ in extra):
            continue
        mass, com, inertia = merge_inertials([inertials[i], *extra])
        bodies[i] = Body(mass, arm.bodies[i].radius, arm.bodies[i].color,
                         (float(com[0]), float(com[1]), float(com[2])),
                         tuple((float(row[0]), float(row[1]), float(row[2])) for row in inertia))
    return replace(arm, bodies=tuple(bodies), urdf_file=None)


def with_payload(arm: Arm, case: LoadCase) -> Arm:
    """``arm`` carrying the load case's payload on its last link: its centre of mass at the tool point plus the
    offset (tool frame), its inertia turned into the link frame {n}; ``arm`` itself for a massless case."""
    if case.mass == 0:
        return arm
    tool = arm.table.tool  # the tool frame in link frame {n}
    R = tool[:3, :3]
    com = tool[:3, 3] + R @ np.asarray(case.offset)
    return _with_parts(arm, {arm.n - 1: [(case.mass, com, R @ np.asarray(case.inertia) @ R.T)]})


def with_link_masses(arm: Arm, masses: ArrayLike) -> Arm:
    """``arm`` with point masses (kg, ``(n,)``) at its joints: ``masses[k]`` (joint k+1's motor and gearbox)
    sits on the link before it, at that joint's origin (link k carries joint k+1's drive); joint 1's sits on the
    base and moves nothing."""
    masses = np.asarray(masses, dtype=float)
    if masses.shape != (arm.n,) or not np.all(np.isfinite(masses)) or np.any(masses < 0):
        raise ValueError(f"drive masses {np.ravel(masses).tolist()} are not allowed: {arm.n} finite masses ≥ 0 kg")
    parts = {k - 1: [(float(masses[k]), np.asarray(arm.table.rows[k].P, dtype=float), np.zeros((3, 3)))]
             for k in range(1, arm.n)}
    return _with_parts(arm, parts)


@dataclass(frozen=True)
class Loads:
    """Per load case ``L``, sample ``T`` and joint ``n``: the load torque ``tau`` (N·m, joint side), the load
    inertia ``inertia`` (kg·m², M_kk) and the static (gravity) torque ``static`` (N·m, joint side), each
    ``(L, T, n)``."""

    tau: NDArray[np.float64]
    inertia: NDArray[np.float64]
    static: NDArray[np.float64]


def joint_loads(arm: Arm, samples: CycleSamples, cases: tuple[LoadCase, ...]) -> Loads:
    """The load of every joint along the cycle for each load case (see the module docstring): the payload held
    only where ``samples.carrying``; the arm's gravity."""
    q, qd, qdd = samples.q, samples.qd, samples.qdd
    n, T = arm.n, q.shape[0]
    empty = _torque_and_inertia(arm, q, qd, qdd)
    tau, inertia, static = (np.empty((len(cases), T, n)) for _ in range(3))
    held = samples.carrying
    for c, case in enumerate(cases):
        tau[c], inertia[c], static[c] = empty
        if case.mass > 0 and held.any():
            tau[c, held], inertia[c, held], static[c, held] = _torque_and_inertia(with_payload(arm, case), q[held],
                                                                                  qd[held], qdd[held])
    return Loads(tau, inertia, static)


def _torque_and_inertia(arm: Arm, q: NDArray, qd: NDArray, qdd: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """τ ``(T, n)`` of the samples, the mass matrix's diagonal ``(T, n)`` and the gravity torque ``(T, n)`` at
    their positions.

    The load a candidate drive sees: the arm's rigid-body torque plus its joints' own friction (the arm's drive
    train's B and T_c, the joints' bearings), without the arm's rotor inertia (a candidate brings its own, added
    by the selection); the mass matrix is the links' alone (J_load of the inertia ratio)."""
    n = arm.n
    rigid = DriveTrain.ideal(n)
    # the drive train adds G²·J_m·q̈ + friction (G and η enter nothing else): without J_m, the friction alone
    joints = rigid if arm.drives is None else replace(arm.drives, rotor_inertia=np.zeros(n))
    tau = arm.inverse_dynamics(q, qd, qdd, drives=joints)
    units = np.broadcast_to(np.eye(n)[:, None, :], (n, q.shape[0], n))  # q̈ = e_k for every sample
    zero = np.zeros_like(units)
    columns = arm.inverse_dynamics(np.broadcast_to(q, units.shape), zero, units, gravity="off", drives=rigid)
    at_rest = np.zeros_like(q)
    return tau, np.einsum("ktk->tk", columns), arm.inverse_dynamics(q, at_rest, at_rest, drives=rigid)
