"""SIGINT and SIGTERM at several moments of the long commands: a prompt exit 130 / 143, no partial output, no
temporaries (issue 13).

Each case is one row of ``MOMENTS``: the command, and when the signal is sent — a number of seconds
after the command printed a line holding a given text. The command runs as a subprocess in a
:class:`contract.Sandbox` (private working directory and TMPDIR), which must be left as it was.
"""

from __future__ import annotations

import os
import signal
import subprocess
import threading
import time

import pytest
from contract import Sandbox

pytestmark = pytest.mark.timeout(240)

#: Seconds a stopped command may take to exit.
PROMPT = 15.0

SIMULATE = ("simulate", "rrrr", "--out", "run")  # paper 000's 15 s constant-rate run: several seconds of work
REPRODUCE = ("reproduce", "--paper", "000", "--fast", "--out", "rep")
VIEW = ("view", "rr", "--port", "7390")

# (argv, text of the line to wait for ("" : the start), seconds after it)
MOMENTS = [
    (SIMULATE, "", 1.5),  # loading the arm, importing Drake
    (SIMULATE, "rrrr: paper 000", 0.0),  # the run folder just made
    (SIMULATE, "rrrr: paper 000", 1.0),  # inside the simulation
    (SIMULATE, "simulated", 0.0),  # writing the files
    (REPRODUCE, "", 2.0),
    (REPRODUCE, "[000]", 0.0),
    (REPRODUCE, "[000]", 3.0),
    (VIEW, "", 1.5),  # importing Drake, starting Meshcat
    (VIEW, "open http", 0.0),
    (VIEW, "open http", 1.0),
]


@pytest.fixture
def box(tmp_path, monkeypatch, capsys) -> Sandbox:
    return Sandbox(tmp_path, monkeypatch, capsys)


def _start(box: Sandbox, *argv: str) -> subprocess.Popen:
    """``armlab ARGV`` in its own process group (as a shell's job), stdout and stderr read as text."""
    return subprocess.Popen(box.command(*argv), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=box.cwd, env=box.env(), start_new_session=True)


def _send(process: subprocess.Popen, signum: int) -> None:
    """SIGINT as Ctrl-C sends it: to the whole process group (workers, helpers included); SIGTERM as ``kill``
    sends it: to the process alone."""
    if signum == signal.SIGINT:
        os.killpg(process.pid, signum)
    else:
        process.send_signal(signum)


def _wait_for(process: subprocess.Popen, text: str, lines: list[str]) -> bool:
    """Read ``process``' stdout into ``lines`` until a line holds ``text``; False if it ended first."""
    for line in process.stdout:
        lines.append(line)
        if text in line:
            threading.Thread(target=lambda: lines.extend(process.stdout), daemon=True).start()
            return True
    return False


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=lambda s: s.name)
@pytest.mark.parametrize(("argv", "text", "delay"), MOMENTS, ids=lambda v: " ".join(v)[:30] if isinstance(v, tuple)
                         else str(v))
def test_a_stop_signal_leaves_nothing(box, argv, text, delay, signum):
    process = _start(box, *argv)
    lines: list[str] = []
    if text:
        assert _wait_for(process, text, lines), (lines, process.stderr.read())
    time.sleep(delay)
    assert process.poll() is None, "the command ended before the signal"
    _send(process, signum)
    sent = time.monotonic()
    _, err = process.communicate(timeout=PROMPT + 60)
    took = time.monotonic() - sent
    assert process.returncode == 128 + signum, (process.returncode, err[-3000:])
    assert took < PROMPT
    assert "Traceback" not in err and "error" not in err, err
    assert box.debris() == []
    assert _ended(box)


def _ended(box: Sandbox) -> bool:
    """No process of the sandbox is left (e.g. a Dask worker), waiting up to 10 s for them to end."""
    end = time.monotonic() + 10
    while box.processes() and time.monotonic() < end:
        time.sleep(0.2)
    return not box.processes()
