"""Planar two-link RR arm of paper 000 (Hroncová et al., "Robot trajectory planning", 2022), Fig. 1.

Link lengths L1 = 0.4 m, L2 = 0.3 m; θ1 at the base, θ2 at the elbow (relative). The end
point M is, eqs. (1)–(2),

    x = L1 cos θ1 + L2 cos(θ1 + θ2),   y = L1 sin θ1 + L2 sin(θ1 + θ2).

The arm moves in the x–y plane (joint axes along z), so x, y are the paper's. Paper 000
simulates it in MSC Adams in a vertical plane with gravity (Fig. 26), so the default
gravity here is −y. The paper gives no masses: the ones below are chosen.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import NDArray

from armlab.kinematics.dh import DHRow, DHTable
from armlab.models.arm import MODELS_DIR, Arm, Forward, chosen, from_paper, parameter_notes
from armlab.models.write_urdf import Body, JointLimits, Point

PAPER = "000: Hroncová et al., Robot trajectory planning, MM Science Journal 2022, Fig. 1, eqs. (1)-(2)"


@dataclass(frozen=True)
class Parameters:
    """Parameters of the RR arm, by the paper's names (SI)."""

    L1: float = from_paper(0.4, "000 §2, L1 = 0.4 m")
    L2: float = from_paper(0.3, "000 §2, L2 = 0.3 m")
    m1: float = chosen(1.2, "000 publishes no masses; a 40 cm aluminium tube of 25 mm radius")
    m2: float = chosen(0.8, "000 publishes no masses; a 30 cm aluminium tube of 20 mm radius")
    r1: float = chosen(0.025, "link radius for inertia and drawing")
    r2: float = chosen(0.02, "link radius for inertia and drawing")
    theta_max: float = chosen(
        3 * np.pi / 2, "joint range ±3π/2 covers Fig. 4's grid 0:0.1:3π/2 and Table 2's ±180°"
    )


def forward(q: NDArray, p: Parameters) -> Forward:
    """Eqs. (1)–(2): elbow O2 and end point M, tool frame rotated by θ1 + θ2 about z."""
    t1, t12 = q[..., 0], q[..., 0] + q[..., 1]
    O2 = np.stack([p.L1 * np.cos(t1), p.L1 * np.sin(t1), np.zeros_like(t1)], axis=-1)
    M = O2 + np.stack([p.L2 * np.cos(t12), p.L2 * np.sin(t12), np.zeros_like(t1)], axis=-1)
    tool = np.broadcast_to(np.eye(4), t1.shape + (4, 4)).copy()
    tool[..., 0, 0] = tool[..., 1, 1] = np.cos(t12)
    tool[..., 1, 0] = np.sin(t12)
    tool[..., 0, 1] = -np.sin(t12)
    tool[..., :3, 3] = M
    return Forward(tool, {"O2": O2, "M": M})


def dh_table(p: Parameters) -> DHTable:
    """Standard DH: a = L1, L2; α = d = θ-offset = 0."""
    return DHTable((DHRow(p.L1, 0.0, 0.0, 0.0), DHRow(p.L2, 0.0, 0.0, 0.0)), "standard")


def build(**overrides: float) -> Arm:
    """The RR arm; keyword arguments override :class:`Parameters` by name."""
    p = Parameters(**overrides)
    limit = JointLimits(-p.theta_max, p.theta_max, effort=100.0, velocity=10.0)
    return Arm(
        name="rr",
        paper=PAPER,
        parameters=asdict(p),
        notes=parameter_notes(p),
        table=dh_table(p).locating_table(),
        bodies=(Body(p.m1, p.r1, (0.85, 0.45, 0.1, 1)), Body(p.m2, p.r2, (0.2, 0.45, 0.8, 1))),
        limits=(limit, limit),
        points=(Point("O2", 1, (p.L1, 0.0, 0.0)), Point("M", 3, (0.0, 0.0, 0.0))),
        tool_name="M",
        gravity=(0.0, -9.81, 0.0),
        forward_fn=lambda q: forward(q, p),
        urdf_file=MODELS_DIR / "rr.urdf" if not overrides else None,
    )
