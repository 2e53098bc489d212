"""Benchmark: clearances of urm6 along a motion and over a workspace's samples, numpy against Drake's SceneGraph.

Run on demand (not a test): ``python scripts/bench/bench_collision.py [--motion 2000] [--samples 1000000]``.

* The clearance of every pair along a ``--motion``-sample motion of urm6 (its paper demo motion), by
  :meth:`armlab.collision.model.CollisionModel.numpy` (batched) and by ``.drake`` (``SceneGraph``'s
  ``ComputeSignedDistancePairClosestPoints``, sample by sample): the goal is ≤ 0.2 s.
* The self-collision check of ``--samples`` random urm6 configurations (what the collision-free workspace
  adds to the raw one) by numpy, and Drake on a 2000-sample subset (scaled): the goal is ≤ 20 s for 10⁶.

Prints the wall times, samples per second and the ratio Drake / numpy measured in the same run, and the largest
difference of the two (Drake's capsule distances are GJK's, above the exact ones by up to 2e-4 m, never below).
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from armlab.analysis.workspace import sample_joints
from armlab.collision.model import CollisionModel
from armlab.models import get_arm


def _timed[T](fn: Callable[..., T], *args: Any) -> tuple[T, float]:
    """``fn(*args)`` and its wall time (s); the process's CPU time of it goes to :data:`CPU` (a shared machine's
    wall time counts the other processes' share of the cores too)."""
    began, cpu = time.perf_counter(), time.process_time()
    out = fn(*args)
    CPU[fn.__name__] = time.process_time() - cpu
    return out, time.perf_counter() - began


#: The CPU time (s) of the last call of each function timed.
CPU: dict[str, float] = {}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--motion", type=int, default=2000, help="samples of the motion (default 2000)")
    parser.add_argument("--samples", type=int, default=1_000_000, help="workspace samples (default 1e6)")
    args = parser.parse_args()
    arm = get_arm("urm6")
    model, built = _timed(CollisionModel, arm)
    assert arm.motion is not None
    motion = arm.motion(arm, None)
    t = np.linspace(0.0, motion.duration, args.motion)
    q = motion.evaluate(t, 1)[0]
    ours, numpy_time = _timed(model.numpy, q)
    drake, drake_time = _timed(model.drake, q)
    excess = drake.distance - ours.distance
    print(f"urm6: {len(model.pairs)} pairs; the model built in {built:.3f} s")
    print(f"motion of {args.motion} samples: numpy {numpy_time:.4f} s ({args.motion / numpy_time:,.0f} samples/s), "
          f"Drake {drake_time:.4f} s ({args.motion / drake_time:,.0f} samples/s), Drake/numpy "
          f"{drake_time / numpy_time:.1f}×; goal ≤ 0.2 s: {'met' if numpy_time <= 0.2 else 'NOT met'}; "
          f"Drake − numpy in [{excess.min():.2e}, {excess.max():.2e}] m; CPU numpy {CPU['numpy']:.4f} s, Drake "
          f"{CPU['drake']:.4f} s")
    qs = sample_joints(arm, args.samples, np.random.default_rng(0))
    found, sample_time = _timed(model.numpy, qs)
    free = np.all(found.distance >= 0, axis=1)
    numpy_cpu = CPU["numpy"]
    subset = qs[:2000]
    _, subset_time = _timed(model.drake, subset)
    scaled = subset_time * args.samples / len(subset)
    print(f"workspace self-collision check of {args.samples:,} samples: numpy {sample_time:.2f} s "
          f"({args.samples / sample_time:,.0f} samples/s); Drake {scaled:.1f} s scaled from {len(subset)} "
          f"({len(subset) / subset_time:,.0f} samples/s), Drake/numpy {scaled / sample_time:.1f}×; goal ≤ 20 s: "
          f"{'met' if sample_time <= 20 else 'NOT met'} (CPU numpy {numpy_cpu:.2f} s, Drake "
          f"{CPU['drake'] * args.samples / len(subset):.1f} s); {free.mean():.1%} of the samples collision-free")


if __name__ == "__main__":
    main()
