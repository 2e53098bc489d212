"""Benchmark: how many times faster than real time each paper motion simulates through Fig. 6's diagram.

For each paper motion (the ones ``armlab simulate ARM`` runs) this times :func:`armlab.diagrams.simulate.simulate`
at the defaults (1 ms loggers, Runge–Kutta 5 at the default accuracy) and, as a reference measured in the same
run on the same machine, a bare plant (no controller, no loggers, zero actuation, same integrator and
accuracy) over the same duration from the same start. The real-time factor is simulated time / wall time;
the ratio says what the diagram costs over integrating the arm alone. Best of ``--repeat`` runs each.

Run: ``.venv/bin/python scripts/bench_simulate.py`` (or ``make bench``).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from armlab.diagrams.build import DEFAULT_LOG_PERIOD
from armlab.diagrams.motions import paper_motion
from armlab.diagrams.plant import make_plant, resolve_gravity
from armlab.diagrams.simulate import DEFAULT_ACCURACY, DEFAULT_INTEGRATOR, MAX_STEP, simulate
from armlab.kinematics.quintic import Motion
from armlab.models import get_arm
from armlab.models.arm import Arm

#: The paper motions (arm, --path).
MOTIONS = (("rr", None), ("rr", "abcd"), ("rrrr", None), ("arm4r", None), ("r2t", None), ("urm6", None))


def plant_only_seconds(arm: Arm, motion: Motion) -> float:
    """Wall time to integrate the bare plant (zero actuation) over ``motion``'s duration, from its start state."""
    from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator

    plant = make_plant(arm, resolve_gravity(arm))
    simulator = Simulator(plant)
    context = simulator.get_mutable_context()
    plant.get_actuation_input_port().FixValue(context, np.zeros(arm.n))
    plant.SetPositions(context, motion.segments[0].q_start)
    plant.SetVelocities(context, motion.segments[0].v_start)
    ResetIntegratorFromFlags(simulator, DEFAULT_INTEGRATOR, MAX_STEP)
    simulator.get_mutable_integrator().set_target_accuracy(DEFAULT_ACCURACY)
    began = time.perf_counter()
    simulator.AdvanceTo(motion.duration)
    return time.perf_counter() - began


def main(argv: list[str] | None = None) -> int:
    """Print one row per paper motion: duration, wall time, real-time factor, plant-only reference."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per motion; the best is reported (default 3)")
    args = parser.parse_args(argv)
    print(f"log period {DEFAULT_LOG_PERIOD * 1e3:g} ms, {DEFAULT_INTEGRATOR} at accuracy {DEFAULT_ACCURACY:g}, "
          f"best of {args.repeat}")
    print(f"{'motion':12s} {'T [s]':>6s} {'wall [s]':>9s} {'× real time':>12s} {'plant-only [s]':>15s} "
          f"{'× real time':>12s} {'diagram/plant':>14s}")
    for name, path in MOTIONS:
        arm = get_arm(name)
        motion = paper_motion(arm, path)
        wall = min(simulate(arm, motion).wall_time for _ in range(args.repeat))
        bare = min(plant_only_seconds(arm, motion) for _ in range(args.repeat))
        label = f"{name} {path}" if path else name
        T = motion.duration
        print(f"{label:12s} {T:6g} {wall:9.3f} {T / wall:12.1f} {bare:15.3f} {T / bare:12.1f} {wall / bare:14.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
