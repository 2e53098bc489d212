"""RRRR manipulator on a fixed stand, paper 000 (Hroncová et al., 2022), Figs. 11, 13, 20.

Standard DH (paper 000, Table 3): link 1 d = L1, θ = q1, a = 0, α = π/2; links 2–4
d = 0, θ = q2 … q4, a = L2, L3, L4, α = 0. The paper's own formulation is the product of
basic-movement matrices, eqs. (21)–(34) (see :mod:`armlab.kinematics.basic_movements`):
``r_0M = T01 T12 T23 T34 r_4M``. The URDF's base frame is the DH base frame {0} (z up).

Lengths L1 … L4 are the values of Figs. 18–19 and 24–25. The paper gives no masses.

The arm's paper motion (:func:`constant_rate_motion`, ``armlab simulate rrrr``) is that of
Figs. 18–19: constant rates ω = (7, 0.05, 0.05, 0.05) rad/s from q = 0 for 15 s; its scheme is
Figs. 11–13 and 20, drawn with Table 3's DH table. It has no closed form here (solved numerically).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import NDArray

from armlab.kinematics.basic_movements import T_Z1, T_Z3, T_Z4
from armlab.kinematics.batch import ZStep, chain_points
from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.quintic import ConstantRate, Motion, check_duration
from armlab.models.arm import MODELS_DIR, Arm, Forward, chosen, from_paper, parameter_notes
from armlab.models.extras import PaperScheme, motion_start
from armlab.models.write_urdf import Body, JointLimits, Point

PAPER = "000: Hroncová et al., Robot trajectory planning, MM Science Journal 2022, Figs. 11-25, eqs. (21)-(47)"


@dataclass(frozen=True)
class Parameters:
    """Parameters of the RRRR arm, by the paper's names (SI)."""

    L1: float = from_paper(0.2, "000 Figs. 18-19, L1 = 0.2 m")
    L2: float = from_paper(0.4, "000 Figs. 18-19, L2 = 0.4 m")
    L3: float = from_paper(0.3, "000 Figs. 18-19, L3 = 0.3 m")
    L4: float = from_paper(0.2, "000 Figs. 18-19, L4 = 0.2 m")
    m1: float = chosen(2.0, "000 publishes no masses; a 20 cm column of 40 mm radius")
    m2: float = chosen(1.5, "000 publishes no masses; a 40 cm tube of 30 mm radius")
    m3: float = chosen(1.0, "000 publishes no masses; a 30 cm tube of 25 mm radius")
    m4: float = chosen(0.5, "000 publishes no masses; a 20 cm tube of 20 mm radius")
    theta_max: float = chosen(
        np.pi, "joints 2-4 limited to ±π; joint 1 turns without limit (000 runs ω01 = 7 rad/s for 15 s)"
    )


def forward(q: NDArray, p: Parameters) -> Forward:
    """Eqs. (21)–(35): the DH frames' origins O1 … O3 and the end point M, tool frame {4}.

    T04 = T01 T12 T23 T34 (eq. 18), each factor the paper's product of basic movements around its
    joint's turn, T01 = T_Z3(L1)·T_Z6(q1)·T_Z4(π/2) (21), T_{i−1,i} = T_Z6(q_i)·T_Z1(L_i) (26, 29, 32),
    multiplied out link by link (:func:`armlab.kinematics.batch.chain_points`; the same product as
    :func:`armlab.kinematics.basic_movements.rrrr_dh_chain`).
    """
    steps = [ZStep(T_Z3(p.L1), True, T_Z4(np.pi / 2))] + [ZStep(None, True, T_Z1(L)) for L in (p.L2, p.L3, p.L4)]
    origin = (0.0, 0.0, 0.0)
    T04, points = chain_points(q, steps, {"O1": (1, origin), "O2": (2, origin), "O3": (3, origin), "M": (4, origin)})
    return Forward(T04, points)


def dh_table(p: Parameters) -> DHTable:
    """Paper 000, Table 3 (standard DH)."""
    return DHTable(
        (DHRow(0.0, np.pi / 2, p.L1, 0.0), DHRow(p.L2, 0.0, 0.0, 0.0),
         DHRow(p.L3, 0.0, 0.0, 0.0), DHRow(p.L4, 0.0, 0.0, 0.0)),
        "standard",
    )


def constant_rate_motion(arm: Arm, tf: float | None = None) -> Motion:
    """Paper 000 Figs. 18–19: q = ω t, ω = (7, 0.05, 0.05, 0.05) rad/s, for ``tf`` s (default 15 s)."""
    tf = 15.0 if tf is None else check_duration(tf)
    motion = Motion(
        (ConstantRate(np.zeros(4), np.array([7.0, 0.05, 0.05, 0.05]), tf, "constant-rate"),),
        f"paper 000 Figs. 18-19: q = ω t, ω = (7, 0.05, 0.05, 0.05) rad/s, for {tf:g} s",
        {"path": "000 Figs. 18-19"},
    )
    motion.check_limits(arm)
    return motion


def build(**overrides: float) -> Arm:
    """The RRRR arm; keyword arguments override :class:`Parameters` by name."""
    p = Parameters(**overrides)
    limit = JointLimits(-p.theta_max, p.theta_max, effort=100.0, velocity=10.0)
    colors = [(0.5, 0.5, 0.55, 1), (0.85, 0.45, 0.1, 1), (0.2, 0.45, 0.8, 1), (0.2, 0.7, 0.3, 1)]
    radii = (0.04, 0.03, 0.025, 0.02)
    masses = (p.m1, p.m2, p.m3, p.m4)
    return Arm(
        name="rrrr",
        paper=PAPER,
        parameters=asdict(p),
        notes=parameter_notes(p),
        table=dh_table(p).locating_table(),
        bodies=tuple(Body(m, r, c, collides=True) for m, r, c in zip(masses, radii, colors, strict=True)),
        limits=(JointLimits(None, None, effort=100.0, velocity=10.0), limit, limit, limit),
        points=(Point("O1", 1, (0.0, 0.0, p.L1)), Point("O2", 2, (p.L2, 0.0, 0.0)),
                Point("O3", 3, (p.L3, 0.0, 0.0)), Point("M", 5, (0.0, 0.0, 0.0))),
        tool_name="M",
        gravity=(0.0, 0.0, -9.81),
        forward_fn=lambda q: forward(q, p),
        urdf_file=MODELS_DIR / "rrrr.urdf" if not overrides else None,
        motion=constant_rate_motion,
        scheme=PaperScheme("000 Figs. 11-13, 20", motion_start, dh_table(p)),
    )
