"""The README's Python blocks and the example scripts run as written, so they cannot rot."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "scripts" / "examples"


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
