"""The ranges armlab accepts for its physical quantities, in one table.

A value outside its range is refused before any work, with a one-line ``ValueError`` naming the
value, the range and the reason (:func:`check_range`): a finite but absurd number (a gain of
1e308, gravity of 1e308 m/s², a payload of a thousand tonnes) would otherwise overflow, stall
the integrator or end in a run that leaves its reference. The options' help texts quote the same
bounds (:func:`allowed`).

These are checks of the values a user gives (typed, or in a file), not of computed ones: the ranges are orders of
magnitude beyond any physical value, so a value is compared with them exactly, without the slack that
:mod:`armlab.bounds` applies to a computed value against a physical bound (a joint limit, a tolerance).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["LIMITS", "Limit", "NotRealError", "allowed", "check_count", "check_positive", "check_range", "real_array",
           "real_number",
           "whole_text"]


class NotRealError(TypeError, ValueError):
    """A value that is not a real number (a bool, a complex or a string, or an array of them) where one is needed.

    A ``TypeError`` (the value's type is wrong) that is also a ``ValueError``, so that everything catching armlab's
    one-line input errors catches it too."""


_REAL_KINDS = "iuf"  # numpy dtype kinds of real numbers: signed and unsigned integers, floats


def real_array(value: ArrayLike, name: str) -> NDArray[np.float64]:
    """``value`` as a float array if its dtype is a real number's; :class:`NotRealError` naming ``name`` and the dtype
    for bools, complex numbers, strings and objects (numpy would drop an imaginary part or read ``True`` as 1)."""
    a = np.asarray(value)
    if a.dtype.kind not in _REAL_KINDS:
        raise NotRealError(f"{name}: expected real numbers, got dtype {a.dtype}")
    return a.astype(float)


def per_joint(value: ArrayLike, n: int, name: str) -> NDArray[np.float64]:
    """``value`` as one real number per joint, ``(n,)``: one number (or a list of one) for every joint, or ``n``;
    ``ValueError`` naming ``name`` and the count otherwise (:class:`NotRealError` for what is not real)."""
    a = real_array(value, name)
    a = np.full(n, a.item()) if a.size == 1 else a
    if a.shape != (n,):
        raise ValueError(f"{name} has {a.size} values; give one, or one per joint ({n})")
    return a


def real_number(value: Any, name: str) -> float:
    """``value`` as a float if it is one real number (an int or float, numpy's too; not a bool or a string);
    :class:`NotRealError` naming ``name`` and the type otherwise."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, int | float | np.integer | np.floating):
        raise NotRealError(f"{name}: expected a real number, got {type(value).__name__}")
    return float(value)


@dataclass(frozen=True)
class Limit:
    """``low ≤ value ≤ high`` in ``unit``; ``why`` says where the bounds come from; ``symbol`` names the value."""

    low: float
    high: float
    unit: str
    why: str
    symbol: str = ""


#: The accepted range of each quantity, by name (an option's name without its dashes).
LIMITS: dict[str, Limit] = {
    "kp": Limit(0.0, 1e6, "1/s²", "error dynamics up to 1000 rad/s"),
    "kd": Limit(0.0, 1e4, "1/s", "error dynamics up to 1000 rad/s"),
    "ki": Limit(0.0, 1e8, "1/s³", "error dynamics up to 1000 rad/s"),
    "gravity": Limit(0.0, 100.0, "m/s²", "about 10 g", "|g|"),
    "payload": Limit(0.0, 1000.0, "kg", "a point mass up to one tonne"),
    "accuracy": Limit(1e-12, 0.1, "", "the integrator's target accuracy"),
    "q": Limit(-1e6, 1e6, "rad or m", "beyond any joint's travel", "q"),
    "coordinate": Limit(-1e6, 1e6, "m", "no arm is a thousand kilometres long", "x, y, z"),
    "angle": Limit(-1e6, 1e6, "rad", "2π shifts keep such an angle exact to 1e-10 rad"),
    "qd": Limit(-1e4, 1e4, "rad/s or m/s", "beyond any drive's speed", "q̇"),
    "qdd": Limit(-1e6, 1e6, "rad/s² or m/s²", "beyond any drive's acceleration", "q̈"),
    "resolution": Limit(1e-6, 100.0, "m", "a workspace's voxel edge, a micrometre to 100 m", "h"),
    "tf": Limit(1e-6, 1e6, "s", "a motion's duration, a microsecond to 11 days", "tf"),
    "dwell": Limit(0.0, 1e6, "s", "a rest in a duty cycle, none to 11 days", "dwell"),
    "rate": Limit(1.0, 1e6, "Hz", "a sampled controller's rate, 1 Hz to 1 MHz"),
    "bandwidth": Limit(1e-3, 1e5, "Hz", "a control loop's bandwidth"),
    "encoder": Limit(2.0, 2.0**31 - 1, "counts/rev", "an encoder's counts per revolution"),
    "noise": Limit(0.0, 1.0, "rad or m", "a position sensor's noise, standard deviation"),
    "delay": Limit(0.0, 1000.0, "samples", "a measurement's delay, in controller samples"),
    "seed": Limit(0.0, 2.0**32 - 1, "", "a random generator's seed"),
    "samples": Limit(2.0, 1e5, "", "IK points along a tool path; 1e5 take about 5 s"),
    "grid": Limit(3.0, 1e5, "", "Toppra's grid points along a path; 1e5 take about 25 s"),
    "velocity_limit": Limit(1e-6, 1e4, "rad/s or m/s", "a joint's speed limit, as q̇'s range", "limit"),
    "acceleration_limit": Limit(1e-6, 1e6, "rad/s² or m/s²", "a joint's acceleration limit, as q̈'s range", "limit"),
    "effort_limit": Limit(1e-6, 1e9, "N·m or N", "a joint's effort limit, a micro- to a giganewton(-metre)", "limit"),
    "motor_speed_limit": Limit(1e-6, 1e5, "rad/s", "a motor's speed limit, up to about 1e6 rpm", "limit"),
    "motor_torque_limit": Limit(1e-6, 1e6, "N·m", "a motor's torque limit", "limit"),
    "sample_rate": Limit(1.0, 1e4, "Hz", "samples per second of motion for sizing drives", "rate"),
    "safety_factor": Limit(1.0, 100.0, "", "a sizing's oversizing of every torque, 1: none", "S"),
    "inertia": Limit(0.0, 1e6, "kg·m²", "a payload's inertia, its largest element; a tonne at a metre is 1e3",
                     "|I|"),
    "viscous": Limit(0.0, 1e4, "N·m·s/rad", "a joint's viscous friction, joint side: a stiffer damper than the "
                     "simulation's explicit integrator can follow", "B"),
    "catalogue": Limit(1e-12, 1e12, "", "a datasheet's number > 0, in its column's unit", "value"),
}


def _key(name: str) -> str:
    return name.lstrip("-")


def _num(value: float) -> str:
    """``1e+06`` → ``1e6``: a number as short text."""
    return re.sub(r"e([+-])0*(\d)", lambda m: f"e{'-' if m[1] == '-' else ''}{m[2]}", f"{value:.6g}")


def whole_text(value: float) -> str:
    """A whole number as short text: ``1e9`` where that is exact, else all its digits (``4294967295``)."""
    text = _num(float(value))
    return text if float(text) == value else str(int(value))


def allowed(name: str) -> str:
    """``"0 ≤ kp ≤ 1e6 1/s²"``: the range of quantity ``name`` (``"kp"`` or ``"--kp"``) as text."""
    limit = LIMITS[_key(name)]
    unit = f" {limit.unit}" if limit.unit else ""
    return f"{_num(limit.low)} ≤ {limit.symbol or _key(name)} ≤ {_num(limit.high)}{unit}"


def check_range(value: ArrayLike, name: str, size: ArrayLike | None = None, key: str | None = None
                ) -> NDArray[np.float64]:
    """``value`` as a float array if each value (or ``size``, e.g. a vector's norm, when given) is finite and in range.

    ``name`` is the quantity's name in :data:`LIMITS`, with or without the option's dashes (the
    message uses it as given), or ``key`` is (then ``name`` may be any label, e.g. ``"--from"`` for ``"q"``).
    ``ValueError`` names the first bad value, the range and its reason.
    """
    values = real_array(value, name)
    measured = np.ravel(values if size is None else real_array(size, name))
    key = name if key is None else key
    limit = LIMITS[_key(key)]
    bad = ~(np.isfinite(measured) & (measured >= limit.low) & (measured <= limit.high))  # not a bound: a user's value
    if np.any(bad):
        worst = float(measured[np.argmax(bad)])
        first = _num(worst)
        if limit.low <= float(first) <= limit.high:  # not a bound: rounded onto or into the range (1000.001 → 1000)
            first = repr(worst)  # shown in full, so that the value refused never reads as an allowed one
        given = first if size is None else f"{','.join(_num(v) for v in np.ravel(values))} ({limit.symbol} = {first})"
        raise ValueError(f"{name} {given} is out of range: allowed {allowed(key)} ({limit.why})")
    return values


def check_count(value: Any, name: str, key: str | None = None) -> int:
    """``value`` as an int if it is a whole number (an int or a float without a fraction, numpy's too; not a bool)
    within its range in :data:`LIMITS` (``name``'s, or ``key``'s as :func:`check_range` reads them): a count such as
    IK samples or grid points, bounded so that the work and memory it sets stay bounded. ``ValueError`` naming
    ``name``, the value and the range (:class:`NotRealError` for what is not a number)."""
    number = real_number(value, name)
    if not number.is_integer():  # NaN and ±inf are not whole either
        limit = LIMITS[_key(name if key is None else key)]
        raise ValueError(f"{name} {_num(number)} is not a whole number: allowed {allowed(name if key is None else key)}"
                         f" ({limit.why})")
    check_range(number, name, key=key)
    return int(number)


def check_positive(value: Any, what: str, unit: str, allowed_text: str) -> float:
    """``value`` as a float if it is a positive finite number (a duration, a tolerance, a resolution …).

    Else ``ValueError`` ``"WHAT = VALUE UNIT is not allowed: ALLOWED_TEXT"``; text that is no number counts as bad.
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not math.isfinite(number) or number <= 0:
        raise ValueError(f"{what} = {value}{' ' + unit if unit else ''} is not allowed: {allowed_text}")
    return number
