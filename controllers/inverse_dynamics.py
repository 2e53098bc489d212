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
the simulated ``plant``'s actuation input.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.limits import check_range

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.systems.controllers import InverseDynamics, InverseDynamicsController
    from pydrake.systems.framework import DiagramBuilder


__all__ = [
    "DEFAULT_KD",
    "DEFAULT_KP",
    "add_inverse_dynamics",
    "add_inverse_dynamics_controller",
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
    kp: float | ArrayLike = DEFAULT_KP,
    kd: float | ArrayLike = DEFAULT_KD,
    ki: float | ArrayLike = 0.0,
    name: str = "InverseDynamicsController",
) -> InverseDynamicsController:
    """Add the computed-torque controller on ``model``, with ``plant``'s state fed back and its actuation driven.

    Its ``desired_state`` ([q_d, q̇_d]) and ``desired_acceleration`` (q̈_d) inputs are left for the
    caller to connect. Returns the controller.
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
    builder.Connect(controller.get_output_port_control(), plant.get_actuation_input_port())
    return controller


def add_inverse_dynamics(
    builder: DiagramBuilder, plant: MultibodyPlant, model: MultibodyPlant, name: str = "InverseDynamics"
) -> InverseDynamics:
    """Add open-loop inverse dynamics on ``model`` driving ``plant``'s actuation input (no feedback).

    Its ``estimated_state`` input takes the *reference* state [q_d, q̇_d] and ``desired_acceleration``
    q̈_d; the caller connects both. ``model``'s actuation matrix must be the identity (one actuator
    per joint, in joint order) so that generalized forces are actuator torques.
    """
    from pydrake.systems.controllers import InverseDynamics

    if not np.array_equal(model.MakeActuationMatrix(), np.eye(model.num_velocities())):
        raise ValueError("inverse dynamics needs one actuator per joint, in joint order")
    inverse_dynamics = InverseDynamics(model, InverseDynamics.InverseDynamicsMode.kInverseDynamics)
    inverse_dynamics.set_name(name)
    builder.AddSystem(inverse_dynamics)
    builder.Connect(inverse_dynamics.get_output_port_generalized_force(), plant.get_actuation_input_port())
    return inverse_dynamics
