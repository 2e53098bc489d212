"""Elastic joints: the gearbox's torsional stiffness and damping between the motor's rotor and the link.

The two-mass model of a joint (Spong 1987, "Modeling and control of elastic joint robots"), joint side::

    J_r φ̈ = τ − K (φ − q) − D (φ̇ − q̇),     the link gets τ_s = K (φ − q) + D (φ̇ − q̇)

with φ = θ_m / G the rotor's angle seen at the joint, J_r = G² J_m the reflected rotor inertia (then no longer on the
link's mass matrix), τ the drive's torque and q the link's angle. The drive file's columns (:mod:`armlab.drives.read`):
``stiffness`` K (N·m/rad, joint side: the gearbox's torsional stiffness, e.g. a strain-wave gear's K₃ from its
datasheet) and optionally ``twist_damping`` D (N·m·s/rad, joint side, default 0). The stiffness is linear: a strain-wave
gear's piecewise stiffness (K₁, K₂, K₃ over its torque ranges) is not modelled.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from armlab.drives.train import joint_vector

__all__ = ["ELASTIC_COLUMNS", "Elasticity"]

#: The elasticity columns of a drive file: the stiffness, and optionally its damping.
ELASTIC_COLUMNS = ("stiffness", "twist_damping")


@dataclass(frozen=True)
class Elasticity:
    """Per joint ``(n,)``: the torsional ``stiffness`` K (N·m/rad, > 0) and ``twist_damping`` D (N·m·s/rad, ≥ 0;
    ``None``: 0) between rotor and link, joint side (the drive file's columns of the same names)."""

    stiffness: NDArray[np.float64]
    twist_damping: NDArray[np.float64] = None  # type: ignore[assignment]  # None: 0 (an array once made)

    def __post_init__(self) -> None:
        k = joint_vector(self.stiffness, "joint stiffness", None, "N·m/rad", "a positive finite number",
                         lambda a: ~np.isfinite(a) | (a <= 0))
        d = np.zeros(k.size) if self.twist_damping is None else self.twist_damping
        d = joint_vector(d, "joint twist_damping", k.size, "N·m·s/rad", "a finite number ≥ 0",
                         lambda a: ~np.isfinite(a) | (a < 0))
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "twist_damping", d)

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.stiffness.size)
