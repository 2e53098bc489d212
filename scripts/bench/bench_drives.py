"""Benchmark: choosing the drives of a 6-DOF arm from 500 motors × 40 gearboxes per joint, every check (issues 19, 31).

The arm is urm6 (paper 004's 6-DOF arm). Its duty cycle is four rest-to-rest quintics, each 1 s, between four
poses inside its limits, with dwells of 0.2 s between them; the payload (3 load cases: 0, 2 and 5 kg) is carried
on the first two moves only. The catalogues are made up here, seeded: 500 motors (rated torque 0.05 … 50 N·m,
log-uniform, with the peak, speeds, inertia and mass scaled from it as datasheets run) and 40 gearboxes
(ratio 3 … 160, log-uniform; efficiency, ratings and mass likewise), so every joint has feasible and infeasible pairs.
Every motor has every column of issue 31 (electrics, winding, brake, drive current and I²t, DC link and braking
resistor, scaled from its rated torque as scripts/examples/catalogues/README.md describes) and every gearbox a life
basis, so every check of sizing/checks.py runs.

Timed (one process, one thread: the BLAS thread count is set to 1 before numpy loads; best of ``--repeat``; wall
clock and, with ``--clock cpu``, the process's CPU time, the steadier figure on a shared machine):

* ``selection``: :func:`armlab.sizing.select.select_joint` for every joint (the screen of 20 000 pairs, the full
  check of the survivors over every sample and load case), given the joint loads — goal ≤ 1 s;
* ``whole``: :func:`armlab.sizing.sizing.size`, sampling, inverse dynamics and the mass iteration included, every
  check — goal ≤ 2 s (issue 31; issue 19's was ≤ 5 s without the checks of sizing/checks.py);
* the reference measured in the same run: the inverse dynamics the selection needs (:func:`joint_loads`: the
  load torques and the mass matrix's diagonal of every load case along the cycle), and the ratios to it.

Run: ``.venv/bin/python scripts/bench/bench_drives.py`` (or ``make bench``).
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # one core, before numpy loads
    os.environ.setdefault(_name, "1")

import numpy as np  # noqa: E402

from armlab.kinematics.quintic import Motion, QuinticSegment  # noqa: E402
from armlab.models import get_arm  # noqa: E402
from armlab.models.arm import Arm  # noqa: E402
from armlab.sizing.catalogue import KGCM2, LIFE_BASES, RPM, Gearboxes, Motors  # noqa: E402
from armlab.sizing.checks import ALPHA_CU  # noqa: E402
from armlab.sizing.duty import DutyCycle, Dwell, LoadCase, Move, sample  # noqa: E402
from armlab.sizing.loads import joint_loads  # noqa: E402
from armlab.sizing.select import JointTask, select_joint  # noqa: E402
from armlab.sizing.sizing import size  # noqa: E402

GOAL_SELECTION, GOAL_WHOLE = 1.0, 2.0


def catalogues(motors: int = 500, gearboxes: int = 40, seed: int = 0) -> tuple[Motors, Gearboxes]:
    """Seeded made-up catalogues of the sizes the issue names (see the module docstring)."""
    rng = np.random.default_rng(seed)
    rated = np.exp(rng.uniform(np.log(0.05), np.log(50.0), motors))
    speed = np.asarray(rng.choice([1500.0, 2000.0, 3000.0], motors), dtype=np.float64) * RPM
    peak = rated * rng.uniform(2.5, 3.5, motors)
    big = rated > 2.5
    bus = np.where(big, 560.0, 325.0)
    no_load = speed * 2.2
    back_emf = bus / np.sqrt(2) / no_load  # V·s/rad: the voltage line ends at the no-load speed
    kt = np.sqrt(3) * back_emf
    r_total = 4.2 * np.sqrt(0.64 / rated)  # K/W winding to ambient
    hot = 1 + ALPHA_CU * (155 - 25)
    resistance = 90 / r_total / (1.5 * (rated / kt) ** 2) / hot  # the rated current heats the winding by 90 K
    m = Motors(tuple(f"M{k:03d}" for k in range(motors)), rated, peak, speed, speed * rng.uniform(1.5, 2.0, motors),
               0.08 * rated**1.3 * KGCM2 * rng.uniform(0.7, 1.4, motors),
               0.9 * rated**0.7 * rng.uniform(0.8, 1.2, motors),
               no_load, rated * 3.8, torque_constant=kt, back_emf=back_emf, resistance=resistance,
               inductance=1.5e-3 * resistance, pole_pairs=np.full(motors, 4.0),
               thermal_resistance_winding=0.3 * r_total, thermal_resistance_housing=0.7 * r_total,
               time_constant_winding=40 * (rated / 0.64) ** 0.3, time_constant_motor=900 * (rated / 0.64) ** 0.35,
               max_winding_temperature=np.full(motors, 155.0), brake_torque=1.3 * rated,
               drive_continuous_current=1.2 * rated / kt,
               drive_peak_current=np.maximum(3.6, 1.1 * peak / rated) * rated / kt,
               drive_peak_time=np.full(motors, 2.0), bus_voltage=bus, bus_max_voltage=np.where(big, 750.0, 390.0),
               bus_capacitance=np.where(big, 470e-6, 680e-6), braking_resistor_power=np.where(big, 100.0, np.nan),
               braking_resistance=np.where(big, 60.0, np.nan))
    ratio = np.exp(rng.uniform(np.log(3.0), np.log(160.0), gearboxes))
    torque = np.exp(rng.uniform(np.log(5.0), np.log(800.0), gearboxes))
    efficiency = np.where(ratio > 60, 0.8, 0.93).astype(np.float64)
    strain = ratio > 60
    g = Gearboxes(tuple(f"G{k:02d}" for k in range(gearboxes)), ratio, efficiency, torque, 2.2 * torque,
                  np.full(gearboxes, 6000.0 * RPM), 0.02 * torque**0.8 * KGCM2 / np.sqrt(ratio), 0.12 * torque**0.6,
                  life_basis=np.where(strain, LIFE_BASES["strain-wave"], LIFE_BASES["rating"]),
                  rated_life=np.where(strain, 35000.0, 30000.0),
                  rated_input_speed=np.where(strain, 2000.0, 3000.0) * RPM)
    return m, g


def cycle(arm: Arm) -> DutyCycle:
    """Four 1 s quintics between poses at 30 %, 70 %, 40 % and 60 % of each joint's range, with dwells."""
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    poses = [lower + f * (upper - lower) for f in (0.3, 0.7, 0.4, 0.6, 0.3)]
    steps: list[Move | Dwell] = []
    for k in range(4):
        steps.append(Move(Motion((QuinticSegment(poses[k], poses[k + 1], 1.0, f"move {k + 1}"),)), payload=k < 2))
        steps.append(Dwell(0.2, payload=k < 1))
    return DutyCycle(tuple(steps), description="4 moves and 4 dwells")


def best(repeat: int, work: Callable[[], object], clock: Callable[[], float]) -> float:
    """The shortest of ``repeat`` runs of ``work`` (s) by ``clock``."""
    times = []
    for _ in range(repeat):
        began = clock()
        work()
        times.append(clock() - began)
    return min(times)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--clock", choices=("wall", "cpu"), default="wall",
                        help="wall clock (default) or the process's CPU time")
    args = parser.parse_args(argv)
    clock = time.process_time if args.clock == "cpu" else time.perf_counter
    arm = get_arm("urm6")
    motors, gearboxes = catalogues()
    duty = cycle(arm)
    cases = (LoadCase(0.0), LoadCase(2.0), LoadCase(5.0))
    samples = sample(duty)
    loads = joint_loads(arm, samples, cases)
    tasks = [JointTask.of(samples, loads, k) for k in range(arm.n)]

    t_id = best(args.repeat, lambda: joint_loads(arm, samples, cases), clock)
    t_select = best(args.repeat, lambda: [select_joint(name, task, motors, gearboxes, 1.2)
                                          for name, task in zip(arm.joint_names, tasks, strict=True)], clock)
    result = size(arm, duty, cases, motors, gearboxes, 1.2)
    t_whole = best(args.repeat, lambda: size(arm, duty, cases, motors, gearboxes, 1.2), clock)
    print(f"urm6, {len(motors)} motors × {len(gearboxes)} gearboxes per joint, {len(cases)} load cases, "
          f"{duty.description} ({duty.duration:g} s, {samples.weight.size} samples); safety factor 1.2; "
          f"{'CPU time' if args.clock == 'cpu' else 'wall clock'}, best of {args.repeat}; load average "
          f"{os.getloadavg()[0]:.1f}")
    print("| what | time [s] | goal [s] | × inverse dynamics |")
    print("|---|---|---|---|")
    print(f"| inverse dynamics (joint_loads: τ_L and M_kk, {len(cases)} load cases) | {t_id:.3f} | — | 1 |")
    print(f"| selection, 6 joints (screen + full checks) | {t_select:.3f} | ≤ {GOAL_SELECTION:g} | "
          f"{t_select / t_id:.1f} |")
    print(f"| whole sizing, {result.iterations} selections (mass iteration"
          f"{', converged' if result.converged else ', not converged'}) | {t_whole:.3f} | ≤ {GOAL_WHOLE:g} | "
          f"{t_whole / t_id:.1f} |")
    for j in result.joints:
        c = j.chosen
        binding = c.binding.name if c is not None and c.binding is not None else ""
        unchecked = [r.name for r in c.unchecked] if c is not None else []
        print(f"  {j.joint}: {j.pairs} pairs, {j.screened} past the screen, {j.checked} checked, "
              f"{j.feasible_count} of them feasible; "
              + (f"{c.motor_name} + {c.gearbox_name} {c.mass:.3g} kg, binds: {binding}"
                 + (f", not checked: {', '.join(unchecked)}" if unchecked else ", every check made") if c else "none"))
    met = t_select <= GOAL_SELECTION and t_whole <= GOAL_WHOLE
    print(f"goals {'met' if met else 'NOT met'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
