"""Benchmark: armlab's multi-start IK (every branch of a pose) against Drake's ``InverseKinematics``.

Run on demand (not a test): ``python scripts/bench_ik.py [--arm urm6] [--poses 10] [--drake-starts 64]``.
For ``--poses`` random in-limit configurations q of the arm, the pose T = FK(q) is solved

* by :func:`armlab.kinematics.ik.solve` with ``all_solutions=True`` (``SEEDS`` starts in one batch), and
* by Drake's ``InverseKinematics`` (position and orientation constraints on the tool frame, 1e-9) solved by
  ``pydrake.solvers.Solve`` from ``--drake-starts`` random starts, one at a time;

and reports per pose the wall time of each, the distinct solutions each finds (Drake's clustered at 0.03
rad, its accuracy), whether q itself is among armlab's, and how many of Drake's are not among armlab's
(it should be none). Then the median times and their ratio (measured in the same run, taking turns).
"""

from __future__ import annotations

import argparse
import time
from typing import TYPE_CHECKING

import numpy as np

from armlab.kinematics.ik import SEEDS, solve
from armlab.models import get_arm
from armlab.models.arm import Arm

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant

#: Drake's solutions closer than this (rad, modulo 2π) are one solution: its IK meets 1e-9 only to about 1e-2 rad.
DRAKE_CLUSTER = 0.03


def _angular_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Max over joints of |a − b| modulo 2π, for every pair: ``(len(a), len(b))``."""
    d = a[:, None, :] - b[None, :, :]
    return np.abs((d + np.pi) % (2 * np.pi) - np.pi).max(axis=-1)


def drake_solutions(plant: MultibodyPlant, arm: Arm, target: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Every solution Drake's ``InverseKinematics`` on ``plant`` (``arm.make_plant()``) reports as a success from
    ``starts``, ``(k, n)``."""
    from pydrake.math import RotationMatrix
    from pydrake.multibody.inverse_kinematics import InverseKinematics
    from pydrake.solvers import Solve

    tool = plant.GetFrameByName(arm.tool_name)
    index = np.array([plant.GetJointByName(name).position_start() for name in arm.joint_names])  # q_plant[index]
    ik = InverseKinematics(plant)
    ik.AddPositionConstraint(tool, np.zeros(3), plant.world_frame(), target[:3, 3] - 1e-9, target[:3, 3] + 1e-9)
    ik.AddOrientationConstraint(plant.world_frame(), RotationMatrix(target[:3, :3]), tool, RotationMatrix(), 1e-9)
    found = []
    for start in starts:
        guess = np.zeros(plant.num_positions())
        guess[index] = start
        result = Solve(ik.prog(), guess)
        if result.is_success():
            found.append(result.GetSolution(ik.q())[index])
    return np.array(found).reshape(-1, arm.n)


def _clusters(q: np.ndarray) -> int:
    """How many distinct solutions (greedy clusters of radius ``DRAKE_CLUSTER``) the rows of ``q`` hold."""
    centres: list[np.ndarray] = []
    for row in q:
        if not centres or _angular_distance(row[None], np.array(centres)).min() > DRAKE_CLUSTER:
            centres.append(row)
    return len(centres)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arm", default="urm6", help="an arm solved numerically (not rr, arm4r, r2t)")
    parser.add_argument("--poses", type=int, default=10, help="random poses to solve")
    parser.add_argument("--drake-starts", type=int, default=64, help="starts for Drake's InverseKinematics")
    args = parser.parse_args(argv)
    arm = get_arm(args.arm)
    rng = np.random.default_rng(0)
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    plant = arm.make_plant()  # built once, outside the timings
    ours_s, drake_s = [], []
    print(f"{arm.name}: {args.poses} random poses; armlab {SEEDS} starts in one batch, Drake "
          f"{args.drake_starts} starts one at a time")
    print(" pose  armlab [s]  solutions  q among them  Drake [s]  solutions  Drake's not among armlab's")
    for k, q in enumerate(rng.uniform(lower, upper, size=(args.poses, arm.n))):
        target = arm.forward(q).tool
        start = time.perf_counter()
        ours = np.array(solve(arm, target, all_solutions=True))
        ours_s.append(time.perf_counter() - start)
        start = time.perf_counter()
        drake = drake_solutions(plant, arm, target, rng.uniform(lower, upper, size=(args.drake_starts, arm.n)))
        drake_s.append(time.perf_counter() - start)
        has_q = bool(_angular_distance(q[None], ours).min() < 1e-6)
        missing = int((_angular_distance(drake, ours).min(axis=1) > DRAKE_CLUSTER).sum()) if len(drake) else 0
        print(f" {k:4d}  {ours_s[-1]:10.3f}  {len(ours):9d}  {has_q!s:>12s}  {drake_s[-1]:9.3f}  "
              f"{_clusters(drake):9d}  {missing:26d}")
    ratio = np.median(drake_s) / np.median(ours_s)
    print(f"median: armlab {np.median(ours_s):.3f} s, Drake {np.median(drake_s):.3f} s per pose "
          f"(Drake / armlab = {ratio:.1f}× with {args.drake_starts} vs {SEEDS} starts)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
