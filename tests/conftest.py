"""Shared fixtures (the helpers test modules import are in helpers.py): each paper arm, a seeded generator, the
session's shared outputs, the arms with masses, a private TMPDIR."""

from __future__ import annotations

import contextlib
import fcntl
import functools
import pickle
import tempfile
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from helpers import ARM_NAMES, arm_and_plant, data

from armlab.models import get_arm


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
    from armlab.papers.reproduce import reproduce

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


@functools.cache
def _dynamic_user_arm(kind: str, folder: str):
    """The user arm with masses ``kind`` ("dh": tests/data/dh_with_masses.csv, a standard-convention DH table with a
    prismatic joint, off-axis centres and products of inertia; "urdf": tests/data/oblique.urdf), from ``folder``."""
    path = Path(folder) / ("oblique.urdf" if kind == "urdf" else "dh_masses.csv")
    path.write_text(data("oblique.urdf" if kind == "urdf" else "dh_with_masses.csv"))
    return get_arm(str(path))


@pytest.fixture(params=ARM_NAMES + ["dh", "urdf"])
def dynamic_arm(request, tmp_path_factory):
    """Each paper arm, a DH arm with masses and a user URDF arm with several welded bodies."""
    if request.param in ARM_NAMES:
        return arm_and_plant(request.param)[0]
    return _dynamic_user_arm(request.param, str(tmp_path_factory.getbasetemp()))


@pytest.fixture
def private_tmp(tmp_path, monkeypatch):
    """A private TMPDIR for this process (``tempfile.gettempdir()`` returns it)."""
    folder = tmp_path / "tmp"
    folder.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    monkeypatch.setenv("TMPDIR", str(folder))
    return folder


#: What a test does, found in its own source (a test function's body): a marker for each (pyproject's markers).
#: `make check` leaves these out; `make test` (CI) runs everything.
KINDS = {
    "browser": ("screenshots(", "chromium("),  # headless Chromium (tests/browser.py)
    # Dask clusters: every sweep runs on one (a LocalCluster of worker processes unless --scheduler is given)
    "cluster": ("run_sweep(", '"sweep"', "--scheduler", "LocalCluster"),
    # armlab or Python processes, the reproduction's worker processes (reproduce's default jobs, _Pool)
    "process": ("subprocess.", "Popen", "sys.executable", "ARMLAB", ".run(", "reproduction", "reproduce", "_Pool("),
}
#: Whole modules of one kind.
MODULE_KINDS = {"test_dask_cluster.py": ("cluster", "process"), "test_signals.py": ("process",),
                "test_cli_usage.py": ("process",), "test_readme.py": ("process",)}


def pytest_collection_modifyitems(items) -> None:
    """Mark each test ``browser``, ``cluster`` or ``process`` by what its source (or its module) does; a test that
    uses the session's reproduction (worker processes) is ``process``."""
    import inspect

    for item in items:
        function = getattr(item, "function", None)
        source = inspect.getsource(function) if function is not None else ""
        source += " ".join(getattr(item, "fixturenames", ()))
        kinds = set(MODULE_KINDS.get(item.path.name, ()))
        kinds |= {kind for kind, needles in KINDS.items() if any(n in source for n in needles)}
        for kind in sorted(kinds):
            item.add_marker(kind)
