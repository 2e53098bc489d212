"""Beyond the papers: two design studies that answer what the papers leave open, in ``armlab reproduce``.

* **004** ends on "a search for an optimum angle ϑi and its impact on the size of the workspace":
  the URM arm's workspace volume as each bend angle ϑ2 … ϑ7 runs over 0 … 90° (the others at
  Table 1's values), the best angle of each, and the volume with all the best angles together.
* **000** sizes drives by simulation: the RR arm's peak joint torques along Fig. 3's motion against
  the motion time t_f and the payload — the drive-sizing map.

Each is a study of :mod:`armlab.analysis.study` evaluated in this process (the reproduction is small;
``armlab sweep`` runs the same studies on a Dask cluster: ``analysis/studies/*.json``). The
reproduction's sample counts are modest (:data:`SAMPLES`); the report says which. :func:`run` adds
each study as a "Beyond the paper" group to its paper's output folder (figures, a table, and the
manifest the report reads).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from armlab.analysis.study import evaluate, parse_study
from armlab.models.urm6 import Parameters
from armlab.scripts.figures import new_figure
from armlab.scripts.paper_output import MANIFEST, PaperOutput

__all__ = ["SAMPLES", "STUDIES", "rr_drive_map", "run", "urm6_bend_angles"]

#: Workspace samples per candidate of the bend-angle study (normal, fast) and its angle steps.
SAMPLES = {False: 100_000, True: 30_000}
ANGLE_STEPS = {False: 7, True: 4}


def _study(data: dict[str, Any]) -> Any:
    return parse_study(data)


def urm6_bend_angles(out: PaperOutput, fast: bool) -> None:
    """Paper 004's open question: workspace volume against each bend angle ϑ2 … ϑ7 (one at a time)."""
    samples, steps = SAMPLES[fast], ANGLE_STEPS[fast]
    nominal = Parameters()
    names = [f"theta{k}" for k in range(2, 8)]

    def volume(angles_deg: dict[str, float]) -> float:
        """The workspace volume (m³) with the bend angles ``angles_deg`` (deg), the others at Table 1's."""
        study = _study({"arm": "urm6", "vary": {n: {"values": [v], "unit": "deg"} for n, v in angles_deg.items()},
                        "evaluate": ["workspace_volume"], "samples": samples})
        return evaluate(study, study.candidates[0])["workspace_volume"]

    curves, table, best = {}, [], {}
    nominal_volume = volume({names[0]: float(np.degrees(getattr(nominal, names[0])))})  # all at Table 1's angles
    for name in names:
        study = _study({"arm": "urm6", "vary": {name: {"from": 0, "to": 90, "steps": steps, "unit": "deg"}},
                        "evaluate": ["workspace_volume"], "samples": samples})
        angles = np.array([values[0] for values in study.candidates])
        volumes = np.array([evaluate(study, values)["workspace_volume"] for values in study.candidates])
        curves[name] = (angles, volumes)
        table_deg = float(np.degrees(getattr(nominal, name)))
        k = int(np.argmax(volumes))
        best[name] = float(angles[k])
        table.append([f"ϑ{name[5:]}", table_deg, float(angles[k]), float(volumes[k]),
                      float(volumes[k] / nominal_volume)])
    combined_volume = volume(best)
    table.append(["all six at their best", "", "[" + ", ".join(f"{best[n]:g}" for n in names) + "]", combined_volume,
                  combined_volume / nominal_volume])

    fig, ax = new_figure("Beyond paper 004 — workspace volume of the URM arm against each bend angle ϑi "
                         "(the others at Table 1's values)", size=(7.5, 4.6))
    for i, name in enumerate(names):
        angles, volumes = curves[name]
        ax.plot(angles, volumes, "o-", ms=3, color=f"C{i}", label=f"ϑ{name[5:]} (Table 1: "
                f"{np.degrees(getattr(nominal, name)):g}°)")
        ax.plot([best[name]], [volumes.max()], "*", ms=11, color=f"C{i}")
    ax.axhline(nominal_volume, color="k", lw=0.8, ls="--", label=f"Table 1's angles: {nominal_volume:.3f} m³")
    ax.set_xlabel("bend angle ϑi [deg]")
    ax.set_ylabel("workspace volume [m³]")
    ax.legend(fontsize=7, ncol=2)
    out.figure(fig, "beyond_bend_angles", "Workspace volume against the bend angles (not in the paper)",
               f"each ϑi over 0…90° in {steps} steps, the others at Table 1's values; ★ the best of each; "
               f"{samples} joint-space samples per candidate, voxel volume extrapolated to h → 0 "
               "(armlab.analysis.workspace)")
    out.table("beyond_bend_angles", "Best bend angles for the workspace volume (not in the paper)",
              ["angle", "Table 1 [deg]", "best [deg]", "volume at best [m³]", "× Table 1's volume"], table,
              note=f"Table 1's angles give {nominal_volume:.4g} m³. One angle varied at a time over a {steps}-step "
                   f"grid, then all six best angles together. {samples} joint-space samples per candidate, a modest "
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
        inside = np.all((line > lo + margin) & (line < hi - margin), axis=1)
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


#: The studies, by the paper whose output they extend: (group title, function).
STUDIES: dict[str, tuple[str, Callable[[PaperOutput, bool], None]]] = {
    "000": ("Beyond the paper: drive sizing — peak torques against motion time and payload", rr_drive_map),
    "004": ("Beyond the paper: the bend angles ϑ2…ϑ7 and the workspace volume (the paper's open question)",
            urm6_bend_angles),
}


def run(paper: str, folder: Path, fast: bool = False, progress: Callable[[str], Any] = print) -> None:
    """Add ``paper``'s study (if it has one) as a group to its finished output in ``folder``."""
    if paper not in STUDIES:
        return
    title, study = STUDIES[paper]
    out = PaperOutput(paper, Path(folder), progress)
    out.manifest = json.loads((out.folder / MANIFEST).read_text())  # the paper's own output, extended
    out.group(title)
    study(out, fast)
    (out.folder / MANIFEST).write_text(json.dumps(out.manifest, indent=1, ensure_ascii=False))
