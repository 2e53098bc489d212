"""The ``armlab`` command line: a thin layer over the library that parses the options and prints the results.
May import: base, kinematics, drives, models, collision, presentation, planning, controllers,
diagrams, sizing, analysis, api, papers.

One module per command family (:data:`COMMANDS` lists the commands, with the line `armlab --help` prints for
each; `armlab COMMAND` imports only its module): :mod:`~armlab.cli.kinematics` (``list``, ``show``, ``fk``, ``ik``),
:mod:`~armlab.cli.simulate` (``simulate``, ``diagram``), :mod:`~armlab.cli.view`, :mod:`~armlab.cli.draw`,
:mod:`~armlab.cli.reproduce`, :mod:`~armlab.cli.analysis` (``workspace``, ``sweep``) and
:mod:`~armlab.cli.export`, :mod:`~armlab.cli.plan`, :mod:`~armlab.cli.size` and :mod:`~armlab.cli.collide`
(``check``); what they share is in
:mod:`~armlab.cli.args`. Only this package imports argparse, and no library module imports it
(tests/test_layers.py). Bad input ends with one line on stderr and exit code 2; the heavy libraries
(:data:`armlab._lazy.LAZY_IMPORTS`: Drake …) are imported only by the commands that need them.
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
import warnings
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from importlib import import_module
from typing import Any

from armlab import __version__
from armlab.cli.args import Parser, error_text, join_negative_values, silence, write_error, write_warning
from armlab.files import stop_on_signals

__all__ = ["COMMANDS", "build_parser", "main"]

#: The message when the standard output is closed (``armlab list >&-``): nothing could be printed.
STDOUT_CLOSED = "standard output is closed"


#: Every command: the module of this package whose ``register`` adds its options, and its line in ``armlab --help``,
#: in that order. ``armlab COMMAND …`` imports only COMMAND's module (and the library it loads), ``armlab --help`` none.
COMMANDS: dict[str, tuple[str, str]] = {
    "list": ("kinematics", "the arms, one line each"),
    "show": ("kinematics", "an arm's joints, parameters and URDF"),
    "fk": ("kinematics", "forward kinematics: tool pose and named points"),
    "ik": ("kinematics", "inverse kinematics: joint values reaching a target position or pose"),
    "simulate": ("simulate", "simulate a motion through paper 000's Fig. 6 diagram; write log, summary, plots, "
                             "diagram"),
    "diagram": ("simulate", "write paper 000's Fig. 6 diagram of an arm as .dot, .svg, .png or .pdf"),
    "plan": ("plan", "a straight line or circular arc of the tool, timed or time-optimal; or 'to': a joint motion "
                     "around a scene's obstacles"),
    "view": ("view", "3-D view of an arm with a slider per joint (Meshcat, in a browser)"),
    "draw": ("draw", "draw an arm's kinematic scheme (frames, joint axes, DH or locating parameters) as .png, .svg or "
                     ".pdf"),
    "reproduce": ("reproduce", "regenerate the papers' figures and tables, with a report"),
    "workspace": ("analysis", "an arm's workspace: volume, reach, manipulability, singular configurations"),
    "sweep": ("analysis", "a design study: candidates evaluated on a Dask cluster into results.csv and plots"),
    "export": ("export", "write an arm as a URDF (any arm) or a DH table (an arm made from one)"),
    "size": ("size", "the motor and gearbox each joint needs, from catalogues, for a duty cycle and load cases"),
    "check": ("collide", "collision check: the clearance of every pair of links (and obstacles); exits 3 when a "
                         "pair is in contact"),
}

#: What a command module may pass to ``add_parser`` besides the name (the help is the command's line in COMMANDS).
_PARSER_OPTIONS = frozenset({"description", "epilog", "formatter_class"})


class _Commands:
    """The subparsers as a command module's ``register`` sees them: ``add_parser(name, **options)`` returns the
    parser :func:`build_parser` made for ``name`` (a command of :data:`COMMANDS`), given ``options``
    (:data:`_PARSER_OPTIONS`)."""

    def __init__(self, parsers: Mapping[str, argparse.ArgumentParser]) -> None:
        self._parsers = parsers

    def add_parser(self, name: str, **options: Any) -> argparse.ArgumentParser:
        if name not in self._parsers:
            raise KeyError(f"command {name!r} is not in armlab.cli.COMMANDS")
        unknown = set(options) - _PARSER_OPTIONS
        if unknown:
            raise TypeError(f"add_parser({name!r}): {sorted(unknown)} not among {sorted(_PARSER_OPTIONS)}")
        parser = self._parsers[name]
        for key, value in options.items():
            setattr(parser, key, value)
        return parser


def build_parser(commands: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """The ``armlab`` argument parser: every command listed, with the options of those in ``commands`` (names of
    :data:`COMMANDS`; the default None: of every command). A name not in COMMANDS adds nothing (argparse rejects it
    as an invalid choice)."""
    parser = Parser(prog="armlab", description="Serial robot arms modelled, checked and simulated with Drake.",
                    epilog="'armlab COMMAND --help' explains a command. 'armlab' alone prints this help and "
                           "exits with code 2; bad input ends with one line 'armlab: error: …' and code 2.")
    parser.add_argument("--version", action="version", version=f"armlab {__version__}",
                        help="print armlab's version and exit")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser, title="commands",
                                metavar="COMMAND", help="what to do (below); 'armlab COMMAND --help' for its options")
    parsers = {name: sub.add_parser(name, help=line) for name, (_, line) in COMMANDS.items()}
    wanted = COMMANDS if commands is None else [name for name in commands if name in COMMANDS]
    for module in dict.fromkeys(COMMANDS[name][0] for name in wanted):
        # the command modules (and the library they load: numpy, the arms …) are imported here, not at the top, so
        # that main's stop-signal handlers are in place first (a Ctrl-C during the start-up is handled like any
        # other), and only the one the command line names (start-up time: armlab --help imports none)
        import_module(f"armlab.cli.{module}").register(_Commands(parsers))
    return parser


def _command(argv: Sequence[str]) -> list[str]:
    """The command ``argv`` names, as a list of one: its first word that is not an option (the options before it are
    armlab's own, ``-h`` and ``--version``, which take no value); empty when it names none."""
    return [word for word in argv if not word.startswith("-")][:1]


def _run(argv: list[str]) -> int:
    parser = build_parser(_command(argv))
    if not argv:  # no command: the usage and the list of commands, exit code 2 (as for any usage error)
        parser.print_help()
        return 2
    args = parser.parse_args(join_negative_values(argv))
    return int(args.func(args) or 0)


def _closed_stderr_to_devnull() -> None:
    """A closed stderr (``armlab … 2>&-``; Python then has no ``sys.stderr``) becomes /dev/null: the messages are
    dropped, the exit code stays what it says, and a child process (dot, a worker) gets a file descriptor 2."""
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w")  # open until the process ends


class _HeldLog(logging.Handler):
    """Drake's log lines (its ``drake`` logger: a file's unknown transmission joint, an MJCF attribute Drake ignores,
    Meshcat's "does not display HalfSpace geometry") held during a command, each distinct message once."""

    def __init__(self) -> None:
        super().__init__()
        self.records: dict[str, logging.LogRecord] = {}

    def emit(self, record: logging.LogRecord) -> None:
        self.records.setdefault(record.getMessage(), record)


@contextmanager
def _drake_log_held() -> Iterator[_HeldLog]:
    """Inside, Drake's log lines are held (:class:`_HeldLog`), not printed; its logger as it was on leaving."""
    logger = logging.getLogger("drake")
    handlers, propagate = logger.handlers[:], logger.propagate
    held = _HeldLog()
    logger.handlers, logger.propagate = [held], False
    try:
        yield held
    finally:
        logger.handlers, logger.propagate = handlers, propagate


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; returns the exit code.

    0: done; 2: bad input, told in one line ``armlab: error: …`` on stderr, and a closed standard output
    (``armlab list >&-``: nothing is run); 130 / 143: stopped by SIGINT / SIGTERM, every temporary removed
    (:func:`armlab.files.stop_on_signals`); 141: the reader of the output went away (``armlab … | head``),
    quietly, as Unix tools do. A closed stderr changes no exit code. Warnings (numpy's overflow …) and Drake's
    log lines (each distinct one once) are shown after a command that succeeded and dropped after an error, whose
    line stays the only one on stderr.
    """
    _closed_stderr_to_devnull()
    if sys.stdout is None:  # fd 1 closed when Python started
        write_error(STDOUT_CLOSED)
        return 2
    with stop_on_signals() as signals, warnings.catch_warnings(record=True) as caught, _drake_log_held() as log:
        try:
            try:
                code = _run(sys.argv[1:] if argv is None else list(argv))
            except SystemExit as stop:  # argparse: --help, --version, a usage error
                code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 2)
            sys.stdout.flush()  # a full disk or a closed pipe shows here, not at the interpreter's exit
        except BrokenPipeError:
            silence(sys.stdout)
            return 141
        except (ValueError, OSError) as error:
            caught.clear()
            log.records.clear()
            if not signals.received:
                write_error(error_text(error))
            code = 2
        except KeyboardInterrupt:
            code = 130
        except Exception:
            if not signals.received:
                raise
            code = 130  # what the stop signal became on its way (e.g. an ImportError when it hit an import)
    if signals.received:
        return 128 + signals.received
    for record in log.records.values():
        logging.getLogger("drake").handle(record)
    for warning in caught:
        if type(warning.message).__module__.startswith("armlab."):  # armlab's own (graphviz's dot missing): one line
            write_warning(str(warning.message))
        else:
            warnings.showwarning(warning.message, warning.category, warning.filename, warning.lineno)
    return code

