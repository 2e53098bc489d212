"""Franka Emika Panda: Craig's modified DH and joint limits from Franka's documentation ("Robot and interface
specifications", frankaemika.github.io/docs/control_parameters.html), inertial parameters from the identification of
Gaz, Cognetti, Oliva, Robuffo Giordano & De Luca, "Dynamic Identification of the Franka Emika Panda Robot With
Retrieval of Feasible Parameters Using Penalty-Based Optimization", IEEE RA-L 4(4), 2019, pp. 4147-4154 (its
supplementary material, Tables VIII and IX; the authors' repository FrankaEmikaPandaDynModel carries the same).

Modified DH, link frames at each joint (Franka's and Gaz et al.'s). Franka's flange frame F is 0.107 m along z7:
armlab puts it into row 7 (d7 = 0.107, as the Robotics Toolbox's Panda does), so that the tool frame, DH frame 7,
is the flange (no hand, no tool offset). Gaz et al. give link 7's centre of mass in Franka's frame 7 (d7 = 0); it is
moved to the flange frame, z − 0.107 m, the inertia (about the centre of mass, axes unchanged) as it is. No other
number is changed: Gaz et al.'s parameters are feasible (physical) by construction. The Robotics Toolbox's DH
Panda carries the same masses and inertias but no centres of mass (its r = 0; the toolbox's issue #688), so its
torques are not the Panda's: tests/test_library.py compares kinematics with it, dynamics with Pinocchio.

Limits (Franka): position, velocity 2.175 rad/s (joints 1-4) and 2.61 rad/s (5-7), torque 87 N·m (1-4) and 12 N·m
(5-7). Seven joints: a pose target is a continuum (one redundant joint); :func:`armlab.kinematics.ik.solve` says
what it returns. No closed form (solved numerically).
"""

from __future__ import annotations

import numpy as np

from armlab.kinematics.dh import DHRow
from armlab.models.arm import Arm
from armlab.models.library._dh_arm import library_dh_arm
from armlab.models.read_dh import DHInertial
from armlab.models.write_urdf import JointLimits

SOURCE = ("Franka Emika Panda; modified DH and limits from Franka's documentation (control_parameters), inertial "
          "parameters identified by Gaz et al., IEEE RA-L 4(4) 2019, Tables VIII-IX of its supplementary material; "
          "tool frame = the flange (0.107 m along z7)")

#: Franka's flange offset along z7 (m).
FLANGE = 0.107
#: (a_{i−1} m, α_{i−1} rad, d_i m) per joint, modified DH, θ offsets 0: Franka's documentation; d7 = the flange.
DH = ((0.0, 0.0, 0.333), (0.0, -np.pi / 2, 0.0), (0.0, np.pi / 2, 0.316), (0.0825, np.pi / 2, 0.0),
      (-0.0825, -np.pi / 2, 0.384), (0.0, np.pi / 2, 0.0), (0.088, np.pi / 2, FLANGE))
#: Position limits (rad), Franka's documentation.
LOWER = (-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973)
UPPER = (2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973)
#: Velocity (rad/s) and torque (N·m) limits, Franka's documentation.
VELOCITY = (2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61)
EFFORT = (87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0)
#: Link masses (kg), Gaz et al. 2019, Table VIII.
MASS = (4.970684, 0.646926, 3.228604, 3.587895, 1.225946, 1.666555, 0.735522)
#: Centres of mass (m) in Franka's link frames i, Gaz et al. 2019, Table VIII.
COM = ((3.875e-03, 2.081e-03, 0.0), (-3.141e-03, -2.872e-02, 3.495e-03), (2.7518e-02, 3.9252e-02, -6.6502e-02),
       (-5.317e-02, 1.04419e-01, 2.7454e-02), (-1.1953e-02, 4.1065e-02, -3.8437e-02),
       (6.0149e-02, -1.4117e-02, -1.0517e-02), (1.0517e-02, -4.252e-03, 6.1597e-02))
#: Inertias about the centre of mass (kg·m²), link-frame axes, as (Ixx, Ixy, Ixz, Iyy, Iyz, Izz): Gaz et al. 2019,
#: Table IX.
INERTIA = ((7.0337e-01, -1.3900e-04, 6.7720e-03, 7.0661e-01, 1.9169e-02, 9.1170e-03),
           (7.9620e-03, -3.9250e-03, 1.0254e-02, 2.8110e-02, 7.0400e-04, 2.5995e-02),
           (3.7242e-02, -4.7610e-03, -1.1396e-02, 3.6155e-02, -1.2805e-02, 1.0830e-02),
           (2.5853e-02, 7.7960e-03, -1.3320e-03, 1.9552e-02, 8.6410e-03, 2.8323e-02),
           (3.5549e-02, -2.1170e-03, -4.0370e-03, 2.9474e-02, 2.2900e-04, 8.6270e-03),
           (1.9640e-03, 1.0900e-04, -1.1580e-03, 4.3540e-03, 3.4100e-04, 5.4330e-03),
           (1.2516e-02, -4.2800e-04, -1.1960e-03, 1.0027e-02, -7.4100e-04, 4.8150e-03))


#: Collision capsule radii (m) per link, along its DH offsets: models/README.md gives the reasoning.
RADII = (0.06, 0.06, 0.06, 0.05, 0.06, 0.05, 0.035)
#: The rest pose (rad, m): models/README.md.
HOME = (0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4)


def _inertial(i: int) -> DHInertial:
    """Link ``i``'s (0-based) mass data in armlab's DH frame i (link 7's centre of mass moved to the flange)."""
    xx, xy, xz, yy, yz, zz = INERTIA[i]
    cx, cy, cz = COM[i]
    return DHInertial(MASS[i], (cx, cy, cz - (FLANGE if i == 6 else 0.0)),
                      ((xx, xy, xz), (xy, yy, yz), (xz, yz, zz)))


def build() -> Arm:
    """The Panda (see the module for every source)."""
    limits = [JointLimits(lo, hi, effort, velocity) for lo, hi, effort, velocity in
              zip(LOWER, UPPER, EFFORT, VELOCITY, strict=True)]
    notes = {
        "kinematics": "modified DH, Franka's documentation; d7 = 0.107 m, the flange (tool frame = flange)",
        "limits": "position, velocity and torque limits from Franka's documentation",
        "masses": "Gaz et al., IEEE RA-L 2019, supplementary Tables VIII-IX (identified, feasible); link 7's "
                  "centre of mass moved from frame 7 to the flange frame",
    }
    return library_dh_arm("panda", SOURCE, "modified", [DHRow(a, alpha, d, 0.0) for a, alpha, d in DH], limits,
                          [_inertial(i) for i in range(7)], notes, RADII, HOME)
