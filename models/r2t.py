"""Cylindrical R-T-T robot of paper 003 (Schonstein & Panc, "Kinematical modelling for
R2T serial structure used in transfer parts between two workstations", 2017), Figs. 1–2.

Joint 1 rotates q1 about z0, joint 2 translates q2 along z, joint 3 translates q3 along
y of frame {3}. The matrix of nominal geometry (paper 003, Table 1):
P1 = (0, 0, l1), P2 = (0, 0, l2), P3 = (l3, 0, 0), tool P4 = (0, l4, −l5), and
T34 = [[0,1,0,0],[1,0,0,l4],[0,0,−1,−l5]] (eq. 18). The paper's own formulation is the
locating-matrix algorithm (:mod:`armlab.kinematics.locating`) and the iterative algorithm
(:mod:`armlab.kinematics.iterative`).

No dimensions are printed; the robot is 0.5 × 0.3 × 1.15 m, 140 kg, payload about 20 kg.
l1 … l5, the strokes and the masses below are chosen to fit that envelope.

The arm's extras (:mod:`armlab.models.extras`): the closed-form inverse kinematics of the tool
position p4 (:func:`armlab.kinematics.ik_closed_form.r2t_ik`, two branches); a demo motion
(:func:`transfer_motion`, ``armlab simulate r2t``: the paper is kinematic only), and the scheme of
Figs. 1–2, drawn with its locating table at the demo's start.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from armlab.kinematics.ik_closed_form import ClosedForm, r2t_ik
from armlab.kinematics.locating import JointRow, LocatingTable
from armlab.kinematics.quintic import Motion, QuinticSegment, check_duration
from armlab.models.arm import MODELS_DIR, Arm, chosen, from_paper, parameter_notes
from armlab.models.extras import PaperScheme, motion_start
from armlab.models.write_urdf import Body, JointLimits, Point

PAPER = (
    "003: Schonstein & Panc, Kinematical modelling for R2T serial structure, Acta Technica Napocensis 2017, "
    "Table 1, eqs. (13)-(33)"
)


@dataclass(frozen=True)
class Parameters:
    """Parameters of the R2T robot, by the paper's names (SI)."""

    l1: float = chosen(0.55, "003 prints no dimensions; column height within the 1.15 m envelope")
    l2: float = chosen(0.25, "003 prints no dimensions; carriage offset, l1 + l2 + q2max stays under 1.15 m")
    l3: float = chosen(0.10, "003 prints no dimensions; arm offset from the column axis")
    l4: float = chosen(0.15, "003 prints no dimensions; gripper offset along y3")
    l5: float = chosen(0.10, "003 prints no dimensions; gripper drop below the arm")
    q2_max: float = chosen(0.30, "003 prints no strokes; vertical stroke 0 … 0.30 m")
    q3_max: float = chosen(0.30, "003 prints no strokes; horizontal stroke 0 … 0.30 m (robot is 0.5 m deep)")
    m1: float = chosen(70.0, "003: robot 140 kg in all; the turning column")
    m2: float = chosen(40.0, "003: robot 140 kg in all; the vertical carriage")
    m3: float = chosen(15.0, "003: robot 140 kg in all; the horizontal arm with gripper")
    payload: float = from_paper(20.0, "003 §2, payload about 20 kg")


def locating_table(p: Parameters) -> LocatingTable:
    """Paper 003, Table 1 and eq. (18)."""
    tool = np.array([[0.0, 1, 0, 0], [1, 0, 0, p.l4], [0, 0, -1, -p.l5], [0, 0, 0, 1]])
    return LocatingTable(
        (
            JointRow("joint1", "R", (0.0, 0.0, p.l1), (0.0, 0.0, 1.0)),
            JointRow("joint2", "T", (0.0, 0.0, p.l2), (0.0, 0.0, 1.0)),
            JointRow("joint3", "T", (p.l3, 0.0, 0.0), (0.0, 1.0, 0.0)),
        ),
        tool=tool,
    )


def transfer_motion(arm: Arm, tf: float | None = None) -> Motion:
    """A demo (paper 003 has no motion): a part transfer, the column turning −45° → +45° while the carriage rises
    from 20 % to 80 % of its stroke and the arm extends from 10 % to 90 % of its stroke, rest to rest in ``tf`` s
    (default 3 s)."""
    tf = 3.0 if tf is None else check_duration(tf)
    lo, hi = arm.limit_arrays()
    q0 = np.array([-np.pi / 4, lo[1] + 0.2 * (hi[1] - lo[1]), lo[2] + 0.1 * (hi[2] - lo[2])])
    qf = np.array([np.pi / 4, lo[1] + 0.8 * (hi[1] - lo[1]), lo[2] + 0.9 * (hi[2] - lo[2])])
    motion = Motion((QuinticSegment(q0, qf, tf, "transfer"),),
                    f"demo (paper 003 has no motion): a part transfer, the column turning -45° → +45° while the "
                    f"carriage rises from 20 % to 80 % of its stroke and the arm extends from 10 % to 90 % of its "
                    f"stroke, rest to rest in {tf:g} s")
    motion.check_limits(arm)
    return motion


def build(**overrides: float) -> Arm:
    """The R2T robot; keyword arguments override :class:`Parameters` by name."""
    p = Parameters(**overrides)
    return Arm(
        name="r2t",
        paper=PAPER,
        parameters=asdict(p),
        notes=parameter_notes(p),
        table=locating_table(p),
        bodies=(Body(p.m1, 0.12, (0.5, 0.5, 0.55, 1), collides=True),
                Body(p.m2, 0.08, (0.85, 0.45, 0.1, 1), collides=True),
                Body(p.m3, 0.05, (0.2, 0.45, 0.8, 1), collides=True)),
        limits=(JointLimits(-np.pi, np.pi, effort=500.0, velocity=3.0),
                JointLimits(0.0, p.q2_max, effort=3000.0, velocity=1.0),
                JointLimits(0.0, p.q3_max, effort=1000.0, velocity=1.0)),
        points=(Point("O1", 1, (0.0, 0.0, 0.0)), Point("O2", 2, (0.0, 0.0, 0.0)),
                Point("O3", 3, (0.0, 0.0, 0.0)), Point("P4", 4, (0.0, 0.0, 0.0))),
        tool_name="P4",
        gravity=(0.0, 0.0, -9.81),
        urdf_file=MODELS_DIR / "r2t.urdf" if not overrides else None,
        closed_form=ClosedForm(lambda position, rotation, near: r2t_ik(position, p.l1, p.l2, p.l3, p.l4, p.l5),
                               ("u = q3 + l4 ≥ 0 (arm pointing out)", "u ≤ 0")),
        motion=transfer_motion,
        scheme=PaperScheme("003 Figs. 1-2", motion_start),
        # the arm slides in the carriage that rides on the column: its root (l3 = 0.10 m from the axis) lies
        # within the column's 0.12 m radius by design
        collision_filters=(("link1", "link3"),),
    )
