"""Paper 000's Fig. 6 controllers: computed torque with feedback, and pure inverse dynamics.

* :func:`add_inverse_dynamics_controller` — Drake's ``InverseDynamicsController``: the computed
  torque law τ = M(q)(q̈_d + kp (q_d − q) + kd (q̇_d − q̇) + ki ∫(q_d − q)) + C(q, q̇) q̇ − τ_g(q)
  with the reference acceleration q̈_d, on the plant's state feedback.
* :func:`add_inverse_dynamics` — what SimMechanics' inverse-dynamics mode of Fig. 6 does: the
  torques from the reference alone, τ = M(q_d) q̈_d + C(q_d, q̇_d) q̇_d − τ_g(q_d), no feedback
  (Drake's ``InverseDynamics`` in ``kInverseDynamics`` mode fed the reference state).

The same τ along a sampled trajectory without a diagram (e.g. to size the drives for a path given point
by point) is ``arm.inverse_dynamics(q, qd, qdd)``: the batch recursive Newton–Euler of
:func:`armlab.kinematics.rnea.inverse_dynamics`.

The controllers use ``model`` as their model of the arm (Fig. 6's exact model: the simulated ``plant``
itself, evaluated on a context of the controller's own, or any finalized plant of the same arm) and drive
the simulated ``plant``'s actuation input. The model has the arm's drive train as its plant does (reflected
inertia and joint damping: Drake's inverse dynamics includes both); the Coulomb friction, which the diagram
applies to the plant outside it (:func:`armlab.drives.friction.add_coulomb_friction`), is added to the
controller's torque by the same system of the state the torque is computed at (:func:`drive_actuation`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.limits import check_range

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.systems.controllers import InverseDynamics, InverseDynamicsController
    from pydrake.systems.framework import DiagramBuilder, OutputPort

    from armlab.drives.train import DriveTrain


__all__ = [
    "DEFAULT_KD",
    "DEFAULT_KP",
    "add_inverse_dynamics",
    "add_inverse_dynamics_controller",
    "drive_actuation",
    "friction_compensated",
    "gain_vector",
]

#: Default position gain (1/s²): natural frequency 10 rad/s of the error dynamics ë + kd ė + kp e = 0.
DEFAULT_KP = 100.0
#: Default velocity gain (1/s): critically damped with DEFAULT_KP (kd = 2√kp).
DEFAULT_KD = 20.0


def gain_vector(gain: float | ArrayLike, n: int, name: str) -> NDArray[np.float64]:
    """A gain as one value per joint (a scalar is used for every joint), each within its range.

    ``name`` is ``"kp"``, ``"kd"`` or ``"ki"`` (or the option ``"--kp"`` …): the ranges are
    :data:`armlab.limits.LIMITS`' (``ValueError`` naming the value and the range).
    """
    g = np.asarray(gain, dtype=float)
    if g.ndim == 0:
        g = np.full(n, float(g))
    if g.shape != (n,):
        raise ValueError(f"{name} has {g.size} values; give one value or {n} (one per joint)")
    return check_range(g, name)


def add_inverse_dynamics_controller(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    model: MultibodyPlant,
    desired_state: OutputPort,
    desired_acceleration: OutputPort,
    kp: float | ArrayLike = DEFAULT_KP,
    kd: float | ArrayLike = DEFAULT_KD,
    ki: float | ArrayLike = 0.0,
    drives: DriveTrain | None = None,
    name: str = "InverseDynamicsController",
) -> tuple[InverseDynamicsController, OutputPort]:
    """Add the computed-torque controller on ``model``, with ``plant``'s state fed back and its actuation driven.

    ``desired_state`` ([q_d, q̇_d]) and ``desired_acceleration`` (q̈_d) are the ports of the reference;
    ``drives``: the arm's drive train, whose Coulomb friction at the plant's rates the torque includes
    (:func:`drive_actuation`). Returns the controller and the port of the torque driving the plant.
    """
    from pydrake.systems.controllers import InverseDynamicsController

    n = model.num_positions()
    controller = InverseDynamicsController(
        model, gain_vector(kp, n, "kp"), gain_vector(ki, n, "ki"), gain_vector(kd, n, "kd"),
        has_reference_acceleration=True,
    )
    controller.set_name(name)
    builder.AddSystem(controller)
    builder.Connect(plant.get_state_output_port(), controller.get_input_port_estimated_state())
    builder.Connect(desired_state, controller.get_input_port_desired_state())
    builder.Connect(desired_acceleration, controller.get_input_port_desired_acceleration())
    torque = drive_actuation(builder, plant, controller.get_output_port_control(), plant.get_state_output_port(),
                             drives)
    return controller, torque


def add_inverse_dynamics(
    builder: DiagramBuilder, plant: MultibodyPlant, model: MultibodyPlant, state: OutputPort,
    acceleration: OutputPort, drives: DriveTrain | None = None, name: str = "InverseDynamics",
) -> tuple[InverseDynamics, OutputPort]:
    """Add open-loop inverse dynamics on ``model`` driving ``plant``'s actuation input (no feedback).

    ``state`` is the port of the *reference* state [q_d, q̇_d] and ``acceleration`` of q̈_d; ``drives``: the arm's
    drive train, whose Coulomb friction at the reference rates the torque includes (:func:`drive_actuation`).
    ``model``'s actuation matrix must be the identity (one actuator per joint, in joint order) so that
    generalized forces are actuator torques. Returns the system and the port of the torque driving the plant.
    """
    from pydrake.systems.controllers import InverseDynamics

    if not np.array_equal(model.MakeActuationMatrix(), np.eye(model.num_velocities())):
        raise ValueError("inverse dynamics needs one actuator per joint, in joint order")
    inverse_dynamics = InverseDynamics(model, InverseDynamics.InverseDynamicsMode.kInverseDynamics)
    inverse_dynamics.set_name(name)
    builder.AddSystem(inverse_dynamics)
    builder.Connect(state, inverse_dynamics.get_input_port_estimated_state())
    builder.Connect(acceleration, inverse_dynamics.get_input_port_desired_acceleration())
    torque = drive_actuation(builder, plant, inverse_dynamics.get_output_port_generalized_force(), state, drives)
    return inverse_dynamics, torque


def drive_actuation(builder: DiagramBuilder, plant: MultibodyPlant, torque: OutputPort, state: OutputPort,
                    drives: DriveTrain | None) -> OutputPort:
    """Connect the model's torque ``torque`` (N·m or N, n) to ``plant``'s actuation input, with the Coulomb friction
    of the rates of ``state`` added (:func:`friction_compensated`); the port of the torque applied."""
    applied = friction_compensated(builder, torque, state, drives)
    builder.Connect(applied, plant.get_actuation_input_port())
    return applied


def friction_compensated(builder: DiagramBuilder, torque: OutputPort, state: OutputPort, drives: DriveTrain | None,
                         ) -> OutputPort:
    """``torque`` (N·m or N, n) with the Coulomb friction T_c·tanh(v/v_s) of the rates of ``state`` ([q, v]) added
    when ``drives`` has any (a ``friction_compensation`` :class:`~armlab.drives.friction.CoulombFriction` and a
    ``drive_torque`` ``Adder``); ``torque`` itself otherwise."""
    if drives is None or not drives.has_coulomb:
        return torque
    from pydrake.systems.primitives import Adder

    # lazy: armlab.drives.friction imports Drake
    from armlab.drives.friction import CoulombFriction

    compensation = builder.AddSystem(CoulombFriction(drives, 1.0, "friction_compensation"))
    builder.Connect(state, compensation.get_input_port())
    adder = builder.AddNamedSystem("drive_torque", Adder(2, drives.n))
    builder.Connect(torque, adder.get_input_port(0))
    builder.Connect(compensation.get_output_port(), adder.get_input_port(1))
    return adder.get_output_port()
