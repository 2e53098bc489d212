"""The ``armlab`` command line.

Subcommands: ``list``, ``show``, ``fk``, ``ik`` (here), ``simulate`` and ``diagram``
(:mod:`armlab.diagrams.commands`), ``view`` (:mod:`armlab.diagrams.view`) and
``reproduce`` (:mod:`armlab.scripts.reproduce`). Bad input ends with one line on stderr
and exit code 2; Drake is imported only by the commands that need it.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["joint_values", "load_arm", "main", "parse_floats"]


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line on stderr and exit code 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"armlab: error: {message}\n")


def parse_floats(text: str, name: str) -> list[float]:
    """``"1,2.5,-3"`` → ``[1.0, 2.5, -3.0]``; ValueError naming the bad item (text, NaN, inf)."""
    values = []
    for item in text.split(","):
        try:
            value = float(item)
        except ValueError:
            raise ValueError(f"{name}: {item.strip()!r} is not a number (expected comma-separated numbers)") from None
        if not math.isfinite(value):
            raise ValueError(f"{name}: {item.strip()!r} is not a finite number")
        values.append(value)
    return values


def load_arm(name: str) -> Arm:
    """A paper arm by name or a user arm from a ``.urdf`` / DH ``.csv`` file."""
    from armlab.models import get_arm

    return get_arm(name)


def joint_values(arm: Arm, text: str, deg: bool = False, name: str = "--q") -> np.ndarray:
    """Joint values from ``"v1,v2,…"``: count checked, revolute values converted from degrees if
    ``deg`` (prismatic values stay metres), and checked against the joint limits."""
    values = np.array(parse_floats(text, name))
    if values.size != arm.n:
        raise ValueError(f"{name}: {arm.name} has {arm.n} joints, got {values.size} values ({text})")
    if deg:
        values = np.where(arm.revolute, np.radians(values), values)
    return arm.check_q(values, name, deg)


def _fmt(values: Sequence[float]) -> str:
    return "  ".join(f"{v:+.6f}" for v in values)


def _cmd_list(args: argparse.Namespace) -> int:
    from armlab.models import ARMS, get_arm

    for name in ARMS:
        arm = get_arm(name)
        print(f"{name:6s} {arm.n} DOF  {''.join(r.kind for r in arm.table.rows):6s} paper {arm.paper}")
    return 0


def _cmd_show(args: argparse.Namespace) -> int:
    arm = load_arm(args.arm)
    info = {
        "name": arm.name,
        "paper": arm.paper,
        "joints": arm.joints(),
        "parameters": dict(arm.parameters),
        "urdf": str(arm.urdf_path),
        "tool_frame": arm.tool_name,
    }
    if args.json:
        print(json.dumps(info, indent=2))
        return 0
    print(f"{arm.name}: {arm.paper}")
    print(f"URDF: {info['urdf']}   tool frame: {arm.tool_name}")
    print("joints:")
    for joint in info["joints"]:
        unit = "rad" if joint["type"] == "revolute" else "m"
        limits = "unlimited" if joint["lower"] is None else f"[{joint['lower']:.6g}, {joint['upper']:.6g}] {unit}"
        print(f"  {joint['name']:8s} {joint['type']:9s} {limits}")
    print("parameters:")
    for key, value in arm.parameters.items():
        note = arm.notes.get(key, "")
        print(f"  {key:12s} {value:<12.6g} {note}")
    return 0


def _cmd_fk(args: argparse.Namespace) -> int:
    arm = load_arm(args.arm)
    q = joint_values(arm, args.q, args.deg)
    fk = arm.forward(q)
    result: dict[str, Any] = {
        "arm": arm.name,
        "q": q.tolist(),
        "tool": {"position": fk.tool[:3, 3].tolist(), "rotation": fk.tool[:3, :3].tolist()},
        "points": {name: p.tolist() for name, p in fk.points.items()},
    }
    if args.json:
        print(json.dumps(result, indent=2))
        return 0
    print(f"{arm.name}  q = {_fmt(q)}  (SI)")
    print(f"tool {arm.tool_name}: position [m] {_fmt(result['tool']['position'])}")
    for row in result["tool"]["rotation"]:
        print(f"     rotation      {_fmt(row)}")
    for name, p in result["points"].items():
        print(f"  {name:5s} {_fmt(p)}")
    return 0


def _cmd_ik(args: argparse.Namespace) -> int:
    from armlab.kinematics.ik import solve

    arm = load_arm(args.arm)
    target = np.array(parse_floats(args.target, "--target"))
    pitch = None
    if args.pitch is not None:
        values = parse_floats(args.pitch, "--pitch")
        if len(values) != 1:
            raise ValueError(f"--pitch {args.pitch}: give one angle (the tool pitch θ2+θ3+θ4 of arm4r)")
        (pitch,) = values
        pitch = math.radians(pitch) if args.deg else pitch
    near = joint_values(arm, args.near, args.deg, "--near") if args.near else None
    solutions = solve(arm, target, pitch=pitch, near=near, all_solutions=args.all)
    if args.json:
        print(json.dumps({"arm": arm.name, "solutions": [s.tolist() for s in solutions]}, indent=2))
        return 0
    unit = "deg" if args.deg else "SI"
    for q in solutions:
        shown = np.where(arm.revolute, np.degrees(q), q) if args.deg else q
        print(f"q ({unit}) = {_fmt(shown)}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The ``armlab`` argument parser with every subcommand."""
    from armlab import __version__
    from armlab.diagrams import commands, draw, view
    from armlab.scripts import reproduce

    parser = _Parser(prog="armlab", description="Serial robot arms modelled, checked and simulated with Drake.",
                     epilog="'armlab COMMAND --help' explains a command. 'armlab' alone prints this help and "
                            "exits with code 2; bad input ends with one line 'armlab: error: …' and code 2.")
    parser.add_argument("--version", action="version", version=f"armlab {__version__}",
                        help="print armlab's version and exit")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser, title="commands",
                                metavar="COMMAND")

    p = sub.add_parser("list", help="the arms, one line each")
    p.set_defaults(func=_cmd_list)

    p = sub.add_parser("show", help="an arm's joints, parameters and URDF")
    p.add_argument("arm", help="arm name (armlab list), or a .urdf / DH .csv file")
    p.add_argument("--json", action="store_true", help="JSON output")
    p.set_defaults(func=_cmd_show)

    p = sub.add_parser("fk", help="forward kinematics: tool pose and named points")
    p.add_argument("arm", help="arm name (armlab list), or a .urdf / DH .csv file")
    p.add_argument("--q", required=True, help="joint values v1,v2,… (rad and m; see --deg)")
    p.add_argument("--deg", action="store_true", help="revolute values in degrees")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_fk)

    p = sub.add_parser("ik", help="inverse kinematics: joint values reaching a target")
    p.add_argument("arm", help="arm name (armlab list), or a .urdf / DH .csv file")
    p.add_argument("--target", required=True, help="x,y,z in metres (rr: x,y)")
    p.add_argument("--pitch", help="tool pitch θ2+θ3+θ4 (arm4r only; default 0: the tool x axis horizontal)")
    p.add_argument("--near", help="current joints v1,v2,…: nearest solution first")
    p.add_argument("--all", action="store_true", help="every solution within the joint limits")
    p.add_argument("--deg", action="store_true", help="angles in degrees")
    p.add_argument("--json", action="store_true", help="JSON output")
    p.set_defaults(func=_cmd_ik)

    commands.register(sub)
    view.register(sub)
    draw.register(sub)
    reproduce.register(sub)

    return parser


_VALUE_OPTIONS = ("--q", "--target", "--near", "--from", "--to", "--pitch", "--gravity")


def _join_negative_values(argv: Sequence[str]) -> list[str]:
    """``--q -1,2`` → ``--q=-1,2``, ``--gravity -y`` → ``--gravity=-y``: argparse takes a value starting with
    "-" for an option. A value option takes the next item as its value unless that is a long option."""
    out: list[str] = []
    for item in argv:
        if out and out[-1] in _VALUE_OPTIONS and item[:1] == "-" and item[:2] != "--":
            out[-1] = f"{out[-1]}={item}"
        else:
            out.append(item)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; returns the exit code."""
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv:  # no command: the usage and the list of commands, exit code 2 (as for any usage error)
        parser.print_help()
        return 2
    args = parser.parse_args(_join_negative_values(argv))
    try:
        return int(args.func(args) or 0)
    except (ValueError, OSError) as error:
        print(f"armlab: error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
