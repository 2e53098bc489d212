"""What a paper arm has beyond its geometry, given to its :class:`~armlab.models.arm.Arm` by its own module.

* :class:`~armlab.kinematics.ik_closed_form.ClosedForm` — its paper's closed-form inverse kinematics
  (``Arm.closed_form``; rr, arm4r, r2t),
  which :func:`armlab.kinematics.ik.solve` uses instead of the numerical solver;
* :data:`MotionFn` — its paper motion (``Arm.motion``, what ``armlab simulate ARM`` runs) and named
  multi-segment paths (``Arm.paths``, rr's ``"abcd"``), run by :func:`armlab.planning.motions.paper_motion`;
* :class:`PaperScheme` — what ``armlab draw`` annotates (``Arm.scheme``): the paper figure the scheme
  reproduces, the DH table drawn and the pose drawn without ``--q``.

Generic code asks the arm for these, never its name: an arm built by a paper arm's module (whatever
its parameters) has them, a user's arm (a URDF or DH table, whatever its name) has none.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from armlab.kinematics.dh import DHTable
    from armlab.kinematics.quintic import Motion
    from armlab.models.arm import Arm

__all__ = ["MotionFn", "PaperScheme", "motion_start"]

#: A paper motion: ``(arm, tf)`` → the :class:`~armlab.kinematics.quintic.Motion`, checked against the arm's
#: limits; ``tf`` (s) overrides the paper's duration (per segment for a path), ``None`` keeps it.
MotionFn = Callable[["Arm", "float | None"], "Motion"]


@dataclass(frozen=True)
class PaperScheme:
    """What ``armlab draw`` shows of a paper arm beyond its model: ``figure``, the paper's figure of the
    scheme (for the title, "000 Fig. 1"); ``q``, ``arm`` → the pose drawn without ``--q`` (n,); ``dh``,
    the DH table drawn (``None``: the arm's locating table, paper 003)."""

    figure: str
    q: Callable[[Arm], NDArray[np.float64]]
    dh: DHTable | None = None


def motion_start(arm: Arm) -> NDArray[np.float64]:
    """The start (n,) of ``arm``'s paper motion: the pose a paper arm is drawn at (e.g. rr at (−38°, 98°), paper
    000 Fig. 3). ``ValueError`` for an arm without a paper motion."""
    if arm.motion is None:
        raise ValueError(f"{arm.name} has no paper motion")
    return np.asarray(arm.motion(arm, None).segments[0].q_start, dtype=float)
