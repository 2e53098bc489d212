"""Differential kinematics of the tool point: the geometric Jacobian, the tool's twist and acceleration,
manipulability and the smallest singular value.

Everything is in the world (= base) frame and follows from the chain of frames T_{0,i} of paper 003's
matrix of nominal geometry (:meth:`armlab.kinematics.locating.LocatingTable.frames`, the URDF's link
frames): joint i turns about, or slides along, the unit axis z_i = R_{0,i} k_i through the origin p_i of
frame {i}. For the tool point p_t (the origin of the tool frame, ``arm.forward(q).tool``), column i of
the geometric Jacobian J = [J_v; J_ω] is (Siciliano et al., *Robotics*, eq. 3.30)

    revolute:  [z_i × (p_t − p_i); z_i],        prismatic:  [z_i; 0],

so the tool's twist is [v; ω] = J q̇. Its classical acceleration [a; ω̇] = J q̈ + J̇ q̇ comes from the
columns' time derivatives, with ż_i = ω_i × z_i (the axis is fixed in link i) and ṗ_i = v_i:

    revolute:  d/dt [z_i × (p_t − p_i)] = (ω_i × z_i) × (p_t − p_i) + z_i × (v_t − v_i),   d/dt z_i = ω_i × z_i
    prismatic: d/dt z_i = ω_i × z_i,

where the angular velocity ω_i of link i and the tool point's velocity relative to the origin of frame {i}
follow from prefix sums over the joints (vectorised over joints and samples): joints j ≤ i move both points
as one body turning at ω_i (a slide moves both alike), joints j > i move the tool point alone, so

    ω_i = Σ_{j ≤ i, revolute} q̇_j z_j,
    v_t − v_i = ω_i × (p_t − p_i) + Σ_{j > i} q̇_j J_v,j     (J_v,j: column j's [v] rows).

Every function takes one configuration ``(n,)`` or a batch ``(..., n)``.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import as_batch, chain_blocks, cross

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["AXES", "default_axes", "jacobian", "manipulability", "sigma_min", "tool_motion"]

#: Samples per block in :func:`tool_motion`: its dozen working arrays ``(n, 3, block)`` then stay small enough to be
#: reused from the heap; at 4096 samples each call page-faults megabytes of fresh memory in (2–2.5× slower).
MOTION_BLOCK = 1024
#: Rows of the Jacobian each ``axes`` choice selects: all six, the translational [v] or the rotational [ω].
AXES = {"all": slice(0, 6), "trans": slice(0, 3), "rot": slice(3, 6)}


def default_axes(n: int) -> Literal["all", "trans"]:
    """The rows of J that measure an n-joint arm's manipulability by default: all six when n ≥ 6 (it can
    reach full poses), else the translational rows v (a position task)."""
    return "all" if n >= 6 else "trans"


def _chain(arm: Arm, q: NDArray[np.float64], size: int | None = None
           ) -> Iterator[tuple[slice, NDArray, NDArray, NDArray]]:
    """A block at a time: ``(block, z, p, p_t)``, the world joint axes z_i and frame origins p_i ``(n, 3, B)``
    and the tool point ``(3, B)`` of the samples ``block`` of ``q`` flattened to ``(N, n)``; blocks of at most
    ``size`` samples if given, else :func:`~armlab.kinematics.batch.chain_blocks`' own."""
    n = arm.n
    k = np.array([row.k for row in arm.table.rows])  # k_i in frame {i}
    flat = q.reshape(-1, n)
    size = size or max(1, flat.shape[0])
    for start in range(0, flat.shape[0], size):
        for block, frames in chain_blocks(flat[start:start + size], arm.table.steps, arm.table.tool):
            R = frames[1:n + 1, :, :3]
            if (k == (0.0, 0.0, 1.0)).all():  # z_i = R_{0,i} k_i
                z = R[:, :, 2]
            else:
                z = np.sum([k[:, j, None, None] * R[:, :, j] for j in range(3) if k[:, j].any()], axis=0)
            yield slice(start + block.start, start + block.stop), z, frames[1:n + 1, :, 3], frames[n + 1, :, 3]


def _columns(revolute: NDArray, z: NDArray, p: NDArray, p_tool: NDArray) -> tuple[NDArray, NDArray]:
    """The Jacobian's columns J_v, J_ω ``(n, 3, B)``: [z_i × (p_t − p_i); z_i] or [z_i; 0]."""
    lever = cross(z, p_tool - p)
    if revolute.all():
        return lever, z
    return np.where(revolute, lever, z), np.where(revolute, z, 0.0)


def jacobian(arm: Arm, q: ArrayLike) -> NDArray[np.float64]:
    """Geometric Jacobian of the tool point in the world frame, rows [v; ω]: ``(6, n)`` or ``(..., 6, n)``.

    ``q`` (rad or m) has shape ``(n,)`` or ``(..., n)``; [v; ω] = J q̇ is the tool point's velocity (m/s)
    and the tool's angular velocity (rad/s) — Drake's ``CalcJacobianSpatialVelocity`` (w.r.t. q̇, tool frame
    origin, world) with its [ω; v] rows swapped.
    """
    q = as_batch(q, arm.n)
    revolute = arm.revolute[:, None, None]
    J = np.empty((6, arm.n, int(np.prod(q.shape[:-1]))))  # stored batch-last
    for block, z, p, p_tool in _chain(arm, q):
        J_v, J_w = _columns(revolute, z, p, p_tool)
        J[:3, :, block] = J_v.transpose(1, 0, 2)
        J[3:, :, block] = J_w.transpose(1, 0, 2)
    return np.moveaxis(J, -1, 0).reshape(q.shape[:-1] + (6, arm.n))


def tool_motion(
    arm: Arm, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The tool's twist [v; ω] and classical acceleration [a; ω̇] in the world frame, each ``(6,)`` or ``(..., 6)``.

    ``q, qd, qdd``: joint positions (rad or m), rates and accelerations, ``(n,)`` or ``(..., n)``
    (broadcast together). v, a are the tool point's velocity (m/s) and acceleration (m/s²); ω, ω̇ the
    tool's angular velocity (rad/s) and acceleration (rad/s²). a = J q̈ + J̇ q̇ (module docstring).
    """
    n = arm.n
    q, qd, qdd = np.broadcast_arrays(as_batch(q, n, "q"), as_batch(qd, n, "qd"), as_batch(qdd, n, "qdd"))
    shape = q.shape[:-1]
    rates, accelerations = (np.ascontiguousarray(a.reshape(-1, n).T)[:, None, :] for a in (qd, qdd))  # (n, 1, N)
    revolute = arm.revolute[:, None, None]
    twist, accel = np.empty((6, rates.shape[-1])), np.empty((6, rates.shape[-1]))  # stored batch-last
    every = bool(revolute.all())
    for block, z, p, p_tool in _chain(arm, np.ascontiguousarray(q), MOTION_BLOCK):
        lever = p_tool - p  # p_t − p_i
        J_v, J_w = _columns(revolute, z, p, p_tool)
        rate, acc = rates[..., block], accelerations[..., block]
        w = np.cumsum(rate * J_w, axis=0)  # ω_i
        v_joints = np.cumsum(rate * J_v, axis=0)  # Σ_{j ≤ i} q̇_j J_v,j; the last is the tool's v
        v_tool = v_joints[-1]
        relative = cross(w, lever)  # v_t − v_i = ω_i × (p_t − p_i) + v_t − Σ_{j ≤ i} q̇_j J_v,j
        relative += v_tool
        relative -= v_joints
        z_dot = cross(w, z)  # ż_i = ω_i × z_i
        J_v_dot = cross(z_dot, lever)
        J_v_dot += cross(z, relative)
        if not every:
            J_v_dot = np.where(revolute, J_v_dot, z_dot)
            z_dot = np.where(revolute, z_dot, 0.0)
        twist[:3, block] = v_tool
        twist[3:, block] = w[-1]
        accel[:3, block] = (acc * J_v + rate * J_v_dot).sum(axis=0)
        accel[3:, block] = (acc * J_w + rate * z_dot).sum(axis=0)
    return twist.T.reshape(shape + (6,)), accel.T.reshape(shape + (6,))


def _singular_values(J: ArrayLike, axes: Literal["all", "trans", "rot"] | None) -> NDArray[np.float64]:
    """Singular values ``(..., min(rows, n))`` of the rows of ``J`` that ``axes`` selects (descending)."""
    J = np.asarray(J, dtype=float)
    if J.ndim < 2 or J.shape[-2] != 6 or J.shape[-1] < 1:
        raise ValueError(f"J has shape {J.shape}; expected a Jacobian of shape (6, n) or (..., 6, n)")
    if not np.isfinite(J).all():
        raise ValueError("J has NaN or infinite entries")
    if axes is None:
        axes = default_axes(J.shape[-1])
    if axes not in AXES:
        raise ValueError(f"axes = {axes!r} is not allowed; allowed: {', '.join(AXES)} or None")
    return np.linalg.svd(J[..., AXES[axes], :], compute_uv=False)


def manipulability(J: ArrayLike, axes: Literal["all", "trans", "rot"] | None = None) -> NDArray[np.float64]:
    """Yoshikawa's manipulability of a Jacobian ``(6, n)`` or ``(..., 6, n)``: a number or an array ``(...)``.

    The product of the singular values of the selected rows J_s (``axes``: ``"all"`` the 6 rows,
    ``"trans"`` rows v, ``"rot"`` rows ω; default ``"all"`` when n ≥ 6, else ``"trans"``), which is
    √det(J_s J_sᵀ) when J_s has no more rows than columns and √det(J_sᵀ J_s) otherwise; zero at a
    singular configuration. Units: the product of the singular values' (m/rad or 1 for the rows v,
    rad/rad or rad/m for ω; ``"all"`` mixes them, so compare its values only for one arm).
    """
    return np.prod(_singular_values(J, axes), axis=-1)


def sigma_min(J: ArrayLike, axes: Literal["all", "trans", "rot"] | None = None) -> NDArray[np.float64]:
    """The smallest singular value of the selected rows J_s of ``J`` (``axes`` as for :func:`manipulability`).

    J_s (r rows, n columns) has min(r, n) singular values; this is the smallest of them: σ_r when r ≤ n
    (zero when the tool loses a direction of motion), σ_n when r > n (zero when some joint motion does
    not move the tool). A number, or an array ``(...)`` for a batch of Jacobians.
    """
    return _singular_values(J, axes)[..., -1]
