"""``armlab list``, ``show``, ``fk`` and ``ik``: the arms, and their kinematics at the joint values given."""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np

from armlab.bounds import tolerated
from armlab.cli.args import add_arm, arm_of
from armlab.cli.collide import SCENE_HELP
from armlab.drives.train import DRIVE_FIELDS
from armlab.kinematics.differential import default_axes
from armlab.kinematics.ik import SEEDS, solve, target_pose
from armlab.models import ARMS, get_arm
from armlab.models.library import LIBRARY
from armlab.models.read_dh import dh_inertials
from armlab.values import joint_rates, joint_values, parse_floats

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["SINGULAR_SIGMA", "arm_info", "register"]


def _fmt(values: Iterable[float]) -> str:
    return "  ".join(f"{v:+.6f}" for v in values)


def _cmd_list(args: argparse.Namespace) -> int:
    for name in ARMS:
        arm = get_arm(name)
        print(f"{name:6s} {arm.n} DOF  {''.join(r.kind for r in arm.table.rows):6s} paper {arm.paper}")
    print("library arms (well-known arms, every number cited; their sources: armlab show NAME):")
    for name in LIBRARY:
        arm = get_arm(name)
        kinds = "".join(r.kind for r in arm.table.rows)
        print(f"{name:8s} {arm.n} DOF  {kinds:7s} {arm.paper.removeprefix('library: ').split(';')[0]}")
    return 0


def _limit_text(value: float | None, unit: str) -> str:
    return "unknown" if value is None else f"{value:.6g} {unit}"


def arm_info(arm: Arm) -> dict[str, Any]:
    """What ``armlab show`` prints: joints with every limit, links with mass data, DH table, gravity, the drive train
    (``None``: ideal drives) (SI)."""
    dh = arm.dh
    return {
        "name": arm.name,
        "paper": arm.paper,
        "dof": arm.n,
        "joints": [dict(joint, effort=lim.effort, velocity=lim.velocity)
                   for joint, lim in zip(arm.joints(), arm.limits, strict=True)],
        "units": {"revolute": {"position": "rad", "velocity": "rad/s", "effort": "N·m"},
                  "prismatic": {"position": "m", "velocity": "m/s", "effort": "N"}, "mass": "kg", "com": "m",
                  "inertia": "kg·m² about the centre of mass, in the link frame (links: the URDF's link frame "
                             "{i}; dh_links: DH frame i, as the table gives them)"},
        "has_dynamics": arm.has_dynamics,
        "links": arm.links(),
        "dh": None if dh is None else {
            "convention": dh.convention,
            "rows": [{"type": r.kind, "a": r.a, "alpha": r.alpha, "d": r.d, "theta": r.theta} for r in dh.rows]},
        "gravity": list(arm.gravity),
        "parameters": dict(arm.parameters),
        "urdf": None if arm.urdf_file is None else str(arm.urdf_file),
        "tool_frame": arm.tool_name,
        "drive_train": None if arm.drives is None else {
            **{name: arm.drives.per_joint(name).tolist() for name in DRIVE_FIELDS},
            "coulomb_speed": arm.drives.coulomb_speed},
        "tool_source": arm.tool_source,
        "dh_links": None if dh is None else _dh_links(arm),
    }


def _dh_links(arm: Arm) -> list[dict[str, Any]] | None:
    """A DH arm's links' mass data as its table gives them, in DH frame i (``None``: a kinematic arm)."""
    inertials = dh_inertials(arm)
    if inertials is None:
        return None
    return [{"name": f"link{i}", "mass": body.mass, "com": list(body.com), "inertia": [list(r) for r in body.inertia]}
            for i, body in enumerate(inertials, start=1)]


def _print_links(links: list[dict[str, Any]], frames: str) -> None:
    """The links' mass, centre of mass and inertia diagonal, one line each, under a line saying their ``frames``."""
    print(f"links: mass [kg], centre of mass [m] and inertia diagonal [kg·m²], {frames}")
    for link in links:
        com = ", ".join(f"{c:+.4g}" for c in np.where(np.abs(link["com"]) < 1e-12, 0.0, link["com"]))
        inertia = ", ".join(f"{v:.4g}" for v in np.diag(link["inertia"]))
        print(f"  {link['name']:10s} {link['mass']:10.6g}  com ({com})  I ({inertia})")


def _cmd_show(args: argparse.Namespace) -> int:
    arm = arm_of(args)
    info = arm_info(arm)
    if args.json:
        print(json.dumps(info, indent=2))
        return 0
    print(f"{arm.name}: {arm.paper}")
    print(f"URDF: {info['urdf'] or 'generated in memory'}   "
          f"gravity: ({', '.join(f'{g:g}' for g in arm.gravity)}) m/s²")
    print(f"tool frame: {arm.tool_name} ({arm.tool_source})")
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
    if arm.notes and info["dh"] is not None:  # a library arm: where each of its numbers comes from
        print("sources:")
        for key, note in arm.notes.items():
            print(f"  {key}: {note}")
    if not arm.has_dynamics:
        print("links: no mass data (a kinematic arm): torques and simulations need masses")
    else:
        if info["dh_links"] is not None:
            _print_links(info["dh_links"], "in DH frame i, as the table gives them (standard DH: at the link's far "
                         "end; modified: at joint i)")
        _print_links(info["links"], "in link frame {i} of the arm's URDF (origin on joint i's axis)")
    if arm.drives is not None:
        coulomb = ("Coulomb T_c+ and T_c− [N·m] (forwards, backwards)" if arm.drives.asymmetric
                   else "Coulomb T_c [N·m]")
        print("drive train: gear ratio G, rotor inertia J_m [kg·m², motor side], efficiency, viscous B [N·m·s/rad] "
              f"and {coulomb} (joint side)")
        for k, name in enumerate(arm.joint_names):
            values = "  ".join(f"{arm.drives.per_joint(field)[k]:<10.6g}" for field in arm.drives.fields())
            print(f"  {name:8s} {values}".rstrip())
    if arm.parameters and info["dh"] is None:
        print("parameters:")
        for key, value in arm.parameters.items():
            note = arm.notes.get(key, "")
            print(f"  {key:12s} {value:<12.6g} {note}")
    return 0


#: Smallest singular value of the tool Jacobian (m or rad per unit joint motion) up to which ``fk`` flags a singularity.
SINGULAR_SIGMA = 1e-6


def _cmd_fk(args: argparse.Namespace) -> int:
    arm = arm_of(args)
    q = joint_values(arm, args.q, args.deg)
    qd = joint_rates(arm, args.qd, args.deg, "--qd")
    qdd = joint_rates(arm, args.qdd, args.deg, "--qdd")
    fk = arm.forward(q)
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
        "singular": bool(tolerated(sigma, SINGULAR_SIGMA)),
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
    arm = arm_of(args)
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
    if args.collision_free or args.scene:
        # lazy: armlab.collision imports Drake (start-up time)
        from armlab.collision.clearance import contacts

        marks = contacts(arm, np.array(solutions), args.scene)
    else:
        marks = None
    if marks is not None and args.collision_free:
        kept = [k for k, (touching, _) in enumerate(marks) if not touching]
        if not kept:
            raise ValueError(f"{arm.name}: every solution found collides ({len(solutions)}: "
                             + "; ".join(", ".join(t) for t, _ in marks) + "): drop --collision-free to see them")
        solutions, marks = [solutions[k] for k in kept], [marks[k] for k in kept]
    if args.json:
        print(json.dumps({"arm": arm.name, "solutions": [s.tolist() for s in solutions]}
                         | ({} if marks is None else {"colliding_pairs": [t for t, _ in marks],
                                                      "min_clearance": [c for _, c in marks]}), indent=2))
        return 0
    unit = "deg" if args.deg else "SI"
    for k, q in enumerate(solutions):
        shown = np.where(arm.revolute, np.degrees(q), q) if args.deg else q
        mark = "" if marks is None else _mark(*marks[k])
        print(f"q ({unit}) = {_fmt(shown)}{mark}")
    return 0


def _mark(touching: list[str], clearance: float | None) -> str:
    """What an IK solution's line says of its collisions."""
    if touching:
        return "  colliding: " + ", ".join(touching)
    return "  collision-free" + ("" if clearance is None else f" (clearance {clearance * 1e3:.4g} mm)")


def register(subparsers: Any) -> None:
    """Add the ``list``, ``show``, ``fk`` and ``ik`` subcommands to the CLI's subparsers."""
    p = subparsers.add_parser("list")
    p.set_defaults(func=_cmd_list)

    p = subparsers.add_parser("show")
    add_arm(p)
    p.add_argument("--json", action="store_true", help="JSON output")
    p.set_defaults(func=_cmd_show)

    p = subparsers.add_parser("fk")
    add_arm(p)
    p.add_argument("--q", required=True, help="joint values v1,v2,… (rad and m; see --deg)")
    p.add_argument("--qd", help="joint rates v1,v2,… (rad/s and m/s; deg/s with --deg): print the tool's twist")
    p.add_argument("--qdd", help="joint accelerations (rad/s² and m/s²; deg/s² with --deg): the tool's acceleration")
    p.add_argument("--deg", action="store_true", help="revolute values in degrees")
    p.add_argument("--json", action="store_true", help="JSON output")
    p.set_defaults(func=_cmd_fk)

    p = subparsers.add_parser("ik")
    add_arm(p)
    p.add_argument("--target", required=True, help="tool position x,y,z in metres (rr: x,y)")
    p.add_argument("--rpy", help="tool orientation roll,pitch,yaw (rad; see --deg), R = Rz(yaw)·Ry(pitch)·Rx(roll) "
                   "as in URDF: makes the target a full pose")
    p.add_argument("--pitch", help="tool pitch θ2+θ3+θ4 (arm4r only, with a position target; default 0: the tool "
                   "x axis horizontal)")
    p.add_argument("--near", help="current joints v1,v2,…: nearest solution first")
    p.add_argument("--all", action="store_true",
                   help="every solution within the joint limits: rr, arm4r, r2t: every branch of the closed form; "
                   f"other arms: every distinct solution found from {SEEDS} starts of the numerical solver "
                   "(a target with fewer constraints than joints has a continuum: then the local solution and those at "
                   "its tool orientation, and for more than six joints at its values of joints 7 …); without --all, "
                   "the solution reached from --near (one start, a few ms)")
    p.add_argument("--deg", action="store_true", help="angles in degrees")
    p.add_argument("--collision-free", action="store_true",
                   help="only the solutions in which the arm touches neither itself nor an obstacle of --scene")
    p.add_argument("--scene", help=SCENE_HELP + "; each solution is marked colliding (with the pairs) or not")
    p.add_argument("--json", action="store_true", help="JSON output")
    p.set_defaults(func=_cmd_ik)
