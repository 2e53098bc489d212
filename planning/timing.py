"""The fastest timing of a path within joint velocity, acceleration and torque limits: Drake's ``Toppra``.

Given a joint path q(s) (the path of a tool line or arc, :mod:`armlab.kinematics.cartesian`, or any
:class:`~armlab.kinematics.quintic.Motion` taken as a path in its own time) and limits per joint, Drake's
``Toppra`` (time-optimal path parameterisation by reachability analysis, Pham & Pham 2018) finds s(t) with the
shortest duration such that, at every grid point of s,

* |q'(s) ṡ| ≤ v_max (velocity),
* |q'(s) s̈ + q''(s) ṡ²| ≤ a_max (acceleration),
* τ_min + F ≤ M(q)(q' s̈ + q'' ṡ²) + C(q, q'ṡ) q'ṡ − τ_g(q) ≤ τ_max − F (torque, Drake's inverse dynamics of
  the arm's plant, :func:`armlab.models.plant.make_plant`, with the drive train's reflected inertia G²·J_m in
  M; F = B·|q̇|max + T_c, the most the drive train's friction takes of the limit: :func:`fastest`),

from rest to rest. The limits default to the arm's file (URDF ``<limit velocity effort>``; a URDF has no
acceleration limit, so none unless given); a :class:`~armlab.drives.train.DriveTrain` with motor-side limits
turns them into joint-side ones (speed ω_m,max/|G|, torque τ_m,max·|G|·η).

Each constraint, written a_i(s) s̈ + b_i(s) ṡ² + c_i(s) ∈ [lo_i, hi_i], bounds ṡ² at every s: the largest ṡ
for which some s̈ is feasible is the *maximum velocity curve* (:func:`limit_curve`, a two-variable linear
program per grid point solved by its vertices). :class:`Fastest` reports the minimum duration, ṡ along s
against that curve, and the constraint active at each grid point.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.quintic import Motion, TrajectorySegment, to_trajectory
from armlab.kinematics.rnea import inverse_dynamics
from armlab.limits import check_positive, per_joint
from armlab.models.plant import PlantOptions, make_plant

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.trajectories import PiecewisePolynomial, Trajectory

    from armlab.drives.train import DriveTrain
    from armlab.models.arm import Arm

__all__ = ["ACTIVE_TOL", "DEFAULT_GRID", "Fastest", "Limits", "fastest", "limit_curve"]

#: Grid points of s by default.
DEFAULT_GRID = 500
#: Toppra's constraint relaxations tried in turn (its LP at a knot can be numerically challenging where a joint's
#: path velocity crosses zero; Drake's message advises a slight relaxation).
RELAXATIONS = (0.0, 1e-8, 1e-6)
#: A constraint is active where its slack is at most this fraction of its range.
ACTIVE_TOL = 2e-3


@dataclass(frozen=True)
class Limits:
    """Symmetric joint limits ``(n,)`` each, ``inf`` where a joint has none: velocity (rad/s or m/s), acceleration
    (rad/s² or m/s²), effort (N·m or N)."""

    velocity: NDArray[np.float64]
    acceleration: NDArray[np.float64]
    effort: NDArray[np.float64]


def _limit(value: float | ArrayLike | None, default: NDArray[np.float64], name: str, unit: str) -> NDArray:
    if value is None:
        return default
    a = per_joint(value, default.size, f"{name} limits")
    for v in a:
        if not np.isinf(v):
            check_positive(float(v), f"{name} limit", unit, f"a {name} limit must be a positive number (or inf)")
    return a.astype(float)


def arm_limits(arm: Arm, velocity: float | ArrayLike | None = None, acceleration: float | ArrayLike | None = None,
               effort: float | ArrayLike | None = None, drives: DriveTrain | None = None,
               motor_speed: float | ArrayLike | None = None, motor_torque: float | ArrayLike | None = None) -> Limits:
    """The limits :func:`fastest` enforces: the arm file's velocity and effort (no acceleration limit), each
    overridden where given; with ``drives`` and motor-side ``motor_speed`` (rad/s) / ``motor_torque`` (N·m) the
    tighter of those and the joint-side ones (ω_m,max/|G|, τ_m,max·|G|·η)."""
    n = arm.n
    velocity_file = np.array([np.inf if lim.velocity is None else lim.velocity for lim in arm.limits])
    effort_file = np.array([np.inf if lim.effort is None else lim.effort for lim in arm.limits])
    v = _limit(velocity, velocity_file, "velocity", "rad/s")
    a = _limit(acceleration, np.full(n, np.inf), "acceleration", "rad/s²")
    e = _limit(effort, effort_file, "effort", "N·m")
    if (motor_speed is not None or motor_torque is not None) and drives is None:
        raise ValueError("motor-side limits need the drive train (its gear ratios and efficiencies)")
    if drives is not None:
        if drives.n != n:
            raise ValueError(f"the drive train has {drives.n} joints; {arm.name} has {n}")
        g = np.abs(drives.gear_ratio)
        v = np.minimum(v, _limit(motor_speed, np.full(n, np.inf), "motor speed", "rad/s") / g)
        e = np.minimum(e, _limit(motor_torque, np.full(n, np.inf), "motor torque", "N·m") * g * drives.efficiency)
    return Limits(v, a, e)


def _path_of(motion_or_path: Motion | Trajectory) -> Trajectory:
    """The joint path q(s) to time: a tool path's own (a path-parameterised segment), or the motion in its time."""
    from pydrake.trajectories import PathParameterizedTrajectory

    if isinstance(motion_or_path, Motion):
        segments = motion_or_path.segments
        if len(segments) == 1 and isinstance(segments[0], TrajectorySegment) and isinstance(
                segments[0].trajectory, PathParameterizedTrajectory):
            return segments[0].trajectory.path()
        return to_trajectory(motion_or_path)
    return motion_or_path


def _derivative(trajectory: Trajectory, points: NDArray, order: int) -> NDArray[np.float64]:
    """The ``order``-th derivative of ``trajectory`` (a column of ``r`` values) at ``points`` ``(m,)``: ``(m, r)``.
    Point by point: ``MakeDerivative`` would copy every piece first (4× longer for a path of 1000 pieces)."""
    return np.array([trajectory.EvalDerivative(float(t), order)[:, 0] for t in points])


def _constraints(arm: Arm, path: Trajectory, s: NDArray, gravity: str | ArrayLike | None,
                 payload: float) -> tuple[NDArray, NDArray, NDArray, list[str]]:
    """Every constraint's row a s̈ + b ṡ² + c at grid points ``s`` ``(m,)``: a, b, c ``(m, K)`` and a name each —
    velocity (b ṡ² ≤ v², a = 0), acceleration and torque rows, n each; their bounds: :func:`_bounds`."""
    q = np.asarray(path.vector_values(s.tolist())).T
    d1, d2 = _derivative(path, s, 1), _derivative(path, s, 2)
    zero = np.zeros_like(q)
    g_tau = inverse_dynamics(arm, q, zero, zero, gravity, payload)  # −τ_g: the torque holding the arm still
    # M q' and M q'' + C(q, q') q' in one batch of 2m rows
    m_tau, b_tau = np.split(inverse_dynamics(arm, np.concatenate([q, q]), np.concatenate([zero, d1]),
                                             np.concatenate([d1, d2]), "off", payload), 2)
    names = [*(f"{j} velocity" for j in arm.joint_names), *(f"{j} acceleration" for j in arm.joint_names),
             *(f"{j} torque" for j in arm.joint_names)]
    a = np.concatenate([zero, d1, m_tau], axis=1)
    b = np.concatenate([d1**2, d2, b_tau], axis=1)
    c = np.concatenate([zero, zero, g_tau], axis=1)
    return a, b, c, names


def _bounds(limits: Limits) -> tuple[NDArray, NDArray]:
    """lo, hi ``(K,)`` of :func:`_constraints`' rows within ``limits``."""
    return (np.concatenate([np.full(limits.velocity.size, -np.inf), -limits.acceleration, -limits.effort]),
            np.concatenate([limits.velocity**2, limits.acceleration, limits.effort]))


def limit_curve(a: NDArray, b: NDArray, c: NDArray, lo: NDArray, hi: NDArray) -> NDArray[np.float64]:
    """The largest ṡ at each grid point for which some s̈ satisfies every constraint ``lo ≤ a s̈ + b ṡ² + c ≤ hi``
    (``a``, ``b``, ``c`` ``(m, K)``, ``lo``, ``hi`` ``(K,)``); ``inf`` where nothing bounds ṡ, NaN where even
    ṡ = 0 is infeasible.

    With x = ṡ², a row with a ≠ 0 bounds s̈ between two lines in x, L_i(x) ≤ s̈ ≤ U_i(x); some s̈ exists iff
    L_i(x) ≤ U_j(x) for every pair i, j (intervals on a line meet iff they meet pairwise), each a half-line of
    x; a row with a = 0 bounds x itself. The curve is √ of the least upper bound, where it is above the lower.
    """
    m = a.shape[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        moving = np.abs(a) > 1e-12 * np.maximum(1.0, np.abs(b))
        # rows on s̈: L = (lo − c − b x)/a, U = (hi − c − b x)/a, swapped where a < 0: L = α + β x, U = γ + δ x
        # (paired only among the columns that bound s̈ somewhere: never the velocity rows)
        on = moving.any(axis=0)
        moving_s, a_s, b_s, c_s = moving[:, on], a[:, on], b[:, on], c[:, on]
        scale = np.where(moving_s, a_s, 1.0)
        low_const, high_const = (lo[on] - c_s) / scale, (hi[on] - c_s) / scale
        slope = -b_s / scale
        negative = a_s < 0
        alpha = np.where(negative, high_const, low_const)
        gamma = np.where(negative, low_const, high_const)
        # each pair (i lower, j upper): (α_i − γ_j) + (β_i − δ_j) x ≤ 0, with β = δ = slope
        A0 = alpha[:, :, None] - gamma[:, None, :]
        A1 = slope[:, :, None] - slope[:, None, :]
        pair = moving_s[:, :, None] & moving_s[:, None, :] & np.isfinite(A0)
        bound = -A0 / np.where(A1 == 0, 1.0, A1)
        upper = np.where(pair & (A1 > 0), bound, np.inf).reshape(m, -1).min(axis=1)
        lower = np.where(pair & (A1 < 0), bound, -np.inf).reshape(m, -1).max(axis=1)
        never = (pair & (A1 == 0) & (A0 > 0)).reshape(m, -1).any(axis=1)
        # rows with a = 0: lo − c ≤ b x ≤ hi − c
        fixed = ~moving & (b != 0)
        bx_hi, bx_lo = np.where(b > 0, (hi - c) / b, (lo - c) / b), np.where(b > 0, (lo - c) / b, (hi - c) / b)
        upper = np.minimum(upper, np.where(fixed & ~np.isnan(bx_hi), bx_hi, np.inf).min(axis=1))
        lower = np.maximum(lower, np.where(fixed & ~np.isnan(bx_lo), bx_lo, -np.inf).max(axis=1))
        never |= (~moving & (b == 0) & ((c > hi) | (c < lo))).any(axis=1)
    infeasible = never | (upper < np.maximum(lower, 0.0)) | (upper < 0)
    return np.where(infeasible, np.nan, np.sqrt(np.maximum(upper, 0.0)))


@dataclass(frozen=True)
class Fastest:
    """The time-optimal timing of a path: ``motion`` (q(s(t)), one trajectory segment), ``duration`` (s), at the
    grid points ``s`` ``(m,)`` the path rate ``sd`` (ṡ, 1/s), its limit curve ``limit`` (:func:`limit_curve`), and
    the constraint active there (``active``, its name, or ``""``), the joints' ``limits``, and the ``friction``
    ``(n,)`` (N·m or N) kept free of each effort limit (:func:`fastest`; zero without friction): Toppra held the
    joint torque of the rigid arm and its reflected inertia within ±(effort − friction)."""

    motion: Motion
    duration: float
    s: NDArray[np.float64]
    sd: NDArray[np.float64]
    limit: NDArray[np.float64]
    active: tuple[str, ...]
    limits: Limits
    friction: NDArray[np.float64]

    @property
    def active_fraction(self) -> float:
        """The fraction of the grid where some constraint is active (bang–bang: most of it)."""
        return float(np.mean([bool(name) for name in self.active]))

    @property
    def most_active(self) -> str | None:
        """The constraint active at most grid points (its name), ``None`` where none is."""
        named = [name for name in self.active if name]
        return max(set(named), key=named.count) if named else None

    def rate_figure(self, title: str, along: str = "the path") -> Any:
        """ṡ along s against its limit curve, a matplotlib figure headed ``title`` (the caller saves and closes it);
        ``along``: what s is the fraction of, for the axis label."""
        # lazy: matplotlib, only for a figure
        from armlab.presentation.figures import new_figure

        fig, ax = new_figure(title, size=(7, 4.5))
        ax.plot(self.s, self.limit, "-", color="0.6", lw=3, label="limit curve (largest feasible ṡ)")
        ax.plot(self.s, self.sd, "k-", lw=1.2, label="time-optimal ṡ(s)")
        ax.set_xlabel(f"s, fraction of {along} [1]")
        ax.set_ylabel("ṡ [1/s]")
        finite = self.limit[np.isfinite(self.limit)]
        ax.set_ylim(0.0, 1.15 * max(float(finite.max()) if finite.size else 0.0, float(self.sd.max())))
        ax.legend(loc="lower center", fontsize=8)
        return fig


def _infeasible(arm: Arm, s: NDArray, c: NDArray, lo: NDArray, hi: NDArray, names: list[str],
                friction: NDArray) -> ValueError:
    """The one-line error for limits no timing meets: where even standing still on the path breaks one."""
    still = (c > hi + 1e-12) | (c < lo - 1e-12)
    where = np.argwhere(still)
    if where.size:
        i, k = where[0]
        limit = hi[k] if c[i, k] > hi[k] else lo[k]
        unit = "N·m" if arm.revolute[k % arm.n] else "N"
        kept = friction[k - 2 * arm.n] if k >= 2 * arm.n else 0.0  # the torque rows are the last n
        less = f" (the effort limit less its friction {kept:.6g} {unit})" if kept > 0 else ""
        return ValueError(f"the limits cannot be met: {names[k]} needs {c[i, k]:.6g} {unit} against gravity at "
                          f"s = {s[i]:.4g} of the path, beyond its limit {limit:.6g} {unit}{less}")
    return ValueError(f"the limits cannot be met anywhere on the path by Toppra ({arm.name}); raise the acceleration "
                      "or effort limits")


def _toppra(path: Trajectory, plant: MultibodyPlant, s: NDArray, limits: Limits) -> PiecewisePolynomial | None:
    """Drake's ``Toppra`` on the grid ``s`` within ``limits`` (s(t), or ``None`` where no timing meets them)."""
    from pydrake.multibody.optimization import Toppra, ToppraDiscretization

    drake_log = logging.getLogger("drake")
    level = drake_log.level
    drake_log.setLevel(logging.CRITICAL)  # an infeasible problem is our one-line error, not Drake's log line
    try:
        for relaxation in RELAXATIONS:  # Drake's advice where its LP at a knot is numerically challenging
            toppra = Toppra(path, plant, s)
            toppra.set_constraint_relaxation(relaxation)
            if np.any(np.isfinite(limits.velocity)):
                toppra.AddJointVelocityLimit(-limits.velocity, limits.velocity)
            if np.any(np.isfinite(limits.acceleration)):
                toppra.AddJointAccelerationLimit(-limits.acceleration, limits.acceleration,
                                                 ToppraDiscretization.kInterpolation)
            if np.any(np.isfinite(limits.effort)):
                toppra.AddJointTorqueLimit(-limits.effort, limits.effort, ToppraDiscretization.kInterpolation)
            scaling = toppra.SolvePathParameterization()
            if scaling is not None:
                return scaling
    finally:
        drake_log.setLevel(level)
    return None


def _rates(scaling: PiecewisePolynomial, s: NDArray) -> tuple[NDArray, NDArray]:
    """ṡ and s̈ at the grid points ``s`` ``(m,)`` of Toppra's time scaling s(t) (interpolated from its knots)."""
    times = np.asarray(scaling.get_segment_times())
    s_at = np.asarray(scaling.vector_values(times.tolist()))[0]
    return (np.interp(s, s_at, _derivative(scaling, times, 1)[:, 0]),
            np.interp(s, s_at, _derivative(scaling, times, 2)[:, 0]))


def fastest(arm: Arm, path: Motion | Trajectory, velocity: float | ArrayLike | None = None,
            acceleration: float | ArrayLike | None = None, effort: float | ArrayLike | None = None,
            drives: DriveTrain | None = None, motor_speed: float | ArrayLike | None = None,
            motor_torque: float | ArrayLike | None = None, grid: int = DEFAULT_GRID,
            gravity: str | ArrayLike | None = None, payload: float = 0.0) -> Fastest:
    """The fastest rest-to-rest timing of ``path`` (a motion, taken as a path; or a Drake ``Trajectory`` q(s))
    within the limits (:func:`arm_limits`), by Drake's ``Toppra`` on ``grid`` uniform points of s.

    ``drives``: the drive train (``None``: the arm's own, ``arm.drives``): its reflected inertia G²·J_m is in the
    torque constraint, its motor-side limits are the joints' (:func:`arm_limits`), and its friction is kept free
    of each effort limit: Toppra's constraints are quadratic in ṡ, friction B·q̇ + T_c·tanh(q̇/v_s) is not, so
    each joint's effort limit is lowered by the most it can take, B·|q̇|max + T_c (|q̇|max: the velocity limit,
    or where there is none, the fastest rate of the timing without friction, which no slower timing exceeds).
    ``gravity``, ``payload``: as the plant's (:class:`~armlab.models.plant.PlantOptions`). ``ValueError`` for a
    bad limit, or limits no timing meets (naming the joint, the point and the two numbers).
    """
    from pydrake.trajectories import PathParameterizedTrajectory

    if not isinstance(grid, int) or isinstance(grid, bool) or grid < 3:
        raise ValueError(f"grid = {grid!r} is not allowed: a whole number ≥ 3")
    train = arm.drives if drives is None else drives
    limits = arm_limits(arm, velocity, acceleration, effort, train, motor_speed, motor_torque)
    if np.all(np.isinf(np.concatenate([limits.velocity, limits.acceleration, limits.effort]))):
        raise ValueError(f"{arm.name} has no velocity, acceleration or effort limit to time the path by: give some")
    # the rigid arm with the train's reflected inertia: what Toppra's torque constraint holds (friction: below)
    rigid = arm.with_drives(None if train is None else replace(train, viscous=np.zeros(arm.n),
                                                                coulomb=np.zeros(arm.n), coulomb_negative=None))
    q_path = _path_of(path)
    s = np.linspace(q_path.start_time(), q_path.end_time(), grid)
    plant = make_plant(rigid, PlantOptions(gravity=gravity, payload=payload, ideal_drives=True))
    a, b, c, names = _constraints(rigid, q_path, s, gravity, payload)
    friction = np.zeros(arm.n)
    if train is not None and np.any((train.viscous > 0) | (train.coulomb_max > 0)):
        rate = limits.velocity
        if np.any(np.isinf(rate) & (train.viscous > 0)):
            unbounded = _toppra(q_path, plant, s, limits)
            if unbounded is None:
                raise _infeasible(arm, s, c, *_bounds(limits), names, friction)
            # the fastest rate |q'(s)|·ṡ of the timing without friction (q': the acceleration rows' coefficient of s̈)
            rate = np.where(np.isfinite(rate), rate,
                            np.abs(a[:, arm.n:2 * arm.n] * _rates(unbounded, s)[0][:, None]).max(axis=0))
        friction = np.where(train.viscous > 0, train.viscous * rate, 0.0) + train.coulomb_max
        if np.any(friction >= limits.effort):
            k = int(np.argmax(friction >= limits.effort))
            unit = "N·m" if arm.revolute[k] else "N"
            raise ValueError(f"the limits cannot be met: {arm.joint_names[k]}'s friction at {rate[k]:.6g} "
                             f"{'rad/s' if arm.revolute[k] else 'm/s'} ({friction[k]:.6g} {unit}) takes its whole "
                             f"effort limit {limits.effort[k]:.6g} {unit}")
    enforced = replace(limits, effort=limits.effort - friction)
    lo, hi = _bounds(enforced)
    scaling = _toppra(q_path, plant, s, enforced)
    if scaling is None:
        raise _infeasible(arm, s, c, lo, hi, names, friction)
    motion = Motion((TrajectorySegment(PathParameterizedTrajectory(q_path, scaling), "time-optimal"),),
                    f"time-optimal timing (Toppra) of {path.description if isinstance(path, Motion) else 'a path'}")
    sd, sdd = _rates(scaling, s)
    value = a * sdd[:, None] + b * (sd**2)[:, None] + c
    span = np.where(np.isfinite(hi - lo), hi - lo, np.where(np.isfinite(hi), np.abs(hi), 1.0))
    slack = np.minimum(hi - value, value - lo) / np.maximum(span, 1e-300)
    tight = np.argmin(np.where(np.isfinite(slack), slack, np.inf), axis=1)
    active = tuple(names[k] if slack[i, k] <= ACTIVE_TOL else "" for i, k in enumerate(tight))
    return Fastest(motion, float(scaling.end_time()), s, sd, limit_curve(a, b, c, lo, hi), active, limits, friction)
