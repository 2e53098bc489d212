"""The tool point's position, velocity and acceleration in the world frame, as a Drake system.

Paper 000 plots the end point M (Figs. 3, 8, 18–19, 24–25, 28–29) and paper 001 the end point's
x, y, z (Fig. 7). :class:`ToolPointKinematics` computes them from the plant's state and its
generalized acceleration v̇:

    p = p_WT(q),   v = J(q) v,   a = J(q) v̇ + J̇(q, v) v,

with ``CalcPointsPositions``, ``CalcJacobianTranslationalVelocity`` and
``CalcBiasTranslationalAcceleration`` (the J̇ v term) on a plant context of its own.
This module imports Drake: import it only where a diagram is built.
"""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import NDArray
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import Frame, JacobianWrtVariable
from pydrake.systems.framework import BasicVector, Context, LeafSystem

__all__ = ["ToolPointKinematics"]


class ToolPointKinematics(LeafSystem):
    """Inputs ``state`` ([q, v]) and ``generalized_acceleration`` (v̇); output ``tool_pva``.

    ``tool_pva`` is the 9-vector [x y z vx vy vz ax ay az] of ``frame``'s origin in the world
    frame (m, m/s, m/s²).
    """

    # The system has no state, but a diagram asks each of its systems for time derivatives at every
    # derivative evaluation, and for a Python system pydrake first looks up a Python override of
    # DoCalcTimeDerivatives. A class without that attribute misses the lookup every time (a few µs:
    # 0.35–0.6× of integrating the bare plant, over a run); a C++ function under the name is taken as "not
    # overridden" once and for all (pybind11 caches that), so the C++ LeafSystem's own (empty) derivatives
    # run. Any pybind11 function serves; it is never called.
    DoCalcTimeDerivatives = LeafSystem.DoGetGraphvizFragment

    def __init__(self, plant: MultibodyPlant, frame: Frame, name: str = "ToolPoint") -> None:
        super().__init__()
        self._plant = plant
        self._frame = frame
        self._context = plant.CreateDefaultContext()
        self._nq = plant.num_positions()
        nv = plant.num_velocities()
        self.DeclareVectorInputPort("state", self._nq + nv)
        self.DeclareVectorInputPort("generalized_acceleration", nv)
        self.DeclareVectorOutputPort("tool_pva", 9, self._calc)
        self.set_name(name)

    def _calc(self, context: Context, output: BasicVector) -> None:
        x = cast(NDArray[np.float64], self.get_input_port(0).Eval(context))  # a vector port's value: (nq + nv,)
        vdot = cast(NDArray[np.float64], self.get_input_port(1).Eval(context))  # (nv,)
        plant, ctx, world, origin = self._plant, self._context, self._plant.world_frame(), np.zeros(3)
        plant.SetPositionsAndVelocities(ctx, x)
        p = plant.CalcPointsPositions(ctx, self._frame, origin, world)[:, 0]
        J = plant.CalcJacobianTranslationalVelocity(ctx, JacobianWrtVariable.kV, self._frame, origin, world, world)
        bias = plant.CalcBiasTranslationalAcceleration(
            ctx, JacobianWrtVariable.kV, self._frame, origin, world, world
        )[:, 0]
        output.SetFromVector(np.concatenate([p, J @ x[self._nq:], J @ vdot + bias]))
