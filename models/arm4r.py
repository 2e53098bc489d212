"""4R arm of paper 001 (Qin et al., "Four degree of freedom manipulator's kinematics
simulation analysis based on MATLAB", Information Technology Journal), Table 1.

Modified (Craig) DH, paper 001 eq. (1): T_{i−1,i} = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i) Tz(d_i);
link 1: a0 = 0, α0 = 0, d1 = 0; link 2: a1 = 0, α1 = −90°, d2; link 3: a2, α2 = 0;
link 4: a3, α3 = 0. At θ = 0, T04 = [[1,0,0,a2+a3],[0,0,1,d2],[0,−1,0,0]] (eq. 6).

The lengths are not printed. The simulation starts "stretched horizontally" at
(2, 0, 0), which gives a2 + a3 = 2 and d2 = 0: the defaults are a2 = a3 = 1 m, d2 = 0.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import NDArray

from armlab.kinematics.batch import chain_points
from armlab.kinematics.dh import DHRow, DHTable
from armlab.models.arm import MODELS_DIR, Arm, Forward, chosen, parameter_notes
from armlab.models.write_urdf import Body, JointLimits, Point

PAPER = "001: Qin et al., Four degree of freedom manipulator's kinematics simulation analysis based on MATLAB, Table 1"

#: Joint limits of paper 001, Table 1 (degrees).
LIMITS_DEG = ((-160.0, 160.0), (-225.0, 45.0), (-150.0, 150.0), (-150.0, 150.0))


@dataclass(frozen=True)
class Parameters:
    """Parameters of the 4R arm, by the paper's names (SI)."""

    a2: float = chosen(1.0, "001 prints no lengths; it starts stretched at (2, 0, 0), so a2 + a3 = 2")
    a3: float = chosen(1.0, "001 prints no lengths; it starts stretched at (2, 0, 0), so a2 + a3 = 2")
    d2: float = chosen(0.0, "001's start point (2, 0, 0) has y = d2 = 0 (eq. 6)")
    m1: float = chosen(4.0, "001 publishes no masses; a shoulder drum")
    m2: float = chosen(3.0, "001 publishes no masses; a 1 m tube of 50 mm radius")
    m3: float = chosen(2.0, "001 publishes no masses; a 1 m tube of 40 mm radius")
    m4: float = chosen(0.5, "001 publishes no masses; a small wrist")


def dh_table(p: Parameters) -> DHTable:
    """Paper 001, Table 1 (modified DH)."""
    return DHTable(
        (DHRow(0.0, 0.0, 0.0, 0.0), DHRow(0.0, -np.pi / 2, p.d2, 0.0),
         DHRow(p.a2, 0.0, 0.0, 0.0), DHRow(p.a3, 0.0, 0.0, 0.0)),
        "modified",
    )


def forward(q: NDArray, p: Parameters) -> Forward:
    """T_{0,i} by the modified DH chain: elbow O3, wrist O4; the tool frame is {4}."""
    origin = (0.0, 0.0, 0.0)
    T04, points = chain_points(q, dh_table(p).steps, {"O3": (3, origin), "O4": (4, origin)})
    return Forward(T04, points)


def build(**overrides: float) -> Arm:
    """The 4R arm; keyword arguments override :class:`Parameters` by name."""
    p = Parameters(**overrides)
    limits = tuple(JointLimits(np.radians(lo), np.radians(hi), effort=200.0, velocity=5.0) for lo, hi in LIMITS_DEG)
    colors = [(0.5, 0.5, 0.55, 1), (0.85, 0.45, 0.1, 1), (0.2, 0.45, 0.8, 1), (0.2, 0.7, 0.3, 1)]
    radii = (0.08, 0.05, 0.04, 0.03)
    masses = (p.m1, p.m2, p.m3, p.m4)
    return Arm(
        name="arm4r",
        paper=PAPER,
        parameters=asdict(p),
        notes=parameter_notes(p),
        table=dh_table(p).locating_table(),
        bodies=tuple(Body(m, r, c) for m, r, c in zip(masses, radii, colors, strict=True)),
        limits=limits,
        points=(Point("O3", 3, (0.0, 0.0, 0.0)), Point("O4", 5, (0.0, 0.0, 0.0))),
        tool_name="O4",
        gravity=(0.0, 0.0, -9.81),
        forward_fn=lambda q: forward(q, p),
        urdf_file=MODELS_DIR / "arm4r.urdf" if not overrides else None,
    )
