"""``armlab reproduce``: every paper's figures and tables regenerated, with a paper-vs-armlab report.

``armlab reproduce [--paper 000|001|003|004|all] [--out DIR] [--fast]`` runs the paper scripts
(``scripts/paper_NNN.py``, each also runnable alone) into a temporary folder beside ``DIR``,
writes ``report.md`` and ``report.html`` there, and only then renames it into place: the
output folder is complete or untouched (:class:`~armlab.files.OutputFolder`). An existing
``DIR`` is replaced only if it is empty or an earlier reproduction (it holds :data:`MARKER`);
reproducing some papers keeps the others an earlier reproduction there holds, and the report
covers them all.
"""

from __future__ import annotations

import argparse
import importlib
import shutil
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from armlab.files import OutputFolder

__all__ = ["MARKER", "PAPERS", "ReproduceResult", "output_folder", "register", "reproduce", "run_alone"]

#: The papers, in report order, and their scripts (modules of :mod:`armlab.scripts`).
PAPERS = ("000", "001", "003", "004")
#: The file that marks a folder as an armlab reproduction (safe to replace).
MARKER = ".armlab-reproduce"


@dataclass(frozen=True)
class ReproduceResult:
    """What :func:`reproduce` wrote: the report's path, its rows and the verdict counts."""

    report: Path
    rows: list[Any]
    counts: dict[str, int]
    elapsed: float


def _script(paper: str) -> Any:
    return importlib.import_module(f"armlab.scripts.paper_{paper}")


def select_papers(paper: str) -> tuple[str, ...]:
    """``"all"`` → every paper; one number → that paper; anything else is a ``ValueError``."""
    if paper == "all":
        return PAPERS
    if paper not in PAPERS:
        raise ValueError(f"--paper {paper!r} is not allowed; allowed: {', '.join(PAPERS)}, all")
    return (paper,)


def _is_previous(folder: Path) -> bool:
    """An earlier reproduction, or a folder holding only single papers reproduced alone."""
    if (folder / MARKER).exists():
        return True
    return all(p.is_dir() and p.name in PAPERS and (p / MARKER).exists() for p in folder.iterdir())


def output_folder(out: str | Path) -> OutputFolder:
    """The output folder of a reproduction, checked before any work (see :class:`~armlab.files.OutputFolder`).

    Allowed: a folder that does not exist yet (its parents are created), an empty folder, or an
    earlier reproduction; the new output is built beside it and renamed into place when complete.
    """
    return OutputFolder(Path(out).expanduser(), _is_previous, f"an earlier armlab reproduction (no {MARKER})")


def reproduce(
    out: Path, papers: Sequence[str] = PAPERS, fast: bool = False, progress: Callable[[str], Any] = print
) -> ReproduceResult:
    """Run the paper scripts into ``out`` (complete or nothing) and write the report; see the module doc.

    Papers not in ``papers`` that an earlier reproduction in ``out`` holds are kept (copied into the
    new output, their rows read back), so reproducing one paper updates it and the report alone.
    """
    from armlab.diagrams.graphviz import require_dot
    from armlab.scripts import beyond
    from armlab.scripts.report import load_rows, verdict_counts, write_report

    start = time.perf_counter()
    for paper in papers:
        select_papers(paper)
    require_dot()  # the Systems diagrams need it: say so before any work
    folder = output_folder(out)
    earlier = {p: load_rows(folder.out / p) for p in PAPERS if p not in papers} if folder.out.is_dir() else {}
    kept = {paper: rows for paper, rows in earlier.items() if rows is not None}
    with folder as tmp:
        rows = []
        for paper in PAPERS:
            if paper in papers:
                rows += _script(paper).run(tmp / paper, fast=fast, progress=progress)
                beyond.run(paper, tmp / paper, fast=fast, progress=progress)  # design studies beyond the paper
            elif paper in kept:
                shutil.copytree(folder.out / paper, tmp / paper)
                rows += kept[paper]
                progress(f"[{paper}] kept from the earlier reproduction in {folder.out}")
        (tmp / MARKER).write_text("armlab reproduce output; `armlab reproduce` may replace this folder\n")
        write_report(tmp, [p for p in PAPERS if p in papers or p in kept], rows, time.perf_counter() - start)
    return ReproduceResult(folder.out / "report.md", rows, verdict_counts(rows), time.perf_counter() - start)


def summary_line(result: ReproduceResult) -> str:
    """The final line: the report's path and the verdict counts."""
    c = result.counts
    return (f"report: {result.report}  ({len(result.rows)} rows: {c['matches']} matches, {c['differs']} differs, "
            f"{c['not reproducible']} not reproducible; {result.elapsed:.1f} s)")


def _cmd(args: argparse.Namespace) -> int:
    result = reproduce(Path(args.out), select_papers(args.paper), fast=args.fast)
    print(summary_line(result))
    return 0


def register(subparsers: Any) -> None:
    """Add the ``reproduce`` subcommand to the ``armlab`` CLI's subparsers."""
    p = subparsers.add_parser("reproduce", help="regenerate the papers' figures and tables, with a report")
    p.add_argument("--paper", default="all", help="000, 001, 003, 004 or all (default all); one paper is redone, "
                   "the others an earlier reproduction in --out holds are kept in the report")
    p.add_argument("--out", default="out", help="output folder (default out/)")
    p.add_argument("--fast", action="store_true", help="coarser sampling and log period (for CI)")
    p.set_defaults(func=_cmd)


def run_alone(paper: str, run: Callable[..., list], argv: Sequence[str] | None = None) -> int:
    """A paper script's ``main``: ``--out DIR`` (default ``out/NNN``) and ``--fast``; prints its verdict counts."""
    from armlab.scripts.report import verdict_counts

    parser = argparse.ArgumentParser(prog=f"paper_{paper}", description=f"Reproduce paper {paper} alone.")
    parser.add_argument("--out", default=f"out/{paper}", help=f"output folder (default out/{paper})")
    parser.add_argument("--fast", action="store_true", help="coarser sampling and log period")
    args = parser.parse_args(argv)
    try:
        folder = output_folder(args.out)
        with folder as tmp:
            rows = run(tmp, fast=args.fast)
            (tmp / MARKER).write_text(f"armlab paper_{paper} output; it may be replaced by a later run\n")
    except (ValueError, OSError) as error:
        print(f"paper_{paper}: error: {error}", file=sys.stderr)
        return 2
    counts = verdict_counts(rows)
    print(f"{folder.out}: {len(rows)} rows: {counts['matches']} matches, {counts['differs']} differs, "
          f"{counts['not reproducible']} not reproducible")
    return 0
