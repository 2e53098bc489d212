"""``armlab view ARM``: the arm in Meshcat with a slider per joint (:func:`armlab.presentation.view.run_view`)."""

from __future__ import annotations

import argparse
from typing import Any

from armlab.cli.args import add_arm, arm_of, integer, number
from armlab.presentation.view import PORT_TRIES, run_view
from armlab.values import joint_values

__all__ = ["register"]


def _cmd_view(args: argparse.Namespace) -> int:
    arm = arm_of(args)
    q0 = joint_values(arm, args.q, args.deg) if args.q is not None else None
    return run_view(arm, q0, port=args.port, deg=args.deg, duration=args.duration)


def register(subparsers: Any) -> None:
    """Add the ``view`` subcommand to the CLI's subparsers."""
    p = subparsers.add_parser("view")
    add_arm(p)
    p.add_argument("--q", help="initial joint values v1,v2,… (rad and m; see --deg); default: zeros within limits")
    p.add_argument("--deg", action="store_true", help="revolute values in degrees: --q, the sliders and the "
                                                      "printed joints")
    p.add_argument("--port", type=integer, help=f"first port to try (then the next {PORT_TRIES - 1}); default: "
                   "the first free one from 7000")
    p.add_argument("--duration", type=number, help="stop after this many seconds (default: run until Ctrl-C)")
    p.set_defaults(func=_cmd_view)
