"""The contract every hostile input is held to, shared by the bad-input suites.

``tests/test_bad_inputs.py`` (numbers, files, resource limits), ``tests/test_outputs.py`` (output
folders and streams) and ``tests/test_signals.py`` (SIGINT / SIGTERM) run ``armlab`` in a
:class:`Sandbox` — a private working directory and TMPDIR — and check with :func:`check` that the
command gave a result, or exactly one stderr line ``armlab: error: …`` and exit code 2; never a
traceback; and with :meth:`Sandbox.debris` that it left no file but its intended output.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import pytest

from armlab.cli import main

ERROR = "armlab: error: "


@dataclass
class Outcome:
    """What a command did: exit code, stdout, stderr."""

    code: int
    out: str
    err: str


def check(outcome: Outcome, code: int, fragment: str = "") -> None:
    """The contract: exit ``code``; no traceback; on an error (code 2) one stderr line ``armlab: error: …`` holding
    ``fragment``; on success ``fragment`` in stdout."""
    assert "Traceback" not in outcome.err, outcome.err
    assert outcome.code == code, (outcome.code, outcome.err[-2000:])
    if code == 2:
        lines = outcome.err.splitlines()
        assert len(lines) == 1 and lines[0].startswith(ERROR), outcome.err
        assert fragment in lines[0], (fragment, lines[0])
    else:
        assert fragment in outcome.out, (fragment, outcome.out[-2000:])


def _tree(root: Path) -> set[Path]:
    return {root, *root.rglob("*")} if root.exists() else set()


class Sandbox:
    """A private working directory (``cwd``) and TMPDIR (``tmp``) under pytest's ``tmp_path``, with armlab run in them.

    :meth:`main` runs ``armlab.cli.main`` in this process (fast); :meth:`run` a subprocess (for signals,
    pipes, streams). :meth:`debris` lists the files that appeared besides the ones a command was meant to write.
    """

    def __init__(self, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
        self.root = tmp_path
        self.cwd = tmp_path / "cwd"
        self.tmp = tmp_path / "tmp"
        self.cwd.mkdir()
        self.tmp.mkdir()
        monkeypatch.chdir(self.cwd)
        monkeypatch.setenv("TMPDIR", str(self.tmp))
        monkeypatch.setattr(tempfile, "tempdir", None)  # tempfile reads TMPDIR again
        self._capsys = capsys
        self._before = self._files()

    def _files(self) -> set[Path]:
        return _tree(self.root)

    def write(self, name: str, content: str | bytes) -> Path:
        """A file ``name`` in the working directory holding ``content``; part of the sandbox, not debris."""
        path = self.cwd / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(content if isinstance(content, bytes) else content.encode())
        self.keep()
        return path

    def mkdir(self, name: str) -> Path:
        """A folder ``name`` in the working directory; part of the sandbox, not debris."""
        path = self.cwd / name
        path.mkdir(parents=True)
        self.keep()
        return path

    def keep(self) -> None:
        """Everything now in the sandbox is part of it (made by a test's set-up), not debris."""
        self._before = self._files()

    def main(self, *argv: str) -> Outcome:
        """``armlab ARGV`` in this process."""
        self._capsys.readouterr()
        code = main(list(argv))
        out, err = self._capsys.readouterr()
        return Outcome(code, out, err)

    def command(self, *argv: str) -> list[str]:
        """The command line running ``armlab ARGV`` with this interpreter."""
        return [sys.executable, "-m", "armlab", *argv]

    def env(self) -> dict[str, str]:
        """The environment of a subprocess: the sandbox's TMPDIR, and a tag its descendants inherit."""
        return {**os.environ, "TMPDIR": str(self.tmp), "ARMLAB_SANDBOX": str(self.root)}

    def processes(self) -> list[int]:
        """The live processes started from this sandbox (subprocesses and their descendants, by their tag)."""
        tag = f"ARMLAB_SANDBOX={self.root}\0".encode()
        found = []
        for environ in Path("/proc").glob("[0-9]*/environ"):
            try:
                if tag in environ.read_bytes():
                    found.append(int(environ.parent.name))
            except OSError:  # ended meanwhile
                pass
        return found

    def run(self, *argv: str, timeout: float = 120, **kwargs) -> Outcome:
        """``armlab ARGV`` as a subprocess in the sandbox."""
        done = subprocess.run(self.command(*argv), capture_output=True, text=True, timeout=timeout, cwd=self.cwd,
                              env=self.env(), **kwargs)
        return Outcome(done.returncode, done.stdout, done.stderr)

    def debris(self, *outputs: str | Path) -> list[Path]:
        """Paths that appeared since the sandbox was made, other than ``outputs`` (relative to ``cwd``) and what
        they hold; also accepted: Python's ``__pycache__``."""
        allowed = [(self.cwd / p).absolute() for p in outputs]
        new = self._files() - self._before
        return sorted(p for p in new if "__pycache__" not in p.parts
                      and not any(p == a or a in p.parents for a in allowed))
