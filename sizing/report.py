"""What a sizing writes: ``sizing.csv`` (per joint and load case, the chosen drive's figures), ``sizing.md`` (the
choice, the runners-up, the nearest infeasible pairs with the checks they fail, the mass iteration) and one
torque–speed figure per joint (``torque_speed_JOINT.png``: the chosen motor's envelope, every load case's
operating points and its RMS point). :func:`summary_lines` is what ``armlab size`` prints.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from armlab.files import OutputFolder, csv_text
from armlab.sizing.select import STATS, Candidate, candidate_train, motor_side

if TYPE_CHECKING:
    from armlab.sizing.sizing import Sizing

__all__ = ["CSV_HEADERS", "figure_names", "sizing_folder", "sizing_markdown", "summary_lines", "torque_speed_figure",
           "write_sizing"]

RPM = 60 / (2 * np.pi)
#: The columns of sizing.csv (SI; speeds in rad/s).
CSV_HEADERS = ("joint", "load_case", "motor", "gearbox", "ratio", "drive_mass_kg", "margin", "peak_torque_Nm",
               "rms_torque_Nm", "peak_speed_rad_s", "mean_speed_rad_s", "peak_power_W", "energy_J", "regenerated_J",
               "inertia_ratio_min", "inertia_ratio_max")


def _tag(joint: str) -> str:
    return "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in joint)


def figure_names(sizing: Sizing) -> list[str]:
    """The torque–speed figures' file names, one per joint."""
    return [f"torque_speed_{_tag(j.joint)}.png" for j in sizing.joints]


def sizing_folder(out: str | Path) -> OutputFolder:
    """The output folder of a sizing (:class:`~armlab.files.OutputFolder`): an earlier one is replaced."""

    def is_previous(folder: Path) -> bool:
        names = {p.name for p in folder.iterdir()}
        return "sizing.csv" in names and all(n.startswith("torque_speed_") or n in ("sizing.csv", "sizing.md")
                                             for n in names)

    return OutputFolder(Path(out).expanduser(), is_previous, "an armlab sizing folder (sizing.csv, sizing.md and "
                                                            "torque–speed figures only)")


def _csv_rows(sizing: Sizing) -> list[list[object]]:
    rows: list[list[object]] = []
    for j in sizing.joints:
        c = j.chosen
        for k, case in enumerate(sizing.cases):
            if c is None:
                empty: list[object] = [j.joint, case.label, *[None] * (5 + len(STATS))]
                rows.append(empty)
                continue
            rows.append([j.joint, case.label, c.motor_name, c.gearbox_name, c.ratio, c.mass, c.margin,
                         *(float(c.stats[s][k]) for s in STATS)])
    return rows


def _pair(c: Candidate) -> str:
    return f"{c.motor_name} + {c.gearbox_name} (G = {c.ratio:g})"


def summary_lines(sizing: Sizing) -> list[str]:
    """The printed summary: one line per joint (its choice, or the nearest pairs and what each fails), the
    iteration and the total."""
    s = sizing
    lines = [f"{s.arm.name}: {s.cycle.description or 'duty cycle'} ({s.cycle.duration:g} s), load cases "
             f"{', '.join(c.label for c in s.cases)}, safety factor {s.safety_factor:g}, ranked by {s.rank}"]
    for j in s.joints:
        c = j.chosen
        if c is None:
            lines.append(f"{j.joint}: no feasible motor and gearbox among {j.pairs} pairs; nearest:")
            lines += [f"  {_pair(n)}: {'; '.join(n.failed)}" for n in j.nearest]
            continue
        k = int(np.argmax(c.stats["rms_torque"]))
        lines.append(f"{j.joint}: {_pair(c)}, {c.mass:.3g} kg, margin {c.margin:.1%}; worst case "
                     f"{s.cases[k].label}: RMS {c.stats['rms_torque'][k]:.3g} N·m, peak "
                     f"{c.stats['peak_torque'].max():.3g} N·m, {c.stats['peak_speed'].max() * RPM:.4g} rpm; "
                     f"{j.pairs} pairs, {j.screened} past the screen, "
                     f"{j.checked} checked in order of {s.rank}, {j.feasible_count} feasible")
    mass = "mass iteration: " + (f"converged after {s.iterations} selections" if s.converged
                                 else f"stopped after {s.iterations} selection(s), not converged")
    lines.append(mass + (f"; total drive mass {s.drive_mass:.4g} kg" if s.feasible else "; no feasible drive set"))
    return lines


def _table(rows: list[list[str]]) -> list[str]:
    return ["| " + " | ".join(rows[0]) + " |", "|" + "---|" * len(rows[0])] + ["| " + " | ".join(r) + " |"
                                                                             for r in rows[1:]]


def sizing_markdown(sizing: Sizing) -> str:
    """``sizing.md``: the summary, then per joint the chosen pair's figures per load case, the feasible
    runners-up and the nearest infeasible pairs with the checks they fail."""
    s = sizing
    out = ["# Drive sizing", "", *[f"{line}  " for line in summary_lines(s)], ""]
    out += ["Feasible: RMS, peak and every operating point inside the torque–speed envelope (torques × the safety "
            "factor), speeds within the motor's and the gearbox's, the gearbox's output torques within its ratings; "
            "every load case. Motor side; the payload is carried where the cycle says.", ""]
    for j in s.joints:
        out += [f"## {j.joint}", "",
                f"{j.pairs} pairs; the screen (accelerating factor α = T²/J against the load factor β = "
                f"{', '.join(f'{b:.4g}' for b in j.beta)} N²·m²/(kg·m²) per load case) kept {j.motors_screened} "
                f"motors and {j.screened} pairs for the full check; {j.checked} were checked, in order of {s.rank} "
                f"until no pair left could rank among the best, {j.feasible_count} of them feasible.", ""]
        c = j.chosen
        if c is not None:
            out += [f"Chosen: **{_pair(c)}**, {c.mass:.4g} kg, margin {c.margin:.2%}.", ""]
            out += _table([["load case", "peak N·m", "RMS N·m", "peak rpm", "mean rpm", "peak W", "energy J",
                            "regen J", "J ratio min", "J ratio max"]]
                          + [[case.label, *(f"{c.stats[st][k] * (RPM if 'speed' in st else 1):.4g}" for st in STATS)]
                             for k, case in enumerate(s.cases)])
            out.append("")
            if len(j.feasible) > 1:
                out += ["Runners-up:", ""]
                out += _table([["motor + gearbox", "mass kg", "margin"]]
                              + [[_pair(f), f"{f.mass:.4g}", f"{f.margin:.2%}"] for f in j.feasible[1:]])
                out.append("")
        if j.nearest:
            out += ["Nearest infeasible:", ""]
            out += _table([["motor + gearbox", "mass kg", "fails"]]
                          + [[_pair(f), f"{f.mass:.4g}", "; ".join(f.failed)] for f in j.nearest])
            out.append("")
    return "\n".join(out)


def torque_speed_figure(sizing: Sizing, k: int) -> Any:
    """Joint k's torque–speed figure (a matplotlib figure; motor side): the chosen motor's envelope, its
    continuous region, each load case's operating points and RMS point. ``ValueError`` for a joint without one."""
    # lazy: matplotlib only when figures are drawn
    from armlab.presentation.figures import new_figure

    s, j = sizing, sizing.joints[k]
    c = j.chosen
    if c is None:
        raise ValueError(f"{j.joint} has no feasible motor and gearbox: no torque–speed figure")
    train = candidate_train(s.motors, s.gearboxes, np.array([c.motor]), np.array([c.gearbox]))  # as the selection
    qd, qdd = s.samples.qd[:, k:k + 1], s.samples.qdd[:, k:k + 1]
    fig, ax = new_figure(f"{s.arm.name} {j.joint}: {_pair(c)} — motor torque against speed, safety factor "
                         f"{s.safety_factor:g}", size=(9.0, 4.8))
    m = s.motors
    top = m.max_speed[c.motor] * RPM
    speeds = np.linspace(0, m.max_speed[c.motor], 200)
    envelope = m.envelope(np.full(speeds.size, c.motor), speeds)
    for sign in (1, -1):
        ax.plot(sign * speeds * RPM, sign * envelope, color="k", lw=1.6,
                label="peak envelope" if sign == 1 else None)
        ax.plot(sign * speeds * RPM, -sign * envelope, color="k", lw=1.6)
    rated, rated_speed = m.rated_torque[c.motor], m.rated_speed[c.motor] * RPM
    ax.fill([-rated_speed, rated_speed, rated_speed, -rated_speed], [-rated, -rated, rated, rated], color="#2e8b57",
            alpha=0.12, label="continuous (rated torque, rated speed)")
    ax.axvline(top, color="k", ls=":", lw=1, label="maximum speed")
    ax.axvline(-top, color="k", ls=":", lw=1)
    for case_index, case in enumerate(s.cases):
        tau_m, omega = motor_side(train, s.loads.tau[case_index, :, k:k + 1], qd, qdd)
        tau_m, omega = tau_m[:, 0], omega[:, 0] * RPM
        (points,) = ax.plot(omega, tau_m, ".", ms=2.5, alpha=0.6, label=f"{case.label}: operating points")
        ax.plot([c.stats["mean_speed"][case_index] * RPM], [c.stats["rms_torque"][case_index]], marker="*", ms=13,
                color=points.get_color(), mec="k", ls="none", label=f"{case.label}: RMS point (mean |ω|, RMS τ)")
    ax.set_xlabel("motor speed ω_m (rpm)")
    ax.set_ylabel("motor torque τ_m (N·m)")
    peak = m.peak_torque[c.motor]
    ax.set_xlim(-1.08 * top, 1.08 * top)
    ax.set_ylim(-1.15 * peak, 1.15 * peak)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7)  # beside the axes: it covers no data
    return fig


def write_sizing(sizing: Sizing, folder: Path) -> list[str]:
    """``sizing.csv``, ``sizing.md`` and (for a feasible sizing) the torque–speed figures into ``folder``; the
    names written."""
    (folder / "sizing.csv").write_text(csv_text(CSV_HEADERS, _csv_rows(sizing)))
    (folder / "sizing.md").write_text(sizing_markdown(sizing) + "\n")
    written = ["sizing.csv", "sizing.md"]
    if sizing.feasible:
        # lazy: matplotlib only when figures are written
        from armlab.presentation.figures import save_png

        written += [save_png(torque_speed_figure(sizing, k), folder / name)
                    for k, name in enumerate(figure_names(sizing))]
    return written
