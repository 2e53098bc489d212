"""Size the drives of my arm for this motion: peak and RMS torque, peak speed and power per joint, limits.

    python scripts/examples/size_drives.py                       # the example arm3r.csv, 2 kg payload
    python -m armlab.scripts.examples.size_drives                # the same from anywhere, armlab installed
    python scripts/examples/size_drives.py my_arm.csv --payload 5 --tf 1.2 --out runs/my_arm

The motion is a rest-to-rest quintic from 20 % to 80 % of every joint's range. The torques come
twice, two independent ways: by inverse dynamics along the sampled reference (no simulation) and
from the simulated Fig. 6 diagram (paper 000) — they agree to the integrator's accuracy. The run's
folder gets drives.csv and drives.png (torque against speed inside each joint's limit box) besides
the usual plots and the 3-D replay.
"""

from __future__ import annotations

import argparse

import numpy as np

import armlab


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("arm", nargs="?", default="example:arm3r",
                        help="a paper arm's name, a .urdf or a DH .csv with masses (default: example:arm3r)")
    parser.add_argument("--payload", type=float, default=2.0, help="kg at the tool (default 2)")
    parser.add_argument("--tf", type=float, default=1.5, help="motion time, s (default 1.5)")
    parser.add_argument("--out", default="runs/size_drives", help="the run's folder (default runs/size_drives)")
    args = parser.parse_args(argv)

    arm = armlab.load(args.arm)
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    motion = armlab.quintic(arm, lower + 0.2 * (upper - lower), lower + 0.8 * (upper - lower), args.tf)

    t = np.linspace(0.0, motion.duration, 1001)
    q, qd, qdd = motion.evaluate(t)
    tau = arm.inverse_dynamics(q, qd, qdd, payload=args.payload)  # (1001, n), no simulation

    run = armlab.simulate(arm, motion, payload=args.payload)
    print(f"{arm.name}: {motion.description}, payload {args.payload:g} kg")
    print(f"{'joint':8s} {'peak |τ|':>12s} {'RMS τ':>9s} {'peak |q̇|':>13s} {'peak power':>11s}  "
          "(effort, speed) limits   peak |τ| by inverse dynamics alone")
    for i, drive in enumerate(run.drives):
        print(f"{drive['joint']:8s} {drive['peak_torque']:9.3f} {drive['torque_unit']:3s}"
              f"{drive['rms_torque']:9.3f} {drive['peak_speed']:8.3f} {drive['speed_unit']:5s}"
              f"{drive['peak_power']:9.2f} W   ({drive['effort_limit']}, {drive['velocity_limit']})"
              f"{np.abs(tau[:, i]).max():16.3f}")
    for v in run.violations:
        print(f"  limit passed: {v['joint']} {v['source']} {v['quantity']} {v['peak']:.4g} {v['unit']} "
              f"(limit {v['limit']:.4g} {v['unit']}) from t = {v['first_time']:.3f} s")
    if not run.violations:
        print("  every position, velocity and effort limit holds")
    print("wrote", args.out + ":", " ".join(run.save(args.out)))
    return 1 if run.diverged else 0


if __name__ == "__main__":
    raise SystemExit(main())
