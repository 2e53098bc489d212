"""The locating-matrix algorithm of paper 003 (Schonstein & Panc, 2017), eqs. (1)–(23).

A serial chain is described by its *matrix of nominal geometry* (paper 003, Table 1):
one row per joint ``i = 1 … n`` with

* the joint type, ``R`` (rotation, Δ_i = 1) or ``T`` (translation, Δ_i = 0),
* ``P_i`` — the origin of frame {i} in frame {i−1} when q = 0, ``ⁱ⁻¹p̄_{i,i−1}``,
* ``k_i`` — the unit joint axis in frame {i},
* ``R_i`` — the constant rotation ``R_{i,i−1}`` of frame {i} in {i−1} at q = 0
  (the identity for every R2T row; other arms need it),

plus the tool row ``T_{n+1,n}`` (eq. 2). Then, eqs. (3)–(4),

    T_{i−1,i}(q_i) = T_{i,i−1} · T_Δ(k_i; q_i),
    T_Δ(k; q) = [ R(k; q·Δ) | (1 − Δ)·q·k ],

and the locating matrices of every frame in the base, eqs. (8)–(9),

    T_{i,0} = Π_{j ≤ i} T_{j−1,j},   T_{n+1,0} = T_{n,0} · T_{n+1,n}.

This is also exactly the semantics of a URDF joint (``origin`` = T_{i,i−1}, ``axis`` = k_i),
which is why every arm's URDF is generated from its table.

The orientation angles of eq. (10)/(22) are α_x, β_y, γ_z with
``R_{n+1,0} = R_z(γ_z)·R_y(β_y)·R_x(α_x)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import ZStep, as_batch, chain_frames

__all__ = ["JointRow", "LocatingTable", "homogeneous", "orientation_angles", "rotation_about"]


def rotation_about(k: ArrayLike, angle: ArrayLike) -> NDArray[np.float64]:
    """R(k; θ): rotation by ``angle`` (shape ``S``) about the unit axis ``k``, shape ``S + (3, 3)``.

    Rodrigues' formula ``R = I + sin θ [k]× + (1 − cos θ) [k]×²``.
    """
    k = np.asarray(k, dtype=float)
    a = np.asarray(angle, dtype=float)[..., None, None]
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(a) * K + (1.0 - np.cos(a)) * (K @ K)


def homogeneous(R: ArrayLike, p: ArrayLike) -> NDArray[np.float64]:
    """The 4×4 matrix ``[R | p; 0 0 0 1]`` (eq. 1), broadcast over leading axes."""
    R = np.asarray(R, dtype=float)
    p = np.asarray(p, dtype=float)
    shape = np.broadcast_shapes(R.shape[:-2], p.shape[:-1])
    # stored in R's memory order (a batch stored last stays last)
    T = np.zeros_like(R, shape=shape + (4, 4)) if R.shape[:-2] == shape else np.zeros(shape + (4, 4))
    T[..., :3, :3] = R
    T[..., :3, 3] = p
    T[..., 3, 3] = 1.0
    return T


def orientation_angles(R: ArrayLike) -> NDArray[np.float64]:
    """(α_x, β_y, γ_z) of eqs. (10), (22) with ``R = R_z(γ) R_y(β) R_x(α)``, shape ``(..., 3)``.

    The angles are found with the two-argument arctangent (the paper's ``A tan 2``, eq. 22).
    At β_y = ±π/2 (gimbal lock) only α_x ∓ γ_z is defined; γ_z = 0 is returned there.
    """
    R = np.asarray(R, dtype=float)
    cos_beta = np.hypot(R[..., 0, 0], R[..., 1, 0])
    beta = np.arctan2(-R[..., 2, 0], cos_beta)
    locked = cos_beta < 1e-12
    alpha = np.where(locked, np.arctan2(-R[..., 1, 2], R[..., 1, 1]), np.arctan2(R[..., 2, 1], R[..., 2, 2]))
    gamma = np.where(locked, 0.0, np.arctan2(R[..., 1, 0], R[..., 0, 0]))
    return np.stack([alpha, beta, gamma], axis=-1)


@dataclass(frozen=True)
class JointRow:
    """One row of the matrix of nominal geometry (paper 003, Table 1)."""

    name: str
    kind: Literal["R", "T"]
    P: tuple[float, float, float]
    k: tuple[float, float, float]
    R: tuple[tuple[float, ...], ...] = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))

    def __post_init__(self) -> None:
        if self.kind not in ("R", "T"):
            raise ValueError(f"joint {self.name!r}: type {self.kind!r} is not allowed (R or T)")
        values = np.concatenate([np.ravel(self.P), np.ravel(self.k), np.ravel(self.R)])
        if values.size != 15 or not np.all(np.isfinite(values)):
            raise ValueError(f"joint {self.name!r}: P, k must be 3 finite numbers and R a 3×3 matrix")
        norm = np.linalg.norm(self.k)
        if abs(norm - 1.0) > 1e-9:
            raise ValueError(f"joint {self.name!r}: axis k = {self.k} is not a unit vector")
        R = np.asarray(self.R)
        if np.abs(R.T @ R - np.eye(3)).max() > 1e-9 or np.linalg.det(R) < 0:
            raise ValueError(f"joint {self.name!r}: R is not a rotation matrix")

    @property
    def delta(self) -> float:
        """Δ_i: 1 for a rotation, 0 for a translation (eq. 3)."""
        return 1.0 if self.kind == "R" else 0.0

    @property
    def T_fixed(self) -> NDArray[np.float64]:
        """T_{i,i−1} of eq. (1): the constant part of the joint's locating matrix."""
        return homogeneous(np.asarray(self.R, dtype=float), np.asarray(self.P, dtype=float))


@dataclass(frozen=True)
class LocatingTable:
    """A serial chain as paper 003's matrix of nominal geometry plus the tool row T_{n+1,n}."""

    rows: tuple[JointRow, ...]
    tool: NDArray[np.float64] = field(default_factory=lambda: np.eye(4))

    @property
    def n(self) -> int:
        """Number of joints."""
        return len(self.rows)

    @cached_property
    def steps(self) -> tuple[ZStep, ...]:
        """Each row as ``T_{i,i−1} · T_Δ(k_i; q_i) = (T_{i,i−1}·A_i) · J_z(q_i) · A_iᵀ`` (eqs. 3–4).

        ``A_i`` is a constant rotation taking z onto k_i (the identity when k_i = z), so the joint's
        motion T_Δ(k_i; q_i) = A_i·J_z(q_i)·A_iᵀ is a turn about (Δ_i = 1) or a slide along (Δ_i = 0) z.
        """
        z = np.array([0.0, 0.0, 1.0])
        steps = []
        for row in self.rows:
            k = np.asarray(row.k, dtype=float)
            if np.array_equal(k, z):
                A = None
            else:  # the rotation about z × k by the angle between z and k (about x for k = −z)
                axis = np.cross(z, k)
                norm = np.linalg.norm(axis)
                A = homogeneous(rotation_about(axis / norm if norm > 0 else (1.0, 0.0, 0.0),
                                               np.arctan2(norm, k[2])), np.zeros(3))
            pre = row.T_fixed if A is None else row.T_fixed @ A
            steps.append(ZStep(pre, row.kind == "R", None if A is None else A.T.copy()))
        return tuple(steps)

    def frames(self, q: ArrayLike) -> NDArray[np.float64]:
        """T_{i,0} for i = 0 … n+1 (eqs. 8–9): base, every link, tool; shape ``(..., n+2, 4, 4)``."""
        return chain_frames(as_batch(q, self.n), self.steps, self.tool)
