"""Benchmark: armlab's multi-start IK (every branch of a pose) against Drake's ``InverseKinematics``.

Run on demand (not a test): ``python scripts/bench/bench_ik.py [--arm urm6] [--poses 10] [--drake-starts 64]``.
For ``--poses`` random in-limit configurations q of the arm, the pose T = FK(q) is solved

* by :func:`armlab.kinematics.ik.solve` with ``all_solutions=True`` (``SEEDS`` starts in one batch), and
* by Drake's ``InverseKinematics`` (position and orientation constraints on the tool frame, 1e-9) solved by
  ``pydrake.solvers.Solve`` from ``--drake-starts`` random starts, one at a time;

and reports per pose the wall time of each, the distinct solutions each finds (Drake's clustered at 0.03
rad, its accuracy), whether q itself is among armlab's, and how many of Drake's are not among armlab's
(it should be none). Then the median times and their ratio (measured in the same run, taking turns).

Then (``--closed-form-poses``, default 20000; 0 skips it) the UR closed form alone (all 8 branches of one pose, goal
≤ 50 µs; a batch of poses in one call, goal ≥ 1e5 poses/s), beside the arm's batched FK of as many configurations.

Then (``--single-poses``, default 50; 0 skips it) the cost of **one** solution nearest ``near`` on the seven library
arms (UR5, UR10 by the UR closed form; Puma 560, IRB 140, KR5, Stanford by the spherical-wrist one; the Panda
numerically, one start), issue 34's goal ≤ 0.5 × the Robotics Toolbox's ``ik_LM`` on every arm (issue 22's: ≤ 5 ms
for a 6-DOF arm): for random in-limit q and near = q + 0.2 rad noise (a tracking step), ``solve(arm, FK(q),
near=near)`` beside Drake's ``InverseKinematics`` from the one start ``near``, and the Robotics Toolbox's ``ik_LM``
from ``near`` where it is installed; median wall times (armlab's and ik_LM's CPU times beside them), their ratios, and
how many calls each solved (armlab's to 1e-9 by its own FK, checked outside the timing, as ik_LM's ``success``).
"""

from __future__ import annotations

import argparse
import time
from typing import TYPE_CHECKING, Any

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


def _drake_one(plant: MultibodyPlant, arm: Arm, target: np.ndarray, near: np.ndarray) -> bool:
    """Whether Drake's ``InverseKinematics`` from the one start ``near`` succeeds on ``target``."""
    return len(drake_solutions(plant, arm, target, near[None, :])) == 1


def single_solution(names: tuple[str, ...], poses: int) -> None:
    """Print the per-call times of one IK solution near ``near`` on ``names``: armlab, Drake, the toolbox's ik_LM."""
    rtb: Any = None  # the toolbox's module, if installed
    try:
        # lazy: the Robotics Toolbox is an optional comparison (the test extra), not armlab's
        import roboticstoolbox
        from spatialmath import SE3

        rtb = roboticstoolbox
    except ImportError:
        pass
    print(f"one solution nearest near (near = q + 0.2 rad noise), {poses} poses per arm; median ms per call "
          "(solved / calls)")
    print(" arm        armlab (CPU)              Drake IK (1 start)   Drake/armlab   toolbox ik_LM (CPU)        "
          "armlab/ik_LM: wall  CPU (goal ≤ 0.5)")
    rng = np.random.default_rng(1)
    for name in names:
        arm = get_arm(name)
        plant = arm.make_plant()
        robot = None
        if rtb is not None:
            robot = {"ur5": rtb.models.DH.UR5, "ur10": rtb.models.DH.UR10, "puma560": rtb.models.DH.Puma560,
                     "panda": rtb.models.DH.Panda, "kr5": rtb.models.DH.KR5, "irb140": rtb.models.DH.IRB140,
                     "stanford": rtb.models.DH.Stanford}[name]()
            robot.tool = SE3()  # armlab's tool is the last DH frame
        lower, upper = arm.limit_arrays(unlimited=np.pi)
        lower, upper = np.maximum(lower, -np.pi), np.minimum(upper, np.pi)
        times: dict[str, list[float]] = {"armlab": [], "drake": [], "rtb": []}
        cpu: list[float] = []  # armlab's CPU time: on a shared machine, the part of its wall time that is its own
        rtb_cpu: list[float] = []  # the toolbox's, likewise
        solved = dict.fromkeys(times, 0)
        for q in rng.uniform(lower + 0.05 * (upper - lower), upper - 0.05 * (upper - lower), size=(poses, arm.n)):
            target = arm.forward(q).tool
            near = np.clip(q + rng.normal(0, 0.2, arm.n), lower, upper)
            start, start_cpu = time.perf_counter(), time.process_time()
            try:
                (ours,) = solve(arm, target, near=near)
            except ValueError:
                ours = None
            times["armlab"].append(time.perf_counter() - start)
            cpu.append(time.process_time() - start_cpu)
            if ours is not None:  # the bench's own check, by the arm's FK, outside the timing (as the toolbox's)
                solved["armlab"] += int(np.abs(arm.forward(ours).tool - target).max() <= 1e-9)
            start = time.perf_counter()
            solved["drake"] += int(_drake_one(plant, arm, target, near))
            times["drake"].append(time.perf_counter() - start)
            if robot is not None:
                start, start_cpu = time.perf_counter(), time.process_time()
                solved["rtb"] += int(robot.ik_LM(target, q0=near).success)
                times["rtb"].append(time.perf_counter() - start)
                rtb_cpu.append(time.process_time() - start_cpu)
        ms = {key: 1e3 * float(np.median(value)) if value else float("nan") for key, value in times.items()}
        ours_cpu, their_cpu = (1e3 * float(np.median(value)) if value else float("nan") for value in (cpu, rtb_cpu))
        print(f" {name:9s} {ms['armlab']:6.2f} ({ours_cpu:5.2f}) ({solved['armlab']:3d}/{poses})  "
              f"{ms['drake']:8.2f} "
              f"({solved['drake']:3d}/{poses})   {ms['drake'] / ms['armlab']:10.1f}×   "
              + (f"{ms['rtb']:8.2f} ({their_cpu:5.2f}) ({solved['rtb']:3d}/{poses})   "
                 f"{ms['armlab'] / ms['rtb']:5.2f} {ours_cpu / their_cpu:5.2f}"
                 if robot is not None else "not installed"))


def closed_form_timing(names: tuple[str, ...], poses: int) -> None:
    """Print the cost of a UR closed form alone (:func:`armlab.kinematics.ik_wrist.ur_branches`): all 8 branches of
    one pose (median CPU µs per pose over ``poses`` poses; goal ≤ 50 µs) and of ``poses`` poses in one batched call
    (poses/s; goal ≥ 1e5), beside the arm's own batched FK of the same number of configurations (the reference, in
    the same run) and a check that every branch reaches its pose to 1e-9 by that FK."""
    from armlab.kinematics.dh import DHRow, DHTable
    from armlab.kinematics.ik_wrist import ur_branches

    print(f"closed form alone (UR layout, ur_branches), {poses} random poses; CPU time, median of 5 for the batch")
    print(" arm     one pose, 8 branches [µs]   batch [poses/s]   batched FK [configurations/s]   FK/IK   worst miss")
    rng = np.random.default_rng(2)
    for name in names:
        arm = get_arm(name)
        module = __import__(f"armlab.models.library.{name}", fromlist=["DH"])
        table = DHTable(tuple(DHRow(a, alpha, d, 0.0) for a, alpha, d in module.DH))
        q = rng.uniform(-np.pi, np.pi, (poses, arm.n))
        targets = arm.forward(q).tool
        position, rotation = targets[:, :3, 3], targets[:, :3, :3]
        one = []
        for k in range(min(poses, 500)):
            start = time.process_time()
            ur_branches(table, position[k], rotation[k], q[k])
            one.append(time.process_time() - start)
        batch, fk = [], []
        for _ in range(5):  # in turns
            start = time.process_time()
            branches = ur_branches(table, position, rotation, q)
            batch.append(time.process_time() - start)
            start = time.process_time()
            arm.forward(q)
            fk.append(time.process_time() - start)
        exists = ~np.isnan(branches[..., 0])
        miss = np.abs(arm.forward(branches[exists]).tool - np.repeat(targets, 8, axis=0)[exists.ravel()]).max()
        rate, fk_rate = poses / float(np.median(batch)), poses / float(np.median(fk))
        print(f" {name:6s}  {1e6 * float(np.median(one)):26.1f}   {rate:15.3g}   {fk_rate:29.3g}   "
              f"{fk_rate / rate:5.1f}   {miss:.1e}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arm", default="urm6", help="an arm solved numerically (not rr, arm4r, r2t)")
    parser.add_argument("--poses", type=int, default=10, help="random poses to solve (0: skip the multi-start part)")
    parser.add_argument("--drake-starts", type=int, default=64, help="starts for Drake's InverseKinematics")
    parser.add_argument("--closed-form-poses", type=int, default=20000,
                        help="poses for the closed form timed alone (0: skip it)")
    parser.add_argument("--single-poses", type=int, default=50,
                        help="poses per library arm for the one-solution timing (0: skip it)")
    args = parser.parse_args(argv)
    arm = get_arm(args.arm)
    rng = np.random.default_rng(0)
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    plant = arm.make_plant()  # built once, outside the timings
    if args.poses > 0:
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
    if args.closed_form_poses > 0:
        closed_form_timing(("ur5", "ur10"), args.closed_form_poses)
    if args.single_poses > 0:
        single_solution(("ur5", "ur10", "puma560", "irb140", "stanford", "kr5", "panda"), args.single_poses)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
