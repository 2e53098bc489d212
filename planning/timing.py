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

Toppra holds its constraints at the grid points only (and not at the last one: its forward pass repeats the
constraint of the point before), and between them the path's q'(s), q''(s) and the dynamics move on: a 500-point
grid lets a torque pass its limit by 5 % between two points, an acceleration by 50 % where q''(s) changes fast.
So :func:`fastest` keeps its limits itself. Toppra gets them less :data:`MARGIN`; the timed motion is then checked
densely (:func:`_dense_check`: at a simulation's log samples and :data:`CHECK_POINTS` times per grid interval,
every velocity, acceleration and torque limit, the drive train's friction and the payload included), and where a
sample passes a limit the grid intervals there are slowed down (:func:`_slow_down`): within each, ṡ² stays
linear in s and s̈ constant, as Toppra's, and the constraint rows are held, less the margin, at points every
1/J of the interval (J from the overshoot, ≥ :data:`LIMITED_POINTS`), at the path's knots and where the check
found a limit passed; a backward pass finds the largest ṡ² each grid point may have, a forward pass the fastest
profile under Toppra's (the intervals it changes around them held at :data:`LIMITED_POINTS` points, less
:data:`RAMP_MARGIN`), and the check runs again where the timing changed, J doubled where a sample still passes,
until none does (at most :data:`ROUNDS` rounds, else a one-line ``ValueError``). The returned motion is within
every limit at every sample of the check, the final instant included; Toppra's grid, its time-optimal profile
elsewhere and the duration to ≤ 0.1 % are kept.
"""

from __future__ import annotations

import base64
import html
import io
import logging
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import above, below, outside, tolerated
from armlab.kinematics.quintic import DEFAULT_LOG_PERIOD, Motion, TrajectorySegment, to_trajectory
from armlab.kinematics.rnea import inverse_dynamics
from armlab.limits import check_count, check_positive, check_range, per_joint
from armlab.models.plant import PlantOptions, make_plant

if TYPE_CHECKING:
    from collections.abc import Callable, Collection

    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.trajectories import PiecewisePolynomial, Trajectory

    from armlab.drives.train import DriveTrain
    from armlab.models.arm import Arm

__all__ = ["ACTIVE_TOL", "CHECK_MARGIN", "DEFAULT_GRID", "MARGIN", "MAX_TIMED_DURATION", "Fastest", "Limits", "fastest",
           "limit_curve"]

#: Grid points of s by default.
DEFAULT_GRID = 500
#: Toppra's constraint relaxations tried in turn (its LP at a knot can be numerically challenging where a joint's
#: path velocity crosses zero; Drake's message advises a slight relaxation).
RELAXATIONS = (0.0, 1e-8, 1e-6)
#: A constraint is active where its slack is at most this fraction of its range.
ACTIVE_TOL = 2e-3
#: The fraction of each limit the timing keeps free (of the range from what standing still needs to the limit):
#: Toppra's limits are the given ones less it, and a slowed-down interval holds its constraints less it at its
#: points, the room for the motion between them. Costs ≤ 0.1 % of the duration (≤ ACTIVE_TOL: still active).
MARGIN = 1e-3
#: The fraction of each limit the timed motion keeps free at every sample of the dense check (:func:`_beyond`): room
#: for what a run adds to the reference, a controller's feedback (4e-5 of the UR5 line's peak torque in the tests).
CHECK_MARGIN = MARGIN / 2
#: Times per grid interval (uniform in time) the dense check samples, beside the simulation's log samples.
CHECK_POINTS = 4
#: Points per grid interval at which a slowed-down interval holds its constraints, at least and at most.
LIMITED_POINTS = 8
#: The longest time-optimal timing (s): its check every :data:`~armlab.kinematics.quintic.DEFAULT_LOG_PERIOD` s
#: makes a million samples, as many as a simulation may log; a longer one (limits of 1e-5 rad/s) is refused before
#: the check would fill the memory.
MAX_TIMED_DURATION = 1000.0
MAX_LIMITED_POINTS = 128
#: The margin of an interval the slow-down changes outside the zone (its ramp into and out of a slowed interval):
#: half Toppra's, so that Toppra's profile, on its limits less :data:`MARGIN` at the grid points, meets it again
#: within a few intervals instead of being lowered along a whole arc.
RAMP_MARGIN = MARGIN / 2
#: Grid intervals on each side of one the slow-down changes whose rows are made with it (fewer, larger batches).
BLOCK = 96
#: Rounds of dense check and slow-down before :func:`fastest` gives up.
ROUNDS = 5


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
            check_range(v, f"{name} limit", key=f"{name.replace(' ', '_')}_limit")  # 1e-300: no timing, no end
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


def _constraints(arm: Arm, path: Trajectory, s: NDArray, gravity: str | ArrayLike | None, payload: float,
                 derivatives: tuple[Trajectory, Trajectory] | None = None) -> tuple[NDArray, NDArray, NDArray,
                                                                                   list[str]]:
    """Every constraint's row a s̈ + b ṡ² + c at grid points ``s`` ``(m,)``: a, b, c ``(m, K)`` and a name each —
    velocity (b ṡ² ≤ v², a = 0), acceleration and torque rows, n each; their bounds: :func:`_bounds`. q'(s) and
    q''(s) from ``derivatives`` (the path's derivative trajectories) if given, else point by point."""
    q = np.asarray(path.vector_values(s.tolist())).T
    if derivatives is None:
        d1, d2 = _derivative(path, s, 1), _derivative(path, s, 2)
    else:
        d1, d2 = (np.asarray(d.vector_values(s.tolist())).T for d in derivatives)
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
        never = (pair & (A1 == 0) & above(A0, 0.0)).reshape(m, -1).any(axis=1)
        # rows with a = 0: lo − c ≤ b x ≤ hi − c
        fixed = ~moving & (b != 0)
        bx_hi, bx_lo = np.where(b > 0, (hi - c) / b, (lo - c) / b), np.where(b > 0, (lo - c) / b, (hi - c) / b)
        upper = np.minimum(upper, np.where(fixed & ~np.isnan(bx_hi), bx_hi, np.inf).min(axis=1))
        lower = np.maximum(lower, np.where(fixed & ~np.isnan(bx_lo), bx_lo, -np.inf).max(axis=1))
        never |= (~moving & (b == 0) & outside(c, lo, hi)).any(axis=1)
    infeasible = never | below(upper, np.maximum(lower, 0.0))
    return np.where(infeasible, np.nan, np.sqrt(np.maximum(upper, 0.0)))


@dataclass(frozen=True)
class Fastest:
    """The time-optimal timing of a path: ``motion`` (q(s(t)), one trajectory segment), ``duration`` (s), at the
    grid points ``s`` ``(m,)`` the path rate ``sd`` (ṡ, 1/s), its limit curve ``limit`` (:func:`limit_curve`), and
    the constraint active there (``active``, its name, or ``""``), the joints' ``limits``, and the ``friction``
    ``(n,)`` (N·m or N) kept free of each effort limit (:func:`fastest`; zero without friction): Toppra held the
    joint torque of the rigid arm and its reflected inertia within ±(effort − friction). ``slowed``: the grid
    intervals the dense check slowed down (a limit passed between Toppra's grid points there; :func:`fastest`)."""

    motion: Motion
    duration: float
    s: NDArray[np.float64]
    sd: NDArray[np.float64]
    limit: NDArray[np.float64]
    active: tuple[str, ...]
    limits: Limits
    friction: NDArray[np.float64]
    slowed: int = 0

    def __repr__(self) -> str:
        slowed = f"; slowed on {self.slowed} grid interval(s)" if self.slowed else ""
        return (f"<Fastest: {self.duration:.6g} s; a limit active on {self.active_fraction:.0%} of the path, mostly "
                f"{self.most_active or 'none'}{slowed}>")

    def _repr_html_(self) -> str:
        """Jupyter's view: the duration and the active constraint, one row per joint with the limits the timing
        holds (rad/s, rad/s², N·m; m/s, m/s², N for a prismatic joint; — none) and the friction kept free, then ṡ
        against its limit curve (:meth:`rate_figure`) as an inline PNG."""

        # lazy: matplotlib, only when a notebook shows the timing
        import matplotlib.pyplot as plt

        def cell(v: float) -> str:
            return "—" if not np.isfinite(v) else f"{v:.4g}"

        rows = "".join(
            f"<tr><td>{k + 1}</td><td>{cell(v)}</td><td>{cell(a)}</td><td>{cell(e)}</td><td>{f:.4g}</td></tr>"
            for k, (v, a, e, f) in enumerate(zip(self.limits.velocity, self.limits.acceleration, self.limits.effort,
                                                 self.friction, strict=True)))
        fig = self.rate_figure("time-optimal path rate against its limit")
        buffer = io.BytesIO()
        fig.savefig(buffer, format="png", dpi=100)
        plt.close(fig)
        image = base64.b64encode(buffer.getvalue()).decode("ascii")
        return (f"<div><b>{html.escape(repr(self)[1:-1])}</b><table><tr><th>joint</th><th>velocity limit</th>"
                "<th>acceleration limit</th><th>effort limit</th><th>friction kept free</th></tr>"
                f'{rows}</table><img src="data:image/png;base64,{image}" alt="ṡ against its limit curve"></div>')

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
    still = outside(c, lo, hi)
    where = np.argwhere(still)
    if where.size:
        i, k = where[0]
        limit = hi[k] if above(c[i, k], hi[k]) else lo[k]
        unit = "N·m" if arm.revolute[k % arm.n] else "N"
        kept = friction[k - 2 * arm.n] if k >= 2 * arm.n else 0.0  # the torque rows are the last n
        less = f" (the effort limit less its friction {kept:.6g} {unit})" if kept > 0 else ""
        return ValueError(f"the limits cannot be met: {names[k]} needs {c[i, k]:.6g} {unit} against gravity at "
                          f"s = {s[i]:.4g} of the path, beyond its limit {limit:.6g} {unit}{less}")
    return ValueError(f"the limits cannot be met anywhere on the path by Toppra ({arm.name}); raise the velocity, "
                      "acceleration or effort limits")


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


def _tightened(limits: Limits) -> Limits:
    """``limits`` less :data:`MARGIN`: what Toppra is given."""
    return Limits(limits.velocity * (1 - MARGIN), limits.acceleration * (1 - MARGIN), limits.effort * (1 - MARGIN))


def _beyond(value: NDArray, limit: NDArray) -> NDArray[np.bool_]:
    """Where |``value``| passes ``limit`` less :data:`CHECK_MARGIN` (broadcast together; ``inf``: no limit), by the
    one boundary rule (:func:`armlab.bounds.above`)."""
    return np.asarray(above(np.abs(value), limit * (1 - CHECK_MARGIN)), dtype=bool)


@dataclass(frozen=True)
class _Timing:
    """A time scaling s(t) as Toppra makes it, ṡ² linear in s and s̈ constant between the grid points: ``s`` (the
    grid, ``(m,)``), ``knots`` (their times, s, ``(m,)``), ``sd`` (ṡ there, 1/s) and ``sdd`` (s̈ from each point on,
    the last interval's at the end, 1/s²), and the ``scaling`` itself."""

    scaling: PiecewisePolynomial
    s: NDArray[np.float64]
    knots: NDArray[np.float64]
    sd: NDArray[np.float64]
    sdd: NDArray[np.float64]

    @classmethod
    def of(cls, scaling: PiecewisePolynomial, s: NDArray) -> _Timing:
        """Toppra's time scaling ``scaling`` of the grid ``s``."""
        return cls(scaling, s, np.asarray(scaling.get_segment_times()), *_rates(scaling, s))

    @classmethod
    def from_rates(cls, s: NDArray, x: NDArray, start: float) -> _Timing:
        """The time scaling from t = ``start`` with ṡ² = ``x`` at the grid points ``s`` ``(m,)``: each interval takes
        2 Δs/(ṡ_i + ṡ_{i+1}); cubic Hermite pieces of s and ṡ, exactly these quadratics."""
        from pydrake.trajectories import PiecewisePolynomial

        sd = np.sqrt(np.maximum(x, 0.0))
        rate = sd[:-1] + sd[1:]
        if np.any(rate <= 0):
            i = int(np.argmax(rate <= 0))
            raise ValueError(f"the limits cannot be met: the timing stands still between s = {s[i]:.4g} and "
                             f"{s[i + 1]:.4g} of the path")
        knots = start + np.concatenate([[0.0], np.cumsum(2 * np.diff(s) / rate)])
        u = np.diff(x) / (2 * np.diff(s))
        scaling = PiecewisePolynomial.CubicHermite(knots.tolist(), [s.tolist()], [sd.tolist()])
        return cls(scaling, s, knots, sd, np.append(u, u[-1]))

    @cached_property
    def derivatives(self) -> tuple[PiecewisePolynomial, PiecewisePolynomial]:
        """ṡ(t) and s̈(t)."""
        return self.scaling.derivative(1), self.scaling.derivative(2)

    def times_of(self, points: NDArray) -> NDArray[np.float64]:
        """The times at which s reaches ``points`` ``(k,)`` (in [s_0, s_end]): each piece's quadratic's root."""
        s, sd, sdd = self.s, self.sd, self.sdd
        i = np.clip(np.searchsorted(s, points, side="right") - 1, 0, s.size - 2)
        ahead = points - s[i]
        # s_i + ṡ_i τ + s̈_i τ²/2 = point: τ = 2 (point − s_i)/(ṡ_i + √(ṡ_i² + 2 s̈_i (point − s_i))), no cancellation
        root = np.sqrt(np.maximum(sd[i] ** 2 + 2 * sdd[i] * ahead, 0.0))
        return self.knots[i] + np.where(ahead > 0, 2 * ahead / np.maximum(sd[i] + root, 1e-300), 0.0)


def _dense_check(arm: Arm, train: DriveTrain | None, path: _TimedPath, timing: _Timing,
                 points: dict[int, int] | None, limits: Limits) -> tuple[NDArray[np.float64], NDArray[np.float64], str]:
    """The timed motion q(s(t)) (``path`` by ``timing``) against ``limits`` at a simulation's log samples (every
    :data:`~armlab.kinematics.quintic.DEFAULT_LOG_PERIOD` s from 0, and the end), where it passes the path's own knots
    (where q‴(s) jumps: the torques' corners) and at times uniform in grid intervals: :data:`CHECK_POINTS` in each
    (``points`` ``None``) or ``points[i]`` in interval i (the ones a slow-down changed: the others' ṡ², s̈ and so
    their values there are the last check's): |q̇|, |q̈| and |τ| — the joint torques with the drive train ``train`` (its
    reflected inertia and friction), the path's gravity and payload, by
    :func:`~armlab.kinematics.rnea.inverse_dynamics` — each against its limit. q, q̇ = q' ṡ and q̈ = q' s̈ + q'' ṡ²
    from Drake's trajectories of s(t), q(s) and their derivatives (the numbers ``PathParameterizedTrajectory``
    gives, to the last bit).

    Returns per grid interval the largest |value|/limit − 1 of its samples that pass a limit (:func:`_beyond`),
    ``-inf`` where none does, ``(m − 1,)``; the path parameters s of those samples; and the worst sample as a
    phrase (``""`` when none passes).
    """
    knots = timing.knots
    start, end = float(knots[0]), float(knots[-1])
    if points is None:
        fill = [(knots[:-1, None] + np.diff(knots)[:, None] * np.arange(CHECK_POINTS) / CHECK_POINTS).ravel()]
    else:
        fill = [knots[i] + (knots[i + 1] - knots[i]) * np.arange(j) / j for i, j in points.items()]
    t = np.unique(np.concatenate([*fill, start + np.arange(0.0, end - start, DEFAULT_LOG_PERIOD), [end],
                                  timing.times_of(path.path_knots)]))
    times = t.tolist()
    s, sd, sdd = (np.asarray(f.vector_values(times))[0] for f in (timing.scaling, *timing.derivatives))
    along = s.tolist()
    q, d1, d2 = (np.asarray(f.vector_values(along)).T for f in (path.path, *path.derivatives))
    qd, qdd = d1 * sd[:, None], d1 * sdd[:, None] + d2 * (sd**2)[:, None]
    tau = inverse_dynamics(arm, q, qd, qdd, path.gravity, path.payload, drives=train)
    values = np.concatenate([qd, qdd, tau], axis=1)
    limit = np.concatenate([limits.velocity, limits.acceleration, limits.effort])
    beyond = _beyond(values, limit)
    out = np.full(knots.size - 1, -np.inf)
    if not beyond.any():
        return out, np.empty(0), ""
    with np.errstate(divide="ignore", invalid="ignore"):
        excess = np.where(beyond, np.abs(values) / limit - 1, -np.inf)
    np.maximum.at(out, np.clip(np.searchsorted(knots, t, side="right") - 1, 0, knots.size - 2), excess.max(axis=1))
    i, k = np.unravel_index(np.argmax(excess), excess.shape)
    joint, kind = int(k) % arm.n, ("velocity", "acceleration", "torque")[int(k) // arm.n]
    unit = {"velocity": "rad/s", "acceleration": "rad/s²", "torque": "N·m"}[kind] if arm.revolute[joint] else \
        {"velocity": "m/s", "acceleration": "m/s²", "torque": "N"}[kind]
    worst = (f"{arm.joint_names[joint]} {kind} {values[i, k]:.6g} {unit} against its limit {limit[k]:.6g} {unit} "
             f"at t = {t[i] - start:.4g} s")
    return out, s[beyond.any(axis=1)], worst


@dataclass(frozen=True)
class _Rows:
    """The constraint rows of grid intervals at points in them, in each interval's unknowns: ṡ² = X at its start
    and s̈ = u throughout (ṡ² = X + 2 u (s − s_i)). Each row, held within its bounds less a margin, bounds u
    between two lines in X, ``lower_p + lower_q X ≤ u ≤ upper_p + upper_q X`` (``(I, R)`` each; p = ∓inf where it
    bounds no side), or, at a point where ṡ does not change it, X alone: ``cap`` ``(I,)``, the least such bound."""

    lower_p: NDArray[np.float64]
    lower_q: NDArray[np.float64]
    upper_p: NDArray[np.float64]
    upper_q: NDArray[np.float64]
    cap: NDArray[np.float64]

    def row(self, i: int) -> tuple[NDArray, NDArray, NDArray, NDArray, float]:
        """Interval ``i``'s lines and cap."""
        return self.lower_p[i], self.lower_q[i], self.upper_p[i], self.upper_q[i], float(self.cap[i])


def _interval_rows(a: NDArray, b: NDArray, c: NDArray, theta: NDArray, delta: NDArray, lo: NDArray,
                   hi: NDArray, margin: float = MARGIN) -> _Rows:
    """:class:`_Rows` of ``I`` grid intervals of lengths ``delta`` ``(I,)`` from :func:`_constraints`' ``a``, ``b``,
    ``c`` ``(I, J, K)`` at their points ``theta`` ``(I, J)`` (fractions of each interval), within ``lo``, ``hi``
    ``(K,)`` (:func:`_bounds`; a padding point has a = b = c = 0).

    At s = s_i + θ Δ a row a s̈ + b ṡ² + c is (a + 2 Δ θ b) u + b X + c; its bounds are less ``margin`` of the
    range from c (what standing still needs; 0 for the kinematic rows) to each, so that X = u = 0 holds every row.
    """
    alpha = a + 2 * (delta[:, None] * theta)[:, :, None] * b
    with np.errstate(invalid="ignore"):
        high = np.where(np.isfinite(hi), hi - margin * (hi - np.maximum(c, 0.0)), np.inf) - c
        low = np.where(np.isfinite(lo), lo + margin * (np.minimum(c, 0.0) - lo), -np.inf) - c
    moving = np.abs(alpha) > 1e-12 * np.maximum(1.0, np.abs(b))
    scale = np.where(moving, alpha, 1.0)
    negative = moving & (alpha < 0)
    with np.errstate(invalid="ignore"):
        lower_p = np.where(moving, np.where(negative, high, low) / scale, -np.inf)
        upper_p = np.where(moving, np.where(negative, low, high) / scale, np.inf)
    slope = np.where(moving, -b / scale, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        caps = np.where(moving | (b == 0), np.inf, np.where(b > 0, high, low) / np.where(b == 0, 1.0, b))
    size = (a.shape[0], -1)
    return _Rows(lower_p.reshape(size), slope.reshape(size), upper_p.reshape(size), slope.reshape(size),
                 caps.reshape(size).min(axis=1))


def _largest_start(rows: tuple[NDArray, NDArray, NDArray, NDArray, float], end: float, cap: float,
                   delta: float) -> float:
    """The largest ṡ² X ≤ ``cap`` at a grid interval's start (of length ``delta``, its :class:`_Rows` ``rows``) from
    which some s̈ keeps every row and reaches ṡ² ∈ [0, ``end``] at its end: the root of the concave gap
    D(X) = min upper − max lower (D(0) ≥ 0: at rest every row holds), by Newton's steps from ``cap`` (exact on a
    piecewise-linear D in a few), bisection where round-off stops them."""
    lower_p, lower_q, upper_p, upper_q, most = rows
    lower_p, lower_q = np.append(lower_p, 0.0), np.append(lower_q, -0.5 / delta)
    upper_p, upper_q = np.append(upper_p, 0.5 * end / delta), np.append(upper_q, -0.5 / delta)
    x = max(0.0, min(cap, most))
    for _ in range(64):
        low, high = lower_p + lower_q * x, upper_p + upper_q * x
        i, j = int(np.argmax(low)), int(np.argmin(high))
        gap = high[j] - low[i]
        if gap >= -1e-12 * max(1.0, abs(high[j]), abs(low[i])):  # not a bound: Newton's stop at round-off of D
            return x
        slope = upper_q[j] - lower_q[i]
        if not slope < 0:  # D concave with D(0) ≥ 0 and D(x) < 0 decreases at x: round-off only
            break
        x = max(0.0, min(x - gap / slope, x * (1 - 1e-15)))
    lo, hi = 0.0, x
    for _ in range(80):
        middle = 0.5 * (lo + hi)
        feasible = np.min(upper_p + upper_q * middle) >= np.max(lower_p + lower_q * middle)  # not a bound: bisection
        lo, hi = (middle, hi) if feasible else (lo, middle)
    return lo


def _fastest_end(rows: tuple[NDArray, NDArray, NDArray, NDArray, float], start: float, end: float,
                 delta: float) -> float:
    """The largest ṡ² ≤ ``end`` at a grid interval's end (of length ``delta``, its :class:`_Rows` ``rows``) reached
    from ṡ² = ``start`` at its start keeping every row: the largest s̈ they and the end allow."""
    _, _, upper_p, upper_q, _ = rows
    u = min(float(np.min(upper_p + upper_q * start)), 0.5 * (end - start) / delta)
    return min(end, max(0.0, start + 2 * delta * u))


def _slow_down(x: NDArray, s: NDArray, zone: Collection[int],
               rows_of: Callable[[int], tuple[NDArray, NDArray, NDArray, NDArray, float]]) -> NDArray[np.float64]:
    """ṡ² at the grid points ``s`` ``(m,)``: the fastest profile under ``x`` (Toppra's, or the last round's) that
    holds the rows (``rows_of(i)``, :meth:`_Rows.row`) of every grid interval in the ``zone`` (where the dense check
    found a limit passed) and of every other interval it changes (the ramps into and out of the zone). A backward
    pass bounds ṡ² at each point by what can still slow down in time, a forward pass takes the largest s̈ each
    interval allows; an interval outside the zone that neither has to change stays as it was."""
    delta = np.diff(s)
    most = x.copy()
    for i in range(s.size - 2, -1, -1):
        if i in zone or most[i + 1] < x[i + 1]:
            most[i] = _largest_start(rows_of(i), most[i + 1], x[i], delta[i])
    out = x.copy()
    out[0] = min(x[0], most[0])
    for i in range(s.size - 1):
        if i in zone or out[i] < x[i] or most[i + 1] < x[i + 1]:
            out[i + 1] = _fastest_end(rows_of(i), out[i], most[i + 1], delta[i])
    return out


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
    within the limits (:func:`arm_limits`), by Drake's ``Toppra`` on ``grid`` uniform points of s, checked densely
    and slowed down where it passes a limit between them (see the module docstring): within every limit at every
    sample of the check, a simulation's log samples among them.

    ``drives``: the drive train (``None``: the arm's own, ``arm.drives``): its reflected inertia G²·J_m is in the
    torque constraint, its motor-side limits are the joints' (:func:`arm_limits`), and its friction is kept free
    of each effort limit: Toppra's constraints are quadratic in ṡ, friction B·q̇ + T_c·tanh(q̇/v_s) is not, so
    each joint's effort limit is lowered by the most it can take, B·|q̇|max + T_c (|q̇|max: the velocity limit,
    or where there is none, the fastest rate of the timing without friction, which no slower timing exceeds).
    ``gravity``, ``payload``: as the plant's (:class:`~armlab.models.plant.PlantOptions`). ``ValueError`` for a
    bad limit, or limits no timing meets (naming the joint, the point and the two numbers).
    """
    grid = check_count(grid, "grid")  # bounded: Toppra's work grows with it
    train = arm.drives if drives is None else drives
    limits = arm_limits(arm, velocity, acceleration, effort, train, motor_speed, motor_torque)
    if np.all(np.isinf(np.concatenate([limits.velocity, limits.acceleration, limits.effort]))):
        raise ValueError(f"{arm.name} has no velocity, acceleration or effort limit to time the path by: give "
                         "velocity=, acceleration= or effort= (armlab plan: --velocity, --acceleration, --effort), "
                         "motor_speed=/motor_torque= with drives (--motor-speed, --motor-torque)")
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
        whole = ~below(friction, limits.effort)  # the friction takes the whole effort limit (or more)
        if np.any(whole):
            k = int(np.argmax(whole))
            unit = "N·m" if arm.revolute[k] else "N"
            raise ValueError(f"the limits cannot be met: {arm.joint_names[k]}'s friction at {rate[k]:.6g} "
                             f"{'rad/s' if arm.revolute[k] else 'm/s'} ({friction[k]:.6g} {unit}) takes its whole "
                             f"effort limit {limits.effort[k]:.6g} {unit}")
    enforced = replace(limits, effort=limits.effort - friction)
    lo, hi = _bounds(enforced)
    given = _tightened(enforced)
    scaling = _toppra(q_path, plant, s, given)
    if scaling is None:  # standing still needs more than the limits less the margin somewhere: the slow-down keeps it
        given = enforced
        scaling = _toppra(q_path, plant, s, given)
    if scaling is None:
        raise _infeasible(arm, s, c, lo, hi, names, friction)
    took = scaling.end_time() - scaling.start_time()
    if above(took, MAX_TIMED_DURATION):
        raise ValueError(f"the time-optimal timing takes {took:.6g} s, more than the {MAX_TIMED_DURATION:g} s allowed "
                         "(checked, and simulated, every 1 ms): raise the velocity, acceleration or effort limits")
    timed = _TimedPath(rigid, q_path, s, a, b, c, lo, hi, names, friction, gravity, payload)
    segment, timing, slowed = timed.within(arm, train, limits, _Timing.of(scaling, s))
    motion = Motion((segment,), f"time-optimal timing (Toppra) of "
                                f"{path.description if isinstance(path, Motion) else 'a path'}")
    sd, sdd = timing.sd, timing.sdd
    value = a * sdd[:, None] + b * (sd**2)[:, None] + c
    low, high = _bounds(given)  # active: on the limits Toppra was given
    span = np.where(np.isfinite(high - low), high - low, np.where(np.isfinite(high), np.abs(high), 1.0))
    slack = np.minimum(high - value, value - low) / np.maximum(span, 1e-300)
    tight = np.argmin(np.where(np.isfinite(slack), slack, np.inf), axis=1)
    active = tuple(names[k] if tolerated(slack[i, k], ACTIVE_TOL) else "" for i, k in enumerate(tight))
    return Fastest(motion, float(segment.duration), s, sd, limit_curve(a, b, c, lo, hi), active, limits, friction,
                   slowed)


@dataclass(frozen=True)
class _TimedPath:
    """A path being timed, and what slowing its timing down needs: the rigid arm (with the train's reflected
    inertia), the path q(s), the grid ``s`` ``(m,)`` and :func:`_constraints`' rows there (``a``, ``b``, ``c``
    ``(m, K)``, ``names``), their bounds ``lo``, ``hi`` ``(K,)`` (:func:`_bounds`), the friction kept free of the
    effort limits ``(n,)`` (for messages), ``gravity`` and ``payload``."""

    rigid: Arm
    path: Trajectory
    s: NDArray[np.float64]
    a: NDArray[np.float64]
    b: NDArray[np.float64]
    c: NDArray[np.float64]
    lo: NDArray[np.float64]
    hi: NDArray[np.float64]
    names: list[str]
    friction: NDArray[np.float64]
    gravity: str | ArrayLike | None
    payload: float

    @cached_property
    def path_knots(self) -> NDArray[np.float64]:
        """The path's own knots inside it (where its pieces meet and q‴(s) jumps), s; none for another trajectory."""
        from pydrake.trajectories import PiecewisePolynomial

        if not isinstance(self.path, PiecewisePolynomial):
            return np.empty(0)
        return np.asarray(self.path.get_segment_times())[1:-1]

    @cached_property
    def derivatives(self) -> tuple[Trajectory, Trajectory]:
        """q'(s) and q''(s), for rows at many points (:func:`_constraints`)."""
        return self.path.MakeDerivative(1), self.path.MakeDerivative(2)

    def dense(self, theta: dict[int, NDArray],
              margin: float = MARGIN) -> dict[int, tuple[NDArray, NDArray, NDArray, NDArray, float]]:
        """The rows (:meth:`_Rows.row`) of the grid intervals ``theta`` (index → points inside, fractions of the
        interval) at those points, at its two ends and at the path's knots in it, held within their bounds less
        ``margin`` (:func:`_interval_rows`); a one-line ``ValueError`` (:func:`_infeasible`) where standing still
        there passes a limit."""
        s, order, knots = self.s, list(theta), self.path_knots
        inside = [np.unique(np.concatenate([theta[i], (knots[(knots > s[i]) & (knots < s[i + 1])] - s[i])
                                            / (s[i + 1] - s[i])])) for i in order]
        inner = np.concatenate([s[i] + (s[i + 1] - s[i]) * f for i, f in zip(order, inside, strict=True)])
        a, b, c, _ = _constraints(self.rigid, self.path, inner, self.gravity, self.payload, self.derivatives)
        if np.any(outside(c, self.lo, self.hi)):
            raise _infeasible(self.rigid, inner, c, self.lo, self.hi, self.names, self.friction)
        width = 2 + max(f.size for f in inside)
        rows = {key: np.zeros((len(order), width, self.a.shape[1])) for key in "abc"}
        where = np.zeros((len(order), width))
        k = 0
        for row, (i, f) in enumerate(zip(order, inside, strict=True)):
            for key, grid_rows, inner_rows in (("a", self.a, a), ("b", self.b, b), ("c", self.c, c)):
                rows[key][row, :f.size + 2] = np.concatenate([grid_rows[i:i + 1], inner_rows[k:k + f.size],
                                                              grid_rows[i + 1:i + 2]])
            where[row, :f.size + 2] = np.concatenate([[0.0], f, [1.0]])
            k += f.size
        held = _interval_rows(rows["a"], rows["b"], rows["c"], where, np.diff(s)[order], self.lo, self.hi, margin)
        return {i: held.row(row) for row, i in enumerate(order)}

    def within(self, arm: Arm, train: DriveTrain | None, limits: Limits,
               timing: _Timing) -> tuple[TrajectorySegment, _Timing, int]:
        """Toppra's ``timing`` of the path, slowed down where the dense check (:func:`_dense_check`, the whole
        ``arm`` with its drive train ``train``) finds it passing ``limits``, until it finds nothing (see the module
        docstring): the timed segment, its timing and the number of grid intervals slowed. ``ValueError`` (one line,
        the worst sample) after :data:`ROUNDS` rounds."""
        from pydrake.trajectories import PathParameterizedTrajectory

        x, last = timing.sd**2, self.s.size - 2
        points: dict[int, int] = {}  # the zone: grid interval → J
        seen: dict[int, NDArray] = {}  # grid interval → where the check found a limit passed in it (fractions)
        rows: dict[int, tuple[NDArray, NDArray, NDArray, NDArray, float]] = {}
        every = np.arange(1, LIMITED_POINTS) / LIMITED_POINTS

        def rows_of(i: int) -> tuple[NDArray, NDArray, NDArray, NDArray, float]:
            if i not in rows:  # an interval the slow-down changes: held at LIMITED_POINTS points, with its neighbours
                rows.update(self.dense({k: every for k in range(max(0, i - BLOCK), min(last, i + BLOCK) + 1)
                                        if k not in rows}, RAMP_MARGIN))
            return rows[i]

        changed: dict[int, int] | None = None  # the first check: every interval
        for round_ in range(ROUNDS + 1):
            excess, where, worst = _dense_check(arm, train, self, timing, changed, limits)
            bad = np.flatnonzero(np.isfinite(excess))
            if bad.size == 0:
                return (TrajectorySegment(PathParameterizedTrajectory(self.path, timing.scaling), "time-optimal",
                                          limits), timing, len(points))
            if round_ == ROUNDS:
                raise ValueError(f"the timing cannot be kept within the limits on a grid of {self.s.size} points: "
                                 f"{worst} after {ROUNDS} rounds of slowing down; give a finer grid")
            # J from the overshoot (Toppra's between its grid points, ∝ 1/J² at points 1/J apart), doubled after;
            # and the samples that passed a limit, held from now on
            index = np.clip(np.searchsorted(self.s, where, side="right") - 1, 0, last)
            flagged = [int(i) for i in bad]
            for i in flagged:
                points[i] = min(MAX_LIMITED_POINTS, 2 * points[i] if i in points else max(
                    LIMITED_POINTS, int(np.ceil(np.sqrt(2 * (excess[i] + MARGIN) / MARGIN)))))
                found = (where[index == i] - self.s[i]) / (self.s[i + 1] - self.s[i])
                seen[i] = np.concatenate([seen.get(i, np.empty(0)), found[(found > 0) & (found < 1)]])
            rows.update(self.dense({i: np.concatenate([np.arange(1, points[i]) / points[i], seen[i]])
                                    for i in flagged}))
            slower = _slow_down(x, self.s, points, rows_of)
            # checked next: an interval the slow-down changed (or held: the zone) at twice the points it was held at
            moved = np.flatnonzero((slower[:-1] != x[:-1]) | (slower[1:] != x[1:]))
            changed = {int(i): 2 * LIMITED_POINTS for i in moved} | {i: 2 * j for i, j in points.items()}
            x = slower
            timing = _Timing.from_rates(self.s, x, float(timing.knots[0]))
        raise AssertionError("unreachable: the last round returns or raises")
