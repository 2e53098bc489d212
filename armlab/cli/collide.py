"""``armlab check``: the arm's clearances at the joint values given, by pair, against itself and a scene.

Exit status 0 when every pair is apart, 3 when a pair is in contact (the ``--strict-limits`` convention: a check
that fails), 2 for bad input."""

from __future__ import annotations

import argparse
import json
from typing import Any

from armlab.bounds import below
from armlab.cli.args import add_arm, arm_of, positive_int
from armlab.values import joint_values

__all__ = ["SCENE_HELP", "register"]

#: The help of ``--scene``, the same on every command that checks collisions.
SCENE_HELP = ("a scene file (JSON: boxes, cylinders, spheres, a floor, each with a pose; the README's 'Collisions' "
              "section): the arm is checked against its obstacles as well as itself")


def _cmd_check(args: argparse.Namespace) -> int:
    # lazy: armlab --help loads armlab.cli.collide but not this (Drake; start-up time)
    from armlab.collision.clearance import as_scene, clearance

    arm = arm_of(args)
    q = joint_values(arm, args.q, args.deg)
    rows = clearance(arm, q, as_scene(args.scene))
    touching = [row for row in rows if below(row["distance"], 0.0)]
    if args.json:
        print(json.dumps({"arm": arm.name, "q": q.tolist(), "units": "m", "in_contact": len(touching) > 0,
                          "clearances": rows}, indent=2))
        return 3 if touching else 0
    shown = rows if args.all else rows[: args.top]
    if not rows:
        print(f"{arm.name}: no pair to check (adjacent links are never checked; give --scene to check obstacles)")
        return 0
    print(f"{arm.name}: {len(rows)} pair(s) checked; "
          + (f"{len(touching)} in contact" if touching else "none in contact")
          + (f"; the {len(shown)} smallest clearances:" if shown else ""))
    for row in shown:
        state = f"in contact, penetration {row['depth'] * 1e3:.4g} mm" if below(row["distance"], 0.0) else "apart"
        print(f"  {row['pair']:28s} {row['distance'] * 1e3:+10.4f} mm  {state}")
    return 3 if touching else 0


def register(subparsers: Any) -> None:
    """Add the ``check`` subcommand to the CLI's subparsers."""
    p = subparsers.add_parser("check")
    add_arm(p)
    p.add_argument("--q", required=True, help="joint values v1,v2,… (rad and m; see --deg)")
    p.add_argument("--deg", action="store_true", help="revolute values in degrees")
    p.add_argument("--scene", help=SCENE_HELP)
    p.add_argument("--top", type=positive_int, default=5,
                   help="how many of the smallest clearances to print (default 5)")
    p.add_argument("--all", action="store_true", help="print every pair")
    p.add_argument("--json", action="store_true", help="JSON output: every pair with its closest points")
    p.set_defaults(func=_cmd_check)
