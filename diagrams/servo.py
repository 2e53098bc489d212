"""The servo loop in Fig. 6's diagram: the controller, sensors and drive electrics a run's options ask for, wired
between the trajectory source and the plant, started consistently, and linearised about a pose.

A run is a **servo run** (:attr:`~armlab.diagrams.simulate.SimulationOptions.servo`) when its options ask for more
than paper 000's ideal loop (continuous computed torque on the exact state): another controller, a sample rate, a
torque saturation, sensors or the motors' electrics. Then :func:`add_servo` builds, from Drake's blocks::

    TrajectorySource ─ [reference_sampling: ZeroOrderHold] ─┐
    plant state ─ [sensors: encoders, noise, sensor_sampling] ─┴→ servo_pid → law → [torque_saturation]
          → [current loops → motors] → MultibodyPlant

(:mod:`armlab.controllers.servo`, :mod:`armlab.controllers.sensors`, :mod:`armlab.controllers.electrics`), and
:meth:`ServoLoop.initialize` gives every held value and register the value it would have had with the arm at its
start state since ever: the loggers' first sample is then the diagram's real output at t = 0.

:func:`linearize_loop` builds the continuous closed loop of the same design about a pose at rest (Drake's
``Linearize``) and :func:`frequency_response` evaluates its q/q_d per joint: the Bode plot, and the loop's
bandwidth to compare with the tuning rule's (:func:`armlab.controllers.servo.loop_bandwidth`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.controllers.elastic import ElasticDesign, add_elastic_rotors, link_side
from armlab.controllers.electrics import CurrentLoopDesign, DriveElectrics, add_drive_electrics
from armlab.controllers.sensors import SensorDesign, add_sensors, encoder_scale
from armlab.controllers.servo import ServoDesign, add_position_controller, joint_inertia, loop_bandwidth
from armlab.models.plant import add_arm_plant, make_plant

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.systems.framework import Context, Diagram, DiagramBuilder, OutputPort
    from pydrake.systems.primitives import LinearSystem

    from armlab.diagrams.simulate import SimulationOptions
    from armlab.models.arm import Arm

__all__ = ["LoopResponse", "ServoLoop", "add_plants", "add_servo", "frequency_response", "linearize_loop",
           "servo_design"]


@dataclass(frozen=True)
class ServoLoop:
    """A servo run's designs (position controller, sensors, current loops, elastic joints: ``None`` where not used),
    its seed and whether its sensors read the motors (``motor_side``: the elastic rotors' angles, not the links')."""

    controller: ServoDesign
    sensors: SensorDesign | None
    current: CurrentLoopDesign | None
    seed: int
    elastic: ElasticDesign | None = None
    motor_side: bool = True

    def describe(self) -> dict[str, Any]:
        """The design as ``summary.json`` has it (SI; gains per joint)."""
        c = self.controller
        out: dict[str, Any] = {
            "controller": c.controller,
            "rate_hz": None if c.period is None else 1.0 / c.period,
            "gains": {"kp": c.kp.tolist(), "kd": c.kd.tolist(), "ki": c.ki.tolist(),
                      **{k: v.tolist() for k, v in c.si_gains().items()},
                      "units": {"kp": "1/s²", "kd": "1/s", "ki": "1/s³", "Kp": "N·m/rad", "Kd": "N·m·s/rad",
                                "Ki": "N·m/(rad·s)"}},
            "joint_inertia": c.inertia.tolist(),
            "design_bandwidth_hz": loop_bandwidth(c.kp, c.kd, c.ki).tolist() if np.all(c.kp > 0) else None,
            "torque_limit": None if c.torque_limit is None else [
                None if not np.isfinite(v) else float(v) for v in c.torque_limit],
            "anti_windup": c.anti_windup,
        }
        s = self.sensors
        out["sensors"] = None if s is None else {
            "encoder_counts": s.counts, "resolution": None if s.resolution is None else s.resolution.tolist(),
            "velocity": s.velocity, "velocity_cutoff_hz": s.cutoff, "noise": s.noise, "seed": self.seed,
            "delay_samples": s.delay}
        e = self.current
        out["current_loop"] = None if e is None else {
            "rate_hz": None if e.period is None else 1.0 / e.period, "bandwidth_hz": e.bandwidth,
            "resistance": e.electrics.resistance.tolist(), "inductance": e.electrics.inductance.tolist(),
            "torque_constant": e.electrics.torque_constant.tolist(), "back_emf": e.electrics.back_emf.tolist(),
            "bus_voltage": e.electrics.bus_voltage.tolist(),
            "peak_current": [None if not np.isfinite(v) else float(v) for v in e.electrics.peak_current]}
        k = self.elastic
        out["elastic_joints"] = None if k is None else {
            "stiffness": k.elasticity.stiffness.tolist(), "twist_damping": k.elasticity.twist_damping.tolist(),
            "rotor_inertia_joint_side": k.inertia.tolist(), "measured": "motor" if self.motor_side else "joint"}
        return out

    def prepare(self, diagram: Diagram, context: Context) -> None:
        """Seed the noise (before the plant's state is set: Drake's ``SetRandomContext`` sets every state)."""
        if self.sensors is not None and self.sensors.noise > 0:
            from pydrake.common import RandomGenerator

            diagram.SetRandomContext(context, RandomGenerator(self.seed))

    def initialize(self, diagram: Diagram, context: Context, q0: ArrayLike, v0: ArrayLike) -> None:
        """Every held value and register as if the arm had been at ``q0`` moving at ``v0`` since ever (the module
        docstring), in the order the signals flow: the elastic rotors twisted by the torque holding the links
        against gravity, the reference, the sensors, then the motors' current of the torque the controller commands
        at t = 0 and the current loop's integral and hold."""
        def sub(name: str) -> tuple[Any, Context]:
            system = diagram.GetSubsystemByName(name)
            return system, system.GetMyMutableContextFromRoot(context)

        measured = np.asarray(q0, dtype=float)
        if self.elastic is not None:
            plant, ctx = sub("MultibodyPlant")
            rotors = self.elastic.initial_state(q0, v0, -plant.CalcGravityGeneralizedForces(ctx))
            _, ctx = sub("elastic_rotors")
            ctx.SetContinuousState(rotors)
            if self.motor_side:
                measured = rotors[:self.elastic.inertia.size]
        if self.controller.period is not None:
            hold, ctx = sub("reference_sampling")
            hold.SetVectorState(ctx, hold.get_input_port().Eval(ctx))
        if self.sensors is not None:
            _, ctx = sub("sensor_sampling")
            ctx.SetDiscreteState(self.sensors.initial_state(measured, v0))
        if self.current is not None:
            command, ctx = sub("current_command")
            i0, z0 = self.current.initial_state(command.get_input_port().Eval(ctx))
            _, ctx = sub("motors")
            ctx.SetContinuousState(i0)
            if diagram.HasSubsystemNamed("current_pi_integral"):
                _, ctx = sub("current_pi_integral")
                (ctx.SetContinuousState if self.current.period is None else ctx.SetDiscreteState)(z0)
            if self.current.period is not None:
                hold, ctx = sub("current_sampling")
                hold.SetVectorState(ctx, hold.get_input_port().Eval(ctx))


def add_plants(builder: DiagramBuilder, arm: Arm, options: SimulationOptions) -> tuple[MultibodyPlant, MultibodyPlant]:
    """The simulated plant of ``arm`` (``MultibodyPlant`` in ``builder``) and the controllers' model of it: the plant
    itself, or with elastic joints the links alone (their rotors are the elastic joints' own) and a rigid model of
    the whole arm beside it (:func:`armlab.models.plant.make_plant`, the rotor inertia on its mass matrix).
    ``ValueError`` for elastic joints without a drive train with stiffness and rotor inertia."""
    if options.elastic:
        drives = arm.drives
        if drives is None or drives.elasticity is None or not np.all(drives.rotor_inertia > 0):
            raise ValueError(f"{arm.name}: elastic joints need a drive train with a stiffness column and a rotor "
                             "inertia above 0 for every joint: give a drive file with them (--drives FILE)")
        plant, _ = add_arm_plant(builder, link_side(arm), options.plant)
        model = make_plant(arm, options.plant)
    else:
        plant, _ = add_arm_plant(builder, arm, options.plant)
        model = plant  # the exact model: the controller evaluates the plant itself, on a context of its own
    plant.set_name("MultibodyPlant")
    return plant, model


def servo_design(arm: Arm, model: MultibodyPlant, options: SimulationOptions, q0: ArrayLike) -> ServoLoop:
    """The designs ``options`` ask for, for ``arm`` whose controllers' ``model`` (:func:`add_plants`) gives the gains'
    inertia at ``q0``.

    ``ValueError`` for electrics without a drive train that has them.
    """
    n = arm.n
    period = None if options.rate is None else 1.0 / options.rate
    drives = arm.drives
    current = None
    if options.electrics:
        if drives is None or drives.electrics is None:
            raise ValueError(f"{arm.name}: electrics need the motors' resistance, inductance, torque_constant and "
                             "bus_voltage: give a drive file with those columns (--drives FILE)")
        current = CurrentLoopDesign(drives.electrics, drives.gear_ratio, options.current_bandwidth,
                                    None if options.current_rate is None else 1.0 / options.current_rate)
    limit = np.full(n, np.inf)
    if options.saturate:
        limit = np.minimum(limit, [np.inf if lim.effort is None else lim.effort for lim in arm.limits])
    if current is not None:
        limit = np.minimum(limit, current.torque_limit)
    gear = np.ones(n) if drives is None else drives.gear_ratio
    sensors = None
    if period is not None:
        sensors = SensorDesign(period, options.encoder, encoder_scale(options.encoder_side, gear, arm.revolute),
                               options.velocity, options.velocity_cutoff, options.noise, options.delay)
    kp, kd, ki = (np.broadcast_to(np.asarray(g, dtype=float), (n,)).copy() for g in (options.kp, options.kd,
                                                                                    options.ki))
    controller = ServoDesign(options.controller, period, kp, kd, ki, joint_inertia(model, q0),
                             None if not np.any(np.isfinite(limit)) else limit, options.anti_windup)
    elastic = None
    if options.elastic and drives is not None and drives.elasticity is not None:  # add_plants checked them
        elastic = ElasticDesign(drives.elasticity, drives.reflected_inertia)
    return ServoLoop(controller, sensors, current, options.seed, elastic, options.encoder_side == "motor")


@dataclass(frozen=True)
class ServoPorts:
    """What :func:`add_servo` leaves for the loggers: the torque ``command`` τ*, the ``torque`` applied to the plant,
    the ``measured`` state [q_m, q̇_m] of a sampled controller's sensors, the drive electrics' ports and the elastic
    rotors' state [φ, φ̇] (``None`` without them)."""

    command: OutputPort
    torque: OutputPort
    measured: OutputPort | None
    electrics: DriveElectrics | None
    rotors: OutputPort | None = None


def add_servo(builder: DiagramBuilder, plant: MultibodyPlant, model: MultibodyPlant, loop: ServoLoop,
              reference: OutputPort, drives: Any, meter: bool = True) -> ServoPorts:
    """Wire ``loop`` between the ``reference`` [q_d, q̇_d, q̈_d] and ``plant``'s actuation (module docstring);
    ``model``: the controller's model of the arm; ``drives``: the arm's drive train (friction compensation);
    ``meter``: the electrics' energy meter too."""
    from pydrake.systems.primitives import PassThrough, ZeroOrderHold

    n = plant.num_positions()
    state = plant.get_state_output_port()
    design = loop.controller
    if design.period is not None:
        hold = builder.AddNamedSystem("reference_sampling", ZeroOrderHold(design.period, 3 * n))
        builder.Connect(reference, hold.get_input_port())
        reference = hold.get_output_port()
    motor = state  # what the motors turn at: the links, or the elastic joints' rotors
    drive = None
    if loop.elastic is not None:  # the rotors' torque is the drives', fed through once the drives are built
        drive = builder.AddNamedSystem("drive_output", PassThrough(n))
        motor, spring = add_elastic_rotors(builder, state, drive.get_output_port(), loop.elastic)
    read = motor if loop.motor_side else state
    sensed = None if loop.sensors is None else add_sensors(builder, read, loop.sensors).get_output_port()
    measured = read if sensed is None else sensed
    command, torque = add_position_controller(builder, model, design, reference, measured, drives)
    electrics = None
    if loop.current is not None:
        electrics = add_drive_electrics(builder, motor, torque, loop.current, meter)
        torque = electrics.torque
    if drive is not None:
        builder.Connect(torque, drive.get_input_port())
        builder.Connect(spring, plant.get_actuation_input_port())
        return ServoPorts(command, spring, sensed, electrics, motor)
    builder.Connect(torque, plant.get_actuation_input_port())
    return ServoPorts(command, torque, sensed, electrics)


# ------------------------------------------------------------------------------------------- linearised
def linearize_loop(arm: Arm, options: SimulationOptions, q0: ArrayLike) -> tuple[LinearSystem, ServoLoop]:
    """The continuous closed loop of ``options``' controller (and current loops) about ``arm`` at rest at ``q0``,
    linearised by Drake's ``Linearize`` from the reference [q_d, q̇_d, q̈_d] ``(3n,)`` to the plant's state
    [q, q̇] ``(2n,)``; with the design it linearised.

    Sampling and sensors are left out (Drake linearises a continuous or a discrete system, not both: the loop of the
    design); the integrals hold the static torque (a PID's integral holds gravity at rest), the motors its current.
    The drive train's smooth Coulomb friction T_c·tanh(v/v_s) is, at rest, the viscous friction of its slope T_c/v_s
    (exactly, to first order), and is linearised as that: Drake's ``Linearize`` differentiates with automatic
    differentiation, which the Python friction system does not support.
    """
    from pydrake.systems.framework import DiagramBuilder
    from pydrake.systems.primitives import Linearize, PassThrough

    q0 = np.asarray(q0, dtype=float)
    drives = arm.drives
    if drives is not None and drives.has_coulomb:
        # the slope at rest, the mean of both directions' (T_c+ + T_c−)/(2 v_s) where they differ
        slope = (drives.coulomb + drives.negative) / (2 * drives.coulomb_speed)
        arm = arm.with_drives(replace(drives, viscous=drives.viscous + slope, coulomb=np.zeros(arm.n),
                                      coulomb_negative=None))
    continuous = replace(options, rate=None, encoder=None, noise=0.0, delay=0, velocity="state", velocity_cutoff=None,
                         current_rate=None)
    n = arm.n
    builder = DiagramBuilder()
    plant, model = add_plants(builder, arm, continuous)
    loop = servo_design(arm, model, continuous, q0)
    reference = builder.AddNamedSystem("reference", PassThrough(3 * n))
    builder.ExportInput(reference.get_input_port(), "reference")
    wired = add_servo(builder, plant, model, loop, reference.get_output_port(), arm.drives, meter=False)
    builder.ExportOutput(plant.get_state_output_port(), "state")
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    plant_context = plant.GetMyMutableContextFromRoot(context)
    plant.SetPositions(plant_context, q0)
    hold = -plant.CalcGravityGeneralizedForces(plant_context)  # the torque holding the links at q0: −τ_g(q0)
    design = loop.controller
    measured = q0 if loop.elastic is None or not loop.motor_side else q0 + hold / loop.elastic.elasticity.stiffness
    reference_port = diagram.get_input_port(0)
    q_d = measured.copy()
    if diagram.HasSubsystemNamed("servo_pid_integral") and design.controller == "pid":
        integral = diagram.GetSubsystemByName("servo_pid_integral")  # the integral holds the links, q_d = q_m
        integral.GetMyMutableContextFromRoot(context).SetContinuousState(hold / design.inertia)
    else:  # the q_d whose torque holds the links (q0 itself when the controller measures the links)
        for _ in range(50):
            reference_port.FixValue(context, np.concatenate([q_d, np.zeros(2 * n)]))
            loop.initialize(diagram, context, q0, np.zeros(n))
            source: Any = wired.command.get_system()
            miss = np.asarray(wired.command.Eval(source.GetMyContextFromRoot(context))) - hold
            if np.all(np.abs(miss) <= 1e-13 * np.maximum(1.0, np.abs(hold))):  # not a bound: a fixed point reached
                break
            q_d = q_d - miss / (design.inertia * design.kp)
    reference_port.FixValue(context, np.concatenate([q_d, np.zeros(2 * n)]))
    loop.initialize(diagram, context, q0, np.zeros(n))
    return Linearize(diagram, context), loop


@dataclass(frozen=True)
class LoopResponse:
    """The linearised loop's q_i/q_d,i per joint: ``frequency`` (Hz, ``(k,)``), ``response`` (complex, ``(k, n)``),
    the −3 dB ``bandwidth`` (Hz, ``(n,)``) and the tuning rule's ``design`` bandwidth (Hz, ``(n,)``)."""

    frequency: NDArray[np.float64]
    response: NDArray[np.complex128]
    bandwidth: NDArray[np.float64]
    design: NDArray[np.float64]


def _transfer(system: LinearSystem, f: NDArray[np.float64], n: int) -> NDArray[np.complex128]:
    """Diagonal q_i/q_d,i of ``system`` at frequencies ``f`` (Hz): C (jω − A)⁻¹ B + D, ``(k, n)``."""
    a, b, c, d = system.A(), system.B()[:, :n], system.C()[:n], system.D()[:n, :n]
    eye = np.eye(a.shape[0])
    out = np.empty((f.size, n), dtype=complex)
    for k, w in enumerate(2 * np.pi * f):
        out[k] = np.diag(c @ np.linalg.solve(1j * w * eye - a, b) + d)
    return out


def frequency_response(arm: Arm, options: SimulationOptions, q0: ArrayLike,
                       frequency: ArrayLike | None = None) -> LoopResponse:
    """The Bode data of :func:`linearize_loop` per joint at ``frequency`` (Hz; default 0.01 Hz … 1 kHz, 400 points):
    q_i/q_d,i with q̇_d = q̈_d = 0 (the position loop's feedback), its −3 dB bandwidth found by bisection on
    |T(j2πf)| = 1/√2 to 1e-12 relative, and the tuning rule's bandwidth for the same gains."""
    system, loop = linearize_loop(arm, options, q0)
    n = arm.n
    f = np.logspace(-2, 3, 400) if frequency is None else np.asarray(frequency, dtype=float)
    response = _transfer(system, f, n)
    bandwidth = np.full(n, np.nan)
    for i in range(n):
        gain = np.abs(response[:, i])
        below = np.nonzero(gain < 1 / np.sqrt(2))[0]
        if below.size == 0 or below[0] == 0:
            continue
        lo, hi = f[below[0] - 1], f[below[0]]
        while hi - lo > 1e-12 * hi:  # not a bound: bisection
            mid = 0.5 * (lo + hi)
            if abs(_transfer(system, np.array([mid]), n)[0, i]) < 1 / np.sqrt(2):
                hi = mid
            else:
                lo = mid
        bandwidth[i] = 0.5 * (lo + hi)
    design = loop.controller
    return LoopResponse(f, response, bandwidth, loop_bandwidth(design.kp, design.kd, design.ki))
