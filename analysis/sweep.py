"""``armlab sweep``: a design study's candidates evaluated on a Dask cluster, resumably.

:func:`run_sweep` checks the study (:func:`armlab.analysis.study.load_study`) and the output folder
before any work, then submits every candidate not yet in ``DIR/results.csv`` to a Dask cluster — by
default a ``LocalCluster`` of worker processes (one thread each, on 127.0.0.1, no dashboard) started
and closed here; with ``scheduler="tcp://HOST:PORT"`` an existing cluster (``dask scheduler`` /
``dask worker``: each worker needs the same armlab installed, and the files a study names — a user
arm's ``.urdf``/``.csv``, a ``segments`` file — at the same paths; their nannies should not set Dask's
``MALLOC_TRIM_THRESHOLD_``, which nearly doubles a workspace candidate's CPU time: a Dask config file, e.g.
``~/.config/dask/armlab.yaml`` holding ``distributed: {nanny: {pre-spawn-environ: {MALLOC_TRIM_THRESHOLD_: null}}}``,
does that for ``dask worker``, as :func:`run_sweep` does for its local cluster). Results are appended to
``results.csv`` as they arrive, one whole line per write, flushed and fsynced, so an interrupted
sweep loses nothing already written and never leaves half a row; a rerun into the same folder
computes only the missing candidates (``study.json`` is written when the folder is made, so a stopped sweep
resumes too). Stopped by Ctrl-C or SIGTERM, it closes the cluster and removes the cluster's private scratch folder
(its workers' stderr included: no worker prints a traceback). A candidate that raises is reported with its
parameters and the error and the others go on; a worker that dies has its tasks rerun by Dask. At the end
``study.json`` (the study as run, the software versions, every run's counts) and the plots
(:mod:`armlab.analysis.plots`) are (re)written.

Exit status of ``armlab sweep``: 0 when every candidate is in ``results.csv``; 2 for a bad study or
option (nothing computed); :data:`EXIT_FAILED` + k when k candidates failed (capped at k = 100).
"""

from __future__ import annotations

import csv
import fcntl
import io
import json
import logging
import os
import shutil
import sys
import tempfile
import time
import uuid
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from armlab.files import csv_cell, signals_held, write_file
from armlab.values import shown

if TYPE_CHECKING:
    from armlab.analysis.study import Study

__all__ = ["EXIT_FAILED", "RESULTS", "STUDY", "WORKERS_PER_CORE", "WORKER_WAIT", "SweepResult", "check_options",
           "read_results", "run_sweep"]

RESULTS = "results.csv"
STUDY = "study.json"
#: ``armlab sweep`` exits with EXIT_FAILED + (number of failed candidates, at most 100).
EXIT_FAILED = 10
#: How long a sweep on an existing scheduler waits for its first worker to join (s).
WORKER_WAIT = 30.0
#: Local worker processes at most, per core this process may use.
WORKERS_PER_CORE = 4
#: The scheduler address, as the errors show it.
_EXAMPLE = "e.g. tcp://127.0.0.1:8786"


@dataclass
class SweepResult:
    """What one :func:`run_sweep` did: candidates in the study, already done before, computed, failed."""

    out: Path
    total: int
    done_before: int
    computed: int
    failed: list[dict[str, Any]] = field(default_factory=list)
    wall_time: float = 0.0
    plots: list[str] = field(default_factory=list)


def versions() -> dict[str, str]:
    """Versions of the software a sweep ran on."""
    # lazy: armlab --help loads this module but not importlib.metadata (start-up time)
    from importlib.metadata import PackageNotFoundError, version

    out = {"python": sys.version.split()[0]}
    for name in ("armlab", "drake", "numpy", "dask", "distributed"):
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            out[name] = "not installed"
    return out


# ------------------------------------------------------------------------------------ results.csv
def _line(values: list[Any]) -> str:
    """One results.csv row, cells as every CSV armlab writes (:func:`armlab.files.csv_cell`)."""
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow([csv_cell(v) for v in values])
    return buffer.getvalue()


def read_results(path: Path, columns: list[str]) -> dict[int, list[str]]:
    """The rows of ``results.csv`` by candidate index. A last line without its newline (a write cut
    short) is removed from the file. ``ValueError`` if the header is not ``columns`` (another study)."""
    with open(path, "rb") as handle:
        data = handle.read()
    if data and not data.endswith(b"\n"):
        cut = data.rfind(b"\n") + 1
        with open(path, "r+b") as handle:
            handle.truncate(cut)
            os.fsync(handle.fileno())
        data = data[:cut]
    rows = list(csv.reader(io.StringIO(data.decode())))
    if not rows or rows[0] != columns:
        raise ValueError(f"{path}: its columns are not this study's ({', '.join(columns)}); give another --out")
    out = {}
    for row in rows[1:]:
        if len(row) != len(columns) or not row[0].isdigit():
            raise ValueError(f"{path}: a row is not one of this study's: {','.join(row)[:80]}")
        out[int(row[0])] = row
    return out


class _Appender:
    """``results.csv`` opened for appending: each row one ``write`` of a whole line, flushed and fsynced."""

    def __init__(self, path: Path) -> None:
        self.fd = os.open(path, os.O_WRONLY | os.O_APPEND)

    def append(self, values: list[Any]) -> None:
        data = _line(values).encode()
        if os.write(self.fd, data) != len(data):
            raise OSError(f"short write to {RESULTS}")
        os.fsync(self.fd)

    def close(self) -> None:
        os.close(self.fd)


def _existing(out: Path, study: Study, study_json: dict[str, Any]) -> dict[int, list[str]] | None:
    """The rows already done when ``out`` is this study's earlier sweep, None when it is new or empty; a
    ``ValueError`` for anything else. Reads only: nothing is made."""
    results, record = out / RESULTS, out / STUDY
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out}: exists and is not a folder")
    if not (out.is_dir() and any(out.iterdir())):
        return None
    if not record.is_file():
        raise ValueError(f"--out {out}: exists and is not an armlab sweep folder (no {RESULTS} and {STUDY}); "
                         "give a new or empty folder")
    try:
        earlier = json.loads(record.read_text())["study"]
    except (OSError, ValueError, KeyError, TypeError):
        raise ValueError(f"--out {out}: its {STUDY} cannot be read; give a new or empty folder") from None
    if earlier != study_json:
        raise ValueError(f"--out {out}: holds a different study; give another --out (or the same study file)")
    # study.json is written first (_prepare): a sweep stopped before its results.csv was made has none done
    return read_results(results, study.columns) if results.is_file() else {}


def _prepare(out: Path, study: Study, study_json: dict[str, Any]) -> dict[int, list[str]]:
    """Check ``out`` (new, empty, or this study's earlier sweep), start it if new; the rows already done."""
    done = _existing(out, study, study_json)
    if done is None or not (out / RESULTS).is_file():
        _record(out, study, study_json, {})  # first: the folder is this study's from the start, a stopped sweep resumes
        write_file(out / RESULTS, _line(study.columns))
    return done or {}


def _lock(stack: ExitStack, out: Path) -> None:
    """Make ``out`` if need be and hold an exclusive lock on it (``flock`` on the folder itself, no lock file)
    until ``stack`` closes; the kernel releases it however the process ends. ``ValueError`` when another sweep
    holds it."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        fd = os.open(out, os.O_RDONLY | os.O_DIRECTORY)
    except OSError as error:
        raise ValueError(f"--out {out}: cannot write in it: {error.strerror or error}") from None
    stack.callback(os.close, fd)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        raise ValueError(f"--out {out}: another armlab sweep is writing into it; wait until it ends or give "
                         "another --out") from None


def check_options(workers: int | None, scheduler: str | None) -> None:
    """``ValueError`` for a bad ``--workers`` (a whole number 1 … :data:`WORKERS_PER_CORE` × cores) or
    ``--scheduler`` (``tcp://HOST:PORT``, or ``tls://HOST:PORT`` with Dask's TLS settings), or both given."""
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ValueError(f"--workers {shown(workers)}: give a whole number ≥ 1")
    cap = WORKERS_PER_CORE * default_workers()
    if workers is not None and workers > cap:
        raise ValueError(f"--workers {workers}: at most {cap} ({WORKERS_PER_CORE} per core this process may use: "
                         "each worker is a process)")
    if workers is not None and scheduler is not None:
        raise ValueError("--workers sets the local cluster's size: do not combine it with --scheduler")
    if scheduler is None:
        return
    scheme, sep, rest = scheduler.partition("://")
    if sep and scheme in ("inproc", "ucx"):
        why = "lives inside one process" if scheme == "inproc" else "is not available in this Dask"
        raise ValueError(f"--scheduler {shown(scheduler)}: {scheme}:// {why}; give tcp://HOST:PORT")
    if not sep or scheme not in ("tcp", "tls"):
        raise ValueError(f"--scheduler {shown(scheduler)}: give the scheduler's address, {_EXAMPLE}")
    host, colon, port = rest.rpartition(":")
    if not (colon and host and port.isdigit() and 1 <= int(port) <= 65535):
        raise ValueError(f"--scheduler {shown(scheduler)}: give HOST:PORT (a port 1 … 65535) after {scheme}://, "
                         f"{_EXAMPLE}")
    if scheme == "tls":
        from distributed.security import Security

        if Security().get_connection_args("client").get("ssl_context") is None:
            raise ValueError(f"--scheduler {shown(scheduler)}: tls:// needs Dask's TLS settings (distributed.comm."
                             "tls.ca-file, .client.cert and .client.key in Dask's configuration)")


def _record(out: Path, study: Study, study_json: dict[str, Any], run: dict[str, Any]) -> None:
    """(Re)write ``study.json``: the study as run, units, versions, and every run so far."""
    path = out / STUDY
    runs = []
    if path.is_file():
        try:
            runs = json.loads(path.read_text()).get("runs", [])
        except (OSError, ValueError):
            runs = []
    record = {"study": study_json, "candidates": len(study.candidates), "columns": study.columns,
              "units": study.units(), "versions": versions(), "runs": [*runs, run] if run else runs}
    write_file(path, json.dumps(record, indent=2, ensure_ascii=False) + "\n")


# ---------------------------------------------------------------------------------------- the engine
def dask_client(stack: ExitStack, workers: int | None, scheduler: str | None) -> Any:
    """A Dask client of the cluster at ``scheduler``, or of a new ``LocalCluster`` whose scheduler and workers keep
    their scratch files in a private temporary folder (made by ``mkdtemp``, mode 0700, not the shared
    ``$TMPDIR/dask-scratch-space``); ``stack`` closes them and removes the folder on every exit path."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as error:
            raise ValueError(f"--scheduler {scheduler}: cannot connect: {error}") from None
        stack.callback(client.close)
        try:
            client.wait_for_workers(1, timeout=WORKER_WAIT)
        except TimeoutError:
            raise ValueError(f"--scheduler {scheduler}: no workers joined in {WORKER_WAIT:g} s; start one with "
                             f"`dask worker {scheduler}`") from None
        return client
    scratch = tempfile.mkdtemp(prefix="armlab-dask-")
    stack.callback(shutil.rmtree, scratch, ignore_errors=True)
    # The scheduler's scratch; and the workers start without Dask's MALLOC_TRIM_THRESHOLD_: setting it turns off glibc's
    # adaptive mmap threshold, so each large numpy array was a fresh mmap, and its page faults doubled a workspace
    # candidate's CPU time (half of it in the kernel).
    stack.enter_context(dask.config.set({"temporary-directory": scratch,
                                         "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}))
    # The workers write their stderr to a log in the scratch folder, as long as the cluster lives (the log is
    # removed with the folder): Ctrl-C reaches the terminal's whole process group, and each worker would print its
    # KeyboardInterrupt's traceback; this process stops and closes them. A worker the nanny starts again after the
    # signal killed it (before the close reached the nanny) inherits this process' file descriptor 2 then, so it
    # stays on the log until the cluster is closed (``stack`` undoes it after closing the cluster); this process'
    # own messages go to its stderr through ``sys.stderr``, kept on the real one meanwhile.
    stack.enter_context(_stderr_to(os.path.join(scratch, "workers.log")))
    # A stop signal during the start waits until the cluster is on ``stack`` (else Dask's atexit hook meets a
    # half-started cluster).
    with signals_held():
        # No dashboard; the scheduler's own HTTP endpoint (health, metrics) on a free port of 127.0.0.1, not 8787.
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address="127.0.0.1:0", scheduler_kwargs={"dashboard": False},
                               local_directory=scratch, silence_logs=logging.CRITICAL)
        stack.callback(cluster.close)
        client = Client(cluster)
        stack.callback(client.close)
    return client


@contextmanager
def _stderr_to(path: str) -> Iterator[None]:
    """File descriptor 2 writes to the file ``path`` (made private, mode 0600) meanwhile: the processes started
    meanwhile keep it as their stderr, and so do the log handlers that hold the original ``sys.stderr`` object
    (distributed's). ``sys.stderr`` itself is a new stream on the original stderr meanwhile: what this process
    prints (a failed candidate's line, the progress bar, an error) still reaches the user."""
    stream = sys.stderr
    stream.flush()
    saved = os.dup(2)
    log = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_APPEND, 0o600)
    kept = None
    try:
        kept = open(os.dup(saved), "w", encoding=getattr(stream, "encoding", None) or "utf-8",
                    errors=getattr(stream, "errors", None) or "backslashreplace", buffering=1)
        os.dup2(log, 2)
        sys.stderr = kept
        yield
    finally:
        if kept is not None:
            kept.flush()
            if sys.stderr is kept:
                sys.stderr = stream
        stream.flush()
        os.dup2(saved, 2)
        os.close(saved)
        os.close(log)
        if kept is not None:
            kept.close()


def default_workers() -> int:
    """Local workers by default: one per core this process may use (also ``armlab reproduce``'s default)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def run_sweep(
    study_file: str | Path,
    out: str | Path,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool | None = None,
    report: Any = None,
) -> SweepResult:
    """Evaluate the study in ``study_file`` into ``out`` (see the module docstring).

    ``workers``: local worker processes (default :func:`default_workers`; not with ``scheduler``);
    ``progress``: a progress bar on stderr (default: when stderr is a terminal); ``report(line)``
    receives the one-line report of each failed candidate (default: stderr).
    """
    # lazy: armlab --help loads armlab.analysis.sweep but not this (start-up time)
    from armlab.analysis.plots import write_plots
    from armlab.analysis.study import load_study

    began = time.perf_counter()
    check_options(workers, scheduler)
    study = load_study(study_file)
    out = Path(out)
    study_json = study.to_json()
    candidates = study.candidates
    result = SweepResult(out, len(candidates), 0, 0)
    report = report or (lambda line: print(line, file=sys.stderr, flush=True))
    run: dict[str, Any] = {"started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "computed": 0,
                           "failed": []}
    with ExitStack() as stack:
        stack.enter_context(_quiet_distributed())
        locked = out.is_dir()
        if locked:  # an existing folder is locked before it is read (another sweep may be starting in it)
            _lock(stack, out)
        earlier = _existing(out, study, study_json)  # checked before anything is made
        # An existing scheduler is reached (and has a worker) before a new folder is made.
        client = dask_client(stack, None, scheduler) if scheduler is not None and len(earlier or ()) < len(
            candidates) else None
        if not locked:
            _lock(stack, out)
        done = _prepare(out, study, study_json)  # again, under the lock: another sweep may have just ended
        for index, row in done.items():
            if index >= len(candidates) or [float(x) for x in row[1:1 + len(study.vary)]] != list(candidates[index]):
                raise ValueError(f"--out {out}: {RESULTS} row {index} is not this study's candidate {index}")
        todo = [i for i in range(len(candidates)) if i not in done]
        result.done_before = len(done)
        if todo:
            run = _compute(study, candidates, todo, out, client, scheduler, workers, progress, report, result)
        result.wall_time = time.perf_counter() - began
        run = run | {"wall_time_s": result.wall_time}
        with signals_held():  # a stop signal now waits for study.json and the plots to be written, all of them
            _record(out, study, study_json, run)
            rows = read_results(out / RESULTS, study.columns)
            result.plots = write_plots(study, rows, out)
    return result


#: The loggers distributed gives its own stream handler (``distributed.config``, its default logging set-up), and
#: asyncio's (an event loop's "Task exception was never retrieved" goes to Python's last-resort handler on stderr).
_DASK_LOGGERS = ("distributed", "distributed.client", "distributed.gc", "bokeh", "tornado", "tornado.application",
                 "asyncio")


@contextmanager
def _quiet_distributed() -> Iterator[None]:
    """distributed's own log lines (a lost scheduler's reconnect traceback, a closed comm's) are not shown
    meanwhile: the sweep reports what matters itself, in one line.

    Not by a level on the ``distributed`` logger alone: its children with their own level (``distributed.client``:
    warning) pass their records on to its handler whatever its level, and ``silence_logging_cmgr`` (a cluster's,
    a worker's) sets its handlers' levels back when it closes. A filter on each of those loggers' handlers drops
    every record, and each logger is set above critical, while this lasts. distributed is imported first: its import
    sets those levels and handlers up (a level set before it would be undone, and no handler would be seen)."""
    import distributed  # noqa: F401  # lazy: Dask; imported here for its logging set-up, before it is changed

    loggers = [logging.getLogger(name) for name in _DASK_LOGGERS]
    handlers = {handler for logger in loggers for handler in logger.handlers}
    levels = [(logger, logger.level) for logger in loggers]
    silent = logging.Filter("\0")  # no logger has this name: every record is dropped
    for handler in handlers:
        handler.addFilter(silent)
    for logger in loggers:
        logger.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        for logger, level in levels:
            logger.setLevel(level)
        for handler in handlers:
            handler.removeFilter(silent)


def _compute(study: Study, candidates: list[tuple[float, ...]], todo: list[int], out: Path, client: Any,
             scheduler: str | None, workers: int | None, progress: bool | None, report: Any,
             result: SweepResult) -> dict[str, Any]:
    """Submit ``todo`` to ``client``, connected to ``scheduler`` (None: a new local cluster of ``workers``), and
    append each result as it arrives; the run's record."""
    from distributed import as_completed
    from tqdm import tqdm

    # lazy: armlab --help loads armlab.analysis.sweep but not this (start-up time)
    from armlab.analysis.study import timed_evaluate

    started = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    with ExitStack() as stack:
        client = client or dask_client(stack, workers or (None if scheduler else default_workers()), scheduler)
        appender = _Appender(out / RESULTS)
        stack.callback(appender.close)
        bar = stack.enter_context(tqdm(total=len(todo), unit="candidate", file=sys.stderr, dynamic_ncols=True,
                                       disable=not (sys.stderr.isatty() if progress is None else progress)))
        n_workers = len(client.scheduler_info(n_workers=-1)["workers"])
        token = uuid.uuid4().hex[:8]  # a sweep's own keys: another sweep's results are never reused
        # The study (a few hundred bytes: the arm is a name or a path) travels inside each task. Not scattered: a
        # broadcast scatter's replication could meet a worker the stop signal's close had already removed, and the
        # scheduler printed a KeyError's traceback.
        futures = {client.submit(timed_evaluate, study, candidates[i], pure=False, key=f"candidate-{i}-{token}"): i
                   for i in todo}
        for future in as_completed(futures):
            index = futures[future]
            try:
                answer = future.result()
            except Exception as error:  # e.g. KilledWorker: the task killed every worker it ran on
                if client.status != "running" or "connection-lost" in str(error):
                    where = f"--scheduler {scheduler}" if scheduler else "the sweep's local cluster"
                    raise ValueError(f"{where}: the connection to the scheduler was lost after {result.computed} of "
                                     f"{len(todo)} candidates; the rows computed are kept in {out / RESULTS}: run the "
                                     "sweep again to go on") from None
                answer = {"error": " ".join(f"{type(error).__name__}: {error}".split()), "worker": ""}
            values = candidates[index]
            if "error" in answer:
                shown = ", ".join(f"{v.name} = {x:g}{' ' + v.unit if v.unit else ''}"
                                  for v, x in zip(study.vary, values, strict=True))
                line = f"candidate {index} ({shown}) failed on {answer['worker'] or 'a worker'}: {answer['error']}"
                (bar.write if not bar.disable else report)(line)
                result.failed.append({"candidate": index, "parameters": list(values), "error": answer["error"]})
            else:
                objectives = answer["objectives"]
                appender.append([index, *values, *(objectives[c] for c in study.objective_columns),
                                 answer["wall_time_s"], answer["worker"]])
                result.computed += 1
            bar.update(1)
    return {"started": started, "scheduler": scheduler or f"LocalCluster ({n_workers} workers)",
            "workers": n_workers, "computed": result.computed, "failed": result.failed}
