"""KUKA KR5 (arc): standard DH and joint limits as the Robotics Toolbox models it (``roboticstoolbox.models.DH.KR5``,
by Gautam Sinha, IIT Kanpur; numbers cross-checked there), from KUKA's KR 5 arc data sheet (lengths, axis ranges).

A kinematic arm: the toolbox gives no mass data and none is invented (``has_dynamics`` False: torques and
simulations are refused with a message saying so). The toolbox's KR5 adds an 11.5 cm tool in its notes but not in
its model; armlab's tool frame is DH frame 6 (the flange), as the toolbox's ``fkine``. No closed form here (its
wrist is spherical but its offsets differ from the Puma's layout): solved numerically.
"""

from __future__ import annotations

import numpy as np

from armlab.kinematics.dh import DHRow
from armlab.models.arm import Arm
from armlab.models.library._dh_arm import degrees, library_dh_arm

SOURCE = ("KUKA KR5 arc; standard DH and limits as the Robotics Toolbox's KR5 (KUKA data sheet); kinematic only "
          "(no published mass data)")

#: (a m, α rad, d m) per joint, standard DH, θ offsets 0: the toolbox's KR5.
DH = ((0.18, np.pi / 2, 0.4), (0.6, np.pi, 0.135), (0.12, -np.pi / 2, 0.135), (0.0, np.pi / 2, 0.62),
      (0.0, -np.pi / 2, 0.0), (0.0, 0.0, 0.0))
#: Joint limits (deg): the toolbox's qlim.
LIMITS_DEG = ((-155, 155), (-180, 65), (-110, 170), (-165, 165), (-140, 140), (-180, 180))


def build() -> Arm:
    """The KR5 (kinematic; see the module)."""
    notes = {"kinematics": "standard DH, the Robotics Toolbox's KR5 (KUKA KR 5 arc data sheet)",
             "limits": "the toolbox's qlim; effort and velocity limits not in the source",
             "masses": "none published: a kinematic arm"}
    return library_dh_arm("kr5", SOURCE, "standard", [DHRow(a, alpha, d, 0.0) for a, alpha, d in DH],
                          [degrees(lo, hi) for lo, hi in LIMITS_DEG], None, notes)
