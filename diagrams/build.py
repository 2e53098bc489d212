"""Paper 000's Fig. 6 as a Drake Systems diagram, for any arm.

Fig. 6 is a SimMechanics scheme: joint trajectories → inverse dynamics → the arm → scopes of the
joint torques. Here, with Drake's own systems, named so that the graphviz picture reads the same::

    TrajectorySource (q_d, q̇_d, q̈_d) → reference_split ─┬→ InverseDynamicsController → MultibodyPlant
                                                         │          ↑ state feedback ─────────┘
    loggers: log_reference, log_state, log_torque, log_tool (ToolPoint: p, v, a of the tool point)

The plant carries the arm's drive train (rotor inertia, gear ratio, joint damping: :mod:`armlab.models.plant`),
and so does the controller's model, the plant itself. An arm whose drive train has Coulomb friction gets two
more systems: ``joint_friction`` (−T_c·tanh(v/v_s) of the plant's rates into its applied generalized force)
and ``friction_compensation`` + ``drive_torque`` (the same term added to the controller's torque; what
``log_torque`` records is that sum, the torque the drives apply).

How the loggers sample (``sampling``, one of :data:`SAMPLINGS`):

* ``"dense"`` (the default): the loggers publish when the diagram is forced to (once, at the end of the
  run), so nothing stops the integrator between its own error-controlled steps; the samples every
  ``log_period`` are made after the run from the integrator's dense output by
  :func:`armlab.diagrams.simulate.run_simulator`, which checks them against the loggers' end sample.
* ``"periodic"``: the loggers publish every ``log_period``, so the integrator stops at every sample
  (the straightforward diagram, 10–30× slower; the reference the tests compare ``"dense"`` with).

``mode="controller"`` is the closed loop (computed torque with reference acceleration, PD gains
kp, kd, optional ki); ``mode="inverse_dynamics"`` is SimMechanics' inverse-dynamics mode: the
torques computed from the reference alone (no feedback) and applied to the plant open-loop.

A servo run (:attr:`~armlab.diagrams.simulate.SimulationOptions.servo`: another controller, a rate, saturation,
sensors, electrics) has :func:`armlab.diagrams.servo.add_servo`'s loop in place of the controller, and more loggers:
``log_command`` (the torque command τ* before the saturation), ``log_measured`` (a sampled controller's measured
state) and, with electrics, ``log_current``, ``log_voltage``
and ``log_energy``; its loggers sample periodically.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armlab.controllers.inverse_dynamics import (
    add_inverse_dynamics,
    add_inverse_dynamics_controller,
    gain_vector,
)
from armlab.diagrams.servo import add_plants, add_servo, servo_design
from armlab.kinematics.quintic import DEFAULT_LOG_PERIOD, Motion, to_trajectory

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.systems.framework import Diagram

    from armlab.diagrams.servo import ServoLoop
    from armlab.diagrams.simulate import SimulationOptions
    from armlab.models.arm import Arm

__all__ = ["DEFAULT_LOG_PERIOD", "MODES", "SAMPLINGS", "RunDiagram", "build_diagram", "check_log_period"]

#: Diagram modes: closed-loop computed torque, or open-loop inverse dynamics (SimMechanics' mode).
MODES = ("controller", "inverse_dynamics")
#: How the loggers sample: from the integrator's dense output after the run, or at periodic publish events.
SAMPLINGS = ("dense", "periodic")


def check_log_period(period: float, duration: float | None = None) -> float:
    """The log period as a float; ``ValueError`` unless positive, finite and (if given) ≤ ``duration``."""
    value = float(period)
    if not np.isfinite(value) or value <= 0:
        raise ValueError(f"log period = {period} s is not allowed: give a positive finite number of seconds")
    if duration is not None and value > duration:
        raise ValueError(f"log period = {period} s is longer than the motion ({duration:g} s)")
    return value


@dataclass
class RunDiagram:
    """A built diagram and handles to its parts (the loggers by role: reference, state, torque, tool).

    ``gains`` are the controller's (kp, kd, ki) per joint (used in ``"controller"`` mode); ``arm`` the arm
    the plant is built from.
    """

    diagram: Diagram
    plant: MultibodyPlant
    model: MultibodyPlant  # the controller's model of the arm: the plant itself (the exact model)
    loggers: dict[str, Any]
    motion: Motion
    gravity: NDArray[np.float64]
    payload: float
    mode: str
    log_period: float
    sampling: str
    gains: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]
    arm: Arm
    servo: ServoLoop | None = None  # a servo run's designs (None: the ideal loop)


def build_diagram(arm: Arm, motion: Motion, options: SimulationOptions | None = None, *,
                  limits_checked: bool = False) -> RunDiagram:
    """Build Fig. 6 for ``arm`` following ``motion`` (one continuous run, see :meth:`Motion.runs`).

    ``options`` (default :class:`~armlab.diagrams.simulate.SimulationOptions`'): the plant's (gravity,
    payload), ``mode`` (one of :data:`MODES`), the gains, ``log_period`` (s, the period of every logger's
    samples; at most the motion's duration), ``sampling`` (one of :data:`SAMPLINGS`, see the module docstring) and
    the servo loop's (the module docstring; its gains' inertia at the run's start pose). The motion is checked
    against the arm's joint limits (:meth:`Motion.check_limits`) unless ``limits_checked`` says the caller
    has checked it (:func:`~armlab.diagrams.simulate.simulate`, which checks the whole motion once).
    """
    from pydrake.systems.framework import DiagramBuilder, TriggerType
    from pydrake.systems.primitives import Demultiplexer, LogVectorOutput, TrajectorySource

    # lazy: cycle, armlab.diagrams.simulate imports this module (build_diagram, DEFAULT_LOG_PERIOD …)
    from armlab.diagrams.simulate import SimulationOptions
    from armlab.diagrams.tool_point import ToolPointKinematics
    from armlab.drives.friction import add_coulomb_friction

    options = SimulationOptions() if options is None else options
    if len(motion.runs()) != 1:
        raise ValueError("build_diagram takes one continuous run; split the motion with Motion.runs()")
    if not limits_checked:
        motion.check_limits(arm)
    log_period = check_log_period(options.log_period, motion.duration)
    mode, sampling = options.mode, options.sampling
    assert sampling is not None  # resolved by SimulationOptions
    n = arm.n

    builder = DiagramBuilder()
    plant, model = add_plants(builder, arm, options)  # the plant, and the controller's model: the plant itself

    source = builder.AddNamedSystem(
        "TrajectorySource", TrajectorySource(to_trajectory(motion), output_derivative_order=2)
    )
    gains = (gain_vector(options.kp, n, "kp"), gain_vector(options.kd, n, "kd"), gain_vector(options.ki, n, "ki"))
    add_coulomb_friction(builder, plant, arm.drives)
    servo, ports, name = None, {}, mode
    if options.servo:
        servo = servo_design(arm, model, options, motion.segments[0].q_start)
        wired = add_servo(builder, plant, model, servo, source.get_output_port(), arm.drives)
        torque_port, ports = wired.torque, {"command": wired.command}
        if wired.measured is not None:
            ports["measured"] = wired.measured
        if wired.rotors is not None:
            ports["rotor"] = wired.rotors
        if wired.electrics is not None and wired.electrics.energy is not None:
            ports.update(current=wired.electrics.current, voltage=wired.electrics.voltage,
                         energy=wired.electrics.energy)
        name = options.controller + ("" if options.rate is None else f" at {options.rate:g} Hz")
    else:
        split = builder.AddNamedSystem("reference_split", Demultiplexer([2 * n, n]))
        builder.Connect(source.get_output_port(), split.get_input_port())
        if mode == "controller":
            _, torque_port = add_inverse_dynamics_controller(builder, plant, model, split.get_output_port(0),
                                                             split.get_output_port(1), *gains, drives=arm.drives)
        else:
            _, torque_port = add_inverse_dynamics(builder, plant, model, split.get_output_port(0),
                                                  split.get_output_port(1), drives=arm.drives)

    tool = builder.AddSystem(ToolPointKinematics(plant, plant.GetFrameByName(arm.tool_name)))
    builder.Connect(plant.get_state_output_port(), tool.get_input_port(0))
    builder.Connect(plant.get_generalized_acceleration_output_port(), tool.get_input_port(1))

    loggers = {}
    for role, port in (("reference", source.get_output_port()), ("state", plant.get_state_output_port()),
                       ("torque", torque_port), ("tool", tool.get_output_port()), *ports.items()):
        if sampling == "periodic":
            logger = LogVectorOutput(port, builder, log_period)
        else:
            logger = LogVectorOutput(port, builder, {TriggerType.kForced})
        logger.set_name(f"log_{role}")
        loggers[role] = logger
    diagram = builder.Build()
    diagram.set_name(f"{arm.name} Fig. 6 ({name})")
    return RunDiagram(diagram, plant, model, loggers, motion, options.plant.gravity_of(arm), options.plant.payload,
                      mode, log_period, sampling, gains, arm, servo)
