"""The one way a library arm is made: its source's DH table, limits and mass data through :func:`from_dh`.

The arm is a user's DH arm in every respect (the same URDF builder, frames and checks, :mod:`armlab.models.read_dh`),
named after its module, carrying its ``SOURCE`` as its citation (``Arm.paper``), a note per cited quantity
(``Arm.notes``, what ``armlab show`` prints) and its closed-form inverse kinematics where it has one.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace

import numpy as np

from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.ik_closed_form import ClosedForm
from armlab.models.arm import Arm
from armlab.models.read_dh import DHInertial, from_dh
from armlab.models.write_urdf import JointLimits

__all__ = ["degrees", "library_dh_arm"]


def degrees(lower: float, upper: float, effort: float | None = None, velocity_deg: float | None = None) -> JointLimits:
    """Revolute limits given in degrees (position, velocity in deg/s) as :class:`JointLimits` in rad, rad/s."""
    velocity = None if velocity_deg is None else float(np.radians(velocity_deg))
    return JointLimits(float(np.radians(lower)), float(np.radians(upper)), effort, velocity)


def library_dh_arm(name: str, source: str, convention: str, rows: Sequence[DHRow], limits: Sequence[JointLimits],
                   inertials: Sequence[DHInertial] | None, notes: Mapping[str, str], radii: Sequence[float],
                   home: Sequence[float], closed_form: Callable[[DHTable], ClosedForm] | None = None) -> Arm:
    """The library arm ``name``: DH ``rows`` (``convention`` standard or modified), ``limits``, ``inertials`` in the
    links' DH frames (``None``: a kinematic arm), cited by ``source`` and ``notes`` (what → where from); ``radii``
    (m) its links' collision capsules along their DH offsets (models/README.md gives each arm's and why; 0: none);
    ``home`` its source's rest pose (rad, m); ``closed_form`` makes its closed-form inverse kinematics from the table
    (:mod:`armlab.kinematics.ik_wrist`)."""
    table = DHTable(tuple(rows), "modified" if convention == "modified" else "standard")
    arm = from_dh(table, limits, inertials, radii, name=name)
    return replace(arm, paper=f"library: {source}", notes=dict(notes), home=tuple(float(v) for v in home),
                   closed_form=None if closed_form is None else closed_form(table))
