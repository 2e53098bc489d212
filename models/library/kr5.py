"""KUKA KR5 (arc): standard DH and joint limits as the Robotics Toolbox 1.5 models it
(``roboticstoolbox.models.DH.KR5``, by Gautam Sinha, IIT Kanpur, updated from ARTE's
robots/KUKA/KR5_arc/parameters.m; numbers cross-checked there).

A kinematic arm: the toolbox gives no mass data and none is invented (``has_dynamics`` False: torques and
simulations are refused with a message saying so). The toolbox's last row includes its 11.5 cm tool along z
(d6 = −0.115 m with α6 = 180°): armlab's tool frame is that DH frame 6, as the toolbox's ``fkine``. Its closed form
(a spherical wrist): :func:`armlab.kinematics.ik_wrist.spherical_wrist_ik`, 8 branches.
"""

from __future__ import annotations

import numpy as np

from armlab.kinematics.dh import DHRow
from armlab.kinematics.ik_wrist import spherical_wrist_closed_form
from armlab.models.arm import Arm
from armlab.models.library._dh_arm import degrees, library_dh_arm

SOURCE = ("KUKA KR5 arc; standard DH and limits as the Robotics Toolbox 1.5's KR5 (from ARTE's KR5_arc parameters), "
          "its 11.5 cm tool included; kinematic only (no published mass data)")

#: (a m, α rad, d m) per joint, standard DH, θ offsets 0: the toolbox 1.5's KR5.
DH = ((0.18, -np.pi / 2, 0.4), (0.6, 0.0, 0.0), (0.12, np.pi / 2, 0.0), (0.0, -np.pi / 2, -0.62),
      (0.0, np.pi / 2, 0.0), (0.0, np.pi, -0.115))
#: Joint limits (deg): the toolbox 1.5's qlim.
LIMITS_DEG = ((-155, 155), (-180, 65), (-15, 158), (-350, 350), (-130, 130), (-350, 350))


#: Collision capsule radii (m) per link, along its DH offsets: models/README.md gives the reasoning.
RADII = (0.1, 0.07, 0.06, 0.05, 0.045, 0.03)
#: The rest pose (rad, m): models/README.md.
HOME = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def build() -> Arm:
    """The KR5 (kinematic; see the module)."""
    notes = {"kinematics": "standard DH, the Robotics Toolbox 1.5's KR5 (ARTE's KR5_arc), its 11.5 cm tool included",
             "limits": "the toolbox's qlim; effort and velocity limits not in the source",
             "masses": "none published: a kinematic arm"}
    return library_dh_arm("kr5", SOURCE, "standard", [DHRow(a, alpha, d, 0.0) for a, alpha, d in DH],
                          [degrees(lo, hi) for lo, hi in LIMITS_DEG], None, notes, RADII, HOME,
                          spherical_wrist_closed_form)
