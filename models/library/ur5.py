"""Universal Robots UR5 (CB3): standard DH and link masses and centres of mass as Universal Robots publishes them,
"Parameters for calculations of kinematics and dynamics" (universal-robots.com support article, table "UR5"), the
numbers the Robotics Toolbox's ``roboticstoolbox.models.DH.UR5`` carries (cross-checked there).

Standard DH, base frame at the base's mounting flange, tool frame DH frame 6 (the tool flange). Centres of mass are
in each link's DH frame. UR publishes no inertias for the CB3 arms: the links are **point masses** at their centres
of mass, as in the toolbox — except link 6, whose centre of mass lies on joint 6's own axis: as a point mass its
inertia about that axis would be 0, the mass matrix singular and no simulation possible. armlab gives link 6 the
inertia of a solid disc of its mass, radius :data:`FLANGE_RADIUS` (chosen, not from UR: the tool flange's radius),
about its axis, Izz = m r²/2, and half that about x and y. **Effect**: Izz = m r²/2 = 1.33e-4 kg·m² (a diagonal entry
of the mass matrix the toolbox has as 0); the torques change by that inertia times the link's angular acceleration.

Position limits ±360° (UR's data sheet: working range ±360° on every joint); velocity 180°/s every joint (UR5/CB3
User Manual's technical specifications); effort 150 N·m joints 1-3, 28 N·m joints 4-6 (UR's support article
"Max. joint torques"; both as UR's own ROS description, ``Universal_Robots_ROS2_Description`` config/ur5/
joint_limits.yaml, carries them). d1 = 0.089159 m, UR's own DH table (the toolbox has 0.089459). Its closed form:
:func:`armlab.kinematics.ik_wrist.ur_ik`, 8 branches.
"""

from __future__ import annotations

import numpy as np

from armlab.kinematics.dh import DHRow
from armlab.kinematics.ik_wrist import ur_closed_form
from armlab.models.arm import Arm
from armlab.models.library._dh_arm import degrees, library_dh_arm
from armlab.models.read_dh import DHInertial

SOURCE = ("Universal Robots UR5 (CB3); DH, masses and centres of mass from Universal Robots, 'Parameters for "
          "calculations of kinematics and dynamics' (as the Robotics Toolbox's UR5); point masses (UR publishes no "
          "inertias) but link 6, a disc of radius 0.0375 m (chosen)")

#: (a m, α rad, d m) per joint, standard DH, θ offsets 0: Universal Robots' table for the UR5.
DH = ((0.0, np.pi / 2, 0.089159), (-0.425, 0.0, 0.0), (-0.39225, 0.0, 0.0), (0.0, np.pi / 2, 0.10915),
      (0.0, -np.pi / 2, 0.09465), (0.0, 0.0, 0.0823))
#: Joint torque limits (N·m), Universal Robots' support article "Max. joint torques" (UR5).
EFFORT = (150.0, 150.0, 150.0, 28.0, 28.0, 28.0)
#: Link masses (kg), Universal Robots' table.
MASS = (3.7, 8.393, 2.33, 1.219, 1.219, 0.1897)
#: Centres of mass (m) in each link's DH frame, Universal Robots' table (the toolbox's values).
COM = ((0, -0.02561, 0.00193), (0.2125, 0, 0.11336), (0.15, 0, 0.0265), (0, -0.0018, 0.01634),
       (0, -0.0018, 0.01634), (0, 0, -0.001159))
#: Link 6's disc radius (m): chosen, not from UR (the UR5 tool flange, ⌀ 75 mm), so that joint 6 has inertia.
FLANGE_RADIUS = 0.0375


#: Collision capsule radii (m) per link, along its DH offsets: models/README.md gives the reasoning.
RADII = (0.075, 0.06, 0.05, 0.045, 0.045, 0.0375)
#: The rest pose (rad, m): models/README.md.
HOME = (0.0, -np.pi / 2, 0.0, -np.pi / 2, 0.0, 0.0)


def disc(mass: float, radius: float) -> tuple[tuple[float, float, float], ...]:
    """A solid disc's inertia about its centre (kg·m²), axis z: diag(m r²/4, m r²/4, m r²/2)."""
    return ((mass * radius**2 / 4, 0.0, 0.0), (0.0, mass * radius**2 / 4, 0.0), (0.0, 0.0, mass * radius**2 / 2))


def build() -> Arm:
    """The UR5 (see the module for every source and choice)."""
    inertials = [DHInertial(m, (float(c[0]), float(c[1]), float(c[2]))) for m, c in zip(MASS, COM, strict=True)]
    inertials[5] = DHInertial(MASS[5], inertials[5].com, disc(MASS[5], FLANGE_RADIUS))
    notes = {
        "kinematics": "standard DH, Universal Robots' 'Parameters for calculations of kinematics and dynamics' (UR5)",
        "limits": "±360° and 180°/s every joint (UR5/CB3 User Manual); effort 150, 150, 150, 28, 28, 28 N·m (UR, "
                  "'Max. joint torques')",
        "masses": "UR's table: masses and centres of mass in the DH frames; point masses (no inertias published)",
        "choice link 6": f"a solid disc of radius {FLANGE_RADIUS} m (the flange) so that joint 6 has inertia",
    }
    return library_dh_arm("ur5", SOURCE, "standard", [DHRow(a, alpha, d, 0.0) for a, alpha, d in DH],
                          [degrees(-360, 360, effort, 180.0) for effort in EFFORT], inertials, notes, RADII, HOME,
                          ur_closed_form)
