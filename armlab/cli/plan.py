"""``armlab plan``: a tool line or arc by IK along it, timed by a profile or as fast as the limits allow; or a
joint motion around obstacles (``armlab plan ARM to --from Q --to Q --scene FILE``).

A thin layer over :func:`armlab.line`, :func:`armlab.arc`, :func:`armlab.fastest` and :func:`armlab.plan_path`
(:mod:`armlab.api`): it parses the points, prints the plan (duration, the joints at both ends and, with
``--fastest``, the minimum duration and the constraint active along the path; ``to``: the path's smallest
clearance, its length, the planning time and the timed duration), may plot ṡ against its limit curve (``--plot``)
and simulate it (``--simulate DIR``, :func:`armlab.simulate`), with a ``--payload`` at the tool (timed with it
too), warning of every limit the run passes (the ones the timing was planned within among them; exit 3 with
``--strict-limits``, as ``armlab simulate``). ``armlab simulate --segments`` runs the same paths from a file.
``to`` exits 3 when no path is found within ``--budget``.
"""

from __future__ import annotations

import argparse
import io
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from armlab.cli.args import add_arm, add_drives, arm_of, integer, number
from armlab.cli.collide import SCENE_HELP
from armlab.cli.simulate import run_status
from armlab.drives.read import with_drives
from armlab.files import write_file
from armlab.kinematics.cartesian import DEFAULT_SAMPLES, PROFILES
from armlab.kinematics.quintic import check_duration
from armlab.limits import allowed, check_count, check_range, per_joint
from armlab.presentation.figures import DPI
from armlab.values import check_payload, joint_values, parse_floats

if TYPE_CHECKING:
    from armlab.kinematics.quintic import Motion
    from armlab.models.arm import Arm
    from armlab.planning.timing import Fastest

__all__ = ["register"]


def _point(text: str, name: str) -> list[float]:
    """A point option ``x,y`` or ``x,y,z`` (m), each coordinate within :data:`armlab.limits.LIMITS`' range."""
    values = parse_floats(text, name)
    if len(values) not in (2, 3):
        raise ValueError(f"{name} {text!r} must be a point x,y or x,y,z in m")
    return check_range(values, name, key="coordinate").tolist()


def _motion(arm: Arm, args: argparse.Namespace) -> Motion:
    # lazy: the API loads the IK and the plant's modules (armlab --help stays fast)
    from armlab.api import arc, line

    q0 = None if args.q0 is None else joint_values(arm, args.q0, args.deg, "--q0")
    tf = args.tf
    if args.fastest and tf is None and args.profile != "trapezoid":
        tf = 1.0  # the path's parameter only: --fastest retimes it, keeping the geometric path
    timing = {"tf": tf, "profile": args.profile, "speed": args.speed, "acceleration": args.tool_acceleration,
              "q0": q0, "branch": args.branch, "samples": args.samples}
    if args.path == "line":
        start = None if args.start is None else _point(args.start, "--from")
        return line(arm, start, _point(args.end, "--to"), **timing)
    if args.through is not None:
        return arc(arm, through=[_point(text, "--through") for text in args.through], **timing)
    if args.centre is None or args.axis is None or args.start is None or args.angle is None:
        raise ValueError("an arc needs --through P1 P2 P3, or --centre, --axis, --from and --angle")
    angle = float(np.radians(args.angle)) if args.deg else args.angle
    return arc(arm, centre=_point(args.centre, "--centre"), axis=parse_floats(args.axis, "--axis"),
               start=_point(args.start, "--from"), angle=angle, **timing)


def _limits(arm: Arm, text: str | None, name: str) -> np.ndarray | None:
    """A limit option: one value for every joint, or one per joint (its count and range checked here to name the
    option; :data:`armlab.limits.LIMITS`' ``velocity_limit`` … ``motor_torque_limit``)."""
    if text is None:
        return None
    return check_range(per_joint(parse_floats(text, name), arm.n, name), name,
                       key=f"{name.removeprefix('--').replace('-', '_')}_limit")


def _plot(best: Fastest, arm: Arm, path: str) -> None:
    # lazy: matplotlib, only for --plot
    import matplotlib.pyplot as plt

    kind = Path(path).suffix.lower().lstrip(".")
    if kind not in ("png", "svg"):
        raise ValueError(f"--plot {path}: the file must end in .png or .svg")
    fig = best.rate_figure(f"{arm.name}: time-optimal path rate against its limit ({best.duration:.4g} s, Toppra)")
    data = io.BytesIO()
    fig.savefig(data, format=kind, dpi=DPI)
    plt.close(fig)
    write_file(path, data.getvalue())  # complete or not at all


def _cmd_plan_to(arm: Arm, args: argparse.Namespace) -> int:
    """``armlab plan ARM to``: :func:`armlab.plan_path`, printed (or JSON), simulated with ``--simulate``."""
    # lazy: the planner loads Drake's SceneGraph and Toppra
    from armlab.api import plan_path
    from armlab.planning.planner import NoPathError

    if args.end is None:
        raise ValueError("plan ARM to needs --to Q: the goal joint values")
    if args.start is None and arm.home is None:
        raise ValueError(f"{arm.name} names no home pose: give --from Q, the start joint values")
    q0 = np.array(arm.home) if args.start is None else joint_values(arm, args.start, args.deg, "--from")
    qf = joint_values(arm, args.end, args.deg, "--to")
    try:
        plan = plan_path(arm, q0, qf, args.scene, clearance=args.clearance, seed=args.seed, budget=args.budget,
                         velocity=_limits(arm, args.velocity, "--velocity"),
                         acceleration=_limits(arm, args.acceleration, "--acceleration"),
                         effort=_limits(arm, args.effort, "--effort"), grid=args.grid)
    except NoPathError as error:
        print(f"armlab: error: {error}", file=sys.stderr)
        return 3
    summary: dict[str, Any] = {
        "arm": arm.name, "scene": args.scene, "clearance": plan.clearance, "min_clearance": plan.min_clearance,
        "closest_pair": plan.closest_pair, "length": plan.length, "planning_time": plan.planning_time,
        "duration": plan.duration, "waypoints": plan.waypoints.tolist(), "nodes": plan.nodes,
        "configurations_checked": plan.samples_checked, "most_active": plan.timed.most_active}
    if args.simulate is not None:
        # lazy: the simulation loads Drake's systems
        from armlab.api import simulate

        run = simulate(arm, plan.motion, scene=args.scene)
        summary["simulation"] = {"out": args.simulate, "written": run.save(args.simulate),
                                 "max_tracking_error": run.summary["max_tracking_error"]}
    if args.json:
        print(json.dumps(summary, indent=2, default=lambda v: None))
        return 0
    where = "itself" if args.scene is None else f"itself and the obstacles of {args.scene}"
    print(f"{arm.name}: a path around {where}: {len(plan.waypoints)} waypoints ({plan.nodes} tree nodes, "
          f"{plan.samples_checked} configurations checked), smoothed")
    print(f"smallest clearance: {plan.min_clearance * 1e3:.4g} mm ({plan.closest_pair}; asked "
          f"{plan.clearance * 1e3:g} mm)")
    print(f"path length: {plan.length:.4g} (joint space, rad and m)")
    print(f"planning time: {plan.planning_time * 1e3:.4g} ms")
    print(f"timed as fast as the limits allow (Toppra): {plan.duration:.4g} s, mostly {plan.timed.most_active}")
    if args.simulate:
        sim = summary["simulation"]
        print(f"simulated: max tracking error {max(sim['max_tracking_error']):.3g}; wrote {args.simulate}: "
              f"{' '.join(sim['written'])}")
    return 0


#: The options of ``plan ARM to`` only, and of ``plan ARM line|arc`` only (given for the other: an error, not ignored).
_TO_ONLY = ("scene", "seed", "budget")
_PATH_ONLY = ("through", "centre", "axis", "angle", "tf", "speed", "tool_acceleration", "q0", "branch", "fastest",
              "plot")


#: The options of ``plan ARM arc`` only (given for a line: an error, not ignored).
_ARC_ONLY = ("through", "centre", "axis", "angle")


def _check_options(args: argparse.Namespace, defaults: dict[str, Any]) -> None:
    """A ``ValueError`` naming the options given that the path kind ignores, or an output given as empty text;
    the counts and the duration checked against their ranges (:data:`armlab.limits.LIMITS`), before any work."""
    for name in ("simulate", "plot"):
        if getattr(args, name) is not None and not getattr(args, name).strip():
            raise ValueError(f"--{name} {getattr(args, name)!r}: give a {'folder' if name == 'simulate' else 'file'} "
                             "name")
    ignored = _PATH_ONLY if args.path == "to" else (*_TO_ONLY, "clearance", *(_ARC_ONLY if args.path == "line" else ()))
    given = [name for name in ignored if getattr(args, name) != defaults[name]]
    if given:
        shown = ", ".join("--" + name.replace("_", "-") for name in given)
        why = ("it times the planned path as fast as the limits allow" if args.path == "to" else
               "--scene, --clearance, --seed and --budget plan a motion around obstacles: 'plan ARM to'"
               if any(name in (*_TO_ONLY, "clearance") for name in given) else
               "--through, --centre, --axis and --angle give an arc: 'plan ARM arc'")
        raise ValueError(f"{shown}: not an option of 'plan ARM {args.path}' ({why})")
    check_count(args.grid, "--grid", key="grid")
    if args.path != "to":
        check_count(args.samples, "--samples", key="samples")
        if args.tf is not None:
            check_duration(args.tf, "--tf")
        if args.angle is not None:
            check_range(args.angle, "--angle", key="angle")


def _error_unit(arm: Arm) -> str:
    """The unit of the largest tracking error over all joints: rad, m, or "rad or m" for a mixed arm."""
    return "rad" if arm.revolute.all() else "m" if not arm.revolute.any() else "rad or m"


def _cmd_plan(args: argparse.Namespace) -> int:
    _check_options(args, args.defaults)
    arm = with_drives(arm_of(args), args.drives)
    if args.path == "to":
        return _cmd_plan_to(arm, args)
    payload = check_payload(args.payload, "--payload")
    motion = _motion(arm, args)
    t = np.linspace(0.0, motion.duration, 4 * args.samples + 1)
    q = motion.evaluate(t, 1)[0]
    summary: dict[str, Any] = {"arm": arm.name, "motion": motion.description, "duration": motion.duration,
                               "payload_kg": payload, "q_start": q[0].tolist(), "q_end": q[-1].tolist(),
                               "q_min": q.min(axis=0).tolist(), "q_max": q.max(axis=0).tolist()}
    if args.fastest:
        # lazy: Drake's Toppra
        from armlab.api import fastest

        best = fastest(arm, motion, _limits(arm, args.velocity, "--velocity"),
                       _limits(arm, args.acceleration, "--acceleration"), _limits(arm, args.effort, "--effort"),
                       motor_speed=_limits(arm, args.motor_speed, "--motor-speed"),
                       motor_torque=_limits(arm, args.motor_torque, "--motor-torque"), grid=args.grid,
                       payload=payload)
        summary["fastest"] = {"duration": best.duration, "active_fraction": best.active_fraction,
                              "most_active": best.most_active,
                              "velocity_limits": best.limits.velocity.tolist(),
                              "acceleration_limits": best.limits.acceleration.tolist(),
                              "effort_limits": best.limits.effort.tolist(),
                              "friction_kept_free": best.friction.tolist(),
                              "slowed_intervals": best.slowed}
        if args.plot is not None:
            _plot(best, arm, args.plot)
        motion = best.motion
    elif args.plot is not None:
        raise ValueError("--plot draws the time-optimal path rate: give --fastest too")
    status = 0
    if args.simulate is not None:
        # lazy: the simulation loads Drake's systems
        from armlab.api import simulate

        run = simulate(arm, motion, payload=payload)
        summary["simulation"] = {"out": args.simulate, "written": run.save(args.simulate),
                                 "max_tracking_error": run.summary["max_tracking_error"],
                                 "max_abs_torque": run.summary["max_abs_torque"],
                                 "limit_violations": run.violations}
        status = run_status(arm, run, args.strict_limits)  # its warnings on stderr, before the plan on stdout
    elif args.strict_limits:
        raise ValueError("--strict-limits checks the simulated run: give --simulate DIR too")
    if args.json:
        print(json.dumps(summary, indent=2, default=lambda v: None))
        return status
    timed = args.tf is not None or args.profile == "trapezoid"
    print(f"{arm.name}: {summary['motion']}" + (f": {summary['duration']:.6g} s" if timed or not args.fastest else ""))
    scale = np.where(arm.revolute, np.degrees(1.0) if args.deg else 1.0, 1.0)
    unit = "(" + " or ".join(dict.fromkeys(("deg" if args.deg else "rad") if r else "m" for r in arm.revolute)) + ")"
    print(f"joints from {unit}  " + "  ".join(f"{v:+.6f}" for v in np.asarray(summary["q_start"]) * scale))
    print(f"joints to   {unit}  " + "  ".join(f"{v:+.6f}" for v in np.asarray(summary["q_end"]) * scale))
    if args.fastest:
        f = summary["fastest"]
        print(f"time-optimal (Toppra, {args.grid} grid points): {f['duration']:.6g} s; a limit is active on "
              f"{f['active_fraction']:.0%} of the path, mostly {f['most_active'] or 'none'}")
        if f["slowed_intervals"]:
            print(f"  slowed down on {f['slowed_intervals']} grid interval(s), where Toppra's timing passed a limit "
                  "between its grid points")
        if any(f["friction_kept_free"]):
            print("  the drives' friction kept free of the effort limits: " + ", ".join(
                f"{name} {v:.4g} {'N·m' if r else 'N'}"
                for name, v, r in zip(arm.joint_names, f["friction_kept_free"], arm.revolute, strict=True)))
    if args.simulate:
        sim = summary["simulation"]
        print(f"simulated{' the time-optimal motion' if args.fastest else ''}: max tracking error "
              f"{max(sim['max_tracking_error']):.3g} {_error_unit(arm)}; wrote {args.simulate}: "
              f"{' '.join(sim['written'])}")
    return status


def register(subparsers: Any) -> None:
    """Add the ``plan`` subcommand to the ``armlab`` CLI's subparsers."""
    p = subparsers.add_parser("plan")
    add_arm(p)
    p.add_argument("path", choices=("line", "arc", "to"), help="the tool's path (line, arc), or 'to': a collision-"
                   "free joint motion from --from to --to (RRT-Connect, smoothed, timed by Toppra)")
    p.add_argument("--from", dest="start", help="start point x,y(,z) m (line: default the tool at --q0; arc: with "
                   "--centre); to: start joint values (default the arm's home pose)")
    p.add_argument("--to", dest="end", help="line: end point x,y(,z) m; to: goal joint values")
    p.add_argument("--scene", help=SCENE_HELP)
    p.add_argument("--clearance", type=number, default=0.0, help="to: the least distance (m) kept from every obstacle "
                   "and between the arm's links (default 0)")
    p.add_argument("--seed", type=integer, default=0, help="to: the random search's seed (default 0)")
    p.add_argument("--budget", type=number, default=5.0, help="to: the search's time budget in s (default 5)")
    p.add_argument("--through", nargs=3, metavar="P", help="arc: three points x,y(,z), from the first by the second "
                   "to the third")
    p.add_argument("--centre", help="arc: centre x,y(,z) m")
    p.add_argument("--axis", help="arc: axis x,y,z (right-handed)")
    p.add_argument("--angle", type=number, help="arc: angle (rad; deg with --deg)")
    p.add_argument("--tf", type=number,
                   help=f"duration (s) of the profile (not needed with --fastest; {allowed('tf')})")
    p.add_argument("--profile", default="minimum-jerk", choices=PROFILES, help="time profile (default minimum-jerk)")
    p.add_argument("--speed", type=number, help="trapezoid: the tool's peak speed along the path (m/s)")
    p.add_argument("--tool-acceleration", type=number, help="trapezoid: the tool's peak acceleration (m/s²)")
    p.add_argument("--q0", help="start joints v1,v2,… (default: the IK solution nearest zero, or --branch)")
    p.add_argument("--branch", type=integer, help="closed-form IK branch at the start (rr: 0 θ2 ≥ 0, 1 θ2 ≤ 0)")
    p.add_argument("--samples", type=integer, default=DEFAULT_SAMPLES,
                   help=f"IK samples along the path (default {DEFAULT_SAMPLES}; {allowed('samples')})")
    p.add_argument("--fastest", action="store_true", help="time-optimal timing by Drake's Toppra within the limits")
    p.add_argument("--velocity", help="--fastest, to: joint velocity limits (one, or one per joint; default the "
                   "file's)")
    p.add_argument("--acceleration", help="--fastest, to: joint acceleration limits (default none)")
    p.add_argument("--effort", help="--fastest, to: joint effort limits (default the file's)")
    p.add_argument("--motor-speed", help="--fastest: motor speed limits, rad/s (one, or one per joint; through the "
                   "drive train's gear ratios)")
    p.add_argument("--motor-torque", help="--fastest: motor torque limits, N·m (through the gear ratios and "
                   "efficiencies)")
    add_drives(p)
    p.add_argument("--grid", type=integer, default=500,
                   help=f"--fastest, to: Toppra's grid points (default 500; {allowed('grid')})")
    p.add_argument("--plot", help="--fastest: write ṡ against its limit curve to this .png/.svg")
    p.add_argument("--simulate", metavar="DIR", help="simulate the plan (the time-optimal one with --fastest) "
                   "through paper 000's Fig. 6 diagram and write the run into DIR, as armlab simulate does")
    p.add_argument("--payload", type=number, default=0.0, metavar="KG",
                   help=f"point mass at the tool point, kg: the simulated run carries it and --fastest times the "
                        f"path with it (default 0; {allowed('payload')})")
    p.add_argument("--strict-limits", action="store_true",
                   help="--simulate: exit with status 3 when the run passes a limit (the arm's, or one --fastest "
                        "timed it within) or a pair collides (always a warning on stderr)")
    p.add_argument("--deg", action="store_true", help="--q0, --angle and the printed joints in degrees")
    p.add_argument("--json", action="store_true", help="JSON output")
    p.set_defaults(func=_cmd_plan)
    p.set_defaults(defaults={name: p.get_default(name) for name in (*_TO_ONLY, *_PATH_ONLY, "clearance", *_ARC_ONLY)})
