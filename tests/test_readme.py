"""The README's CLI tour, its Python blocks and the example scripts run as written, so they cannot rot."""

from __future__ import annotations

import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import armlab_main

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "scripts" / "examples"
README = (ROOT / "README.md").read_text()


# --------------------------------------------------------------------------- the CLI tour
def cli_tour() -> list[tuple[str, list[str]]]:
    """The README's CLI tour (its ```console block): each ``$ armlab …`` command with the lines shown under it.

    A ``#`` line right under a command is the command's comment, not output.
    """
    block = re.search(r"```console\n(.*?)```", README, flags=re.S)
    assert block is not None, "the README has its CLI tour"
    tour: list[tuple[str, list[str]]] = []
    for line in block.group(1).splitlines():
        if line.startswith("$ "):
            tour.append((line[2:], []))
        elif line and not (line.startswith("#") and not tour[-1][1]):
            tour[-1][1].append(line)
    return tour


#: Wall-clock times: the machine's speed, not armlab's results; their digits are not compared.
_TIMES = [re.compile(p) for p in (r"in \d+\.\d+ s \(\d+\.\d+× real time\)", r"failed \(\d+\.\d+ s\)",
                                  r"not reproducible; \d+\.\d+ s\)")]
#: The viewer's port: the first free one from 7000, which another program (or a parallel test) may hold.
_PORT = re.compile(r"localhost:\d+")
_NUMBER = re.compile(r"([-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?)")
#: Lines whose order is a tie (slices of the shown output), per command: sorted before they are compared.
#: arm4r's IK at (1, 1, 1.4) has two pairs of solutions at the same distance from q = 0 (each pair's joint
#: magnitudes are one set, permuted), so "nearest first" does not order them; kinematics/ik.py's tie-break
#: is not the README's business.
_TIES = {"ik arm4r --target 1,1,1.4 --all --deg": [slice(0, 2), slice(2, 4)]}


#: Commands that take seconds each (a simulation, a Meshcat server, a Dask cluster, 1e6 samples, every paper):
#: the tests marked slow.
_SLOW = ("simulate", "view", "sweep", "workspace", "reproduce")


def _masked(line: str) -> str:
    for pattern in _TIMES:
        line = pattern.sub("<time>", line)
    return _PORT.sub("localhost:<port>", line)


def _same_line(printed: str, shown: str) -> bool:
    """The same text, and the same numbers: a number the README prints with decimals may differ by one unit in
    its last digit (a value that sits on a rounding boundary), integers not at all."""
    printed_parts, shown_parts = _NUMBER.split(_masked(printed)), _NUMBER.split(_masked(shown))
    if len(printed_parts) != len(shown_parts) or printed_parts[::2] != shown_parts[::2]:
        return False
    for got, want in zip(printed_parts[1::2], shown_parts[1::2], strict=True):
        mantissa, _, exponent = want.lower().partition("e")
        if "." not in mantissa:
            if got != want:
                return False
            continue
        unit = 10.0 ** (int(exponent or 0) - len(mantissa.split(".")[1]))
        if abs(float(got) - float(want)) > unit * (1 + 1e-9):  # 1e-9: the unit's own rounding in binary
            return False
    return True


def assert_output_as_shown(command: str, printed: list[str], shown: list[str]) -> None:
    """``printed`` is ``shown``, line by line (:func:`_same_line`).

    A shown ``…`` line means "among other lines, in any order" (``reproduce``'s progress: the papers' workers
    finish in any order): each line shown above the last is printed somewhere above the last.
    """
    if "…" in shown:
        shown = [line for line in shown if line != "…"]
        for want in shown[:-1]:
            assert any(_same_line(got, want) for got in printed[:-1]), f"{command}: does not print\n{want}"
        printed, shown = printed[-1:], shown[-1:]
    for tie in _TIES.get(command, []):
        printed[tie], shown[tie] = sorted(printed[tie]), sorted(shown[tie])
    assert len(printed) == len(shown), f"{command}: prints\n" + "\n".join(printed)
    for got, want in zip(printed, shown, strict=True):
        assert _same_line(got, want), f"{command}: prints\n{got}\nwhere the README shows\n{want}"


def _tour_params() -> list:
    params = []
    for command, shown in cli_tour():
        if "HOST" in command:  # the cluster example: HOST is the user's scheduler
            continue
        slow = command.split()[1] in _SLOW
        params.append(pytest.param(command, shown, id=command.split("#")[0].strip()[len("armlab "):],
                                   marks=[pytest.mark.slow] if slow else []))
    return params


@pytest.mark.parametrize(("command", "shown"), _tour_params())
def test_readme_cli_tour_prints_what_the_readme_shows(tmp_path, monkeypatch, command, shown):
    """Each command of the tour, run in a folder laid out as the repository (its example arm and studies), prints
    what the README shows under it (stdout, then stderr) and exits as the README says: 2 after an error line,
    the ``exit N`` of its comment, else 0."""
    argv = shlex.split(command, comments=True)
    assert argv[0] == "armlab"
    shutil.copytree(EXAMPLES, tmp_path / "scripts" / "examples")
    shutil.copytree(ROOT / "analysis" / "studies", tmp_path / "analysis" / "studies")
    monkeypatch.chdir(tmp_path)
    if argv[1] == "view":  # serves until Ctrl-C: here for 3 s, in its own process (it prints to the real stdout)
        result = subprocess.run([sys.executable, "-m", "armlab", *argv[1:], "--duration", "3"], capture_output=True,
                                text=True, timeout=300, check=False)
    else:
        result = armlab_main(*argv[1:])
    exit_comment = re.search(r"# exit (\d+)", command)
    expected = 2 if shown and shown[-1].startswith("armlab: error:") else int(exit_comment[1]) if exit_comment else 0
    assert result.returncode == expected, result.stderr
    if shown:
        assert_output_as_shown(" ".join(argv[1:]), (result.stdout + result.stderr).splitlines(), list(shown))


def python_blocks() -> list[tuple[str, str | None]]:
    """The README's ```python code blocks in order, each with the ```text block printed right after it (or None)."""
    pattern = r"```python\n(.*?)```\n(?:```text\n(.*?)```)?"
    return [(code, out or None) for code, out in re.findall(pattern, (ROOT / "README.md").read_text(), flags=re.S)]


def test_readme_python_blocks_run_and_print_what_the_readme_shows(tmp_path, monkeypatch, capsys):
    blocks = python_blocks()
    assert len(blocks) >= 4, "the README's Python section has its code blocks"
    shutil.copytree(EXAMPLES, tmp_path / "scripts" / "examples")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "readme"}
    for k, (code, shown) in enumerate(blocks, start=1):
        exec(compile(code, f"README.md python block {k}", "exec"), namespace)
        printed = capsys.readouterr().out
        if shown is not None:
            assert printed.rstrip() == shown.rstrip(), f"README python block {k} prints something else"
    assert (tmp_path / "runs" / "arm3r" / "drives.csv").is_file()


@pytest.mark.parametrize(("script", "args", "expected"), [
    ("size_drives.py", ["--tf", "1.5", "--out", "runs/drives"], ["joint1", "drives.csv"]),
    ("reachable.py", [], ["solution(s) reach", "position error"]),
    ("reachable.py", ["arm4r", "--position", "9,9,9"], ["not reachable: target"]),
    ("paper_figures.py", ["--out", "runs/figures"], ["max |τ|", "torques.png"]),
])
def test_example_scripts_run(tmp_path, script, args, expected):
    result = subprocess.run([sys.executable, str(EXAMPLES / script), *args], cwd=tmp_path, capture_output=True,
                            text=True, timeout=300, check=False)
    assert "Traceback" not in result.stderr, result.stderr
    for text in expected:
        assert text in result.stdout, result.stdout
    assert result.returncode == (1 if "not reachable" in expected[0] else 0)
    if "--out" in args:
        folder = tmp_path / args[args.index("--out") + 1]
        assert (folder / "summary.json").is_file() and (folder / "drives.png").is_file()
