"""Replacing an output folder survives a kill at any point (issue 24, item 2).

A child process replaces ``out`` through :class:`armlab.files.OutputFolder` and SIGKILLs itself at a chosen
moment: between the two renames of the fallback (no atomic swap), right after the atomic swap, and while
writing. Whatever it leaves, the earlier or the new output is whole at ``out`` once the next command on that
folder has run, and no temporary of a dead process stays beside it; a live writer's temporary is left alone.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import pytest

from armlab import files
from armlab.files import OutputFolder, RecoveredWarning

pytestmark = pytest.mark.process

#: The child: writes ``out`` (file ``data.txt`` = TEXT) through OutputFolder; KILL says where it dies.
CHILD = textwrap.dedent("""
    import os, signal, sys
    from pathlib import Path
    from armlab import files
    out, text, kill = Path(sys.argv[1]), sys.argv[2], sys.argv[3]
    die = lambda: os.kill(os.getpid(), signal.SIGKILL)
    if kill == "between-renames":  # no atomic swap: killed after `out` was moved aside, before the new one is in
        files._exchange = lambda a, b: False
        rename = os.replace
        def replace(src, dst):
            rename(src, dst)
            if Path(src) == out:
                die()
        os.replace = replace
    if kill == "after-swap":  # the swap done, the earlier output (now at the temporary's name) not yet removed
        swap = files._exchange
        files._exchange = lambda a, b: swap(a, b) and die()
    with files.OutputFolder(out, lambda folder: (folder / "data.txt").exists(), "a test output") as tmp:
        (tmp / "data.txt").write_text(text)
        if kill == "writing":
            die()
""")


def _child(out: Path, text: str, kill: str = "") -> int:
    return subprocess.run([sys.executable, "-c", CHILD, str(out), text, kill], timeout=60).returncode


def _beside(out: Path) -> list[str]:
    """The hidden entries beside ``out`` (temporaries)."""
    return sorted(p.name for p in out.parent.iterdir() if p.name.startswith("."))


def _next_command(out: Path) -> None:
    """What the next command on ``out`` does first (its OutputFolder), without writing anything."""
    folder = OutputFolder(out, lambda f: (f / "data.txt").exists(), "a test output")
    with pytest.raises(RuntimeError), folder:
        raise RuntimeError("no output this time")


def test_a_kill_between_the_two_renames_loses_nothing(tmp_path):
    out = tmp_path / "run"
    assert _child(out, "first") == 0
    assert _child(out, "second", "between-renames") == -9
    assert not out.exists() and any(name.endswith(".old") for name in _beside(out))  # the window, as it was
    with pytest.warns(RecoveredWarning, match="put back the earlier output"):
        _next_command(out)
    assert (out / "data.txt").read_text() == "first"
    assert _beside(out) == []


def test_a_kill_right_after_the_swap_leaves_the_new_output_and_its_debris_is_cleaned(tmp_path):
    out = tmp_path / "run"
    assert _child(out, "first") == 0
    assert _child(out, "second", "after-swap") == -9
    assert (out / "data.txt").read_text() == "second"
    assert len(_beside(out)) == 1  # the earlier output under the dead child's temporary name
    _next_command(out)
    assert _beside(out) == [] and (out / "data.txt").read_text() == "second"


def test_a_kill_while_writing_keeps_the_earlier_output_and_its_temporary_is_cleaned(tmp_path):
    out = tmp_path / "run"
    assert _child(out, "first") == 0
    assert _child(out, "second", "writing") == -9
    assert (out / "data.txt").read_text() == "first" and len(_beside(out)) == 1
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing to put back: no warning
        _next_command(out)
    assert _beside(out) == []


def test_a_replacement_is_one_atomic_swap_here(tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    (a / "x").write_text("a")
    # Linux (armlab's machines) has renameat2(RENAME_EXCHANGE) on its local file systems; the fallback is tested above
    assert files._exchange(a, b), "renameat2(RENAME_EXCHANGE) failed here"
    assert (b / "x").read_text() == "a" and not (a / "x").exists()


def test_a_live_writers_temporary_is_left_alone(tmp_path):
    out = tmp_path / "run"
    with OutputFolder(out, lambda f: True, "a test output") as first:
        (first / "data.txt").write_text("mine")
        _next_command(out)  # another command on the same folder meanwhile (this process: alive)
        assert (first / "data.txt").read_text() == "mine"
    assert (out / "data.txt").read_text() == "mine" and _beside(out) == []
