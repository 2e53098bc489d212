"""Benchmark: the papers' vectorised kinematics against Drake's per-configuration queries.

Run on demand (not a test): ``python scripts/bench_kinematics.py [--n 100000]``. For every arm
it times the batched paper formulation (``Arm.forward``) and paper 003's iterative algorithm over
``n`` samples, and Drake's ``CalcRelativeTransform`` / spatial-velocity queries one sample at a
time over a smaller set measured in the same run, and prints time per sample and the ratio.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from armlab.kinematics.iterative import iterative_kinematics
from armlab.models import ARMS, get_arm


def _per_sample(seconds: float, count: int) -> float:
    return seconds / count * 1e6


def main() -> None:
    """Print a table: µs per sample for armlab batch FK, iterative algorithm, Drake loop; ratios."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000, help="batch size for armlab (default 100000)")
    parser.add_argument("--drake-n", type=int, default=2_000, help="samples for the Drake loop (default 2000)")
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    print(f"{'arm':6s} {'FK batch µs':>12s} {'iterative µs':>13s} {'Drake FK µs':>12s} {'Drake vel µs':>13s}"
          f" {'FK speed-up':>12s} {'vel speed-up':>13s}")
    for name in ARMS:
        arm = get_arm(name)
        plant = arm.make_plant()
        ctx = plant.CreateDefaultContext()
        q = rng.uniform(-1, 1, (args.n, arm.n)) * 0.2
        qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
        t0 = time.perf_counter()
        arm.forward(q)
        fk = _per_sample(time.perf_counter() - t0, args.n)
        t0 = time.perf_counter()
        iterative_kinematics(arm.table, q, qd, qdd)
        it = _per_sample(time.perf_counter() - t0, args.n)
        world, tool = plant.world_frame(), plant.GetFrameByName(arm.tool_name)
        t0 = time.perf_counter()
        for k in range(args.drake_n):
            plant.SetPositions(ctx, q[k])
            plant.CalcRelativeTransform(ctx, world, tool)
        dfk = _per_sample(time.perf_counter() - t0, args.drake_n)
        t0 = time.perf_counter()
        for k in range(args.drake_n):
            plant.SetPositionsAndVelocities(ctx, np.concatenate([q[k], qd[k]]))
            tool.CalcSpatialVelocityInWorld(ctx)
            plant.CalcSpatialAccelerationsFromVdot(ctx, qdd[k])
        dvel = _per_sample(time.perf_counter() - t0, args.drake_n)
        print(f"{name:6s} {fk:12.3f} {it:13.3f} {dfk:12.3f} {dvel:13.3f} {dfk / fk:11.1f}x {dvel / it:12.1f}x")


if __name__ == "__main__":
    main()
