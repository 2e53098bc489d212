"""Benchmark: workspace volume and design-study sweeps (issue 11's goals).

1. The urm6 workspace volume from 10⁷ joint-space samples (:func:`armlab.analysis.workspace.workspace`,
   volume only: no Jacobians), the median of ``--repeat`` runs (goal ≤ 10 s on a 2-core machine).
2. A 100-candidate urm6 bend-angle sweep (ϑ2 × ϑ3 over 0 … 90° in 10 steps each, workspace volume at
   2·10⁵ samples each) through ``armlab sweep``'s engine (:func:`armlab.analysis.sweep.run_sweep`) on a
   LocalCluster of 1 and of 2 workers, each into a fresh folder: the whole call (cluster start and stop,
   plots included; goal ≤ 60 s at 2 workers) and the throughput in candidates/s and samples/s over the
   compute part (the sum of the candidates' wall times over the workers, reported beside it).

Run: ``.venv/bin/python scripts/bench/bench_analysis.py [--repeat 3] [--quick]``.
"""

from __future__ import annotations

import argparse
import csv
import json
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

from armlab.analysis.sweep import RESULTS, run_sweep
from armlab.analysis.workspace import workspace
from armlab.models import get_arm

#: The sweep's study: 100 candidates.
STUDY = {"arm": "urm6", "vary": {"theta2": {"from": 0, "to": 90, "steps": 10, "unit": "deg"},
                                 "theta3": {"from": 0, "to": 90, "steps": 10, "unit": "deg"}},
         "evaluate": ["workspace_volume"], "samples": 200_000}


def volume_seconds(samples: int, repeat: int) -> tuple[float, float]:
    """Median wall time (s) of the urm6 volume from ``samples`` samples, and the volume (m³)."""
    arm = get_arm("urm6")
    times, volume = [], 0.0
    for _ in range(repeat):
        began = time.perf_counter()
        volume = workspace(arm, samples, jacobians=False).volume
        times.append(time.perf_counter() - began)
    return statistics.median(times), volume


def sweep_seconds(workers: int, study: dict, folder: Path) -> dict[str, float]:
    """One sweep of ``study`` on a LocalCluster of ``workers``: whole call, summed candidate times, counts."""
    path = folder / f"study_{workers}.json"
    path.write_text(json.dumps(study))
    began = time.perf_counter()
    result = run_sweep(path, folder / f"out_{workers}", workers=workers, progress=False)
    total = time.perf_counter() - began
    with open(folder / f"out_{workers}" / RESULTS, newline="") as handle:
        busy = sum(float(row["wall_time_s"]) for row in csv.DictReader(handle))
    return {"total": total, "busy": busy, "candidates": result.computed, "failed": len(result.failed)}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs of the volume benchmark (median)")
    parser.add_argument("--quick", action="store_true", help="10⁶ samples and a 20-candidate sweep (a smoke run)")
    args = parser.parse_args()
    samples = 1_000_000 if args.quick else 10_000_000
    seconds, volume = volume_seconds(samples, args.repeat)
    print(f"urm6 workspace volume from {samples:.0e} samples: {seconds:.2f} s (median of {args.repeat}; goal ≤ 10 s "
          f"for 1e7), {samples / seconds / 1e6:.2f} M samples/s, volume {volume:.4f} m³")
    study: dict[str, Any] = dict(STUDY)
    if args.quick:
        study["vary"] = {"theta2": {"from": 0, "to": 90, "steps": 4, "unit": "deg"},
                         "theta3": {"from": 0, "to": 90, "steps": 5, "unit": "deg"}}
    with tempfile.TemporaryDirectory() as tmp:
        for workers in (1, 2):
            r = sweep_seconds(workers, study, Path(tmp))
            n = r["candidates"]
            compute = r["busy"] / workers
            print(f"sweep of {n:.0f} urm6 candidates × {study['samples']:.0e} samples, LocalCluster of {workers}: "
                  f"{r['total']:.1f} s in all (goal ≤ 60 s at 2 workers), {r['busy']:.1f} s of candidate time; "
                  f"{n / r['total']:.2f} candidates/s and {n * study['samples'] / r['total'] / 1e6:.2f} M samples/s "
                  f"overall, {n / compute:.2f} candidates/s while computing; {r['failed']:.0f} failed")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
