"""Paper 004 (Ondočko et al., "Position forward kinematics of 6-DOF robotic arm") reproduced.

* Table 2: the position vectors p1 … p7 (mm) for Table 1's configuration, computed by the
  paper's rotation-matrix form (eqs. 1–7), cross-checked against its homogeneous form (eq. 22)
  and against Drake's plant built from the URDF — the paper's own check was "two independent
  models (Simulink and Simscape Multibody) agree".
* Fig. 4: the arm drawn in 3-D with its position vectors.

Run alone: ``python papers/paper_004.py --out out/004`` or ``python -m armlab.papers.paper_004``.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from armlab.bounds import tolerated
from armlab.kinematics.urm import position_vectors_homogeneous
from armlab.models import get_arm
from armlab.models.urm6 import TABLE1_PHI_DEG
from armlab.papers.errata import ERRATA, drake_sample
from armlab.papers.paper_output import PaperOutput
from armlab.papers.report_rows import MATCHES, Row, compare, differs
from armlab.planning.motions import paper_motion
from armlab.presentation.figures import draw_chain_3d, new_figure, set_equal_3d

PAPER = "004"
TITLE = "Ondočko et al., Position forward kinematics of 6-DOF robotic arm"

#: Paper 004, Table 2 (mm): p1 … p7 as printed by both of its models — the PAPER's values.
PAPER_TABLE2_MM = {
    "p1": (0.0, 0.0, 300.0),
    "p2": (62.5000, 16.7468, 541.4814),
    "p3": (173.6615, 98.2962, 686.3703),
    "p4": (208.0427, 238.3718, 727.5622),
    "p5": (197.5341, 266.4384, 822.9657),
    "p6": (171.5064, 309.0897, 821.1157),
    "p7": (178.0814, 312.0638, 797.1799),
}
#: The paper prints 4 decimals and truncates (not rounds) the last one: agreement within 2e-4 mm.
TABLE2_TOL_MM = 2e-4


def drake_points(arm: Any, q: np.ndarray, names: list[str]) -> np.ndarray:
    """Positions (m) of the named URDF frames at ``q``, by Drake's ``CalcRelativeTransform``."""
    plant = arm.make_plant()
    context = plant.CreateDefaultContext()
    plant.SetPositions(context, q)
    world = plant.world_frame()
    return np.array([plant.CalcRelativeTransform(context, world, plant.GetFrameByName(n)).translation()
                     for n in names])


def _figure(out: PaperOutput, points_mm: np.ndarray, names: list[str], phi_deg: np.ndarray) -> None:
    """The whole arm with its position vectors, and the wrist (p4 … p7, which lie within 0.1 m) enlarged."""
    fig, axes = new_figure("Paper 004, Fig. 4 — URM arm and its position vectors p1…p7 (Table 1 configuration); "
                           "right: the wrist p4…p7 enlarged", 1, 2, size=(12, 6.2), projection="3d")
    ax, wrist = axes[0]
    chain = np.vstack([np.zeros(3), points_mm])
    draw_chain_3d(ax, chain, label="segments r1…r7", names=["O", *names[:4]])
    for k, p in enumerate(points_mm):
        ax.quiver(0, 0, 0, *p, color=f"C{k % 7}", arrow_length_ratio=0.04, lw=0.9, alpha=0.75,
                  label=f"{names[k]} = ({p[0]:.1f}, {p[1]:.1f}, {p[2]:.1f}) mm")
    set_equal_3d(ax, chain)
    ax.legend(loc="upper left", bbox_to_anchor=(0.0, 1.0), fontsize=7, title="φ = " + ", ".join(
        f"{v:g}" for v in phi_deg) + "°", title_fontsize=7)
    draw_chain_3d(wrist, points_mm[3:], label="segments r5…r7", names=names[3:])
    set_equal_3d(wrist, points_mm[3:])
    wrist.legend(loc="upper left", fontsize=7)
    for a in (ax, wrist):
        a.set_xlabel("x0 [mm]")
        a.set_ylabel("y0 [mm]")
        a.set_zlabel("z0 [mm]")
        a.view_init(elev=22, azim=-60)
    out.figure(fig, "fig04_arm_3d", "Fig. 4", "the arm in 3-D with its position vectors p1…p7 (Table 1 configuration)")


def run(out_dir: Path, fast: bool = False, progress: Callable[[str], Any] = print) -> list[Row]:
    """Reproduce paper 004 into ``out_dir``; returns its report rows (``fast`` changes nothing here)."""
    out = PaperOutput(PAPER, Path(out_dir), progress, TITLE)
    arm = get_arm("urm6")
    phi = np.radians(TABLE1_PHI_DEG)
    out.scheme(arm, phi, "scheme_urm6", "the URM arm (cf. Figs. 1-3) at Table 1's configuration, drawn from armlab's "
               "model")
    out.group("Table 2 and Fig. 4: the position vectors p1…p7 at Table 1's configuration",
              "Computed by the paper's rotation-matrix form (eqs. 1-7), cross-checked against its homogeneous form "
              "(eq. 22, corrected) and Drake's plant from the URDF; the paper's own check was two independent models.")
    names = [f"p{k}" for k in range(1, 8)]
    fk = arm.forward(phi).points  # eqs. (1)-(7)
    rotation_form = np.array([fk[n] for n in names]) * 1e3
    p = arm.parameters
    r = np.array([p[f"r{k}"] for k in range(1, 8)])
    theta = np.array([p[f"theta{k}"] for k in range(2, 8)])
    homogeneous_form = position_vectors_homogeneous(phi, theta, r) * 1e3  # eq. (22)
    drake = drake_points(arm, phi, names) * 1e3
    forms_gap = float(np.abs(rotation_form - homogeneous_form).max())
    drake_gap = float(np.abs(rotation_form - drake).max())
    note = (f"eqs. (1)-(7); eq. (22) agrees to {forms_gap:.1e} mm, Drake's plant to {drake_gap:.1e} mm; "
            f"tolerance {TABLE2_TOL_MM:g} mm (the paper truncates its 4th decimal)")
    table = []
    for k, name in enumerate(names):
        for axis, paper_value, value in zip("xyz", PAPER_TABLE2_MM[name], rotation_form[k], strict=True):
            out.add(compare(PAPER, f"Table 2, {name} {axis} [mm]", paper_value, float(value), TABLE2_TOL_MM, note))
        table.append([name, *rotation_form[k], *PAPER_TABLE2_MM[name],
                      float(np.abs(rotation_form[k] - PAPER_TABLE2_MM[name]).max()), *map(float, drake[k])])
    out.table("table2_position_vectors", "Table 2 — position vectors p1…p7 [mm], armlab vs paper vs Drake",
              ["point", "x armlab", "y armlab", "z armlab", "x paper", "y paper", "z paper", "max |dev|",
               "x Drake", "y Drake", "z Drake"], table,
              note=f"armlab: the paper's eqs. (1)-(7); Drake: the URDF plant's frames p1…p7. {note}.")
    out.add(Row(PAPER, "Table 2: two independent models give the same p1…p7 (max |difference| [mm])",
                "the same (Simulink and Simscape Multibody)", drake_gap, drake_gap,
                MATCHES if tolerated(drake_gap, 1e-9)
                else differs(f"eqs. (1)-(7) and Drake differ by {drake_gap:.3g} mm"),
                "here: the paper's eqs. (1)-(7) vs Drake's plant from the URDF; tolerance 1e-9 mm"))
    _figure(out, rotation_form, names, np.asarray(TABLE1_PHI_DEG))
    demo = paper_motion(arm)
    t = np.linspace(0.0, demo.duration, 201)
    out.replay(arm, t, demo.evaluate(t)[0], "demo", f"the arm moving to Table 1's configuration ({demo.description})")

    out.group("Eqs. (7) and (22): the general formulas as printed, at Table 1's configuration")
    sample = drake_sample(arm, phi[None])
    for e in (e for e in ERRATA if e.paper == PAPER):
        if e.printed is None or e.corrected is None or e.reference is None:
            raise ValueError(f"{PAPER} {e.equation}: this erratum cannot be evaluated (printed form only)")
        off = np.linalg.norm(e.printed(sample)[0] - e.reference(sample)[0], axis=-1) * 1e3  # p2 … p7, mm
        corrected = float(np.abs(e.corrected(sample)[0] - e.reference(sample)[0]).max()) * 1e3
        out.add(Row(PAPER, f"{e.equation} (misprint): p2…p7 as printed at Table 1's configuration, "
                    "max |printed − Drake| [mm]", "printed form", "corrected form", float(off.max()),
                    MATCHES if tolerated(off.max(), 1e-6) else differs("misprint (see the errata below)"),
                    "|printed − Drake| per point: " + ", ".join(f"p{k + 2} {v:.4g} mm" for k, v in enumerate(off))
                    + f"; the corrected form agrees with Drake to {corrected:.1e} mm"))
    out.chosen_parameters(arm, ("module_mass",))
    return out.finish()


if __name__ == "__main__":
    from armlab.cli.reproduce import run_alone

    raise SystemExit(run_alone(PAPER, run))
