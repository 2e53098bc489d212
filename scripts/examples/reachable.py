"""Is this target reachable, and how? Every inverse-kinematics branch of a tool pose, with its manipulability.

    python scripts/examples/reachable.py                          # urm6, a pose made from Table 1's angles
    python -m armlab.scripts.examples.reachable                   # the same from anywhere, armlab installed
    python scripts/examples/reachable.py arm4r --position 1,1,1.4
    python scripts/examples/reachable.py my_arm.csv --position 0.5,0.2,0.6 --rpy 0,90,0

A target is a position (x, y, z in m) or a pose (position and roll, pitch, yaw in degrees,
R = Rz(yaw)·Ry(pitch)·Rx(roll)); without one, the tool pose where a paper arm's paper motion ends
(urm6's demo ends at Table 1's angles), any other arm's at q = 0. Each solution is checked by forward
kinematics; an unreachable target prints how close the arm can come.
"""

from __future__ import annotations

import argparse

import numpy as np

import armlab
from armlab.kinematics.ik_target import pose


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("arm", nargs="?", default="urm6", help="a paper arm's name, a .urdf or a DH .csv")
    parser.add_argument("--position", help="x,y,z in m (default: the tool pose where a paper arm's paper motion "
                        "ends, urm6: at Table 1's angles; other arms: at q = 0)")
    parser.add_argument("--rpy", help="roll,pitch,yaw of the tool in degrees: a full pose")
    args = parser.parse_args(argv)

    arm = armlab.load(args.arm)
    if args.position is None:
        target = arm.fk(np.zeros(arm.n) if arm.motion is None else arm.motion(arm, None).segments[-1].q_end)
    else:
        position = np.array([float(v) for v in args.position.split(",")])
        target = position if args.rpy is None else pose(position, np.radians([float(v) for v in args.rpy.split(",")]))
    try:
        solutions = arm.ik(target, all=True)
    except ValueError as error:
        print(f"not reachable: {error}")
        return 1
    position = target[:3, 3] if np.ndim(target) == 2 else target
    print(f"{arm.name}: {len(solutions)} solution(s) reach {np.round(position, 6).tolist()} m"
          + (" with the given orientation" if np.ndim(target) == 2 else ""))
    for q in solutions:
        T = arm.fk(q)
        miss = np.linalg.norm(T[:3, 3] - position)
        shown = np.where(arm.revolute, np.degrees(q), q)
        print(f"  q = {np.array2string(shown, precision=3, suppress_small=True)} (deg, m)   "
              f"manipulability {float(arm.manipulability(q)):.4g}   position error {miss:.1e} m")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
