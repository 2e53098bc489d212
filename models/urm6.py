"""6-DOF arm of URM modules, paper 004 (Ondočko et al., "Position forward kinematics of
6-DOF robotic arm"), Fig. 1, eqs. (1)–(22), Table 1.

Segments r1 … r7 lie along their module's z axis; joints φ1 … φ6 turn about z without
limit; bends θ2 … θ7 about y are fixed structural parameters. The paper's own
formulation is :mod:`armlab.kinematics.urm`. Table 1: |r| = 300, 250, 200, 150, 100,
50, 25 mm; θ2 … θ7 = 15, 30, 45, 60, 75, 90°. The paper gives no masses.

The arm's extras (:mod:`armlab.models.extras`): a demo motion (:func:`table1_motion`, ``armlab
simulate urm6``: the paper is kinematic only) and the scheme of Figs. 1–3, drawn with its locating
table at φ = 0. It has no closed form here (solved numerically).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import NDArray

from armlab.kinematics.basic_movements import T_Z3, T_Z5
from armlab.kinematics.locating import JointRow, LocatingTable, homogeneous
from armlab.kinematics.quintic import Motion, QuinticSegment, check_duration
from armlab.kinematics.urm import rotation_form
from armlab.models.arm import MODELS_DIR, Arm, Forward, chosen, from_paper, parameter_notes
from armlab.models.extras import PaperScheme, motion_start
from armlab.models.write_urdf import Body, JointLimits, Point

PAPER = "004: Ondočko et al., Position forward kinematics of 6-DOF robotic arm, eqs. (1)-(22), Tables 1-2"

#: φ1 … φ6 of paper 004, Table 1 (degrees): the configuration of its Table 2.
TABLE1_PHI_DEG = (15.0, 30.0, 50.0, 130.0, 230.0, 340.0)


@dataclass(frozen=True)
class Parameters:
    """Parameters of the URM arm, by the paper's names (SI)."""

    r1: float = from_paper(0.300, "004 Table 1, r1 = 300 mm")
    r2: float = from_paper(0.250, "004 Table 1, r2 = 250 mm")
    r3: float = from_paper(0.200, "004 Table 1, r3 = 200 mm")
    r4: float = from_paper(0.150, "004 Table 1, r4 = 150 mm")
    r5: float = from_paper(0.100, "004 Table 1, r5 = 100 mm")
    r6: float = from_paper(0.050, "004 Table 1, r6 = 50 mm")
    r7: float = from_paper(0.025, "004 Table 1, r7 = 25 mm")
    theta2: float = from_paper(np.radians(15), "004 Table 1, θ2 = 15°")
    theta3: float = from_paper(np.radians(30), "004 Table 1, θ3 = 30°")
    theta4: float = from_paper(np.radians(45), "004 Table 1, θ4 = 45°")
    theta5: float = from_paper(np.radians(60), "004 Table 1, θ5 = 60°")
    theta6: float = from_paper(np.radians(75), "004 Table 1, θ6 = 75°")
    theta7: float = from_paper(np.radians(90), "004 Table 1, θ7 = 90°")
    module_mass: float = chosen(1.2, "004 publishes no masses; each URM module of the base size, scaled by its radius")

    @property
    def r(self) -> NDArray:
        """|r1| … |r7|."""
        return np.array([self.r1, self.r2, self.r3, self.r4, self.r5, self.r6, self.r7])

    @property
    def theta(self) -> NDArray:
        """θ2 … θ7."""
        return np.array([self.theta2, self.theta3, self.theta4, self.theta5, self.theta6, self.theta7])


def forward(q: NDArray, p: Parameters) -> Forward:
    """Eqs. (3)–(7): the position vectors p1 … p7; the tool frame is module 7's at p7."""
    points, R = rotation_form(q, p.theta, p.r)
    return Forward(homogeneous(R, points[..., 6, :]), {f"p{k + 1}": points[..., k, :] for k in range(7)})


def locating_table(p: Parameters) -> LocatingTable:
    """Joint k+1 sits at the end of segment r_k, bent by θ_{k+1} about y; the tool at p7."""
    z = (0.0, 0.0, 1.0)
    rows = [JointRow("joint1", "R", (0.0, 0.0, 0.0), z)]
    for k in range(1, 6):
        R = T_Z5(p.theta[k - 1])[:3, :3]
        rows.append(JointRow(f"joint{k + 1}", "R", (0.0, 0.0, p.r[k - 1]), z, tuple(map(tuple, R))))
    tool = T_Z3(p.r[5]) @ T_Z5(p.theta[5]) @ T_Z3(p.r[6])
    return LocatingTable(tuple(rows), tool=tool)


def table1_motion(arm: Arm, tf: float | None = None) -> Motion:
    """A demo (paper 004 is kinematic only): from φ = 0 to Table 1's φ1 … φ6, rest to rest in ``tf`` s (default 4 s)."""
    tf = 4.0 if tf is None else check_duration(tf)
    motion = Motion((QuinticSegment(np.zeros(arm.n), np.radians(TABLE1_PHI_DEG), tf, "home-Table1"),),
                    f"demo (paper 004 is kinematic only): from φ = 0 to Table 1's φ1…φ6 = "
                    f"{', '.join(f'{v:g}' for v in TABLE1_PHI_DEG)}°, rest to rest in {tf:g} s")
    motion.check_limits(arm)
    return motion


def build(**overrides: float) -> Arm:
    """The URM arm; keyword arguments override :class:`Parameters` by name."""
    p = Parameters(**overrides)
    radii = 0.045 * np.array([1.0, 0.9, 0.8, 0.7, 0.6, 0.5])
    masses = p.module_mass * (radii / radii[0]) ** 2
    palette = [(0.85, 0.45, 0.1, 1), (0.2, 0.45, 0.8, 1)]
    return Arm(
        name="urm6",
        paper=PAPER,
        parameters=asdict(p),
        notes=parameter_notes(p),
        table=locating_table(p),
        bodies=tuple(
            Body(float(m), float(r), palette[i % 2], collides=True)
            for i, (m, r) in enumerate(zip(masses, radii, strict=True))
        ),
        limits=tuple(JointLimits(None, None, effort=50.0, velocity=3.0) for _ in range(6)),
        points=tuple(Point(f"p{k}", k, (0.0, 0.0, p.r[k - 1])) for k in range(1, 7)) + (Point("p7", 7, (0, 0, 0)),),
        tool_name="p7",
        gravity=(0.0, 0.0, -9.81),
        forward_fn=lambda q: forward(q, p),
        urdf_file=MODELS_DIR / "urm6.urdf" if not overrides else None,
        motion=table1_motion,
        scheme=PaperScheme("004 Figs. 1-3", motion_start),
    )
