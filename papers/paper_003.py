"""Paper 003 (Schonstein & Panc, "Kinematical modelling for R2T serial structure", 2017) reproduced.

* eqs. (17), (20), (22)–(23), (43), (46), (48): the printed forms that are right, evaluated
  along a demo motion and compared with armlab's locating matrices and with Drake;
* the misprinted equations (eqs. 19/21, 44, 45, 47, 61, 63/68, 65/69; Table 1's k2): printed and
  corrected forms against Drake (:mod:`armlab.papers.errata`);
* the courses of the end effector's and every link's velocity and acceleration (iterative
  algorithm, eqs. 24–33) along a demo motion — the paper prints no motion or plot;
* the symbolic expressions of eqs. (17), (19)–(21), (43)–(49), (61)–(65) in LaTeX.

Run alone: ``python papers/paper_003.py --out out/003`` or ``python -m armlab.papers.paper_003``.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from armlab.bounds import tolerated
from armlab.kinematics.iterative import iterative_kinematics
from armlab.kinematics.locating import orientation_angles
from armlab.models import get_arm
from armlab.papers.errata import ERRATA, drake_sample, wrap_angle
from armlab.papers.paper_output import PaperOutput, errata_checked
from armlab.papers.report_rows import MATCHES, Row, differs
from armlab.planning.motions import paper_motion
from armlab.presentation.figures import new_figure

PAPER = "003"
TITLE = "Schonstein & Panc, Kinematical modelling for R2T serial structure (2017)"


# ----------------------------------------------------------------------------- the PAPER's printed forms
def paper_T03(q: np.ndarray, l: dict[str, float]) -> np.ndarray:
    """Eq. (17) as printed: ⁰₃[T], rows 1-3."""
    c, s = np.cos(q[:, 0]), np.sin(q[:, 0])
    z, o = np.zeros_like(c), np.ones_like(c)
    return np.stack([np.stack([c, -s, z, l["l3"] * c - q[:, 2] * s], -1),
                     np.stack([s, c, z, q[:, 2] * c + l["l3"] * s], -1),
                     np.stack([z, z, o, l["l1"] + l["l2"] + q[:, 1]], -1)], axis=-2)


def paper_R04(q: np.ndarray) -> np.ndarray:
    """Eq. (20) as printed: ⁰₄[R] = [[−s1, c1, 0], [c1, s1, 0], [0, 0, −1]]."""
    c, s = np.cos(q[:, 0]), np.sin(q[:, 0])
    z = np.zeros_like(c)
    return np.stack([np.stack([-s, c, z], -1), np.stack([c, s, z], -1), np.stack([z, z, -np.ones_like(c)], -1)], -2)


def paper_angles(q: np.ndarray) -> np.ndarray:
    """Eqs. (22)-(23) as printed: α_x = π, β_y = 0, γ_z = π/2 + q1."""
    return np.stack([np.full(q.shape[0], np.pi), np.zeros(q.shape[0]), np.pi / 2 + q[:, 0]], axis=-1)


def paper_v3(q: np.ndarray, qd: np.ndarray, l: dict[str, float]) -> np.ndarray:
    """Eq. (43) as printed: ⁰v3."""
    c, s = np.cos(q[:, 0]), np.sin(q[:, 0])
    return np.stack([-s * qd[:, 2] - l["l3"] * s * qd[:, 0] - q[:, 2] * c * qd[:, 0],
                     c * qd[:, 2] + l["l3"] * c * qd[:, 0] - q[:, 2] * s * qd[:, 0], qd[:, 1]], axis=-1)


def _wrap(x: np.ndarray) -> np.ndarray:
    return wrap_angle(x)


def _check(out: PaperOutput, quantity: str, printed: str, computed: str, gap: float, tol: float, note: str) -> None:
    """A row comparing a printed form with what armlab computes (``computed`` says what, at the samples)."""
    out.add(Row(PAPER, quantity, printed, computed, gap,
                MATCHES if tolerated(gap, tol) else differs(f"the printed form is off by up to {gap:.3g}"), note))


def _rows(out: PaperOutput, arm: Any, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> Any:
    l = dict(arm.parameters)
    out.group("Eqs. (17)-(23), (43)-(48): the printed forms checked against Drake",
              "Along the demo motion (the paper prints no motion); the misprinted equations are listed in the errata "
              "below and checked here against Drake at random configurations.")
    sample = drake_sample(arm, q, qd, qdd)
    frames = arm.table.frames(q)
    motion = iterative_kinematics(arm.table, q, qd, qdd)
    where = f"at {q.shape[0]} samples of the demo motion; tolerance 1e-9"
    _check(out, "eq. (17): ⁰₃[T], max |entry difference|", "printed ⁰₃[T]",
           "⁰₃[T] of the locating matrices and of Drake",
           float(max(np.abs(paper_T03(q, l) - frames[:, 3, :3]).max(),
                     np.abs(paper_T03(q, l) - sample.pose[:, 2, :3]).max())),
           1e-9, f"vs the locating matrices (eqs. 8-9) and Drake's link 3 pose {where}")
    R = sample.pose[:, -1, :3, :3]
    _check(out, "eq. (20): ⁰₄[R], max |entry difference|", "[[−s1, c1, 0], [c1, s1, 0], [0, 0, −1]]",
           "Drake's tool rotation and the locating matrices'",
           float(max(np.abs(paper_R04(q) - R).max(), np.abs(paper_R04(q) - frames[:, -1, :3, :3]).max())), 1e-9,
           f"vs Drake's tool rotation and the locating matrices {where}")
    angles = orientation_angles(R)
    for i, (name, form) in enumerate((("α_x", "π"), ("β_y", "0"), ("γ_z", "π/2 + q1"))):
        gap = float(np.abs(_wrap(angles[:, i] - paper_angles(q)[:, i])).max())
        span = f"{angles[:, i].min() + 0.0:.6g} … {angles[:, i].max() + 0.0:.6g} over the samples"
        _check(out, f"eqs. (22)-(23): {name} [rad]", form, span, gap, 1e-9,
               f"R = Rz(γ) Ry(β) Rx(α) of Drake's tool rotation (kinematics.locating.orientation_angles, by the "
               f"standard two-argument arctangent: eq. (22)'s case table is an erratum, below), modulo 2π, {where}")
    v3 = paper_v3(q, qd, l)
    gap = float(max(np.abs(v3 - sample.v[:, 2]).max(), np.abs(v3 - motion.v_0[:, 2]).max()))
    _check(out, "eq. (43): ⁰v3 [m/s]", "printed ⁰v3", "⁰v3 of Drake and of the iterative algorithm", gap, 1e-9,
           f"vs Drake and the iterative algorithm {where}")
    omega = np.stack([np.zeros(len(q)), np.zeros(len(q)), qd[:, 0]], -1)
    _check(out, "eq. (46): ⁰ω4 = (0, 0, q̇1) [rad/s]", "(0, 0, q̇1)", "Drake's ⁰ω4",
           float(np.abs(omega - sample.omega[:, -1]).max()), 1e-9, f"vs Drake {where}")
    omega_dot = np.stack([np.zeros(len(q)), np.zeros(len(q)), qdd[:, 0]], -1)
    _check(out, "eq. (48): ⁰ω̇4 = (0, 0, q̈1) [rad/s²]", "(0, 0, q̈1)", "Drake's ⁰ω̇4",
           float(np.abs(omega_dot - sample.omega_dot[:, -1]).max()), 1e-9, f"vs Drake {where}")
    samples = 20
    for e, printed, corrected in errata_checked(samples, PAPER):
        out.add(Row(PAPER, f"{e.equation} (misprint), max |printed − Drake|", "printed form", "corrected form",
                    printed, MATCHES if tolerated(printed, 1e-9) else differs("misprint (see the errata below)"),
                    f"the corrected form agrees with Drake to {corrected:.1e} at {samples} random configurations "
                    "within the joint limits; tolerance 1e-9"))
    return sample, motion


def _end_effector(out: PaperOutput, t: np.ndarray, v: np.ndarray, w: np.ndarray, vd: np.ndarray, wd: np.ndarray,
                  frame: str, title: str, stem: str, label: str, caption: str) -> None:
    """The tool's v, ω, v̇, ω̇ (each (N, 3), projected on ``frame``, "0" or "4") in a 2 × 2 figure."""
    prefix = "" if frame == "0" else "⁴"
    fig, axes = new_figure(title, 2, 2, size=(11, 6.5), sharex=True)
    panels = ((v, "v4 [m/s]"), (w, "ω4 [rad/s]"), (vd, "v̇4 [m/s²]"), (wd, "ω̇4 [rad/s²]"))
    for ax, (values, name) in zip(axes.ravel(), panels, strict=True):
        for i, axis in enumerate("xyz"):
            ax.plot(t, values[:, i], label=f"{axis}{frame}")
        ax.set_ylabel(prefix + name)
        ax.legend(loc="best")
    for ax in axes[1]:
        ax.set_xlabel("t [s]")
    out.figure(fig, stem, label, caption)


def _figures(out: PaperOutput, arm: Any, t: np.ndarray, motion: Any, drake_gap: float) -> None:
    out.group("Eqs. (24)-(33), (46)-(49), (62)-(69): the motion of the end effector and of every link",
              "The iterative algorithm along the demo motion (the paper prints no motion or plot).")
    _end_effector(out, t, motion.v_0[:, -1], motion.w_0[:, -1], motion.vd_0[:, -1], motion.wd_0[:, -1], "0",
                  "Paper 003 — end effector (tool P4) velocity and acceleration in {0}, eqs. (32)-(33), demo transfer",
                  "fig_end_effector", "End-effector courses (eqs. 32-33, 46-49)",
                  f"tool velocity and acceleration in {{0}}, iterative algorithm; Drake agrees to {drake_gap:.1e}")
    _end_effector(out, t, motion.v_i[:, -1], motion.w_i[:, -1], motion.vd_i[:, -1], motion.wd_i[:, -1], "4",
                  "Paper 003 — end effector in its own frame {4}, eqs. (62)-(69), demo transfer",
                  "fig_end_effector_own_frame", "End effector in {4} (eqs. 62-69)",
                  "tool velocity and acceleration projected on the tool frame")

    fig, axes = new_figure("Paper 003 — every link: speed and acceleration magnitudes (eqs. 24-27), demo transfer",
                           2, 2, size=(11, 6.5), sharex=True)
    names = ["link 1 (R, q1)", "link 2 (T, q2)", "link 3 (T, q3)", "tool P4"]
    panels = ((motion.v_0, "|v_i| [m/s]"), (motion.w_0, "|ω_i| [rad/s]"), (motion.vd_0, "|v̇_i| [m/s²]"),
              (motion.wd_0, "|ω̇_i| [rad/s²]"))
    for ax, (values, label) in zip(axes.ravel(), panels, strict=True):
        for i, name in enumerate(names):
            ax.plot(t, np.linalg.norm(values[:, i], axis=-1), label=name, ls="-" if i < 3 else "--")
        ax.set_ylabel(label)
        ax.legend(loc="best")
    for ax in axes[1]:
        ax.set_xlabel("t [s]")
    out.figure(fig, "fig_links", "Per-link courses (eqs. 24-31)",
               "speed and acceleration of the origin of every link frame and the tool")


def _symbolic(out: PaperOutput) -> None:
    from armlab.kinematics.symbolic import latex_table

    out.group("Eqs. (17), (19)-(21), (43)-(49), (61)-(65): the symbolic expressions")
    errata = [e for e in ERRATA if e.paper == PAPER]
    checked = {"17", "20", "43", "46", "48"}  # the printed forms _rows evaluates
    entries = []
    for item in latex_table(include_accelerations=False):
        if not item.source.startswith("003"):
            continue
        numbers = set(re.findall(r"\((\d+)\)", item.source))
        found = [e for e in errata if numbers & set(re.findall(r"\((\d+)\)", e.equation))]
        if found:
            note = "differs from the printed form (erratum): " + " ".join(e.description for e in found)
        elif numbers & checked:
            note = f"matches the paper's printed form (checked against Drake: the eq. ({min(numbers & checked)}) row)"
        else:
            note = "the paper's printed form is missing from the text extraction; not compared"
        entries.append((item, note))
    out.expressions("symbolic", "Symbolic expressions, eqs. 17, 19-21, 43-49, 61-65 (LaTeX)",
                    "Paper 003 — symbolic expressions (eqs. 17, 19-21, 43-49, 61-65), rederived with sympy",
                    "Rederived from the locating matrices (eqs. 13-18) and by time differentiation "
                    "(kinematics.symbolic); each note says whether the paper's printed form agrees.", entries)


def run(out_dir: Path, fast: bool = False, progress: Callable[[str], Any] = print) -> list[Row]:
    """Reproduce paper 003 into ``out_dir``; ``fast``: fewer samples."""
    out = PaperOutput(PAPER, Path(out_dir), progress, TITLE)
    arm = get_arm("r2t")
    demo = paper_motion(arm)
    t = np.linspace(0.0, demo.duration, 151 if fast else 601)
    q, qd, qdd = demo.evaluate(t)
    out.scheme(arm, q[len(t) // 2], "scheme_r2t", "the R2T arm (cf. Figs. 1-2) half-way through the demo motion, "
               "drawn from armlab's model")
    every = max(1, len(t) // 25)
    sample, _ = _rows(out, arm, q[::every], qd[::every], qdd[::every])

    motion = iterative_kinematics(arm.table, q, qd, qdd)
    gap = max(float(np.abs(getattr(motion, a)[::every, -1] - getattr(sample, b)[:, -1]).max())
              for a, b in (("v_0", "v"), ("w_0", "omega"), ("vd_0", "v_dot"), ("wd_0", "omega_dot")))
    _figures(out, arm, t, motion, gap)
    out.replay(arm, t, q, "demo", f"the demo motion ({demo.description})")
    _symbolic(out)
    out.chosen_parameters(arm, ("l1", "l2", "l3", "l4", "l5", "q2_max", "q3_max", "m1", "m2", "m3"))
    out.chosen("demo motion", demo.description, "paper 003 prints no motion")
    return out.finish()


if __name__ == "__main__":
    from armlab.cli.reproduce import run_alone

    raise SystemExit(run_alone(PAPER, run))
