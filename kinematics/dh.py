"""Denavit–Hartenberg chains: standard (paper 000, eq. 9) and modified (paper 001, Craig).

Standard DH (000, eq. 9; the transform of frame i in frame i−1):

    T_{i−1,i} = T_Z3(d_i) · T_Z6(θ_i) · T_Z1(a_i) · T_Z4(α_i)

Modified DH (001, eq. 1; Craig's convention, parameters of row i are a_{i−1}, α_{i−1}, d_i, θ_i):

    T_{i−1,i} = T_Z4(α_{i−1}) · T_Z1(a_{i−1}) · T_Z6(θ_i) · T_Z3(d_i)

For a revolute joint θ_i = q_i + offset_i; for a prismatic joint d_i = q_i + offset_i.
:meth:`DHTable.locating_table` turns a table into paper 003's matrix of nominal geometry,
from which armlab writes the URDF of a user's DH arm.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.basic_movements import T_Z1, T_Z3, T_Z4, T_Z6
from armlab.kinematics.batch import ZStep, as_batch, chain_frames
from armlab.kinematics.locating import JointRow, LocatingTable

__all__ = ["DHRow", "DHTable"]


@dataclass(frozen=True)
class DHRow:
    """One DH row. For ``convention="modified"`` ``a`` and ``alpha`` are a_{i−1}, α_{i−1}."""

    a: float
    alpha: float
    d: float
    theta: float
    kind: Literal["R", "T"] = "R"

    def __post_init__(self) -> None:
        if self.kind not in ("R", "T"):
            raise ValueError(f"DH joint type {self.kind!r} is not allowed (R or T)")
        for key in ("a", "alpha", "d", "theta"):
            value = getattr(self, key)
            if not isinstance(value, (int, float)) or not np.isfinite(value):
                raise ValueError(f"DH parameter {key} = {value!r} is not a finite number")


@dataclass(frozen=True)
class DHTable:
    """A DH table; ``theta`` (revolute) or ``d`` (prismatic) is the joint's offset."""

    rows: tuple[DHRow, ...]
    convention: Literal["standard", "modified"] = "standard"

    def __post_init__(self) -> None:
        if self.convention not in ("standard", "modified"):
            raise ValueError(f"DH convention {self.convention!r} is not allowed (standard or modified)")
        if not self.rows:
            raise ValueError("a DH table needs at least one row")

    @property
    def n(self) -> int:
        """Number of joints."""
        return len(self.rows)

    def _constant(self, row: DHRow) -> NDArray[np.float64]:
        """The part of a row that does not move: the row's transform at q_i = 0."""
        if self.convention == "standard":
            return T_Z3(row.d) @ T_Z6(row.theta) @ T_Z1(row.a) @ T_Z4(row.alpha)  # 000 eq. (9)
        return T_Z4(row.alpha) @ T_Z1(row.a) @ T_Z6(row.theta) @ T_Z3(row.d)  # 001 eq. (1)

    @cached_property
    def steps(self) -> tuple[ZStep, ...]:
        """Each row as (constant) · J_z(q_i) · (constant).

        The joint's motion R_z(q_i) (revolute) or T_z(q_i) (prismatic) commutes with T_Z3(d_i) and
        T_Z6(θ_i), so it moves to the front of a standard row, T_{i−1,i} = J_z(q_i)·T_{i−1,i}(0), and to
        the back of a modified row, T_{i−1,i} = T_{i−1,i}(0)·J_z(q_i).
        """
        if self.convention == "standard":
            return tuple(ZStep(None, row.kind == "R", self._constant(row)) for row in self.rows)
        return tuple(ZStep(self._constant(row), row.kind == "R") for row in self.rows)

    def frames(self, q: ArrayLike) -> NDArray[np.float64]:
        """T_{0,i} for i = 0 … n (base first), shape ``(..., n+1, 4, 4)``."""
        return chain_frames(as_batch(q, self.n), self.steps)

    def end_pose(self, q: ArrayLike) -> NDArray[np.float64]:
        """T_{0,n}, shape ``(..., 4, 4)``."""
        return self.frames(q)[..., -1, :, :]

    def locating_table(self) -> LocatingTable:
        """The same chain as paper 003's matrix of nominal geometry (joint axes along z).

        Each joint's motion is moved to the front of its row (Rz(q) and Tz(q) commute with
        Tz(d) and Rz(θ) respectively), so the constant remainder becomes the next row's
        T_{i,i−1}; the tool row is the last remainder, making the tool frame DH frame n.
        """
        z = (0.0, 0.0, 1.0)
        rows = []
        carried = np.eye(4)  # the remainder of the previous row, applied after its joint moved
        for i, (row, step) in enumerate(zip(self.rows, self.steps, strict=True)):
            T = carried if step.pre is None else carried @ step.pre
            rows.append(JointRow(f"joint{i + 1}", row.kind, tuple(T[:3, 3]), z, tuple(map(tuple, T[:3, :3]))))
            carried = np.eye(4) if step.post is None else step.post
        return LocatingTable(tuple(rows), tool=carried)
