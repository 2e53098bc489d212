"""The Stanford arm (Scheinman): kinematics from Stanford AIM-177 (Fig. 2.3), dynamics from Paul, "Robot
manipulators: mathematics, programming and control", 1981, Tables 6.5-6.6, as the Robotics Toolbox carries them
(``roboticstoolbox.models.DH.Stanford``; numbers cross-checked there). Joint 3 is prismatic: 12 to 50 inches
(0.3048 m to 1.27 m, Dobrotin & Scheinman, IJCAI 1973).

Standard DH, the toolbox's frames; the tool frame DH frame 6. Masses, centres of mass and inertias are in each
link's DH frame, as the toolbox gives them, with one correction and one caveat:

* **Correction, link 5**: principal moments (0.003, 0.0004, 0) kg·m² break the triangle inequality (0.0004 + 0 <
  0.003). armlab raises Izz to 0.0026 kg·m² (the least physical value). **Effect**: gravity torques none; the mass
  matrix's entries change by at most 0.0026 kg·m².
* **Caveat**: the toolbox's centres of mass of links 2, 3, 5 and 6 lie 1.05, 6.45, 0.57 and 1.55 m from their
  frames, on an arm whose boom strokes 1.27 m: they read like a factor-10 unit slip, but Paul's tables were not
  available to check. armlab keeps them as the toolbox has them, so that its torques agree with the toolbox's; they
  are the toolbox's Stanford arm, not a measured one.

Motor inertias (the toolbox's Jm with G = 1, "reflected armature inertia") are left out: they are a drive train,
not the links' mass data. Its closed form (a spherical wrist on a sliding boom):
:func:`armlab.kinematics.ik_wrist.spherical_wrist_ik`, 8 branches (4 with the boom's length positive).
"""

from __future__ import annotations

import numpy as np

from armlab.kinematics.dh import DHRow
from armlab.kinematics.ik_wrist import spherical_wrist_closed_form
from armlab.models.arm import Arm
from armlab.models.library._dh_arm import degrees, library_dh_arm
from armlab.models.read_dh import DHInertial
from armlab.models.write_urdf import JointLimits

SOURCE = ("Stanford arm (Scheinman); kinematics Stanford AIM-177 Fig. 2.3, dynamics Paul 1981 Tables 6.5-6.6, as the "
          "Robotics Toolbox's Stanford; link 5's inertia corrected; the toolbox's centres of mass kept (1-6 m from "
          "their frames: the toolbox's arm, not a measured one)")

INCH = 0.0254
#: (a m, α rad, d m, θ rad, type) per joint, standard DH: the toolbox's Stanford (joint 3 prismatic, θ3 = −90°).
DH = ((0.0, -np.pi / 2, 0.412, 0.0, "R"), (0.0, np.pi / 2, 0.154, 0.0, "R"), (0.0203, 0.0, 0.0, -np.pi / 2, "T"),
      (0.0, -np.pi / 2, 0.0, 0.0, "R"), (0.0, np.pi / 2, 0.0, 0.0, "R"), (0.0, 0.0, 0.0, 0.0, "R"))
#: Masses (kg), Paul 1981 Table 6.5 as the toolbox's m.
MASS = (9.29, 5.01, 4.25, 1.08, 0.630, 0.51)
#: Centres of mass (m) in the DH frames, the toolbox's r (see the caveat).
COM = ((0, 0.0175, -0.1105), (0, -1.054, 0), (0, 0, -6.447), (0, 0.092, -0.054), (0, 0.566, 0.003), (0, 0, 1.554))
#: Principal moments (Ixx, Iyy, Izz) kg·m², products 0: Paul 1981 Table 6.6 as the toolbox's I; link 5's Izz (0
#: there) corrected to 0.0026 (see the module).
INERTIA = ((0.276, 0.255, 0.071), (0.108, 0.018, 0.100), (2.51, 2.51, 0.006), (0.002, 0.001, 0.001),
           (0.003, 0.0004, 0.0026), (0.013, 0.013, 0.0003))
#: The source's own value where armlab corrects it: (link, (Ixx, Iyy, Izz) kg·m²).
SOURCE_VALUES = ((5, (0.003, 0.0004, 0.0)),)


#: Collision capsule radii (m) per link, along its DH offsets: models/README.md gives the reasoning.
RADII = (0.08, 0.06, 0.04, 0.04, 0.035, 0.03)
#: The rest pose (rad, m): models/README.md.
HOME = (0.0, 0.0, 0.6, 0.0, 0.0, 0.0)


def build() -> Arm:
    """The Stanford arm (see the module for every source, the correction and the caveat)."""
    rows = [DHRow(a, alpha, d, theta, kind) for a, alpha, d, theta, kind in DH]  # type: ignore[arg-type]
    limits = [degrees(-170, 170), degrees(-170, 170), JointLimits(12 * INCH, 50 * INCH), degrees(-170, 170),
              degrees(-90, 90), degrees(-170, 170)]
    inertials = [DHInertial(m, (float(c[0]), float(c[1]), float(c[2])), tuple(map(tuple, np.diag(moments).tolist())))
                 for m, c, moments in zip(MASS, COM, INERTIA, strict=True)]
    notes = {
        "kinematics": "standard DH, Stanford AIM-177 Fig. 2.3 (the Robotics Toolbox's Stanford); joint 3 prismatic",
        "limits": "the toolbox's qlim (joint 3: 12-50 in, Dobrotin & Scheinman 1973); effort, velocity unknown",
        "masses": "Paul 1981 Tables 6.5-6.6 as the toolbox's; centres of mass of links 2, 3, 5, 6 kept as the "
                  "toolbox's though 0.57-6.45 m from their frames (not a measured arm)",
        "correction link 5": "Izz 0 → 0.0026 kg·m² (triangle inequality); gravity torques unchanged",
    }
    return library_dh_arm("stanford", SOURCE, "standard", rows, limits, inertials, notes, RADII, HOME,
                          spherical_wrist_closed_form)
