"""Benchmark: armlab's batched kinematics and dynamics against Pinocchio and Drake called per sample.

Run on demand (not a test; ``make bench`` runs it): ``python scripts/bench/bench_kinematics.py [--n 100000]``.
For every paper arm, over ``n`` random in-limit states, it times

* forward kinematics — armlab ``Arm.forward`` (the paper's formulation, one batched call) vs Pinocchio
  ``framesForwardKinematics`` + the tool frame's placement vs Drake ``CalcRelativeTransform``;
* the tool-point Jacobian — :func:`armlab.kinematics.differential.jacobian` vs Pinocchio
  ``computeFrameJacobian(…, LOCAL_WORLD_ALIGNED)`` vs Drake ``CalcJacobianSpatialVelocity``;
* inverse dynamics with gravity — :func:`armlab.kinematics.rnea.inverse_dynamics` vs Pinocchio ``rnea``
  vs Drake ``CalcInverseDynamics`` (+ ``CalcForceElementsContribution``);

Pinocchio and Drake one sample at a time from Python, both models built from the arm's own URDF. Before
timing, all three are checked to give the same numbers (1e-9) on the first samples. Each time is the
median of ``--repeat`` rounds (the nine measurements of an arm take turns in each round), in µs per sample,
wall-clock time or (``--clock cpu``) this process's CPU time; "×" columns are Pinocchio's time over armlab's.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np
import pinocchio as pin

from armlab.kinematics.differential import jacobian
from armlab.kinematics.rnea import inverse_dynamics
from armlab.models import ARMS, get_arm
from armlab.models.arm import Arm

CHECK = 20  # samples compared between armlab, Pinocchio and Drake before timing
CLOCKS = {"wall": time.perf_counter, "cpu": time.process_time}


def _medians_us(runs: dict[str, tuple[Callable[[], object], int]], repeat: int, clock: Callable[[], float]
                ) -> dict[str, float]:
    """Median over ``repeat`` rounds of each run's time, in µs per sample, the runs taking turns in every
    round (so a busy machine slows all of them alike). ``runs``: name → (function, samples)."""
    times: dict[str, list[float]] = {name: [] for name in runs}
    for _ in range(repeat):
        for name, (run, count) in runs.items():
            start = clock()
            run()
            times[name].append((clock() - start) / count * 1e6)
    return {name: float(np.median(values)) for name, values in times.items()}


class Pinocchio:
    """Pinocchio's model of the arm's URDF (or of the URDF text ``urdf``, e.g. a file armlab exported), its gravity,
    and q in Pinocchio's layout (cos, sin for continuous)."""

    def __init__(self, arm: Arm, urdf: str | None = None) -> None:
        self.model = pin.buildModelFromXML(arm.urdf() if urdf is None else urdf)
        self.model.gravity.linear = np.asarray(arm.gravity, dtype=float)
        self.data = self.model.createData()
        self.frame = self.model.getFrameId(arm.tool_name)
        self.joints = [self.model.joints[self.model.getJointId(name)] for name in arm.joint_names]
        self.v_index = [joint.idx_v for joint in self.joints]  # Pinocchio's velocity index of each arm joint

    def configurations(self, q: np.ndarray) -> np.ndarray:
        """q ``(N, n)`` → Pinocchio's ``(N, nq)``: a continuous joint is (cos q, sin q)."""
        out = np.empty((q.shape[0], self.model.nq))
        for i, joint in enumerate(self.joints):
            if joint.nq == 2:
                out[:, joint.idx_q], out[:, joint.idx_q + 1] = np.cos(q[:, i]), np.sin(q[:, i])
            else:
                out[:, joint.idx_q] = q[:, i]
        return out

    def velocities(self, v: np.ndarray) -> np.ndarray:
        """Joint rates ``(N, n)`` in Pinocchio's velocity order."""
        out = np.empty_like(v)
        out[:, self.v_index] = v
        return out

    def forward(self, qp: np.ndarray) -> list:
        return [pin.framesForwardKinematics(self.model, self.data, x) or self.data.oMf[self.frame].homogeneous
                for x in qp]

    def jacobian(self, qp: np.ndarray) -> list:
        return [pin.computeFrameJacobian(self.model, self.data, x, self.frame, pin.LOCAL_WORLD_ALIGNED) for x in qp]

    def rnea(self, qp: np.ndarray, v: np.ndarray, a: np.ndarray) -> list:
        return [pin.rnea(self.model, self.data, x, y, z) for x, y, z in zip(qp, v, a, strict=True)]


class Drake:
    """Drake's plant of the arm (its gravity), queried one sample at a time."""

    def __init__(self, arm: Arm) -> None:
        from pydrake.multibody.tree import MultibodyForces

        self.plant = arm.make_plant()
        self.context = self.plant.CreateDefaultContext()
        self.tool, self.world = self.plant.GetFrameByName(arm.tool_name), self.plant.world_frame()
        self.forces = MultibodyForces(self.plant)

    def forward(self, q: np.ndarray) -> list:
        out = []
        for x in q:
            self.plant.SetPositions(self.context, x)
            out.append(self.plant.CalcRelativeTransform(self.context, self.world, self.tool).GetAsMatrix4())
        return out

    def jacobian(self, q: np.ndarray) -> list:
        from pydrake.multibody.tree import JacobianWrtVariable

        out = []
        for x in q:
            self.plant.SetPositions(self.context, x)
            J = self.plant.CalcJacobianSpatialVelocity(self.context, JacobianWrtVariable.kV, self.tool, np.zeros(3),
                                                       self.world, self.world)
            out.append(np.vstack([J[3:], J[:3]]))
        return out

    def inverse_dynamics(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> list:
        out = []
        for x, y, z in zip(q, qd, qdd, strict=True):
            self.plant.SetPositions(self.context, x)
            self.plant.SetVelocities(self.context, y)
            self.plant.CalcForceElementsContribution(self.context, self.forces)
            out.append(self.plant.CalcInverseDynamics(self.context, z, self.forces))
        return out


def _check(name: str, what: str, armlab: np.ndarray, *others: tuple[str, list]) -> None:
    """Stop the benchmark unless every other library's numbers equal armlab's (1e-9, relative for torques)."""
    for library, values in others:
        gap = float(np.abs(np.asarray(values) - armlab).max()) / max(1.0, float(np.abs(armlab).max()))
        if gap > 1e-9:
            raise SystemExit(f"{name}: {what} of armlab and {library} differ by {gap:.3g}: the benchmark would "
                             "compare different things")


def bench_arm(name: str, n: int, drake_n: int, repeat: int, rng: np.random.Generator,
              clock: Callable[[], float]) -> dict[str, float]:
    """µs per sample of FK, Jacobian and inverse dynamics for armlab, Pinocchio and Drake."""
    arm = get_arm(name)
    q = rng.uniform(*arm.limit_arrays(unlimited=np.pi), size=(n, arm.n))
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
    pino, drake = Pinocchio(arm), Drake(arm)
    qp, vp, ap = pino.configurations(q), pino.velocities(qd), pino.velocities(qdd)
    first = slice(0, CHECK)
    _check(name, "tool poses", arm.forward(q[first]).tool, ("Pinocchio", pino.forward(qp[first])),
           ("Drake", drake.forward(q[first])))
    J = jacobian(arm, q[first])
    _check(name, "Jacobians", J, ("Pinocchio", [Jp[:, pino.v_index] for Jp in pino.jacobian(qp[first])]),
           ("Drake", drake.jacobian(q[first])))
    tau = inverse_dynamics(arm, q[first], qd[first], qdd[first])
    tau_pin = [t[pino.v_index] for t in pino.rnea(qp[first], vp[first], ap[first])]
    _check(name, "torques", tau, ("Pinocchio", tau_pin),
           ("Drake", drake.inverse_dynamics(q[first], qd[first], qdd[first])))
    d = slice(0, drake_n)
    return _medians_us({
        "fk": (lambda: arm.forward(q), n),
        "fk_pin": (lambda: pino.forward(qp), n),
        "fk_drake": (lambda: drake.forward(q[d]), drake_n),
        "jac": (lambda: jacobian(arm, q), n),
        "jac_pin": (lambda: pino.jacobian(qp), n),
        "jac_drake": (lambda: drake.jacobian(q[d]), drake_n),
        "id": (lambda: inverse_dynamics(arm, q, qd, qdd), n),
        "id_pin": (lambda: pino.rnea(qp, vp, ap), n),
        "id_drake": (lambda: drake.inverse_dynamics(q[d], qd[d], qdd[d]), drake_n),
    }, repeat, clock)


def main() -> None:
    """Print one table: per arm, µs per sample for armlab, Pinocchio, Drake and Pinocchio/armlab ratios."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000, help="samples for armlab and Pinocchio (default 100000)")
    parser.add_argument("--drake-n", type=int, default=5_000, help="samples for the Drake loops (default 5000)")
    parser.add_argument("--repeat", type=int, default=5, help="runs per measurement, median taken (default 5)")
    parser.add_argument("--arms", default=",".join(ARMS), help="comma-separated paper arms (default: all)")
    parser.add_argument("--clock", choices=CLOCKS, default="wall",
                        help="wall: elapsed time; cpu: this process's CPU time (steadier on a busy machine)")
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    print(f"{args.clock} clock, µs per sample, N = {args.n} (Drake: {args.drake_n}), median of {args.repeat}; "
          "× = Pinocchio loop / armlab batch (goals: FK ≥ 5×, Jacobian ≥ 3×, inverse dynamics ≥ 2×)")
    header = "| arm | " + " | ".join(
        f"{what} armlab | {what} Pinocchio | {what} Drake | {what} ×" for what in ("FK", "Jacobian", "ID")) + " |"
    print(header)
    print("|---" * (1 + 12) + "|")
    for name in args.arms.split(","):
        r = bench_arm(name, args.n, args.drake_n, args.repeat, rng, CLOCKS[args.clock])
        cells = []
        for key in ("fk", "jac", "id"):
            cells += [f"{r[key]:.3f}", f"{r[key + '_pin']:.2f}", f"{r[key + '_drake']:.1f}",
                      f"{r[key + '_pin'] / r[key]:.1f}×"]
        print(f"| {name} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
