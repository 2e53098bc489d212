"""Run paper 000's Fig. 6 diagram: one Drake ``Simulator`` run per continuous piece of a motion.

:func:`simulate` builds :func:`~armlab.diagrams.build.build_diagram` for each run of the motion
(:meth:`~armlab.kinematics.quintic.Motion.runs`), starts the plant at the run's reference state
(rest, or the constant rates), integrates with Drake's error-controlled Runge–Kutta 5 (4) at
:data:`DEFAULT_ACCURACY`, and gathers the four loggers into one :class:`SimulationLog` on the
motion's time axis. :func:`summarize` gives the numbers of ``summary.json``. What a simulation is asked
for — the plant's options, mode, gains, log period, sampling, accuracy, divergence tolerance — is one frozen
:class:`SimulationOptions`, checked once when made; :func:`simulate` and ``build_diagram`` take it, and
:func:`armlab.simulate` makes it from its keywords.

Where the time goes, and why the samples come from the dense output: loggers that publish every
1 ms make the integrator stop at every sample (2000 steps of 7 derivative evaluations for a 2 s
motion instead of the ~200 its error control needs) and evaluate the whole diagram, the Python
ToolPoint included, at each one: 16–93× the cost of integrating the bare plant. So by default
(``sampling="dense"``, :mod:`armlab.diagrams.build`) the loggers publish only at the end of a run,
the integrator takes its own steps and keeps its dense output (the state between steps), and
:func:`log_samples` makes each sample at t = 0, Δt, 2Δt, …, and the end from the state there, as
the diagram's systems would: the TrajectorySource's polynomials and their derivatives, the controller's
law τ = ID(q, q̇, q̈_d + kp (q_d − q) + kd (q̇_d − q̇) + ki ∫(q_d − q)) (or τ = ID(q_d, q̇_d, q̈_d) open
loop) by the batched recursive Newton–Euler of :mod:`armlab.kinematics.rnea`, and the tool point's
p, v, a from the same Newton–Euler pass (closed loop) or by :mod:`armlab.kinematics.differential` (open
loop, where the torques are the reference's and the state is not). The loggers' own end sample is checked against the
last row. ``tests/test_simulate.py`` checks every sample against the periodic loggers (``sampling="periodic"``).

Before it starts, :func:`check_work` refuses a motion that would make more than :data:`MAX_SAMPLES`
log samples or needs more than :data:`MAX_STEPS` integrator steps; while it runs, a progress bar shows on
a terminal (stderr), Ctrl-C stops it within one integrator step, and so does a run that takes more steps
than :data:`MAX_STEPS`.
"""

from __future__ import annotations

import contextlib
import functools
import sys
import time
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import above
from armlab.controllers.electrics import energy_balance
from armlab.controllers.inverse_dynamics import DEFAULT_KD, DEFAULT_KP
from armlab.controllers.sensors import ENCODER_SIDES, VELOCITY_SOURCES
from armlab.controllers.servo import CONTROLLERS, tuned_gains
from armlab.diagrams.build import DEFAULT_LOG_PERIOD, MODES, SAMPLINGS, RunDiagram, build_diagram, check_log_period
from armlab.diagrams.drives import DIVERGENCE_TOLERANCE, check_tolerance, torque_stats
from armlab.drives.motor import DEFAULT_CURRENT_BANDWIDTH
from armlab.drives.train import DRIVE_FIELDS, motor_speed, motor_torque
from armlab.kinematics.differential import tool_motion
from armlab.kinematics.quintic import Motion
from armlab.kinematics.rnea import inverse_dynamics, inverse_dynamics_and_tool_point
from armlab.limits import check_range
from armlab.models.plant import PlantOptions

if TYPE_CHECKING:
    from collections.abc import Callable

    from pydrake.systems.framework import Context, Diagram

    from armlab.models.arm import Arm

__all__ = [
    "DEFAULT_ACCURACY",
    "DEFAULT_INTEGRATOR",
    "MAX_SAMPLES",
    "MAX_STEPS",
    "SimulationLog",
    "SimulationOptions",
    "check_work",
    "log_samples",
    "max_step",
    "run_simulator",
    "sample_times",
    "servo_stats",
    "simulate",
    "state_rows",
    "summarize",
]

#: Drake integrator scheme (``ResetIntegratorFromFlags`` name) and its target accuracy: meets
#: 1e-6 rad tracking with the exact model on every paper motion (``tests/test_simulate.py``).
DEFAULT_INTEGRATOR = "runge_kutta5"
DEFAULT_ACCURACY = 1e-6
#: Largest step (s) the integrator may take in ``"controller"`` mode (its error control asks for no smaller
#: steps on the paper motions), and open loop (``"inverse_dynamics"``), where no feedback damps the
#: integration error and the error control, per step, lets it grow to 3e-6 rad in rr's 2 s at 10 ms
#: (at 2 ms: 1e-9 rad).
MAX_STEP = 0.01
OPEN_LOOP_MAX_STEP = 0.002
#: Most log samples one simulation may make (all its runs): a million rows of ``log.csv`` are 0.5–1 GB.
MAX_SAMPLES = 1_000_000
#: Most integrator steps one simulation may take (all its runs): about half a minute to a few minutes.
MAX_STEPS = 500_000
#: Largest joint travel (rad or m) assumed per integrator step when estimating the steps a motion needs.
TRAVEL_PER_STEP = 0.5


#: A controller gain as the options keep it: one value for every joint, or one per joint.
Gain = float | tuple[float, ...]


def _gain(value: float | ArrayLike, name: str) -> Gain:
    """A gain (``name``: kp, kd or ki) checked against its range (:func:`armlab.limits.check_range`), made immutable.

    How many values the arm needs is checked when the diagram is built (:func:`~armlab.controllers.inverse_dynamics.
    gain_vector`), where the arm is known.
    """
    values = check_range(np.asarray(value, dtype=float), name)

    def frozen(x: Any) -> Any:  # nested lists → nested tuples: a wrong shape stays for gain_vector to name
        return tuple(frozen(v) for v in x) if isinstance(x, list) else x

    return frozen(values.tolist())


def _whole(value: Any, name: str) -> int:
    """A whole number in its :data:`armlab.limits.LIMITS` range (``name``: encoder, delay or seed)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} = {value!r} is not allowed: give a whole number")
    return int(check_range(float(value), name))


def _choice(value: Any, name: str, allowed: tuple[str, ...]) -> None:
    if value not in allowed:
        raise ValueError(f"{name} {value!r} is not allowed; allowed: {', '.join(allowed)}")


@dataclass(frozen=True)
class SimulationOptions:
    """What a simulation of Fig. 6 is asked for, checked once when made (``ValueError`` naming the bad value).

    ``plant``: the plant's options (gravity, payload; the drives ideal: a simulated plant is driven by its joint
    torques); ``mode``: one of :data:`~armlab.diagrams.build.MODES`; ``kp`` (1/s²), ``kd`` (1/s), ``ki`` (1/s³):
    the controller's gains, one value or one per joint; ``log_period``: the loggers' period (s); ``sampling``: one
    of :data:`~armlab.diagrams.build.SAMPLINGS` (``None``: ``"dense"`` for the ideal loop, ``"periodic"`` — the only
    one a servo run has — otherwise); ``accuracy``: the integrator's target accuracy; ``divergence_tolerance``: the
    tracking error (rad or m) past which the run has diverged (:func:`armlab.diagrams.drives.divergence`).

    The servo loop (:mod:`armlab.diagrams.servo`; the default is paper 000's ideal loop, continuous computed torque
    on the exact state): ``controller`` (one of :data:`~armlab.controllers.servo.CONTROLLERS`); ``rate`` (Hz; ``None``:
    continuous); ``bandwidth`` (Hz: the gains by the tuning rule, :func:`~armlab.controllers.servo.tuned_gains`,
    instead of ``kp``, ``kd``, ``ki``); ``saturate`` (the torque command clamped at each joint's effort limit) and
    ``anti_windup`` (the integral's back-calculation; ``False``: it winds up, as a teacher may want to show); the
    sensors of a sampled controller (:mod:`armlab.controllers.sensors`): ``encoder`` (counts per
    revolution; ``None``: exact), ``encoder_side`` (``"motor"`` or ``"joint"``), ``velocity`` (``"state"`` or
    ``"difference"``), ``velocity_cutoff`` (Hz, the difference's low-pass), ``noise`` (rad or m, standard deviation),
    ``seed``, ``delay`` (samples); ``electrics`` (the motors' current loops and windings, from the arm's drive train:
    :mod:`armlab.controllers.electrics`), ``current_rate`` (Hz; ``None``: continuous) and ``current_bandwidth`` (Hz);
    ``elastic`` (each joint a two-mass model, the drive train's gearbox stiffness between rotor and link:
    :mod:`armlab.controllers.elastic`; the sensors then read the rotors on the motor side, the links on the joint
    side).
    :func:`armlab.simulate` makes one from its keywords.
    """

    plant: PlantOptions = field(default_factory=functools.partial(PlantOptions, ideal_drives=True))
    mode: str = "controller"
    kp: ArrayLike = DEFAULT_KP  # the gains as given; each kept as a Gain once checked (_gain)
    kd: ArrayLike = DEFAULT_KD
    ki: ArrayLike = 0.0
    log_period: float = DEFAULT_LOG_PERIOD
    sampling: str | None = None
    accuracy: float = DEFAULT_ACCURACY
    divergence_tolerance: float = DIVERGENCE_TOLERANCE
    controller: str = "computed-torque"
    rate: float | None = None
    bandwidth: float | None = None
    saturate: bool = False
    anti_windup: bool = True
    encoder: int | None = None
    encoder_side: str = "motor"
    velocity: str = "state"
    velocity_cutoff: float | None = None
    noise: float = 0.0
    seed: int = 0
    delay: int = 0
    electrics: bool = False
    current_rate: float | None = None
    current_bandwidth: float = DEFAULT_CURRENT_BANDWIDTH
    elastic: bool = False

    def __post_init__(self) -> None:
        if not self.plant.ideal_drives:
            raise ValueError("a simulated plant is driven by its joint torques: "
                             "give PlantOptions(ideal_drives=True, …)")
        _choice(self.mode, "mode", MODES)
        _choice(self.controller, "controller", CONTROLLERS)
        _choice(self.encoder_side, "encoder side", ENCODER_SIDES)
        _choice(self.velocity, "velocity", VELOCITY_SOURCES)
        for name in ("kp", "kd", "ki"):
            object.__setattr__(self, name, _gain(getattr(self, name), name))
        if self.bandwidth is not None:
            object.__setattr__(self, "bandwidth", float(check_range(self.bandwidth, "bandwidth")))
            tuned = tuple(float(g) for g in tuned_gains(self.controller, self.bandwidth))
            if (self.kp, self.kd, self.ki) not in ((DEFAULT_KP, DEFAULT_KD, 0.0), tuned):
                raise ValueError("give the gains (kp, kd, ki) or a bandwidth, not both")
            for name, value in zip(("kp", "kd", "ki"), tuned, strict=True):
                object.__setattr__(self, name, _gain(value, name))
        for name in ("rate", "current_rate"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, float(check_range(getattr(self, name), name, key="rate")))
        object.__setattr__(self, "current_bandwidth", float(check_range(self.current_bandwidth, "current bandwidth",
                                                                        key="bandwidth")))
        if self.velocity_cutoff is not None:
            object.__setattr__(self, "velocity_cutoff", float(check_range(self.velocity_cutoff, "velocity cutoff",
                                                                          key="bandwidth")))
        if self.encoder is not None:
            object.__setattr__(self, "encoder", _whole(self.encoder, "encoder"))
        object.__setattr__(self, "delay", _whole(self.delay, "delay"))
        object.__setattr__(self, "seed", _whole(self.seed, "seed"))
        object.__setattr__(self, "noise", float(check_range(self.noise, "noise")))
        self._check_servo()
        check_log_period(self.log_period)  # kept as given: the check against a motion's duration quotes it so
        object.__setattr__(self, "accuracy", float(check_range(self.accuracy, "accuracy")))
        object.__setattr__(self, "divergence_tolerance", check_tolerance(self.divergence_tolerance))

    def _check_servo(self) -> None:
        """The servo options that need each other, and the sampling the run has."""
        sensed = [name for name, on in (("an encoder", self.encoder is not None), ("noise", self.noise > 0),
                                        ("a delay", self.delay > 0), ("velocity by difference",
                                                                      self.velocity == "difference")) if on]
        if sensed and self.rate is None:
            raise ValueError(f"{' and '.join(sensed)} need{'s' if len(sensed) == 1 else ''} a sampled controller: "
                             "give a rate (--rate HZ)")
        if self.velocity_cutoff is not None and self.velocity != "difference":
            raise ValueError("a velocity cutoff filters the velocity by difference: give velocity 'difference'")
        if self.current_rate is not None and not self.electrics:
            raise ValueError("a current-loop rate needs the motors' electrics (--electrics)")
        if self.servo and self.mode != "controller":
            raise ValueError("the servo options (controller, rate, saturation, sensors, electrics, elastic joints) "
                             "drive the closed loop: use mode 'controller'")
        if self.sampling is not None:
            _choice(self.sampling, "sampling", SAMPLINGS)
        if self.sampling is None:
            object.__setattr__(self, "sampling", "periodic" if self.servo else "dense")
        elif self.servo and self.sampling == "dense":
            raise ValueError("a servo run's loggers sample periodically: give sampling 'periodic' (or leave it out)")

    @property
    def servo(self) -> bool:
        """True when the options ask for more than paper 000's ideal loop (continuous computed torque on the exact
        state): a servo run (:mod:`armlab.diagrams.servo`)."""
        return (self.controller != "computed-torque" or self.rate is not None or self.saturate or self.electrics
                or self.velocity != "state" or self.encoder is not None or self.noise > 0 or self.delay > 0
                or self.elastic)


@dataclass
class SimulationLog:
    """Everything logged in a simulation, one row per log sample, on the motion's time axis.

    Arrays are ``(m, n)`` except ``t``, ``run``, ``segment`` ``(m,)`` and ``tool`` ``(m, 9)`` =
    [x y z vx vy vz ax ay az] of the tool point in the world frame; ``tau`` is joint side, the torque the drives
    apply (with the arm's drive train: reflected inertia and friction included), :attr:`tau_motor` and
    :attr:`motor_speed` its motor side. Where a motion is made of
    several runs, the time at a join appears twice (end of one run, start of the next). ``diagram`` is the
    first run's Fig. 6 diagram, :attr:`diagram_dot` its picture.

    A servo run has its design in ``servo`` (:meth:`armlab.diagrams.servo.ServoLoop.describe`, the first run's) and
    its torque command τ* before the saturation in ``tau_command`` ``(m, n)``, a sampled controller's measured state
    [q_m, q̇_m] in ``measured`` ``(m, 2n)``, elastic joints' rotors [φ, φ̇] in ``rotor`` ``(m, 2n)``; with electrics
    ``current`` (A) and ``voltage`` (V) ``(m, n)`` and ``energy`` ``(m, 3n)`` = [∫V i, ∫τ q̇, ∫R i²] (J) from each
    run's start. The samples of a servo run are the loggers' at t_k, which see the values held over the period before
    t_k.
    """

    arm: Arm
    motion: Motion
    mode: str
    gravity: NDArray[np.float64]
    payload: float
    log_period: float
    accuracy: float
    t: NDArray[np.float64]
    run: NDArray[np.intp]
    segment: NDArray[np.intp]
    q_ref: NDArray[np.float64]
    qd_ref: NDArray[np.float64]
    qdd_ref: NDArray[np.float64]
    q: NDArray[np.float64]
    qd: NDArray[np.float64]
    tau: NDArray[np.float64]
    tool: NDArray[np.float64]
    run_starts: list[float]
    wall_time: float
    diagram: Diagram = field(repr=False, compare=False)
    servo: dict[str, Any] | None = None
    tau_command: NDArray[np.float64] | None = None
    measured: NDArray[np.float64] | None = None
    rotor: NDArray[np.float64] | None = None
    current: NDArray[np.float64] | None = None
    voltage: NDArray[np.float64] | None = None
    energy: NDArray[np.float64] | None = None

    @cached_property
    def tau_motor(self) -> NDArray[np.float64] | None:
        """Motor-side torques ``(m, n)`` (N·m) of :attr:`tau` by :func:`armlab.drives.train.motor_torque` (τ/(G·η)
        delivering, τ·η/G driven back), ``None`` for ideal drives (the arm has no drive train); made when first
        asked for (the log's files, summary and replay all read it)."""
        drives = self.arm.drives
        return None if drives is None else motor_torque(drives, self.tau, self.qd)

    @cached_property
    def motor_speed(self) -> NDArray[np.float64] | None:
        """Motor speeds G·q̇ ``(m, n)`` (rad/s), ``None`` for ideal drives; made when first asked for."""
        drives = self.arm.drives
        return None if drives is None else motor_speed(drives, self.qd)

    @cached_property
    def diagram_dot(self) -> str:
        """Graphviz text of :attr:`diagram`, one level deep (made when first asked for: 0.6 ms, as much as a
        fifth of the samples, that most callers never use)."""
        return self.diagram.GetGraphvizString(max_depth=1)

    def segment_rows(self, k: int) -> NDArray[np.bool_]:
        """The samples of segment ``k``, both ends included (a join's time belongs to both segments it joins)."""
        breaks = self.motion.breaks
        run = int(self.run[np.argmax(self.segment == k)])
        return (self.run == run) & (self.t >= breaks[k] - 1e-12) & (self.t <= breaks[k + 1] + 1e-12)


# ----------------------------------------------------------------------------------------- the work
def max_step(mode: str) -> float:
    """The integrator's largest step (s) in ``mode``: :data:`MAX_STEP` or :data:`OPEN_LOOP_MAX_STEP`."""
    return MAX_STEP if mode == "controller" else OPEN_LOOP_MAX_STEP


def _sample_count(duration: float, period: float) -> int:
    """How many samples :func:`sample_times` gives, without making them (at most one more)."""
    return int(duration // period) + 2


def sample_times(duration: float, period: float) -> NDArray[np.float64]:
    """The loggers' sample times: k·``period`` for k = 0, 1, … up to ``duration``, and ``duration`` itself.

    Exactly the times periodic publish events happen at in Drake (k·period, offset 0) and the end
    sample :func:`run_simulator` adds when the period does not divide the duration.
    """
    t = np.arange(_sample_count(duration, period), dtype=np.float64) * period
    t = t[t <= duration]
    return t if t[-1] >= duration - 1e-9 * period else np.append(t, duration)


def _travel(motion: Motion) -> float:
    """The largest path length of one joint over ``motion`` (rad or m), from 64 samples per segment."""
    t = np.linspace(0.0, motion.duration, 64 * len(motion.segments) + 1)
    return float(np.max(np.sum(np.abs(np.diff(motion.evaluate(t, 1)[0], axis=0)), axis=0)))


def check_work(motion: Motion, log_period: float, mode: str = "controller") -> tuple[int, int]:
    """(log samples, least integrator steps) of simulating ``motion`` in ``mode``; ``ValueError`` past the limits.

    The steps are at least duration / :func:`max_step` and the largest joint travel / :data:`TRAVEL_PER_STEP`
    per run; more than :data:`MAX_STEPS` of them, or more than :data:`MAX_SAMPLES` samples, could not finish
    in reasonable time or memory, and is refused with the number and the option to change; so is a log period
    longer than a run of the motion (one rule for ``simulate`` and the design studies).
    """
    runs = [piece for _, piece in motion.runs()]
    check_log_period(log_period, min(piece.duration for piece in runs))
    samples = 0
    for piece in runs:  # as many as sample_times gives, without making them
        k = np.floor(piece.duration / log_period)
        samples += int(k) + 1 + int(k * log_period < piece.duration - 1e-9 * log_period)
    if samples > MAX_SAMPLES:
        raise ValueError(f"a {motion.duration:g} s motion logged every {log_period:g} s makes {samples:,} log samples, "
                         f"more than the {MAX_SAMPLES:,} allowed: give a longer log period (--dt) or a shorter motion")
    travels = [_travel(piece) for piece in runs]
    travel = max(travels)
    steps = sum(max(piece.duration / max_step(mode), length / TRAVEL_PER_STEP)
                for piece, length in zip(runs, travels, strict=True))
    if steps > MAX_STEPS:
        raise ValueError(f"a {motion.duration:g} s motion with {travel:.3g} rad (or m) of joint travel needs at least "
                         f"{steps:,.0f} integrator steps (≤ {max_step(mode):g} s and ≤ {TRAVEL_PER_STEP:g} rad each), "
                         f"more than the {MAX_STEPS:,} allowed: give a shorter motion (--tf) or less joint travel")
    return samples, int(np.ceil(steps))


class _Watch:
    """The simulator's monitor over all runs: progress on a terminal, Ctrl-C and the step budget checked per step."""

    def __init__(self, name: str, duration: float, accuracy: float) -> None:
        self.duration, self.accuracy, self.steps, self.offset = duration, accuracy, 0, 0.0
        self.tqdm: Any = None  # the progress bar, on a terminal only (made off one, tqdm alone costs 1 ms a run)
        self.bar: contextlib.AbstractContextManager[Any] = contextlib.nullcontext()
        isatty = getattr(sys.stderr, "isatty", None)
        if isatty is not None and isatty():
            from tqdm import tqdm

            self.tqdm = self.bar = tqdm(
                total=duration, desc=f"simulating {name}", unit="s", delay=0.2, leave=False, file=sys.stderr,
                bar_format="{desc}: {n:.2f}/{total:g} s |{bar}| {elapsed}<{remaining}, {rate_fmt}")

    def __call__(self, context: Context) -> None:
        self.steps += 1
        t = self.offset + context.get_time()
        if self.steps > MAX_STEPS:
            raise ValueError(f"the integrator took more than {MAX_STEPS:,} steps and reached only t = {t:.4g} s of "
                             f"{self.duration:g} s: the arm cannot follow this motion at accuracy {self.accuracy:g}; "
                             "give it more time (--tf) or less joint travel")
        if self.tqdm is not None:
            self.tqdm.update(t - self.tqdm.n)


# ---------------------------------------------------------------------------------- the samples
def state_rows(run: RunDiagram, context: Context) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Rows of the diagram's continuous state holding the plant's [q, v], and the others (the PID's ∫(q_d − q)).

    Found by writing 0, 1, 2, … into the state and reading the plant's part; the state is restored.
    """
    x = context.get_continuous_state_vector().CopyToVector()
    context.SetContinuousState(np.arange(x.size, dtype=float))
    plant = run.plant.GetPositionsAndVelocities(run.plant.GetMyContextFromRoot(context)).astype(np.intp)
    context.SetContinuousState(x)
    return plant, np.setdiff1d(np.arange(x.size), plant)


def _forward_dynamics(run: RunDiagram, q: NDArray, v: NDArray, tau: NDArray) -> NDArray[np.float64]:
    """v̇ = M(q)⁻¹ (τ − C(q, v) v + τ_g(q)) per sample, M column by column from the batched inverse dynamics."""
    arm, n = run.arm, q.shape[1]
    bias = inverse_dynamics(arm, q, v, np.zeros(n), run.gravity, run.payload)
    mass = np.stack([inverse_dynamics(arm, q, np.zeros(n), e, np.zeros(3), run.payload) for e in np.eye(n)], axis=-1)
    return np.linalg.solve(mass, (tau - bias)[..., None])[..., 0]


def log_samples(run: RunDiagram, t: NDArray[np.float64], x: NDArray[np.float64], plant_rows: NDArray[np.intp],
                other_rows: NDArray[np.intp]) -> dict[str, NDArray[np.float64]]:
    """What the loggers of ``run`` record at times ``t`` ``(m,)`` with the diagram's continuous state ``x`` ``(m, k)``.

    ``plant_rows``, ``other_rows``: :func:`state_rows`, the rows of ``x`` holding the plant's [q, v] and the
    PID's ∫(q_d − q) (controller mode). Returns ``{"reference": (m, 3n), "state": (m, 2n), "torque": (m, n),
    "tool": (m, 9)}``, computed as the diagram's systems compute their outputs (see the module docstring), for all
    samples at once.
    """
    arm, n = run.arm, run.arm.n
    ref = np.hstack(run.motion.evaluate(t))  # the TrajectorySource's polynomials, in numpy (Horner's rule)
    q_d, v_d, a_d = ref[:, :n], ref[:, n:2 * n], ref[:, 2 * n:]
    state = x[:, plant_rows]
    q, v = state[:, :n], state[:, n:]
    if run.mode == "controller":
        kp, kd, ki = run.gains
        # the controller's model is the plant (same arm, gravity, payload): the plant's v̇ is the commanded one
        vdot = a_d + kp * (q_d - q) + kd * (v_d - v) + ki * x[:, other_rows]
        tau, tool = inverse_dynamics_and_tool_point(arm, q, v, vdot, run.gravity, run.payload)  # one pass for both
    else:
        tau = inverse_dynamics(arm, q_d, v_d, a_d, run.gravity, run.payload)
        vdot = _forward_dynamics(run, q, v, tau)
        twist, accel = tool_motion(arm, q, v, vdot)
        tool = np.hstack([arm.forward(q).tool[:, :3, 3], twist[:, :3], accel[:, :3]])
    return {"reference": ref, "state": state, "torque": tau, "tool": tool}


def _logged(run: RunDiagram, context: Context) -> dict[str, NDArray[np.float64]]:
    """The loggers' records by role, ``(m, size)`` each, with their common times under ``"t"``."""
    logs = {role: logger.FindLog(context) for role, logger in run.loggers.items()}
    times = [log.sample_times() for log in logs.values()]
    if any(not np.array_equal(times[0], other) for other in times[1:]):
        raise RuntimeError("the loggers sampled at different times")
    out = {"t": np.array(times[0])}
    out.update({role: np.array(log.data()).T for role, log in logs.items()})
    return out


def _check_end(run: RunDiagram, logged: dict[str, NDArray], made: dict[str, NDArray]) -> None:
    """``RuntimeError`` unless the loggers' end sample (the diagram's own outputs) equals the last sample made."""
    for role, values in made.items():
        own, last = logged[role][-1], values[-1]
        scale = max(1.0, float(np.max(np.abs(values))))
        if not np.allclose(own, last, rtol=0, atol=1e-9 * scale):
            raise RuntimeError(f"the {role} samples made from the integrator's dense output differ from the "
                               f"diagram's own at t = {logged['t'][-1]:g} s: {last.tolist()} vs {own.tolist()}")


# ------------------------------------------------------------------------------------------- the runs
def run_simulator(run: RunDiagram, accuracy: float = DEFAULT_ACCURACY,
                  monitor: Callable[[Context], None] | None = None) -> dict[str, NDArray[np.float64]]:
    """Simulate one built diagram from its motion's start state to its end; the loggers' data by role.

    The samples are at :func:`sample_times` (every ``log_period`` from t = 0, and the end); with
    ``run.sampling == "dense"`` they are made by :func:`log_samples` from the integrator's dense output and
    checked against the loggers' end sample, with ``"periodic"`` the loggers record them. ``monitor`` is called
    after every integrator step with the root context (it may raise to stop the run).

    Returns ``{"t": (m,), "reference": (m, 3n), "state": (m, 2n), "torque": (m, n), "tool": (m, 9)}`` and a servo
    run's ``"command"`` (m, n), ``"measured"`` (m, 2n) with sensors and, with electrics, ``"current"``, ``"voltage"``
    (m, n) and ``"energy"`` (m, 3n).
    """
    from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator

    check_range(accuracy, "accuracy")
    motion = run.motion
    simulator = Simulator(run.diagram)
    context = simulator.get_mutable_context()
    rows = state_rows(run, context)
    plant_context = run.plant.GetMyMutableContextFromRoot(context)
    first = motion.segments[0]
    if run.servo is not None:
        run.servo.prepare(run.diagram, context)
    run.plant.SetPositions(plant_context, first.q_start)
    run.plant.SetVelocities(plant_context, first.v_start)
    if run.servo is not None:
        run.servo.initialize(run.diagram, context, first.q_start, first.v_start)
    ResetIntegratorFromFlags(simulator, DEFAULT_INTEGRATOR, max_step(run.mode))
    integrator = simulator.get_mutable_integrator()
    integrator.set_target_accuracy(accuracy)
    if monitor is not None:
        simulator.set_monitor(monitor)
    simulator.Initialize()
    dense = run.sampling == "dense"
    if dense:
        integrator.StartDenseIntegration()
    for end in motion.jumps()[1:]:  # stop where q̈_d may jump (joins, a timing's knots): no step straddles a jump
        simulator.AdvanceTo(end)
    if not dense:
        if run.loggers["state"].FindLog(context).sample_times()[-1] < motion.duration - 1e-9 * run.log_period:
            run.diagram.ForcedPublish(context)  # the period does not divide the duration: log the end too
        return _logged(run, context)
    t = sample_times(motion.duration, run.log_period)
    made = log_samples(run, t, integrator.StopDenseIntegration().vector_values(t.tolist()).T, *rows)
    run.diagram.ForcedPublish(context)  # the loggers' one sample: the diagram's own outputs at the end
    _check_end(run, _logged(run, context), made)
    return {"t": t, **made}


def simulate(arm: Arm, motion: Motion, options: SimulationOptions | None = None) -> SimulationLog:
    """Simulate ``arm`` following ``motion`` through Fig. 6's diagram with ``options`` (default
    :class:`SimulationOptions`'; :func:`build_diagram` builds each run's diagram).

    Each run of the motion (consecutive segments that join in q and q̇) is its own simulation
    starting at its reference state; where segments do not join the robot would have to
    reconfigure between them, which is not simulated. ``ValueError`` before anything runs for work
    past :func:`check_work`'s limits, and during the run if the integrator needs more than
    :data:`MAX_STEPS` steps. A progress bar shows on stderr when it is a terminal.
    """
    options = SimulationOptions() if options is None else options
    mode, accuracy = options.mode, options.accuracy
    motion.check_limits(arm)
    log_period = float(options.log_period)  # checked by SimulationOptions; against the runs by check_work
    check_work(motion, log_period, mode)  # the log period against the motion's runs too
    n = arm.n
    parts: list[dict[str, Any]] = []
    diagrams: list[Diagram] = []  # the first run's diagram, kept for the log
    designs: list[dict[str, Any]] = []  # the first run's servo design
    wall = 0.0
    first_segment = 0
    watch = _Watch(arm.name, motion.duration, accuracy)
    with watch.bar:
        for k, (start, piece) in enumerate(motion.runs()):
            run = build_diagram(arm, piece, options, limits_checked=True)  # the whole motion's checked above
            if k == 0:
                diagrams.append(run.diagram)
                designs.append(run.servo.describe() if run.servo is not None else {})
            watch.offset = start
            began = time.perf_counter()
            data: dict[str, NDArray] = run_simulator(run, accuracy, watch)
            wall += time.perf_counter() - began
            data["run"] = np.full(data["t"].shape, k)
            data["segment"] = first_segment + piece.segment_index(data["t"])
            data["t"] = data["t"] + start
            parts.append(data)
            first_segment += len(piece.segments)
            gravity_vector, payload_mass = run.gravity, run.payload

    def cat(key: str) -> NDArray:
        return np.concatenate([p[key] for p in parts])

    reference, state = cat("reference"), cat("state")
    return SimulationLog(
        arm=arm, motion=motion, mode=mode, gravity=gravity_vector, payload=payload_mass, log_period=log_period,
        accuracy=accuracy, t=cat("t"), run=cat("run"), segment=cat("segment"),
        q_ref=reference[:, :n], qd_ref=reference[:, n:2 * n], qdd_ref=reference[:, 2 * n:],
        q=state[:, :n], qd=state[:, n:], tau=cat("torque"), tool=cat("tool"),
        run_starts=[start for start, _ in motion.runs()], wall_time=wall, diagram=diagrams[0],
        servo=designs[0] or None, **{name: cat(role) for name, role in (
            ("tau_command", "command"), ("measured", "measured"), ("rotor", "rotor"), ("current", "current"),
            ("voltage", "voltage"), ("energy", "energy")) if role in parts[0]},
    )


def _stats(log: SimulationLog, rows: NDArray[np.bool_]) -> dict[str, Any]:
    stats = torque_stats(log.tau[rows], log.qd[rows])
    return {
        "max_abs_torque": stats["max_abs_torque"].tolist(),
        "rms_torque": stats["rms_torque"].tolist(),
        "peak_power": stats["peak_power"],
        "max_tracking_error": np.max(np.abs(log.q[rows] - log.q_ref[rows]), axis=0).tolist(),
    }


def summarize(log: SimulationLog) -> dict[str, Any]:
    """The numbers of ``summary.json``: overall and per-segment maxima, coefficients, the setup.

    ``max_abs_torque``, ``rms_torque``, ``max_tracking_error``: per joint (N·m or N; rad or m);
    ``peak_power``: max over time of |Σ τ_i q̇_i| (W); ``drive_train``: the arm's (``None``: ideal drives), its
    parameters per joint; ``quintic_coefficients``: per segment, per joint, [a1 … a6] of θ(τ) = a1 τ⁵ + … + a6 in
    the segment's local time τ (paper 000 eqs. 3–6), ``None`` for a motion with a trajectory segment (a tool path,
    a time-optimal timing), which has no such coefficients.
    """
    arm, motion = log.arm, log.motion
    joins = motion.joins()
    segments = []
    breaks = motion.breaks
    for k, (label, s) in enumerate(zip(motion.labels, motion.segments, strict=True)):
        rows = log.segment_rows(k)
        run = int(log.run[rows][0])
        entry = {"label": label, "kind": type(s).__name__, "t_start": float(breaks[k]), "t_end": float(breaks[k + 1]),
                 "q_start": s.q_start.tolist(), "q_end": s.q_end.tolist(), "run": run}
        if k > 0:
            entry["joins_previous"] = joins[k - 1]
            if not joins[k - 1]:
                entry["jump_from_previous"] = (s.q_start - motion.segments[k - 1].q_end).tolist()
        entry.update(_stats(log, rows))
        segments.append(entry)
    revolute = arm.revolute
    summary: dict[str, Any] = {
        "arm": arm.name,
        "paper": arm.paper,
        "motion": motion.description,
        "figures": dict(motion.figures),
        "mode": log.mode,
        "duration": motion.duration,
        "joint_units": ["rad" if r else "m" for r in revolute],
        "torque_units": ["N·m" if r else "N" for r in revolute],
        "gravity": log.gravity.tolist(),
        "payload_kg": log.payload,
        "drive_train": None if arm.drives is None else {
            **{name: arm.drives.per_joint(name).tolist() for name in DRIVE_FIELDS},
            "coulomb_speed": arm.drives.coulomb_speed,
            "units": {"rotor_inertia": "kg·m² (motor side)", "viscous": "N·m·s/rad (joint side)",
                      "coulomb": "N·m (joint side; T_c+, q̇ ≥ 0)", "coulomb_negative": "N·m (joint side; T_c−, q̇ < 0)"}},
        "log_period": log.log_period,
        "integrator": {"scheme": DEFAULT_INTEGRATOR, "target_accuracy": log.accuracy, "max_step": max_step(log.mode)},
        **_stats(log, np.ones(log.t.shape, dtype=bool)),
        "quintic_coefficients": motion.coefficients().tolist() if motion.polynomial else None,
        "segments": segments,
        "runs": {
            "count": len(log.run_starts),
            "starts": log.run_starts,
            "note": "each run is simulated from rest (or its constant rates) at its own start; consecutive "
                    "segments that do not join in joint space would need the robot to reconfigure in between, "
                    "which is not simulated" if len(log.run_starts) > 1 else "one continuous run",
        },
        "wall_time_s": log.wall_time,
        "real_time_factor": motion.duration / log.wall_time if log.wall_time > 0 else None,
        "servo": None if log.servo is None else {**log.servo, **servo_stats(log)},
    }
    return summary


def servo_stats(log: SimulationLog) -> dict[str, Any]:
    """What a servo run did, per joint: ``rms_tracking_error`` (rad or m), ``saturation_time`` (s the torque command
    τ* spent past its limit, counted in log periods: each sample after its run's first stands for the period before
    it; ``None`` without a saturation), and with electrics ``peak_current`` (A), ``peak_voltage`` (V),
    ``voltage_saturation_time`` (s at the bus voltage) and ``energy`` (J: electrical ∫V i, mechanical ∫τ q̇, copper
    ∫R i², magnetic Δ½Li², summed over the runs, and the balance's relative residual:
    :func:`~armlab.controllers.electrics.energy_balance`)."""
    assert log.servo is not None
    out: dict[str, Any] = {"rms_tracking_error": np.sqrt(np.mean((log.q - log.q_ref) ** 2, axis=0)).tolist()}
    later = np.r_[False, log.run[1:] == log.run[:-1]]  # each sample after its run's first
    limit = log.servo["torque_limit"]
    if limit is None or log.tau_command is None:
        out["saturation_time"] = None
    else:
        bound = np.array([np.inf if v is None else v for v in limit])
        out["saturation_time"] = (np.sum(above(np.abs(log.tau_command), bound) & later[:, None], axis=0)
                                  * log.log_period).tolist()
    if log.current is not None and log.voltage is not None and log.energy is not None:
        loop = log.servo["current_loop"]
        bus, inductance = np.asarray(loop["bus_voltage"]), np.asarray(loop["inductance"])
        at_bus = ~above(bus, np.abs(log.voltage))  # |V| on the bus voltage (within the slack)
        out["peak_current"] = np.max(np.abs(log.current), axis=0).tolist()
        out["peak_voltage"] = np.max(np.abs(log.voltage), axis=0).tolist()
        out["voltage_saturation_time"] = (np.sum(at_bus & later[:, None], axis=0) * log.log_period).tolist()
        balance = energy_balance(log.energy, log.current, inductance, log.run)
        out["energy"] = {**{k: v.tolist() for k, v in balance.items()}, "unit": "J"}
    return out
