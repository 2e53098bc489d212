"""A one-joint planar arm defined only here: a paper arm is its own module and nothing else.

Importing this module registers the arm ``arm1r`` (:func:`armlab.models.register`); no other module
knows it. One link of length L turns about z at the base; its tip T is (L cos q, L sin q, 0). Its
extras: a closed form, q = atan2(y, x) on the circle |(x, y)| = L in z = 0 (one branch); a "paper
motion", a quarter turn; a scheme, "test Fig. 1" with its one-row DH table. ``tests/test_arm_extras.py``
loads, solves, moves and draws it through the generic code.
"""

from __future__ import annotations

import sys
from dataclasses import asdict, dataclass
from functools import partial

import numpy as np
from numpy.typing import NDArray

from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.ik_closed_form import ClosedForm
from armlab.kinematics.quintic import Motion, QuinticSegment, check_duration
from armlab.models import register
from armlab.models.arm import Arm, chosen, parameter_notes
from armlab.models.extras import PaperScheme
from armlab.models.write_urdf import Body, JointLimits, Point

PAPER = "test: a one-joint arm of tests/arm1r.py"
#: Where the quarter turn starts and ends (rad).
TURN = (-np.pi / 4, np.pi / 4)


@dataclass(frozen=True)
class Parameters:
    """The link's length and mass (SI)."""

    L: float = chosen(0.5, "a test arm")
    m: float = chosen(1.0, "a test arm")


def dh_table(p: Parameters) -> DHTable:
    """Standard DH: a = L."""
    return DHTable((DHRow(p.L, 0.0, 0.0, 0.0),), "standard")


def inverse(p: Parameters, position: NDArray, rotation: NDArray | None, near: NDArray) -> NDArray[np.float64]:
    """The one branch ``(1, 1)``: q = atan2(y, x); ``ValueError`` off the circle of radius L in z = 0 (1e-12 L)."""
    x, y, z = position
    if abs(np.hypot(x, y) - p.L) > 1e-12 * p.L or abs(z) > 1e-12 * p.L:
        raise ValueError(f"target {position.tolist()} is out of reach of arm1r: its tip moves on the circle of "
                         f"radius {p.L:g} m in z = 0")
    return np.array([[np.arctan2(y, x)]])


def quarter_turn(arm: Arm, tf: float | None = None) -> Motion:
    """q from −45° to +45°, rest to rest in ``tf`` s (default 1 s)."""
    tf = 1.0 if tf is None else check_duration(tf)
    motion = Motion((QuinticSegment(np.array([TURN[0]]), np.array([TURN[1]]), tf, "quarter"),),
                    f"test: a quarter turn in {tf:g} s")
    motion.check_limits(arm)
    return motion


def build(**overrides: float) -> Arm:
    """The one-joint arm; keyword arguments override :class:`Parameters` by name."""
    p = Parameters(**overrides)
    return Arm(
        name="arm1r",
        paper=PAPER,
        parameters=asdict(p),
        notes=parameter_notes(p),
        table=dh_table(p).locating_table(),
        bodies=(Body(p.m, 0.02, (0.85, 0.45, 0.1, 1)),),
        limits=(JointLimits(-np.pi, np.pi, effort=10.0, velocity=5.0),),
        points=(Point("T", 2, (0.0, 0.0, 0.0)),),
        tool_name="T",
        gravity=(0.0, 0.0, -9.81),
        closed_form=ClosedForm(partial(inverse, p), ("the only one",)),
        motion=quarter_turn,
        scheme=PaperScheme("test Fig. 1", lambda arm: np.array([TURN[1]]), dh_table(p)),
    )


register(sys.modules[__name__])
