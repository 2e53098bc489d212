"""Paper 001 (Qin et al., "Four degree of freedom manipulator's kinematics simulation analysis
based on MATLAB") reproduced.

* eq. (6): T04 at θ = 0, by the paper's modified-DH chain and by Drake;
* §3: the start (2, 0, 0) and the target (1, 1, 1.4), every inverse-kinematics solution of
  eqs. (9)–(21) (corrected, see the errata) within Table 1's limits;
* Figs. 4–7: joint angles, velocities, accelerations and the end point's x, y, z over the 2 s
  motion, and the arm drawn in 3-D (Fig. 3, the Robotics Toolbox's view);
* beyond the paper: the motion simulated through paper 000's Fig. 6 diagram (joint torques for
  the chosen masses) and replayed in 3-D, as the Robotics Toolbox animates it.

Run alone: ``python papers/paper_001.py --out out/001`` or ``python -m armlab.papers.paper_001``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from armlab.bounds import above, below, tolerated, within
from armlab.diagrams.build import DEFAULT_LOG_PERIOD
from armlab.diagrams.simulate import SimulationOptions, simulate
from armlab.kinematics.ik import solve
from armlab.kinematics.ik_closed_form import arm4r_ik
from armlab.models import get_arm
from armlab.models.arm4r import Parameters, dh_table
from armlab.papers.errata import drake_sample, wrap_angle
from armlab.papers.paper_output import PaperOutput
from armlab.papers.report_rows import Row, differs, matches, not_reproducible
from armlab.planning.motions import paper_motion
from armlab.presentation.figures import draw_chain_3d, new_figure, set_equal_3d

PAPER = "001"
TITLE = "Qin et al., Four degree of freedom manipulator's kinematics simulation analysis based on MATLAB"

#: §3: start and target of the tool (m) — the paper's values.
PAPER_START = (2.0, 0.0, 0.0)
PAPER_TARGET = (1.0, 1.0, 1.4)


#: d2 ≠ 0 at which eq. (6) tells the modified-DH reading of Table 1 from the standard one (m).
D2_PROBE = 0.25


def paper_T04_at_zero(a2: float, a3: float, d2: float) -> np.ndarray:
    """The paper's eq. (6), rows 1-3: T04 at θ = 0 as printed, in the arm's a2, a3, d2."""
    return np.array([[1.0, 0, 0, a2 + a3], [0, 0, 1, d2], [0, -1, 0, 0]])


def fig4_splits(target: tuple[float, float, float] = PAPER_TARGET, reach: float = 2.0,
                samples: int = 20001) -> np.ndarray:
    """The link lengths with which Fig. 4's claim holds exactly: rows (a2, θ) with a2 + a3 = ``reach``
    (the stretched start), d2 = 0, such that θ = (θ1, θ, θ, θ1), θ1 = atan2(y, x), puts the tool at ``target``.

    Eq. (5) with d2 = 0 and θ2 = θ3 = θ: c1 (a2 cθ + a3 c2θ) = ρ c1 and −(a2 sθ + a3 s2θ) = p_z, ρ = |(p_x, p_y)|.
    The first is linear in a2, a2(θ) = (ρ − reach·c2θ)/(cθ − c2θ); the roots in θ of the second,
    g(θ) = a2(θ) sθ + (reach − a2(θ)) s2θ + p_z, are bracketed on a grid of ``samples`` angles and refined
    by bisection to round-off. Only roots with 0 < a2 < reach are returned, sorted by a2.
    """
    rho, pz = float(np.hypot(target[0], target[1])), float(target[2])

    def a2_of(theta: np.ndarray) -> np.ndarray:  # ±inf where cθ = c2θ (θ = 0, ±2π/3): no root there
        with np.errstate(divide="ignore", invalid="ignore"):
            return (rho - reach * np.cos(2 * theta)) / (np.cos(theta) - np.cos(2 * theta))

    def g(theta: np.ndarray) -> np.ndarray:
        a2 = a2_of(theta)
        with np.errstate(invalid="ignore"):
            return a2 * np.sin(theta) + (reach - a2) * np.sin(2 * theta) + pz

    grid = np.linspace(-np.pi, np.pi, samples)
    a2, values = a2_of(grid), g(grid)
    inside = ~np.isnan(a2) & above(a2, 0.0) & below(a2, reach)  # positive lengths beyond round-off (NaN: both)
    k = np.nonzero(inside[:-1] & inside[1:] & (np.sign(values[:-1]) * np.sign(values[1:]) < 0))[0]
    lo, hi = grid[k], grid[k + 1]
    for _ in range(60):  # bisection, all brackets at once
        mid = (lo + hi) / 2
        left = np.sign(g(lo)) * np.sign(g(mid)) <= 0  # not a bound: the sign change bisection follows
        lo, hi = np.where(left, lo, mid), np.where(left, mid, hi)
    theta = (lo + hi) / 2
    roots = np.stack([a2_of(theta), theta], axis=-1)
    return roots[np.argsort(roots[:, 0])]


def _rows(out: PaperOutput, arm: Any, motion: Any) -> tuple[np.ndarray, list[np.ndarray]]:
    p = arm.parameters
    zero = np.zeros(arm.n)
    T = arm.forward(zero).tool[:3]
    drake_T = drake_sample(arm, zero[None]).pose[0, -1, :3]
    gap = float(np.abs(T - paper_T04_at_zero(p["a2"], p["a3"], p["d2"])).max())
    probe = Parameters(a2=p["a2"], a3=p["a3"], d2=D2_PROBE)
    printed = paper_T04_at_zero(probe.a2, probe.a3, probe.d2)
    modified, standard = (float(np.abs(table.end_pose(zero)[:3] - printed).max())
                          for table in (dh_table(probe), replace(dh_table(probe), convention="standard")))
    out.group("Eq. (6) and §3: the start and the target",
              "001 prints no link lengths: armlab chose a2 = a3 = 1 m and d2 = 0 from §3's stretched start (2, 0, 0).")
    out.add(Row(PAPER, "eq. (6): T04 at θ = 0, max |entry difference|", "[[1,0,0,a2+a3],[0,0,1,d2],[0,-1,0,0]]",
                gap, gap,
                (matches(f"holds for the chosen lengths: with d2 = {p['d2']:g} Table 1 read as standard DH gives the "
                         "same T04") if tolerated(gap, 1e-12) else differs(f"entries differ by {gap:.3g}")),
                f"modified DH of Table 1 (kinematics.dh); Drake's plant agrees to {np.abs(T - drake_T).max():.1e}; "
                f"a2 = {p['a2']:g}, a3 = {p['a3']:g}, d2 = {p['d2']:g} m; with d2 = {D2_PROBE:g} m the modified "
                f"reading still gives eq. (6) (to {modified:.1e}), the standard one is off by {standard:.3g}; "
                "tolerance 1e-12"))
    start = arm.forward(motion.segments[0].q_start).tool[:3, 3]
    miss = float(np.linalg.norm(start - PAPER_START))
    out.add(Row(PAPER, "§3: start (2, 0, 0) m reached stretched horizontally (θ = 0), |miss| [m]",
                "(2, 0, 0)", f"({start[0]:.6g}, {start[1]:.6g}, {start[2]:.6g})", miss,
                (matches("by construction: a2 + a3 = 2 and d2 = 0 were chosen from this sentence")
                 if tolerated(miss, 1e-9)
                 else differs(f"θ = 0 puts the tool {miss:.3g} m away")),
                "forward kinematics at the start's IK solution; tolerance 1e-9 m"))
    q0 = motion.segments[0].q_start
    pitch = float(q0[1] + q0[2] + q0[3])
    solutions = solve(arm, PAPER_TARGET, pitch=pitch, near=q0, all_solutions=True)
    hits = np.array([arm.forward(q).tool[:3, 3] for q in solutions])
    miss = float(np.abs(hits - PAPER_TARGET).max())
    raw = arm4r_ik(PAPER_TARGET, pitch, p["a2"], p["a3"], p["d2"])
    out.add(Row(PAPER, "§3: target (1, 1, 1.4) m reachable; max |FK(IK) − target| over the solutions [m]",
                "reachable", f"{len(solutions)} of {raw.shape[0]} IK solutions within Table 1's limits", miss,
                (matches("holds for the chosen lengths a2 = a3 = 1 m") if solutions and tolerated(miss, 1e-9)
                 else differs("no solution within the limits reaches it")),
                "eqs. (9)-(21) as corrected (kinematics.ik_closed_form.arm4r_ik) with the start's pitch; "
                "tolerance 1e-9 m"))
    return raw, solutions


def _fig4_claim(out: PaperOutput, arm: Any, q: np.ndarray) -> None:
    """Fig. 4's claim (joints 1 and 4 coincide, 2 and 3 coincide) with armlab's lengths, and the lengths with which
    it holds (:func:`fig4_splits`), each checked by forward kinematics and against Table 1's limits."""
    gap14 = float(np.degrees(np.abs(q[:, 0] - q[:, 3]).max()))
    gap23 = float(np.degrees(np.abs(q[:, 1] - q[:, 2]).max()))
    reach = arm.parameters["a2"] + arm.parameters["a3"]
    theta1 = float(np.arctan2(PAPER_TARGET[1], PAPER_TARGET[0]))
    lo, hi = arm.limit_arrays()
    holds: list[str] = []
    outside: list[str] = []
    lengths: list[str] = []
    for a2, theta in fig4_splits(PAPER_TARGET, reach):
        split = get_arm("arm4r", a2=float(a2), a3=float(reach - a2), d2=0.0)
        joints = wrap_angle(np.array([theta1, theta, theta, theta1]))
        miss = float(np.abs(split.forward(joints).tool[:3, 3] - PAPER_TARGET).max())
        text = (f"a2 = {a2:.4f} m, a3 = {reach - a2:.4f} m with θ2 = θ3 = {np.degrees(theta):.2f}°, θ1 = θ4 = "
                f"{np.degrees(theta1):g}° (FK reaches the target to {miss:.0e} m)")
        inside = bool(np.all(within(joints, lo, hi)))
        (holds if inside else outside).append(text)
        lengths += [f"a2 = {a2:.4f} m"] if inside else []
    note = (f"armlab's motion (a2 = a3 = {reach / 2:g} m, the start's pitch kept) gives max |θ1 − θ4| = {gap14:.4g}°, "
            f"|θ2 − θ3| = {gap23:.4g}°. With a2 + a3 = {reach:g} m the claim holds exactly for "
            + " or ".join(holds) + (f"; outside Table 1's limits also for {'; '.join(outside)}" if outside else ""))
    out.add(Row(PAPER, "Fig. 4 claim: joints 1 and 4 coincide, joints 2 and 3 coincide; max |θ1 − θ4|, |θ2 − θ3| [deg]",
                "coincide", f"{gap14:.4g}, {gap23:.4g}", max(gap14, gap23),
                not_reproducible("the paper prints neither the link lengths nor the target orientation (its stop "
                                 "values are garbled); the claim depends on both: it holds exactly for "
                                 + " or ".join(lengths) + f" (a2 + a3 = {reach:g} m, θ2 = θ3, θ1 = θ4 = "
                                 f"{np.degrees(theta1):g}°), not for the chosen a2 = a3 = {reach / 2:g} m"),
                note))


def _figures(out: PaperOutput, arm: Any, motion: Any, t: np.ndarray) -> None:
    q, qd, qdd = motion.evaluate(t)
    fk = arm.forward(q)
    end = fk.tool[:, :3, 3]
    for number, values, what, unit, scale in ((4, q, "displacement", "deg", 180 / np.pi),
                                              (5, qd, "velocity", "deg/s", 180 / np.pi),
                                              (6, qdd, "acceleration", "deg/s²", 180 / np.pi)):
        fig, ax = new_figure(f"Paper 001, Fig. {number} — {what} of joints 1-4 (quintic, 2 s)", size=(7, 4.2))
        for j in range(arm.n):
            ax.plot(t, values[:, j] * scale, label=f"joint {j + 1}")
        ax.set_xlabel("t [s]")
        ax.set_ylabel(f"{what} [{unit}]")
        ax.legend(loc="best")
        out.figure(fig, f"fig{number:02d}_joint_{what}", f"Fig. {number}", f"joint {what} over the motion")
    fig, ax = new_figure("Paper 001, Fig. 7 — end point of the manipulator: x, y, z over time", size=(7, 4.2))
    for i, axis in enumerate("xyz"):
        ax.plot(t, end[:, i], label=f"{axis}")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("end-point position [m]")
    ax.legend(loc="best")
    out.figure(fig, "fig07_end_point", "Fig. 7", "x, y, z of the end point from (2, 0, 0) to (1, 1, 1.4)")

    fig, ax = new_figure("Paper 001, Fig. 3 — the 4R arm in 3-D along the motion (start, 1/3, 2/3, target)",
                         size=(7, 6.5), projection="3d")
    chains = []
    for k, alpha in zip(np.linspace(0, len(t) - 1, 4).astype(int), (1.0, 0.4, 0.4, 1.0), strict=True):
        chain = np.vstack([np.zeros(3), fk.points["O3"][k], fk.points["O4"][k]])
        chains.append(chain)
        draw_chain_3d(ax, chain, label=f"t = {t[k]:.2f} s", color=f"C{len(chains) - 1}", alpha=alpha)
    ax.plot(end[:, 0], end[:, 1], end[:, 2], "k:", lw=1, label="end-point path")
    ax.set_xlabel("x0 [m]")
    ax.set_ylabel("y0 [m]")
    ax.set_zlabel("z0 [m]")
    set_equal_3d(ax, np.vstack(chains + [end]))
    ax.view_init(elev=20, azim=-50)
    ax.legend(loc="upper left")
    out.figure(fig, "fig03_arm_3d", "Fig. 3", "the arm in 3-D at the start, along the motion and at the target")


def _dynamics(out: PaperOutput, arm: Any, motion: Any, log_period: float) -> None:
    """Beyond the paper (kinematic only): §3's motion through Drake's Fig. 6 diagram, its torques and replay."""
    log = simulate(arm, motion, SimulationOptions(log_period=log_period))
    out.simulated_run(log, "motion", "§3's motion (2, 0, 0) → (1, 1, 1.4) m, as the Robotics Toolbox animates it")
    fig, ax = new_figure("Beyond paper 001 — joint torques of §3's motion (gravity −z, armlab's chosen masses)",
                         size=(7, 4.2))
    for j in range(arm.n):
        ax.plot(log.t, log.tau[:, j], label=f"τ{j + 1}")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("joint torque [N·m]")
    ax.legend(loc="best")
    error = np.abs(log.q - log.q_ref).max()
    out.figure(fig, "torques", "Joint torques (not in the paper)",
               f"simulated through paper 000's Fig. 6 diagram; tracking error {error:.1e} rad; chosen masses")


def run(out_dir: Path, fast: bool = False, progress: Callable[[str], Any] = print) -> list[Row]:
    """Reproduce paper 001 into ``out_dir``; ``fast``: fewer samples."""
    out = PaperOutput(PAPER, Path(out_dir), progress, TITLE)
    arm = get_arm("arm4r")
    motion = paper_motion(arm)  # §3: (2, 0, 0) → (1, 1, 1.4), the start's pitch, nearest solution, 2 s
    out.scheme(arm, motion.segments[0].q_end, "scheme_arm4r", "the 4R arm (cf. Figs. 1-2) at the target's IK solution, "
               "drawn from armlab's model")
    raw, solutions = _rows(out, arm, motion)
    within = [any(np.allclose(np.cos(r - s), 1.0) for s in solutions) for r in raw]
    out.table("ik_solutions", "§3 — inverse-kinematics solutions for the target (1, 1, 1.4) m (deg)",
              ["solution", "θ1", "θ2", "θ3", "θ4", "within Table 1's limits", "chosen (nearest the start)"],
              [[k + 1, *np.degrees(r).tolist(), "yes" if w else "no",
                "yes" if np.allclose(np.cos(r - motion.segments[0].q_end), 1.0) else ""]
               for k, (r, w) in enumerate(zip(raw, within, strict=True))],
              note="Eqs. (11), (13), (18), (19) corrected, θ4 from the pitch θ2+θ3+θ4 kept at the start's "
                   "(the paper: 'the state is the same with the original state'). Angles as solved, before wrapping "
                   "into the limits.")
    t = np.linspace(0.0, motion.duration, 101 if fast else 401)
    q = motion.evaluate(t)[0]
    out.group("Figs. 3-7: the motion from the start to the target")
    _fig4_claim(out, arm, q)
    _figures(out, arm, motion, t)
    out.group("Beyond the paper: the motion's joint torques and its 3-D replay")
    _dynamics(out, arm, motion, 0.02 if fast else DEFAULT_LOG_PERIOD)
    out.chosen_parameters(arm, ("a2", "a3", "d2", "m1", "m2", "m3", "m4"))
    out.chosen("motion", "rest-to-rest quintic per joint in 2 s", "the Robotics Toolbox's jtraj is a quintic; §3's 2 s")
    pitch = np.degrees(sum(motion.segments[0].q_start[1:]))
    out.chosen("target orientation", f"pitch θ2+θ3+θ4 = {pitch:g}° (the start's)",
               "the stop values are garbled; 'the state is the same with the original state'")
    return out.finish()


if __name__ == "__main__":
    from armlab.cli.reproduce import run_alone

    raise SystemExit(run_alone(PAPER, run))
