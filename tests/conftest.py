"""Shared fixtures: the paper arms, their Drake plants, random in-limit configurations."""

from __future__ import annotations

import contextlib
import fcntl
import functools
import io
import pickle
import subprocess
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from armlab.models import ARMS, get_arm
from armlab.models.arm import Arm

ARM_NAMES = list(ARMS)


@functools.cache
def arm_and_plant(name: str):
    """(arm, plant, context) for a paper arm with default parameters, built once per session."""
    arm = get_arm(name)
    plant = arm.make_plant()
    return arm, plant, plant.CreateDefaultContext()


def random_q(arm: Arm, rng: np.random.Generator, size: int) -> np.ndarray:
    """``size`` random configurations within the joint limits (unlimited joints: ±2π)."""
    return rng.uniform(*arm.limit_arrays(unlimited=2 * np.pi), size=(size, arm.n))


def armlab_main(*argv: str) -> subprocess.CompletedProcess:
    """``armlab ARGV`` run in this process: ``armlab.cli.main`` (what the console script and ``python -m armlab``
    call), its exit code, stdout and stderr (the real process's start and exit: test_cli_usage.py, test_signals.py).
    A Dask cluster's or a reproduction's worker processes are real all the same."""
    from armlab.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return subprocess.CompletedProcess(["armlab", *argv], code, out.getvalue(), err.getvalue())


@pytest.fixture(params=ARM_NAMES)
def arm_name(request) -> str:
    """Each paper arm's name in turn."""
    return request.param


@pytest.fixture
def rng() -> np.random.Generator:
    """A seeded generator: failures are reproducible."""
    return np.random.default_rng(20261123)


@pytest.fixture(scope="session")
def shared_root(tmp_path_factory, worker_id) -> Path:
    """A temporary folder all pytest-xdist workers of this session share (their own folders' parent)."""
    root = tmp_path_factory.getbasetemp()
    return root if worker_id == "master" else root.parent


@contextlib.contextmanager
def _locked(root: Path, name: str) -> Iterator[None]:
    """Hold the session-wide lock ``name``: one worker at a time makes a shared output."""
    with open(root / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield


@pytest.fixture(scope="session")
def reproduction(shared_root):
    """One fast ``armlab reproduce`` of every paper for the whole session: (output folder, result, progress lines).

    The most expensive fixture of the suite (a minute of CPU), so pytest-xdist's workers share it: the first
    to need it runs it under a file lock in the session's common temporary folder, the others wait for it and
    read the same result (pickled: the rows as ``reproduce`` returned them). Tests only read the folder; a test
    that changes a reproduction works on a copy.
    """
    from armlab.scripts.reproduce import reproduce

    out, saved = shared_root / "reproduction" / "out", shared_root / "reproduction" / "result.pickle"
    with _locked(shared_root, "reproduction"):
        if not saved.exists():
            lines: list[str] = []
            result = reproduce(out, fast=True, progress=lines.append, jobs=2)  # workers, whatever the CPUs
            saved.write_bytes(pickle.dumps((result, lines)))
    result, lines = pickle.loads(saved.read_bytes())
    return out, result, lines


@pytest.fixture(scope="session")
def simulated(shared_root):
    """``simulated(*argv)``: the output folder of ``armlab simulate *argv --out DIR``, run once per session (shared
    by the workers, like :func:`reproduction`) for the tests that only read what it wrote; it must exit 0."""
    from armlab.cli import main

    def run(*argv: str) -> Path:
        key = "_".join(argv)
        out = shared_root / "simulated" / key
        with _locked(shared_root, f"simulated-{key}"):
            if not (out / "summary.json").exists():
                assert main(["simulate", *argv, "--out", str(out)]) == 0, argv
        return out

    return run
