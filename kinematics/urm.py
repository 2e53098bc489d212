"""Position vectors p1 … p7 of the 6-DOF URM-module arm, paper 004 (Ondočko et al.).

Segments r1 … r7 lie along their module's local z axis; the active joints φ1 … φ6
turn about the module's z axis, and the fixed bends θ2 … θ7 about its y axis.

Rotation-matrix form, eqs. (1)–(7):

    p1 = R_z1(φ1) r1                                                  (3)
    p_k = p_{k−1} + R_z1(φ1) Π_{j=2..k} [R_yj(θj) R_zj(φj)] r_k         (4)–(7)

(the seventh segment has a bend θ7 but no joint: φ7 = 0).

Homogeneous form, eqs. (8)–(22), with T_y(θ, t) of eq. (10) carrying segment r_{j−1}:

    p_{i+1} = T_z1(φ1) Π_{j=1..i} [T_y(j+1)(θ_{j+1}, r_j) T_z(j+1)(φ_{j+1})] r_{i+1}   (22)

Both take φ of shape ``(..., 6)`` and return the points as ``(..., 7, 3)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.basic_movements import T_Z5, T_Z6
from armlab.kinematics.batch import as_batch, blocks, cos_sin, times_constant, turn_z

__all__ = ["position_vectors", "position_vectors_homogeneous", "rotation_form"]


def _angles(phi: ArrayLike, theta: ArrayLike, r: ArrayLike) -> tuple[NDArray, NDArray, NDArray]:
    phi = as_batch(phi, 6, "phi")
    phi7 = np.concatenate([phi, np.zeros(phi.shape[:-1] + (1,))], axis=-1)  # no joint in module 7
    theta = as_batch(theta, 6, "theta")  # θ2 … θ7
    r = as_batch(r, 7, "r")  # |r1| … |r7|
    return phi7, theta, r


def rotation_form(phi: ArrayLike, theta: ArrayLike, r: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Eqs. (1)–(7): the points p1 … p7, shape ``(..., 7, 3)``, and module 7's rotation, ``(..., 3, 3)``.

    ``phi`` ``(..., 6)``; the structure ``theta`` (θ2 … θ7) and ``r`` (|r1| … |r7|) are constants, ``(6,)``
    and ``(7,)``. Each segment r_k lies along its module's z axis, so R·r_k is |r_k| times R's third
    column; the bend R_y(θ_k) is a product by a constant and the turn R_z(φ_k) mixes R's first two columns.
    """
    phi7, theta, r = _angles(phi, theta, r)
    if theta.ndim != 1 or r.ndim != 1:
        raise ValueError(f"theta and r have shapes {theta.shape}, {r.shape}: they are the arm's constants, (6,), (7,)")
    shape = phi7.shape[:-1]
    angles = np.ascontiguousarray(phi7[..., :6].reshape(-1, 6).T)  # (6, N): one joint's values contiguous
    points, R_out = np.empty((7, 3, angles.shape[1])), np.empty((3, 3, angles.shape[1]))  # stored batch-last
    bends = [T_Z5(angle)[:3, :3] for angle in theta]
    for block in blocks(angles.shape[1]):
        c, s = cos_sin(angles[:, block])
        R = np.zeros((3, 3, c.shape[1]))  # R_z1(φ1), eq. (1)
        R[0, 0] = R[1, 1] = c[0]
        R[1, 0] = s[0]
        R[0, 1] = -s[0]
        R[2, 2] = 1.0
        p = points[..., block]
        p[0] = r[0] * R[:, 2]  # eq. (3)
        for k in range(1, 7):  # eqs. (4)–(7): R ← R·R_yk(θk)·R_zk(φk), p_k = p_{k−1} + R·r_k
            R = times_constant(bends[k - 1], R)
            if k < 6:  # φ7 = 0: module 7 has no joint
                turn_z(R, c[k], s[k])
            p[k] = p[k - 1] + r[k] * R[:, 2]
        R_out[..., block] = R
    return np.moveaxis(points, -1, 0).reshape(shape + (7, 3)), np.moveaxis(R_out, -1, 0).reshape(shape + (3, 3))


def position_vectors(phi: ArrayLike, theta: ArrayLike, r: ArrayLike) -> NDArray[np.float64]:
    """p1 … p7 by the rotation matrices of eqs. (1)–(7), shape ``(..., 7, 3)``."""
    return rotation_form(phi, theta, r)[0]


def _T_y(theta: ArrayLike, t_z: float) -> NDArray[np.float64]:
    """T_y(θ, t) of eq. (10) for a segment t = (0, 0, t_z)."""
    T = T_Z5(theta)
    T[..., 2, 3] = t_z
    return T


def _module_frames(phi7: NDArray, theta: NDArray, r: NDArray) -> list[NDArray]:
    """T_z1(φ1) Π_{j=1..i} [T_y(j+1)(θ_{j+1}, r_j) T_z(j+1)(φ_{j+1})] for i = 0 … 6 (eq. 22)."""
    T = T_Z6(phi7[..., 0])  # T_z1(φ1), eq. (8)
    frames = [T]
    for i in range(1, 7):
        T = T @ _T_y(theta[..., i - 1], r[i - 1]) @ T_Z6(phi7[..., i])  # eq. (16)
        frames.append(T)
    return frames


def position_vectors_homogeneous(phi: ArrayLike, theta: ArrayLike, r: ArrayLike) -> NDArray[np.float64]:
    """p1 … p7 by the homogeneous transformations of eqs. (8)–(22), shape ``(..., 7, 3)``."""
    phi7, theta, r = _angles(phi, theta, r)
    frames = _module_frames(phi7, theta, r)
    return np.stack([(T @ np.array([0.0, 0.0, r[i], 1.0]))[..., :3] for i, T in enumerate(frames)], axis=-2)
