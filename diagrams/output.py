"""Writing a simulation run into its folder: completely or not at all.

:class:`RunFolder` makes a temporary folder next to the requested one before anything is
simulated (so an unwritable place is an error up front), collects the files there, and renames it
onto the requested folder only when every file is written. A previous armlab run in that folder is
replaced; any other non-empty folder is left alone (an error).
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from armlab.diagrams.simulate import SimulationLog

__all__ = ["RUN_FILES", "RunFolder", "csv_header", "write_log_csv", "write_summary"]

#: Files that mark a folder as an armlab run (which ``--out`` may replace).
RUN_FILES = ("log.csv", "summary.json")


def csv_header(n: int) -> list[str]:
    """Column names of ``log.csv`` for ``n`` joints."""
    cols = ["t"]
    for fmt in ("q{}_ref", "qd{}_ref", "qdd{}_ref", "q{}", "qd{}", "tau{}"):
        cols += [fmt.format(i) for i in range(1, n + 1)]
    return cols + ["x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az"]


def write_log_csv(log: SimulationLog, path: str | Path) -> Path:
    """``log.csv``: a header row, then one row per log sample (:func:`csv_header`), SI units."""
    table = np.column_stack([log.t, log.q_ref, log.qd_ref, log.qdd_ref, log.q, log.qd, log.tau, log.tool])
    np.savetxt(path, table, fmt="%.12g", delimiter=",", header=",".join(csv_header(log.arm.n)), comments="")
    return Path(path)


def write_summary(summary: dict[str, Any], path: str | Path) -> Path:
    """``summary.json``, indented."""
    Path(path).write_text(json.dumps(summary, indent=2, ensure_ascii=False) + "\n")
    return Path(path)


class RunFolder:
    """``with RunFolder(out) as tmp:`` write into ``tmp``; on success it becomes ``out``, on error it is removed."""

    def __init__(self, out: str | Path) -> None:
        self.out = Path(out)
        if self.out.exists():
            if not self.out.is_dir():
                raise ValueError(f"--out {self.out}: exists and is not a folder")
            contents = {p.name for p in self.out.iterdir()}
            if contents and not set(RUN_FILES) <= contents:
                raise ValueError(f"--out {self.out}: exists and is not an armlab run folder (no "
                                 f"{' and '.join(RUN_FILES)}); give a new or empty folder")
        parent = self.out.absolute().parent
        try:
            parent.mkdir(parents=True, exist_ok=True)
            self.tmp = Path(tempfile.mkdtemp(dir=parent, prefix=f".{self.out.name}.", suffix=".tmp"))
            umask = os.umask(0o022)
            os.umask(umask)
            self.tmp.chmod(0o777 & ~umask)  # mkdtemp makes it private; the run folder is an ordinary folder
        except OSError as error:
            raise ValueError(f"--out {self.out}: cannot write in {parent}: {error.strerror or error}") from None

    def __enter__(self) -> Path:
        return self.tmp

    def __exit__(self, kind, value, traceback) -> None:
        if kind is not None:
            shutil.rmtree(self.tmp, ignore_errors=True)
            return
        old = None
        if self.out.exists():
            old = Path(tempfile.mkdtemp(dir=self.tmp.parent, prefix=f".{self.out.name}.", suffix=".old"))
            os.replace(self.out, old / "run")
        try:
            os.replace(self.tmp, self.out)
        except OSError:
            if old is not None:
                os.replace(old / "run", self.out)
            shutil.rmtree(self.tmp, ignore_errors=True)
            raise
        finally:
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
