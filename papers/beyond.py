"""Beyond the papers: two design studies that answer what the papers leave open, in ``armlab reproduce``.

* **004** ends on "a search for an optimum angle ϑi and its impact on the size of the workspace":
  the URM arm's workspace volume as each bend angle ϑ2 … ϑ7 runs over 0 … 90° (the others at
  Table 1's values), the best angle of each, and the volume with all the best angles together, counted over
  every sampled pose and, beside it, over the poses in which the arm does not pass through itself.
* **000** sizes drives by simulation: the RR arm's peak joint torques along Fig. 3's motion against
  the motion time t_f and the payload — the drive-sizing map; and then what its §5 asks for, the drives
  themselves: a motor and gearbox per joint from armlab's example catalogue that carry every payload of
  the range along Fig. 3's motion, "oversized" by a safety factor (:func:`rr_drives_chosen`); and with those
  drives, the servo loop an engineer would build instead of Fig. 6's ideal controller: a 1 kHz discrete PID on a
  4096-count motor encoder (:func:`rr_servo`).

Each is a study of :mod:`armlab.analysis.study` evaluated in this process (the reproduction is small;
``armlab sweep`` runs the same studies on a Dask cluster: ``analysis/studies/*.json``). The
reproduction's sample counts are modest (:data:`SAMPLES`); the report says which. :func:`run` adds
each study as a "Beyond the paper" group to its paper's output folder (figures, a table, and the
manifest the report reads).
"""

from __future__ import annotations

import functools
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armlab.analysis.study import evaluate, parse_study
from armlab.models.urm6 import Parameters
from armlab.papers.paper_output import MANIFEST, PaperOutput
from armlab.presentation.figures import new_figure

__all__ = ["OVERSIZE", "SAMPLES", "SERVO", "STUDIES", "rr_drive_map", "rr_drives_chosen", "rr_servo", "run",
           "urm6_bend_angles"]

#: Paper 000 §5: "It is necessary to oversize the drives" — by how much it does not say; armlab's choice, the
#: safety factor on every torque of the drives chosen for the RR arm.
OVERSIZE = 1.5
#: The RR arm's payload range for the drives (kg): the drive-sizing map's.
RR_PAYLOADS = {False: (0.0, 1.0, 2.0, 3.0, 5.0), True: (0.0, 2.0, 5.0)}

#: The servo loop set against Fig. 6's ideal controller (:func:`rr_servo`): armlab.simulate's servo options.
SERVO: dict[str, Any] = {"controller": "pid", "bandwidth": 5.0, "rate": 1000.0, "encoder": 4096, "saturate": True}

#: Workspace samples per candidate of the bend-angle study (normal, fast) and its angle steps.
SAMPLES = {False: 100_000, True: 30_000}
ANGLE_STEPS = {False: 7, True: 4}


def _study(data: dict[str, Any]) -> Any:
    return parse_study(data)


def urm6_bend_angles(out: PaperOutput, fast: bool) -> None:
    """Paper 004's open question: workspace volume against each bend angle ϑ2 … ϑ7 (one at a time), counted over all
    sampled poses and over the self-collision-free poses only (the URM modules are designed not to collide)."""
    samples, steps = SAMPLES[fast], ANGLE_STEPS[fast]
    nominal = Parameters()
    names = [f"theta{k}" for k in range(2, 8)]
    evaluated = ["workspace_volume", "collision_free_volume", "min_clearance"]

    def volumes(angles_deg: dict[str, float]) -> NDArray[np.float64]:
        """The raw and the collision-free workspace volume (m³) and the smallest self-clearance over the samples (m)
        with the bend angles ``angles_deg`` (deg)."""
        study = _study({"arm": "urm6", "vary": {n: {"values": [v], "unit": "deg"} for n, v in angles_deg.items()},
                        "evaluate": evaluated, "samples": samples})
        found = evaluate(study, study.candidates[0])
        return np.array([found[e] for e in evaluated])

    curves: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}
    best: dict[str, dict[str, float]] = {e: {} for e in evaluated[:2]}
    nominal_volumes = volumes({names[0]: float(np.degrees(getattr(nominal, names[0])))})  # all at Table 1's
    for name in names:
        study = _study({"arm": "urm6", "vary": {name: {"from": 0, "to": 90, "steps": steps, "unit": "deg"}},
                        "evaluate": evaluated, "samples": samples})
        angles = np.array([values[0] for values in study.candidates])
        found = [evaluate(study, values) for values in study.candidates]
        curves[name] = (angles, np.array([[f[e] for e in evaluated] for f in found]))  # (steps, 3)
        for j, e in enumerate(evaluated[:2]):
            best[e][name] = float(angles[int(np.argmax(curves[name][1][:, j]))])
    combined: dict[str, NDArray[np.float64]] = {}  # both volumes at each answer's best angles (evaluated once
    for e in evaluated[:2]:                         # when both answers agree, as they are expected to)
        agreeing = next((combined[d] for d in combined if best[d] == best[e]), None)  # exact: grid angles
        combined[e] = volumes(best[e]) if agreeing is None else agreeing
    table = []
    for name in names:
        angles, v = curves[name]
        raw_k, free_k = (int(np.argmax(v[:, j])) for j in range(2))
        table.append([f"ϑ{name[5:]}", float(np.degrees(getattr(nominal, name))), float(angles[raw_k]),
                      float(v[raw_k, 0]), float(angles[free_k]), float(v[free_k, 1]), float(v[raw_k, 1]),
                      float(v[:, 2].min() * 1e3)])
    for e, label in zip(evaluated[:2], ("all six at their raw best", "all six at their collision-free best"),
                        strict=True):
        table.append([label, "", "[" + ", ".join(f"{best[e][n]:g}" for n in names) + "]", float(combined[e][0]), "",
                      float(combined[e][1]), "", float(combined[e][2] * 1e3)])
    nearest = min(min(float(v[:, 2].min()) for _, v in curves.values()), *(float(c[2]) for c in combined.values()))
    same = all(best["workspace_volume"][n] == best["collision_free_volume"][n] for n in names)  # exact: grid angles
    finding = (f"No sampled pose of any candidate passes through itself (the smallest clearance between "
               f"non-adjacent modules is {nearest * 1e3:.3g} mm): with Table 1's segment lengths, which shrink "
               "outwards, bends of at most 90° cannot fold an outer module back onto an inner one, so the "
               "collision-free volumes equal the raw ones and the best angles stay as they were."
               if nearest > 0 else
               "Some sampled poses pass through the arm itself (smallest clearance "
               f"{nearest * 1e3:.3g} mm, a penetration); the collision-free volumes leave their tool points out"
               + (", and the best angles stay as they were." if same else
                  ", and that moves the best angles where marked."))

    fig, ax = new_figure("Beyond paper 004 — workspace volume of the URM arm against each bend angle ϑi "
                         "(the others at Table 1's values): all poses (solid) and self-collision-free poses (dashed)",
                         size=(7.5, 5.0))
    for i, name in enumerate(names):
        angles, v = curves[name]
        ax.plot(angles, v[:, 0], "o-", ms=3, color=f"C{i}", label=f"ϑ{name[5:]} (Table 1: "
                f"{np.degrees(getattr(nominal, name)):g}°)")
        ax.plot(angles, v[:, 1], "s--", ms=3, color=f"C{i}", lw=1.0)
        ax.plot([best["collision_free_volume"][name]], [v[:, 1].max()], "*", ms=11, color=f"C{i}")
    ax.axhline(nominal_volumes[0], color="k", lw=0.8, ls="--",
               label=f"Table 1's angles: {nominal_volumes[0]:.3f} m³ (collision-free {nominal_volumes[1]:.3f} m³)")
    ax.set_xlabel("bend angle ϑi [deg]")
    ax.set_ylabel("workspace volume [m³]")
    ax.legend(fontsize=7, ncol=2)
    out.figure(fig, "beyond_bend_angles", "Workspace volume against the bend angles (not in the paper)",
               f"each ϑi over 0…90° in {steps} steps, the others at Table 1's values; solid: every sampled pose, "
               "dashed: the poses in which no two non-adjacent modules touch (armlab.collision: a capsule per "
               f"module); ★ the collision-free best of each; {samples} joint-space samples per candidate, voxel "
               "volume extrapolated to h → 0 (armlab.analysis.workspace)")
    out.table("beyond_bend_angles", "Best bend angles for the workspace volume (not in the paper)",
              ["angle", "Table 1 [deg]", "best, all poses [deg]", "volume there [m³]", "best, collision-free [deg]",
               "collision-free volume there [m³]", "collision-free volume at the all-poses best [m³]",
               "smallest self-clearance [mm]"], table,
              note=f"Over all poses and over the self-collision-free poses only. Table 1's angles give "
                   f"{nominal_volumes[0]:.4g} m³, {nominal_volumes[1]:.4g} m³ of it reached "
                   "without the arm passing through itself. One angle varied at a time over a "
                   f"{steps}-step grid, then all six best angles together. {finding} "
                   f"{samples} joint-space samples per candidate, a modest "
                   "count that keeps the reproduction short: at this count the estimates still grow by a few per "
                   "cent per doubling of the samples (see `armlab workspace urm6 --samples 10000000`), so angles "
                   "whose volumes differ by less than that may swap places. `armlab sweep "
                   "analysis/studies/urm6_bend_angles.json` runs a larger study on a Dask cluster.")


def _label_places(lines: Any, x: Any, y: Any) -> list[tuple[float, float]]:
    """Where a contour plot's labels go: on each level's longest line, the point half-way along it of those at
    least a tenth of the panel from its border (matplotlib's own choice puts some at the border, cut off).
    ``x``, ``y``: the grid's coordinates."""
    lo, hi = np.array([np.min(x), np.min(y)]), np.array([np.max(x), np.max(y)])
    margin = 0.1 * (hi - lo)
    places = []
    for segments in lines.allsegs:
        if not segments:
            continue
        line = max(segments, key=lambda s: float(np.sum(np.linalg.norm(np.diff(s, axis=0), axis=1))))
        inside = np.all((line > lo + margin) & (line < hi - margin), axis=1)  # not a bound: where a label goes
        if not inside.any():
            continue
        along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(line / (hi - lo), axis=0), axis=1))])
        k = np.nonzero(inside)[0]
        places.append(tuple(line[k[np.argmin(np.abs(along[k] - along[-1] / 2))]]))
    return places


def rr_drive_map(out: PaperOutput, fast: bool) -> None:
    """Paper 000's RR arm: peak joint torques along Fig. 3's motion against t_f and payload."""
    tfs = [0.5, 1.0, 2.0, 3.0] if fast else [0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0]
    payloads = [0.0, 1.0, 2.0, 5.0] if fast else [0.0, 0.5, 1.0, 2.0, 3.0, 5.0]
    study = _study({"arm": "rr", "vary": {"tf": {"values": tfs, "unit": "s"}, "payload": {"values": payloads,
                                                                                          "unit": "kg"}},
                    "evaluate": ["peak_torque", "peak_power"]})
    results = {values: evaluate(study, values) for values in study.candidates}
    fig, axes = new_figure("Beyond paper 000 — drive sizing of the RR arm: peak joint torques along Fig. 3's motion "
                           "against the motion time and the payload", 1, 2, size=(11.0, 4.6))
    for j, ax in enumerate(np.ravel(axes)):
        grid = np.array([[results[(tf, m)][f"peak_torque_{j + 1}"] for tf in tfs] for m in payloads])
        ax.grid(False)
        image = ax.contourf(tfs, payloads, grid, levels=14, cmap="viridis")
        lines = ax.contour(tfs, payloads, grid, levels=image.levels[1::3], colors="w", linewidths=0.6)
        ax.clabel(lines, fontsize=7, fmt="%.3g", manual=_label_places(lines, tfs, payloads))
        fig.colorbar(image, ax=ax, label=f"peak |τ{j + 1}| [N·m]")
        ax.set_xlabel("motion time t_f [s]")
        ax.set_ylabel("payload at the tool [kg]")
        ax.set_title(f"joint {j + 1}", fontsize=9)
    out.figure(fig, "beyond_drive_map", "Drive-sizing map (not in the paper)",
               "peak |τ1|, |τ2| of the rest-to-rest quintic θ1 −38° → 62°, θ2 98° → 68° (Figs. 3, 5, 7) with the "
               "motion time and a point payload at M; batch inverse dynamics every 1 ms (armlab.kinematics.rnea), "
               "gravity −y, armlab's chosen link masses")
    rows = [[tf, m, results[(tf, m)]["peak_torque_1"], results[(tf, m)]["peak_torque_2"],
             results[(tf, m)]["peak_power"]] for tf in tfs for m in payloads]
    out.table("beyond_drive_map", "Peak joint torques and power against t_f and payload (not in the paper)",
              ["t_f [s]", "payload [kg]", "peak |τ1| [N·m]", "peak |τ2| [N·m]", "peak power [W]"], rows,
              note="Gravity dominates slow motions (the peaks level off as t_f grows); the inertial part falls as "
                   "1/t_f². The same study on a Dask cluster: `armlab sweep analysis/studies/rr_drive_sizing.json`.")


def _nearest(joint: Any) -> str:
    """The nearest infeasible pair of a joint's selection and the checks it fails."""
    if not joint.nearest:
        return ""
    n = joint.nearest[0]
    return f"{n.motor_name} + {n.gearbox_name}: {'; '.join(n.failed)}"


@functools.cache
def _rr_sizing(fast: bool) -> Any:
    """The RR arm's drives for Fig. 3's motion over :data:`RR_PAYLOADS`, oversized by :data:`OVERSIZE` (sized once
    per reproduction: :func:`rr_drives_chosen` reports them, :func:`rr_servo` drives the arm with them)."""
    # lazy: the reproduction of the other papers does not need the drives
    from armlab.api import size_drives
    from armlab.models import get_arm

    return size_drives(get_arm("rr"), None, RR_PAYLOADS[fast], safety_factor=OVERSIZE)  # None: Fig. 3's motion


def rr_drives_chosen(out: PaperOutput, fast: bool) -> None:
    """Paper 000 §5's drives: a motor and gearbox per joint of the RR arm from armlab's example catalogues, for
    Fig. 3's motion over the payload range, oversized by :data:`OVERSIZE` (:func:`armlab.size_drives`)."""
    # lazy: the reproduction of the other papers does not need the drives
    from armlab.sizing.report import torque_speed_figure

    payloads = RR_PAYLOADS[fast]
    sizing = _rr_sizing(fast)
    rows: list[list[Any]] = []
    for j in sizing.joints:
        c = j.chosen
        if c is None:
            rows.append([j.joint, "none feasible", "", "", "", "", _nearest(j)])
            continue
        worst = int(np.argmax(c.stats["rms_torque"]))
        rows.append([j.joint, f"{c.motor_name} + {c.gearbox_name}", c.ratio, c.mass, c.margin,
                     f"{sizing.cases[worst].label}: RMS {c.stats['rms_torque'][worst]:.4g} N·m, peak "
                     f"{c.stats['peak_torque'].max():.4g} N·m", _nearest(j)])
    out.table("beyond_drives", f"Drives chosen for Fig. 3's motion, payloads {', '.join(f'{m:g}' for m in payloads)} "
              f"kg, safety factor {OVERSIZE:g} (not in the paper)",
              ["joint", "motor + gearbox", "ratio G", "mass [kg]", "margin", "worst load case (motor side)",
               "the nearest infeasible pair"], rows,
              note=f"The lightest motor and gearbox of armlab's example catalogues (illustrative values of the kind "
                   f"datasheets give, not a vendor's; scripts/examples/catalogues/) per joint that carry every "
                   f"payload along Fig. 3's motion and pass every check armlab makes (torque and speed; voltage, "
                   f"current, winding temperature, regeneration, brake, gearbox life and inertia ratio where the "
                   f"catalogues give their data: sizing/checks.py), every torque × {OVERSIZE:g} (the paper's "
                   f"\"oversize\", "
                   f"a factor it does not give: armlab's choice). The drives' masses ride on the links (joint 2's "
                   f"on link 1); the selection converged after {sizing.iterations} rounds. "
                   "`armlab size rr --payload " + ",".join(f"{m:g}" for m in payloads)
                   + f" --safety-factor {OVERSIZE:g} --out DIR` gives the same.")
    for k, j in enumerate(sizing.joints):
        if j.chosen is not None:
            out.figure(torque_speed_figure(sizing, k), f"beyond_drives_joint{k + 1}",
                       f"Joint {k + 1}'s drive: motor torque against speed (not in the paper)",
                       "the chosen motor's peak envelope, its voltage limit at the bus voltage and its continuous "
                       "region, every payload's operating points along Fig. 3's motion and its RMS point (mean |ω|, "
                       "RMS τ), motor side through the gearbox")


def rr_servo(out: PaperOutput, fast: bool) -> None:
    """Fig. 6's ideal controller (continuous computed torque on the exact state) against :data:`SERVO`, a 1 kHz
    discrete PID on 4096-count motor encoders, the RR arm carrying the drives :func:`rr_drives_chosen` chose
    (their gear ratios and rotor inertias, their masses on the links), along Fig. 3's motion with no payload."""
    # lazy: the reproduction of the other papers does not simulate the servo loop
    from armlab.api import simulate
    from armlab.planning.motions import paper_motion
    from armlab.presentation.servo_plots import bode_figure

    sizing = _rr_sizing(fast)
    arm = sizing.arm.with_drives(sizing.drive_train())  # the chosen drives' masses ride on the links
    motion = paper_motion(arm)
    runs = {"Fig. 6's ideal controller": simulate(arm, motion, log_period=1e-3, divergence_tolerance=1.0),
            "1 kHz PID, 4096-count motor encoders": simulate(arm, motion, log_period=1e-3, divergence_tolerance=1.0,
                                                             **SERVO)}
    fig, axes = new_figure("Beyond paper 000 — the RR arm's tracking error along Fig. 3's motion: Fig. 6's ideal "
                           "controller against a 1 kHz PID on encoders, with the chosen drives", 2, 1, size=(9.0, 6.0),
                           sharex=True)
    for j, ax in enumerate(axes[:, 0]):
        for (label, run), style in zip(runs.items(), ("-", "--"), strict=True):
            ax.plot(run.t, 1e3 * (run.q[:, j] - run.q_ref[:, j]), style, label=label)
        ax.set_ylabel(f"q{j + 1} − q{j + 1},d [mrad]")
        ax.legend(fontsize=8)
    axes[-1, 0].set_xlabel("time t [s]")
    out.figure(fig, "beyond_servo_tracking", "Tracking error: ideal controller against a sampled PID (not in the "
               "paper)", f"the PID tuned by armlab's rule to a {SERVO['bandwidth']:g} Hz position-loop bandwidth from "
               "each joint's inertia with its drive (M_ii at the start, G²J_m included), its torque saturated at the "
               "arm's effort limits with anti-windup; the ideal loop's error is its integrator's (≤ 1e-6 rad)")
    rows = []
    for label, run in runs.items():
        servo = run.summary["servo"]
        error = np.abs(run.q - run.q_ref)
        rows.append([label, *np.max(error, axis=0), *np.sqrt(np.mean(error**2, axis=0)), *run.summary["max_abs_torque"],
                     "" if servo is None else max(servo["saturation_time"] or [0.0])])  # "": no saturation
    out.table("beyond_servo", "Ideal controller against a 1 kHz PID on encoders, the chosen drives (not in the paper)",
              ["loop", "max |e1| [rad]", "max |e2| [rad]", "RMS e1 [rad]", "RMS e2 [rad]", "peak |τ1| [N·m]",
               "peak |τ2| [N·m]", "saturated [s]"], rows,
              note="The PID has no model of the arm: its integral holds gravity, which it learns as the arm sags at "
                   "the start; the encoders' step at the joint is 2π/(4096·G). The same loop: `armlab simulate rr "
                   "--drives FILE --controller pid --bandwidth 5 --rate 1000 --encoder 4096 --saturate`; against "
                   "rate and encoder resolution as a Dask sweep: `armlab sweep "
                   "analysis/studies/rr_servo_rate_encoder.json`.")
    pid = runs["1 kHz PID, 4096-count motor encoders"]
    response = pid.frequency_response()
    out.figure(bode_figure("Beyond paper 000 — the RR arm's PID position loop with the chosen drives, linearised at "
                           "Fig. 3's start pose", arm.joint_names, response.frequency, response.response,
                           response.bandwidth, response.design), "beyond_servo_bode",
               "Frequency response of the PID loop (not in the paper)",
               "q_i/q_d,i per joint of the continuous loop linearised by Drake's Linearize about the start pose at "
               "rest, its −3 dB bandwidth against the tuning rule's (the joints' coupling moves it off the rule's, "
               "which is exact for an uncoupled joint)")


#: The studies, by the paper whose output they extend: (group title, function) each.
STUDIES: dict[str, tuple[tuple[str, Callable[[PaperOutput, bool], None]], ...]] = {
    "000": (("Beyond the paper: drive sizing — peak torques against motion time and payload", rr_drive_map),
            ("Beyond the paper: the drives — a motor and gearbox per joint from a catalogue, oversized",
             rr_drives_chosen),
            ("Beyond the paper: the servo loop — a 1 kHz PID on encoders against Fig. 6's ideal controller",
             rr_servo)),
    "004": (("Beyond the paper: the bend angles ϑ2…ϑ7 and the workspace volume (the paper's open question)",
             urm6_bend_angles),),
}


def run(paper: str, folder: Path, fast: bool = False, progress: Callable[[str], Any] = print) -> None:
    """Add ``paper``'s studies (if it has any), each a group, to its finished output in ``folder``."""
    if paper not in STUDIES:
        return
    out = PaperOutput(paper, Path(folder), progress)
    out.manifest = json.loads((out.folder / MANIFEST).read_text())  # the paper's own output, extended
    for title, study in STUDIES[paper]:
        out.group(title)
        study(out, fast)
    (out.folder / MANIFEST).write_text(json.dumps(out.manifest, indent=1, ensure_ascii=False))
