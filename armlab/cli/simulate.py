"""``armlab simulate`` and ``armlab diagram``: paper 000's Fig. 6 run for any arm, and its picture.

``armlab simulate ARM --out DIR`` runs the arm's paper motion (:func:`armlab.planning.motions.paper_motion`)
or the motion the options give, through the Drake diagram of :mod:`armlab.diagrams.build`, and writes
``log.csv``, ``summary.json``, ``diagram.svg`` (the Fig. 6 view, :func:`~armlab.presentation.graphviz.fig6_dot`),
``diagram_full.svg`` (Drake's whole graph, also as ``diagram.dot``), the plots and ``replay.html`` (the run as
a 3-D animation, :mod:`armlab.presentation.replay`) into DIR, all or nothing.
``armlab diagram ARM --out FILE.{dot,svg,png,pdf}`` writes the diagram alone.

Drake is imported only when a command runs, so ``armlab --help`` stays fast.
"""

from __future__ import annotations

import argparse
import sys
import textwrap
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from armlab.cli.args import add_arm, add_drives, arm_of, integer, number
from armlab.cli.collide import SCENE_HELP
from armlab.controllers.sensors import ENCODER_SIDES, VELOCITY_SOURCES
from armlab.controllers.servo import CONTROLLERS
from armlab.diagrams.drives import DIVERGENCE_TOLERANCE, check_tolerance, format_violation
from armlab.drives.motor import DEFAULT_CURRENT_BANDWIDTH
from armlab.drives.read import with_drives
from armlab.kinematics.quintic import Motion, QuinticSegment, check_duration
from armlab.limits import allowed, check_range
from armlab.planning.motions import SEGMENTS_FILE_HELP, paper_motion, quintic_motion, read_segments
from armlab.values import joint_values, parse_floats

if TYPE_CHECKING:
    from armlab.diagrams.run import Run
    from armlab.kinematics.quintic import Motion
    from armlab.models.arm import Arm

__all__ = ["cmd_diagram", "cmd_simulate", "motion_from_args", "register", "run_status"]

_MOTION_HELP = (
    "Without motion options: the arm's paper motion — rr: paper 000 Fig. 3 (-38°,98° → 62°,68° in 2 s); "
    "rr --path abcd: 000's A-B-C-D-A (Figs. 8-10, 2 s per segment); rrrr: 000's constant rates "
    "ω = (7, 0.05, 0.05, 0.05) rad/s for 15 s; arm4r: 001's (2,0,0) → (1,1,1.4) m in 2 s; r2t: a demo part "
    "transfer (3 s); urm6: a demo from φ = 0 to paper 004's Table 1 (4 s)."
)


def _gains(text: str | None, default: float, name: str) -> float | list[float]:
    if text is None:
        return default
    values = parse_floats(text, name)
    return values[0] if len(values) == 1 else values


def motion_from_args(arm: Arm, args: argparse.Namespace, payload: float = 0.0,
                     gravity: str | ArrayLike | None = None) -> Motion:
    """The motion the options give: ``--segments`` (its ``"fastest"`` segments timed with the run's ``payload``, kg,
    and ``gravity``), ``--from``/``--to``, or the paper motion (``--path``, ``--tf``)."""
    tf = None
    if args.tf is not None:
        values = parse_floats(args.tf, "--tf") if isinstance(args.tf, str) else [args.tf]
        if len(values) != 1:
            raise ValueError(f"--tf {args.tf}: give one duration in seconds")
        tf = check_duration(values[0], "--tf")
    if args.segments is not None:
        if args.q_from or args.q_to or args.path or tf is not None:
            raise ValueError("--segments gives the whole motion: do not combine it with --from, --to, --path or --tf")
        return read_segments(arm, args.segments, payload, gravity)
    if args.q_from or args.q_to:
        if args.path:
            raise ValueError("--path is a paper motion: do not combine it with --from/--to")
        if not args.q_to:
            raise ValueError("--from needs --to (the end joints)")
        qf = joint_values(arm, args.q_to, args.deg, "--to")
        q0 = (joint_values(arm, args.q_from, args.deg, "--from") if args.q_from
              else paper_motion(arm).segments[0].q_start)
        return quintic_motion(arm, q0, qf, 2.0 if tf is None else tf,
                              f"rest-to-rest quintic from --from to --to in {2.0 if tf is None else tf:g} s")
    return paper_motion(arm, args.path, tf)


def _hold_motion(arm: Arm) -> Motion:
    """Standing still for 1 s at q = 0 (clipped into the limits): a trajectory for drawing a user arm's diagram."""
    q = np.clip(np.zeros(arm.n), *arm.limit_arrays())
    return Motion((QuinticSegment(q, q, 1.0, "hold"),), "standing still")


def _setup(arm: Arm, args: argparse.Namespace) -> dict[str, Any]:
    """The diagram options shared by both commands (and simulate's ``--accuracy``), checked before anything
    runs: ``ValueError`` naming a value outside its range (:data:`armlab.limits.LIMITS`)."""
    # lazy: armlab --help loads armlab.cli.simulate but not this (start-up time)
    from armlab.controllers.inverse_dynamics import DEFAULT_KD, DEFAULT_KP, gain_vector
    from armlab.values import check_payload, resolve_gravity

    if getattr(args, "accuracy", None) is not None:
        check_range(args.accuracy, "--accuracy")
    setup = {
        "gravity": resolve_gravity(arm, args.gravity),
        "payload": check_payload(args.payload, "--payload"),
        "mode": args.mode,
        **{name: default if text is None else gain_vector(_gains(text, default, f"--{name}"), arm.n, f"--{name}")
           for name, text, default in (("kp", args.kp, DEFAULT_KP), ("kd", args.kd, DEFAULT_KD), ("ki", args.ki, 0.0))},
        "controller": args.controller, "rate": args.rate, "bandwidth": args.bandwidth, "saturate": args.saturate,
        "anti_windup": not args.no_anti_windup, "encoder": args.encoder, "encoder_side": args.encoder_side,
        "velocity": args.velocity, "velocity_cutoff": args.velocity_cutoff, "noise": args.noise, "seed": args.seed,
        "delay": args.delay, "electrics": args.electrics, "current_rate": args.current_rate,
        "current_bandwidth": args.current_bandwidth, "elastic": args.elastic,
    }
    return setup


def _servo_lines(summary: dict[str, Any]) -> list[str]:
    """What ``armlab simulate`` prints of a servo run: its loop, tracking, saturation, current and energy."""
    servo = summary["servo"]
    if servo is None:
        return []
    rate = servo["rate_hz"]
    units = summary["joint_units"]

    def joints(values: list[float | None], unit: str | list[str], fmt: str = ".3g") -> str:
        unit_of = unit if isinstance(unit, list) else [unit] * len(values)
        return ", ".join(f"{i + 1}: " + ("—" if v is None else f"{v:{fmt}} {u}")
                         for i, (v, u) in enumerate(zip(values, unit_of, strict=True)))

    lines = [f"servo: {servo['controller']} {'continuous' if rate is None else f'at {rate:g} Hz'}; RMS tracking "
             f"error {joints(servo['rms_tracking_error'], units)}"]
    if servo["saturation_time"] is not None:
        lines.append(f"torque saturated for (s) {joints(servo['saturation_time'], 's', '.4g')}")
    if "peak_current" in servo:
        lines.append(f"peak current {joints(servo['peak_current'], 'A')}; peak voltage "
                     f"{joints(servo['peak_voltage'], 'V')}; at the bus voltage for "
                     f"{joints(servo['voltage_saturation_time'], 's', '.4g')}")
        energy = servo["energy"]
        lines.append(f"energy: electrical {joints(energy['electrical'], 'J')}; copper {joints(energy['copper'], 'J')}"
                     f"; balance residual (relative) {max(energy['relative_residual']):.2g}")
    return lines


def cmd_simulate(args: argparse.Namespace) -> int:
    """``armlab simulate``: see the module docstring. Exit 3 when the run diverged, or passed a limit with
    ``--strict-limits``."""
    # lazy: armlab --help loads armlab.cli.simulate but not this (start-up time)
    from armlab.api import simulate
    from armlab.collision.clearance import as_scene
    from armlab.diagrams.build import check_log_period
    from armlab.presentation.output import run_folder

    arm = with_drives(arm_of(args), args.drives)
    arm.require_dynamics("armlab simulate")  # before anything is printed (the plant checks it again)
    setup = _setup(arm, args)
    motion = motion_from_args(arm, args, setup["payload"], setup["gravity"])
    log_period = check_log_period(args.dt, min(m.duration for _, m in motion.runs()))
    tolerance = check_tolerance(args.divergence_tolerance)
    scene = as_scene(args.scene)
    with run_folder(args.out) as folder:  # made first: an unwritable or occupied --out is an error before the run
        print(f"{arm.name}: {motion.description}", flush=True)
        run = simulate(arm, motion, log_period=log_period, accuracy=args.accuracy, divergence_tolerance=tolerance,
                       scene=scene, **setup)
        summary = run.summary
        print(f"simulated {motion.duration:g} s in {run.log.wall_time:.2f} s ({summary['real_time_factor']:.1f}× "
              f"real time), mode {run.log.mode}, {summary['runs']['count']} run(s)", flush=True)
        written = run.write(folder, deg=args.deg)  # graphviz's dot missing: a warning main() shows as one line
    print("max |τ|: " + ", ".join(f"τ{i + 1} = {v:.4f} {u}" for i, (v, u) in enumerate(zip(
        summary["max_abs_torque"], summary["torque_units"], strict=True)))
          + f"; peak power {summary['peak_power']:.4g} W; max tracking error "
          + ", ".join(f"{v:.3g} {u}" for v, u in zip(summary["max_tracking_error"], summary["joint_units"],
                                                      strict=True)))
    for line in _servo_lines(summary):
        print(line)
    print(f"wrote {args.out}: {' '.join(written)}")
    return run_status(arm, run, args.strict_limits)


def run_status(arm: Arm, run: Run, strict_limits: bool) -> int:
    """What a simulated ``run`` of ``arm`` tells its command: a warning line on stderr for every limit it passed (the
    arm's, and those its motion was timed within) and every pair that collided; the exit status: 3 when it
    diverged (an error line), or passed a limit or collided with ``strict_limits``; else 0."""
    # lazy: armlab --help loads armlab.cli.simulate but not the collision checks (start-up time)
    from armlab.collision.clearance import format_collision

    for violation in run.violations:
        print(f"armlab: warning: {arm.name} {format_violation(violation)}", file=sys.stderr)
    for collision in run.collisions:
        print(f"armlab: warning: {arm.name} {format_collision(collision)}", file=sys.stderr)
    if run.diverged:
        d = run.summary["divergence"]
        print(f"armlab: error: the run diverged: {d['joint']} left the reference at t = {d['time']:.4g} s "
              f"(tolerance {d['tolerance']:g} {d['unit']}; its largest tracking error {d['max_error']:.3g} "
              f"{d['unit']}); "
              f"{'raise --kp/--kd' if run.log.mode == 'controller' else 'open-loop inverse dynamics does not '
                 'correct errors: use --mode controller'}", file=sys.stderr)
        return 3
    if (run.violations or run.collisions) and strict_limits:
        passed = [f"{count} {what}" for count, what in ((len(run.violations), "limit violation(s)"),
                                                        (len(run.collisions), "collision(s)")) if count]
        print(f"armlab: error: {' and '.join(passed)} (--strict-limits)", file=sys.stderr)
        return 3
    return 0


def cmd_diagram(args: argparse.Namespace) -> int:
    """``armlab diagram``: the Fig. 6 diagram of ARM as DOT, SVG, PNG or PDF (by the suffix of --out)."""
    # lazy: armlab --help loads armlab.cli.simulate but not this (start-up time)
    from armlab.diagrams.build import build_diagram
    from armlab.diagrams.simulate import SimulationOptions
    from armlab.models.plant import PlantOptions
    from armlab.presentation.graphviz import fig6_dot, graph_format, write_graph

    arm = with_drives(arm_of(args), args.drives)
    graph_format(args.out)
    arm.require_dynamics("armlab diagram (its Fig. 6 diagram holds the arm's plant)")
    setup = _setup(arm, args)
    motion = paper_motion(arm).runs()[0][1] if arm.motion is not None else _hold_motion(arm)
    gravity, payload = setup.pop("gravity"), setup.pop("payload")
    run = build_diagram(arm, motion, SimulationOptions(PlantOptions(gravity, payload, ideal_drives=True), **setup))
    dot = run.diagram.GetGraphvizString(max_depth=1)
    path = write_graph(dot if args.full else fig6_dot(dot), args.out)
    print(f"wrote {path}")
    return 0


def _diagram_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--mode", choices=("controller", "inverse_dynamics"), default="controller",
                   help="controller: computed torque with PD feedback (default); inverse_dynamics: torques from the "
                        "reference alone, open loop (SimMechanics' inverse-dynamics mode of paper 000 Fig. 6)")
    p.add_argument("--gravity", default="default",
                   help="default (the arm's: rr -y, others -z), off, +x/-x/+y/-y/+z/-z (9.81 m/s²), or gx,gy,gz in "
                        f"m/s², {allowed('gravity')}")
    p.add_argument("--payload", type=number, default=0.0, metavar="KG",
                   help=f"point mass at the tool point, kg (default 0; r2t's nominal payload is 20 kg; "
                        f"{allowed('payload')})")
    p.add_argument("--kp", help=f"position gain(s), 1/s²: one value or one per joint (default 100; {allowed('kp')})")
    p.add_argument("--kd", help=f"velocity gain(s), 1/s: one value or one per joint (default 20; {allowed('kd')})")
    p.add_argument("--ki", help=f"integral gain(s), 1/s³: one value or one per joint (default 0; {allowed('ki')})")
    servo = p.add_argument_group(
        "servo loop", "the loop a drive engineer builds (default: paper 000's ideal loop, continuous computed torque "
        "on the exact state); the gains kp, kd, ki are normalised by each joint's inertia J = M_ii at the start "
        "(K_p = J kp N·m/rad)")
    servo.add_argument("--controller", choices=CONTROLLERS, default="computed-torque",
                       help="computed-torque (default), pid (independent joints, no model), pd+feedforward "
                            "(PD plus the inverse dynamics of the reference)")
    servo.add_argument("--rate", type=number, metavar="HZ",
                       help=f"a sampled controller at this rate, its inputs held (default: continuous; "
                            f"{allowed('rate')})")
    servo.add_argument("--bandwidth", type=number, metavar="HZ",
                       help="the gains by the tuning rule: the position loop's -3 dB bandwidth (PD with a double "
                            "pole; pid: PID with a triple pole) instead of --kp/--kd/--ki")
    servo.add_argument("--saturate", action="store_true",
                       help="clamp the torque command at each joint's effort limit (and the drive's peak current)")
    servo.add_argument("--no-anti-windup", action="store_true",
                       help="let the integral wind up while saturated (default: back-calculation)")
    servo.add_argument("--encoder", type=integer, metavar="COUNTS",
                       help="encoder counts per revolution (needs --rate; default: the exact position)")
    servo.add_argument("--encoder-side", choices=ENCODER_SIDES, default="motor",
                       help="the encoder on the motor (default: resolution 2π/(counts·G) at the joint) or the joint")
    servo.add_argument("--velocity", choices=VELOCITY_SOURCES, default="state",
                       help="the measured velocity: state (a tachometer, default) or difference (of the positions)")
    servo.add_argument("--velocity-cutoff", type=number, metavar="HZ",
                       help="first-order low-pass of the velocity by difference")
    servo.add_argument("--noise", type=number, default=0.0, metavar="SIGMA",
                       help="position measurement noise, standard deviation, rad or m (default 0)")
    servo.add_argument("--seed", type=integer, default=0, help="the noise's seed (default 0)")
    servo.add_argument("--delay", type=integer, default=0, metavar="K", help="the measurement delayed K samples")
    servo.add_argument("--electrics", action="store_true",
                       help="simulate each motor's current loop and winding (the drive file's resistance, "
                            "inductance, torque_constant, bus_voltage columns): current and voltage logged")
    servo.add_argument("--current-rate", type=number, metavar="HZ",
                       help="the current loop sampled at this rate (default: continuous)")
    servo.add_argument("--current-bandwidth", type=number, default=DEFAULT_CURRENT_BANDWIDTH, metavar="HZ",
                       help=f"the current loop's bandwidth (default {DEFAULT_CURRENT_BANDWIDTH:g} Hz)")
    servo.add_argument("--elastic", action="store_true",
                       help="elastic joints: each rotor coupled to its link by the drive file's stiffness (N·m/rad) "
                            "and twist_damping columns (a two-mass model; a motor-side encoder reads the rotor)")
    add_drives(p)


def register(subparsers: Any) -> None:
    """Add the ``simulate`` and ``diagram`` subcommands to the CLI's subparsers."""
    p = subparsers.add_parser(
        "simulate",
        description=textwrap.fill(
            "Simulate ARM through paper 000's Fig. 6 as a Drake diagram (trajectory source → inverse dynamics "
            "controller → MultibodyPlant, with loggers) and write DIR/log.csv, summary.json, diagram.svg "
            "(Fig. 6 view), diagram_full.svg (Drake's whole graph), diagram.dot, joints.png, torques.png, "
            "tool_path.png, tool_motion.png and replay.html (the run as a 3-D "
            "animation that plays in any browser, no server or network needed).", 100)
        + "\n\n" + textwrap.fill(_MOTION_HELP, 100),
        epilog=SEGMENTS_FILE_HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_arm(p)
    p.add_argument("--from", dest="q_from", metavar="Q", help="start joints q1,q2,… (rad and m; see --deg)")
    p.add_argument("--to", dest="q_to", metavar="Q", help="end joints q1,q2,…: a rest-to-rest quintic")
    p.add_argument("--tf", metavar="T", help="duration, s (--from/--to: default 2; paper motions: their own; "
                                             "--path: per segment)")
    p.add_argument("--deg", action="store_true", help="revolute joint values in degrees")
    p.add_argument("--path", choices=("abcd",), help="rr: paper 000's A-B-C-D-A path (Figs. 8-10)")
    p.add_argument("--segments", metavar="FILE", help="a JSON file of segments (see below)")
    p.add_argument("--dt", type=number, default=1e-3, metavar="S", help="log period, s (default 0.001)")
    p.add_argument("--accuracy", type=number,
                   help=f"integrator target accuracy (default 1e-6, Runge-Kutta 5; {allowed('accuracy')})")
    p.add_argument("--strict-limits", action="store_true",
                   help="exit with status 3 when the run passes a position, velocity or effort limit or a pair "
                        "collides (always a warning on stderr and an entry in summary.json's limit_violations or "
                        "collisions)")
    p.add_argument("--scene", help=SCENE_HELP)
    p.add_argument("--divergence-tolerance", type=number, default=DIVERGENCE_TOLERANCE, metavar="E",
                   help=f"tracking error (rad or m) past which the run has diverged: exit status 3 "
                        f"(default {DIVERGENCE_TOLERANCE:g})")
    _diagram_options(p)
    p.add_argument("--out", required=True, metavar="DIR", help="output folder (written completely or not at all)")
    p.set_defaults(func=cmd_simulate)

    p = subparsers.add_parser("diagram",
                              description="Write the Drake diagram of ARM (the one armlab simulate runs) as paper "
                                          "000's Fig. 6 (connected ports only, signals named; --full: Drake's whole "
                                          "graph) as DOT, or SVG/PNG/PDF through graphviz's dot, chosen by the "
                                          "suffix of --out.")
    add_arm(p)
    _diagram_options(p)
    p.add_argument("--out", required=True, metavar="FILE", help="FILE.dot, FILE.svg, FILE.png or FILE.pdf")
    p.add_argument("--full", action="store_true", help="Drake's full graph (every port of every system) instead "
                                                       "of the Fig. 6 view (connected ports only, signals named)")
    p.set_defaults(func=cmd_diagram)
