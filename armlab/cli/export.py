"""``armlab export ARM --urdf FILE --dh FILE``: the arm as a URDF and as a DH table (:mod:`armlab.models.export`)."""

from __future__ import annotations

import argparse
from typing import Any

from armlab.cli.args import add_arm, arm_of
from armlab.models.export import check_output, export

__all__ = ["register"]


def _cmd_export(args: argparse.Namespace) -> int:
    if args.urdf is None and args.dh is None:
        raise ValueError("nothing to export: give --urdf FILE.urdf and/or --dh FILE.csv")
    for path, suffix, what in ((args.urdf, ".urdf", "--urdf"), (args.dh, ".csv", "--dh")):
        if path is not None:  # before the arm is read: a path that cannot be written costs nothing
            check_output(path, suffix, what)
    for path in export(arm_of(args), urdf=args.urdf, dh=args.dh):
        print(f"wrote {path}")
    return 0


def register(subparsers: Any) -> None:
    """Add the ``export`` subcommand to the CLI's subparsers."""
    p = subparsers.add_parser(
        "export",
        description="Write ARM as a URDF file (any arm: joint origins and axes from its geometry, each link's "
                    "mass, centre of mass and inertia in the URDF's link frames, a drive train as Drake's "
                    "<drake:gear_ratio>/<drake:rotor_inertia> tags) and/or as a DH table file (an arm made from "
                    "one: radians, mass data in the DH frames, '# base:' and '# tool:' lines), which ROS, Drake, "
                    "Pinocchio, MuJoCo and armlab read back to the same kinematics and dynamics (MuJoCo: an arm "
                    "with mass and inertia on every moving link; a one-line warning says when it will not load "
                    "the URDF, and why). Each file is written completely or not at all; a path that cannot be "
                    "written is refused first.")
    add_arm(p)
    p.add_argument("--urdf", metavar="FILE", help="the URDF file to write (FILE.urdf)")
    p.add_argument("--dh", metavar="FILE", help="the DH table file to write (FILE.csv)")
    p.set_defaults(func=_cmd_export)
