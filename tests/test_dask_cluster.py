"""Sweeps on real Dask clusters: a LocalCluster of 2 workers, and a `dask scheduler` with two `dask worker`
processes started here on 127.0.0.1 — the same results as in-process, even when a worker is killed mid-sweep."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from helpers import armlab_main, assert_same_objectives, objectives, rows, write_study

from armlab.analysis.study import evaluate, load_study
from armlab.analysis.sweep import RESULTS, run_sweep

DASK = str(Path(__file__).resolve().parents[1] / ".venv" / "bin" / "dask")
#: rr's workspace against its link lengths: 8 candidates of a fraction of a second each.
STUDY = {"arm": "rr", "vary": {"L1": {"from": 0.3, "to": 0.45, "steps": 4}, "L2": {"values": [0.2, 0.3]}},
         "evaluate": ["workspace_volume", "reach", "mean_manipulability"], "samples": 200000}
COLUMNS = ["workspace_volume", "reach", "mean_manipulability"]
#: The Dask config file the sweep's docstring gives for `dask worker`.
DASK_CONFIG = "distributed: {nanny: {pre-spawn-environ: {MALLOC_TRIM_THRESHOLD_: null}}}\n"


class Cluster:
    """A `dask scheduler` and `dask worker` processes on 127.0.0.1, each in its own process group."""

    def __init__(self, folder: Path) -> None:
        folder.mkdir(exist_ok=True)
        self.file = folder / "scheduler.json"
        self.folder = folder
        self.procs: list[subprocess.Popen] = []
        self.workers: list[subprocess.Popen] = []
        self.names: dict[int, str] = {}  # worker pid → its --name
        self.started = 0  # workers started so far
        self.procs.append(self._start([DASK, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                                       "--scheduler-file", str(self.file)], "scheduler.log"))
        deadline = time.monotonic() + 60
        while not (self.file.exists() and self.file.stat().st_size > 0):
            assert time.monotonic() < deadline, "the dask scheduler did not start"
            time.sleep(0.2)
        self.address = json.loads(self.file.read_text())["address"]
        assert self.address.startswith("tcp://127.0.0.1:")

    def _start(self, command: list[str], log: str) -> subprocess.Popen:
        """``command`` with the Dask config file armlab's sweep documents for hand-started workers."""
        config = self.folder / "dask-config"
        config.mkdir(exist_ok=True)
        (config / "armlab.yaml").write_text(DASK_CONFIG)
        handle = open(self.folder / log, "w")
        proc = subprocess.Popen(command, stdout=handle, stderr=subprocess.STDOUT, start_new_session=True,
                                cwd=self.folder, env={**os.environ, "DASK_CONFIG": str(config)})
        handle.close()
        return proc

    def add_worker(self, name: str) -> subprocess.Popen:
        proc = self._start([DASK, "worker", "--scheduler-file", str(self.file), "--nthreads", "1", "--no-dashboard",
                            "--host", "127.0.0.1", "--name", name], f"{name}.log")
        self.procs.append(proc)
        self.workers.append(proc)
        self.names[proc.pid] = name
        self.started += 1
        return proc

    def replace_dead_workers(self) -> None:
        """A new worker for each that ended, and wait until the scheduler lists exactly the live ones."""
        from distributed import Client

        for dead in [w for w in self.workers if w.poll() is not None]:
            self.workers.remove(dead)
            self.procs.remove(dead)
            self.add_worker(f"w{self.started + 1}")
        names = {self.names[w.pid] for w in self.workers}
        deadline = time.monotonic() + 120
        with Client(self.address, timeout="30s") as client:
            while {w["name"] for w in client.scheduler_info(n_workers=-1)["workers"].values()} != names:
                assert time.monotonic() < deadline, "the replaced dask worker did not join"
                time.sleep(0.1)

    def wait_for_workers(self, n: int) -> None:
        from distributed import Client

        with Client(self.address, timeout="30s") as client:
            client.wait_for_workers(n, timeout=120)

    @staticmethod
    def kill(proc: subprocess.Popen) -> None:
        """SIGKILL the process group (a `dask worker` is a nanny and its worker process)."""
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)

    def close(self) -> None:
        for proc in reversed(self.procs):
            try:
                self.kill(proc)
            except ProcessLookupError:
                pass


@pytest.fixture(scope="module")
def shared_cluster(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Cluster]:
    """One `dask scheduler` with two `dask worker` processes for this module's tests (each start costs seconds)."""
    c = Cluster(tmp_path_factory.mktemp("cluster"))
    try:
        c.add_worker("w1")
        c.add_worker("w2")
        c.wait_for_workers(2)
        yield c
    finally:
        c.close()


@pytest.fixture
def cluster(shared_cluster: Cluster) -> Iterator[Cluster]:
    """The module's cluster as a fresh one would be: the scheduler and two live workers, all running (a test may kill a
    worker: the next one finds it replaced)."""
    c = shared_cluster
    assert c.procs[0].poll() is None, "the dask scheduler ended"
    c.replace_dead_workers()
    yield c


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> dict[int, list[float]]:
    """Every candidate evaluated in this process, without Dask."""
    folder = tmp_path_factory.mktemp("reference")
    study = load_study(write_study(folder, STUDY))
    return {i: [evaluate(study, values)[c] for c in COLUMNS] for i, values in enumerate(study.candidates)}


def test_local_cluster_of_two_workers(tmp_path: Path, reference: dict[int, list[float]]) -> None:
    out = tmp_path / "out"
    run = armlab_main("sweep", str(write_study(tmp_path, STUDY)), "--out", str(out), "--workers", "2")
    assert run.returncode == 0, run.stderr
    assert "8 candidates: 0 done before, 8 computed, 0 failed" in run.stdout
    assert_same_objectives(objectives(out, COLUMNS), reference)
    workers = {r["worker"] for r in rows(out).values()}
    assert len(workers) == 2 and all(w.startswith("tcp://127.0.0.1:") for w in workers)
    record = json.loads((out / "study.json").read_text())
    assert record["runs"][0]["scheduler"] == "LocalCluster (2 workers)"


def test_external_scheduler_gives_the_local_results(tmp_path: Path, cluster: Cluster,
                                                    reference: dict[int, list[float]]) -> None:
    out = tmp_path / "out"
    run = armlab_main("sweep", str(write_study(tmp_path, STUDY)), "--out", str(out), "--scheduler", cluster.address)
    assert run.returncode == 0, run.stderr
    assert_same_objectives(objectives(out, COLUMNS), reference)
    assert len({r["worker"] for r in rows(out).values()}) == 2
    assert json.loads((out / "study.json").read_text())["runs"][0]["scheduler"] == cluster.address
    assert all(proc.poll() is None for proc in cluster.procs)  # armlab leaves the user's cluster running


def test_a_killed_worker_s_tasks_are_rerun(tmp_path: Path, cluster: Cluster,
                                           reference: dict[int, list[float]]) -> None:
    out = tmp_path / "out"
    study = write_study(tmp_path, STUDY)
    result: dict = {}
    thread = threading.Thread(target=lambda: result.update(done=run_sweep(study, out, scheduler=cluster.address,
                                                                          progress=False)))
    thread.start()
    deadline = time.monotonic() + 300
    while not ((out / RESULTS).exists() and (out / RESULTS).read_text().count("\n") >= 3):  # header + 2 rows
        assert time.monotonic() < deadline and thread.is_alive(), "the sweep made no progress"
        time.sleep(0.05)
    cluster.kill(cluster.workers[0])
    assert (out / RESULTS).read_text().count("\n") - 1 < 8  # killed mid-sweep: candidates were left to do
    thread.join(timeout=600)
    assert not thread.is_alive()
    done = result["done"]
    assert done.failed == [] and done.computed == 8
    assert_same_objectives(objectives(out, COLUMNS), reference)
    assert rows(out).keys() == reference.keys()


def test_workers_keep_glibc_s_adaptive_malloc(cluster: Cluster) -> None:
    """Neither the sweep's local workers nor `dask worker` started with the documented config get Dask's
    MALLOC_TRIM_THRESHOLD_ (it turns off glibc's adaptive mmap threshold: page faults nearly doubled a workspace
    candidate's CPU time); the rest of Dask's worker environment (one BLAS thread) stays."""
    from contextlib import ExitStack

    from distributed import Client

    from armlab.analysis.sweep import dask_client

    def environment() -> tuple[str | None, str | None]:
        return os.environ.get("MALLOC_TRIM_THRESHOLD_"), os.environ.get("OPENBLAS_NUM_THREADS")

    with ExitStack() as stack:
        local = dask_client(stack, 1, None)
        assert list(local.run(environment).values()) == [(None, "1")]
    with Client(cluster.address) as client:
        assert list(client.run(environment).values()) == [(None, "1")] * 2


def test_a_scheduler_without_workers_is_a_bounded_wait_that_makes_nothing(tmp_path: Path, monkeypatch) -> None:
    """A live `dask scheduler` no worker ever joins: one line after WORKER_WAIT seconds, and no --out folder."""
    monkeypatch.setattr("armlab.analysis.sweep.WORKER_WAIT", 1.5)
    lonely = Cluster(tmp_path / "lonely")
    try:
        began = time.monotonic()
        with pytest.raises(ValueError, match=r"no workers joined in 1.5 s; start one with `dask worker tcp://"):
            run_sweep(write_study(tmp_path, STUDY), tmp_path / "sw", scheduler=lonely.address)
        assert time.monotonic() - began < 30
        assert not (tmp_path / "sw").exists()
    finally:
        lonely.close()


def test_a_killed_scheduler_ends_the_sweep_in_one_line(tmp_path: Path) -> None:
    """Issue 36 item 20: the scheduler killed mid-sweep gave 123 lines of distributed's tracebacks (distributed's
    logging, set up when it is imported, undid the sweep's quieting) and a failure line per candidate left. Now: one
    line naming the scheduler, exit 2, the rows computed kept (the same command goes on)."""
    study = str(Path(__file__).resolve().parents[1] / "analysis" / "studies" / "urm6_theta3_theta5.json")
    lost = Cluster(tmp_path / "lost")
    out = tmp_path / "sw"
    try:
        lost.add_worker("w1")
        lost.wait_for_workers(1)
        process = subprocess.Popen([sys.executable, "-m", "armlab", "sweep", study, "--out", str(out), "--scheduler",
                                    lost.address], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                   cwd=tmp_path)
        deadline = time.monotonic() + 300
        while not ((out / RESULTS).exists() and (out / RESULTS).read_text().count("\n") >= 3):  # header + 2 rows
            assert time.monotonic() < deadline and process.poll() is None, "the sweep made no progress"
            time.sleep(0.05)
        lost.kill(lost.procs[0])
        _, err = process.communicate(timeout=300)
    finally:
        lost.close()
    assert process.returncode == 2, err[-3000:]
    assert err.count("\n") == 1 and err.startswith(f"armlab: error: --scheduler {lost.address}: the connection to "
                                                   "the scheduler was lost after "), err[-3000:]
    assert (out / RESULTS).read_text().count("\n") >= 3  # the rows computed are kept
