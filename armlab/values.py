"""Values written as text (``"1,2.5,-3"``), as the command line and the files give them, checked and in SI.

Each function raises a one-line ``ValueError`` naming the bad item and what is allowed; ``name`` is how the
caller calls the value (an option such as ``"--q"``), quoted in the message.
"""

from __future__ import annotations

import math
import re
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.limits import NotRealError, allowed, check_range, real_number

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = [
    "DECIMAL",
    "GRAVITY_NAMES",
    "NOT_A_NUMBER",
    "NOT_FINITE",
    "SHOWN",
    "G",
    "check_payload",
    "cut",
    "decimal",
    "gravity_vector",
    "joint_rates",
    "joint_values",
    "parse_floats",
    "resolve_gravity",
    "shown",
]

#: The most characters of a user's value an error message echoes (:func:`shown`).
SHOWN = 60


def cut(text: str, limit: int = SHOWN) -> str:
    """``text`` cut to ``limit`` characters (``…`` marks the cut): an error line stays readable whatever the input
    (a 1 MB key, a 10⁷-row array)."""
    return text if len(text) <= limit else text[:limit - 1] + "…"  # not a bound: a count of characters


def shown(value: object, limit: int = SHOWN) -> str:
    """``repr(value)`` cut to ``limit`` characters (:func:`cut`)."""
    return cut(repr(value), limit)


#: A plain decimal number (``-0.5``, ``2``, ``1e-3``, ``.5``): what every number armlab reads from text may be (an
#: option, a DH table, a drive file, a catalogue cell). ``float`` also takes ``1_0`` (= 10), ``nan``, ``inf`` and other
#: scripts' digits (``١``); these are refused. ASCII digits (re's ``\d``: any script).
DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")

#: The reasons :func:`decimal` gives.
NOT_A_NUMBER = "is not a number"
NOT_FINITE = "is not a finite number"


def decimal(text: str) -> float:
    """``text`` (white space around it ignored) as a float if it is a plain decimal (:data:`DECIMAL`) and finite:
    the one rule for a number given as text. Else a ``ValueError`` whose text is the reason, :data:`NOT_FINITE`
    (``nan``, ``-inf``, ``1e309``) or :data:`NOT_A_NUMBER` (``1_0``, ``0x1``, ``ten``, not a string), for the caller
    to prefix with the value's name and the text as typed."""
    stripped = text.strip() if isinstance(text, str) else ""
    if not DECIMAL.fullmatch(stripped):
        try:
            finite = math.isfinite(float(stripped))
        except ValueError:
            finite = True
        raise ValueError(NOT_A_NUMBER if finite else NOT_FINITE)
    value = float(stripped)
    if not math.isfinite(value):  # 1e309, 400 digits
        raise ValueError(NOT_FINITE)
    return value


def parse_floats(text: str, name: str) -> list[float]:
    """``"1,2.5,-3"`` → ``[1.0, 2.5, -3.0]``: comma-separated plain decimals (:func:`decimal`); ValueError naming
    ``name`` and the bad item (text, ``1_0``, NaN, inf), or ``text`` if it is not a string."""
    if not isinstance(text, str):
        raise ValueError(f"{name}: {shown(text)} is not text: give comma-separated numbers")
    values = []
    for item in text.split(","):
        try:
            values.append(decimal(item))
        except ValueError as reason:
            hint = " (expected comma-separated plain decimals, e.g. 0.5,-2,1e-3)" if str(reason) == NOT_A_NUMBER else ""
            raise ValueError(f"{name}: {item.strip()!r} {reason}{hint}") from None
    return values


def _per_joint(arm: Arm, text: str, name: str) -> np.ndarray:
    """``"v1,v2,…"`` as one value per joint of ``arm``, (n,); ValueError for a wrong count."""
    values = np.array(parse_floats(text, name))
    if values.size != arm.n:
        raise ValueError(f"{name}: {arm.name} has {arm.n} joints, got {values.size} values ({text})")
    return values


def joint_values(arm: Arm, text: str, deg: bool = False, name: str = "--q") -> np.ndarray:
    """Joint values (n,) from ``"v1,v2,…"``: count checked, revolute values converted from degrees if
    ``deg`` (prismatic values stay metres), and checked against the joint limits (rad, m)."""
    values = _per_joint(arm, text, name)
    if deg:
        values = np.where(arm.revolute, np.radians(values), values)
    return arm.check_q(values, name, deg)


def joint_rates(arm: Arm, text: str | None, deg: bool, name: str) -> np.ndarray:
    """Joint rates (n,) from ``"v1,v2,…"`` (zeros when ``text`` is None): count checked, revolute values
    converted from deg/s (deg/s² for ``--qdd``) if ``deg``, and checked against :data:`armlab.limits.LIMITS`
    (rad/s and m/s, or rad/s² and m/s²)."""
    if text is None:
        return np.zeros(arm.n)
    values = _per_joint(arm, text, name)
    return check_range(np.where(arm.revolute, np.radians(values), values) if deg else values, name,
                       key="qdd" if name == "--qdd" else "qd")


#: Standard gravity (m/s²), the magnitude of every arm's default gravity.
G = 9.81

#: Named gravity settings: "off", and a direction of magnitude G along a base axis.
GRAVITY_NAMES = ("default", "off", "+x", "-x", "+y", "-y", "+z", "-z")


def resolve_gravity(arm: Arm, gravity: str | ArrayLike | None = None) -> NDArray[np.float64]:
    """The gravity vector (m/s², base frame) for ``gravity`` (see :func:`gravity_vector`); ``None`` or
    ``"default"`` → the arm's default (rr: −y, the vertical plane of paper 000's Adams model; the others: −z)."""
    g = gravity_vector(gravity)
    return np.asarray(arm.gravity, dtype=float) if g is None else g


def gravity_vector(gravity: str | ArrayLike | None) -> NDArray[np.float64] | None:
    """The gravity vector (m/s², base frame) for ``gravity``, ``None`` for the arm's own.

    ``None`` or ``"default"`` → ``None``; ``"off"`` → zero; ``"+x"`` … ``"-z"`` → 9.81 m/s² along that
    base axis; or three numbers (a sequence, or text ``"gx,gy,gz"``). ``ValueError`` for anything else.
    """
    if gravity is None:
        return None
    if isinstance(gravity, str):
        text = gravity.strip().lower()
        if text == "default":
            return None
        if text == "off":
            return np.zeros(3)
        if text in GRAVITY_NAMES:
            g = np.zeros(3)
            g["xyz".index(text[1])] = G if text[0] == "+" else -G
            return g

        try:
            values = parse_floats(gravity, "--gravity")
        except ValueError as error:
            raise ValueError(f"{error}; or one of {', '.join(GRAVITY_NAMES)}") from None
        gravity = values

    g = np.asarray(gravity, dtype=float)
    if g.shape != (3,) or not np.all(np.isfinite(g)):
        raise ValueError(f"gravity {np.ravel(g).tolist()} is not allowed: give 3 finite numbers gx,gy,gz (m/s²) "
                         f"or one of {', '.join(GRAVITY_NAMES)}")
    return check_range(g, "gravity", math.hypot(*g))


def check_payload(payload: float, name: str = "payload") -> float:
    """``payload`` (kg) as a float; ``ValueError`` (naming it ``name``) unless it is a mass in
    :data:`armlab.limits.LIMITS`' range."""
    if isinstance(payload, str):
        raise NotRealError(f"{name} {shown(payload)} is not allowed: a payload is a mass, {allowed('payload')}")
    return float(check_range(real_number(payload, name), name))
