"""What every ``armlab`` command shares: the parser whose errors are one line, argparse value types, the help of
the ARM argument, the rewriting of negative values, and the one-line error on stderr."""

from __future__ import annotations

import argparse
import os
import re
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

__all__ = ["ARM_HELP", "Parser", "add_arm", "add_drives", "arm_of", "error_text", "integer",
           "join_negative_values", "number", "positive_int", "silence", "write_error", "write_warning"]

#: The help of every command's ARM argument.
ARM_HELP = "arm name (armlab list: paper and library arms), or a .urdf, .sdf, MJCF .xml or DH .csv file"


def add_arm(parser: argparse.ArgumentParser) -> None:
    """The ARM argument of a command, and the options that say how to read a URDF file's arm."""
    parser.add_argument("arm", help=ARM_HELP)
    parser.add_argument("--tool", metavar="LINK", help="a URDF's tool frame: this link (the last moving link or one "
                        "welded to it; default: the end of the chain; 'armlab show' lists the choices)")
    parser.add_argument("--package-path", metavar="DIR", action="append", default=[],
                        help="a folder holding the ROS packages of a URDF's package:// meshes (repeatable; "
                        "ROS_PACKAGE_PATH is searched too)")


def add_drives(parser: argparse.ArgumentParser) -> None:
    """The ``--drives FILE`` option: the arm's drive train from a drive file (:func:`armlab.drives.read.with_drives`
    applies it)."""
    parser.add_argument("--drives", metavar="FILE",
                        help="a drive file (CSV, one row per joint: gear_ratio, rotor_inertia, efficiency, viscous, "
                             "coulomb; see the README) giving the arm its drive train instead of the one its file "
                             "gives")


def arm_of(args: argparse.Namespace) -> Any:
    """The arm the options of :func:`add_arm` name (:func:`armlab.models.get_arm`)."""
    # lazy: armlab --help imports this module, not the arms (start-up time)
    from armlab.models import get_arm

    if args.tool is not None and not args.tool.strip():
        raise ValueError(f"--tool {args.tool!r}: give a link's name (armlab show lists the choices)")
    return get_arm(args.arm, args.tool, args.package_path)


#: An item that starts like a negative number: ``-1e-6``, ``-.5,2``, ``-inf`` (argparse knows only ``-1``, ``-0.5``).
_NEGATIVE = re.compile(r"-(\.?\d|inf|nan)", re.IGNORECASE)


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line on stderr and exit code 2; an item that starts like a negative
    number (:data:`_NEGATIVE`) is a value, and a one-value option takes ``--`` as its value (``--q=--``: the value
    ``"--"``, refused as a number is; argparse would give ``[]``)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        # an item that starts like a negative number is a value, not an option, wherever it stands: the third point
        # of --through P1 P2 P3 too (argparse 3.12 knows only -1 and -0.5; 3.13 reads -\.?\d as this does)
        self._negative_number_matcher = _NEGATIVE

    def _get_values(self, action: argparse.Action, arg_strings: list[str]) -> Any:
        if action.option_strings and action.nargs is None and arg_strings == ["--"]:
            value = self._get_value(action, "--")
            self._check_value(action, value)
            return value
        return super()._get_values(action, arg_strings)

    def error(self, message: str) -> NoReturn:
        write_error(message)
        raise SystemExit(2)


#: What a number option's error adds: the one rule for numbers as text (:func:`armlab.values.decimal`).
_PLAIN = "a plain decimal, e.g. 0.5, -2, 1e-3"


def number(text: str) -> float:
    """An argparse type: a number as a plain decimal (:func:`armlab.values.decimal`: not ``1_0``, ``0x1``, ``ten``);
    else the one-line error argparse prints. A non-finite one (``nan``, ``-inf``, ``1e400``) is returned as such, for
    the option's own check to refuse with its range."""
    # lazy: armlab --help imports this module but not numpy, which armlab.values does (start-up time)
    from armlab.values import NOT_FINITE, decimal

    try:
        return decimal(text)
    except ValueError as reason:
        if str(reason) == NOT_FINITE:
            return float(text)
        raise argparse.ArgumentTypeError(f"invalid float value: {text!r} ({_PLAIN})") from None


def integer(text: str) -> int:
    """An argparse type: a whole number in plain digits (``"42"``, ``"-1"``; :func:`armlab.values.decimal` without
    a point or an exponent: not ``1_000``, ``1e3`` or ``4.0``); else the one-line error argparse prints."""
    # lazy: armlab --help imports this module but not numpy, which armlab.values does (start-up time)
    from armlab.values import decimal

    try:
        decimal(text)
    except ValueError:
        pass
    else:
        if text.strip().lstrip("+-").isdecimal():
            return int(text)
    raise argparse.ArgumentTypeError(f"invalid int value: {text!r} (a whole number in digits, e.g. 42)")


def positive_int(text: str) -> int:
    """An argparse type: a whole number ≥ 1 as a plain decimal (``"4"``, ``"4.0"``, ``"1e9"``: :func:`number`); else
    the one-line error argparse prints."""
    try:
        value = number(text)
    except argparse.ArgumentTypeError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number ({_PLAIN})") from None
    if not value.is_integer() or value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number ≥ 1")
    return int(value)


_VALUE_OPTIONS = ("--q", "--qd", "--qdd", "--target", "--rpy", "--near", "--from", "--to", "--pitch", "--gravity")


def join_negative_values(argv: Sequence[str]) -> list[str]:
    """``--q -1,2`` → ``--q=-1,2``, ``--gravity -y`` → ``--gravity=-y``, ``--accuracy -1e-6`` → ``--accuracy=-1e-6``:
    argparse takes a value starting with "-" for an option. A value option takes the next item as its value
    unless that is a long option; any long option takes a next item that starts like a negative number."""
    out: list[str] = []
    for item in argv:
        previous = out[-1] if out else ""
        takes = previous in _VALUE_OPTIONS or (previous[:2] == "--" and previous != "--" and "=" not in previous
                                                and _NEGATIVE.match(item))
        if takes and item[:1] == "-" and item[:2] != "--":
            out[-1] = f"{previous}={item}"
        else:
            out.append(item)
    return out


def silence(stream: Any) -> None:
    """Point a stream that can no longer be written (a full disk, a closed pipe) at /dev/null, so that the
    interpreter's last flush of what it still holds succeeds (a failing one would change the exit code)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, stream.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # no file descriptor (a captured stream): nothing is left to flush
        pass


def write_error(message: str) -> None:
    """``armlab: error: MESSAGE`` as one line on stderr (line breaks in MESSAGE become spaces); dropped if stderr
    cannot be written (the exit code still says 2)."""
    _write_line("error", message)


def write_warning(message: str) -> None:
    """``armlab: warning: MESSAGE`` as one line on stderr, like :func:`write_error`."""
    _write_line("warning", message)


def _write_line(kind: str, message: str) -> None:
    try:
        sys.stderr.write(f"armlab: {kind}: {' '.join(message.splitlines())}\n")
        sys.stderr.flush()
    except OSError:
        silence(sys.stderr)


def error_text(error: Exception) -> str:
    """The error's text; for an operating-system error its reason and file, without the errno."""
    if isinstance(error, OSError) and error.strerror:
        return f"{error.filename}: {error.strerror}" if error.filename else error.strerror
    return str(error)
