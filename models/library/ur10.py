"""Universal Robots UR10 (CB3): standard DH, link masses, centres of mass and inertia matrices as Universal Robots
publishes them, "Parameters for calculations of kinematics and dynamics" (universal-robots.com support article, table
"UR10"), the numbers the Robotics Toolbox 1.5's ``roboticstoolbox.models.DH.UR10`` carries (cross-checked there).

Standard DH, base frame at the mounting flange, tool frame DH frame 6 (the tool flange). Centres of mass and inertias
(about the centre of mass, DH-frame axes) are in each link's DH frame. One number is not physical: link 6's inertia
diag(0, 0.0004, 0.0003) kg·m² breaks the triangle inequality (0 + 0.0003 < 0.0004; the toolbox notes it as UR's own
and that it makes the mass matrix near-singular). armlab raises its Ixx to 0.00011 kg·m²: the least physical value,
0.0001 (Iyy − Izz, on the inequality, which MuJoCo refuses once rounded to binary), plus a margin of 1e-5 kg·m².
**Effect**: gravity torques none (inertia does not enter them); the mass matrix's entries within 0.00011 kg·m² of the
toolbox's. Position limits ±360° (UR data sheet); velocity 120°/s joints 1-2, 180°/s joints 3-6 (UR10/CB3 User
Manual's technical specifications); effort 330, 330, 150, 56, 56, 56 N·m (UR's support article "Max. joint torques";
both as UR's own ROS description, ``Universal_Robots_ROS2_Description`` config/ur10/joint_limits.yaml). Closed form:
:func:`armlab.kinematics.ik_wrist.ur_ik`, 8 branches.
"""

from __future__ import annotations

import numpy as np

from armlab.kinematics.dh import DHRow
from armlab.kinematics.ik_wrist import ur_closed_form
from armlab.models.arm import Arm
from armlab.models.library._dh_arm import degrees, library_dh_arm
from armlab.models.read_dh import DHInertial

SOURCE = ("Universal Robots UR10 (CB3); DH, masses, centres of mass and inertias from Universal Robots, 'Parameters "
          "for calculations of kinematics and dynamics' (as the Robotics Toolbox's UR10); link 6's inertia corrected "
          "to be physical (no effect on gravity torques)")

#: (a m, α rad, d m) per joint, standard DH, θ offsets 0: Universal Robots' table for the UR10.
DH = ((0.0, np.pi / 2, 0.1273), (-0.612, 0.0, 0.0), (-0.5723, 0.0, 0.0), (0.0, np.pi / 2, 0.163941),
      (0.0, -np.pi / 2, 0.1157), (0.0, 0.0, 0.0922))
#: Joint torque limits (N·m), Universal Robots' support article "Max. joint torques" (UR10).
EFFORT = (330.0, 330.0, 150.0, 56.0, 56.0, 56.0)
#: Joint speed limits (deg/s), the UR10/CB3 User Manual's technical specifications.
SPEED_DEG = (120.0, 120.0, 180.0, 180.0, 180.0, 180.0)
#: Link masses (kg), Universal Robots' table.
MASS = (7.1, 12.7, 4.27, 2.0, 2.0, 0.365)
#: Centres of mass (m) in each link's DH frame, Universal Robots' table.
COM = ((0.021, 0, 0.027), (0.38, 0, 0.158), (0.24, 0, 0.068), (0, 0.007, 0.018), (0, 0.007, 0.018), (0, 0, -0.026))
#: Inertia matrices (kg·m², about the centre of mass, DH-frame axes), Universal Robots' table; link 6's Ixx (0
#: there) corrected to 0.00011 (see the module).
INERTIA = (((0.0341, 0, -0.0043), (0, 0.0353, 0.0001), (-0.0043, 0.0001, 0.0216)),
           ((0.0281, 0.0001, -0.0156), (0.0001, 0.7707, 0), (-0.0156, 0, 0.7694)),
           ((0.0101, 0.0001, 0.0092), (0.0001, 0.3093, 0), (0.0092, 0, 0.3065)),
           ((0.0030, 0, 0), (0, 0.0022, -0.0002), (0, -0.0002, 0.0026)),
           ((0.0030, 0, 0), (0, 0.0022, -0.0002), (0, -0.0002, 0.0026)),
           ((0.00011, 0, 0), (0, 0.0004, 0), (0, 0, 0.0003)))
#: The source's own value where armlab corrects it: (link, (Ixx, Iyy, Izz) kg·m²).
SOURCE_VALUES = ((6, (0.0, 0.0004, 0.0003)),)


#: Collision capsule radii (m) per link, along its DH offsets: models/README.md gives the reasoning.
RADII = (0.095, 0.075, 0.06, 0.05, 0.05, 0.045)
#: The rest pose (rad, m): models/README.md.
HOME = (0.0, -np.pi / 2, 0.0, -np.pi / 2, 0.0, 0.0)


def build() -> Arm:
    """The UR10 (see the module for every source and the correction)."""
    inertials = [DHInertial(m, (float(c[0]), float(c[1]), float(c[2])), inertia)
                 for m, c, inertia in zip(MASS, COM, INERTIA, strict=True)]
    notes = {
        "kinematics": "standard DH, Universal Robots' 'Parameters for calculations of kinematics and dynamics' (UR10)",
        "limits": "±360° every joint; 120, 120, 180, 180, 180, 180 °/s (UR10/CB3 User Manual); effort 330, 330, 150, "
                  "56, 56, 56 N·m (UR, 'Max. joint torques')",
        "masses": "UR's table: masses, centres of mass and inertias in the DH frames",
        "correction link 6": "Ixx 0 → 0.00011 kg·m² (triangle inequality, with a 1e-5 margin); gravity torques "
                             "unchanged",
    }
    return library_dh_arm("ur10", SOURCE, "standard", [DHRow(a, alpha, d, 0.0) for a, alpha, d in DH],
                          [degrees(-360, 360, effort, speed) for effort, speed in zip(EFFORT, SPEED_DEG, strict=True)],
                          inertials, notes, RADII, HOME, ur_closed_form)
