"""Each joint's drive as current and voltage: the current loop (a PI at its own rate, the back-EMF fed forward,
the voltage saturated at the bus), the motor's winding, and an energy meter, all from Drake's blocks.

The torque command τ* (joint side) becomes the current command i* = τ*/(G k_t); the PI (:func:`~armlab.controllers.
servo.add_pi`, anti-windup by back-calculation with T_t = T_i = L/R) puts out V* = K_p (i* − i) + z + k_e ω_m, Drake's
``Saturation`` clamps it at ± V_bus, and the winding (:mod:`armlab.drives.motor`)

    L di/dt = V − R i − k_e G q̇,      τ = G k_t i

is one continuous Drake ``LinearSystem`` for all joints, whose torque drives the plant. Sampled at a rate, the
current loop holds its inputs (i*, i, q̇) with Drake's ``ZeroOrderHold`` and integrates z in discrete time.

``energy_meter`` (a Drake ``SymbolicVectorSystem``) integrates, per joint, the electrical energy ∫V·i dt, the
mechanical ∫τ·q̇ dt (from the plant's actuation and rates: the torque the plant gets) and the copper losses
∫R i² dt, so that a run's energy balance ∫V i = ∫τ q̇ + ∫R i² + Δ(½ L i²) is checked from the simulation
itself (:func:`energy_balance`), not from samples.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armlab.controllers.servo import add_pi, add_saturation, block_diagonal
from armlab.drives.motor import MotorElectrics, current_gains

if TYPE_CHECKING:
    from pydrake.systems.framework import DiagramBuilder, OutputPort

__all__ = ["CurrentLoopDesign", "DriveElectrics", "add_drive_electrics", "energy_balance"]


@dataclass(frozen=True)
class CurrentLoopDesign:
    """The current loops as built: the motors' ``electrics``, the ``gear_ratio`` G ``(n,)``, the loop's
    ``bandwidth`` (Hz, :func:`~armlab.drives.motor.current_gains`) and ``period`` (s; ``None``: continuous)."""

    electrics: MotorElectrics
    gear_ratio: NDArray[np.float64]
    bandwidth: float
    period: float | None

    @property
    def torque_per_amp(self) -> NDArray[np.float64]:
        """G k_t (N·m/A, joint side) per joint."""
        return self.gear_ratio * self.electrics.torque_constant

    @property
    def torque_limit(self) -> NDArray[np.float64]:
        """|G| k_t I_peak (N·m), the joint torque at the drive's peak current (inf: no current limit)."""
        return np.abs(self.torque_per_amp) * self.electrics.peak_current

    def initial_state(self, tau0: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(i₀ A, z₀ V) for a start at the torque ``tau0`` ``(n,)``: the current of that torque, the integral holding
        the winding's R i₀ (so that V₀ = R i₀ + k_e ω_m₀ and nothing jumps at t = 0)."""
        i0 = tau0 / self.torque_per_amp
        return i0, self.electrics.resistance * i0


@dataclass(frozen=True)
class DriveElectrics:
    """The ports of :func:`add_drive_electrics`: the ``torque`` the motors apply to the plant, the ``current`` i (A),
    the ``voltage`` V (V) and the ``energy`` [∫V i, ∫τ q̇, ∫R i²] (J, ``(3n,)``)."""

    torque: OutputPort
    current: OutputPort
    voltage: OutputPort
    energy: OutputPort | None


def add_drive_electrics(builder: DiagramBuilder, state: OutputPort, torque_command: OutputPort,
                        design: CurrentLoopDesign, meter: bool = True) -> DriveElectrics:
    """The current loops, motors and (``meter``) energy meter of ``design`` (module docstring), commanded by
    ``torque_command`` τ* (N·m or N, ``(n,)``) and fed back the plant's ``state`` [q, q̇]; its ports (``energy``
    ``None`` without the meter). The caller connects :attr:`DriveElectrics.torque` to the plant's actuation input."""
    from pydrake.symbolic import MakeVectorVariable
    from pydrake.systems.primitives import (
        Demultiplexer,
        LinearSystem,
        MatrixGain,
        Multiplexer,
        SymbolicVectorSystem,
        ZeroOrderHold,
    )

    e, g = design.electrics, design.gear_ratio
    n = e.n
    kp, ki = current_gains(e, design.bandwidth)
    command = builder.AddNamedSystem("current_command", MatrixGain(np.diag(1.0 / design.torque_per_amp)))
    builder.Connect(torque_command, command.get_input_port())
    signal = builder.AddNamedSystem("current_signal", Multiplexer([n, n, 2 * n]))
    builder.Connect(command.get_output_port(), signal.get_input_port(0))
    builder.Connect(state, signal.get_input_port(2))
    measured = signal.get_output_port()
    if design.period is not None:
        hold = builder.AddNamedSystem("current_sampling", ZeroOrderHold(design.period, 4 * n))
        builder.Connect(measured, hold.get_input_port())
        measured = hold.get_output_port()
    proportional = block_diagonal(kp, -kp, 0.0, e.back_emf * g)
    integral = block_diagonal(ki, -ki, 0.0, 0.0)
    demand, windup = add_pi(builder, "current_pi", measured, proportional, integral, ki / kp, design.period)
    voltage = add_saturation(builder, "voltage_saturation", demand, e.bus_voltage, windup)

    inputs = builder.AddNamedSystem("motor_inputs", Multiplexer([n, 2 * n]))
    builder.Connect(voltage, inputs.get_input_port(0))
    builder.Connect(state, inputs.get_input_port(1))
    a_mat = -np.diag(e.resistance / e.inductance)
    b_mat = block_diagonal(1.0 / e.inductance, 0.0, -e.back_emf * g / e.inductance)
    c_mat = np.vstack([np.eye(n), np.diag(design.torque_per_amp)])
    motors = builder.AddNamedSystem("motors", LinearSystem(a_mat, b_mat, c_mat, np.zeros((2 * n, 3 * n))))
    builder.Connect(inputs.get_output_port(), motors.get_input_port())
    outputs = builder.AddNamedSystem("motor_outputs", Demultiplexer([n, n]))
    builder.Connect(motors.get_output_port(), outputs.get_input_port())
    current, torque = outputs.get_output_port(0), outputs.get_output_port(1)
    builder.Connect(current, signal.get_input_port(1))
    if not meter:
        return DriveElectrics(torque, current, voltage, None)

    x, u = MakeVectorVariable(3 * n, "E"), MakeVectorVariable(5 * n, "u")  # u = [V, i, τ, q, q̇]
    v_, i_, t_, w_ = u[:n], u[n:2 * n], u[2 * n:3 * n], u[4 * n:]
    rates = [v_[k] * i_[k] for k in range(n)] + [t_[k] * w_[k] for k in range(n)] + [
        float(e.resistance[k]) * i_[k] * i_[k] for k in range(n)]
    energy = SymbolicVectorSystem(state=x, input=u, dynamics=np.array(rates), output=x)
    builder.AddNamedSystem("energy_meter", energy)
    meter_inputs = builder.AddNamedSystem("energy_inputs", Multiplexer([n, n, n, 2 * n]))
    for k, port in enumerate((voltage, current, torque, state)):
        builder.Connect(port, meter_inputs.get_input_port(k))
    builder.Connect(meter_inputs.get_output_port(), energy.get_input_port())
    return DriveElectrics(torque, current, voltage, energy.get_output_port())


def energy_balance(energy: NDArray[np.float64], current: NDArray[np.float64], inductance: NDArray[np.float64],
                   run: NDArray[np.intp] | None = None) -> dict[str, NDArray[np.float64]]:
    """A run's energy balance per joint from the logged ``energy`` ``(m, 3n)`` ([∫V i, ∫τ q̇, ∫R i²] from each run's
    start) and ``current`` ``(m, n)``, the runs told apart by ``run`` ``(m,)`` (``None``: one run): the electrical,
    mechanical, copper and magnetic (Δ ½ L i²) energies (J), summed over the runs, and the residual electrical −
    (mechanical + copper + magnetic) relative to the sum of their magnitudes, each ``(n,)``."""
    n = current.shape[1]
    run = np.zeros(current.shape[0], dtype=np.intp) if run is None else np.asarray(run)
    first = np.r_[True, run[1:] != run[:-1]]  # each run's first and last sample
    last = np.r_[run[1:] != run[:-1], True]

    def change(values: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.sum(values[last], axis=0) - np.sum(values[first], axis=0)

    electrical, mechanical, copper = (change(energy[:, k * n:(k + 1) * n]) for k in range(3))
    magnetic = 0.5 * inductance * change(current**2)
    scale = np.abs(electrical) + np.abs(mechanical) + np.abs(copper) + np.abs(magnetic)
    residual = electrical - mechanical - copper - magnetic
    relative = np.abs(residual) / np.where(scale > 0, scale, 1.0)
    return {"electrical": electrical, "mechanical": mechanical, "copper": copper, "magnetic": magnetic,
            "relative_residual": relative}
