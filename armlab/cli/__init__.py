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
import os
import re
import sys
import warnings
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["joint_values", "load_arm", "main", "parse_floats"]


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line on stderr and exit code 2."""

    def error(self, message: str) -> NoReturn:
        _write_error(message)
        raise SystemExit(2)


def positive_int(text: str) -> int:
    """An argparse type: a whole number ≥ 1 (``"4"``, ``"4.0"``); else the one-line error argparse prints."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not value.is_integer() or value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number ≥ 1")
    return int(value)


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


def _limit_text(value: float | None, unit: str) -> str:
    return "unknown" if value is None else f"{value:.6g} {unit}"


def arm_info(arm: Arm) -> dict[str, Any]:
    """What ``armlab show`` prints: joints with every limit, links with mass data, DH table, gravity (SI)."""
    dh = arm.dh
    return {
        "name": arm.name,
        "paper": arm.paper,
        "dof": arm.n,
        "joints": [dict(joint, effort=lim.effort, velocity=lim.velocity)
                   for joint, lim in zip(arm.joints(), arm.limits, strict=True)],
        "units": {"revolute": {"position": "rad", "velocity": "rad/s", "effort": "N·m"},
                  "prismatic": {"position": "m", "velocity": "m/s", "effort": "N"}, "mass": "kg", "com": "m",
                  "inertia": "kg·m² about the centre of mass, in the link frame"},
        "has_dynamics": arm.has_dynamics,
        "links": arm.links(),
        "dh": None if dh is None else {
            "convention": dh.convention,
            "rows": [{"type": r.kind, "a": r.a, "alpha": r.alpha, "d": r.d, "theta": r.theta} for r in dh.rows]},
        "gravity": list(arm.gravity),
        "parameters": dict(arm.parameters),
        "urdf": None if arm.urdf_file is None else str(arm.urdf_file),
        "tool_frame": arm.tool_name,
    }


def _cmd_show(args: argparse.Namespace) -> int:
    arm = load_arm(args.arm)
    info = arm_info(arm)
    if args.json:
        print(json.dumps(info, indent=2))
        return 0
    print(f"{arm.name}: {arm.paper}")
    print(f"URDF: {info['urdf'] or 'generated in memory'}   tool frame: {arm.tool_name}   "
          f"gravity: ({', '.join(f'{g:g}' for g in arm.gravity)}) m/s²")
    print("joints:             position limits             velocity limit   effort limit")
    for joint in info["joints"]:
        units = info["units"][joint["type"]]
        limits = ("unlimited" if joint["lower"] is None
                  else f"[{joint['lower']:.6g}, {joint['upper']:.6g}] {units['position']}")
        velocity = _limit_text(joint["velocity"], units["velocity"])
        print(f"  {joint['name']:8s} {joint['type']:9s} {limits:27s} {velocity:16s} "
              f"{_limit_text(joint['effort'], units['effort'])}")
    if info["dh"] is not None:
        print(f"DH table ({info['dh']['convention']}; a, d in m, alpha, theta in rad):")
        print("  joint type        a      alpha          d      theta")
        for i, row in enumerate(info["dh"]["rows"], start=1):
            values = " ".join(f"{row[key]:+10.6g}" for key in ("a", "alpha", "d", "theta"))
            print(f"  {i:5d} {row['type']:4s} {values}")
    if not arm.has_dynamics:
        print("links: no mass data (a kinematic arm): torques and simulations need masses")
    else:
        print("links: mass [kg], centre of mass [m] and inertia diagonal [kg·m²], in link frame {i} (origin on "
              "joint i's axis)")
        for link in info["links"]:
            com = ", ".join(f"{c:+.4g}" for c in np.where(np.abs(link["com"]) < 1e-12, 0.0, link["com"]))
            inertia = ", ".join(f"{v:.4g}" for v in np.diag(link["inertia"]))
            print(f"  {link['name']:10s} {link['mass']:10.6g}  com ({com})  I ({inertia})")
    if arm.parameters and info["dh"] is None:
        print("parameters:")
        for key, value in arm.parameters.items():
            note = arm.notes.get(key, "")
            print(f"  {key:12s} {value:<12.6g} {note}")
    return 0


#: Smallest singular value of the tool Jacobian (m or rad per unit joint motion) below which ``fk`` flags a singularity.
SINGULAR_SIGMA = 1e-6


def _rates(arm: Arm, text: str | None, deg: bool, name: str) -> np.ndarray:
    """Joint rates from ``"v1,v2,…"`` (zeros when not given): count checked, deg/s converted if ``deg``."""
    if text is None:
        return np.zeros(arm.n)
    from armlab.limits import check_range

    values = np.array(parse_floats(text, name))
    if values.size != arm.n:
        raise ValueError(f"{name}: {arm.name} has {arm.n} joints, got {values.size} values ({text})")
    return check_range(np.where(arm.revolute, np.radians(values), values) if deg else values, name,
                       key="qdd" if name == "--qdd" else "qd")


def _cmd_fk(args: argparse.Namespace) -> int:
    arm = load_arm(args.arm)
    q = joint_values(arm, args.q, args.deg)
    qd = _rates(arm, args.qd, args.deg, "--qd")
    qdd = _rates(arm, args.qdd, args.deg, "--qdd")
    fk = arm.forward(q)
    from armlab.kinematics.differential import default_axes

    axes = default_axes(arm.n)
    sigma = float(arm.sigma_min(q, axes))
    result: dict[str, Any] = {
        "arm": arm.name,
        "q": q.tolist(),
        "tool": {"position": fk.tool[:3, 3].tolist(), "rotation": fk.tool[:3, :3].tolist()},
        "points": {name: p.tolist() for name, p in fk.points.items()},
        "jacobian_rows": axes,
        "manipulability": float(arm.manipulability(q, axes)),
        "sigma_min": sigma,
        "singular": sigma < SINGULAR_SIGMA,
    }
    if args.qd is not None or args.qdd is not None:
        twist, accel = arm.tool_motion(q, qd, qdd)
        result["tool"].update({"velocity": twist[:3].tolist(), "angular_velocity": twist[3:].tolist(),
                               "acceleration": accel[:3].tolist(), "angular_acceleration": accel[3:].tolist()})
    if args.json:
        print(json.dumps(result, indent=2))
        return 0
    if args.deg:
        print(f"{arm.name}  q = {_fmt(np.where(arm.revolute, np.degrees(q), q))}  (deg for revolute joints, m)")
    else:
        print(f"{arm.name}  q = {_fmt(q)}  (rad, m)")
    tool = result["tool"]
    print(f"tool {arm.tool_name}: position [m] {_fmt(tool['position'])}")
    for row in tool["rotation"]:
        print(f"     rotation      {_fmt(row)}")
    if "velocity" in tool:
        print(f"     velocity [m/s]           {_fmt(tool['velocity'])}")
        print(f"     angular velocity [rad/s] {_fmt(tool['angular_velocity'])}")
        print(f"     acceleration [m/s²]      {_fmt(tool['acceleration'])}")
        print(f"     angular accel. [rad/s²]  {_fmt(tool['angular_acceleration'])}")
    for name, p in result["points"].items():
        print(f"  {name:5s} {_fmt(p)}")
    rows = "[v; ω]" if axes == "all" else "v"
    flag = f"  SINGULAR (σ_min < {SINGULAR_SIGMA:g})" if result["singular"] else ""
    print(f"Jacobian rows {rows}: manipulability {result['manipulability']:.6g}, σ_min {sigma:.6g}{flag}")
    return 0


def _cmd_ik(args: argparse.Namespace) -> int:
    from armlab.kinematics.ik import solve, target_pose

    arm = load_arm(args.arm)
    target = np.array(parse_floats(args.target, "--target"))
    if args.rpy is not None:
        rpy = parse_floats(args.rpy, "--rpy")
        if len(rpy) != 3:
            raise ValueError(f"--rpy {args.rpy}: give 3 angles roll,pitch,yaw (R = Rz(yaw)·Ry(pitch)·Rx(roll))")
        target = target_pose(arm, target, np.radians(rpy) if args.deg else rpy)
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
    from armlab.analysis import commands as analysis_commands
    from armlab.diagrams import commands, draw, view
    from armlab.scripts import reproduce

    parser = _Parser(prog="armlab", description="Serial robot arms modelled, checked and simulated with Drake.",
                     epilog="'armlab COMMAND --help' explains a command. 'armlab' alone prints this help and "
                            "exits with code 2; bad input ends with one line 'armlab: error: …' and code 2.")
    parser.add_argument("--version", action="version", version=f"armlab {__version__}",
                        help="print armlab's version and exit")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser, title="commands",
                                metavar="COMMAND", help="what to do (below); 'armlab COMMAND --help' for its options")

    p = sub.add_parser("list", help="the arms, one line each")
    p.set_defaults(func=_cmd_list)

    p = sub.add_parser("show", help="an arm's joints, parameters and URDF")
    p.add_argument("arm", help="arm name (armlab list), or a .urdf / DH .csv file")
    p.add_argument("--json", action="store_true", help="JSON output")
    p.set_defaults(func=_cmd_show)

    p = sub.add_parser("fk", help="forward kinematics: tool pose and named points")
    p.add_argument("arm", help="arm name (armlab list), or a .urdf / DH .csv file")
    p.add_argument("--q", required=True, help="joint values v1,v2,… (rad and m; see --deg)")
    p.add_argument("--qd", help="joint rates v1,v2,… (rad/s and m/s; deg/s with --deg): print the tool's twist")
    p.add_argument("--qdd", help="joint accelerations (rad/s² and m/s²; deg/s² with --deg): the tool's acceleration")
    p.add_argument("--deg", action="store_true", help="revolute values in degrees")
    p.add_argument("--json", action="store_true", help="JSON output")
    p.set_defaults(func=_cmd_fk)

    from armlab.kinematics.ik import SEEDS

    p = sub.add_parser("ik", help="inverse kinematics: joint values reaching a target position or pose")
    p.add_argument("arm", help="arm name (armlab list), or a .urdf / DH .csv file")
    p.add_argument("--target", required=True, help="tool position x,y,z in metres (rr: x,y)")
    p.add_argument("--rpy", help="tool orientation roll,pitch,yaw (rad; see --deg), R = Rz(yaw)·Ry(pitch)·Rx(roll) "
                   "as in URDF: makes the target a full pose")
    p.add_argument("--pitch", help="tool pitch θ2+θ3+θ4 (arm4r only, with a position target; default 0: the tool "
                   "x axis horizontal)")
    p.add_argument("--near", help="current joints v1,v2,…: nearest solution first")
    p.add_argument("--all", action="store_true",
                   help="every solution within the joint limits: rr, arm4r, r2t: every branch of the closed form; "
                   f"other arms: every distinct solution found from {SEEDS} starts of the numerical solver "
                   "(a target with fewer constraints than joints has infinitely many: these are samples)")
    p.add_argument("--deg", action="store_true", help="angles in degrees")
    p.add_argument("--json", action="store_true", help="JSON output")
    p.set_defaults(func=_cmd_ik)

    commands.register(sub)
    view.register(sub)
    draw.register(sub)
    reproduce.register(sub)
    analysis_commands.register(sub)

    return parser


_VALUE_OPTIONS = ("--q", "--qd", "--qdd", "--target", "--rpy", "--near", "--from", "--to", "--pitch", "--gravity")


#: An item that starts like a negative number: ``-1e-6``, ``-.5,2``, ``-inf`` (argparse knows only ``-1``, ``-0.5``).
_NEGATIVE = re.compile(r"-(\.?\d|inf|nan)", re.IGNORECASE)


def _join_negative_values(argv: Sequence[str]) -> list[str]:
    """``--q -1,2`` → ``--q=-1,2``, ``--gravity -y`` → ``--gravity=-y``, ``--accuracy -1e-6`` → ``--accuracy=-1e-6``:
    argparse takes a value starting with "-" for an option. A value option takes the next item as its value
    unless that is a long option; any long option takes a next item that starts like a negative number."""
    out: list[str] = []
    for item in argv:
        previous = out[-1] if out else ""
        takes = previous in _VALUE_OPTIONS or (previous[:2] == "--" and "=" not in previous and _NEGATIVE.match(item))
        if takes and item[:1] == "-" and item[:2] != "--":
            out[-1] = f"{previous}={item}"
        else:
            out.append(item)
    return out


def _silence(stream: Any) -> None:
    """Point a stream that can no longer be written (a full disk, a closed pipe) at /dev/null, so that the
    interpreter's last flush of what it still holds succeeds (a failing one would change the exit code)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, stream.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # no file descriptor (a captured stream): nothing is left to flush
        pass


def _write_error(message: str) -> None:
    """``armlab: error: MESSAGE`` as one line on stderr (line breaks in MESSAGE become spaces); dropped if stderr
    cannot be written (the exit code still says 2)."""
    try:
        sys.stderr.write(f"armlab: error: {' '.join(message.splitlines())}\n")
        sys.stderr.flush()
    except OSError:
        _silence(sys.stderr)


def _message(error: Exception) -> str:
    """The error's text; for an operating-system error its reason and file, without the errno."""
    if isinstance(error, OSError) and error.strerror:
        return f"{error.filename}: {error.strerror}" if error.filename else error.strerror
    return str(error)


def _run(argv: list[str]) -> int:
    parser = build_parser()
    if not argv:  # no command: the usage and the list of commands, exit code 2 (as for any usage error)
        parser.print_help()
        return 2
    args = parser.parse_args(_join_negative_values(argv))
    return int(args.func(args) or 0)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; returns the exit code.

    0: done; 2: bad input, told in one line ``armlab: error: …`` on stderr; 130 / 143: stopped by SIGINT /
    SIGTERM, every temporary removed (:func:`armlab.files.stop_on_signals`); 141: the reader of the output
    went away (``armlab … | head``), quietly. Warnings (numpy's overflow …) are shown after a command that
    succeeded and dropped after an error, whose line stays the only one on stderr.
    """
    from armlab.files import stop_on_signals

    with stop_on_signals() as signals, warnings.catch_warnings(record=True) as caught:
        try:
            try:
                code = _run(sys.argv[1:] if argv is None else list(argv))
            except SystemExit as stop:  # argparse: --help, --version, a usage error
                code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 2)
            sys.stdout.flush()  # a full disk or a closed pipe shows here, not at the interpreter's exit
        except BrokenPipeError:
            _silence(sys.stdout)
            return 141
        except (ValueError, OSError) as error:
            caught.clear()
            if not signals.received:
                _write_error(_message(error))
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
        warnings.showwarning(warning.message, warning.category, warning.filename, warning.lineno)
    return code


if __name__ == "__main__":
    sys.exit(main())
