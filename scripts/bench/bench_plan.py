"""Benchmark: planning a tool line for urm6 (6 joints) — IK along it and its time-optimal timing — against Drake.

Run on demand (not a test): ``python scripts/bench/bench_plan.py [--samples 1000] [--grid 500] [--repeat 5]``.

* IK along a 3 cm straight line of the tool, orientation held, at ``--samples`` samples:
  :func:`armlab.kinematics.ik_path.solve_path` (batched, seeded along the path; goal ≤ 0.3 s) vs Drake's
  ``InverseKinematics`` (position and orientation constraints to 1e-9, each sample seeded by the previous
  sample's solution, solved one at a time by ``pydrake.solvers.Solve``);
* the time-optimal timing of the line's joint path by :func:`armlab.planning.timing.fastest` with ``--grid``
  grid points (velocity and effort limits from urm6's file, 5 rad/s² acceleration; goal ≤ 0.2 s) beside
  Drake's ``Toppra.SolvePathParameterization`` alone on the same path and plant.

Best of ``--repeat`` wall-clock times, the two timings of the path taken in turns in the same run; the plant is
built once, outside them.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from armlab.kinematics.cartesian import joint_path, line_path
from armlab.kinematics.ik_path import solve_path
from armlab.models import get_arm
from armlab.planning.timing import arm_limits, fastest

#: A well-conditioned start of urm6 (σ_min of its Jacobian ≈ 0.04) and the line's displacement (m).
START = np.array([1.14594114, -1.78069309, -1.09635936, 1.30034083, 0.46536681, 0.04729932])
DISPLACEMENT = np.array([0.03, 0.0, 0.0])


def best(tasks: tuple[Callable[[], object], ...], repeat: int) -> list[tuple[float, float]]:
    """For each of ``tasks``, the least wall time and the least CPU time of this process (s) of ``repeat`` runs,
    the tasks taken in turns (a slow moment of a shared machine falls on all of them alike; the CPU time says what
    the work costs, the wall time what a user waits)."""
    wall: list[list[float]] = [[] for _ in tasks]
    cpu: list[list[float]] = [[] for _ in tasks]
    for _ in range(repeat):
        for k, task in enumerate(tasks):
            start, start_cpu = time.perf_counter(), time.process_time()
            task()
            wall[k].append(time.perf_counter() - start)
            cpu[k].append(time.process_time() - start_cpu)
    return [(min(w), min(c)) for w, c in zip(wall, cpu, strict=True)]


def drake_ik(plant: Any, arm: Any, targets: np.ndarray, q0: np.ndarray) -> np.ndarray:
    """Drake's ``InverseKinematics`` at each target pose ``(m, 4, 4)``, seeded by the previous solution."""
    from pydrake.math import RotationMatrix
    from pydrake.multibody.inverse_kinematics import InverseKinematics
    from pydrake.solvers import Solve

    tool = plant.GetFrameByName(arm.tool_name)
    q, out = q0, []
    for target in targets:
        ik = InverseKinematics(plant)
        ik.AddPositionConstraint(tool, np.zeros(3), plant.world_frame(), target[:3, 3] - 1e-9, target[:3, 3] + 1e-9)
        ik.AddOrientationConstraint(plant.world_frame(), RotationMatrix(target[:3, :3]), tool, RotationMatrix(), 1e-9)
        result = Solve(ik.prog(), q)
        q = result.GetSolution(ik.q())
        out.append(q)
    return np.array(out)


def main(argv: list[str] | None = None) -> int:
    from pydrake.multibody.optimization import Toppra

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1000, help="samples along the line for the IK")
    parser.add_argument("--grid", type=int, default=500, help="Toppra's grid points")
    parser.add_argument("--repeat", type=int, default=5, help="runs of each, the best taken")
    args = parser.parse_args(argv)
    arm = get_arm("urm6")
    T0 = arm.fk(START)
    T1 = T0.copy()
    T1[:3, 3] += DISPLACEMENT
    path = line_path(T0, T1)
    s = np.linspace(0.0, 1.0, args.samples)
    p, dp, ddp = path.points(s)
    rotations = path.rotations(s)
    assert rotations is not None

    def ours() -> object:
        return solve_path(arm, "the line", s, p, dp, ddp, START, *rotations)

    joints = solve_path(arm, "the line", s, p, dp, ddp, START, *rotations)
    tool = arm.forward(joints.q).tool
    error = float(np.abs(tool[:, :3, 3] - p).max())
    plant = arm.make_plant()
    targets = np.concatenate([np.concatenate([rotations[0], p[:, :, None]], axis=2),
                              np.tile([[[0.0, 0.0, 0.0, 1.0]]], (s.size, 1, 1))], axis=1)
    [(ik_ours, ik_ours_cpu)] = best((ours,), args.repeat)
    [(ik_drake, ik_drake_cpu)] = best((lambda: drake_ik(plant, arm, targets, START),), 1)
    print(f"urm6: IK along a {np.linalg.norm(DISPLACEMENT) * 100:g} cm line, orientation held, {args.samples} "
          f"samples (tool error ≤ {error:.1e} m): armlab {ik_ours:.3f} s (CPU {ik_ours_cpu:.3f} s), Drake "
          f"InverseKinematics {ik_drake:.3f} s (CPU {ik_drake_cpu:.3f} s); Drake / armlab = "
          f"{ik_drake / ik_ours:.0f}× wall; goal armlab ≤ 0.3 s")

    q_path = joint_path(joints)
    limits = arm_limits(arm, acceleration=5.0)
    grid = np.linspace(0.0, 1.0, args.grid)
    toppra_plant = arm.make_plant()

    def drake_only() -> object:
        toppra = Toppra(q_path, toppra_plant, grid)
        toppra.AddJointVelocityLimit(-limits.velocity, limits.velocity)
        toppra.AddJointAccelerationLimit(-limits.acceleration, limits.acceleration)
        toppra.AddJointTorqueLimit(-limits.effort, limits.effort)
        return toppra.SolvePathParameterization()

    result = fastest(arm, q_path, acceleration=5.0, grid=args.grid)
    (ours_toppra, ours_toppra_cpu), (bare, bare_cpu) = best(
        (lambda: fastest(arm, q_path, acceleration=5.0, grid=args.grid), drake_only), args.repeat)
    print(f"urm6: time-optimal timing of that path, {args.grid} grid points (duration {result.duration:.4f} s, a "
          f"limit active on {result.active_fraction:.0%} of the grid): armlab fastest() {ours_toppra:.3f} s "
          f"(CPU {ours_toppra_cpu:.3f} s; plant, limits, Toppra, active constraints, limit curve), Drake's Toppra "
          f"alone {bare:.3f} s (CPU {bare_cpu:.3f} s); fastest / Toppra = {ours_toppra / bare:.2f}×; goal ≤ 0.2 s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
