"""Run paper 000's Fig. 6 diagram: one Drake ``Simulator`` run per continuous piece of a motion.

:func:`simulate` builds :func:`~armlab.diagrams.build.build_diagram` for each run of the motion
(:meth:`~armlab.kinematics.quintic.Motion.runs`), starts the plant at the run's reference state
(rest, or the constant rates), integrates with Drake's error-controlled Runge–Kutta 5 (4) at
:data:`DEFAULT_ACCURACY`, and gathers the four loggers into one :class:`SimulationLog` on the
motion's time axis. :func:`summarize` gives the numbers of ``summary.json``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.controllers.inverse_dynamics import DEFAULT_KD, DEFAULT_KP
from armlab.diagrams.build import DEFAULT_LOG_PERIOD, MODES, RunDiagram, build_diagram, check_log_period
from armlab.kinematics.quintic import Motion

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = [
    "DEFAULT_ACCURACY",
    "DEFAULT_INTEGRATOR",
    "SimulationLog",
    "run_simulator",
    "simulate",
    "summarize",
]

#: Drake integrator scheme (``ResetIntegratorFromFlags`` name) and its target accuracy: meets
#: 1e-6 rad tracking with the exact model on every paper motion (``tests/test_simulate.py``).
DEFAULT_INTEGRATOR = "runge_kutta5"
DEFAULT_ACCURACY = 1e-6
#: Largest step (s) the integrator may take; the loggers' publish times bound it further.
MAX_STEP = 0.01


@dataclass
class SimulationLog:
    """Everything logged in a simulation, one row per log sample, on the motion's time axis.

    Arrays are ``(m, n)`` except ``t``, ``run``, ``segment`` ``(m,)`` and ``tool`` ``(m, 9)`` =
    [x y z vx vy vz ax ay az] of the tool point in the world frame. Where a motion is made of
    several runs, the time at a join appears twice (end of one run, start of the next).
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
    diagram_dot: str

    def segment_rows(self, k: int) -> NDArray[np.bool_]:
        """The samples of segment ``k``, both ends included (a join's time belongs to both segments it joins)."""
        breaks = self.motion.breaks
        run = int(self.run[np.argmax(self.segment == k)])
        return (self.run == run) & (self.t >= breaks[k] - 1e-12) & (self.t <= breaks[k + 1] + 1e-12)


def run_simulator(run: RunDiagram, accuracy: float = DEFAULT_ACCURACY) -> dict[str, NDArray[np.float64]]:
    """Simulate one built diagram from its motion's start state to its end; the loggers' data by role.

    The loggers sample every ``log_period`` from t = 0, and at the end time when the period does not divide it.

    Returns ``{"t": (m,), "reference": (m, 3n), "state": (m, 2n), "torque": (m, n), "tool": (m, 9)}``.
    """
    from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator

    if not np.isfinite(accuracy) or accuracy <= 0:
        raise ValueError(f"accuracy = {accuracy} is not allowed: give a positive finite target accuracy")
    motion = run.motion
    simulator = Simulator(run.diagram)
    context = simulator.get_mutable_context()
    plant_context = run.plant.GetMyMutableContextFromRoot(context)
    first = motion.segments[0]
    run.plant.SetPositions(plant_context, first.q_start)
    run.plant.SetVelocities(plant_context, first.v_start)
    ResetIntegratorFromFlags(simulator, DEFAULT_INTEGRATOR, MAX_STEP)
    simulator.get_mutable_integrator().set_target_accuracy(accuracy)
    simulator.AdvanceTo(motion.duration)
    logs = {role: logger.FindLog(context) for role, logger in run.loggers.items()}
    if logs["state"].sample_times()[-1] < motion.duration - 1e-9 * run.log_period:
        run.diagram.ForcedPublish(context)  # the period does not divide the duration: log the end too
    times = [log.sample_times() for log in logs.values()]
    if any(not np.array_equal(times[0], other) for other in times[1:]):
        raise RuntimeError("the loggers sampled at different times")
    out = {"t": np.array(times[0])}
    out.update({role: np.array(log.data()).T for role, log in logs.items()})
    return out


def simulate(
    arm: Arm,
    motion: Motion,
    gravity: str | ArrayLike | None = None,
    payload: float = 0.0,
    log_period: float = DEFAULT_LOG_PERIOD,
    mode: str = "controller",
    kp: float | ArrayLike = DEFAULT_KP,
    kd: float | ArrayLike = DEFAULT_KD,
    ki: float | ArrayLike = 0.0,
    accuracy: float = DEFAULT_ACCURACY,
) -> SimulationLog:
    """Simulate ``arm`` following ``motion`` through Fig. 6's diagram; see :func:`build_diagram` for the options.

    Each run of the motion (consecutive segments that join in q and q̇) is its own simulation
    starting at its reference state; where segments do not join the robot would have to
    reconfigure between them, which is not simulated.
    """
    if mode not in MODES:
        raise ValueError(f"mode {mode!r} is not allowed; allowed: {', '.join(MODES)}")
    motion.check_limits(arm)
    log_period = check_log_period(log_period, min(m.duration for _, m in motion.runs()))
    n = arm.n
    parts: list[dict[str, Any]] = []
    dot = ""
    wall = 0.0
    first_segment = 0
    for k, (start, piece) in enumerate(motion.runs()):
        run = build_diagram(arm, piece, gravity, payload, log_period, mode, kp, kd, ki)
        if k == 0:
            dot = run.diagram.GetGraphvizString(max_depth=1)
        began = time.perf_counter()
        data = run_simulator(run, accuracy)
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
        run_starts=[start for start, _ in motion.runs()], wall_time=wall, diagram_dot=dot,
    )


def _stats(log: SimulationLog, rows: NDArray[np.bool_]) -> dict[str, Any]:
    tau, qd = log.tau[rows], log.qd[rows]
    return {
        "max_abs_torque": np.max(np.abs(tau), axis=0).tolist(),
        "rms_torque": np.sqrt(np.mean(tau**2, axis=0)).tolist(),
        "peak_power": float(np.max(np.abs(np.sum(tau * qd, axis=1)))),
        "max_tracking_error": np.max(np.abs(log.q[rows] - log.q_ref[rows]), axis=0).tolist(),
    }


def summarize(log: SimulationLog) -> dict[str, Any]:
    """The numbers of ``summary.json``: overall and per-segment maxima, coefficients, the setup.

    ``max_abs_torque``, ``rms_torque``, ``max_tracking_error``: per joint (N·m or N; rad or m);
    ``peak_power``: max over time of |Σ τ_i q̇_i| (W); ``quintic_coefficients``: per segment, per
    joint, [a1 … a6] of θ(τ) = a1 τ⁵ + … + a6 in the segment's local time τ (paper 000 eqs. 3–6).
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
        "log_period": log.log_period,
        "integrator": {"scheme": DEFAULT_INTEGRATOR, "target_accuracy": log.accuracy, "max_step": MAX_STEP},
        **_stats(log, np.ones(log.t.shape, dtype=bool)),
        "quintic_coefficients": motion.coefficients().tolist(),
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
    }
    return summary
