"""Paper 000 (Hroncová et al., "Robot trajectory planning", MM Science Journal 2022) reproduced.

RR arm (Figs. 1–10, Tables 1–3): the quintic of Fig. 3 (coefficients, end points, Figs. 3, 5),
the workspace (Fig. 4), the joint torques by Drake's Fig. 6 diagram (Fig. 7), the path
A→B→C→D→A (Table 2, Figs. 8–10, Table 3) with the circle it is claimed to be and the Cartesian
alternative, and the arm in the vertical plane with its tool (Figs. 28–29). RRRR arm (Figs.
15–19, 22–25): the printed symbolic expressions rederived and compared, and the constant-rate
courses of both formulations.

Run alone: ``python papers/paper_000.py --out out/000`` or ``python -m armlab.papers.paper_000``.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from armlab.api import arc, fastest
from armlab.bounds import tolerated
from armlab.diagrams.build import DEFAULT_LOG_PERIOD
from armlab.diagrams.simulate import SimulationOptions, simulate, summarize
from armlab.kinematics.basic_movements import rrrr_dh_chain, rrrr_point_M, rrrr_yup_chain
from armlab.kinematics.quintic import Motion, TrajectorySegment
from armlab.models import get_arm
from armlab.models.plant import PlantOptions
from armlab.models.rr import ABCD_POINTS, ABCD_SEGMENTS, abcd_motion
from armlab.papers.errata import ERRATA
from armlab.papers.paper_output import PaperOutput
from armlab.papers.report_rows import MATCHES, Row, compare, differs, not_reproducible
from armlab.planning.motions import paper_motion
from armlab.presentation.figures import new_figure

PAPER = "000"
TITLE = "Hroncová et al., Robot trajectory planning (MM Science Journal, 2022)"

# ----------------------------------------------------------------------------- the PAPER's printed values
#: §4: the quintic coefficients of Fig. 3's motion (rad, s) — the paper's values.
PAPER_COEFFICIENTS = {"a1": 0.3272, "a2": -1.6362, "a3": 2.1817, "b1": -0.0982, "b2": 0.4909, "b3": -0.6545}
#: §4: peak torques of Fig. 7 (N·m) — the paper's values.
PAPER_PEAK_TORQUES = (20.8183, 0.4888)
#: Table 2 (deg): θ10, θ20, θ1tf, θ2tf per segment — the paper's values.
PAPER_TABLE2_DEG = {"A-B": (-74.0, 90.0, 0.0, 0.0), "B-C": (0.0, 0.0, 74.0, -90.0),
                    "C-D": (0.0, 90.0, 0.0, 180.0), "D-A": (0.0, -180.0, 0.0, -90.0)}
#: Table 3 (N·m): τ1max, τ2max per segment — the paper's values.
PAPER_TABLE3 = {"A-B": (2.4775, 0.4565), "B-C": (2.478, 0.4565), "C-D": (2.4903, 0.4896), "D-A": (2.4899, 0.4892)}
#: Figs. 15, 17, 22: the printed Matlab expressions, transcribed from the text (the paper's forms).
PAPER_PRINTED = {
    "Fig. 15 x0M (DH form)": "L2*cos(q1)*cos(q2) + L4*cos(q4)*(cos(q1)*cos(q2)*cos(q3) - cos(q1)*sin(q2)*sin(q3)) - "
                             "L4*sin(q4)*(cos(q1)*cos(q2)*sin(q3) + cos(q1)*cos(q3)*sin(q2)) + "
                             "L3*cos(q1)*cos(q2)*cos(q3) - L3*cos(q1)*sin(q2)*sin(q3)",
    "Fig. 15 y0M (DH form)": "L2*cos(q2)*sin(q1) - L4*cos(q4)*(sin(q1)*sin(q2)*sin(q3) - cos(q2)*cos(q3)*sin(q1)) - "
                             "L4*sin(q4)*(cos(q2)*sin(q1)*sin(q3) + cos(q3)*sin(q1)*sin(q2)) + "
                             "L3*cos(q2)*cos(q3)*sin(q1) - L3*sin(q1)*sin(q2)*sin(q3)",
    "Fig. 15 z0M (DH form)": "L1 + L2*sin(q2) + L4*cos(q4)*(cos(q2)*sin(q3) + cos(q3)*sin(q2)) + "
                             "L4*sin(q4)*(cos(q2)*cos(q3) - sin(q2)*sin(q3)) + L3*cos(q2)*sin(q3) + L3*cos(q3)*sin(q2)",
    "Fig. 22 x0M (y-up form)": "L2*cos(q1)*cos(q2) + L4*cos(q4)*(cos(q1)*cos(q2)*cos(q3) - cos(q1)*sin(q2)*sin(q3)) - "
                               "L4*sin(q4)*(cos(q1)*cos(q2)*sin(q3) + cos(q1)*cos(q3)*sin(q2)) + "
                               "L3*cos(q1)*cos(q2)*cos(q3) - L3*cos(q1)*sin(q2)*sin(q3)",
    "Fig. 22 y0M (y-up form)": "L1 + L2*sin(q2) + L4*cos(q4)*(cos(q2)*sin(q3) + cos(q3)*sin(q2)) + "
                               "L4*sin(q4)*(cos(q2)*cos(q3) - sin(q2)*sin(q3)) + L3*cos(q2)*sin(q3) + "
                               "L3*cos(q3)*sin(q2)",
    "Fig. 22 z0M (y-up form)": "L4*cos(q4)*(sin(q1)*sin(q2)*sin(q3) - cos(q2)*cos(q3)*sin(q1)) - L2*cos(q2)*sin(q1) + "
                               "L4*sin(q4)*(cos(q2)*sin(q1)*sin(q3) + cos(q3)*sin(q1)*sin(q2)) - "
                               "L3*cos(q2)*cos(q3)*sin(q1) + L3*sin(q1)*sin(q2)*sin(q3)",
    "Fig. 17 |r0M|": "((L2*cos(q1)*cos(q2) + L4*cos(q4)*(cos(q1)*cos(q2)*cos(q3) - cos(q1)*sin(q2)*sin(q3)) - "
                     "L4*sin(q4)*(cos(q1)*cos(q2)*sin(q3) + cos(q1)*cos(q3)*sin(q2)) + L3*cos(q1)*cos(q2)*cos(q3) - "
                     "L3*cos(q1)*sin(q2)*sin(q3))^2 + "
                     "(L4*cos(q4)*(sin(q1)*sin(q2)*sin(q3) - cos(q2)*cos(q3)*sin(q1)) - "
                     "L2*cos(q2)*sin(q1) + L4*sin(q4)*(cos(q2)*sin(q1)*sin(q3) + cos(q3)*sin(q1)*sin(q2)) - "
                     "L3*cos(q2)*cos(q3)*sin(q1) + L3*sin(q1)*sin(q2)*sin(q3))^2 + (L1 + L2*sin(q2) + "
                     "L4*cos(q4)*(cos(q2)*sin(q3) + cos(q3)*sin(q2)) + "
                     "L4*sin(q4)*(cos(q2)*cos(q3) - sin(q2)*sin(q3)) + "
                     "L3*cos(q2)*sin(q3) + L3*cos(q3)*sin(q2))^2)^(1/2)",
}

#: Circle of Table 1's points (m): centre and radius, from the points themselves (checked at run time).
SEGMENTS = ("A-B", "B-C", "C-D", "D-A")
SEGMENT_TIME = 2.0  # s, the t_f that reproduces §4's coefficients; Table 2's segments get the same
TOOL_MASS = 0.25  # kg, chosen: the basket of Fig. 26 as a point mass at M
#: IK samples per quarter of the true circle (it touches the reach at B and D, where the joints' slopes come from
#: the samples: denser keeps M on the circle to 1e-9 m between them).
ARC_SAMPLES = 801
#: Table 2 tolerance (deg): the paper prints whole degrees, so half of the last printed unit.
TABLE2_TOL_DEG = 0.5


def _deg(x: np.ndarray) -> np.ndarray:
    return np.degrees(x)


# ----------------------------------------------------------------------------- RR: Fig. 3 motion
def _fig3_kinematics(out: PaperOutput, arm: Any, motion: Any, t: np.ndarray) -> None:
    out.group("§4, Figs. 3 and 5: the quintic of Fig. 3's motion",
              "θ1 −38° → 62°, θ2 98° → 68° (the printed angles) by a rest-to-rest quintic per joint. The paper "
              "prints no coordinates of M0 or M_fin; Fig. 3 marks the ones armlab computes from those angles.")
    coefficients = motion.coefficients()[0]  # (2 joints, 6): [a1 … a6]
    names = ("a", "b")
    table = []
    for j, stem in enumerate(names):
        for k in range(3):
            key = f"{stem}{k + 1}"
            out.add(compare(PAPER, f"§4 quintic coefficient {key} [rad/s^{5 - k}]", PAPER_COEFFICIENTS[key],
                            float(coefficients[j, k]), 5e-5,
                            f"kinematics.quintic: 6×6 system of eqs. (3)-(6), t_f = {motion.duration:g} s; "
                            "tolerance: half the 4th printed decimal"))
        table.append([f"θ{j + 1}", *coefficients[j].tolist()])
    out.table("quintic_coefficients", "§4 — quintic coefficients of Fig. 3's motion (rad, s)",
              ["joint", "a1 (t^5)", "a2 (t^4)", "a3 (t^3)", "a4 (t^2)", "a5 (t)", "a6 (1)"], table,
              note=f"θ(t) = a1 t⁵ + a2 t⁴ + a3 t³ + a4 t² + a5 t + a6 (paper eqs. 3-6; 'b' for θ2), "
                   f"t_f = {motion.duration:g} s. Paper: "
                   + ", ".join(f"{key} = {value:g}" for key, value in PAPER_COEFFICIENTS.items()) + ".")
    q, qd, qdd = motion.evaluate(t)
    M = arm.forward(q).points["M"]
    O2 = arm.forward(q).points["O2"]

    fig, ax = new_figure("Paper 000, Fig. 3 — trajectory of the end point M\n(θ1 −38° → 62°, θ2 98° → 68°, t_f = "
                         f"{motion.duration:g} s)", size=(6.5, 6))
    ax.plot(M[:, 0], M[:, 1], label="M(t), quintic in joint space")
    for k, alpha in ((0, 1.0), (len(t) // 4, 0.35), (len(t) // 2, 0.35), (3 * len(t) // 4, 0.35), (-1, 1.0)):
        ax.plot([0, O2[k, 0], M[k, 0]], [0, O2[k, 1], M[k, 1]], "-o", color="0.3", alpha=alpha, ms=3, lw=2,
                label="arm at t = 0, t_f/4, t_f/2, 3t_f/4, t_f" if k == 0 else None)
    ax.annotate(f"M0 ({M[0, 0]:.4f}, {M[0, 1]:.4f}), armlab", M[0, :2], xytext=(10, -14),
                textcoords="offset points")
    ax.annotate(f"M_fin ({M[-1, 0]:.4f}, {M[-1, 1]:.4f}), armlab", M[-1, :2], xytext=(8, 6),
                textcoords="offset points")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")
    ax.legend(loc="lower left")
    out.figure(fig, "fig03_trajectory", "Fig. 3", "trajectory of M for the quintic of §4 (M0, M_fin: armlab's FK "
               "of the printed angles, eqs. 1-2)")

    fig, axes = new_figure("Paper 000, Fig. 5 — angles, angular velocities and accelerations (Fig. 3's motion)",
                           3, 1, size=(7, 7), sharex=True)
    for j in range(2):
        axes[0, 0].plot(t, _deg(q[:, j]), label=f"θ{j + 1}")
        axes[1, 0].plot(t, qd[:, j], label=f"ω{j + 1}")
        axes[2, 0].plot(t, qdd[:, j], label=f"α{j + 1}")
    for ax, unit in zip(axes[:, 0], ("θ [deg]", "ω [rad/s]", "α [rad/s²]"), strict=True):
        ax.set_ylabel(unit)
        ax.legend(loc="best")
    axes[2, 0].set_xlabel("t [s]")
    out.figure(fig, "fig05_joint_courses", "Fig. 5", "θ, ω, α of both joints for the quintic of §4")


def _fig4_workspace(out: PaperOutput, arm: Any, fast: bool) -> None:
    out.group("Fig. 4: the workspace")
    grid = np.arange(0.0, 1.5 * np.pi, 0.1)  # the paper's theta = 0:0.1:3*pi/2 (Matlab's colon: ends ≤ 3π/2)
    t1, t2 = np.meshgrid(grid, grid, indexing="ij")
    M = arm.forward(np.stack([t1.ravel(), t2.ravel()], axis=-1)).points["M"]
    fig, ax = new_figure(f"Paper 000, Fig. 4 — positions of M for θ1, θ2 = 0:0.1:3π/2 ({M.shape[0]} combinations)",
                         size=(6.5, 6))
    cloud = ax.scatter(M[:, 0], M[:, 1], s=3, c=t1.ravel(), cmap="viridis", label="M(θ1, θ2)")
    fig.colorbar(cloud, ax=ax, label="θ1 [rad] (the colour of each point)", shrink=0.8)
    L1, L2 = arm.parameters["L1"], arm.parameters["L2"]
    phi = np.linspace(0, 2 * np.pi, 361)
    for r, style in ((L1 + L2, "--"), (L1 - L2, ":")):
        ax.plot(r * np.cos(phi), r * np.sin(phi), style, color="0.4", lw=1, label=f"|M| = {r:.1f} m")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.09), ncols=3, markerscale=3)  # below: covers no point
    out.figure(fig, "fig04_workspace", "Fig. 4", "end point M over the paper's grid of θ1, θ2")


# ----------------------------------------------------------------------------- RR: A→B→C→D→A
def _circle(points: dict[str, tuple[float, float]]) -> tuple[np.ndarray, float]:
    """Centre and radius of the circle through A, B, C (the paper says all four lie on one)."""
    a, b, c = (np.asarray(points[k]) for k in "ABC")
    # perpendicular bisectors of AB and BC: 2 (b − a)·x = |b|² − |a|², 2 (c − b)·x = |c|² − |b|²
    A = 2 * np.array([b - a, c - b])
    rhs = np.array([b @ b - a @ a, c @ c - b @ b])
    centre = np.linalg.solve(A, rhs)
    return centre, float(np.linalg.norm(a - centre))


def _true_arc(arm: Any, centre: np.ndarray, tau: np.ndarray) -> tuple[Any, dict[str, np.ndarray]]:
    """The true circle A→B→C→D→A by the library (:func:`armlab.arc`): per segment a quarter turn of the tool about
    the centre (axis +z), timed by the minimum-jerk profile over the segment time (a rest-to-rest quintic in the
    polar angle φ), IK along it on IK branch 0 (θ2 ≥ 0, the branch A is left on in Table 2) and each segment
    starting at the joints the previous one ends at: one continuous motion.

    Returns the motion and its q, q̇, q̈ at the segments' local times ``tau`` (segments, samples, 2) and M.
    """
    segments: list[Any] = []
    q0 = None
    for label in SEGMENTS:
        motion = arc(arm, centre=np.append(centre, 0.0), axis=[0.0, 0.0, 1.0], start=ABCD_POINTS[label[0]],
                     angle=np.pi / 2, tf=SEGMENT_TIME, q0=q0, branch=0 if q0 is None else None, samples=ARC_SAMPLES)
        (piece,) = motion.segments
        assert isinstance(piece, TrajectorySegment)  # a tool path is one trajectory segment
        segments.append(TrajectorySegment(piece.trajectory, label))
        q0 = segments[-1].q_end
    circle = Motion(tuple(segments), "the tool along the circle A-B-C-D-A (true arcs, IK branch 0)")
    out: dict[str, list[np.ndarray]] = {key: [] for key in ("q", "qd", "qdd", "M")}
    for k in range(4):
        q, qd, qdd = _segment_samples(circle, k, tau)
        for key, value in (("q", q), ("qd", qd), ("qdd", qdd), ("M", arm.forward(q).points["M"][:, :2])):
            out[key].append(value)
    return circle, {key: np.stack(value) for key, value in out.items()}


def _segment_samples(motion: Any, k: int, tau: np.ndarray) -> np.ndarray:
    """q, q̇, q̈ of segment ``k`` at its local times ``tau``, each (m, n)."""
    return motion.evaluate(motion.breaks[k] + np.clip(tau, 0, motion.segments[k].duration * (1 - 1e-12)))


def _abcd(out: PaperOutput, arm: Any, fast: bool, log_period: float) -> None:
    motion = abcd_motion(arm, SEGMENT_TIME)
    labels = motion.labels
    # ---- Table 2: exact IK angles at each segment's ends, on the branch Table 2 uses there
    out.group("Table 2: joint angles at A, B, C and D",
              "armlab: exact inverse kinematics (law of cosines) of Table 1's points on the IK branch Table 2 uses "
              "at each end. Table 2 prints whole degrees: a value matches within half a degree.")
    names = ("θ10", "θ20", "θ1tf", "θ2tf")
    ends = np.array([[seg.q_start, seg.q_end] for seg in motion.segments])  # (4, 2, 2)
    points = np.array([[ABCD_POINTS[label[0]], ABCD_POINTS[label[-1]]] for label in labels])
    fk_gap = float(np.abs(arm.forward(ends.reshape(-1, 2)).points["M"][:, :2] - points.reshape(-1, 2)).max())
    table2 = []
    for k, (label, seg) in enumerate(zip(labels, motion.segments, strict=True)):
        values = _deg(np.array([seg.q_start[0], seg.q_start[1], seg.q_end[0], seg.q_end[1]]))
        branches = ABCD_SEGMENTS[k]
        start_branch = "as reached" if branches[1] is None else branches[1]
        note = (f"kinematics.ik_closed_form.rr_ik on IK branch {start_branch}/{branches[3]} at start/end (0: θ2 ≥ 0, "
                f"1: θ2 ≤ 0), the branch Table 2 uses; forward kinematics of armlab's angles reproduces Table 1's "
                f"points to {fk_gap:.1e} m; tolerance {TABLE2_TOL_DEG:g}° (whole degrees printed)")
        for name, paper_value, value in zip(names, PAPER_TABLE2_DEG[label], values, strict=True):
            out.add(compare(PAPER, f"Table 2 {label} {name} [deg]", paper_value, float(value), TABLE2_TOL_DEG, note))
        table2.append([label, *values.tolist(), *PAPER_TABLE2_DEG[label]])
    out.table("table2_ik_angles", "Table 2 — joint angles at the ends of each segment (deg), armlab vs paper",
              ["segment", "θ10", "θ20", "θ1tf", "θ2tf", "θ10 paper", "θ20 paper", "θ1tf paper", "θ2tf paper"], table2)
    _branch_switches(out, motion)

    # ---- the circle claim: radial deviation of M along each joint-space segment, and the Cartesian arc
    centre, radius = _circle(ABCD_POINTS)
    d_on_circle = abs(np.linalg.norm(np.asarray(ABCD_POINTS["D"]) - centre) - radius)
    tau = np.linspace(0.0, SEGMENT_TIME, 101 if fast else 401)
    joint_space = [_segment_samples(motion, k, tau) for k in range(4)]
    M_joint = np.stack([arm.forward(q).points["M"][:, :2] for q, _, _ in joint_space])
    radial_joint = np.abs(np.linalg.norm(M_joint - centre, axis=-1) - radius).max(axis=1)
    circle, true_arc = _true_arc(arm, centre, tau)
    M_arc = true_arc["M"]
    radial_arc = np.abs(np.linalg.norm(M_arc - centre, axis=-1) - radius).max(axis=1)

    # ---- simulation (Fig. 6 diagram) and inverse dynamics of the same reference
    log = simulate(arm, motion, SimulationOptions(log_period=log_period))
    tau_id = arm.inverse_dynamics(log.q_ref, log.qd_ref, log.qdd_ref)
    id_gap = float(np.abs(tau_id - log.tau).max())
    tau_arc = np.stack([arm.inverse_dynamics(q, qd, qdd) for q, qd, qdd in zip(
        true_arc["q"], true_arc["qd"], true_arc["qdd"], strict=True)])
    segments = summarize(log)["segments"]  # per segment, both ends included, as armlab simulate reports them
    peaks = np.array([segments[k]["max_abs_torque"] for k in range(4)])
    peaks_arc = np.abs(tau_arc).max(axis=1)

    out.group("Fig. 8: is the path A→B→C→D→A a circle?")
    for k, label in enumerate(labels):
        out.add(compare(
            PAPER, f"Fig. 8 claim: M on the circle through A-D, max radial deviation on {label} [m]", 0.0,
            float(radial_joint[k]), 1e-9,
            f"circle centre ({centre[0]:.4g}, {centre[1]:.4g}) m, r = {radius:.4g} m from A, B, C (D lies on it to "
            f"{d_on_circle:.1e} m); joint-space quintic, FK at {tau.size} samples",
            "the joint-space quintic leaves the circle (the paper's 'as expected, the circle' is not)"))
    out.claim(
        "the path A→B→C→D→A is a circle (Fig. 8)",
        f"Table 1's points lie on the circle of radius {radius:.4g} m about ({centre[0]:.4g}, {centre[1]:.4g}) m, and "
        "the paper says M draws it. Each segment is a quintic in joint space, so M follows the circle only where θ1 "
        "stays constant (C-D, D-A: θ2 alone turns M about the elbow at (0.4, 0)). On A-B and B-C M leaves the circle. "
        "The Cartesian alternative moves M along the true arc (a rest-to-rest quintic in the polar angle, joint "
        "values by IK along it, all on IK branch 0) in the same 2 s per segment; its peak torques are beside the "
        "joint-space ones (Drake, armlab's chosen masses).",
        ["segment", "max radial dev. joint-space [m]", "max radial dev. Cartesian [m]", "τ1max joint [N·m]",
         "τ2max joint [N·m]", "τ1max Cartesian [N·m]", "τ2max Cartesian [N·m]"],
        [[label, float(radial_joint[k]), float(radial_arc[k]), *peaks[k].tolist(), *peaks_arc[k].tolist()]
         for k, label in enumerate(labels)])
    fig, ax = new_figure("Paper 000, Fig. 8 — trajectory of M from A to B, C, D and back to A", size=(6.5, 6))
    phi = np.linspace(0, 2 * np.pi, 361)
    ax.plot(centre[0] + radius * np.cos(phi), centre[1] + radius * np.sin(phi), "-", color="0.75", lw=5,
            label=f"circle r = {radius:.2g} m (claimed)")
    for k, label in enumerate(labels):
        ax.plot(M_joint[k, :, 0], M_joint[k, :, 1], label=f"{label} joint-space quintic (max dev. "
                f"{radial_joint[k] * 1e3:.1f} mm)")
    ax.plot(M_arc[..., 0].ravel(), M_arc[..., 1].ravel(), "k--", lw=1, label="Cartesian arc (IK along it)")
    for name, xy in ABCD_POINTS.items():
        ax.plot(*xy, "ko", ms=4)
        ax.annotate(name, xy, xytext=(6, 4), textcoords="offset points", fontweight="bold")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")
    ax.legend(loc="upper left", fontsize=7)
    out.figure(fig, "fig08_abcd_path", "Fig. 8", "M along A-B-C-D-A: joint-space quintics vs the circle")
    _circle_done(out, arm, circle, centre, radius, radial_joint)

    out.group("Table 3, Figs. 9 and 10: the A→B→C→D→A run and its peak torques",
              "Simulated through Drake's Fig. 6 diagram with armlab's chosen masses: the paper publishes no mass "
              "properties, so its torques are not reproducible; the shapes of Figs. 9-10 are.")
    table3 = []
    for k, label in enumerate(labels):
        for j in range(2):
            out.add(Row(PAPER, f"Table 3 {label} τ{j + 1}max [N·m]", PAPER_TABLE3[label][j], float(peaks[k, j]),
                        float(peaks[k, j] - PAPER_TABLE3[label][j]),
                        not_reproducible("mass properties not published (no masses, inertias or gravity direction)"),
                        "armlab: Drake's Fig. 6 diagram with the chosen masses (parameters below); not tuned"))
        table3.append([label, *PAPER_TABLE3[label], *peaks[k].tolist(), *peaks_arc[k].tolist()])
    out.table("table3_peak_torques", "Table 3 — peak joint torques per segment (N·m): paper, armlab joint-space, "
              "armlab Cartesian arc",
              ["segment", "τ1max paper", "τ2max paper", "τ1max joint-space", "τ2max joint-space", "τ1max Cartesian",
               "τ2max Cartesian"], table3,
              note=f"Joint space: simulated (controller torques of Fig. 6's diagram; Drake inverse dynamics of the "
                   f"reference agrees to {id_gap:.2e} N·m). Cartesian: the true arc by IK along it, torques by Drake's "
                   "inverse dynamics. Masses are armlab's choice: the paper's values are not reproducible.")
    out.simulated_run(log, "abcd", "the A-B-C-D-A run (Figs. 8-10)")

    fig, axes = new_figure("Paper 000, Fig. 9 — θ, ω, α for the sections a) A-B, b) B-C, c) C-D, d) D-A",
                           3, 4, size=(12, 7.5), sharex=True)
    for k, label in enumerate(labels):
        q, qd, qdd = joint_space[k]
        for j in range(2):
            axes[0, k].plot(tau, _deg(q[:, j]), label=f"θ{j + 1}")
            axes[1, k].plot(tau, qd[:, j], label=f"ω{j + 1}")
            axes[2, k].plot(tau, qdd[:, j], label=f"α{j + 1}")
        axes[0, k].set_title(f"{'abcd'[k]}) {label}")
        axes[2, k].set_xlabel("t [s]")
    for row, unit in enumerate(("θ [deg]", "ω [rad/s]", "α [rad/s²]")):
        axes[row, 0].set_ylabel(unit)
        axes[row, 0].legend(loc="best")
    out.figure(fig, "fig09_abcd_joints", "Fig. 9", "joint angles, velocities, accelerations per segment")

    fig, axes = new_figure("Paper 000, Fig. 10 — joint torques τ1, τ2 for a) A-B, b) B-C, c) C-D, d) D-A "
                           "(joint-space simulated; Cartesian arc dashed)", 2, 4, size=(12, 6), sharex=True)
    for k, label in enumerate(labels):
        rows = log.segment_rows(k)
        t_local = log.t[rows] - motion.breaks[k]
        for j in range(2):
            axes[j, k].plot(t_local, log.tau[rows, j], label=f"τ{j + 1} joint-space (simulated)")
            axes[j, k].plot(tau, tau_arc[k][:, j], "--", label=f"τ{j + 1} Cartesian arc (inverse dynamics)")
        axes[0, k].set_title(f"{'abcd'[k]}) {label}")
        axes[1, k].set_xlabel("t [s]")
    axes[0, 0].set_ylabel("τ1 [N·m]")
    axes[1, 0].set_ylabel("τ2 [N·m]")
    axes[0, 0].legend(loc="best", fontsize=7)
    axes[1, 0].legend(loc="best", fontsize=7)
    out.figure(fig, "fig10_abcd_torques", "Fig. 10", "joint torques per segment, joint-space and Cartesian")


def _circle_done(out: PaperOutput, arm: Any, circle: Motion, centre: np.ndarray, radius: float,
                 radial_joint: np.ndarray) -> None:
    """Fig. 8 done as the paper meant it: the circle as true arcs of the tool (armlab.arc), checked densely, and
    its fastest timing under the RR arm's own limits (Drake's Toppra, armlab.fastest)."""
    out.group("Fig. 8 done as meant: the circle A→B→C→D→A as true arcs of the tool",
              "armlab.arc about the circle's centre, a quarter turn per segment in 2 s (minimum-jerk timing), IK "
              "along it on branch 0 throughout (one continuous motion), beside the paper's joint-space quintics.")
    t = np.linspace(0.0, circle.duration, 8001)
    q, qd, qdd = circle.evaluate(t)
    radial = float(np.abs(np.linalg.norm(arm.forward(q).points["M"][:, :2] - centre, axis=-1) - radius).max())
    out.add(compare(PAPER, "Fig. 8 claim, done as meant: M on the circle along the true arcs, max radial deviation "
                    "[m]", 0.0, radial, 1e-9,
                    f"armlab.arc per segment, FK at {t.size} times over the {circle.duration:g} s, between the "
                    f"{4 * ARC_SAMPLES} IK samples too; the paper's joint-space quintics leave it by "
                    f"{radial_joint.max() * 1e3:.1f} mm"))
    whole = arc(arm, centre=np.append(centre, 0.0), axis=[0.0, 0.0, 1.0], start=ABCD_POINTS["A"], angle=2 * np.pi,
                tf=4 * SEGMENT_TIME, branch=0, samples=4 * ARC_SAMPLES)
    best = fastest(arm, whole)
    limits = best.limits
    out.claim(
        "the fastest circle the RR arm's drives allow",
        f"The whole circle A→B→C→D→A as one arc of the tool (IK branch 0), timed by Drake's Toppra within the RR "
        f"arm's limits from its URDF (|q̇| ≤ {limits.velocity.max():g} rad/s, |τ| ≤ {limits.effort.max():g} N·m, "
        f"gravity −y, no acceleration limit in the file): {best.duration:.4g} s, against the paper's "
        f"{4 * SEGMENT_TIME:g} s with stops at B, C and D. A limit is active on {best.active_fraction:.0%} of the "
        f"path, mostly {best.most_active or 'none'}.",
        ["quantity", "value"],
        [["time-optimal duration [s]", best.duration], ["paper's duration [s]", 4 * SEGMENT_TIME],
         ["path fraction with an active limit", best.active_fraction], ["max radial deviation of the arcs [m]",
                                                                        radial]])
    rate = best.rate_figure("Paper 000, Fig. 8 done as meant — the fastest circle: path rate ṡ against its limit\n"
                            f"(Toppra, RR arm's URDF limits, {best.duration:.3g} s)", "the circle from A")
    out.figure(rate, "fig08_fastest_circle", "Fig. 8 (done as meant)",
               "path rate of the time-optimal circle against its limit curve")
    fig, axes = new_figure("Paper 000, Fig. 8 done as meant — joint angles and torques along the true arcs",
                           2, 1, size=(7, 5.5), sharex=True)
    tau = arm.inverse_dynamics(q, qd, qdd)
    for j in range(2):
        axes[0, 0].plot(t, _deg(q[:, j]), label=f"θ{j + 1}")
        axes[1, 0].plot(t, tau[:, j], label=f"τ{j + 1} (inverse dynamics)")
    axes[0, 0].set_ylabel("θ [deg]")
    axes[1, 0].set_ylabel("τ [N·m]")
    axes[1, 0].set_xlabel("t [s]")
    axes[0, 0].legend(loc="best")
    axes[1, 0].legend(loc="best")
    out.figure(fig, "fig08_arc_joints", "Fig. 8 (done as meant)", "joint angles and torques of the true circle")


def _branch_switches(out: PaperOutput, motion: Any) -> None:
    """The claim that Table 2 is one closed motion: the joins where its end angles are not the next start's."""
    labels, segments = motion.labels, motion.segments
    jumps, reconfigurations = [], []
    for k in range(4):
        a, b = segments[k], segments[(k + 1) % 4]
        end, start = _deg(a.qf), _deg(b.q0)
        jump = float(np.abs(start - end).max())
        jumps.append([f"{labels[k]} → {labels[(k + 1) % 4]}", *end.tolist(), *start.tolist(), jump])
        if not tolerated(jump, 1e-9):
            shown = np.round(np.concatenate([end, start]), 2) + 0.0  # + 0.0: no "-0.00"
            reconfigurations.append(f"at {labels[k][-1]} (reached at ({shown[0]:.2f}°, {shown[1]:.2f}°), left at "
                                    f"({shown[2]:.2f}°, {shown[3]:.2f}°))")
    runs = ["-".join([piece.labels[0].split("-")[0]] + [label.split("-")[1] for label in piece.labels])
            for _, piece in motion.runs()]
    out.claim(
        "Table 2 describes one closed motion; its IK branch switches between segments",
        f"Table 2's end angles of one segment are not the start angles of the next {'; '.join(reconfigurations)}: "
        "the IK branch changes there, or θ2 jumps by a full turn (the same pose, but the joint would have to "
        "unwind). The robot would have to reconfigure at rest between those segments; armlab simulates "
        f"{', '.join(runs)} as separate runs. On the Cartesian alternative (Fig. 8 below) the arm stays on IK "
        "branch 0 throughout.",
        ["join", "θ1 end [deg]", "θ2 end [deg]", "θ1 next start [deg]", "θ2 next start [deg]", "max jump [deg]"], jumps)


def _dynamics(out: PaperOutput, arm: Any, motion: Any, log_period: float) -> None:
    """Fig. 7 (torques of Fig. 3's motion) and Figs. 28-29 (the arm with its tool, vertical plane)."""
    out.group("§4, Fig. 7: joint torques of Fig. 3's motion",
              "Simulated through Drake's version of the paper's Fig. 6 diagram (quintic trajectory source → inverse "
              "dynamics controller → plant → scopes) with armlab's chosen masses.")
    log = simulate(arm, motion, SimulationOptions(log_period=log_period))
    out.simulated_run(log, "fig07", "Fig. 3's motion (Figs. 5, 7)")
    tau_id = arm.inverse_dynamics(log.q_ref, log.qd_ref, log.qdd_ref)
    id_gap = float(np.abs(tau_id - log.tau).max())
    peak = np.abs(log.tau).max(axis=0)
    for j in range(2):
        out.add(Row(PAPER, f"§4 peak torque τ{j + 1} of Fig. 7 [N·m]", PAPER_PEAK_TORQUES[j], float(peak[j]),
                    float(peak[j] - PAPER_PEAK_TORQUES[j]),
                    not_reproducible("mass properties not published (no masses, inertias or gravity direction)"),
                    f"armlab: Fig. 6 diagram with the chosen masses, gravity −y; inverse dynamics of the reference "
                    f"agrees to {id_gap:.2e} N·m; not tuned"))
    fig, axes = new_figure("Paper 000, Fig. 7 — joint torques τ1, τ2 for Fig. 3's motion", 2, 1, size=(7, 5.5),
                           sharex=True)
    for j in range(2):
        axes[j, 0].plot(log.t, log.tau[:, j], label=f"τ{j + 1}, simulated (Fig. 6 diagram)")
        axes[j, 0].plot(log.t, tau_id[:, j], "--", label=f"τ{j + 1}, inverse dynamics of the reference")
        axes[j, 0].set_ylabel(f"τ{j + 1} [N·m]")
        axes[j, 0].legend(loc="best")
    axes[1, 0].set_xlabel("t [s]")
    out.figure(fig, "fig07_torques", "Fig. 7", "joint torques of the quintic of §4 (armlab's chosen masses)")

    out.group("Figs. 26-29: the arm with its tool in the vertical plane")
    tool_log = simulate(arm, motion, SimulationOptions(PlantOptions(payload=TOOL_MASS, ideal_drives=True),
                                                     log_period=log_period))
    out.simulated_run(tool_log, "fig28", "the arm with its tool in the vertical plane (Figs. 28-29)")
    q_ref = tool_log.q_ref
    M_ref = arm.forward(q_ref).points["M"]
    gap = float(np.abs(tool_log.tool[:, :3] - M_ref).max())
    for number, offset, what, unit in ((28, 0, "position", "m"), (29, 3, "velocity", "m/s")):
        fig, axes = new_figure(f"Paper 000, Fig. {number} — {what} of the tool's centre of mass (vertical plane, "
                               f"gravity −y, tool {TOOL_MASS:g} kg)", 3, 1, size=(7, 6.5), sharex=True)
        for i, axis in enumerate("xyz"):
            symbol = f"{axis}_M" if offset == 0 else f"v_{axis}M"
            axes[i, 0].plot(tool_log.t, tool_log.tool[:, offset + i], label=f"{symbol}, simulated")
            axes[i, 0].set_ylabel(f"{'abc'[i]}) {symbol} [{unit}]")
            axes[i, 0].legend(loc="best")
        axes[2, 0].set_xlabel("t [s]")
        out.figure(fig, f"fig{number}_tool_{what}", f"Fig. {number}",
                   f"tool {what} in the simulated run (tracks the kinematic reference to {gap:.1e} m)")


# ----------------------------------------------------------------------------- RRRR
def _rrrr(out: PaperOutput) -> None:
    from armlab.kinematics.symbolic import arm_kinematics

    arm = get_arm("rrrr")
    out.group("§7, Figs. 18-19 and 24-25: the RRRR arm at constant joint rates",
              "Both formulations of the paper: DH (Figs. 11-19) and basic movements with y up (Figs. 20-25).")
    out.scheme(arm, np.radians([30.0, 40.0, -60.0, 30.0]), "scheme_rrrr", "the RRRR arm (cf. Figs. 11-13, 20) at "
               "q = (30°, 40°, −60°, 30°), drawn from armlab's model")
    motion = paper_motion(arm)  # q = ω t, ω = (7, 0.05, 0.05, 0.05) rad/s, 15 s
    t = np.linspace(0.0, motion.duration, round(motion.duration / 0.05) + 1)  # the paper's t = 0:0.05:15
    q = motion.evaluate(t)[0]
    L = (arm.parameters["L1"], arm.parameters["L2"], arm.parameters["L3"], arm.parameters["L4"])
    dh = rrrr_point_M(rrrr_dh_chain(q, L))
    yup = rrrr_point_M(rrrr_yup_chain(q, L))
    sym = arm_kinematics(get_arm("rrrr")).numeric().position(q)
    sym_gap = float(np.abs(sym - dh).max())
    norm_gap = float(np.abs(np.linalg.norm(dh, axis=1) - np.linalg.norm(yup, axis=1)).max())
    out.add(Row(PAPER, "§7 claim: |r0M| of the y-up form (Fig. 20) identical to the DH form's (Fig. 17), max "
                "difference on the run of Figs. 18/24 [m]", "identical", norm_gap, norm_gap,
                MATCHES if tolerated(norm_gap, 1e-12) else differs(f"the two forms differ by {norm_gap:.3g} m"),
                f"basic-movement chains eqs. (21)-(34) and (36)-(47); sympy's r0M agrees with eqs. (21)-(34) to "
                f"{sym_gap:.1e} m; tolerance 1e-12 m"))
    for number, points, form in ((18, dh, "DH form, Fig. 13"), (24, yup, "y-up form, Fig. 20")):
        fig, axes = new_figure(f"Paper 000, Fig. {number} — components of r0M over time ({form}; "
                               "ω = 7, 0.05, 0.05, 0.05 rad/s)", 3, 1, size=(7.5, 6.5), sharex=True)
        for i, axis in enumerate("xyz"):
            axes[i, 0].plot(t, points[:, i], lw=1, label=f"{axis}0M(t)")
            axes[i, 0].set_ylabel(f"{axis}0M [m]")
            axes[i, 0].legend(loc="upper right")
        axes[2, 0].set_xlabel("t [s]")
        out.figure(fig, f"fig{number}_rrrr_components", f"Fig. {number}",
                   f"x0M, y0M, z0M of the RRRR arm over t = 0:0.05:15 s ({form})")
    for number, points, pairs, form in ((19, dh, ((0, 1), (0, 2), (1, 2)), "DH form"),
                                        (25, yup, ((0, 2), (0, 1), (2, 1)), "y-up form")):
        fig, axes = new_figure(f"Paper 000, Fig. {number} — trajectory of M in the coordinate planes ({form})",
                               1, 3, size=(12, 4.2))
        for k, (a, b) in enumerate(pairs):
            ax = axes[0, k]
            ax.plot(points[:, a], points[:, b], lw=0.8, label=f"{'xyz'[b]}0M = f({'xyz'[a]}0M)")
            ax.set_xlabel(f"{'xyz'[a]}0M [m]")
            ax.set_ylabel(f"{'xyz'[b]}0M [m]")
            ax.set_aspect("equal", adjustable="datalim")
            ax.legend(loc="upper right")
        out.figure(fig, f"fig{number}_rrrr_planes", f"Fig. {number}", f"trajectory of M in the planes ({form})")
    out.replay(arm, t, q, "rrrr", "the RRRR arm's constant-rate motion of Figs. 18-19 (q = ω t, 15 s)")


def _symbolic(out: PaperOutput) -> None:
    """Figs. 15-17, 22-23 rederived with sympy; each printed form compared at random points."""
    import sympy as sp

    from armlab.kinematics.symbolic import latex_table, rrrr_dh, rrrr_yup

    out.group("Figs. 15-17, 22-23: the printed symbolic expressions")
    dh, yup = rrrr_dh(), rrrr_yup()
    derived = {"Fig. 15 x0M (DH form)": dh.x0M, "Fig. 15 y0M (DH form)": dh.y0M, "Fig. 15 z0M (DH form)": dh.z0M,
               "Fig. 22 x0M (y-up form)": yup.x0M, "Fig. 22 y0M (y-up form)": yup.y0M,
               "Fig. 22 z0M (y-up form)": yup.z0M, "Fig. 17 |r0M|": dh.norm}
    symbols = {s.name: s for s in (*dh.q, *dh.L)}
    rng = np.random.default_rng(0)
    values = {name: rng.uniform(-np.pi, np.pi, 200) if name.startswith("q") else rng.uniform(0.1, 1.0, 200)
              for name in symbols}
    notes: dict[str, str] = {}
    for key, text in PAPER_PRINTED.items():
        printed = sp.sympify(text.replace("^", "**"), locals=symbols)
        args = list(symbols.values())
        f_printed, f_derived = (sp.lambdify(args, e, "numpy") for e in (printed, derived[key]))
        inputs = [values[s.name] for s in args]
        gap = float(np.max(np.abs(f_printed(*inputs) - f_derived(*inputs))))
        verdict = MATCHES if tolerated(gap, 1e-12) else differs(f"the printed form is off by up to {gap:.3g}")
        out.add(Row(PAPER, f"{key}, printed symbolic expression", "printed (Matlab)", "sympy, rederived", gap, verdict,
                    "max |printed − rederived| at 200 random (q, L); tolerance 1e-12"))
        notes[key] = "matches the paper's printed form" if verdict == MATCHES else verdict
    errata = {e.equation: e for e in ERRATA if e.paper == PAPER}
    entries, beyond = [], []
    for item in latex_table(include_accelerations=True):
        if not item.source.startswith("000"):
            continue
        figure = item.source.removeprefix("000 ")
        key = f"{figure} |r0M|" if item.label.startswith("|") else f"{figure} {item.label[0]}0M"
        match = [v for k, v in notes.items() if k.startswith(key)]
        if figure == "Fig. 16":
            note = (f"the printed entry (2, 3) is an erratum: {errata['Fig. 16, T04 entry (2, 3)'].description} "
                    "The other entries are garbled in the text extraction and were not compared.")
        elif figure == "Fig. 23":
            note = "rows 2 and 3 are z and −y of Fig. 16's rows (checked in the tests); the extraction garbles signs."
        elif match:
            note = match[0]
        else:
            note = "not printed in the paper (derived: v_0M, a_0M by time differentiation, §7)"
            beyond.append(item.label)
        entries.append((item, note))
    out.expressions("symbolic", "Symbolic expressions, Figs. 15-17, 22-23 (LaTeX)",
                    "Paper 000 — symbolic expressions (Figs. 15-17, 22-23), rederived with sympy",
                    "Each expression is rederived from the paper's matrices of basic movements (kinematics.symbolic) "
                    "and compared with the printed Matlab output at 200 random (q, L).", entries, beyond)


# ----------------------------------------------------------------------------- the whole paper
def run(out_dir: Path, fast: bool = False, progress: Callable[[str], Any] = print) -> list[Row]:
    """Reproduce paper 000 into ``out_dir``; ``fast``: fewer samples and a 20 ms log period."""
    out = PaperOutput(PAPER, Path(out_dir), progress, TITLE)
    arm = get_arm("rr")
    out.scheme(arm, np.radians([-38.0, 98.0]), "scheme_rr", "the RR arm (cf. Fig. 1) at Fig. 3's start, "
               "θ = (−38°, 98°), drawn from armlab's model")
    motion = paper_motion(arm, tf=SEGMENT_TIME)
    log_period = 0.02 if fast else DEFAULT_LOG_PERIOD
    t = np.linspace(0.0, motion.duration, 101 if fast else 401)
    _fig3_kinematics(out, arm, motion, t)
    _fig4_workspace(out, arm, fast)
    _dynamics(out, arm, motion, log_period)
    _abcd(out, arm, fast, log_period)
    _rrrr(out)
    _symbolic(out)
    out.chosen_parameters(arm, ("m1", "m2", "r1", "r2"))
    out.chosen("t_f of Fig. 3's quintic", f"{SEGMENT_TIME:g} s",
               "not printed; the only t_f that gives §4's coefficients")
    out.chosen("time per segment A-B … D-A", f"{SEGMENT_TIME:g} s", "not printed; Fig. 3's t_f")
    out.chosen("gravity", "−9.81 m/s² along −y", "the Adams model moves in the vertical plane (§8); direction not "
               "given for Figs. 7, 10")
    out.chosen("tool (basket) of Figs. 26-29", f"{TOOL_MASS:g} kg point mass at M", "no tool mass is published")
    out.chosen("log period of the simulations", f"{log_period * 1e3:g} ms",
               "armlab simulate's default; peaks are the largest logged samples")
    out.chosen("Cartesian alternative", "armlab.arc: minimum-jerk (rest-to-rest quintic) timing of each quarter "
               "turn, IK branch 0 at A, one continuous motion", "the paper has none; the same 2 s per segment")
    return out.finish()


if __name__ == "__main__":
    from armlab.cli.reproduce import run_alone

    raise SystemExit(run_alone(PAPER, run))
