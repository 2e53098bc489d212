"""Output folders, files and streams under hostile use: complete output or none, one error line, no debris.

Output folders and files are rows of tables (``OUTPUT_FOLDERS``, ``OUTPUT_FILES``) run in-process;
streams (a reader that goes away, a full disk behind stdout or stderr) run as subprocesses.
The contract is :func:`contract.check`; debris is anything new besides the intended output
(:meth:`contract.Sandbox.debris`), hidden ``.tmp`` / ``.old`` folders included.
"""

from __future__ import annotations

import json
import subprocess

import pytest
from contract import Sandbox, check

pytestmark = pytest.mark.timeout(180)

#: A short run: rr's paper motion in 0.5 s, logged every 10 ms.
SHORT = ("simulate", "rr", "--tf", "0.5", "--dt", "0.01")


@pytest.fixture
def box(tmp_path, monkeypatch, capsys) -> Sandbox:
    return Sandbox(tmp_path, monkeypatch, capsys)


def _taken_file(box: Sandbox) -> None:
    box.write("taken", "not a folder")


def _foreign_folder(box: Sandbox) -> None:
    box.write("mine/notes.txt", "")


def _previous_run(box: Sandbox) -> None:
    check(box.main(*SHORT, "--out", "run"), 0, "wrote run")
    box.keep()


def _inside(box: Sandbox) -> None:
    box.mkdir("sub")


# (set-up or None, argv, exit code, fragment, outputs that may appear)
OUTPUT_FOLDERS = [
    (None, (*SHORT, "--out", "."), 2, "--out '.' is the working directory, which cannot be replaced", ()),
    (None, (*SHORT, "--out", ""), 2, "--out '' is the working directory", ()),
    (None, (*SHORT, "--out", "./"), 2, "is the working directory", ()),
    (None, (*SHORT, "--out", "../cwd"), 2, "is the working directory", ()),
    (None, (*SHORT, "--out", ".."), 2, "is a folder holding the working directory", ()),
    (None, (*SHORT, "--out", "/"), 2, "--out '/' is a folder holding the working directory", ()),
    (None, (*SHORT, "--out", "/proc"), 2, "--out '/proc' is the root of a file system", ()),
    (None, (*SHORT, "--out", "/proc/armlab-run"), 2, "cannot write in /proc", ()),
    (_taken_file, (*SHORT, "--out", "taken"), 2, "--out taken: exists and is not a folder", ()),
    (_foreign_folder, (*SHORT, "--out", "mine"), 2, "--out mine: exists and is not an armlab run folder", ()),
    (None, (*SHORT, "--out", "new dir é/ü x"), 0, "wrote new dir é/ü x", ("new dir é",)),
    (None, (*SHORT, "--out", "run/"), 0, "wrote run/", ("run",)),
    (_previous_run, (*SHORT, "--out", "run"), 0, "wrote run", ("run",)),
    (_inside, (*SHORT, "--out", "sub/../run"), 0, "wrote", ("run",)),
    (None, ("reproduce", "--paper", "004", "--fast", "--out", "."), 2, "is the working directory", ()),
    (None, ("reproduce", "--paper", "004", "--fast", "--out", "/"), 2, "holding the working directory", ()),
    (None, ("reproduce", "--paper", "004", "--fast", "--out", "/proc"), 2, "root of a file system", ()),
    (_taken_file, ("reproduce", "--paper", "004", "--fast", "--out", "taken"), 2, "exists and is not a folder", ()),
    (None, ("workspace", "rr", "--samples", "1000", "--out", "."), 2, "is the working directory", ()),
    (None, ("workspace", "rr", "--samples", "1000", "--out", "/"), 2, "holding the working directory", ()),
    (_taken_file, ("workspace", "rr", "--samples", "1000", "--out", "taken"), 2, "exists and is not a folder", ()),
]


@pytest.mark.slow  # three simulate runs, for the output folder's replacement (no number)
def test_replacing_a_run_keeps_only_the_new_one(box):
    check(box.main(*SHORT, "--out", "run"), 0, "wrote run")
    check(box.main("simulate", "rr", "--tf", "0.3", "--dt", "0.01", "--out", "run"), 0, "wrote run")
    assert json.loads((box.cwd / "run" / "summary.json").read_text())["duration"] == pytest.approx(0.3)
    assert box.debris("run") == []


def _folder_named_like_the_file(box: Sandbox) -> None:
    box.mkdir("taken.dot")


OUTPUT_FILES = [
    (None, ("diagram", "rr", "--out", "d.txt"), 2, "--out d.txt: the suffix must be one of", ()),
    (None, ("diagram", "rr", "--out", "/proc/armlab/d.dot"), 2, "cannot write in /proc/armlab", ()),
    (_folder_named_like_the_file, ("diagram", "rr", "--out", "taken.dot"), 2, "taken.dot", ()),
    (None, ("diagram", "rr", "--out", "é ü/d.svg"), 0, "wrote é ü/d.svg", ("é ü",)),
    (None, ("diagram", "rr", "--out", "d.dot"), 0, "wrote d.dot", ("d.dot",)),
]


@pytest.mark.slow
@pytest.mark.parametrize(("setup", "argv", "code", "fragment", "outputs"), OUTPUT_FOLDERS + OUTPUT_FILES,
                         ids=lambda v: " ".join(v)[:50] if isinstance(v, tuple) else getattr(v, "__name__", None))
def test_outputs(box, setup, argv, code, fragment, outputs):
    """A folder or file written whole, or one error line; no debris, no .tmp/.old left inside the output."""
    if setup is not None:
        setup(box)
    check(box.main(*argv), code, fragment)
    assert box.debris(*outputs) == []
    for out in outputs:
        assert not [p for p in (box.cwd / out).rglob("*") if p.suffix in (".tmp", ".old")]


# ---- streams: a reader that goes away, a full disk behind stdout or stderr (subprocesses) -----------------------
def _closed_reader(box: Sandbox, *argv: str) -> tuple[int, str]:
    """Run ``armlab ARGV`` with its stdout a pipe whose reader is gone; its exit code and stderr."""
    process = subprocess.Popen(box.command(*argv), stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=box.cwd,
                               env=box.env())
    process.stdout.close()
    _, err = process.communicate(timeout=120)
    return process.returncode, err.decode()


@pytest.mark.parametrize("argv", [("list",), ("fk", "urm6", "--q", "0,0,0,0,0,0", "--json"), (*SHORT, "--out", "run"),
                                  (*SHORT, "--out", "new/deeper/run")], ids=lambda v: " ".join(v)[-20:])
def test_a_reader_that_goes_away_ends_it_quietly(box, argv):
    """``armlab … | head``: exit 141 (128 + SIGPIPE, as the shell's own tools), nothing on stderr, no output."""
    code, err = _closed_reader(box, *argv)
    assert (code, err) == (141, "")
    assert box.debris() == []


# (argv, which stream is the full disk, exit code, fragment of stderr when it is not the full one)
FULL_DISK = [
    (("fk", "rr", "--q", "x"), "stderr", 2, ""),
    (("fk", "rr"), "stderr", 2, ""),
    (("simulate", "rr", "--kp", "1e308", "--out", "run"), "stderr", 2, ""),
    (("fk", "rr", "--q", "0,0"), "stdout", 2, "armlab: error: No space left on device"),
    ((*SHORT, "--out", "run"), "stdout", 2, "armlab: error: No space left on device"),
]


@pytest.mark.parametrize(("argv", "stream", "code", "fragment"), FULL_DISK, ids=lambda v: str(v)[:40])
def test_a_full_disk_behind_a_stream(box, argv, stream, code, fragment):
    with open("/dev/full", "w") as full:
        kwargs = {"stderr": full, "stdout": subprocess.PIPE} if stream == "stderr" else {"stdout": full,
                                                                                        "stderr": subprocess.PIPE}
        done = subprocess.run(box.command(*argv), cwd=box.cwd, env=box.env(), timeout=120, text=True, **kwargs)
    assert done.returncode == code
    if stream == "stdout":
        assert done.stderr.splitlines() == [fragment]
    assert box.debris() == []


@pytest.mark.parametrize("late", [ValueError("a late error"), KeyboardInterrupt()], ids=["error", "stop signal"])
def test_a_workspace_stopped_while_it_samples_leaves_no_temporary(box, monkeypatch, late):
    """An error or a stop signal during the sampling (after the output folder was checked and its temporary
    made) removes the temporary (issue 24, item 20: .ws.XXXX.tmp was left)."""
    def sampling(*_args, **_kwargs):
        raise late

    monkeypatch.setattr("armlab.cli.analysis.workspace", sampling)
    code = box.main("workspace", "rr", "--samples", "1000", "--out", "ws").code
    assert code == (2 if isinstance(late, ValueError) else 130)
    assert box.debris() == []
