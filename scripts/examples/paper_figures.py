"""The papers' figures for my own arm: paper 000's motion, torque and tool-path figures, and its drawing.

    python scripts/examples/paper_figures.py                      # the example arm3r.csv
    python -m armlab.scripts.examples.paper_figures               # the same from anywhere, armlab installed
    python scripts/examples/paper_figures.py my_arm.urdf --out runs/my_arm_figures

Paper 000 moves its arm by a rest-to-rest quintic (Fig. 3), plots the joint angles (Fig. 5) and the
torques the inverse dynamics gives (Fig. 7) from the Fig. 6 diagram. Here the same is done for any
arm: the quintic goes from q = 0 (clipped into the limits) to a third of the way to each upper limit.
"""

from __future__ import annotations

import argparse

import numpy as np

import armlab


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("arm", nargs="?", default="example:arm3r",
                        help="a .urdf or DH .csv with masses, or an example (default: example:arm3r)")
    parser.add_argument("--tf", type=float, default=2.0, help="motion time, s (default 2, Fig. 3's)")
    parser.add_argument("--out", default="runs/paper_figures", help="folder for the figures")
    args = parser.parse_args(argv)

    arm = armlab.load(args.arm)
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    q0 = np.clip(np.zeros(arm.n), lower, upper)
    motion = armlab.quintic(arm, q0, q0 + (upper - q0) / 3, args.tf, "paper 000's rest-to-rest quintic (Fig. 3)")
    run = armlab.simulate(arm, motion)
    written = run.save(args.out)
    print(f"{arm.name}: {motion.description}; max |τ| = "
          + ", ".join(f"{v:.4g} {u}" for v, u in zip(run.summary["max_abs_torque"], run.summary["torque_units"],
                                                    strict=True)))
    print("wrote", args.out + ":", " ".join(written))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
