"""The ``armlab`` command line: a thin layer over the library that parses the options and prints the results.
May import: base, kinematics, drives, models, collision, presentation, planning, controllers,
diagrams, sizing, analysis, api, papers.

One module per command family: :mod:`~armlab.cli.kinematics` (``list``, ``show``, ``fk``, ``ik``),
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
import os
import sys
import warnings
from collections.abc import Sequence

from armlab import __version__
from armlab.cli.args import Parser, error_text, join_negative_values, silence, write_error, write_warning
from armlab.files import stop_on_signals

__all__ = ["build_parser", "main"]

#: The message when the standard output is closed (``armlab list >&-``): nothing could be printed.
STDOUT_CLOSED = "standard output is closed"


def build_parser() -> argparse.ArgumentParser:
    """The ``armlab`` argument parser with every subcommand."""
    # lazy: the command modules (and the library they load: numpy, the arms …) are imported here, not at the top, so
    # that main's stop-signal handlers are in place first: a Ctrl-C during the start-up is handled like any other.
    from armlab.cli import analysis, collide, draw, export, kinematics, plan, reproduce, simulate, size, view

    parser = Parser(prog="armlab", description="Serial robot arms modelled, checked and simulated with Drake.",
                    epilog="'armlab COMMAND --help' explains a command. 'armlab' alone prints this help and "
                           "exits with code 2; bad input ends with one line 'armlab: error: …' and code 2.")
    parser.add_argument("--version", action="version", version=f"armlab {__version__}",
                        help="print armlab's version and exit")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser, title="commands",
                                metavar="COMMAND", help="what to do (below); 'armlab COMMAND --help' for its options")
    kinematics.register(sub)
    simulate.register(sub)
    plan.register(sub)
    view.register(sub)
    draw.register(sub)
    reproduce.register(sub)
    analysis.register(sub)
    export.register(sub)
    size.register(sub)
    collide.register(sub)
    return parser


def _run(argv: list[str]) -> int:
    parser = build_parser()
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


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; returns the exit code.

    0: done; 2: bad input, told in one line ``armlab: error: …`` on stderr, and a closed standard output
    (``armlab list >&-``: nothing is run); 130 / 143: stopped by SIGINT / SIGTERM, every temporary removed
    (:func:`armlab.files.stop_on_signals`); 141: the reader of the output went away (``armlab … | head``),
    quietly, as Unix tools do. A closed stderr changes no exit code. Warnings (numpy's overflow …) are shown
    after a command that succeeded and dropped after an error, whose line stays the only one on stderr.
    """
    _closed_stderr_to_devnull()
    if sys.stdout is None:  # fd 1 closed when Python started
        write_error(STDOUT_CLOSED)
        return 2
    with stop_on_signals() as signals, warnings.catch_warnings(record=True) as caught:
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
    for warning in caught:
        if type(warning.message).__module__.startswith("armlab."):  # armlab's own (graphviz's dot missing): one line
            write_warning(str(warning.message))
        else:
            warnings.showwarning(warning.message, warning.category, warning.filename, warning.lineno)
    return code

