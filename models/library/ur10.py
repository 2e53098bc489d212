"""Universal Robots UR10 (CB3): standard DH, link masses and centres of mass from the same Universal Robots article
as the UR5 (:mod:`armlab.models.library.ur5`, table "UR10"), the numbers the Robotics Toolbox's
``roboticstoolbox.models.DH.UR10`` carries (cross-checked there).

As the UR5: point masses at the centres of mass (the toolbox defines inertia matrices for the UR10 but never hands
them to its links, and its link 6 matrix diag(0, 0.0004, 0.0003) breaks the triangle inequality: armlab does not use
them), link 6 a solid disc of radius :data:`FLANGE_RADIUS` (chosen) so that joint 6 has inertia. Position limits
±360° (UR data sheet); effort and velocity limits not in the source. Closed form:
:func:`armlab.kinematics.ik_wrist.ur_ik`, 8 branches.
"""

from __future__ import annotations

import numpy as np

from armlab.kinematics.dh import DHRow
from armlab.kinematics.ik_wrist import ur_closed_form
from armlab.models.arm import Arm
from armlab.models.library._dh_arm import degrees, library_dh_arm
from armlab.models.library.ur5 import disc
from armlab.models.read_dh import DHInertial

SOURCE = ("Universal Robots UR10 (CB3); DH, masses and centres of mass from Universal Robots, 'Parameters for "
          "calculations of kinematics and dynamics' (as the Robotics Toolbox's UR10); point masses but link 6, a "
          "disc of radius 0.045 m (chosen)")

#: (a m, α rad, d m) per joint, standard DH, θ offsets 0: Universal Robots' table for the UR10.
DH = ((0.0, np.pi / 2, 0.1273), (-0.612, 0.0, 0.0), (-0.5723, 0.0, 0.0), (0.0, np.pi / 2, 0.163941),
      (0.0, -np.pi / 2, 0.1157), (0.0, 0.0, 0.0922))
#: Link masses (kg), Universal Robots' table.
MASS = (7.1, 12.7, 4.27, 2.0, 2.0, 0.365)
#: Centres of mass (m) in each link's DH frame, Universal Robots' table (the toolbox's values).
COM = ((0.021, 0, 0.027), (0.38, 0, 0.158), (0.24, 0, 0.068), (0, 0.007, 0.018), (0, 0.007, 0.018), (0, 0, -0.026))
#: Link 6's disc radius (m): chosen, not from UR (the UR10 tool flange), so that joint 6 has inertia.
FLANGE_RADIUS = 0.045


def build() -> Arm:
    """The UR10 (see the module for every source and choice)."""
    inertials = [DHInertial(m, (float(c[0]), float(c[1]), float(c[2]))) for m, c in zip(MASS, COM, strict=True)]
    inertials[5] = DHInertial(MASS[5], inertials[5].com, disc(MASS[5], FLANGE_RADIUS))
    notes = {
        "kinematics": "standard DH, Universal Robots' 'Parameters for calculations of kinematics and dynamics' (UR10)",
        "limits": "±360° every joint (UR data sheet); effort and velocity limits not in the source",
        "masses": "UR's table: masses and centres of mass in the DH frames; point masses (the toolbox's inertia "
                  "matrices are unused there and link 6's is not physical)",
        "choice link 6": f"a solid disc of radius {FLANGE_RADIUS} m (the flange) so that joint 6 has inertia",
    }
    return library_dh_arm("ur10", SOURCE, "standard", [DHRow(a, alpha, d, 0.0) for a, alpha, d in DH],
                          [degrees(-360, 360)] * 6, inertials, notes, ur_closed_form)
