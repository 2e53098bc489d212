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
import sys
import threading
import time
from pathlib import Path

import pytest
from contract import Sandbox

pytestmark = pytest.mark.timeout(240)

#: Seconds a stopped command may take to exit.
PROMPT = 15.0

SIMULATE = ("simulate", "rrrr", "--out", "run")  # paper 000's 15 s constant-rate run: several seconds of work
REPRODUCE = ("reproduce", "--paper", "000", "--fast", "--out", "rep")
VIEW = ("view", "rr", "--port", "7390")
SIZE = ("size", "rr", "--payload", "0,1,2,3,4,5", "--rate", "5000", "--out", "sz")  # seconds of sizing

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
    (SIZE, "", 4.0),  # issue 36 item 24: inside the sizing, its output folder's temporary made
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
            return True
    return False


def _stop(process: subprocess.Popen, signum: int, lines: list[str], target: int | None = None) -> tuple[str, float]:
    """Send ``signum`` (as :func:`_send` does, or to ``target``: a process id, or minus a process group's, as for
    ``os.kill``) while a thread keeps reading stdout into ``lines``; the process' stderr and the seconds it took to
    end. The one thread reads stdout to its end, so no second reader races it."""
    reader = threading.Thread(target=lambda: lines.extend(process.stdout), daemon=True)
    reader.start()
    if target is None:
        _send(process, signum)
    else:
        os.kill(target, signum)
    sent = time.monotonic()
    process.wait(timeout=PROMPT + 60)
    took = time.monotonic() - sent
    err = process.stderr.read()
    reader.join(timeout=10)
    return err, took


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
    err, took = _stop(process, signum, lines)
    assert process.returncode == 128 + signum, (process.returncode, err[-3000:])
    assert took < PROMPT
    assert "Traceback" not in err and "error" not in err, err
    assert box.debris() == []
    assert _ended(box)


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=lambda s: s.name)
def test_a_stopped_reproduction_stops_its_workers_quietly(box, signum):
    """Ctrl-C (the workers ignore it, the parent stops them) or SIGTERM (the parent alone) while both of
    ``armlab reproduce``'s workers run a paper: nothing at all on stderr (no warning of a lock a killed worker
    held), besides what every stop is held to."""
    process = _start(box, "reproduce", "--fast", "--jobs", "2", "--out", "rep")
    lines: list[str] = []
    for paper in ("[000]", "[004]"):  # 000 starts on one worker, 004 on the other
        assert any(paper in line for line in lines) or _wait_for(process, paper, lines), lines
    err, took = _stop(process, signum, lines)
    assert process.returncode == 128 + signum and err == "", (process.returncode, err[-3000:])
    assert took < PROMPT
    assert box.debris() == []
    assert _ended(box)


#: Moments of a two-worker reproduction of paper 000 (one worker runs the paper, the other waits for a task):
#: (text of the line to wait for ("": the start), seconds after it)
REPRODUCE_MOMENTS = [
    ("", 2.0),  # importing, the workers starting
    ("[000]", 0.0),  # the paper just started
    ("[000]", 3.0),  # inside the paper
    ("(not in the paper) → beyond_drive_map.csv", 0.0),  # the paper done: both workers render its report's LaTeX
]


def _earlier_reproduction(box: Sandbox) -> dict[str, str]:
    """An earlier reproduction in ``rep`` (its marker and a report), part of the sandbox; its files' contents."""
    from armlab.papers.reproduce import MARKER

    files = {MARKER: "armlab reproduce output\n", "report.md": "# the earlier report\n"}
    for name, text in files.items():
        box.write(f"rep/{name}", text)
    return files


def _contents(folder: Path) -> dict[str, str]:
    return {p.name: p.read_text() for p in folder.iterdir()}


def _workers(pid: int) -> list[int]:
    """The live worker processes (spawned by multiprocessing) whose parent is ``pid``."""
    found = []
    for status in Path("/proc").glob("[0-9]*/status"):
        try:
            ppid = next(line for line in status.read_text().splitlines() if line.startswith("PPid:"))
            cmdline = (status.parent / "cmdline").read_bytes()
        except (OSError, StopIteration):  # ended meanwhile
            continue
        if int(ppid.split()[1]) == pid and b"spawn_main" in cmdline:
            found.append(int(status.parent.name))
    return found


@pytest.mark.parametrize(("text", "delay", "group"), [
    pytest.param(text, delay, group, id=f"to the {'group' if group else 'process'}, {text[:12] or 'start'} + {delay}")
    for group, moments in ((True, REPRODUCE_MOMENTS), (False, REPRODUCE_MOMENTS[:3])) for text, delay in moments])
def test_sigterm_ends_a_reproduction_and_its_workers(box, text, delay, group):
    """SIGTERM to ``armlab reproduce``'s process group (``timeout -s TERM``, ``kill -- -PGID``: the workers die of
    it too) or to the process alone (it stops the workers), at several moments: exit 143 promptly (it hung for
    ever when the group's SIGTERM killed a worker waiting for a task: the pool's clean-up waited for the task
    queue's lock the dead worker held), no temporaries, no worker left, the earlier reproduction intact."""
    earlier = _earlier_reproduction(box)
    process = _start(box, "reproduce", "--paper", "000", "--fast", "--jobs", "2", "--out", "rep")
    lines: list[str] = []
    if text:
        assert _wait_for(process, text, lines), (lines, process.stderr.read())
    time.sleep(delay)
    assert process.poll() is None, "the reproduction ended before the signal"
    err, took = _stop(process, signal.SIGTERM, lines, -process.pid if group else process.pid)
    assert process.returncode == 143, (process.returncode, err[-3000:])
    assert took < PROMPT
    assert err == "", err[-3000:]
    assert box.debris() == []
    assert _ended(box)
    assert _contents(box.cwd / "rep") == earlier


def test_ctrl_c_while_the_workers_start_prints_nothing(box):
    """Ctrl-C (to the whole process group) as soon as the two workers exist, while they import their modules
    (seconds): exit 130 and nothing on stderr (a worker that took its KeyboardInterrupt printed its traceback), no
    worker left."""
    process = _start(box, "reproduce", "--paper", "000", "--fast", "--jobs", "2", "--out", "rep")
    end = time.monotonic() + 120
    while len(_workers(process.pid)) < 2:
        assert process.poll() is None and time.monotonic() < end, (process.poll(), "no workers")
        time.sleep(0.01)
    err, took = _stop(process, signal.SIGINT, [])
    assert process.returncode == 130 and err == "", (process.returncode, err[-3000:])
    assert took < PROMPT
    assert box.debris() == []
    assert _ended(box)


def test_a_worker_killed_alone_ends_a_reproduction_with_an_error(box):
    """A worker killed (the kernel's out-of-memory killer, say) while the other runs paper 000: one error line
    naming it, exit 2, promptly (a multiprocessing pool waited for ever for its task), the other worker stopped,
    no temporaries, the earlier reproduction intact."""
    earlier = _earlier_reproduction(box)
    process = _start(box, "reproduce", "--paper", "000", "--fast", "--jobs", "2", "--out", "rep")
    lines: list[str] = []
    assert _wait_for(process, "[000]", lines), (lines, process.stderr.read())
    workers = _workers(process.pid)
    assert len(workers) == 2, workers
    err, took = _stop(process, signal.SIGKILL, lines, workers[0])
    assert process.returncode == 2, (process.returncode, err[-3000:])
    assert err == (f"armlab: error: a reproduce worker process (pid {workers[0]}) ended unexpectedly (killed by "
                   "SIGKILL)\n")
    assert took < PROMPT
    assert box.debris() == []
    assert _ended(box)
    assert _contents(box.cwd / "rep") == earlier


def _ended(box: Sandbox) -> bool:
    """No process of the sandbox is left (e.g. a Dask worker), waiting up to 10 s for them to end."""
    end = time.monotonic() + 10
    while box.processes() and time.monotonic() < end:
        time.sleep(0.2)
    return not box.processes()


STUDY = str(Path(__file__).parents[1] / "analysis" / "studies" / "urm6_theta3_theta5.json")


#: When the signal is sent to a sweep: (lines results.csv holds, seconds after it does, or after the start if 0 lines)
SWEEP_MOMENTS = [
    (0, 1.5),  # importing, reading the study
    (1, 0.3),  # the header written: the local cluster starting, its workers importing
    (2, 0.0),  # the first candidate's row: computing
    (8, 1.0),  # later on
]


def _wait_lines(path: Path, lines: int, process: subprocess.Popen) -> None:
    """Wait until the file ``path`` holds ``lines`` whole lines (while ``process`` runs, at most 120 s)."""
    end = time.monotonic() + 120
    while not (path.exists() and path.read_text().count("\n") >= lines):
        assert process.poll() is None and time.monotonic() < end, (process.poll(), "no such line")
        time.sleep(0.02)


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=lambda s: s.name)
@pytest.mark.parametrize(("lines", "delay"), SWEEP_MOMENTS, ids=lambda v: str(v))
def test_a_stop_signal_ends_a_sweep(box, lines, delay, signum):
    """``armlab sweep`` keeps the candidates computed so far (its results.csv resumes), but no temporaries, no
    half-written file, no Dask scratch folder in TMPDIR and no worker process are left, no worker prints a traceback,
    and it exits promptly."""
    process = _start(box, "sweep", STUDY, "--out", "sweep", "--workers", "2")
    if lines:
        _wait_lines(box.cwd / "sweep" / "results.csv", lines, process)
    time.sleep(delay)
    assert process.poll() is None, "the sweep ended before the signal"
    err, took = _stop(process, signum, [])
    assert process.returncode == 128 + signum, (process.returncode, err[-3000:])
    assert took < PROMPT
    assert "Traceback" not in err, err
    assert box.debris("sweep") == []
    assert {p.name for p in (box.cwd / "sweep").glob("*")} <= {"results.csv", "study.json"}
    results = box.cwd / "sweep" / "results.csv"
    if results.exists():
        rows = [line.split(",") for line in results.read_text().splitlines()]
        assert rows and all(len(row) == len(rows[0]) for row in rows)
    assert _ended(box)


def test_a_stop_signal_inside_a_weakref_callback_still_stops():
    """A signal whose handler runs inside a weakref callback (garbage collection, a WeakKeyDictionary's clean-up):
    Python only prints the Interrupted raised there and goes on, so the signal is sent again and stops the work
    after the callback; nothing is printed."""
    import sys
    import weakref

    from armlab.files import Interrupted, stop_on_signals

    class Thing:
        pass

    def callback(_):
        signal.raise_signal(signal.SIGINT)  # the handler runs at the callback's next instructions
        sum(range(1000))

    printed = []
    hook, sys.unraisablehook = sys.unraisablehook, printed.append  # what Python would print
    try:
        with pytest.raises(Interrupted), stop_on_signals() as state:
            thing = Thing()
            ref = weakref.ref(thing, callback)
            del thing  # the callback runs now
            assert ref() is None
            end = time.monotonic() + 5
            while time.monotonic() < end:  # the work after the callback, stopped by the signal sent again
                time.sleep(0.01)
            raise AssertionError("the signal raised inside the callback was lost")
    finally:
        sys.unraisablehook = hook
    assert state.received == signal.SIGINT and printed == []


_NATIVE = """
import resource, sys
resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))  # the parse grows without end: a bound for the test
from pathlib import Path
from armlab.files import stop_on_signals
from armlab.models.plant import parse_model_file
with stop_on_signals():
    print("parsing", flush=True)
    parse_model_file(Path(sys.argv[1]), {})  # Drake's own parser, past armlab's refusal of the include
print("returned", flush=True)
"""


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_stop_signal_ends_a_process_stuck_in_a_native_parse(box, signum):
    """Issue 36, item 5: an MJCF file that includes itself keeps Drake's parser (native code, where Python's handler
    cannot run) growing; a stop signal still ends the process at once (its default action)."""
    model = Path(__file__).parent / "data" / "formats" / "two_link.xml"
    (box.cwd / "self.xml").write_text(model.read_text().replace("<worldbody>",
                                                                '<include file="self.xml"/><worldbody>'))
    process = subprocess.Popen([os.sys.executable, "-c", _NATIVE, "self.xml"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, cwd=box.cwd, env=box.env(), start_new_session=True)
    assert process.stdout.readline() == "parsing\n"
    time.sleep(1.0)
    start = time.monotonic()
    process.send_signal(signum)
    try:
        process.wait(PROMPT)
    finally:
        process.kill()
    assert process.returncode == -signum, process.stderr.read()[-300:]
    assert time.monotonic() - start < PROMPT


def test_a_signal_sent_again_after_the_work_prints_nothing_at_exit():
    """Issue 36 item 19: a stop signal that arrived inside an import (Ctrl-C early in ``armlab export``) is sent
    again from a timer; when the command has ended first, the timer fired into the interpreter's exit, which printed
    "Exception ignored in: <module 'threading'> … KeyboardInterrupt". Leaving stop_on_signals cancels it."""
    code = ("import signal, sys\n"
            "from armlab import files\n"
            "with files.stop_on_signals():\n"
            "    files._send_again(signal.SIGINT)  # as for a signal that arrived inside an import\n"
            "sys.exit(0)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert (done.returncode, done.stderr) == (0, "")
