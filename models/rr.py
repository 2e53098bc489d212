"""Planar two-link RR arm of paper 000 (Hroncová et al., "Robot trajectory planning", 2022), Fig. 1.

Link lengths L1 = 0.4 m, L2 = 0.3 m; θ1 at the base, θ2 at the elbow (relative). The end
point M is, eqs. (1)–(2),

    x = L1 cos θ1 + L2 cos(θ1 + θ2),   y = L1 sin θ1 + L2 sin(θ1 + θ2).

The arm moves in the x–y plane (joint axes along z), so x, y are the paper's. Paper 000
simulates it in MSC Adams in a vertical plane with gravity (Fig. 26), so the default
gravity here is −y. The paper gives no masses: the ones below are chosen.

The arm's extras (:mod:`armlab.models.extras`): the closed-form inverse kinematics
(:func:`armlab.kinematics.ik_closed_form.rr_ik`, both elbow branches, either chosen by number); the
paper motions

* Fig. 3/5/7 (:func:`fig3_motion`, ``armlab simulate rr``): θ1 −38° → 62°, θ2 98° → 68°, rest to rest
  in t_f = 2 s (the t_f that reproduces the paper's coefficients a1 … b3);
* path ``abcd`` (:func:`abcd_motion`), Figs. 8–10: A → B → C → D → A through the points of Table 1,
  each segment a rest-to-rest quintic between the exact inverse-kinematics angles on the branch
  Table 2 uses at each end (Table 2 rounds 73.7398° to 74°). The paper gives no segment time:
  2 s each is chosen (Fig. 3's t_f). Table 2 leaves C and A on another branch than it reaches
  them on, and D at θ2 = −180° after reaching it at +180° (the same pose, but the joint would
  have to unwind), so the motion is three runs: A–B–C, C–D, D–A (see
  :meth:`armlab.kinematics.quintic.Motion.runs`);

and the scheme of Fig. 1, drawn with its DH table at the start of Fig. 3.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import NDArray

from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.ik import solve_branch
from armlab.kinematics.ik_closed_form import ClosedForm, planar_target, rr_ik
from armlab.kinematics.quintic import Motion, QuinticSegment, Segment, check_duration
from armlab.models.arm import MODELS_DIR, Arm, Forward, chosen, from_paper, parameter_notes
from armlab.models.extras import PaperScheme, motion_start
from armlab.models.write_urdf import Body, JointLimits, Point

PAPER = "000: Hroncová et al., Robot trajectory planning, MM Science Journal 2022, Fig. 1, eqs. (1)-(2)"

#: Paper 000, Table 1: the points A, B, C, D (m).
ABCD_POINTS: dict[str, tuple[float, float]] = {"A": (0.4, -0.3), "B": (0.7, 0.0), "C": (0.4, 0.3), "D": (0.1, 0.0)}
#: Paper 000, Table 2's segments as (start point, its IK branch, end point, its IK branch); branch 0 has
#: θ2 ≥ 0, branch 1 θ2 ≤ 0 (:func:`armlab.kinematics.ik_closed_form.rr_ik`). ``None``: start where the previous
#: ends.
ABCD_SEGMENTS: tuple[tuple[str, int | None, str, int], ...] = (
    ("A", 0, "B", 0), ("B", None, "C", 1), ("C", 0, "D", 0), ("D", 1, "A", 1)
)


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


def fig3_motion(arm: Arm, tf: float | None = None) -> Motion:
    """Paper 000 Figs. 3, 5, 7: θ1 −38° → 62°, θ2 98° → 68°, rest to rest in ``tf`` s (default 2 s)."""
    tf = 2.0 if tf is None else check_duration(tf)
    motion = Motion(
        (QuinticSegment(np.radians([-38.0, 98.0]), np.radians([62.0, 68.0]), tf, "Fig3"),),
        f"paper 000 Figs. 3, 5, 7: θ1 -38° → 62°, θ2 98° → 68°, rest to rest in {tf:g} s",
        {"joints": "000 Fig. 5", "torques": "000 Fig. 7", "path": "000 Fig. 3"},
    )
    motion.check_limits(arm)
    return motion


def abcd_motion(arm: Arm, tf: float | None = None) -> Motion:
    """Paper 000's A → B → C → D → A (Tables 1–2, Figs. 8–10), ``tf`` seconds per segment (default 2 s)."""
    tf = 2.0 if tf is None else check_duration(tf)
    segments: list[Segment] = []
    for start, start_branch, end, end_branch in ABCD_SEGMENTS:
        q0 = segments[-1].q_end if start_branch is None else solve_branch(arm, ABCD_POINTS[start], start_branch)
        qf = solve_branch(arm, ABCD_POINTS[end], end_branch)
        segments.append(QuinticSegment(q0, qf, tf, f"{start}-{end}"))
    motion = Motion(
        tuple(segments),
        f"paper 000 Figs. 8-10: A-B-C-D-A through Table 1's points, Table 2's IK branches, {tf:g} s per segment",
        {"joints": "000 Fig. 9", "torques": "000 Fig. 10", "path": "000 Fig. 8"},
    )
    motion.check_limits(arm)
    return motion


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
        bodies=(Body(p.m1, p.r1, (0.85, 0.45, 0.1, 1), collides=True),
                Body(p.m2, p.r2, (0.2, 0.45, 0.8, 1), collides=True)),
        limits=(limit, limit),
        points=(Point("O2", 1, (p.L1, 0.0, 0.0)), Point("M", 3, (0.0, 0.0, 0.0))),
        tool_name="M",
        gravity=(0.0, -9.81, 0.0),
        forward_fn=lambda q: forward(q, p),
        urdf_file=MODELS_DIR / "rr.urdf" if not overrides else None,
        closed_form=ClosedForm(lambda position, rotation, near: rr_ik(position[:2], p.L1, p.L2),
                               ("θ2 ≥ 0", "θ2 ≤ 0"), coordinates=planar_target, selectable=True),
        motion=fig3_motion,
        paths={"abcd": abcd_motion},
        scheme=PaperScheme("000 Fig. 1", motion_start, dh_table(p)),
    )
