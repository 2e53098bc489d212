"""``armlab draw ARM``: the arm's kinematic scheme (:func:`armlab.presentation.draw.draw_arm`) into a picture file."""

from __future__ import annotations

import argparse
from typing import Any

from armlab.cli.args import add_arm, arm_of
from armlab.presentation.draw import default_q, draw_arm
from armlab.values import joint_values

__all__ = ["register"]


def _cmd_draw(args: argparse.Namespace) -> int:
    arm = arm_of(args)
    q = joint_values(arm, args.q, args.deg) if args.q is not None else default_q(arm)
    path = draw_arm(arm, q, args.out)
    print(f"wrote {path}")
    return 0


def register(subparsers: Any) -> None:
    """Add the ``draw`` subcommand to the CLI's subparsers."""
    p = subparsers.add_parser("draw",
                              description="Draw ARM's kinematic scheme at the joint values --q, like the papers' "
                                          "figures: links, joint axes, frames {0}…{n} and the tool as RGB triads, "
                                          "and the DH (a, α, d, θ) or locating (P_i, k_i) parameters.")
    add_arm(p)
    p.add_argument("--q", help="joint values v1,v2,… (rad and m; see --deg); default: a paper arm's paper motion "
                               "start, other arms' zeros (within the limits)")
    p.add_argument("--deg", action="store_true", help="revolute values in degrees")
    p.add_argument("--out", required=True, metavar="FILE", help="FILE.png, FILE.svg or FILE.pdf")
    p.set_defaults(func=_cmd_draw)
