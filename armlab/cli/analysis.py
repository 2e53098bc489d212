"""``armlab workspace`` and ``armlab sweep``: the command-line side of :mod:`armlab.analysis`.

``armlab workspace ARM [--samples N] [--resolution H] [--seed S] [--out DIR] [--json]`` measures an
arm's workspace (:func:`armlab.analysis.workspace.workspace`) and writes, into DIR, all or nothing
(:mod:`armlab.analysis.output`):
``workspace.json``, ``slices.png``, ``convergence.png``, ``singular.png`` and ``workspace.html`` (a 3-D
point cloud that opens in any browser). ``armlab sweep STUDY.json --out DIR`` runs a design study
(:mod:`armlab.analysis.sweep`). Dask, Drake and matplotlib are imported only when a command runs.
"""

from __future__ import annotations

import argparse
import json
import textwrap
from contextlib import nullcontext
from pathlib import Path
from typing import Any

import numpy as np

import armlab.analysis
from armlab.analysis.output import workspace_folder, write_workspace
from armlab.analysis.sweep import EXIT_FAILED, RESULTS, STUDY, run_sweep
from armlab.analysis.workspace import (
    DEFAULT_SAMPLES,
    MAX_SAMPLES,
    MAX_SEED,
    SAMPLES_PER_CELL,
    check_resolution,
    check_samples,
    check_seed,
    workspace,
)
from armlab.cli.args import add_arm, arm_of, integer, number, positive_int
from armlab.cli.collide import SCENE_HELP
from armlab.limits import allowed, whole_text

__all__ = ["cmd_sweep", "cmd_workspace", "register"]

#: The example design studies (``armlab sweep --help`` names them).
STUDIES = Path(armlab.analysis.__file__).resolve().parent / "studies"


def _format(summary: dict[str, Any]) -> list[str]:
    s = summary
    lines = [f"{s['arm']}: workspace {s['measure']} {s['volume']:.6g} {s['volume_unit']} ({s['samples']} samples; "
             f"occupied voxels of {s['resolution']:.4g} m: {s['volume_voxels']:.6g}, extrapolated to h → 0 from h "
             "and 2h)" + (f"; {s['note']}" if "note" in s else ""),
             f"reach {s['reach']:.6g} m; bounding box x {s['bbox']['min'][0]:+.4f} … {s['bbox']['max'][0]:+.4f}, "
             f"y {s['bbox']['min'][1]:+.4f} … {s['bbox']['max'][1]:+.4f}, "
             f"z {s['bbox']['min'][2]:+.4f} … {s['bbox']['max'][2]:+.4f} m"]
    if "collision_check" in s:
        lines.append(f"collision-free {s['measure']} {s['collision_free_volume']:.6g} {s['volume_unit']} "
                     f"({s['collision_free_fraction']:.1%} of the samples touch nothing; {s['collision_check']})")
    c = s["convergence"]
    lines.append(f"{s['measure']} vs samples: " + "  ".join(
        f"{int(n)}: " + ("— (cells not filled)" if v is None else f"{v:.5g}")
        for n, v in zip(c["samples"], c["volume_vs_samples"], strict=True)))
    lines.append(f"occupied voxels' {s['measure']} vs voxel edge h: " + "  ".join(f"{h:.4g} m: {v:.5g}" for h, v in zip(
        c["resolution"], c["volume_vs_resolution"], strict=True)))
    if "manipulability" in s:
        m, g = s["manipulability"], s["sigma_min"]
        lines.append(f"manipulability ({s['singular']['rows']} rows of J, {m['configurations']} configurations): "
                     f"min {m['min']:.3g}, median {m['median']:.3g}, max {m['max']:.3g}; σ_min min {g['min']:.3g}, "
                     f"median {g['median']:.3g}")
        sing = s["singular"]
        if "loci" in sing:
            loci = sing["loci"]
            if loci["values"]:
                shown = np.degrees(loci["values"]) if loci["unit"] == "rad" else np.array(loci["values"])
                unit = "deg" if loci["unit"] == "rad" else "m"
                values = ", ".join(f"{v:g}" for v in np.round(shown, 9) + 0.0)
                anywhere = ", whatever the other joints" if loci["independent_of_other_joints"] else ""
                lines.append(f"singular where {loci['joint']} = {values} {unit}{anywhere}")
            else:
                lines.append(f"no singular configuration within the limits (σ_min ≥ {g['min']:.3g})")
        else:
            lines.append(f"σ_min depends on {', '.join(sing['depends_on']) or 'no joint'}; "
                         f"{len(sing.get('configurations', []))} singular configurations found and listed "
                         f"(σ_min < {sing['tolerance']:g})")
    return lines


def cmd_workspace(args: argparse.Namespace) -> int:
    """``armlab workspace``: see the module docstring."""
    # lazy: armlab --help loads armlab.cli.analysis but not this (Drake; start-up time)
    from armlab.collision.clearance import as_scene

    check_samples(args.samples, "--samples")
    check_seed(args.seed, "--seed")
    if args.resolution is not None:
        check_resolution(args.resolution, "--resolution")
    arm = arm_of(args)
    scene = as_scene(args.scene)
    folder = workspace_folder(args.out) if args.out is not None else None
    # The temporary folder goes on any exit from here (an error or a stop signal during the sampling too).
    with folder if folder is not None else nullcontext() as tmp:
        ws = workspace(arm, args.samples, args.resolution, args.seed, collisions=args.collision_free, scene=scene)
        summary = ws.summary()
        written = write_workspace(arm, ws, tmp) if tmp is not None else []
    if args.json:
        print(json.dumps(summary, indent=2, ensure_ascii=False))
    else:
        print("\n".join(_format(summary)))
        if folder is not None:
            print(f"wrote {args.out}: {' '.join(written)}")
    return 0


def cmd_sweep(args: argparse.Namespace) -> int:
    """``armlab sweep``: see :mod:`armlab.analysis.sweep`."""
    result = run_sweep(args.study, args.out, args.workers, args.scheduler)
    print(f"{args.out}: {result.total} candidates: {result.done_before} done before, {result.computed} computed, "
          f"{len(result.failed)} failed ({result.wall_time:.1f} s); wrote {RESULTS} {STUDY} {' '.join(result.plots)}")
    return EXIT_FAILED + min(len(result.failed), 100) if result.failed else 0


def register(subparsers: Any) -> None:
    """Add the ``workspace`` and ``sweep`` subcommands to the CLI's subparsers."""
    p = subparsers.add_parser(
        "workspace",
        description=textwrap.fill(
            "Sample ARM's joint space (within the limits; a revolute joint without limits over a full turn), "
            "and report the workspace volume (area for a planar arm) from the voxels the tool point occupies, with "
            "its convergence in the samples N and the voxel edge h, the reach, the bounding box, the manipulability "
            "(Yoshikawa's and σ_min of the Jacobian) and the singular configurations. With --out, write "
            "workspace.json, slices.png, convergence.png, singular.png and workspace.html (a 3-D point cloud).", 100),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_arm(p)
    p.add_argument("--samples", type=positive_int, default=DEFAULT_SAMPLES, metavar="N",
                   help=f"joint-space samples, 1000 … {whole_text(MAX_SAMPLES)} "
                        f"(default {whole_text(DEFAULT_SAMPLES)})")
    p.add_argument("--resolution", type=number, metavar="H",
                   help=f"voxel edge in metres, {allowed('resolution')} (default: about {SAMPLES_PER_CELL} samples "
                        "per occupied cell)")
    p.add_argument("--seed", type=integer, default=0, help=f"seed of the random samples, 0 … {MAX_SEED} (default 0)")
    p.add_argument("--collision-free", action="store_true",
                   help="also the collision-free volume: from the samples in which the arm touches neither itself "
                        "nor an obstacle of --scene (and collisions.png: where the two differ)")
    p.add_argument("--scene", help=SCENE_HELP + " (implies --collision-free)")
    p.add_argument("--out", metavar="DIR", help="output folder (written completely or not at all)")
    p.add_argument("--json", action="store_true", help="print the summary (workspace.json) as JSON")
    p.set_defaults(func=cmd_workspace)

    p = subparsers.add_parser(
        "sweep",
        description="Evaluate every candidate of the study in STUDY.json on a Dask cluster (a local one by default) "
                    "and write DIR/results.csv (one row per candidate), study.json and the plots. A rerun into the "
                    "same DIR computes only the candidates not yet in results.csv.",
        epilog=textwrap.dedent(f"""\
            study file (JSON):
              {{"arm": "urm6",
               "vary": {{"theta3": {{"from": 0, "to": 90, "steps": 7, "unit": "deg"}},
                        "theta5": {{"values": [30, 60, 90], "unit": "deg"}}}},
               "evaluate": ["workspace_volume", "reach", "min_manipulability"],
               "samples": 200000}}
            vary: the arm's parameters (armlab show ARM), payload (kg) and tf (s); evaluate: workspace_volume,
            reach, min_manipulability, mean_manipulability, peak_torque, rms_torque, peak_power, and the drives
            chosen from catalogues for the motion (armlab size): drive_mass (kg), drives_feasible, drive_margin,
            and the servo loop's max_tracking_error, rms_tracking_error (rad or m; vary rate in Hz and encoder
            counts; "servo": {{"controller": "pid", "bandwidth": 5, …}}: armlab simulate's servo options).
            Optional: samples, resolution (m), seed, payload, tf, simulate (true: paper 000's Fig. 6
            simulation; false: batch inverse dynamics along the motion every 1 ms), segments (a motion file
            instead of the paper motion), safety_factor, motors, gearboxes (catalogue CSVs; default armlab's
            examples), drives (a drive file). Example studies: {STUDIES}/*.json.

            exit status: 0 every candidate computed; 2 bad study or options (nothing computed);
            {EXIT_FAILED} + k when k candidates failed (k at most 100); each failure is reported on stderr."""),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("study", metavar="STUDY.json", help="the study file")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder (a rerun resumes it)")
    p.add_argument("--workers", type=positive_int, metavar="N",
                   help="local worker processes (default: one per core)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="an existing Dask scheduler to run on (its workers need the same armlab installed, and run "
                        "workspace candidates up to 3× faster with the Dask config MALLOC_TRIM_THRESHOLD_: null under "
                        "distributed.nanny.pre-spawn-environ; see armlab.analysis.sweep)")
    p.set_defaults(func=cmd_sweep)
