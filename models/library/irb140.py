"""ABB IRB 140: standard DH and joint limits as the Robotics Toolbox models it (``roboticstoolbox.models.DH.IRB140``,
from ABB's IRB 140 data sheet and Djuric & Urbanic; numbers cross-checked there); velocity limits from ABB's data
sheet as ARTE (A Robotics Toolbox for Education, robots/ABB/IRB140/parameters.m) gives them: 200, 200, 260, 360,
360, 450 °/s.

A kinematic arm. The toolbox's IRB 140 mass data is not used, and why: it gives masses for links 1-3 only (the
wrist massless, so the mass matrix would be singular and nothing could be simulated), and two of its centres of mass
are unit slips — link 2's at (198.29, 9.73, 92.43)·10³ m (198 km; the ×1e03 was meant as ×1e-3, millimetres) and
link 3's at (−4.56, −79.96, −5.86) m (80 m; millimetres without the ×1e-3). ARTE's own IRB 140 dynamics say they
"do not correspond to the actual IRB 140". armlab invents none: ``has_dynamics`` False, torques and simulations are
refused with a message saying so. Joint 6 turns ±400°. Its closed form (a spherical wrist, a1 = 70 mm):
:func:`armlab.kinematics.ik_wrist.spherical_wrist_ik`, 8 branches.
"""

from __future__ import annotations

import numpy as np

from armlab.kinematics.dh import DHRow
from armlab.kinematics.ik_wrist import spherical_wrist_closed_form
from armlab.models.arm import Arm
from armlab.models.library._dh_arm import degrees, library_dh_arm

SOURCE = ("ABB IRB 140; standard DH and limits as the Robotics Toolbox's IRB140 (ABB data sheet), velocity limits "
          "ABB's as ARTE gives them; kinematic only (the toolbox's mass data has unit slips and no wrist masses)")

#: (a m, α rad, d m) per joint, standard DH, θ offsets 0: the toolbox's IRB140 (d1, a1, a2, d4, d6).
DH = ((0.070, -np.pi / 2, 0.352), (0.360, 0.0, 0.0), (0.0, -np.pi / 2, 0.0), (0.0, np.pi / 2, 0.380),
      (0.0, -np.pi / 2, 0.0), (0.0, 0.0, 0.065))
#: Joint limits (deg): the toolbox's qlim (ABB data sheet), and velocity limits (deg/s), ABB's as ARTE gives them.
LIMITS_DEG = ((-180, 180), (-100, 100), (-220, 60), (-200, 200), (-120, 120), (-400, 400))
VELOCITY_DEG = (200, 200, 260, 360, 360, 450)


#: Collision capsule radii (m) per link, along its DH offsets: models/README.md gives the reasoning.
RADII = (0.1, 0.07, 0.06, 0.05, 0.045, 0.03)
#: The rest pose (rad, m): models/README.md.
HOME = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def build() -> Arm:
    """The IRB 140 (kinematic; see the module)."""
    notes = {"kinematics": "standard DH, the Robotics Toolbox's IRB140 (ABB IRB 140 data sheet)",
             "limits": "position: the toolbox's qlim (joint 6 ±400°); velocity: ABB's, as ARTE's parameters.m",
             "masses": "not used: the toolbox's have centres of mass at 198 km and 80 m (unit slips) and none for "
                       "the wrist; a kinematic arm"}
    limits = [degrees(lo, hi, velocity_deg=v) for (lo, hi), v in zip(LIMITS_DEG, VELOCITY_DEG, strict=True)]
    return library_dh_arm("irb140", SOURCE, "standard", [DHRow(a, alpha, d, 0.0) for a, alpha, d in DH], limits,
                          None, notes, RADII, HOME, spherical_wrist_closed_form)
