"""``armlab reproduce``: every paper's figures and tables regenerated, with a paper-vs-armlab report.

``armlab reproduce [--paper 000|001|003|004|all] [--out DIR] [--fast] [--jobs N]`` runs the paper
scripts (``papers/paper_NNN.py``, each also runnable alone) into a temporary folder beside ``DIR``,
in ``N`` worker processes (default: one per CPU, at most four; the papers are independent, and the workers
render the report's mathematics and embed its figures as each paper ends), writes ``report.md``
and ``report.html`` there, and only then renames it into place: the output folder is complete or
untouched (:class:`~armlab.files.OutputFolder`). An existing ``DIR`` is replaced only if it is empty
or an earlier reproduction (it holds :data:`MARKER`); reproducing some papers keeps the others an
earlier reproduction there holds, and the report covers them all.
"""

from __future__ import annotations

import importlib
import multiprocessing
import os
import shutil
import signal
import threading
import time
import traceback
import warnings
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from multiprocessing import resource_tracker
from multiprocessing.connection import Connection, wait
from pathlib import Path
from typing import Any

from armlab.analysis.sweep import default_workers
from armlab.files import OutputFolder, signals_held
from armlab.papers.report_rows import verdict_counts

__all__ = ["MARKER", "PAPERS", "ReproduceResult", "default_jobs", "output_folder", "reproduce", "reproduce_alone"]

#: The papers, in report order, and their scripts (modules of :mod:`armlab.papers`).
PAPERS = ("000", "001", "003", "004")
#: The file that marks a folder as an armlab reproduction (safe to replace).
MARKER = ".armlab-reproduce"
#: The papers in the order their scripts start: the longest first (000 takes about half of the time).
LONGEST_FIRST = ("000", "004", "003", "001")
#: Tasks each paper's report mathematics is split into when workers render it.
MATH_TASKS = 4
#: More worker processes than this would only wait: at most four papers, then four mathematics tasks at a time.
MAX_JOBS = 4
#: The workers' numerical libraries run one thread each: there is a worker per CPU already, and the threads of
#: OpenBLAS (numpy's) and OpenMP wait for work spinning, costing CPU the other worker needs.
ONE_THREAD = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


@dataclass(frozen=True)
class ReproduceResult:
    """What :func:`reproduce` wrote: the report's path, its rows and the verdict counts."""

    report: Path
    rows: list[Any]
    counts: dict[str, int]
    elapsed: float


def _script(paper: str) -> Any:
    return importlib.import_module(f"armlab.papers.paper_{paper}")


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


def default_jobs() -> int:
    """Worker processes by default: one per CPU armlab may use (``armlab sweep``'s
    :func:`~armlab.analysis.sweep.default_workers`), at most :data:`MAX_JOBS`."""
    return min(default_workers(), MAX_JOBS)


def _job(task: Callable[..., Any], args: tuple, progress: Callable[[str], Any]) -> tuple[Any, list]:
    """``task(*args, progress=progress)``'s value and the warnings it raised (``(category, message)``, to raise
    again in the parent)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = task(*args, progress=progress)
    return value, [(w.category, str(w.message)) for w in caught]


class WorkerTracebackError(Exception):
    """A worker's traceback (its text): the cause of the worker's error raised again in the parent."""


def _error_end(error: Exception) -> tuple[str, tuple[Exception, str]]:
    """A task's end for an error: ``("error", (error, its traceback in the worker))``."""
    return "error", (error, '\n"""\n' + "".join(traceback.format_exception(error)) + '"""')


def _worker(connection: Connection) -> None:
    """A worker process: runs each ``(task, args)`` the parent sends on ``connection`` (:func:`_job`) until the
    parent closes it. It sends back each progress line, ``("line", text)``, then the task's end, ``("value",
    (value, warnings))`` or ``("error", (exception, traceback))`` (:func:`_error_end`): one pipe, so a task's
    lines precede its end.

    Ctrl-C is the parent's to handle (it stops the workers): ignored here, and blocked until then (since the
    process started, :func:`_ctrl_c_blocked`). tqdm's bars (the simulations') share a thread lock
    here, not the interprocess lock tqdm makes by default: a worker the parent terminates cannot release an
    interprocess lock, and Python warns of it on exit.
    """
    from tqdm import tqdm

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a Ctrl-C pending since the start is dropped
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    tqdm.set_lock(threading.RLock())

    def progress(line: str) -> None:
        connection.send(("line", line))

    while True:
        try:
            task, args = connection.recv()
        except EOFError:  # the parent is done
            return
        try:
            end: tuple[str, Any] = ("value", _job(task, args, progress))
        except Exception as error:  # raised again in the parent, with this traceback as its cause
            end = _error_end(error)
        try:
            connection.send(end)
        except Exception as error:  # a value or an exception that pickle cannot carry
            connection.send(_error_end(RuntimeError(f"Error sending result: '{end[1]!r}'. Reason: '{error!r}'")))


def _paper(paper: str, folder: Path, fast: bool, progress: Callable[[str], Any]
           ) -> tuple[list[Any], list[str], list[str]]:
    """One paper: its script, then its study beyond the paper, into ``folder``; its rows, and its report's LaTeX
    and figures."""
    # lazy: armlab --help loads armlab.papers.reproduce but not this (start-up time)
    from armlab.papers import beyond
    from armlab.papers.report import report_images, report_math

    rows = _script(paper).run(folder, fast=fast, progress=progress)
    beyond.run(paper, folder, fast=fast, progress=progress)
    return rows, report_math(folder), report_images(folder)


def _math(pieces: Sequence[str], progress: Callable[[str], Any]) -> dict[str, str]:
    """LaTeX pieces rendered as the report shows them (LaTeX → HTML)."""
    # lazy: armlab --help loads armlab.papers.reproduce but not this (start-up time)
    from armlab.papers.math_html import latex_html

    return {piece: latex_html(piece) for piece in pieces}


def _images(out: Path, images: Sequence[str], progress: Callable[[str], Any]) -> dict[str, str]:
    """Figures embedded as the report embeds them (path relative to ``out`` → data URI)."""
    # lazy: armlab --help loads armlab.papers.reproduce but not this (start-up time)
    from armlab.papers.report import embed_images

    return embed_images(out, images)


@contextmanager
def _ctrl_c_blocked() -> Iterator[None]:
    """SIGINT blocked in this thread meanwhile: a process started meanwhile inherits the block, so a Ctrl-C while
    it imports (seconds, before :func:`_worker` ignores it) raises no KeyboardInterrupt there, with its traceback;
    here it arrives when the block ends. (Python's resource tracker starts its process the same way.)"""
    blocked = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, blocked)


class _Pool:
    """``jobs`` worker processes (spawned: no state of the caller's is inherited) that run :func:`_job` tasks,
    their progress lines passed to ``progress`` as they come; with ``jobs == 1`` the tasks run in this process.

    Each worker has a pipe of its own and shares no lock with the others, so a worker that ends at any moment
    (the process group's SIGTERM, a kill) blocks nothing: the pool sees its pipe close, and raises
    ``ChildProcessError`` if it was not stopping anyway. Leaving the ``with`` block by an exception (a task's,
    or a stop signal) terminates the workers at once, so the caller's temporary output is removed only after no
    worker writes into it any more.
    """

    def __init__(self, jobs: int, progress: Callable[[str], Any]) -> None:
        self.jobs, self.progress = jobs, progress
        self.workers: dict[Connection, Any] = {}  # our end of a worker's pipe → its process
        self.idle: list[Connection] = []
        self.running: dict[Connection, Any] = {}  # a busy worker → the key of its task
        self.queued: deque[tuple[Any, Callable[..., Any], tuple]] = deque()  # tasks waiting for a worker
        self.ended: dict[Any, tuple[Any, list]] = {}  # tasks ended, not yet yielded: key → (value, warnings)

    def __enter__(self) -> _Pool:
        if self.jobs > 1:
            try:
                self._start()
            except BaseException as error:
                self._end(stop=True)
                if not isinstance(error, OSError):
                    raise
                self.progress(f"worker processes are not available here ({error}); working in this process")
        return self

    def _start(self) -> None:
        context = multiprocessing.get_context("spawn")
        saved = {name: os.environ.get(name) for name in ONE_THREAD}
        os.environ.update(ONE_THREAD)  # the workers' environment (a spawned process copies it when it starts)
        try:
            # Started before the workers (a spawned process needs it): its start ends any block of SIGINT.
            resource_tracker.ensure_running()
            for _ in range(self.jobs):
                ours, theirs = context.Pipe()
                process = context.Process(target=_worker, args=(theirs,), daemon=True)
                with signals_held(), _ctrl_c_blocked():  # a stop signal waits until the worker is known here
                    process.start()
                    self.workers[ours] = process
                    theirs.close()  # the worker's copy is the only one left: its end closes the pipe
                self.idle.append(ours)
        finally:
            for name, value in saved.items():
                if value is None:
                    os.environ.pop(name)
                else:
                    os.environ[name] = value

    def __exit__(self, *exc: Any) -> None:
        self._end(stop=exc[0] is not None)

    def _end(self, stop: bool) -> None:
        """Close the pipes (an idle worker then returns) and wait for the workers; ``stop``: terminate them first
        (those a signal to the process group has not ended already)."""
        for connection, process in self.workers.items():
            connection.close()
            if stop:
                process.terminate()
        for process in self.workers.values():
            process.join()
        self.workers.clear()
        self.idle.clear()
        self.running.clear()

    def submit(self, key: Any, task: Callable[..., Any], *args: Any) -> None:
        """Start ``task(*args, progress=…)`` (once a worker is free); :meth:`done` yields ``(key, value)`` when it
        ends."""
        if not self.workers:
            self.ended[key] = _job(task, args, self.progress)
        else:
            self.queued.append((key, task, args))
            self._dispatch()

    def _dispatch(self) -> None:
        """The queued tasks to the idle workers, in order."""
        while self.idle and self.queued:
            key, task, args = self.queued.popleft()
            connection = self.idle.pop()
            connection.send((task, args))
            self.running[connection] = key

    def _receive(self) -> None:
        """Wait for the workers' next messages: progress lines passed on, ended tasks kept, a task's error raised;
        a worker that ended is a ``ChildProcessError``."""
        ready = wait(list(self.workers))
        for connection in [c for c in self.workers if c in ready]:  # wait gives back the objects it was given
            try:
                kind, content = connection.recv()
            except EOFError:
                raise ChildProcessError(self._lost(connection)) from None
            if kind == "line":
                self.progress(content)
                continue
            key = self.running.pop(connection)
            self.idle.append(connection)
            if kind == "error":
                error, remote = content
                error.__cause__ = WorkerTracebackError(remote)
                raise error
            self.ended[key] = content
        self._dispatch()

    def _lost(self, connection: Connection) -> str:
        """Why the worker at ``connection``'s other end ended (its pipe closed)."""
        process = self.workers[connection]
        process.join()
        code = process.exitcode
        how = f"killed by {signal.Signals(-code).name}" if code < 0 else f"exit code {code}"
        return f"a reproduce worker process (pid {process.pid}) ended unexpectedly ({how})"

    def done(self) -> Iterator[tuple[Any, Any]]:
        """``(key, value)`` of each task as it ends (tasks submitted meanwhile included), after the progress
        lines it printed; a task's exception is raised here, and the warnings it raised are raised again."""
        while self.ended or self.running:
            if not self.ended:
                self._receive()
                continue
            key = next(iter(self.ended))
            value, caught = self.ended.pop(key)
            for category, message in caught:
                warnings.warn(message, category, stacklevel=2)
            yield key, value


def reproduce(
    out: Path, papers: Sequence[str] = PAPERS, fast: bool = False, progress: Callable[[str], Any] = print,
    jobs: int | None = None,
) -> ReproduceResult:
    """Run the paper scripts into ``out`` (complete or nothing) and write the report; see the module doc.

    The papers run in ``jobs`` worker processes (default :func:`default_jobs`; at most :data:`MAX_JOBS`), the
    longest first; the workers also render the report's mathematics and embed its figures, as each paper ends.
    Papers not in ``papers`` that an earlier reproduction in ``out`` holds are kept (copied into the new output,
    their rows read back), so reproducing one paper updates it and the report alone.

    Called from a script of your own, call it under ``if __name__ == "__main__":`` (as for any
    :mod:`multiprocessing` pool: a spawned worker imports the script again), or pass ``jobs=1``.
    """
    # lazy: armlab --help loads armlab.papers.reproduce but not this (start-up time)
    from armlab.papers.paper_output import load_rows
    from armlab.papers.report import write_report
    from armlab.presentation.graphviz import require_dot

    start = time.perf_counter()
    for paper in papers:
        select_papers(paper)
    if jobs is not None and jobs < 1:
        raise ValueError(f"--jobs {jobs} is not allowed; allowed: 1 or more worker processes")
    require_dot()  # the Systems diagrams need it: say so before any work
    folder = output_folder(out)
    earlier = {p: load_rows(folder.out / p) for p in PAPERS if p not in papers} if folder.out.is_dir() else {}
    kept = {paper: rows for paper, rows in earlier.items() if rows is not None}
    jobs = min(jobs, MAX_JOBS) if jobs else default_jobs()
    with folder as tmp, _Pool(jobs, progress) as pool:
        for paper in (p for p in LONGEST_FIRST if p in papers):
            pool.submit(paper, _paper, paper, tmp / paper, fast)
        rows: dict[str, list[Any]] = {}
        for paper in (p for p in PAPERS if p in kept):
            shutil.copytree(folder.out / paper, tmp / paper)
            rows[paper] = kept[paper]
            progress(f"[{paper}] kept from the earlier reproduction in {folder.out}")
        math: dict[str, str] = {}
        images: dict[str, str] = {}
        tasks = MATH_TASKS if jobs > 1 else 1
        for key, value in pool.done():
            if key in PAPERS:  # a paper ended: its mathematics (longest first, spread over the workers), its figures
                rows[key], pieces, pngs = value
                pieces = sorted(pieces, key=len, reverse=True)
                for k in range(tasks):
                    pool.submit(("math", key, k), _math, pieces[k::tasks])
                pool.submit(("images", key), _images, tmp, pngs)
            else:
                (math if key[0] == "math" else images).update(value)
        (tmp / MARKER).write_text("armlab reproduce output; `armlab reproduce` may replace this folder\n")
        shown = [p for p in PAPERS if p in rows]
        all_rows = [row for p in shown for row in rows[p]]
        write_report(tmp, shown, all_rows, time.perf_counter() - start, math, images)
    return ReproduceResult(folder.out / "report.md", all_rows, verdict_counts(all_rows), time.perf_counter() - start)


def summary_line(result: ReproduceResult) -> str:
    """The final line: the report's path and the verdict counts."""
    c = result.counts
    return (f"report: {result.report}  ({len(result.rows)} rows: {c['matches']} matches, {c['differs']} differs, "
            f"{c['not reproducible']} not reproducible; {result.elapsed:.1f} s)")


def reproduce_alone(paper: str, run: Callable[..., list], out: str | Path, fast: bool = False) -> tuple[Path, list]:
    """One paper script's ``run`` alone into ``out`` (complete or nothing, see :func:`output_folder`), marked with
    :data:`MARKER` so that a later run may replace it; the output folder and the rows."""
    folder = output_folder(out)
    with folder as tmp:
        rows = run(tmp, fast=fast)
        (tmp / MARKER).write_text(f"armlab paper_{paper} output; it may be replaced by a later run\n")
    return folder.out, rows
