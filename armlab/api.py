"""armlab from a Python script: load an arm, move it, simulate it.

The names here are exported from ``armlab`` itself (``import armlab; armlab.load("urm6")``); the
``armlab`` command line is a thin layer over them. An arm's own kinematics and dynamics are methods
of :class:`~armlab.models.arm.Arm` (``fk``, ``jacobian``, ``tool_motion``, ``inverse_dynamics``,
``manipulability``, ``sigma_min``, ``ik``); motions and simulations are functions:
    >>> import armlab
    >>> arm = armlab.load("rr")
    >>> motion = armlab.quintic(arm, [0.0, 0.5], [1.0, 1.0], tf=2.0)
    >>> run = armlab.simulate(arm, motion, payload=0.5)        # doctest: +SKIP
    >>> run.summary["max_abs_torque"], run.violations            # doctest: +SKIP

Angles are radians, lengths metres, times seconds, torques N·m (forces N for prismatic joints)
throughout. Every function raises ``ValueError`` with a one-line message naming a bad value.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from armlab.collision.clearance import as_scene
from armlab.collision.scene import Scene
from armlab.diagrams.run import Run
from armlab.diagrams.simulate import (
    DEFAULT_ACCURACY,
    DEFAULT_KD,
    DEFAULT_KP,
    DEFAULT_LOG_PERIOD,
    DIVERGENCE_TOLERANCE,
    SimulationOptions,
)
from armlab.diagrams.simulate import simulate as run_diagram
from armlab.drives.motor import DEFAULT_CURRENT_BANDWIDTH
from armlab.drives.read import with_drives
from armlab.kinematics.cartesian import (
    DEFAULT_SAMPLES,
    arc_path,
    arc_through,
    line_path,
    path_profile,
    tool_motion_along,
)
from armlab.kinematics.profiles import spline
from armlab.kinematics.profiles import trapezoidal as joint_trapezoid
from armlab.kinematics.quintic import ConstantRate, Motion, QuinticSegment, check_duration
from armlab.models import get_arm
from armlab.models.arm import Arm
from armlab.models.plant import PlantOptions
from armlab.planning.motions import paper_motion as motion_of_paper
from armlab.planning.motions import quintic_motion
from armlab.planning.motions import read_segments as read
from armlab.planning.planner import Plan
from armlab.planning.planner import plan_path as plan_around
from armlab.planning.timing import DEFAULT_GRID, Fastest
from armlab.planning.timing import fastest as time_optimal
from armlab.sizing.catalogue import Gearboxes, Motors, read_gearboxes, read_motors
from armlab.sizing.checks import Conditions
from armlab.sizing.duty import DEFAULT_RATE, DutyCycle, LoadCase, load_cases_of, read_duty_cycle
from armlab.sizing.sizing import Sizing, size

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from armlab.drives.train import DriveTrain

__all__ = ["arc", "constant_rate", "draw", "fastest", "line", "load", "paper_motion", "plan_path", "quintic",
           "read_segments", "simulate", "size_drives", "through", "trapezoidal"]


def load(name: str | Path, *, drives: str | Path | DriveTrain | None = None, tool: str | None = None,
         package_paths: Sequence[str | Path] = (), **parameters: float) -> Arm:
    """An arm: a paper arm's name (``armlab list``: rr, rrrr, arm4r, r2t, urm6), a library arm's (puma560, ur5, ur10,
    panda, stanford, irb140, kr5: well-known arms, every number cited), a ``.urdf``, ``.sdf``, MJCF ``.xml`` or DH
    ``.csv`` file.

    ``parameters`` override a paper arm's parameters (e.g. ``load("urm6", theta3=0.5)``; names as in
    ``armlab show ARM``). ``drives``: its drive train, a drive file (CSV, see the README) or a
    :class:`~armlab.drives.train.DriveTrain`, instead of the one its file gives (``None``: that one; none: ideal
    drives). For a URDF: ``tool`` names the tool frame's link (default: the end of the chain; ``armlab show`` lists
    the choices) and ``package_paths`` the folders holding the ROS packages of its ``package://`` meshes
    (``ROS_PACKAGE_PATH`` is searched too). ``ValueError`` for an unknown arm or parameter, or a malformed file.
    """
    return with_drives(get_arm(str(name), tool, package_paths, **parameters), drives)


def quintic(arm: Arm, q0: ArrayLike, qf: ArrayLike, tf: float, label: str = "") -> Motion:
    """A rest-to-rest quintic from ``q0`` to ``qf`` (each ``(n,)``) in ``tf`` s (paper 000, eqs. 3–6).

    Zero velocity and acceleration at both ends; both ends are checked against the joint limits.
    """
    return quintic_motion(arm, q0, qf, tf, label or "rest-to-rest quintic")


def through(arm: Arm, waypoints: ArrayLike, tf: float | Sequence[float], stop: bool = True, degree: int = 5,
            velocities: ArrayLike | None = None, accelerations: ArrayLike | None = None) -> Motion:
    """Quintics through ``waypoints`` ``(k + 1, n)``: k segments of ``tf`` s each (or one tf each).

    ``stop=True``: rest to rest, the arm stops at every waypoint, as paper 000's A → B → C → D → A does.
    ``stop=False``: through the via points without stopping (MATLAB ``quinticpolytraj`` / ``cubicpolytraj``,
    ``degree`` 5 or 3): ``velocities`` (and ``accelerations``) at the waypoints, default Craig's rule
    (:func:`armlab.kinematics.profiles.via_rule`: the mean of the adjacent segments' slopes, 0 where they differ
    in sign; at rest at both ends).
    """
    if not stop:
        return spline(arm, waypoints, tf, degree, velocities, accelerations)
    points = np.asarray(waypoints, dtype=float)
    if points.ndim != 2 or points.shape[0] < 2:
        raise ValueError(f"waypoints have shape {points.shape}; give at least two rows of {arm.n} joint values")
    durations = (list(tf) if isinstance(tf, Iterable) and np.ndim(tf) != 0
                 else np.broadcast_to(np.asarray(tf, dtype=float), (points.shape[0] - 1,)))
    if len(durations) != points.shape[0] - 1:
        raise ValueError(f"tf has {len(durations)} values; {points.shape[0] - 1} segments need one each (or one tf)")
    segments = tuple(QuinticSegment(a, b, check_duration(t), f"{k + 1}")
                     for k, (a, b, t) in enumerate(zip(points[:-1], points[1:], durations, strict=True)))
    motion = Motion(segments, f"rest-to-rest quintics through {points.shape[0]} waypoints")
    motion.check_limits(arm)
    return motion


def constant_rate(arm: Arm, q0: ArrayLike, rate: ArrayLike, tf: float) -> Motion:
    """Constant joint rates: q = q0 + ω t for ``tf`` s (paper 000's RRRR run, Figs. 18–19); ``rate`` in rad/s or m/s."""
    # as ConstantRate reads them (its fields are the arrays it makes of them)
    start, omega = np.asarray(q0, dtype=float), np.asarray(rate, dtype=float)
    motion = Motion((ConstantRate(start, omega, check_duration(tf), "constant-rate"),), "constant joint rates")
    motion.check_limits(arm)
    return motion


def trapezoidal(arm: Arm, q0: ArrayLike, qf: ArrayLike, velocity: float | ArrayLike | None = None,
                acceleration: float | ArrayLike | None = None, tf: float | None = None) -> Motion:
    """A synchronised trapezoidal velocity profile from ``q0`` to ``qf`` (RTB ``trapezoidal``/``mtraj``, MATLAB
    ``trapveltraj``): each joint's peak ``velocity`` and ``acceleration`` (one value or one per joint), or a
    duration ``tf`` (s; peak rate 1.5 × the mean, RTB's default); every joint arrives at the same time."""
    return joint_trapezoid(arm, q0, qf, velocity, acceleration, tf)


def line(arm: Arm, start: ArrayLike | None, end: ArrayLike, tf: float | None = None, profile: str = "minimum-jerk",
         speed: float | None = None, acceleration: float | None = None, q0: ArrayLike | None = None,
         branch: int | None = None, samples: int = DEFAULT_SAMPLES) -> Motion:
    """The tool along the straight line from ``start`` to ``end`` (RTB ``ctraj``, MATLAB ``transformtraj``).

    ``start``, ``end``: points (x, y, z) m (rr: (x, y)) or 4×4 poses. A 6-joint arm (or more) holds the tool's
    rotation at the start configuration when ``start`` is a point (RTB ``ctraj``'s rule), and slerps it between
    two given poses (a pose start and a point end: held); ``start=None``: the tool's pose at ``q0``. Timing
    ``profile``: ``"minimum-jerk"`` or ``"cubic"`` over ``tf`` s,
    or ``"trapezoid"`` with the tool's peak ``speed`` (m/s) and ``acceleration`` (m/s²) or ``tf``. The joints by
    IK at ``samples`` points on one branch, starting at ``q0``, closed-form IK ``branch`` or the IK solution
    nearest zero; ``ValueError`` with the path parameter s and the point where the line leaves the reach, a
    joint limit or passes a singularity.
    """
    if start is None:
        if q0 is None:
            raise ValueError("give the line's start point, or the start configuration q0")
        start = arm.fk(q0)[:3, 3] if arm.n < 6 else arm.fk(q0)
    path = line_path(start, end)
    return tool_motion_along(arm, path, profile=path_profile(path, profile, tf, speed, acceleration), q0=q0,
                             branch=branch, samples=samples)


def arc(arm: Arm, through: Sequence[ArrayLike] | None = None, tf: float | None = None,
        centre: ArrayLike | None = None, axis: ArrayLike | None = None, start: ArrayLike | None = None,
        angle: float | None = None, profile: str = "minimum-jerk", speed: float | None = None,
        acceleration: float | None = None, q0: ArrayLike | None = None, branch: int | None = None,
        samples: int = DEFAULT_SAMPLES) -> Motion:
    """The tool along a circular arc: ``through`` three points (from the first by the second to the third), or
    about ``centre`` and ``axis`` by ``angle`` (rad, right-handed) from ``start``. Timing and IK as :func:`line`."""
    if through is not None:
        if centre is not None or axis is not None or angle is not None:
            raise ValueError("give an arc three points, or a centre, axis, start and angle, not both")
        if len(through) != 3:
            raise ValueError(f"an arc through points needs 3 of them, got {len(through)}")
        path = arc_through(*through)
    else:
        if centre is None or axis is None or start is None or angle is None:
            raise ValueError("give an arc three points (through=), or its centre, axis, start and angle")
        path = arc_path(centre, axis, start, angle)
    return tool_motion_along(arm, path, profile=path_profile(path, profile, tf, speed, acceleration), q0=q0,
                             branch=branch, samples=samples)


def fastest(arm: Arm, path: Motion, velocity: float | ArrayLike | None = None,
            acceleration: float | ArrayLike | None = None, effort: float | ArrayLike | None = None,
            drives: DriveTrain | None = None, motor_speed: float | ArrayLike | None = None,
            motor_torque: float | ArrayLike | None = None, grid: int = DEFAULT_GRID, payload: float = 0.0,
            gravity: str | ArrayLike | None = None) -> Fastest:
    """The fastest timing of ``path`` (any motion, its geometric path kept; a tool line or arc) within the joint
    limits, by Drake's ``Toppra`` (MATLAB ``contopptraj``, plus torque limits): the arm file's velocity and effort
    limits unless given, an ``acceleration`` limit if given, motor-side limits through ``drives``; ``payload``
    (kg) and ``gravity`` as :func:`simulate` takes them (give the run the same). Checked densely afterwards (a
    simulation's log samples among the points) and slowed down where it passes a limit between Toppra's grid
    points: within every limit there. Returns a :class:`~armlab.planning.timing.Fastest`: ``.motion`` (what
    :func:`simulate` takes; its run is checked against these limits too), ``.duration`` (s), ``.active`` (the
    constraint active along the path) and ṡ against its limit curve."""
    return time_optimal(arm, path, velocity, acceleration, effort, drives, motor_speed, motor_torque, grid,
                        gravity=gravity, payload=payload)


def plan_path(arm: Arm, q0: ArrayLike, qf: ArrayLike, scene: Scene | str | Path | None = None,
              clearance: float = 0.0, seed: int = 0, budget: float = 5.0, velocity: float | ArrayLike | None = None,
              acceleration: float | ArrayLike | None = None, effort: float | ArrayLike | None = None,
              drives: DriveTrain | None = None, grid: int = DEFAULT_GRID) -> Plan:
    """A motion from ``q0`` to ``qf`` (rad, m) that misses ``scene``'s obstacles (a :class:`Scene` or a scene file)
    and the arm itself by ``clearance`` (m) at every point, as fast as the limits allow (MATLAB's
    ``manipulatorRRT`` then ``contopptraj``; :mod:`armlab.planning.planner`): RRT-Connect (seeded by ``seed``,
    within ``budget`` s), edges certified free in batches, shortcut, smoothed, confirmed by Drake's query, timed by
    :func:`fastest` with the limits given (the arm file's otherwise). A :class:`~armlab.planning.planner.Plan`:
    ``.motion`` (what :func:`simulate` takes), ``.min_clearance`` (m), ``.length``, ``.planning_time``,
    ``.duration`` (s). One-line ``ValueError`` for a start or goal outside the limits or not clear;
    :class:`~armlab.planning.planner.NoPathError` (a ``ValueError``) when the budget runs out."""
    return plan_around(arm, q0, qf, as_scene(scene), clearance, seed, budget, velocity=velocity,
                       acceleration=acceleration, effort=effort, drives=drives, grid=grid)


def paper_motion(arm: Arm, path: str | None = None, tf: float | None = None) -> Motion:
    """The motion of the arm's paper (what ``armlab simulate ARM`` runs without motion options)."""
    return motion_of_paper(arm, path, tf)


def read_segments(arm: Arm, path: str | Path, payload: float = 0.0, gravity: str | ArrayLike | None = None) -> Motion:
    """The motion in a segments file (JSON; ``armlab simulate --help`` documents the format); its ``"fastest"``
    segments timed with the ``payload`` (kg) and ``gravity`` the run will carry (as :func:`simulate` takes them)."""
    return read(arm, path, payload, gravity)


def simulate(
    arm: Arm,
    motion: Motion,
    payload: float = 0.0,
    gravity: str | ArrayLike | None = None,
    mode: str = "controller",
    kp: float | ArrayLike | None = None,
    kd: float | ArrayLike | None = None,
    ki: float | ArrayLike = 0.0,
    log_period: float | None = None,
    accuracy: float | None = None,
    divergence_tolerance: float | None = None,
    scene: Scene | str | Path | None = None,
    *,
    controller: str = "computed-torque",
    rate: float | None = None,
    bandwidth: float | None = None,
    saturate: bool = False,
    anti_windup: bool = True,
    encoder: int | None = None,
    encoder_side: str = "motor",
    velocity: str = "state",
    velocity_cutoff: float | None = None,
    noise: float = 0.0,
    seed: int = 0,
    delay: int = 0,
    electrics: bool = False,
    current_rate: float | None = None,
    current_bandwidth: float = DEFAULT_CURRENT_BANDWIDTH,
    elastic: bool = False,
) -> Run:
    """Simulate ``arm`` following ``motion`` through paper 000's Fig. 6 as a Drake diagram; a :class:`Run`.

    ``payload``: point mass at the tool (kg); ``gravity``: ``None`` (the arm's), ``"off"``, ``"-z"`` …, or
    (gx, gy, gz) m/s²; ``mode``: ``"controller"`` (computed torque, PD gains ``kp`` 1/s², ``kd`` 1/s, ``ki``
    1/s³; defaults 100, 20, 0) or ``"inverse_dynamics"`` (open loop); ``log_period`` (s, default 0.001);
    ``accuracy``: the integrator's target accuracy (default 1e-6); ``divergence_tolerance``: the tracking
    error (rad or m, default 0.01) past which the run counts as diverged; ``scene``: obstacles (a scene file or
    :class:`~armlab.collision.scene.Scene`) the run is checked against, beside the arm itself (collisions in
    ``run.collisions`` and ``summary.json``). The arm needs mass data.

    The servo loop (default: paper 000's ideal loop, continuous computed torque on the exact state): ``controller``
    ``"computed-torque"``, ``"pid"`` or ``"pd+feedforward"``; ``rate`` (Hz; ``None``: continuous); ``bandwidth`` (Hz:
    the gains by the tuning rule from each joint's inertia, instead of ``kp``, ``kd``, ``ki``); ``saturate`` (at each
    joint's effort limit) with ``anti_windup``; a sampled controller's sensors: ``encoder`` counts per revolution on
    the ``encoder_side`` (``"motor"`` or ``"joint"``), ``velocity`` ``"state"`` or ``"difference"`` (with its low-pass
    ``velocity_cutoff``, Hz), position ``noise`` (rad or m, standard deviation) with its ``seed``, a ``delay`` of k
    samples; ``electrics``: each motor's current loop and winding from the drive train (R, L, k_t, bus voltage …),
    the loop at ``current_rate`` (Hz; ``None``: continuous) with bandwidth ``current_bandwidth`` (Hz); ``elastic``:
    each joint a two-mass model with the drive train's gearbox stiffness (``stiffness`` column). What they mean:
    :mod:`armlab.diagrams.servo`. A servo run's summary has a ``servo`` section (the design, saturation time, peak
    current, energy balance) and :meth:`Run.frequency_response` its linearised loop.

    The keywords are checked once, as a :class:`~armlab.diagrams.simulate.SimulationOptions` (what the inner layers
    take).
    """
    if not isinstance(arm, Arm):
        raise TypeError(f"arm: expected an Arm (armlab.load(...)), got {type(arm).__name__}")
    if not isinstance(motion, Motion):
        raise TypeError(f"motion: expected a Motion (armlab.quintic(...), armlab.through(...), …), got "
                        f"{type(motion).__name__}")
    options = SimulationOptions(  # None: the option's default
        PlantOptions(gravity=gravity, payload=payload, ideal_drives=True), mode=mode,
        kp=DEFAULT_KP if kp is None else kp, kd=DEFAULT_KD if kd is None else kd, ki=ki,
        log_period=DEFAULT_LOG_PERIOD if log_period is None else log_period,
        accuracy=DEFAULT_ACCURACY if accuracy is None else accuracy,
        divergence_tolerance=DIVERGENCE_TOLERANCE if divergence_tolerance is None else divergence_tolerance,
        controller=controller, rate=rate, bandwidth=bandwidth, saturate=saturate, anti_windup=anti_windup,
        encoder=encoder, encoder_side=encoder_side, velocity=velocity, velocity_cutoff=velocity_cutoff, noise=noise,
        seed=seed, delay=delay, electrics=electrics, current_rate=current_rate, current_bandwidth=current_bandwidth,
        elastic=elastic)
    scene = as_scene(scene)  # a bad scene file is an error before the run
    return Run(run_diagram(arm, motion, options), options.divergence_tolerance, scene, options)


def size_drives(
    arm: Arm,
    cycle: DutyCycle | Motion | str | Path | None = None,
    payloads: float | Sequence[float] | LoadCase | Sequence[LoadCase] = 0.0,
    motors: Motors | str | Path | None = None,
    gearboxes: Gearboxes | str | Path | None = None,
    safety_factor: float = 1.0,
    rank: str = "mass",
    mass_iteration: bool = True,
    rate: float = DEFAULT_RATE,
    conditions: Conditions | None = None,
) -> Sizing:
    """The motor and gearbox of every joint of ``arm`` for a duty cycle and every load case; a
    :class:`~armlab.sizing.sizing.Sizing` (``.joints[k].chosen``, ``.feasible``, ``.drive_mass``, ``.iterations``).

    ``cycle``: a :class:`~armlab.sizing.duty.DutyCycle`, a duty-cycle JSON file, a :class:`Motion` (repeated,
    carrying the payload throughout) or ``None`` (the arm's paper motion); ``payloads``: point masses (kg) or
    :class:`~armlab.sizing.duty.LoadCase` objects, each a load case; ``motors``, ``gearboxes``: catalogues (CSV
    files or read ones; ``None``: armlab's example catalogues, illustrative values); ``safety_factor`` ≥ 1 on every
    torque; ``rank``: ``"mass"`` (lightest first), ``"margin"`` or ``"inertia"`` (smallest inertia ratio);
    ``mass_iteration``: put the chosen drives' masses on the links and repeat until the choice holds; ``rate``:
    samples per second of motion; ``conditions``: the ambient temperature, bus voltage, brake factor and required
    gearbox life (:class:`~armlab.sizing.checks.Conditions`; default its defaults). See :mod:`armlab.sizing.select`
    and :mod:`armlab.sizing.checks` for what feasible means.
    """
    if cycle is None:
        cycle = motion_of_paper(arm)
    if isinstance(cycle, str | Path):
        cycle = read_duty_cycle(arm, cycle)
    if isinstance(cycle, Motion):
        cycle = DutyCycle.of(cycle)
    motors = motors if isinstance(motors, Motors) else read_motors(motors)
    gearboxes = gearboxes if isinstance(gearboxes, Gearboxes) else read_gearboxes(gearboxes)
    return size(arm, cycle, load_cases_of(payloads), motors, gearboxes, safety_factor, rank, mass_iteration, rate,
                conditions=conditions)


def draw(arm: Arm, q: ArrayLike | None = None, path: str | Path | None = None) -> Figure:
    """The arm's kinematic scheme at joint values ``q`` ``(n,)`` (rad, m; default: the pose ``armlab draw`` shows)
    as a matplotlib figure (a notebook shows it); written to ``path`` (``.png``, ``.svg``, ``.pdf``) only if given.
    """
    # lazy: the drawing needs matplotlib, which armlab.load does not
    from armlab.presentation.draw import default_q, scheme_figure, write_figure

    fig = scheme_figure(arm, default_q(arm) if q is None else q)
    if path is not None:
        write_figure(fig, path)
    return fig
