"""Joint-space trajectories of paper 000 (Hroncová et al., 2022): rest-to-rest quintics and constant rates.

Paper 000 moves each joint by a 5th-degree polynomial, eqs. (3)–(6),

    θ(t) = a1 t⁵ + a2 t⁴ + a3 t³ + a4 t² + a5 t + a6,   a6 = θ(0),

whose coefficients come from "a set of equations compiled in matrix form" for zero velocity and
acceleration at both ends (§3, so a4 = a5 = 0). :func:`quintic_coefficients` solves exactly that
6 × 6 system. The RRRR run of Figs. 18–19, 24–25 turns its joints at constant rates,
q = q0 + ω t, which is the same polynomial form with a1 … a4 = 0, a5 = ω, a6 = q0.

A :class:`Motion` is a sequence of segments laid end to end in time, each a :class:`QuinticSegment`
or a :class:`ConstantRate`, each in its own local time τ = t − t_start (the paper's t of each
section A–B, B–C, …). Consecutive segments need not join in joint space (paper 000's Table 2 leaves
C on another IK branch than it reaches it on): :meth:`Motion.runs` splits a motion into the
continuous pieces that can be simulated as one run each. :func:`to_piecewise_polynomial` gives
Drake's ``PiecewisePolynomial`` with exactly the same polynomials.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import as_batch
from armlab.limits import check_positive, check_range, real_number

if TYPE_CHECKING:
    from pydrake.trajectories import PiecewisePolynomial

    from armlab.models.arm import Arm

__all__ = [
    "ConstantRate",
    "Motion",
    "QuinticSegment",
    "Segment",
    "check_duration",
    "evaluate_coefficients",
    "quintic_coefficients",
    "to_piecewise_polynomial",
]

#: Powers of τ for the coefficients [a1 … a6]: θ = Σ a_k τ^(6 − k).
_POWERS = np.arange(5, -1, -1)


def check_duration(tf: float, name: str = "tf") -> float:
    """``tf`` as a float, or ``ValueError`` unless it is a positive finite number of seconds within
    ``armlab.limits.LIMITS["tf"]`` (a longer one could not be simulated or sampled)."""
    real_number(tf, name)  # a number, not a string or a bool
    return float(check_range(check_positive(tf, name, "s", "a duration must be a positive finite number of seconds"),
                             name, key="tf"))


def _joint_vector(q: ArrayLike, name: str) -> NDArray[np.float64]:
    a = np.asarray(q, dtype=float)
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


Segment = QuinticSegment | ConstantRate


@dataclass(frozen=True)
class Motion:
    """Segments laid end to end in time, from t = 0; each is a polynomial in its own local time.

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

    def coefficients(self) -> NDArray[np.float64]:
        """[a1 … a6] per segment and joint, shape ``(k, n, 6)``, each in its segment's local time."""
        return np.stack([s.coefficients() for s in self.segments])

    def segment_index(self, t: ArrayLike) -> NDArray[np.intp]:
        """Index of the segment holding each time: breaks[i] ≤ t < breaks[i+1] (the last one closed)."""
        return np.clip(np.searchsorted(self.breaks, np.asarray(t, dtype=float), side="right") - 1,
                       0, len(self.segments) - 1)

    def evaluate(self, t: ArrayLike, orders: int = 3) -> tuple[NDArray[np.float64], ...]:
        """q, q̇, q̈ at times ``t`` (shape ``(m,)``), each ``(m, n)``, from the closed-form polynomials.

        Each segment's θ(τ) = Σ a_k τ^(6−k) and its derivatives in the segment's local time τ, by Horner's
        rule (numpy's ``polyval``), as Drake's ``PiecewisePolynomial`` evaluates them. ``orders``: how many
        of q, q̇, q̈ to return (1 to 3).
        """
        # lazy: armlab --help loads this module but not numpy.polynomial (start-up time)
        from numpy.polynomial.polynomial import polyder, polyval

        t = np.atleast_1d(np.asarray(t, dtype=float))
        out = tuple(np.empty((t.size, self.n)) for _ in range(orders))
        index = self.segment_index(t)
        for k, (start, c) in enumerate(zip(self.breaks, self.coefficients(), strict=False)):
            rows = index == k
            low = c[:, ::-1].T  # (6, n), lowest power first
            for d in range(orders):
                out[d][rows] = polyval(t[rows] - start, polyder(low, d)).T
        return out

    def joins(self) -> list[bool]:
        """For each segment after the first: does it start where (q and q̇) the previous one ends, exactly?"""
        return [bool(np.array_equal(a.q_end, b.q_start) and np.array_equal(a.v_end, b.v_start))
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

    def check_limits(self, arm: Arm) -> None:
        """``ValueError`` if a segment starts or ends outside ``arm``'s joint limits.

        A rest-to-rest quintic is monotone between its ends and a constant rate is linear, so
        the ends bound the whole segment.
        """
        if self.n != arm.n:
            raise ValueError(f"the motion has {self.n} joints; {arm.name} has {arm.n}")
        for label, s in zip(self.labels, self.segments, strict=True):
            for where, q in (("start", s.q_start), ("end", s.q_end)):
                try:
                    arm.check_q(q)
                except ValueError as error:
                    raise ValueError(f"segment {label} {where}: {error}") from None


def to_piecewise_polynomial(motion: Motion) -> PiecewisePolynomial:
    """Drake's ``PiecewisePolynomial`` of ``motion``: one ``(n, 1)`` Polynomial matrix per segment.

    Drake evaluates segment i in local time t − breaks[i], as the paper's polynomials are
    written, so the coefficients are passed unchanged (lowest power first, as Drake wants).
    """
    from pydrake.polynomial import Polynomial
    from pydrake.trajectories import PiecewisePolynomial

    matrices = []
    for c in motion.coefficients():
        m = np.empty((motion.n, 1), dtype=object)
        for i in range(motion.n):
            m[i, 0] = Polynomial(np.ascontiguousarray(c[i, ::-1]))
        matrices.append(m)
    return PiecewisePolynomial(matrices, motion.breaks.tolist())
