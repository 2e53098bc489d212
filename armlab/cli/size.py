"""``armlab size``: the motor and gearbox each joint needs, chosen from catalogues (:func:`armlab.size_drives`).

``armlab size ARM [motion options | --duty-cycle FILE] [--payload KG,…] [--load-cases FILE] [--motors CSV]
[--gearboxes CSV] [--safety-factor S] [--rank mass|margin|inertia] [--no-mass-iteration] [--ambient °C]
[--bus-voltage V] [--brake-factor K] [--required-life H] [--out DIR]`` prints one line per joint (its choice, or
the nearest pairs and the check each fails) and writes, with ``--out``, ``sizing.csv``, ``sizing.md`` and
``torque_speed_JOINT.png`` per joint into DIR (all or nothing). Exit 3 when a joint has no feasible pair (its
nearest candidates are printed; sizing.csv/md still written).
"""

from __future__ import annotations

import argparse
import textwrap
from contextlib import nullcontext
from typing import Any

from armlab.cli.args import add_arm, arm_of, number
from armlab.cli.simulate import motion_from_args
from armlab.limits import allowed, check_range
from armlab.planning.motions import SEGMENTS_FILE_HELP
from armlab.sizing.catalogue import GEARBOX_COLUMNS, MOTOR_COLUMNS
from armlab.sizing.checks import Conditions
from armlab.sizing.duty import DEFAULT_RATE, DUTY_FILE_HELP, LOAD_CASES_HELP
from armlab.sizing.select import RANKS
from armlab.values import check_payload, parse_floats

__all__ = ["EXIT_INFEASIBLE", "cmd_size", "register"]

#: Exit code when some joint has no feasible motor and gearbox.
EXIT_INFEASIBLE = 3


def cmd_size(args: argparse.Namespace) -> int:
    """``armlab size``: see the module docstring."""
    # lazy: armlab --help loads armlab.cli.size but not these (start-up time)
    from armlab.api import size_drives
    from armlab.sizing.duty import DutyCycle, load_cases_of, read_load_cases
    from armlab.sizing.report import sizing_folder, summary_lines, write_sizing

    check_range(args.rate, "--rate", key="sample_rate")  # before any work: 1e9 samples a second fill the memory
    if args.out is not None and not args.out.strip():
        raise ValueError(f"--out {args.out!r}: give a folder name (written completely or not at all)")
    arm = arm_of(args)
    arm.require_dynamics("armlab size")
    if args.duty_cycle is not None:
        if args.q_from or args.q_to or args.path or args.tf is not None or args.segments is not None:
            raise ValueError("--duty-cycle gives the whole cycle: do not combine it with --from, --to, --path, --tf "
                             "or --segments")
        cycle: Any = args.duty_cycle
    else:
        cycle = DutyCycle.of(motion_from_args(arm, args))
    payloads = [] if args.payload is None else [check_payload(m, "--payload") for m in parse_floats(args.payload,
                                                                                                   "--payload")]
    cases = list(load_cases_of(payloads)) if args.payload is not None else []
    if args.load_cases is not None:
        cases += read_load_cases(args.load_cases)
    conditions = Conditions(args.ambient, args.bus_voltage, args.brake_factor, args.required_life)
    folder = sizing_folder(args.out) if args.out is not None else None  # an unwritable --out: an error before
    # The temporary folder goes on any exit from here (an error or a stop signal during the sizing too).
    with folder if folder is not None else nullcontext() as tmp:
        sizing = size_drives(arm, cycle, cases or 0.0, args.motors, args.gearboxes, args.safety_factor, args.rank,
                             not args.no_mass_iteration, args.rate, conditions)
        lines = summary_lines(sizing)
        written = write_sizing(sizing, tmp) if tmp is not None else []
    print("\n".join(lines))
    if folder is not None:
        print(f"wrote {args.out}: {' '.join(written)}")
    return 0 if sizing.feasible else EXIT_INFEASIBLE


def register(subparsers: Any) -> None:
    """Add the ``size`` subcommand to the CLI's subparsers."""
    p = subparsers.add_parser(
        "size",
        description=textwrap.fill(
            "Choose every joint's motor and gearbox from the catalogues for the motion (or duty cycle) and every "
            "load case: RMS and peak motor torque (times the safety factor) within the motor's rated and peak "
            "torque, every operating point inside its torque-speed envelope, speeds within the motor's and the "
            "gearbox's, the gearbox's output torque within its ratings, and where the catalogues give the data: "
            "the inertia ratio, the voltage at the bus voltage, the drive's current and I2t, the winding "
            "temperature over the cycle repeated until periodic, the regenerated energy (DC-link capacitors or "
            "braking resistor), the holding brake and the gearbox life. A check without its data is reported as "
            "not checked. The chosen drives' masses are put on the links that carry them and the choice repeated "
            "until it holds. Prints one line per joint; --out writes sizing.csv, sizing.md and a torque-speed "
            "figure per joint.", 100),
        epilog=textwrap.dedent("""\
            motion: the arm's paper motion, --from/--to/--tf, --segments FILE (carrying the payload throughout),
            or --duty-cycle FILE.
            """) + DUTY_FILE_HELP + "\n" + LOAD_CASES_HELP + "\n" + SEGMENTS_FILE_HELP + textwrap.dedent(f"""

            motor catalogue (CSV) columns: name,{','.join(MOTOR_COLUMNS)}
              (the first six required); gearbox catalogue: name,{','.join(GEARBOX_COLUMNS)} (the first
              seven required). Without --motors/--gearboxes: armlab's example catalogues (illustrative values, not
              a vendor's; scripts/examples/catalogues/README.md says where real values come from).

            exit status: 0 a drive for every joint; 2 bad input; {EXIT_INFEASIBLE} a joint without a feasible motor and
            gearbox (its nearest candidates and the check each fails are printed)."""),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_arm(p)
    p.add_argument("--from", dest="q_from", metavar="Q", help="start joints q1,q2,… (rad and m; see --deg)")
    p.add_argument("--to", dest="q_to", metavar="Q", help="end joints q1,q2,…: a rest-to-rest quintic")
    p.add_argument("--tf", metavar="T", help="duration, s (--from/--to: default 2; paper motions: their own)")
    p.add_argument("--deg", action="store_true", help="revolute joint values in degrees")
    p.add_argument("--path", choices=("abcd",), help="rr: paper 000's A-B-C-D-A path (Figs. 8-10)")
    p.add_argument("--segments", metavar="FILE", help="a JSON file of segments (see below)")
    p.add_argument("--duty-cycle", metavar="FILE", help="a JSON duty cycle: moves and dwells, payload on or off")
    p.add_argument("--payload", metavar="KG", help="load cases: point masses at the tool, kg, e.g. 0,1,2 (default 0)")
    p.add_argument("--load-cases", metavar="FILE", help="load cases with offset and inertia (JSON, see below)")
    p.add_argument("--motors", metavar="CSV", help="motor catalogue (default: armlab's example)")
    p.add_argument("--gearboxes", metavar="CSV", help="gearbox catalogue (default: armlab's example)")
    p.add_argument("--safety-factor", type=number, default=1.0, metavar="S",
                   help="on every torque, ≥ 1 (default 1)")
    p.add_argument("--rank", choices=RANKS, default="mass",
                   help="order of the feasible pairs: lightest, largest margin or smallest inertia ratio first "
                        "(default mass)")
    p.add_argument("--no-mass-iteration", action="store_true",
                   help="size for the arm alone (do not put the chosen drives' masses on the links)")
    p.add_argument("--ambient", type=number, default=Conditions.ambient, metavar="°C",
                   help=f"ambient temperature of the motors (default {Conditions.ambient:g} °C, IEC 60034-1)")
    p.add_argument("--bus-voltage", type=number, metavar="V",
                   help="DC bus voltage of every drive (default: each drive's bus_voltage_V in the catalogue)")
    p.add_argument("--brake-factor", type=number, default=Conditions.brake_factor, metavar="K",
                   help=f"holding brake safety factor: T_H ≥ K·T_static/G (default {Conditions.brake_factor:g})")
    p.add_argument("--required-life", type=number, default=Conditions.required_life, metavar="H",
                   help=f"gearbox life required, L10 hours (default {Conditions.required_life:g})")
    p.add_argument("--rate", type=number, default=DEFAULT_RATE, metavar="HZ",
                   help=f"samples per second of motion (default {DEFAULT_RATE:g}; {allowed('sample_rate')})")
    p.add_argument("--out", metavar="DIR", help="output folder (written completely or not at all)")
    p.set_defaults(func=cmd_size)
