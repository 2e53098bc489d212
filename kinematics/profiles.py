"""Joint-space motions as people plan them: time profiles, trapezoids, minimum jerk, splines through via points.

A :class:`Profile` is a scalar s(t) from 0 to 1 over its duration, piecewise polynomial (degree ≤ 5):

* :func:`trapezoid_profile` — constant acceleration, cruise, constant deceleration (RTB ``trapezoidal``,
  MATLAB ``trapveltraj``), from a peak rate and acceleration of s, or a duration (then the peak rate is
  1.5/T, the Robotics Toolbox's default, and the blends take T/3 each);
* :func:`minimum_jerk_profile` — s = 10τ³ − 15τ⁴ + 6τ⁵, τ = t/T: the rest-to-rest path of least ∫ jerk²
  (Flash & Hogan 1985), the same polynomial as paper 000's rest-to-rest quintic;
* :func:`cubic_profile` — s = 3τ² − 2τ³ (zero velocity at both ends).

A profile times a joint move q = q0 + s·(qf − q0) (:func:`trapezoidal`: all joints arrive together, the one
nearest its limit sets the pace) or a tool path (:mod:`armlab.kinematics.cartesian`).

:func:`spline` passes through via points without stopping: cubics (continuous velocity) or quintics
(continuous velocity and acceleration). The via velocities, unless given, follow the rule of Craig
(*Introduction to Robotics*, §7.3) that MATLAB's ``cubicpolytraj`` examples and RTB's ``mstraj`` approximate:
at an interior via each joint moves at the mean of the average velocities of the two segments it joins, or
is at rest where those differ in sign (or one is zero); the ends are at rest. Quintics choose their via
accelerations by the same rule applied to the via velocities.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import as_batch
from armlab.kinematics.quintic import Motion, PolynomialSegment, check_duration
from armlab.limits import check_positive, per_joint

if TYPE_CHECKING:
    from pydrake.trajectories import PiecewisePolynomial

    from armlab.models.arm import Arm

__all__ = [
    "Profile",
    "cubic_profile",
    "hermite_coefficients",
    "minimum_jerk_profile",
    "spline",
    "trapezoid_profile",
    "trapezoidal",
    "via_rule",
]


@dataclass(frozen=True)
class Profile:
    """A scalar time profile s(t), 0 → 1: pieces of ``durations`` (s), each a polynomial [a1 … a6] of its local
    time (``coefficients`` ``(k, 6)``, θ = a1 τ⁵ + … + a6, paper 000's order). ``name`` says what it is."""

    durations: tuple[float, ...]
    coefficients: NDArray[np.float64]
    name: str

    @property
    def duration(self) -> float:
        """Total duration (s)."""
        return float(sum(self.durations))

    def joint_segments(self, q0: NDArray[np.float64], qf: NDArray[np.float64],
                       label: str = "") -> tuple[PolynomialSegment, ...]:
        """The segments of q(t) = q0 + s(t)·(qf − q0) for joints ``(n,)``: one per piece of the profile."""
        delta = qf - q0
        segments = []
        for k, (tf, c) in enumerate(zip(self.durations, self.coefficients, strict=True)):
            poly = delta[:, None] * c[None, :]
            poly[:, 5] += q0
            segments.append(PolynomialSegment(poly, tf, f"{label} {self.name} {k + 1}".strip()))
        return tuple(segments)

    def piecewise(self) -> PiecewisePolynomial:
        """Drake's ``PiecewisePolynomial`` of s(t), ``(1, 1)`` values (a ``PathParameterizedTrajectory``'s time
        scaling)."""
        from pydrake.polynomial import Polynomial
        from pydrake.trajectories import PiecewisePolynomial

        matrices = []
        for c in self.coefficients:
            m = np.empty((1, 1), dtype=object)
            m[0, 0] = Polynomial(np.ascontiguousarray(c[::-1]))
            matrices.append(m)
        return PiecewisePolynomial(matrices, np.concatenate([[0.0], np.cumsum(self.durations)]).tolist())


def _rate(value: float, what: str, unit: str) -> float:
    return check_positive(value, what, unit, f"a peak {what.split()[-1]} must be a positive finite number")


def trapezoid_profile(velocity: float | None = None, acceleration: float | None = None,
                      duration: float | None = None) -> Profile:
    """The trapezoidal s(t), 0 → 1, from its peak rate ``velocity`` (1/s) and ``acceleration`` (1/s²), or from a
    ``duration`` (s) alone (peak rate 1.5/T, RTB's default), or a duration and a peak rate in (1/T, 2/T].

    Blend time t_b = v/a and duration T = 1/v + t_b; where 1/v < t_b (the peak rate is never reached) the
    profile is a triangle, t_b = √(1/a), T = 2 t_b. ``ValueError`` for a rate or acceleration ≤ 0, NaN, a
    rate that the duration does not allow, or another combination.
    """
    if duration is not None:
        T = check_duration(duration, "duration")
        if acceleration is not None:
            raise ValueError("give a trapezoid a duration (and perhaps a peak velocity), or a peak velocity and "
                             "acceleration, not a duration and an acceleration")
        v = 1.5 / T if velocity is None else _rate(velocity, "peak velocity", "1/s")
        if not 1.0 / T < v <= 2.0 / T:
            raise ValueError(f"peak velocity {v:g} of s is not allowed for duration {T:g} s: between 1/T = "
                             f"{1 / T:g} (exclusive) and 2/T = {2 / T:g} 1/s")
        blend = T - 1.0 / v
        a = v / blend
    else:
        if velocity is None or acceleration is None:
            raise ValueError("a trapezoid needs a duration, or a peak velocity and a peak acceleration")
        v, a = _rate(velocity, "peak velocity", "1/s"), _rate(acceleration, "peak acceleration", "1/s²")
        blend = v / a
        if 1.0 / v < blend:  # never cruises: a triangle
            blend = float(np.sqrt(1.0 / a))
            v = a * blend
        T = 1.0 / v + blend
    cruise = T - 2 * blend
    s_blend = 0.5 * a * blend**2
    pieces = [(blend, [0, 0, 0, 0.5 * a, 0, 0])]
    if cruise > 1e-12 * T:
        pieces.append((cruise, [0, 0, 0, 0, v, s_blend]))
    pieces.append((blend, [0, 0, 0, -0.5 * a, v, 1.0 - s_blend]))
    return Profile(tuple(check_duration(p[0], "blend time") for p in pieces),
                   np.array([p[1] for p in pieces], dtype=float), "trapezoid")


def minimum_jerk_profile(duration: float) -> Profile:
    """s = 10τ³ − 15τ⁴ + 6τ⁵, τ = t/T: rest to rest with zero acceleration at both ends, least ∫ jerk² dt."""
    T = check_duration(duration, "duration")
    return Profile((T,), np.array([[6 / T**5, -15 / T**4, 10 / T**3, 0.0, 0.0, 0.0]]), "minimum-jerk")


def cubic_profile(duration: float) -> Profile:
    """s = 3τ² − 2τ³, τ = t/T: rest to rest (the acceleration jumps at both ends)."""
    T = check_duration(duration, "duration")
    return Profile((T,), np.array([[0.0, 0.0, -2 / T**3, 3 / T**2, 0.0, 0.0]]), "cubic")


def _joints(arm: Arm, q: ArrayLike, name: str) -> NDArray[np.float64]:
    return arm.check_q(as_batch(q, arm.n, name), name)


def _per_joint(value: float | ArrayLike, n: int, name: str, unit: str) -> NDArray[np.float64]:
    a = per_joint(value, n, name)
    for v in a:
        _rate(float(v), name, unit)
    return a


def trapezoidal(arm: Arm, q0: ArrayLike, qf: ArrayLike, velocity: float | ArrayLike | None = None,
                acceleration: float | ArrayLike | None = None, duration: float | None = None) -> Motion:
    """A synchronised trapezoidal move of ``arm`` from ``q0`` to ``qf`` ``(n,)``: all joints start and arrive
    together on one trapezoidal s(t) (:func:`trapezoid_profile`).

    ``velocity`` and ``acceleration``: each joint's peak (rad/s, rad/s²; m for prismatic), one value or one per
    joint; the joint needing most time sets the pace (the s-rate is min_j v_j/|Δq_j|, the s-acceleration
    min_j a_j/|Δq_j|), so no joint exceeds its peaks. Or a ``duration`` (s). Both ends are checked against the
    joint limits (the move is monotone between them).
    """
    start, end = _joints(arm, q0, "q0"), _joints(arm, qf, "qf")
    delta = np.abs(end - start)
    moving = delta > 0
    if not moving.any():
        raise ValueError(f"q0 = qf = {start.tolist()}: a trapezoid needs a move")

    def s_rate(value: float | ArrayLike | None, name: str, unit: str) -> float | None:
        """The joints' peaks as the peak of s: the least v_j/|Δq_j| over the moving joints."""
        if value is None:
            return None
        return float(np.min(_per_joint(value, arm.n, name, unit)[moving] / delta[moving]))

    profile = trapezoid_profile(s_rate(velocity, "peak velocity", "rad/s or m/s"),
                                s_rate(acceleration, "peak acceleration", "rad/s² or m/s²"), duration)
    motion = Motion(profile.joint_segments(start, end), "synchronised trapezoidal velocity profile")
    motion.check_limits(arm)
    return motion


def hermite_coefficients(q0: NDArray, v0: NDArray, a0: NDArray, q1: NDArray, v1: NDArray, a1: NDArray,
                         tf: float | NDArray) -> NDArray[np.float64]:
    """[a1 … a6] ``(..., n, 6)`` of the quintics with q, q̇, q̈ = (q0, v0, a0) at τ = 0 and (q1, v1, a1) at τ = tf:
    the values ``(..., n)``, the durations ``tf`` (s) a scalar or ``(...)`` (one per leading index)."""
    T = np.asarray(tf, dtype=float)[..., None, None]
    zero, one = np.zeros_like(T), np.ones_like(T)
    A = np.concatenate([np.concatenate(row, axis=-1) for row in (
        (zero, zero, zero, zero, zero, one), (zero, zero, zero, zero, one, zero),
        (zero, zero, zero, 2 * one, zero, zero), (T**5, T**4, T**3, T**2, T, one),
        (5 * T**4, 4 * T**3, 3 * T**2, 2 * T, one, zero), (20 * T**3, 12 * T**2, 6 * T, 2 * one, zero, zero))],
        axis=-2)  # (..., 6, 6)
    b = np.stack(np.broadcast_arrays(q0, v0, a0, q1, v1, a1), axis=-2)  # (..., 6, n)
    return np.swapaxes(np.linalg.solve(A, b), -1, -2)


def _cubic_coefficients(q0: NDArray, v0: NDArray, q1: NDArray, v1: NDArray, tf: float) -> NDArray[np.float64]:
    """[0, 0, c3, c2, c1, c0] ``(n, 6)`` of the cubic with q, q̇ = (q0, v0) at 0 and (q1, v1) at ``tf``."""
    T = tf
    c = np.zeros((q0.size, 6))
    c[:, 2] = (2 * (q0 - q1) + (v0 + v1) * T) / T**3
    c[:, 3] = (3 * (q1 - q0) - (2 * v0 + v1) * T) / T**2
    c[:, 4] = v0
    c[:, 5] = q0
    return c


def via_rule(values: NDArray[np.float64], durations: NDArray[np.float64]) -> NDArray[np.float64]:
    """Craig's via-point rule: the rates ``(k + 1, n)`` at the points ``values`` ``(k + 1, n)`` reached after
    ``durations`` ``(k,)``: 0 at the ends; inside, the mean of the two adjacent slopes, or 0 where they differ in
    sign or one of them is 0."""
    slopes = np.diff(values, axis=0) / durations[:, None]
    left, right = slopes[:-1], slopes[1:]
    inner = np.where(left * right > 0, 0.5 * (left + right), 0.0)
    zero = np.zeros((1, values.shape[1]))
    return np.concatenate([zero, inner, zero])


def spline(arm: Arm, waypoints: ArrayLike, durations: float | Sequence[float], degree: int = 5,
           velocities: ArrayLike | None = None, accelerations: ArrayLike | None = None) -> Motion:
    """Through ``waypoints`` ``(k + 1, n)`` without stopping: k cubics (``degree`` 3, continuous q̇) or quintics
    (5, continuous q̇ and q̈), segment i taking ``durations[i]`` s (or one duration each).

    ``velocities`` (and for quintics ``accelerations``) ``(k + 1, n)`` at the waypoints, default
    :func:`via_rule` (rest at both ends). Every waypoint and the whole motion (between its ends too) are
    checked against the joint limits.
    """
    points = np.asarray(waypoints, dtype=float)
    if points.ndim != 2 or points.shape[0] < 2 or points.shape[1] != arm.n:
        raise ValueError(f"waypoints have shape {points.shape}; give at least two rows of {arm.n} joint values")
    for k, q in enumerate(points):
        try:
            _joints(arm, q, f"waypoint {k + 1}")
        except ValueError as error:
            raise ValueError(f"waypoint {k + 1}: {error}") from None
    if degree not in (3, 5):
        raise ValueError(f"degree {degree!r} is not allowed: 3 (cubic) or 5 (quintic)")
    m = points.shape[0] - 1
    times = np.broadcast_to(np.asarray(durations, dtype=float), (m,)) if np.ndim(durations) == 0 \
        else np.asarray(durations, dtype=float)
    if times.shape != (m,):
        raise ValueError(f"durations has {times.size} values; {m} segments need one each (or one duration)")
    times = np.array([check_duration(t, f"segment {k + 1} duration") for k, t in enumerate(times)])

    def rates(given: ArrayLike | None, of: NDArray, name: str, unit: str) -> NDArray[np.float64]:
        if given is None:
            return via_rule(of, times)
        a = np.asarray(given, dtype=float)
        if a.shape != points.shape:
            raise ValueError(f"{name} have shape {a.shape}; expected one row per waypoint, {points.shape}")
        return as_batch(a, arm.n, name)

    v = rates(velocities, points, "velocities", "rad/s")
    a = rates(accelerations, v, "accelerations", "rad/s²") if degree == 5 else None
    if degree == 3 and accelerations is not None:
        raise ValueError("accelerations apply to quintics (degree 5); a cubic spline takes velocities only")
    segments = []
    for k in range(m):
        if a is None:
            c = _cubic_coefficients(points[k], v[k], points[k + 1], v[k + 1], float(times[k]))
        else:
            c = hermite_coefficients(points[k], v[k], a[k], points[k + 1], v[k + 1], a[k + 1], float(times[k]))
        segments.append(PolynomialSegment(c, float(times[k]), f"{k + 1}"))
    kind = "cubics" if degree == 3 else "quintics"
    motion = Motion(tuple(segments), f"{kind} through {m + 1} waypoints without stopping")
    motion.check_limits(arm)
    return motion
