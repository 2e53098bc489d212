"""The joint servo as engineers build it in Simulink: a controller chosen per run, continuous or sampled, with its
gains from a bandwidth, its torque saturated at the drive's peak and its integrator protected from wind-up.

Three controllers (:data:`CONTROLLERS`), each on the measured state (q_m, q̇_m) and the reference (q_d, q̇_d, q̈_d),
with one PID core whose output is an acceleration (gains normalised by the joint's inertia, so ``kp`` 1/s², ``kd``
1/s and ``ki`` 1/s³ mean the same in every controller)::

    a = c·q̈_d + kp (q_d − q_m) + kd (q̇_d − q̇_m) + z,      ż = ki (q_d − q_m) + (τ_sat − τ*) / (J T_t)

* ``"computed-torque"`` (c = 1): τ* = ID(q_m, q̇_m, a), Drake's ``InverseDynamics`` on the measured state (the ideal
  continuous loop of paper 000's Fig. 6 is Drake's ``InverseDynamicsController``, :mod:`.inverse_dynamics`);
* ``"pid"`` (c = 0): τ* = J a, independent joint PID without a model (its integral holds gravity);
* ``"pd+feedforward"`` (c = 0): τ* = J a + ID(q_d, q̇_d, q̈_d), the inverse dynamics along the reference fed forward.

J_i is the joint's inertia M_ii(q₀) at the run's start pose (the arm's link inertia seen by the joint plus the
reflected rotor inertia G²J_m, both in the plant's mass matrix): the SI gains are K_p = J kp, K_d = J kd, K_i = J ki.

**The tuning rule** (:func:`tuned_gains`): a bandwidth f_b (Hz) is the −3 dB frequency of the position loop q_m/q_d
(q̇_d = q̈_d = 0: the feedback alone, the feedforward making the reference's own transfer 1) of the joint as the
double integrator J s² it is to its controller: PD (``computed-torque``, ``pd+feedforward``) puts both poles at −ω,
kp = ω², kd = 2ω; PID (``pid``) puts three at −ω, kp = 3ω², kd = 3ω, ki = ω³; ω follows from f_b through the
loop's transfer T(s) = (kp s + ki)/(s³ + kd s² + kp s + ki) (:func:`loop_bandwidth`), not from a typed-in ratio.
The default gains 100, 20, 0 are the PD rule at ω = 10 rad/s.

**Sampled** (a period h): the reference and the measurement are held over each period (Drake's ``ZeroOrderHold``,
the sensors of :mod:`.sensors`), the law is evaluated on the held values, so its torque is held too, and the
integral is Drake's discrete ``LinearSystem`` z[k+1] = z[k] + h (ki e[k] + …), forward Euler as Simulink's discrete
PID has it by default.

**Saturation and anti-windup**: τ = sat(τ*) at ± the joint's torque limit (Drake's ``Saturation``); the integral
winds back by back-calculation (Åström & Hägglund, *Advanced PID control*, 2006, §3.5) with the tracking time
T_t = √(T_i T_d) = √(kd/ki) (T_i = kp/ki when kd = 0). Drake's ``PidController`` has neither, so the PID core is built
from Drake's ``MatrixGain``, ``LinearSystem`` and ``Adder`` (:func:`add_pi`), the windup signal (τ_sat, τ*) entering
the integral on a port of its own so that no algebraic loop is closed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.controllers.inverse_dynamics import friction_compensated

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.systems.framework import DiagramBuilder, InputPort, OutputPort

    from armlab.drives.train import DriveTrain

__all__ = [
    "CONTROLLERS",
    "ServoDesign",
    "add_pi",
    "add_position_controller",
    "add_saturation",
    "block_diagonal",
    "joint_inertia",
    "loop_bandwidth",
    "tracking_time",
    "tuned_gains",
]

#: The controllers a run may use (``--controller``).
CONTROLLERS = ("computed-torque", "pid", "pd+feedforward")


def loop_bandwidth(kp: ArrayLike, kd: ArrayLike, ki: ArrayLike) -> NDArray[np.float64]:
    """The −3 dB frequency (Hz) of T(s) = (kp s + ki)/(s³ + kd s² + kp s + ki) per joint (``(n,)`` each; ki = 0: the
    PD loop kp/(s² + kd s + kp)): the smallest x = ω² > 0 where |T(jω)|² = ½, a root of
    −x³ + (2kp − kd²) x² + (kp² + 2 ki kd) x + ki² (numpy's polynomial roots). ``ValueError`` where kp = 0."""
    kp, kd, ki = (np.atleast_1d(np.asarray(g, dtype=float)) for g in (kp, kd, ki))
    out = []
    for p, d, i in zip(*np.broadcast_arrays(kp, kd, ki), strict=True):
        if p <= 0:
            raise ValueError(f"a position loop with kp = {p:g} has no bandwidth: give kp > 0")
        roots = np.roots([-1.0, 2 * p - d * d, p * p + 2 * i * d, i * i])
        real = roots[(np.abs(roots.imag) <= 1e-9 * np.abs(roots)) & (roots.real > 0)].real
        out.append(np.sqrt(real.min()) / (2 * np.pi))
    return np.array(out)


def _rule(controller: str, omega: float) -> tuple[float, float, float]:
    """(kp, kd, ki) of the tuning rule at pole ω (module docstring)."""
    if controller == "pid":
        return 3 * omega**2, 3 * omega, omega**3
    return omega**2, 2 * omega, 0.0


def tuned_gains(controller: str, bandwidth: float) -> tuple[float, float, float]:
    """(kp 1/s², kd 1/s, ki 1/s³) of the tuning rule for ``controller`` at position-loop bandwidth ``bandwidth`` (Hz).

    The rule's ω scales its loop's bandwidth linearly, so ω = 2π f_b / (2π · :func:`loop_bandwidth` at ω = 1).
    """
    unit = loop_bandwidth(*_rule(controller, 1.0))[0]
    return _rule(controller, float(bandwidth) / unit)


def tracking_time(kp: NDArray[np.float64], kd: NDArray[np.float64], ki: NDArray[np.float64]) -> NDArray[np.float64]:
    """The anti-windup tracking time T_t (s) per joint: √(kd/ki), or kp/ki where kd = 0; inf where ki = 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(kd > 0, np.sqrt(kd / ki), kp / ki)
    return np.where(ki > 0, t, np.inf)


def joint_inertia(plant: MultibodyPlant, q: ArrayLike) -> NDArray[np.float64]:
    """J_i = M_ii(q) (kg·m² or kg), ``(n,)``: the diagonal of ``plant``'s mass matrix at ``q`` (reflected rotor inertia
    included), by Drake's ``CalcMassMatrix``."""
    context = plant.CreateDefaultContext()
    plant.SetPositions(context, np.asarray(q, dtype=float))
    return np.diag(plant.CalcMassMatrix(context)).copy()


def block_diagonal(*blocks: ArrayLike) -> NDArray[np.float64]:
    """Row of diagonal blocks ``[diag(b₀) diag(b₁) …]`` ``(n, k·n)`` of per-joint vectors ``(n,)`` (a block may be a
    scalar, times the identity)."""
    n = max(np.size(b) for b in blocks)
    return np.hstack([np.diag(np.broadcast_to(np.asarray(b, dtype=float), (n,))) for b in blocks])


@dataclass(frozen=True)
class ServoDesign:
    """The position controller as it is built, every array ``(n,)``: ``controller`` (one of :data:`CONTROLLERS`),
    ``period`` (s; ``None``: continuous), the normalised gains ``kp`` 1/s², ``kd`` 1/s, ``ki`` 1/s³, the joint
    inertia ``inertia`` J (kg·m² or kg) they are scaled by, ``torque_limit`` (N·m or N; inf: not saturated;
    ``None``: no saturation at all) and ``anti_windup`` (the integral's back-calculation; off: it winds up)."""

    controller: str
    period: float | None
    kp: NDArray[np.float64]
    kd: NDArray[np.float64]
    ki: NDArray[np.float64]
    inertia: NDArray[np.float64]
    torque_limit: NDArray[np.float64] | None
    anti_windup: bool = True

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.kp.size)

    def si_gains(self) -> dict[str, NDArray[np.float64]]:
        """K_p (N·m/rad), K_d (N·m·s/rad), K_i (N·m/(rad·s)) per joint: J times the normalised gains (for the
        computed-torque law, which multiplies by M(q) itself, the same at the tuning pose's diagonal)."""
        return {"Kp": self.inertia * self.kp, "Kd": self.inertia * self.kd, "Ki": self.inertia * self.ki}

    @property
    def back_calculation(self) -> NDArray[np.float64]:
        """1/(J T_t) per joint (1/(kg·m²·s)): the torque excess's gain into the integral; 0 where ki = 0 (and
        everywhere without anti-windup)."""
        on = (self.ki > 0) & self.anti_windup
        return np.where(on, 1.0 / (self.inertia * tracking_time(self.kp, self.kd, self.ki)), 0.0)


def add_pi(builder: DiagramBuilder, name: str, signal: OutputPort, proportional: NDArray[np.float64],
           integral: NDArray[np.float64], back_calculation: NDArray[np.float64] | None, period: float | None,
           ) -> tuple[OutputPort, tuple[InputPort, InputPort] | None]:
    """A PI(D) core u = P s + z on ``signal`` s ``(p,)``: ``proportional`` P and ``integral`` I ``(m, p)``, ż = I s +
    b ⊙ (u_sat − u*) with ``back_calculation`` b ``(m,)`` (``None``: no saturation follows).

    Continuous, or a discrete integral at ``period`` (forward Euler: z[k+1] = z[k] + h (I s[k] + …)). Without any
    integral action (I = 0) the core is the gain alone. Returns the output port u and, when ``back_calculation`` is
    given and there is an integral, the integral's windup inputs (u_sat, u*) for :func:`add_saturation` to connect.
    """
    from pydrake.systems.primitives import Adder, LinearSystem, MatrixGain, Multiplexer

    m, p = proportional.shape
    gain = builder.AddNamedSystem(f"{name}_gains", MatrixGain(proportional))
    builder.Connect(signal, gain.get_input_port())
    if not np.any(integral):
        return gain.get_output_port(), None
    back = np.zeros(m) if back_calculation is None else back_calculation
    windup = bool(np.any(back))
    b = np.hstack([integral, np.diag(back), -np.diag(back)]) if windup else integral
    if period is None:
        system = LinearSystem(np.zeros((m, m)), b, np.eye(m), np.zeros((m, b.shape[1])))
    else:
        system = LinearSystem(np.eye(m), period * b, np.eye(m), np.zeros((m, b.shape[1])), period)
    z = builder.AddNamedSystem(f"{name}_integral", system)
    ports = None
    if windup:
        mux = builder.AddNamedSystem(f"{name}_integral_inputs", Multiplexer([p, m, m]))
        builder.Connect(signal, mux.get_input_port(0))
        builder.Connect(mux.get_output_port(), z.get_input_port())
        ports = (mux.get_input_port(1), mux.get_input_port(2))
    else:
        builder.Connect(signal, z.get_input_port())
    total = builder.AddNamedSystem(f"{name}_sum", Adder(2, m))
    builder.Connect(gain.get_output_port(), total.get_input_port(0))
    builder.Connect(z.get_output_port(), total.get_input_port(1))
    return total.get_output_port(), ports


def add_saturation(builder: DiagramBuilder, name: str, command: OutputPort, limit: NDArray[np.float64],
                   windup: tuple[InputPort, InputPort] | None) -> OutputPort:
    """Drake's ``Saturation`` of ``command`` at ± ``limit`` ``(m,)`` (inf: not limited), feeding (saturated, command)
    back to a PI core's ``windup`` inputs (:func:`add_pi`) if given; the saturated port."""
    from pydrake.systems.primitives import Saturation

    sat = builder.AddNamedSystem(name, Saturation(-limit, limit))
    builder.Connect(command, sat.get_input_port())
    if windup is not None:
        builder.Connect(sat.get_output_port(), windup[0])
        builder.Connect(command, windup[1])
    return sat.get_output_port()


def add_position_controller(builder: DiagramBuilder, model: MultibodyPlant, design: ServoDesign, reference: OutputPort,
                            measured: OutputPort, drives: DriveTrain | None) -> tuple[OutputPort, OutputPort]:
    """The controller of ``design`` (module docstring) on the ``reference`` [q_d, q̇_d, q̈_d] ``(3n,)`` and the
    ``measured`` state [q_m, q̇_m] ``(2n,)`` (both held when sampled: their ports come from holds); ``model``: the
    controller's model of the arm (the computed-torque law and the feedforward); ``drives``: the arm's drive train,
    whose Coulomb friction the model-based laws compensate (at the measured rates for computed torque, at the
    reference's for the feedforward; :func:`~armlab.controllers.inverse_dynamics.friction_compensated`).

    Returns (τ*, τ): the torque command and the torque after the saturation (the same port without one).
    """
    from pydrake.systems.controllers import InverseDynamics
    from pydrake.systems.primitives import Adder, Demultiplexer, MatrixGain, Multiplexer

    n, c = design.n, 1.0 if design.controller == "computed-torque" else 0.0
    signal = builder.AddNamedSystem("servo_signal", Multiplexer([3 * n, 2 * n]))
    builder.Connect(reference, signal.get_input_port(0))
    builder.Connect(measured, signal.get_input_port(1))
    proportional = block_diagonal(design.kp, design.kd, c, -design.kp, -design.kd)
    integral = block_diagonal(design.ki, 0.0, 0.0, -design.ki, 0.0)
    saturate = design.torque_limit is not None
    accel, windup = add_pi(builder, "servo_pid", signal.get_output_port(), proportional, integral,
                           design.back_calculation if saturate else None, design.period)
    if design.controller == "computed-torque":
        law = InverseDynamics(model)
        builder.AddNamedSystem("computed_torque", law)
        builder.Connect(measured, law.get_input_port_estimated_state())
        builder.Connect(accel, law.get_input_port_desired_acceleration())
        command = friction_compensated(builder, law.get_output_port_generalized_force(), measured, drives)
    else:
        scale = builder.AddNamedSystem("joint_inertia", MatrixGain(np.diag(design.inertia)))
        builder.Connect(accel, scale.get_input_port())
        command = scale.get_output_port()
        if design.controller == "pd+feedforward":
            split = builder.AddNamedSystem("feedforward_reference", Demultiplexer([2 * n, n]))
            builder.Connect(reference, split.get_input_port())
            forward = InverseDynamics(model)
            builder.AddNamedSystem("feedforward", forward)
            builder.Connect(split.get_output_port(0), forward.get_input_port_estimated_state())
            builder.Connect(split.get_output_port(1), forward.get_input_port_desired_acceleration())
            feedforward = friction_compensated(builder, forward.get_output_port_generalized_force(),
                                               split.get_output_port(0), drives)
            total = builder.AddNamedSystem("servo_torque", Adder(2, n))
            builder.Connect(command, total.get_input_port(0))
            builder.Connect(feedforward, total.get_input_port(1))
            command = total.get_output_port()
    if not saturate:
        return command, command
    assert design.torque_limit is not None
    return command, add_saturation(builder, "torque_saturation", command, design.torque_limit, windup)
