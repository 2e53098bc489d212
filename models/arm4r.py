"""4R arm of paper 001 (Qin et al., "Four degree of freedom manipulator's kinematics
simulation analysis based on MATLAB", Information Technology Journal), Table 1.

Modified (Craig) DH, paper 001 eq. (1): T_{i−1,i} = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i) Tz(d_i);
link 1: a0 = 0, α0 = 0, d1 = 0; link 2: a1 = 0, α1 = −90°, d2; link 3: a2, α2 = 0;
link 4: a3, α3 = 0. At θ = 0, T04 = [[1,0,0,a2+a3],[0,0,1,d2],[0,−1,0,0]] (eq. 6).

The lengths are not printed. The simulation starts "stretched horizontally" at
(2, 0, 0), which gives a2 + a3 = 2 and d2 = 0: the defaults are a2 = a3 = 1 m, d2 = 0.

The arm's extras (:mod:`armlab.models.extras`): the analytical inverse kinematics of eqs. (9)–(21)
(:func:`armlab.kinematics.ik_closed_form.arm4r_ik`, four branches, with the tool pitch); the paper
motion of §3 (:func:`section3_motion`, ``armlab simulate arm4r``): from (2, 0, 0) to (1, 1, 1.4) in
2 s, the tool pitch kept at the start's ("the state is the same with the original state"), both ends
by the paper's inverse kinematics, the solution nearest the start (the paper's rule); and the scheme
of Figs. 1–2, drawn with Table 1's DH table at the motion's start.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from functools import partial

import numpy as np
from numpy.typing import NDArray

from armlab.kinematics.batch import chain_points
from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.ik_closed_form import ClosedForm, arm4r_ik
from armlab.kinematics.quintic import Motion, QuinticSegment, check_duration
from armlab.models.arm import MODELS_DIR, Arm, Forward, chosen, parameter_notes
from armlab.models.extras import PaperScheme, motion_start
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
    return forward_by_table(q, dh_table(p))


def forward_by_table(q: NDArray, table: DHTable) -> Forward:
    """:func:`forward` by ``table`` (:func:`dh_table` of the parameters): an arm keeps its own, made once, so that
    its chain's steps (:attr:`~armlab.kinematics.dh.DHTable.steps`, cached by the table) are not made again at
    every call."""
    origin = (0.0, 0.0, 0.0)
    T04, points = chain_points(q, table.steps, {"O3": (3, origin), "O4": (4, origin)})
    return Forward(T04, points)


def inverse(
    p: Parameters, position: NDArray, rotation: NDArray | None, near: NDArray, pitch: float | None = None
) -> NDArray[np.float64]:
    """The four branches ``(4, 4)`` of :func:`~armlab.kinematics.ik_closed_form.arm4r_ik` reaching ``position``
    (3,) m with the tool ``pitch`` θ2 + θ3 + θ4 (rad; 0 if not given), or with a pose's ``rotation`` (3, 3).

    For a pose, θ1 and the pitch are read off its rotation R04 = Rz(θ1)·Rx(−90°)·Rz(pitch) (tool z axis
    (−s1, c1, 0)), and a pitch too is refused; else on the z0 axis (d2 = 0) θ1 is free and ``near[0]`` is used.
    """
    theta1_free = float(near[0])
    if rotation is not None:
        if pitch is not None:
            raise ValueError(f"a pitch (here {pitch:.6g} rad) is not allowed with a pose target: the pose sets "
                             "the tool pitch")
        theta1_free = float(np.arctan2(-rotation[0, 2], rotation[1, 2]))
        c1, s1 = np.cos(theta1_free), np.sin(theta1_free)
        pitch = float(np.arctan2(-rotation[2, 0], c1 * rotation[0, 0] + s1 * rotation[1, 0]))
    pitch = 0.0 if pitch is None else float(pitch)
    return arm4r_ik(position, pitch, p.a2, p.a3, p.d2, theta1_free=theta1_free)


def section3_motion(arm: Arm, tf: float | None = None) -> Motion:
    """Paper 001 §3: the tool from (2, 0, 0) to (1, 1, 1.4) m with the start's pitch, both ends by the inverse
    kinematics (the solution nearest the start), rest to rest in ``tf`` s (default 2 s)."""
    tf = 2.0 if tf is None else check_duration(tf)
    q0 = arm.ik((2.0, 0.0, 0.0), pitch=0.0)[0]
    pitch = float(q0[1] + q0[2] + q0[3])
    qf = arm.ik((1.0, 1.0, 1.4), pitch=pitch, near=q0)[0]
    motion = Motion(
        (QuinticSegment(q0, qf, tf, "(2,0,0)-(1,1,1.4)"),),
        f"paper 001 §3: tool from (2, 0, 0) to (1, 1, 1.4) m with the start's pitch, IK solution nearest "
        f"the start, rest to rest in {tf:g} s",
        {"joints": "001 Figs. 4-6", "path": "001 Fig. 7"},
    )
    motion.check_limits(arm)
    return motion


def build(**overrides: float) -> Arm:
    """The 4R arm; keyword arguments override :class:`Parameters` by name."""
    p = Parameters(**overrides)
    table = dh_table(p)  # the arm's, with the overrides: its steps made once (forward runs in every log sample)
    limits = tuple(JointLimits(np.radians(lo), np.radians(hi), effort=200.0, velocity=5.0) for lo, hi in LIMITS_DEG)
    colors = [(0.5, 0.5, 0.55, 1), (0.85, 0.45, 0.1, 1), (0.2, 0.45, 0.8, 1), (0.2, 0.7, 0.3, 1)]
    radii = (0.08, 0.05, 0.04, 0.03)
    masses = (p.m1, p.m2, p.m3, p.m4)
    return Arm(
        name="arm4r",
        paper=PAPER,
        parameters=asdict(p),
        notes=parameter_notes(p),
        table=table.locating_table(),
        bodies=tuple(Body(m, r, c, collides=True) for m, r, c in zip(masses, radii, colors, strict=True)),
        limits=limits,
        points=(Point("O3", 3, (0.0, 0.0, 0.0)), Point("O4", 5, (0.0, 0.0, 0.0))),
        tool_name="O4",
        gravity=(0.0, 0.0, -9.81),
        forward_fn=partial(forward_by_table, table=table),
        urdf_file=MODELS_DIR / "arm4r.urdf" if not overrides else None,
        closed_form=ClosedForm(partial(inverse, p), ("θ1 root +, θ3 +", "θ1 root +, θ3 −", "θ1 root −, θ3 +",
                                                     "θ1 root −, θ3 −"), {"pitch": "its tool pitch θ2+θ3+θ4"}),
        motion=section3_motion,
        scheme=PaperScheme("001 Figs. 1-2", motion_start, table),
    )
