"""The drive train's Coulomb friction as a Drake system: ``sign``·T_c±·tanh(v/v_s) of a state's rates (T_c+ for
v ≥ 0, T_c− below: :meth:`armlab.drives.train.DriveTrain.coulomb_friction`).

Drake's ``MultibodyPlant`` has no joint Coulomb friction (it ignores a URDF's ``<dynamics friction>``), so the
diagram applies it as a generalized force: :class:`CoulombFriction` with ``sign`` = −1 on the plant's state
feeds the plant's ``applied_generalized_force`` input (the friction the joints feel), and with ``sign`` = +1 on
the controller's state adds the same term to the controller's torque (its model's friction, compensated). The
smooth model and v_s are :meth:`armlab.drives.train.DriveTrain.friction`'s. This module imports Drake: import it
only where a diagram is built.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

import numpy as np
from numpy.typing import NDArray
from pydrake.systems.framework import BasicVector, Context, LeafSystem

from armlab.drives.train import DriveTrain

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.systems.framework import DiagramBuilder

__all__ = ["CoulombFriction", "add_coulomb_friction"]


class CoulombFriction(LeafSystem):
    """Input ``state`` ([q, v], 2n); output ``friction`` = ``sign``·T_c±·tanh(v/v_s) (N·m or N, n)."""

    # No state: a C++ function under the name spares pydrake's per-evaluation lookup of a Python override
    # (see armlab.diagrams.tool_point.ToolPointKinematics); it is never called.
    DoCalcTimeDerivatives = LeafSystem.DoGetGraphvizFragment

    def __init__(self, drives: DriveTrain, sign: float, name: str) -> None:
        super().__init__()
        self._n, self._drives, self._sign = drives.n, drives, sign
        self.DeclareVectorInputPort("state", 2 * self._n)
        self.DeclareVectorOutputPort("friction", self._n, self._calc)
        self.set_name(name)

    def _calc(self, context: Context, output: BasicVector) -> None:
        x = cast(NDArray[np.float64], self.get_input_port(0).Eval(context))  # a vector port's value: (2n,)
        output.SetFromVector(self._sign * self._drives.coulomb_friction(x[self._n:]))


def add_coulomb_friction(builder: DiagramBuilder, plant: MultibodyPlant, drives: DriveTrain | None) -> None:
    """Apply ``drives``' Coulomb friction −T_c·tanh(v/v_s) at ``plant``'s rates to its ``applied_generalized_force``
    input (a ``joint_friction`` :class:`CoulombFriction`); nothing when the drive train has none (or is ``None``)."""
    if drives is None or not drives.has_coulomb:
        return
    friction = builder.AddSystem(CoulombFriction(drives, -1.0, "joint_friction"))
    builder.Connect(plant.get_state_output_port(), friction.get_input_port())
    builder.Connect(friction.get_output_port(), plant.get_applied_generalized_force_input_port())
