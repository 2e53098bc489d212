"""The one boundary rule: how a computed value is compared with a bound, so that round-off never decides.

Two OpenBLAS kernels (or two CPUs, or a batch and a single call) round the same computation a few ulps apart,
≈ 1e-16 relative each. A value that sits on a bound in exact arithmetic — paper 000's circle ending on joint 2's
limit, a time-optimal torque on its effort limit, a drive's ratio limit/value at 1, a deviation of exactly half
a printed digit — then lands on either side of it, and a bare ``<`` gives a different answer on each machine.
So every comparison of a computed value against a bound (joint, velocity, acceleration, effort and motor limits;
a clearance against zero or a margin; singular-value thresholds; reach; the tolerances that decide a report row's
verdict; sizing margins) goes through this module, with one slack:

    **a value within SLACK · max(1, |bound|) of a bound counts as on it** (:func:`allowance`), SLACK = 1e-9,

and a value on a bound is within it: only a value beyond the bound by more than the allowance is
:func:`above` / :func:`below` it. The floor of 1 is in SI units (rad, m, N·m, s, a ratio): it makes the
allowance absolute, 1e-9, near a bound of zero (a clearance, a margin), where a relative one would vanish; above 1
the allowance is relative. 1e-9 is far above round-off (≈ 1e-15 for unit-scale quantities, 1e-13 for
sums over thousands of samples) and far below anything physical (a nanometre, a nanoradian, a nano-newton-metre,
a part in 10⁹ of a motor's rating).

A **tolerance** is a bound on a magnitude that is zero in exact arithmetic where all is well — an error, a
residual, a gap between two forms, a singular value at a singularity — often far below 1 (1e-9 m for an IK
solution, 1e-12 for a printed form against its derivation, 1e-6 for σ_min): the floor would swamp it (``below(σ,
1e-9)`` could never hold), so :func:`tolerated` applies the slack relative to the tolerance itself (the magnitude
divided by its tolerance compared with 1): magnitude ≤ tol·(1 + SLACK). That protects a magnitude computed from
quantities up to about 10⁶ times the tolerance (their round-off, ≈ 1e-16 of their size, stays below tol·SLACK); a
tolerance far below the round-off of what it compares (1e-12 against unit-scale quantities) is a test for
round-off itself, whose magnitudes are round-off or far beyond it, never on it by construction. A physical bound
(a limit, a reach, a clearance, a margin, a paper's value ± its printed resolution) is applied by :func:`above`,
:func:`below`, :func:`outside` or :func:`within`.

Each function takes numbers or numpy arrays (broadcast together: a value ``(..., n)`` against bounds ``(n,)``)
and returns numpy booleans of the broadcast shape. **NaN is beyond every bound**: above and below it at once,
outside any interval, never within or tolerated (a NaN never passes a check; ``above(x, a) & below(x, b)`` is true
of it, so a caller asking "strictly between" tests ``isnan`` too). An infinite bound (an unlimited joint) has no
allowance and bounds nothing finite.
:func:`clamp` moves a value on a bound (within its allowance outside it) onto it, for code that then needs it
inside (an IK solution clipped into the joint limits); a value beyond is left for its check to report.

This module imports nothing of armlab's (a base room, like :mod:`armlab.limits` and :mod:`armlab.values`);
``tests/test_bounds.py`` checks that no library module compares a value with a bound by hand.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["SLACK", "Interval", "above", "above_value", "allowance", "below", "below_value", "clamp", "outside",
           "tolerated", "within"]

#: The one slack (dimensionless): a value within SLACK · max(1, |bound|) of a bound counts as on it.
SLACK = 1e-9


def allowance(bound: ArrayLike) -> NDArray[np.float64]:
    """How far (the bound's unit) a value may pass ``bound`` and still count as on it: SLACK · max(1, |bound|),
    the bound's shape; 0 for an infinite bound (nothing finite passes it, and ±inf stays itself)."""
    bound = np.asarray(bound, dtype=float)
    return np.where(np.isfinite(bound), SLACK * np.maximum(1.0, np.abs(bound)), 0.0)


def above(value: ArrayLike, bound: ArrayLike) -> NDArray[np.bool_]:
    """``value`` is beyond the upper bound ``bound`` by more than :func:`allowance` (NaN: always), broadcast shape."""
    return np.logical_not(np.less_equal(value, np.add(bound, allowance(bound))))


def below(value: ArrayLike, bound: ArrayLike) -> NDArray[np.bool_]:
    """``value`` is beyond the lower bound ``bound`` by more than :func:`allowance` (NaN: always), broadcast shape."""
    return np.logical_not(np.greater_equal(value, np.subtract(bound, allowance(bound))))


def outside(value: ArrayLike, lower: ArrayLike, upper: ArrayLike) -> NDArray[np.bool_]:
    """``value`` is :func:`below` ``lower`` or :func:`above` ``upper`` (NaN: always), broadcast shape."""
    return np.logical_or(below(value, lower), above(value, upper))


def _allowance_value(bound: float) -> float:
    """:func:`allowance` of one Python float, without numpy's per-call cost."""
    return SLACK * max(1.0, abs(bound)) if math.isfinite(bound) else 0.0


def above_value(value: float, bound: float) -> bool:
    """:func:`above` of one Python float against one bound, without numpy's per-call cost (a closed form solving one
    pose makes several such checks; each would cost more than its arithmetic): the same rule, a ``bool``."""
    return not value <= bound + _allowance_value(bound)


def below_value(value: float, bound: float) -> bool:
    """:func:`below` of one Python float against one bound (as :func:`above_value`), a ``bool``."""
    return not value >= bound - _allowance_value(bound)


class Interval:
    """[``lower``, ``upper``] (numbers or arrays, e.g. per joint) with each end's allowance made once: its methods are
    the functions of the same names against these bounds (the same rule and results), for code that compares many
    values with the same bounds one at a time (a solver's iterations), where making the allowances would cost more
    than the comparisons."""

    __slots__ = ("_highest", "_lower_up", "_lowest", "_upper_down", "lower", "upper")

    def __init__(self, lower: ArrayLike, upper: ArrayLike) -> None:
        self.lower, self.upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
        self._lowest = np.subtract(self.lower, allowance(self.lower))  # below(·, lower): beyond this
        self._highest = np.add(self.upper, allowance(self.upper))  # above(·, upper)
        self._lower_up = np.add(self.lower, allowance(self.lower))  # above(·, lower)
        self._upper_down = np.subtract(self.upper, allowance(self.upper))  # below(·, upper)

    def outside(self, value: ArrayLike) -> NDArray[np.bool_]:
        """:func:`outside` ``(value, lower, upper)``."""
        return np.logical_or(np.logical_not(np.greater_equal(value, self._lowest)),
                             np.logical_not(np.less_equal(value, self._highest)))

    def above_upper(self, value: ArrayLike) -> NDArray[np.bool_]:
        """:func:`above` ``(value, upper)``."""
        return np.logical_not(np.less_equal(value, self._highest))

    def above_lower(self, value: ArrayLike) -> NDArray[np.bool_]:
        """:func:`above` ``(value, lower)``: off the lower bound, inwards (or NaN)."""
        return np.logical_not(np.less_equal(value, self._lower_up))

    def below_upper(self, value: ArrayLike) -> NDArray[np.bool_]:
        """:func:`below` ``(value, upper)``: off the upper bound, inwards (or NaN)."""
        return np.logical_not(np.greater_equal(value, self._upper_down))


def within(value: ArrayLike, lower: ArrayLike, upper: ArrayLike) -> NDArray[np.bool_]:
    """``value`` is in [``lower``, ``upper``], each end widened by its :func:`allowance` (not :func:`outside`;
    NaN: never), broadcast shape."""
    return np.logical_not(outside(value, lower, upper))


def tolerated(error: ArrayLike, tolerance: ArrayLike) -> NDArray[np.bool_]:
    """``error`` (≥ 0, e.g. |deviation|) is at most ``tolerance`` (> 0, the error's unit) up to the slack relative
    to the tolerance: error ≤ tolerance · (1 + SLACK) (NaN: never), broadcast shape."""
    return np.less_equal(error, np.multiply(tolerance, 1.0 + SLACK))


def clamp(value: ArrayLike, lower: ArrayLike, upper: ArrayLike) -> NDArray[np.float64]:
    """``value`` with each entry :func:`within` [``lower``, ``upper``] clipped into it (a value on a bound but
    round-off beyond it lands exactly on it); entries :func:`outside` (and NaN) are returned as they are, for the
    caller's check to report. Broadcast shape, float."""
    value = np.asarray(value, dtype=float)
    return np.where(within(value, lower, upper), np.clip(value, lower, upper), value)
