"""What a paper arm has beyond its geometry, given to its :class:`~armlab.models.arm.Arm` by its own module.

* :class:`ClosedForm` — its paper's closed-form inverse kinematics (``Arm.closed_form``; rr, arm4r, r2t),
  which :func:`armlab.kinematics.ik.solve` uses instead of the numerical solver;
* :data:`MotionFn` — its paper motion (``Arm.motion``, what ``armlab simulate ARM`` runs) and named
  multi-segment paths (``Arm.paths``, rr's ``"abcd"``), run by :func:`armlab.diagrams.motions.paper_motion`;
* :class:`PaperScheme` — what ``armlab draw`` annotates (``Arm.scheme``): the paper figure the scheme
  reproduces, the DH table drawn and the pose drawn without ``--q``.

Generic code asks the arm for these, never its name: an arm built by a paper arm's module (whatever
its parameters) has them, a user's arm (a URDF or DH table, whatever its name) has none.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from armlab.kinematics.dh import DHTable
    from armlab.kinematics.quintic import Motion
    from armlab.models.arm import Arm

__all__ = ["ClosedForm", "MotionFn", "PaperScheme", "motion_start"]

#: A paper motion: ``(arm, tf)`` → the :class:`~armlab.kinematics.quintic.Motion`, checked against the arm's
#: limits; ``tf`` (s) overrides the paper's duration (per segment for a path), ``None`` keeps it.
MotionFn = Callable[["Arm", "float | None"], "Motion"]


@dataclass(frozen=True)
class ClosedForm:
    """A paper's closed-form inverse kinematics of one arm, its parameters bound.

    ``solve(position, rotation, near, **options)`` gives every branch reaching the tool position
    ``position`` (3,) m, shape ``(len(branches), n)``, in the order of ``branches``, not fitted into the
    joint limits; ``rotation`` (3, 3) (a pose target) or ``None`` and ``near`` (n,) are there for a
    closed form that uses them (arm4r reads θ1 and its pitch off the rotation; on the z0 axis its θ1 is
    ``near``'s); ``ValueError`` for an unreachable position. The dispatcher keeps the branches whose
    orientation matches a pose target.
    """

    solve: Callable[..., NDArray[np.float64]]
    #: What each branch is, in ``solve``'s order (their number is the branch count): rr ("θ2 ≥ 0", "θ2 ≤ 0").
    branches: tuple[str, ...]
    #: Extra keyword arguments ``solve`` takes, and what each is: arm4r {"pitch": "its tool pitch θ2+θ3+θ4"}.
    options: Mapping[str, str] = field(default_factory=dict)
    #: A position target as the user gives it → the coordinates the closed form takes, the rest of the tool
    #: position being 0 (rr: x,y or x,y,0 → (x, y)); ``None``: x, y, z.
    coordinates: Callable[[NDArray], NDArray[np.float64]] | None = None
    #: Whether a user may choose a branch by its number (rr: paper 000's Table 2 names the elbow of each point).
    selectable: bool = False
    #: Whether it solves a full pose only (a six-axis arm's: ``rotation`` must be given); a position target is then
    #: solved as :func:`armlab.kinematics.ik.solve` says for a continuum.
    needs_pose: bool = False


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
