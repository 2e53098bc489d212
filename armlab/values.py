"""Values written as text (``"1,2.5,-3"``), as the command line and the files give them, checked and in SI.

Each function raises a one-line ``ValueError`` naming the bad item and what is allowed; ``name`` is how the
caller calls the value (an option such as ``"--q"``), quoted in the message.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from armlab.limits import check_range

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["SHOWN", "cut", "joint_rates", "joint_values", "parse_floats", "shown"]

#: The most characters of a user's value an error message echoes (:func:`shown`).
SHOWN = 60


def cut(text: str, limit: int = SHOWN) -> str:
    """``text`` cut to ``limit`` characters (``…`` marks the cut): an error line stays readable whatever the input
    (a 1 MB key, a 10⁷-row array)."""
    return text if len(text) <= limit else text[:limit - 1] + "…"  # not a bound: a count of characters


def shown(value: object, limit: int = SHOWN) -> str:
    """``repr(value)`` cut to ``limit`` characters (:func:`cut`)."""
    return cut(repr(value), limit)


def parse_floats(text: str, name: str) -> list[float]:
    """``"1,2.5,-3"`` → ``[1.0, 2.5, -3.0]``; ValueError naming the bad item (text, NaN, inf)."""
    values = []
    for item in text.split(","):
        try:
            value = float(item)
        except ValueError:
            raise ValueError(f"{name}: {item.strip()!r} is not a number (expected comma-separated numbers)") from None
        if not math.isfinite(value):
            raise ValueError(f"{name}: {item.strip()!r} is not a finite number")
        values.append(value)
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
