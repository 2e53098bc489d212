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

where the angular velocity ω_i of link i and the velocity v_i of the origin of frame {i} follow from a
forward recursion over the joints (prefix sums, vectorised over joints and samples):

    ω_i = Σ_{j ≤ i, revolute} q̇_j z_j,
    v_i = ω_i × p_i − Σ_{j ≤ i, revolute} q̇_j z_j × p_j + Σ_{j ≤ i, prismatic} q̇_j z_j.

Every function takes one configuration ``(n,)`` or a batch ``(..., n)``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import as_batch

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["AXES", "jacobian", "manipulability", "sigma_min", "tool_motion"]

#: Rows of the Jacobian each ``axes`` choice selects: all six, the translational [v] or the rotational [ω].
AXES = {"all": slice(0, 6), "trans": slice(0, 3), "rot": slice(3, 6)}


def _axes_and_origins(arm: Arm, q: NDArray[np.float64]) -> tuple[NDArray, NDArray, NDArray]:
    """World joint axes z_i ``(..., n, 3)``, frame origins p_i ``(..., n, 3)`` and the tool point ``(..., 3)``."""
    frames = arm.table.frames(q)
    n = arm.n
    k = np.array([row.k for row in arm.table.rows])  # k_i in frame {i}
    z = np.einsum("...ijk,ik->...ij", frames[..., 1:n + 1, :3, :3], k)  # z_i = R_{0,i} k_i
    return z, frames[..., 1:n + 1, :3, 3], frames[..., n + 1, :3, 3]


def _columns(arm: Arm, z: NDArray, p: NDArray, p_tool: NDArray) -> tuple[NDArray, NDArray]:
    """The Jacobian's columns as rows: J_v ``(..., n, 3)`` and J_ω ``(..., n, 3)``."""
    revolute = arm.revolute[:, None]
    J_w = np.where(revolute, z, 0.0)
    J_v = np.where(revolute, np.cross(z, p_tool[..., None, :] - p), z)
    return J_v, J_w


def jacobian(arm: Arm, q: ArrayLike) -> NDArray[np.float64]:
    """Geometric Jacobian of the tool point in the world frame, rows [v; ω]: ``(6, n)`` or ``(..., 6, n)``.

    ``q`` (rad or m) has shape ``(n,)`` or ``(..., n)``; [v; ω] = J q̇ is the tool point's velocity (m/s)
    and the tool's angular velocity (rad/s) — Drake's ``CalcJacobianSpatialVelocity`` (w.r.t. q̇, tool frame
    origin, world) with its [ω; v] rows swapped.
    """
    q = as_batch(q, arm.n)
    J_v, J_w = _columns(arm, *_axes_and_origins(arm, q))
    return np.concatenate([np.swapaxes(J_v, -1, -2), np.swapaxes(J_w, -1, -2)], axis=-2)


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
    z, p, p_tool = _axes_and_origins(arm, q)
    J_v, J_w = _columns(arm, z, p, p_tool)
    rate = qd[..., None]  # q̇_i per column
    w = np.cumsum(rate * J_w, axis=-2)  # ω_i
    prismatic = np.where(arm.revolute[:, None], 0.0, z)
    v = np.cross(w, p) - np.cumsum(rate * np.cross(J_w, p), axis=-2) + np.cumsum(rate * prismatic, axis=-2)
    v_tool = np.einsum("...ij,...i->...j", J_v, qd)
    w_tool = w[..., -1, :]
    z_dot = np.cross(w, z)  # ż_i = ω_i × z_i
    J_v_dot = np.where(arm.revolute[:, None],
                       np.cross(z_dot, p_tool[..., None, :] - p) + np.cross(z, v_tool[..., None, :] - v), z_dot)
    J_w_dot = np.where(arm.revolute[:, None], z_dot, 0.0)
    a = np.einsum("...ij,...i->...j", J_v, qdd) + np.einsum("...ij,...i->...j", J_v_dot, qd)
    w_dot = np.einsum("...ij,...i->...j", J_w, qdd) + np.einsum("...ij,...i->...j", J_w_dot, qd)
    return np.concatenate([v_tool, w_tool], axis=-1), np.concatenate([a, w_dot], axis=-1)


def _singular_values(J: ArrayLike, axes: Literal["all", "trans", "rot"] | None) -> NDArray[np.float64]:
    """Singular values ``(..., min(rows, n))`` of the rows of ``J`` that ``axes`` selects (descending)."""
    J = np.asarray(J, dtype=float)
    if J.ndim < 2 or J.shape[-2] != 6 or J.shape[-1] < 1:
        raise ValueError(f"J has shape {J.shape}; expected a Jacobian of shape (6, n) or (..., 6, n)")
    if not np.isfinite(J).all():
        raise ValueError("J has NaN or infinite entries")
    if axes is None:
        axes = "all" if J.shape[-1] >= 6 else "trans"
    if axes not in AXES:
        raise ValueError(f"axes = {axes!r} is not allowed; allowed: {', '.join(AXES)} or None")
    return np.linalg.svd(J[..., AXES[axes], :], compute_uv=False)


def manipulability(J: ArrayLike, axes: Literal["all", "trans", "rot"] | None = None) -> NDArray[np.float64]:
    """Yoshikawa's manipulability of a Jacobian ``(6, n)`` or ``(..., 6, n)``: a number or an array ``(...)``.

    The product of the singular values of the selected rows J_s (``axes``: ``"all"`` the 6 rows,
    ``"trans"`` rows v, ``"rot"`` rows ω; default ``"all"`` when n ≥ 6, else ``"trans"``), which is
    √det(J_s J_sᵀ) when J_s has no more rows than columns and √det(J_sᵀ J_s) otherwise. Zero exactly
    at a singular configuration (for ``"trans"``: m²·… units of m per rad, mixed for ``"all"``).
    """
    return np.prod(_singular_values(J, axes), axis=-1)


def sigma_min(J: ArrayLike, axes: Literal["all", "trans", "rot"] | None = None) -> NDArray[np.float64]:
    """The smallest singular value of the selected rows J_s of ``J`` (``axes`` as for :func:`manipulability`).

    J_s (r rows, n columns) has min(r, n) singular values; this is the smallest of them: σ_r when r ≤ n
    (zero when the tool loses a direction of motion), σ_n when r > n (zero when some joint motion does
    not move the tool). A number, or an array ``(...)`` for a batch of Jacobians.
    """
    return _singular_values(J, axes)[..., -1]
