"""What a new user meets first: ``armlab`` alone, ``--version``, and help on every argument."""

from __future__ import annotations

import argparse
import subprocess
import sys

import pytest

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


def test_help_imports_no_command_module_nor_numpy():
    """``armlab --help`` lists every command from armlab.cli.COMMANDS without importing the command modules or the
    library (start-up time); ``armlab fk --help`` imports only the module of fk."""
    code = ("import sys; from armlab.cli import main\n"
            "try:\n    main([*sys.argv[1:], '--help'])\nexcept SystemExit:\n    pass\n"
            "print(sorted(m for m in sys.modules if m.startswith(('armlab.cli.', 'numpy'))))")
    listed = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert listed.stdout.splitlines()[-1] == "['armlab.cli.args']"
    assert "    fk        forward kinematics" in listed.stdout
    fk = subprocess.run([sys.executable, "-c", code, "fk"], capture_output=True, text=True, check=True)
    loaded = eval(fk.stdout.splitlines()[-1])
    assert "armlab.cli.kinematics" in loaded and "armlab.cli.simulate" not in loaded and "numpy" in loaded
    assert "usage: armlab fk [-h]" in fk.stdout


def test_every_command_has_its_options_and_commands_lists_each_once():
    """A command's own parser from build_parser([name]) is the one build_parser() gives (same help), and a module's
    register can fill in only the commands COMMANDS names."""
    from armlab.cli import COMMANDS, _Commands

    every = commands(build_parser())
    assert list(every) == list(COMMANDS)
    for name in COMMANDS:
        assert commands(build_parser([name]))[name].format_help() == every[name].format_help(), name
    with pytest.raises(KeyError, match=r"'nothing' is not in armlab\.cli\.COMMANDS"):
        _Commands({}).add_parser("nothing")
    with pytest.raises(TypeError, match="aliases"):
        _Commands({"fk": argparse.ArgumentParser()}).add_parser("fk", aliases=["f"])
