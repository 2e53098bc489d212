"""Elastic joints in the diagram: each rotor a mass of its own, coupled to its link through the gearbox's spring.

The two-mass model of :mod:`armlab.drives.elastic` from Drake's blocks: the rotors are one continuous
``LinearSystem`` (state [φ, φ̇], input [τ, q, q̇]; J_r φ̈ = τ − K (φ − q) − D (φ̇ − q̇)) whose output is its state only,
and the spring's torque τ_s = K (φ − q) + D (φ̇ − q̇) a ``MatrixGain`` on [φ, φ̇, q, q̇] that drives the plant (two
systems, so that the controller that reads the rotors and drives them closes no algebraic loop). The plant then has
no rotor inertia on its mass matrix (:func:`link_side`): the rotors carry it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.controllers.servo import block_diagonal
from armlab.drives.elastic import Elasticity

if TYPE_CHECKING:
    from pydrake.systems.framework import DiagramBuilder, OutputPort

    from armlab.models.arm import Arm

__all__ = ["ElasticDesign", "add_elastic_rotors", "link_side"]


@dataclass(frozen=True)
class ElasticDesign:
    """The elastic joints as built: the gearboxes' ``elasticity`` and the rotors' ``inertia`` J_r = G² J_m
    (kg·m² or kg, joint side, ``(n,)``, each > 0)."""

    elasticity: Elasticity
    inertia: NDArray[np.float64]

    def initial_state(self, q0: ArrayLike, v0: ArrayLike, torque: ArrayLike) -> NDArray[np.float64]:
        """[φ₀, φ̇₀] of rotors whose springs carry ``torque`` τ_s (N·m, ``(n,)``) with the links at ``q0`` moving at
        ``v0``: φ₀ = q0 + τ_s/K, φ̇₀ = v0."""
        phi = np.asarray(q0, dtype=float) + np.asarray(torque, dtype=float) / self.elasticity.stiffness
        return np.concatenate([phi, np.asarray(v0, dtype=float)])


def link_side(arm: Arm) -> Arm:
    """``arm`` with its drive train's rotor inertia taken off the links (the elastic joints' rotors carry it)."""
    assert arm.drives is not None
    return arm.with_drives(replace(arm.drives, rotor_inertia=np.zeros(arm.n)))


def add_elastic_rotors(builder: DiagramBuilder, state: OutputPort, torque: OutputPort,
                       design: ElasticDesign) -> tuple[OutputPort, OutputPort]:
    """The rotors (``elastic_rotors``) driven by ``torque`` τ (joint side, ``(n,)``) and coupled to the links of the
    plant's ``state`` [q, q̇]; (the rotors' state [φ, φ̇] port, the spring torque τ_s port for the plant)."""
    from pydrake.systems.primitives import LinearSystem, MatrixGain, Multiplexer

    k, d, j = design.elasticity.stiffness, design.elasticity.twist_damping, design.inertia
    n = k.size
    inputs = builder.AddNamedSystem("elastic_inputs", Multiplexer([n, 2 * n]))
    builder.Connect(torque, inputs.get_input_port(0))
    builder.Connect(state, inputs.get_input_port(1))
    a_mat = np.block([[np.zeros((n, n)), np.eye(n)], [-np.diag(k / j), -np.diag(d / j)]])
    b_mat = np.vstack([np.zeros((n, 3 * n)), block_diagonal(1.0 / j, k / j, d / j)])
    rotors = builder.AddNamedSystem("elastic_rotors", LinearSystem(a_mat, b_mat, np.eye(2 * n),
                                                                   np.zeros((2 * n, 3 * n))))
    builder.Connect(inputs.get_output_port(), rotors.get_input_port())
    both = builder.AddNamedSystem("elastic_twist", Multiplexer([2 * n, 2 * n]))
    builder.Connect(rotors.get_output_port(), both.get_input_port(0))
    builder.Connect(state, both.get_input_port(1))
    spring = builder.AddNamedSystem("elastic_spring", MatrixGain(block_diagonal(k, d, -k, -d)))
    builder.Connect(both.get_output_port(), spring.get_input_port())
    return rotors.get_output_port(), spring.get_output_port()
