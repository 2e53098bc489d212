"""Joint-space trajectories of paper 000 (Hroncová et al., 2022): rest-to-rest quintics and constant rates.

Paper 000 moves each joint by a 5th-degree polynomial, eqs. (3)–(6),

    θ(t) = a1 t⁵ + a2 t⁴ + a3 t³ + a4 t² + a5 t + a6,   a6 = θ(0),

whose coefficients come from "a set of equations compiled in matrix form" for zero velocity and
acceleration at both ends (§3, so a4 = a5 = 0). :func:`quintic_coefficients` solves exactly that
6 × 6 system. The RRRR run of Figs. 18–19, 24–25 turns its joints at constant rates,
q = q0 + ω t, which is the same polynomial form with a1 … a4 = 0, a5 = ω, a6 = q0.

A :class:`Motion` is a sequence of segments laid end to end in time, each in its own local time
τ = t − t_start (the paper's t of each section A–B, B–C, …): any trajectory armlab plans is one.
A segment is a :class:`QuinticSegment` (rest to rest), a :class:`ConstantRate`, a
:class:`PolynomialSegment` (any degree-≤5 polynomial per joint, which may start and end moving: the
profiles and via-point splines of :mod:`armlab.kinematics.profiles`) or a :class:`TrajectorySegment`
(a Drake ``Trajectory``: a ``PiecewisePolynomial`` or a ``PathParameterizedTrajectory``, e.g. a tool
path by IK, :mod:`armlab.kinematics.cartesian`, or Toppra's timing, :mod:`armlab.planning.timing`).
Consecutive segments need not join in joint space (paper 000's Table 2 leaves C on another IK branch
than it reaches it on): :meth:`Motion.joins` checks q and q̇ where they meet (to the slack,
:func:`armlab.bounds.within`) and
:meth:`Motion.runs` splits a motion into the continuous pieces that can be simulated as one run each.
:func:`to_trajectory` gives the Drake ``Trajectory`` of a motion (:func:`to_piecewise_polynomial`,
exactly the same polynomials, when every segment is a polynomial).
"""

from __future__ import annotations

import html
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import outside, within
from armlab.kinematics.batch import as_batch
from armlab.limits import LIMITS, NotRealError, check_positive, check_range, real_array, real_number

if TYPE_CHECKING:
    from pydrake.trajectories import PiecewisePolynomial, Trajectory

    from armlab.models.arm import Arm
    from armlab.planning.timing import Limits

__all__ = [
    "DEFAULT_LOG_PERIOD",
    "ConstantRate",
    "Motion",
    "PolynomialSegment",
    "QuinticSegment",
    "Segment",
    "TrajectorySegment",
    "check_duration",
    "evaluate_coefficients",
    "polynomial_matrix",
    "quintic_coefficients",
    "to_piecewise_polynomial",
    "to_trajectory",
]

#: Default period (s) at which a run samples a motion (its loggers, :mod:`armlab.diagrams.build`) and at which
#: :func:`armlab.planning.timing.fastest` checks a timing: 1 ms.
DEFAULT_LOG_PERIOD = 1e-3
#: A trajectory segment's limits are checked at its knots and this many points between each two.
KNOT_SAMPLES = 8
#: Knots of a motion closer than this (relative to its duration, at least 1 s) are one time to step to
#: (:meth:`Motion.jumps`): far below any piece of a path or a timing, far above the round-off of their times.
JUMP_SEPARATION = 1e-12

#: Powers of τ for the coefficients [a1 … a6]: θ = Σ a_k τ^(6 − k).
_POWERS = np.arange(5, -1, -1)


def check_duration(tf: float, name: str = "tf") -> float:
    """``tf`` as a float, or ``ValueError`` unless it is a positive finite number of seconds within
    ``armlab.limits.LIMITS["tf"]`` (a longer one could not be simulated or sampled)."""
    real_number(tf, name)  # a number, not a string or a bool
    return float(check_range(check_positive(tf, name, "s", "a duration must be a positive finite number of seconds"),
                             name, key="tf"))


def _joint_vector(q: ArrayLike, name: str) -> NDArray[np.float64]:
    """``q`` as one vector of joint values ``(n,)``; ``ValueError`` naming ``name`` (:class:`NotRealError` for
    ``None``, bools, text)."""
    if q is None:
        raise NotRealError(f"{name} is None: give the joint values, one per joint (rad, m)")
    a = real_array(q, name)
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"{name} has shape {a.shape}; expected one vector of joint values")
    return as_batch(a, a.size, name)


def quintic_coefficients(q0: ArrayLike, qf: ArrayLike, tf: float) -> NDArray[np.float64]:
    """Paper 000's rest-to-rest quintic coefficients [a1 … a6] per joint, shape ``(n, 6)``.

    Eqs. (3)–(6) with the side conditions of §3: θ(0) = q0, θ(tf) = qf and θ̇ = θ̈ = 0 at
    t = 0 and t = tf, written as the 6 × 6 linear system A·[a1 … a6]ᵀ = b of the paper
    ("compiled in matrix form and solved") and solved for all joints at once. ``q0`` and
    ``qf`` are ``(n,)`` (or broadcastable batches ``(..., n)``, giving ``(..., n, 6)``).
    """
    tf = check_duration(tf)
    q0 = np.asarray(q0, dtype=float)
    qf = np.asarray(qf, dtype=float)
    if q0.ndim == 0 or qf.ndim == 0:
        raise ValueError(f"q0 and qf must be joint vectors; got shapes {q0.shape} and {qf.shape}")
    q0 = as_batch(q0, q0.shape[-1], "q0")
    qf = as_batch(qf, q0.shape[-1], "qf")
    q0, qf = np.broadcast_arrays(q0, qf)
    T = tf
    A = np.array(
        [
            [0, 0, 0, 0, 0, 1],  # θ(0) = q0
            [0, 0, 0, 0, 1, 0],  # θ̇(0) = 0
            [0, 0, 0, 2, 0, 0],  # θ̈(0) = 0
            [T**5, T**4, T**3, T**2, T, 1],  # θ(tf) = qf
            [5 * T**4, 4 * T**3, 3 * T**2, 2 * T, 1, 0],  # θ̇(tf) = 0
            [20 * T**3, 12 * T**2, 6 * T, 2, 0, 0],  # θ̈(tf) = 0
        ]
    )
    zeros = np.zeros_like(q0)
    b = np.stack([q0, zeros, zeros, qf, zeros, zeros], axis=-1)  # (..., n, 6)
    return np.linalg.solve(A, b.reshape(-1, 6).T).T.reshape(b.shape)


def evaluate_coefficients(
    coefficients: ArrayLike, tau: ArrayLike, derivative: int = 0
) -> NDArray[np.float64]:
    """The ``derivative``-th time derivative of θ(τ) = Σ a_k τ^(6−k) for coefficients ``(..., 6)``.

    ``tau`` broadcasts against the leading axes of ``coefficients`` (use ``tau[:, None]``
    for a time column against ``(n, 6)``). Derivatives 0, 1, 2, … are exact polynomial
    derivatives, e.g. θ̇ = 5 a1 τ⁴ + 4 a2 τ³ + 3 a3 τ² + 2 a4 τ + a5.
    """
    c = np.asarray(coefficients, dtype=float)
    tau = np.asarray(tau, dtype=float)
    powers = _POWERS - derivative
    factor = np.ones(6)
    for k in range(derivative):
        factor = factor * (_POWERS - k)
    terms = c * factor * np.where(powers >= 0, tau[..., None] ** np.maximum(powers, 0), 0.0)
    return terms.sum(axis=-1)


@dataclass(frozen=True)
class QuinticSegment:
    """A rest-to-rest quintic from ``q0`` to ``qf`` in ``tf`` seconds (paper 000, eqs. 3–6)."""

    q0: NDArray[np.float64]
    qf: NDArray[np.float64]
    tf: float
    label: str = ""

    def __post_init__(self) -> None:
        q0 = _joint_vector(self.q0, f"{self._name}: start")
        qf = _joint_vector(self.qf, f"{self._name}: end")
        if qf.size != q0.size:
            raise ValueError(f"{self._name}: end has {qf.size} joint values, start has {q0.size}")
        object.__setattr__(self, "q0", q0)
        object.__setattr__(self, "qf", qf)
        object.__setattr__(self, "tf", check_duration(self.tf, f"{self._name}: tf"))

    @property
    def _name(self) -> str:
        return f"segment {self.label}" if self.label else "segment"

    @property
    def duration(self) -> float:
        """Length of the segment in seconds."""
        return self.tf

    @property
    def q_start(self) -> NDArray[np.float64]:
        """Joint values at the start."""
        return self.q0

    @property
    def q_end(self) -> NDArray[np.float64]:
        """Joint values at the end."""
        return self.qf

    @property
    def v_start(self) -> NDArray[np.float64]:
        """Joint velocities at the start (zero: rest to rest)."""
        return np.zeros_like(self.q0)

    @property
    def v_end(self) -> NDArray[np.float64]:
        """Joint velocities at the end (zero: rest to rest)."""
        return np.zeros_like(self.q0)

    def coefficients(self) -> NDArray[np.float64]:
        """[a1 … a6] per joint, shape ``(n, 6)`` (:func:`quintic_coefficients`)."""
        return quintic_coefficients(self.q0, self.qf, self.tf)


@dataclass(frozen=True)
class ConstantRate:
    """Joints turning at constant rates, q = q0 + ω τ for ``duration`` seconds (paper 000, Figs. 18–19)."""

    q0: NDArray[np.float64]
    omega: NDArray[np.float64]
    duration: float
    label: str = ""

    def __post_init__(self) -> None:
        name = f"segment {self.label}" if self.label else "constant-rate segment"
        q0 = _joint_vector(self.q0, f"{name}: start")
        omega = _joint_vector(self.omega, f"{name}: rates")
        if omega.size != q0.size:
            raise ValueError(f"{name}: {omega.size} rates for {q0.size} joints")
        object.__setattr__(self, "q0", q0)
        object.__setattr__(self, "omega", omega)
        object.__setattr__(self, "duration", check_duration(self.duration, f"{name}: duration"))

    @property
    def q_start(self) -> NDArray[np.float64]:
        """Joint values at the start."""
        return self.q0

    @property
    def q_end(self) -> NDArray[np.float64]:
        """Joint values at the end, q0 + ω·duration."""
        return self.q0 + self.omega * self.duration

    @property
    def v_start(self) -> NDArray[np.float64]:
        """Joint velocities at the start (ω)."""
        return self.omega

    @property
    def v_end(self) -> NDArray[np.float64]:
        """Joint velocities at the end (ω)."""
        return self.omega

    def coefficients(self) -> NDArray[np.float64]:
        """The paper's form [a1 … a6] = [0, 0, 0, 0, ω, q0] per joint, shape ``(n, 6)``."""
        c = np.zeros((self.q0.size, 6))
        c[:, 4] = self.omega
        c[:, 5] = self.q0
        return c


@dataclass(frozen=True)
class PolynomialSegment:
    """Any polynomial of degree ≤ 5 per joint in local time τ ∈ [0, ``duration``]: coefficients [a1 … a6] of
    θ(τ) = a1 τ⁵ + … + a6, shape ``(n, 6)`` (paper 000's order; a lower degree has leading zeros).

    It may start and end moving: the pieces of a trapezoidal profile, a via-point spline's segments
    (:mod:`armlab.kinematics.profiles`).
    """

    poly: NDArray[np.float64]
    duration: float
    label: str = ""

    def __post_init__(self) -> None:
        name = f"segment {self.label}" if self.label else "polynomial segment"
        c = np.asarray(self.poly, dtype=float)
        if c.ndim != 2 or c.shape[0] == 0 or c.shape[1] != 6:
            raise ValueError(f"{name}: coefficients have shape {c.shape}; expected (joints, 6): [a1 … a6] per joint")
        if not np.all(np.isfinite(c)):
            raise ValueError(f"{name}: coefficients {c.tolist()} have a value that is not a finite number")
        object.__setattr__(self, "poly", c)
        object.__setattr__(self, "duration", check_duration(self.duration, f"{name}: duration"))

    @property
    def q_start(self) -> NDArray[np.float64]:
        """Joint values at the start (a6)."""
        return self.poly[:, 5].copy()

    @property
    def q_end(self) -> NDArray[np.float64]:
        """Joint values at the end."""
        return evaluate_coefficients(self.poly, np.asarray(self.duration))

    @property
    def v_start(self) -> NDArray[np.float64]:
        """Joint velocities at the start (a5)."""
        return self.poly[:, 4].copy()

    @property
    def v_end(self) -> NDArray[np.float64]:
        """Joint velocities at the end."""
        return evaluate_coefficients(self.poly, np.asarray(self.duration), 1)

    def coefficients(self) -> NDArray[np.float64]:
        """[a1 … a6] per joint, shape ``(n, 6)``."""
        return self.poly


PolynomialKind = QuinticSegment | ConstantRate | PolynomialSegment


def _shifted(trajectory: Trajectory, start: float) -> Trajectory:
    """``trajectory`` moved in time to begin at ``start`` (a ``PiecewisePolynomial`` or a
    ``PathParameterizedTrajectory``, whose time scaling is moved)."""
    from pydrake.trajectories import PathParameterizedTrajectory, PiecewisePolynomial

    offset = start - trajectory.start_time()
    if isinstance(trajectory, PiecewisePolynomial):
        moved = cast("PiecewisePolynomial", trajectory.Clone())
        moved.shiftRight(offset)
        return moved
    if isinstance(trajectory, PathParameterizedTrajectory):
        if offset == 0.0:  # it owns copies of its path and scaling (its constructor clones them): nothing to do
            return trajectory
        scaling = trajectory.time_scaling()
        if not isinstance(scaling, PiecewisePolynomial):
            raise ValueError(f"a path-parameterised segment needs a PiecewisePolynomial time scaling, not "
                             f"{type(scaling).__name__}")
        return PathParameterizedTrajectory(trajectory.path(), _shifted(scaling, scaling.start_time() + offset))
    raise ValueError(f"a trajectory segment takes a PiecewisePolynomial or a PathParameterizedTrajectory, not "
                     f"{type(trajectory).__name__}")


@dataclass(frozen=True)
class TrajectorySegment:
    """A segment given by a Drake ``Trajectory`` of the joints, ``(n, 1)`` values, over its own
    [start_time, end_time]: a ``PiecewisePolynomial`` or a ``PathParameterizedTrajectory`` q(s(t)) (a tool
    path by IK timed by a profile, :mod:`armlab.kinematics.cartesian`; Toppra's timing of a path,
    :mod:`armlab.planning.timing`). Local time τ = 0 is the trajectory's start time. ``limits``: the joint
    limits the timing was planned within (:func:`armlab.planning.timing.fastest`'s), which a simulated run of it
    is checked against too (:func:`armlab.diagrams.drives.limit_violations`); ``None``: none beyond the arm's.
    """

    trajectory: Trajectory
    label: str = ""
    limits: Limits | None = None

    def __post_init__(self) -> None:
        name = f"segment {self.label}" if self.label else "trajectory segment"
        trajectory = _shifted(self.trajectory, 0.0)  # checks the kind; local time from 0
        if trajectory.cols() != 1 or trajectory.rows() == 0:
            raise ValueError(f"{name}: the trajectory has {trajectory.rows()} × {trajectory.cols()} values; "
                             "expected a column of joint values")
        check_duration(trajectory.end_time(), f"{name}: duration")
        object.__setattr__(self, "trajectory", trajectory)

    @cached_property
    def _derivatives(self) -> tuple[Trajectory, Trajectory]:
        """q̇(τ) and q̈(τ) as trajectories, made when first asked for (each copies the trajectory: 15 ms for a
        path of 1000 pieces, which a time-optimal timing need not spend)."""
        return self.trajectory.MakeDerivative(1), self.trajectory.MakeDerivative(2)

    @property
    def duration(self) -> float:
        """Length of the segment in seconds."""
        return float(self.trajectory.end_time())

    def _at(self, tau: float, derivative: int = 0) -> NDArray[np.float64]:
        source = self.trajectory if derivative == 0 else self._derivatives[derivative - 1]
        return np.asarray(source.value(tau), dtype=float)[:, 0]

    @property
    def q_start(self) -> NDArray[np.float64]:
        """Joint values at the start."""
        return self._at(0.0)

    @property
    def q_end(self) -> NDArray[np.float64]:
        """Joint values at the end."""
        return self._at(self.duration)

    @property
    def v_start(self) -> NDArray[np.float64]:
        """Joint velocities at the start."""
        return self._at(0.0, 1)

    @property
    def v_end(self) -> NDArray[np.float64]:
        """Joint velocities at the end."""
        return self._at(self.duration, 1)

    def evaluate(self, tau: NDArray[np.float64], orders: int = 3) -> tuple[NDArray[np.float64], ...]:
        """q, q̇, q̈ (the first ``orders``) at local times ``tau`` ``(m,)``, each ``(m, n)``, by Drake's trajectory
        and its derivative trajectories."""
        sources = (self.trajectory, *self._derivatives)[:orders]
        times = np.asarray(tau, dtype=np.float64).tolist()
        return tuple(np.asarray(s.vector_values(times), dtype=np.float64).T for s in sources)

    def knots(self) -> NDArray[np.float64]:
        """Local times where the trajectory's pieces meet (of its path for a path-parameterised one), with the ends."""
        from pydrake.trajectories import PathParameterizedTrajectory

        trajectory = self.trajectory
        if isinstance(trajectory, PathParameterizedTrajectory):
            scaling = cast("PiecewisePolynomial", trajectory.time_scaling())
            t = np.asarray(scaling.get_segment_times())  # the path's knots in s, mapped back to t below
            s_knots = np.asarray(cast("PiecewisePolynomial", trajectory.path()).get_segment_times())
            s_of_t = np.asarray(scaling.vector_values(t.tolist()))[0]
            # s(t) is monotone: the time of each path knot by interpolation, refined on the time scaling's knots
            return np.unique(np.concatenate([t, np.interp(s_knots, s_of_t, t)]))
        return np.asarray(cast("PiecewisePolynomial", trajectory).get_segment_times(), dtype=np.float64)


Segment = PolynomialKind | TrajectorySegment


def _polynomial_values(c: NDArray[np.float64], tau: NDArray[np.float64], orders: int) -> tuple[NDArray, ...]:
    """θ and its first ``orders − 1`` derivatives at ``tau`` ``(m,)`` for coefficients [a1 … a6] ``(n, 6)``,
    each ``(m, n)``, by Horner's rule (numpy's ``polyval``), as Drake's ``PiecewisePolynomial`` evaluates them."""
    # lazy: armlab --help loads this module but not numpy.polynomial (start-up time)
    from numpy.polynomial.polynomial import polyder, polyval

    low = c[:, ::-1].T  # (6, n), lowest power first
    return tuple(polyval(tau, polyder(low, d)).T for d in range(orders))


def _extreme_times(c: NDArray[np.float64], duration: float) -> NDArray[np.float64]:
    """The local times in [0, ``duration``] where some joint of coefficients ``(n, 6)`` may reach its extremes:
    the ends and the real roots of θ̇ inside (each joint's polynomial is monotone between them)."""
    times = [0.0, duration]
    for row in c:
        derivative = np.polyder(np.trim_zeros(row, "f") if np.any(row) else np.zeros(1))
        if derivative.size > 1:
            roots = np.roots(derivative)
            real = roots[np.abs(roots.imag) <= 1e-12 * max(1.0, duration)].real
            inside = (real > 1e-9 * duration) & (real < duration * (1 - 1e-9))  # the ends are in already
            times.extend(real[inside].tolist())
    return np.unique(np.asarray(times))


@dataclass(frozen=True)
class Motion:
    """Segments laid end to end in time, from t = 0; each in its own local time.

    ``description`` says what the motion is (shown in summaries and plot titles); ``figures``
    names the paper figures the motion reproduces, if any.
    """

    segments: tuple[Segment, ...]
    description: str = ""
    figures: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        segments = tuple(self.segments)
        if not segments:
            raise ValueError("a motion needs at least one segment")
        n = segments[0].q_start.size
        for k, s in enumerate(segments):
            if s.q_start.size != n:
                raise ValueError(f"segment {k + 1} ({s.label or 'unnamed'}) has {s.q_start.size} joints; "
                                 f"segment 1 has {n}")
        object.__setattr__(self, "segments", segments)

    def __repr__(self) -> str:
        return (f"<Motion {self.description or 'unnamed'}: {self.duration:g} s, {len(self.segments)} segment(s), "
                f"{self.segments[0].q_start.size} joints>")

    def _repr_html_(self) -> str:
        """Jupyter's view: what the motion is, then one row per segment: its label, start and end time (s) and its
        joints at both ends (rad or m)."""

        def joints(q: NDArray) -> str:
            return ", ".join(f"{v:+.4g}" for v in q)

        rows, start = [], 0.0
        for k, segment in enumerate(self.segments):
            end = start + segment.duration
            rows.append(f"<tr><td>{html.escape(segment.label or str(k + 1))}</td><td>{start:.4g}</td><td>{end:.4g}</td>"
                        f"<td>{joints(segment.q_start)}</td><td>{joints(segment.q_end)}</td></tr>")
            start = end
        return (f"<div><b>{html.escape(repr(self)[1:-1])}</b><table><tr><th>segment</th><th>from (s)</th>"
                f"<th>to (s)</th><th>q at its start</th><th>q at its end</th></tr>{''.join(rows)}</table></div>")

    @property
    def n(self) -> int:
        """Number of joints."""
        return self.segments[0].q_start.size

    @property
    def breaks(self) -> NDArray[np.float64]:
        """Segment start times and the end time, shape ``(k + 1,)``."""
        return np.concatenate([[0.0], np.cumsum([s.duration for s in self.segments])])

    @property
    def duration(self) -> float:
        """Total duration in seconds."""
        return float(self.breaks[-1])

    @property
    def labels(self) -> list[str]:
        """Segment labels (``"1"``, ``"2"``, … where a segment has none)."""
        return [s.label or str(k + 1) for k, s in enumerate(self.segments)]

    @property
    def polynomial(self) -> bool:
        """Whether every segment is a polynomial of degree ≤ 5 (then :meth:`coefficients` gives them all)."""
        return all(not isinstance(s, TrajectorySegment) for s in self.segments)

    def coefficients(self) -> NDArray[np.float64]:
        """[a1 … a6] per segment and joint, shape ``(k, n, 6)``, each in its segment's local time; ``ValueError``
        for a motion with a trajectory segment (see :attr:`polynomial`)."""
        polynomials = [s for s in self.segments if not isinstance(s, TrajectorySegment)]
        if len(polynomials) != len(self.segments):
            raise ValueError(f"motion {self.description!r} has segments that are not polynomials of degree ≤ 5")
        return np.stack([s.coefficients() for s in polynomials])

    def segment_index(self, t: ArrayLike) -> NDArray[np.intp]:
        """Index of the segment holding each time: breaks[i] ≤ t < breaks[i+1] (the last one closed)."""
        return np.clip(np.searchsorted(self.breaks, np.asarray(t, dtype=float), side="right") - 1,
                       0, len(self.segments) - 1)

    def evaluate(self, t: ArrayLike, orders: int = 3) -> tuple[NDArray[np.float64], ...]:
        """q, q̇, q̈ at times ``t`` (shape ``(m,)``), each ``(m, n)``.

        A polynomial segment's θ(τ) = Σ a_k τ^(6−k) and its derivatives in the segment's local time τ, by Horner's
        rule (numpy's ``polyval``), as Drake's ``PiecewisePolynomial`` evaluates them; a trajectory segment by its
        Drake trajectory. ``orders``: how many of q, q̇, q̈ to return (1 to 3).
        """
        t = np.atleast_1d(np.asarray(t, dtype=float))
        out = tuple(np.empty((t.size, self.n)) for _ in range(orders))
        index = self.segment_index(t)
        for k, (start, segment) in enumerate(zip(self.breaks, self.segments, strict=False)):
            rows = index == k
            if not rows.any():
                continue
            tau = t[rows] - start
            values = (segment.evaluate(tau, orders) if isinstance(segment, TrajectorySegment)
                      else _polynomial_values(segment.coefficients(), tau, orders))
            for d in range(orders):
                out[d][rows] = values[d]
        return out

    def joins(self) -> list[bool]:
        """For each segment after the first: does it start where (q and q̇) the previous one ends, to the slack
        (:func:`armlab.bounds.within`: the ends of segments computed independently, a via-point spline's pieces,
        differ by round-off only)?"""
        def close(a: NDArray, b: NDArray) -> bool:
            return bool(np.all(within(b, a, a)))

        return [close(a.q_end, b.q_start) and close(a.v_end, b.v_start)
                for a, b in zip(self.segments[:-1], self.segments[1:], strict=True)]

    def runs(self) -> list[tuple[float, Motion]]:
        """The continuous pieces of the motion: ``(start time, sub-motion starting at 0)`` each.

        Consecutive segments that :meth:`joins` reports joined form one run; where they do not,
        the robot would have to reconfigure, so the next run starts from rest (or its own rate)
        at its own start, a separate simulation.
        """
        groups: list[list[int]] = [[0]]
        for k, joined in enumerate(self.joins(), start=1):
            if joined:
                groups[-1].append(k)
            else:
                groups.append([k])
        breaks = self.breaks
        return [(float(breaks[g[0]]), Motion(tuple(self.segments[k] for k in g), self.description, self.figures))
                for g in groups]

    def jumps(self) -> NDArray[np.float64]:
        """Times (s) where q̈ may jump, sorted, ``(k,)``, from 0 to the duration: the segments' joins and a trajectory
        segment's knots (its pieces' joins, where a time-optimal timing switches its s̈). A simulation steps to each,
        so that no integrator step straddles a jump (its error control would meet it as a large local error)."""
        breaks = self.breaks
        times = [breaks] + [start + segment.knots() for segment, start in zip(self.segments, breaks, strict=False)
                            if isinstance(segment, TrajectorySegment)]
        t = np.unique(np.clip(np.concatenate(times), 0.0, breaks[-1]))
        # knots closer than round-off of the times (a path knot mapped onto a knot of the timing) are one
        keep = np.concatenate([np.diff(t) > JUMP_SEPARATION * max(1.0, float(breaks[-1])), [True]])
        keep[0] = True
        return t[keep]

    def check_times(self, k: int) -> NDArray[np.float64]:
        """Local times of segment ``k`` that bound its joint values: for a polynomial the ends and the roots of
        θ̇ (exact); for a trajectory its knots and :data:`KNOT_SAMPLES` points between each two."""
        segment = self.segments[k]
        if not isinstance(segment, TrajectorySegment):
            return _extreme_times(segment.coefficients(), segment.duration)
        knots = segment.knots()
        fill = knots[:-1, None] + np.diff(knots)[:, None] * np.arange(1, KNOT_SAMPLES + 1) / (KNOT_SAMPLES + 1)
        return np.unique(np.concatenate([knots, fill.ravel()]))

    def check_limits(self, arm: Arm) -> None:
        """``ValueError`` if the motion leaves ``arm``'s joint limits anywhere, naming the segment and the time.

        Each segment is checked where its joints can reach their extremes (:meth:`check_times`): a polynomial
        is monotone between the roots of its θ̇, so those and its ends bound it exactly (a rest-to-rest quintic:
        its ends); a trajectory segment at its knots and between them.
        """
        if self.n != arm.n:
            raise ValueError(f"the motion has {self.n} joints; {arm.name} has {arm.n}")
        lower, upper = arm.limit_arrays()
        held = LIMITS["q"]  # an unlimited joint is held to ±1e6 (rad, m), as arm.check_q holds it
        for k, (label, start) in enumerate(zip(self.labels, self.breaks, strict=False)):
            tau = self.check_times(k)
            q = self.evaluate(start + np.clip(tau, 0.0, self.segments[k].duration), 1)[0]
            beyond = np.flatnonzero(np.any(outside(q, lower, upper) | outside(q, held.low, held.high), axis=1)
                                    | ~np.all(np.isfinite(q), axis=1))  # the rule arm.check_q applies
            if beyond.size == 0:
                continue
            i = beyond[0]
            where = ("start" if tau[i] == 0.0 else "end" if tau[i] == self.segments[k].duration  # exact: the ends
                     else f"at t = {start + tau[i]:.6g} s")
            try:
                arm.check_q(q[i])
            except ValueError as error:
                raise ValueError(f"segment {label} {where}: {error}") from None


def polynomial_matrix(c: NDArray[np.float64]) -> NDArray[np.object_]:
    """Drake ``Polynomial`` s of coefficients [a1 … a6] per joint ``(n, 6)``, an ``(n, 1)`` matrix (lowest power
    first, as Drake wants)."""
    from pydrake.polynomial import Polynomial

    m = np.empty((c.shape[0], 1), dtype=object)
    for i in range(c.shape[0]):
        m[i, 0] = Polynomial(np.ascontiguousarray(c[i, ::-1]))
    return m


def to_piecewise_polynomial(motion: Motion) -> PiecewisePolynomial:
    """Drake's ``PiecewisePolynomial`` of a polynomial ``motion``: one ``(n, 1)`` Polynomial matrix per segment.

    Drake evaluates segment i in local time t − breaks[i], as the paper's polynomials are
    written, so the coefficients are passed unchanged (lowest power first, as Drake wants).
    """
    from pydrake.trajectories import PiecewisePolynomial

    return PiecewisePolynomial([polynomial_matrix(c) for c in motion.coefficients()], motion.breaks.tolist())


def to_trajectory(motion: Motion) -> Trajectory:
    """The Drake ``Trajectory`` of ``motion`` over [0, duration]: :func:`to_piecewise_polynomial` when every
    segment is a polynomial, else a ``CompositeTrajectory`` of the segments' trajectories, each moved to its
    start time (what Drake's ``TrajectorySource`` and ``Toppra`` take)."""
    from pydrake.trajectories import CompositeTrajectory, PiecewisePolynomial

    if motion.polynomial:
        return to_piecewise_polynomial(motion)
    pieces = []
    for start, end, segment in zip(motion.breaks[:-1], motion.breaks[1:], motion.segments, strict=True):
        if isinstance(segment, TrajectorySegment):
            pieces.append(_shifted(segment.trajectory, float(start)))
        else:
            pieces.append(PiecewisePolynomial([polynomial_matrix(segment.coefficients())], [start, end]))
    return CompositeTrajectory(pieces)
