"""Unimation Puma 560: kinematics, masses, centres of mass, inertias and drive train of Corke & Armstrong-Hélouvry,
"A search for consensus among model parameters reported for the PUMA 560 robot", ICRA 1994, pp. 1608-1613 — the set
the Robotics Toolbox carries (``roboticstoolbox.models.DH.Puma560``, from which the numbers were cross-checked) —
and joint limits of Wang & Chen, IEEE Trans. Robotics and Automation 7(4), 1991, p. 489.

Standard DH, link frames at the distal end of each link (the toolbox's). The base height: d1 = 26.45 in = 0.67183 m from
the mounting surface to the shoulder axis (the toolbox 1.5's ``base = 26.45 * inch``); the base frame is on the
mounting surface.
The tool frame is DH frame 6, at the wrist centre (d6 = 0, no tool). Centres of mass and inertias are in each
link's own DH frame; the inertias' products are 0 in the source.

Two of the source's numbers are not physical, and armlab (which refuses non-physical mass data) corrects them,
each with its effect on the torques:

* **Link 1**: m = 0 with I = diag(0, 0.35, 0) kg·m² (Armstrong measured no mass for it; the toolbox's note: it
  does not appear in τ1). A massless body cannot have inertia, and (0, 0.35, 0) breaks the triangle inequality.
  armlab gives link 1 m1 = 1 kg at its frame's origin and Ixx = Izz = 0.175 kg·m² (the least that makes 0.35 ≤
  Ixx + Izz). **Effect on the torques: none.** Link 1 turns only about z0, which is its y1 axis (α1 = 90°), so its
  angular velocity is always along y1 and only Iyy = 0.35 enters the torques; its centre of mass lies on the joint 1
  axis, so its weight and mass give no joint torque.
* **Link 3**: principal moments (0.066, 0.086, 0.0125) kg·m², 0.066 + 0.0125 < 0.086. armlab raises Izz to
  0.0200 kg·m² (Ixx + Izz = Iyy, the least physical value). **Effect**: gravity torques none (inertia does not
  enter them); the mass matrix's entries change by at most 0.0075 kg·m² (tests/test_library.py checks the bound
  against the toolbox's numbers).

The drive train (:func:`drive_train`): motor inertia J_m, gear ratio G, viscous friction B_m and Coulomb friction
T_c,m, all motor side as the source gives them, to the joint side by
:meth:`armlab.drives.train.DriveTrain.from_motor_side`. The source's Coulomb friction differs by direction
(T_c+ while the joint turns forwards, T_c− backwards, as the toolbox's ``Tc`` pairs and its ``Link.friction``
apply them, by the sign of the joint velocity): the drive train carries both (``coulomb``, ``coulomb_negative``).
Efficiency is not in the source: 1 (an ideal gearbox). :func:`build` gives the arm this train: its
``Arm.drives``; tests/test_library.py checks its inverse dynamics against the toolbox's ``Puma560().rne``.

Its closed form (``Arm.closed_form``): the spherical wrist's 8 branches,
:func:`armlab.kinematics.ik_wrist.spherical_wrist_ik`.
"""

from __future__ import annotations

import numpy as np

from armlab.drives.train import DriveTrain
from armlab.kinematics.dh import DHRow
from armlab.kinematics.ik_wrist import spherical_wrist_closed_form
from armlab.models.arm import Arm
from armlab.models.library._dh_arm import degrees, library_dh_arm
from armlab.models.read_dh import DHInertial

SOURCE = ("Unimation Puma 560; Corke & Armstrong-Hélouvry, ICRA 1994, pp. 1608-1613 (kinematics, dynamics, drive "
          "train), as the Robotics Toolbox's Puma560; limits Wang & Chen, IEEE T-RA 7(4) 1991; base height 26.45 in; "
          "links 1 and 3 corrected to be physical (no effect on gravity torques; see the module)")

INCH = 0.0254
#: (a m, α rad, d m, θ offset rad) per joint, standard DH: Corke & Armstrong-Hélouvry 1994 (the toolbox's
#: D3 = 150.05 mm, "closer to data from Lee, AKB86 and Tarn"; α as Paul's, righty at q = 0); d1 the base height.
DH = ((0.0, np.pi / 2, 26.45 * INCH, 0.0), (0.4318, 0.0, 0.0, 0.0), (0.0203, -np.pi / 2, 0.15005, 0.0),
      (0.0, np.pi / 2, 0.4318, 0.0), (0.0, -np.pi / 2, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0))
#: Joint limits (deg): Wang & Chen 1991, as the toolbox's qlim.
LIMITS_DEG = ((-160, 160), (-45, 225), (-225, 45), (-110, 170), (-100, 100), (-266, 266))
#: Link masses (kg), Corke & Armstrong-Hélouvry 1994; link 1's 0 corrected to 1 kg (see the module).
MASS = (1.0, 17.4, 4.8, 0.82, 0.34, 0.09)
#: Centres of mass (m) in each link's DH frame, Corke & Armstrong-Hélouvry 1994 (the toolbox's r).
COM = ((0, 0, 0), (-0.3638, 0.006, 0.2275), (-0.0203, -0.0141, 0.070), (0, 0.019, 0), (0, 0, 0), (0, 0, 0.032))
#: Principal moments (Ixx, Iyy, Izz) kg·m² about the centre of mass, DH-frame axes, products 0: Corke &
#: Armstrong-Hélouvry 1994; link 1's Ixx, Izz (0 there) and link 3's Izz (0.0125 there) corrected (see the module).
INERTIA = ((0.175, 0.35, 0.175), (0.13, 0.524, 0.539), (0.066, 0.086, 0.0200), (1.8e-3, 1.3e-3, 1.8e-3),
           (0.3e-3, 0.4e-3, 0.3e-3), (0.15e-3, 0.15e-3, 0.04e-3))
#: The source's own values where armlab corrects them: (link, mass kg, (Ixx, Iyy, Izz) kg·m²).
SOURCE_VALUES = ((1, 0.0, (0.0, 0.35, 0.0)), (3, 4.8, (0.066, 0.086, 0.0125)))

#: Drive train, motor side, Corke & Armstrong-Hélouvry 1994 (the toolbox's G, Jm, B, Tc): gear ratio (its sign the
#: motor's direction), rotor inertia kg·m², viscous friction N·m·s/rad, Coulomb friction (T_c+, T_c−) N·m.
GEAR_RATIO = (-62.6111, 107.815, -53.7063, 76.0364, 71.923, 76.686)
ROTOR_INERTIA = (200e-6, 200e-6, 200e-6, 33e-6, 33e-6, 33e-6)
VISCOUS_MOTOR = (1.48e-3, 0.817e-3, 1.38e-3, 71.2e-6, 82.6e-6, 36.7e-6)
COULOMB_MOTOR = ((0.395, -0.435), (0.126, -0.071), (0.132, -0.105), (11.2e-3, -16.9e-3), (9.26e-3, -14.5e-3),
                 (3.96e-3, -10.5e-3))

#: The toolbox's named configurations (rad): zero ("L" shape), ready (arm up), stretched along x, nominal. qn's
#: θ3 = π there is outside Wang & Chen's [−225°, 45°]; −π is the same configuration inside them.
CONFIGURATIONS = {"qz": (0, 0, 0, 0, 0, 0), "qr": (0, np.pi / 2, -np.pi / 2, 0, 0, 0),
                  "qs": (0, 0, -np.pi / 2, 0, 0, 0), "qn": (0, np.pi / 4, -np.pi, 0, np.pi / 4, 0)}


#: Collision capsule radii (m) per link, along its DH offsets: models/README.md gives the reasoning.
RADII = (0.09, 0.07, 0.06, 0.05, 0.04, 0.03)


def drive_train() -> DriveTrain:
    """The Puma 560's drive train, joint side (:meth:`DriveTrain.from_motor_side` of the source's motor-side data,
    T_c+ and |T_c−| per joint)."""
    positive, negative = np.abs(np.array(COULOMB_MOTOR)).T
    return DriveTrain.from_motor_side(GEAR_RATIO, ROTOR_INERTIA, np.ones(6), VISCOUS_MOTOR, positive,
                                      coulomb_negative_motor=negative)


def build() -> Arm:
    """The Puma 560 (see the module for every source and correction)."""
    rows = [DHRow(a, alpha, d, theta) for a, alpha, d, theta in DH]
    inertials = [DHInertial(m, (float(c[0]), float(c[1]), float(c[2])), tuple(map(tuple, np.diag(moments).tolist())))
                 for m, c, moments in zip(MASS, COM, INERTIA, strict=True)]
    notes = {
        "kinematics": "standard DH, Corke & Armstrong-Hélouvry 1994 (the Robotics Toolbox's Puma560); base height "
                      "d1 = 26.45 in = 0.67183 m (mounting surface to shoulder axis); tool frame = DH frame 6 "
                      "(wrist centre)",
        "limits": "Wang & Chen, IEEE T-RA 7(4) 1991 (the toolbox's qlim); effort and velocity limits not published",
        "masses": "Corke & Armstrong-Hélouvry 1994, in each link's DH frame",
        "correction link 1": "m 0 → 1 kg, Ixx = Izz 0 → 0.175 kg·m² (physical); no effect on any torque",
        "correction link 3": "Izz 0.0125 → 0.0200 kg·m² (triangle inequality); gravity torques unchanged, mass "
                             "matrix within 0.0075 kg·m²",
        "drive train": "Corke & Armstrong-Hélouvry 1994 motor-side J_m, G, B_m, T_c+ and T_c− → "
                       "armlab.models.library.puma560.drive_train(), the arm's own (arm.drives)",
    }
    arm = library_dh_arm("puma560", SOURCE, "standard", rows, [degrees(lo, hi) for lo, hi in LIMITS_DEG],
                         inertials, notes, RADII, CONFIGURATIONS["qr"], spherical_wrist_closed_form)
    return arm.with_drives(drive_train())
