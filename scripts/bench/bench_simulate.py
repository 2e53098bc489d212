"""Benchmark: each paper motion through Fig. 6's diagram against the bare plant, and the CLI's start-up time.

For each paper motion (the ones ``armlab simulate ARM`` runs) this times :func:`armlab.diagrams.simulate.simulate`
at the defaults (1 ms log samples, Runge–Kutta 5 at the default accuracy; ``wall_time``: the simulator, its
integration and the log samples, not building the diagram) and, as a reference measured in the same run on the
same machine, a bare plant (no controller, no loggers, zero actuation, same integrator, accuracy and largest
step) over the same duration from the same start. The real-time factor is simulated time / wall time; the ratio
says what the diagram costs over integrating the arm alone (goal: ≤ 3×). ``simulate()`` is the whole call,
building the diagrams included. The two are run in turns, ``--repeat`` times each; every column is the median of
its runs and the ratio the median of the ratios of the turns (on a loaded machine the load drifts between turns
less than over the whole run). With ``--clock cpu`` every time is the process's CPU time (steadier on a busy
machine) and the diagram's column is the whole ``simulate()`` call.

Then the whole-process wall time of ``armlab --help`` (goal ≤ 0.2 s) and ``armlab fk urm6 --q 0,0,0,0,0,0``
(goal ≤ 0.5 s), the median of ``--repeat`` runs each (after one unmeasured run, so the files are cached), each
beside the same interpreter's bare start-up ``python -c pass`` run in turns with it (the reference: on a loaded
machine both slow down, their ratio less).

Run: ``.venv/bin/python scripts/bench/bench_simulate.py`` (or ``make bench``).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from armlab.diagrams.build import DEFAULT_LOG_PERIOD
from armlab.diagrams.simulate import DEFAULT_ACCURACY, DEFAULT_INTEGRATOR, MAX_STEP, simulate
from armlab.kinematics.quintic import Motion
from armlab.models import get_arm
from armlab.models.arm import Arm
from armlab.models.plant import PlantOptions
from armlab.planning.motions import paper_motion

#: The paper motions (arm, --path).
MOTIONS = (("rr", None), ("rr", "abcd"), ("rrrr", None), ("arm4r", None), ("r2t", None), ("urm6", None))
#: The start-up commands timed, with their goals (s).
COMMANDS = ((("--help",), 0.2), (("fk", "urm6", "--q", "0,0,0,0,0,0"), 0.5))


def plant_only_seconds(arm: Arm, motion: Motion, clock: Callable[[], float] = time.perf_counter) -> float:
    """Wall time to integrate the bare plant (zero actuation) over ``motion``'s duration, from its start state."""
    from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator

    plant = arm.make_plant(PlantOptions(ideal_drives=True))  # the plant simulate() runs
    simulator = Simulator(plant)
    context = simulator.get_mutable_context()
    plant.get_actuation_input_port().FixValue(context, np.zeros(arm.n))
    plant.SetPositions(context, motion.segments[0].q_start)
    plant.SetVelocities(context, motion.segments[0].v_start)
    ResetIntegratorFromFlags(simulator, DEFAULT_INTEGRATOR, MAX_STEP)
    simulator.get_mutable_integrator().set_target_accuracy(DEFAULT_ACCURACY)
    began = clock()
    simulator.AdvanceTo(motion.duration)
    return clock() - began


def simulate_seconds(arm: Arm, motion: Motion, clock: Callable[[], float] = time.perf_counter) -> tuple[float, float]:
    """(the simulation's time, the whole ``simulate`` call's) for ``motion``: ``wall_time`` (integration and
    samples, not building the diagram) when ``clock`` is the wall clock, else the whole call's both times."""
    began = clock()
    log = simulate(arm, motion)
    whole = clock() - began
    return (log.wall_time if clock is time.perf_counter else whole), whole


def command_seconds(argv: tuple[str, ...], repeat: int) -> tuple[float, float]:
    """Median whole-process wall times (s) of ``armlab ARGV`` and of the reference ``python -c pass`` (the bare
    interpreter), run in turns ``repeat`` times each after one warm-up run of both."""
    runs = ([str(Path(sys.executable).with_name("armlab")), *argv], [sys.executable, "-c", "pass"])
    times: tuple[list[float], list[float]] = ([], [])
    for k in range(repeat + 1):
        for command, column in zip(runs, times, strict=True):
            began = time.perf_counter()
            subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
            if k:
                column.append(time.perf_counter() - began)
    return statistics.median(times[0]), statistics.median(times[1])


def main(argv: list[str] | None = None) -> int:
    """Print one row per paper motion (diagram vs bare plant), then the start-up times."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per measurement (default 5)")
    parser.add_argument("--clock", choices=("wall", "cpu"), default="wall",
                        help="wall-clock time (default) or the process's CPU time (steadier on a busy machine)")
    parser.add_argument("--startup", action=argparse.BooleanOptionalAction, default=True,
                        help="time the CLI's start-up too (default; --no-startup: the motions alone)")
    args = parser.parse_args(argv)
    clock = time.perf_counter if args.clock == "wall" else time.process_time
    print(f"log period {DEFAULT_LOG_PERIOD * 1e3:g} ms, {DEFAULT_INTEGRATOR} at accuracy {DEFAULT_ACCURACY:g}, "
          f"largest step {MAX_STEP:g} s; {args.clock} clock, median of {args.repeat} in turns")
    print(f"{'motion':12s} {'T [s]':>6s} {'diagram [s]':>12s} {'× real time':>12s} {'bare plant [s]':>15s} "
          f"{'× real time':>12s} {'diagram/plant':>14s} {'simulate() [s]':>15s}")
    for name, path in MOTIONS:
        arm = get_arm(name)
        motion = paper_motion(arm, path)
        simulate(arm, motion)  # one unmeasured run of each: the code paths loaded, numpy's caches warm
        plant_only_seconds(arm, motion, clock)
        turns = [(*simulate_seconds(arm, motion, clock), plant_only_seconds(arm, motion, clock))
                 for _ in range(args.repeat)]
        wall, whole, bare = (statistics.median(column) for column in zip(*turns, strict=True))
        ratio = statistics.median(w / b for w, _, b in turns)
        label = f"{name} {path}" if path else name
        T = motion.duration
        print(f"{label:12s} {T:6g} {wall:12.4f} {T / wall:12.1f} {bare:15.4f} {T / bare:12.1f} {ratio:14.2f} "
              f"{whole:15.4f}")
    if not args.startup:
        return 0
    print(f"\nstart-up (whole process, median of {args.repeat}; reference: python -c pass, in turns):")
    for command, goal in COMMANDS:
        seconds, bare = command_seconds(command, args.repeat)
        print(f"  armlab {' '.join(command):36s} {seconds:6.3f} s   python -c pass {bare:6.3f} s   "
              f"{seconds / bare:5.1f}×   (goal ≤ {goal:g} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
