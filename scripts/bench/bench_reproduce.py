"""Benchmark: ``armlab reproduce`` as ``make run`` runs it on a fresh machine, in worker processes and in one.

Each run is a whole ``armlab reproduce --out DIR`` process started cold in the ways a first run after
``make setup`` is: a new, empty matplotlib cache folder (``MPLCONFIGDIR``: its font list is built again)
and no bytecode cache for armlab's own modules (the ``__pycache__`` folders of this source tree are
removed: each module is compiled again; pip compiled the installed packages at install). The default
(one worker process per CPU) is timed against ``--jobs 1`` (everything in one process) in turns, so
the ratio holds while the machine's speed drifts; the goal is ≤ 20 s for the default (issue 10, goal
5). Both must report the same rows.

Run: ``.venv/bin/python scripts/bench/bench_reproduce.py`` (or ``make bench``).
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from armlab.papers.reproduce import default_jobs

#: The goal for the default run (s).
GOAL = 20.0
#: The source tree (armlab is installed from it in editable mode).
ROOT = Path(__file__).resolve().parents[1]


def _forget_bytecode() -> None:
    """Remove the bytecode caches of armlab's own modules (not the virtual environment's)."""
    for cache in ROOT.rglob("__pycache__"):
        if not cache.relative_to(ROOT).parts[0].startswith("."):
            shutil.rmtree(cache, ignore_errors=True)


def cold_seconds(jobs: int | None, folder: Path) -> tuple[float, str]:
    """Wall time of one cold ``armlab reproduce`` (``--jobs`` if given) into a new folder under ``folder``, and the
    summary line it printed."""
    run = Path(tempfile.mkdtemp(dir=folder))
    env = {**os.environ, "MPLCONFIGDIR": str(run / "mpl")}
    _forget_bytecode()
    command = [str(Path(sys.executable).with_name("armlab")), "reproduce", "--out", str(run / "out")]
    command += ["--jobs", str(jobs)] if jobs else []
    began = time.perf_counter()
    done = subprocess.run(command, env=env, capture_output=True, text=True, check=True)
    seconds = time.perf_counter() - began
    return seconds, done.stdout.strip().splitlines()[-1]


def main(argv: list[str] | None = None) -> int:
    """Print the cold reproduction's wall time with the default workers and with one process, and their ratio."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs of each, in turns (default 3; median)")
    args = parser.parse_args(argv)

    times: dict[str, list[float]] = {"default": [], "one": []}
    summaries = set()
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(args.repeat):
            for key, jobs in (("default", None), ("one", 1)):
                seconds, summary = cold_seconds(jobs, Path(folder))
                times[key].append(seconds)
                summaries.add(summary.split("(", 1)[1].split(";", 1)[0])  # the row counts, not the time
    if len(summaries) != 1:
        raise SystemExit(f"the runs reported different rows: {sorted(summaries)}")
    default, one = statistics.median(times["default"]), statistics.median(times["one"])
    ratios = [b / a for a, b in zip(times["default"], times["one"], strict=True)]
    print(f"cold `armlab reproduce` (new matplotlib cache, armlab compiled again), median of {args.repeat}; "
          f"{summaries.pop()}")
    print(f"  {default_jobs()} worker processes (default): {default:6.1f} s   (goal ≤ {GOAL:g} s)   "
          f"runs: {', '.join(f'{t:.1f}' for t in times['default'])}")
    print(f"  one process (--jobs 1):      {one:6.1f} s   runs: {', '.join(f'{t:.1f}' for t in times['one'])}")
    print(f"  one process / workers: {statistics.median(ratios):.2f}× (median of the pairs)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
