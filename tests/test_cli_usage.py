"""What a new user meets first: ``armlab`` alone, ``--version``, and help on every argument."""

from __future__ import annotations

import argparse
import subprocess
import sys

from armlab import __version__
from armlab.cli import build_parser


def armlab(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "armlab", *args], capture_output=True, text=True, timeout=120)


def commands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def test_armlab_alone_prints_the_usage_and_every_command_and_exits_2():
    out = armlab()
    assert out.returncode == 2
    assert out.stdout.startswith("usage: armlab")
    for name in commands(build_parser()):
        assert f"\n    {name} " in out.stdout or f"\n    {name}\n" in out.stdout, name
    assert out.stderr == ""


def test_version():
    out = armlab("--version")
    assert out.returncode == 0 and out.stdout.strip() == f"armlab {__version__}"


def test_every_argument_of_every_command_has_help():
    parser = build_parser()
    missing = [f"armlab {action.dest}" for action in parser._actions if not action.help]
    listing = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    missing += [f"armlab {c.dest} (in the list of commands)" for c in listing._choices_actions if not c.help]
    for name, sub in commands(parser).items():
        missing += [f"armlab {name} {'/'.join(a.option_strings) or a.dest}" for a in sub._actions if not a.help]
    assert missing == []
    assert {"draw", "diagram", "view", "simulate"} <= set(commands(parser))
