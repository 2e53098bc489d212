"""``armlab reproduce`` (:func:`armlab.papers.reproduce.reproduce`), and the command line of each paper script run
alone (``python -m armlab.papers.paper_000``, :func:`run_alone`)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from armlab.cli.args import positive_int
from armlab.papers.report_rows import verdict_counts
from armlab.papers.reproduce import (
    MAX_JOBS,
    default_jobs,
    reproduce,
    reproduce_alone,
    select_papers,
    summary_line,
)

__all__ = ["register", "run_alone"]


def _cmd(args: argparse.Namespace) -> int:
    result = reproduce(Path(args.out), select_papers(args.paper), fast=args.fast, jobs=args.jobs)
    print(summary_line(result))
    return 0


def register(subparsers: Any) -> None:
    """Add the ``reproduce`` subcommand to the ``armlab`` CLI's subparsers."""
    p = subparsers.add_parser("reproduce")
    p.add_argument("--paper", default="all", help="000, 001, 003, 004 or all (default all); one paper is redone, "
                   "the others an earlier reproduction in --out holds are kept in the report")
    p.add_argument("--out", default="out", help="output folder (default out/)")
    p.add_argument("--fast", action="store_true", help="coarser sampling and log period (for CI)")
    p.add_argument("--jobs", type=positive_int, default=None, metavar="N",
                   help=f"worker processes (default: one per CPU armlab may use, at most {MAX_JOBS}: here "
                        f"{default_jobs()}); 1 runs everything in this process")
    p.set_defaults(func=_cmd)


def run_alone(paper: str, run: Callable[..., list], argv: Sequence[str] | None = None) -> int:
    """A paper script's ``main``: ``--out DIR`` (default ``out/NNN``) and ``--fast``; prints its verdict counts."""
    parser = argparse.ArgumentParser(prog=f"paper_{paper}", description=f"Reproduce paper {paper} alone.")
    parser.add_argument("--out", default=f"out/{paper}", help=f"output folder (default out/{paper})")
    parser.add_argument("--fast", action="store_true", help="coarser sampling and log period")
    args = parser.parse_args(argv)
    try:
        out, rows = reproduce_alone(paper, run, args.out, fast=args.fast)
    except (ValueError, OSError) as error:
        print(f"paper_{paper}: error: {error}", file=sys.stderr)
        return 2
    counts = verdict_counts(rows)
    print(f"{out}: {len(rows)} rows: {counts['matches']} matches, {counts['differs']} differs, "
          f"{counts['not reproducible']} not reproducible")
    return 0
