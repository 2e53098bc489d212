"""Benchmark: motions planned around obstacles (issue 30), armlab's planner against OMPL's RRT-Connect.

Scenes written for it: a table and a shelf in front of UR5, Panda, Puma 560 and urm6, each placed in the arm's
workspace: from 20 000 random configurations' tool points above the floor, X the 95th percentile of x and z_p
the p-th percentile of z (urm6 reaches only 0.56-1.0 m high, the others from the floor up). The **table**: a
0.04 m top of 0.9X × 1.6X at x = 0.6X, z = z₂₅, over a floor; the **shelf**: two 0.03 m boards of 0.45X × 1.4X at
x = 0.7X, z = z₁₅ and z₆₀, a back wall at x = 0.95X from z₁₅ to z₆₀, and the floor. Queries: seeded random
pairs of free configurations (joints within their limits, clipped to ±π), the same for every planner.

* the **straight joint line**'s failure rate (armlab's certified edge check) over 200 random free pairs per scene:
  how often a plain quintic between two free poses would hit something;
* the queries planned: the first ``--queries`` of those pairs whose straight line is blocked (the ones that need a
  planner), for each:
* **armlab** (:meth:`armlab.planning.planner.Planner.route`: RRT-Connect with batched, certified edge checks,
  shortcutting and smoothing; the search's time and the whole route's), budget ``--budget`` s;
* armlab's **lazy PRM** (:class:`armlab.planning.planner.Roadmap`, 400 nodes, 10 neighbours, built once per
  scene, its time reported apart): each query's route through it, the edges checked so far remembered;
* **OMPL**'s ``RRTConnect`` (PyPI ``ompl``, the bench extra) in the same joint space with the **same** checker:
  its state validity is armlab's clearance of one configuration (numpy's closed forms) ≥ 0, its motions checked
  at OMPL's resolution (``--resolution`` rad between checks, OMPL's discrete validator: not certified between
  its checks), the same range (:data:`armlab.planning.planner.STEP`) and budget; its ``solve`` time (no
  simplification: OMPL's ``simplifySolution`` through Python callbacks takes 10-30 s a path). OMPL calls the
  checker one configuration at a time, through Python (tens of µs a call); armlab checks an edge's samples in one
  batch: the ratio measures that as much as the two searches.

Then the dense check's rate: configurations per second of :meth:`Planner.clearances` on 10⁵ random UR5
configurations among the table scene's obstacles (the issue's goal ≥ 10⁵/s on one core), and alone (self only).

Prints per scene and overall: success rates, median and 90th-percentile times, the ratio OMPL / armlab of the median
search times measured in the same run. Goals (issue 30): 6-DOF median ≤ 100 ms and success ≥ 99 %, Panda median
≤ 200 ms, at least as fast as OMPL. Run: ``.venv/bin/python scripts/bench/bench_planner.py [--queries 10]
[--budget 2] [--quick]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from typing import Any

import numpy as np

from armlab.collision.scene import Scene, scene_from_dict
from armlab.models import get_arm
from armlab.models.arm import Arm
from armlab.planning.planner import STEP, NoPathError, Planner, Roadmap

ARMS = ("ur5", "panda", "puma560", "urm6")


def workspace(arm: Arm) -> tuple[float, float, float, float]:
    """X, z₁₅, z₂₅, z₆₀ (m) of the arm's tool points above the floor over 20 000 seeded random configurations."""
    q = _uniform(arm, np.random.default_rng(0), 20_000)
    points = arm.forward(q).tool[:, :3, 3]
    points = points[points[:, 2] > 0]
    z15, z25, z60 = np.percentile(points[:, 2], [15, 25, 60])
    return float(np.percentile(points[:, 0], 95)), float(z15), float(z25), float(z60)


def _limits(arm: Arm) -> tuple[np.ndarray, np.ndarray]:
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    return np.maximum(lower, -np.pi), np.minimum(upper, np.pi)


def _uniform(arm: Arm, rng: np.random.Generator, count: int) -> np.ndarray:
    return rng.uniform(*_limits(arm), (count, arm.n))


def scenes(X: float, z15: float, z25: float, z60: float) -> dict[str, Scene]:
    """The table and the shelf in a workspace of :func:`workspace`'s numbers (m) (module docstring)."""
    floor = {"name": "floor", "shape": "floor", "z": -0.02}
    table = [{"name": "table", "shape": "box", "size": [0.9 * X, 1.6 * X, 0.04], "xyz": [0.6 * X, 0, z25]}]
    shelf = [{"name": "low board", "shape": "box", "size": [0.45 * X, 1.4 * X, 0.03], "xyz": [0.7 * X, 0, z15]},
             {"name": "high board", "shape": "box", "size": [0.45 * X, 1.4 * X, 0.03], "xyz": [0.7 * X, 0, z60]},
             {"name": "back", "shape": "box", "size": [0.03, 1.4 * X, z60 - z15],
              "xyz": [0.95 * X, 0, (z15 + z60) / 2]}]
    return {"table": scene_from_dict({"obstacles": [*table, floor]}, "table"),
            "shelf": scene_from_dict({"obstacles": [*shelf, floor]}, "shelf")}


def queries(planner: Planner, rng: np.random.Generator, count: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """``count`` pairs of configurations each free of the scene and the arm itself."""
    out: list[tuple[np.ndarray, np.ndarray]] = []
    while len(out) < count:
        q = _uniform(planner.arm, rng, 400)
        free = q[planner.free(q)]
        out.extend((free[k], free[k + 1]) for k in range(0, len(free) - 1, 2))
    return out[:count]


def ompl_solve(planner: Planner, q0: np.ndarray, qf: np.ndarray, budget: float, resolution: float,
               seed: int) -> tuple[bool, float]:
    """OMPL's RRT-Connect on the query with armlab's one-configuration check: (solved, solve time s)."""
    from ompl import base as ob
    from ompl import geometric as og
    from ompl import util

    util.setLogLevel(util.LOG_NONE)
    util.RNG.setSeed(seed + 1)  # OMPL refuses seed 0
    n = planner.arm.n
    space = ob.RealVectorStateSpace(n)
    bounds = ob.RealVectorBounds(n)
    lower, upper = _limits(planner.arm)
    for i in range(n):
        bounds.setLow(i, float(lower[i]))
        bounds.setHigh(i, float(upper[i]))
    space.setBounds(bounds)
    setup = og.SimpleSetup(space)

    def valid(state: Any) -> bool:
        return bool(planner.free(np.array([[state[i] for i in range(n)]]))[0])

    setup.setStateValidityChecker(valid)
    info = setup.getSpaceInformation()
    info.setStateValidityCheckingResolution(resolution / space.getMaximumExtent())
    start, goal = space.allocState(), space.allocState()
    for i in range(n):
        start[i], goal[i] = float(q0[i]), float(qf[i])
    setup.setStartAndGoalStates(start, goal)
    rrt = og.RRTConnect(info)
    rrt.setRange(STEP)
    setup.setPlanner(rrt)
    began = time.perf_counter()
    solved = bool(setup.solve(budget)) and setup.haveExactSolutionPath()
    return solved, time.perf_counter() - began


def _stats(times: list[float]) -> str:
    if not times:
        return "none"
    return (f"median {statistics.median(times) * 1e3:7.1f} ms, 90 % {np.percentile(times, 90) * 1e3:7.1f} ms "
            f"({len(times)})")


def check_rate(count: int) -> tuple[float, float]:
    """Configurations per second of the dense check: UR5 among the table scene's obstacles, and alone."""
    arm = get_arm("ur5")
    q = _uniform(arm, np.random.default_rng(1), count)
    rates = []
    for scene in (scenes(*workspace(arm))["table"], None):
        planner = Planner(arm, scene)
        planner.clearances(q[:100])
        cpu = time.process_time()
        planner.clearances(q)
        rates.append(count / (time.process_time() - cpu))
    return rates[0], rates[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--queries", type=int, default=10, help="queries per scene (default 10)")
    parser.add_argument("--budget", type=float, default=2.0, help="each planner's budget per query, s (default 2)")
    parser.add_argument("--resolution", type=float, default=0.01, help="OMPL's motion check step, rad (0.01)")
    parser.add_argument("--quick", action="store_true", help="3 queries per scene")
    args = parser.parse_args()
    count = 3 if args.quick else args.queries
    print(f"load average {os.getloadavg()[0]:.2f}; {count} queries per scene, budget {args.budget:g} s each")
    table_rate, self_rate = check_rate(20_000 if args.quick else 100_000)
    print(f"dense check, UR5 (CPU time): {table_rate:,.0f} configurations/s among the table's obstacles, "
          f"{self_rate:,.0f}/s alone; goal ≥ 100,000/s: {'met' if table_rate >= 1e5 else 'NOT met'}")
    overall: dict[str, dict[str, list[float]]] = {}
    for name in ARMS:
        arm = get_arm(name)
        X, *heights = workspace(arm)
        for label, scene in scenes(X, *heights).items():
            planner = Planner(arm, scene)
            rng = np.random.default_rng(30)
            candidates = queries(planner, rng, 200)
            blocked_flags = [not planner.edge_free(a, b) for a, b in candidates]
            blocked = sum(blocked_flags)
            pairs = [pair for pair, flag in zip(candidates, blocked_flags, strict=True) if flag][:count]
            found: dict[str, list[float]] = {"search": [], "route": [], "prm": [], "ompl": []}
            failures = {"armlab": 0, "ompl": 0, "prm": 0}
            began = time.perf_counter()
            roadmap = Roadmap(planner, nodes=400, neighbours=10, seed=0)
            built = time.perf_counter() - began
            for seed, (a, b) in enumerate(pairs):
                try:
                    route = planner.route(a, b, seed=seed, budget=args.budget)
                    found["search"].append(route.search_time)
                    found["route"].append(route.planning_time)
                except NoPathError:
                    failures["armlab"] += 1
                try:
                    found["prm"].append(planner.route(a, b, seed=seed, roadmap=roadmap).planning_time)
                except NoPathError:
                    failures["prm"] += 1
                solved, solve = ompl_solve(planner, a, b, args.budget, args.resolution, seed)
                if solved:
                    found["ompl"].append(solve)
                else:
                    failures["ompl"] += 1
            key = "6-DOF" if arm.n == 6 else f"{arm.n}-DOF"
            for what, times in found.items():
                overall.setdefault(key, {}).setdefault(what, []).extend(times)
            overall[key].setdefault("failures armlab", []).append(failures["armlab"])
            overall[key].setdefault("failures ompl", []).append(failures["ompl"])
            overall[key].setdefault("failures prm", []).append(failures["prm"])
            overall[key].setdefault("queries", []).append(len(pairs))
            ratio = (statistics.median(found["ompl"]) / statistics.median(found["search"])
                     if found["ompl"] and found["search"] else float("nan"))
            overall[key].setdefault("blocked", []).extend([blocked, len(candidates)])
            print(f"{name:8s} {label:6s} X = {X:.3f} m: straight line blocked {blocked}/{len(candidates)}; of "
                  f"those planned, armlab {len(pairs) - failures['armlab']}/{len(pairs)} (search "
                  f"{_stats(found['search'])}; route {_stats(found['route'])}); PRM built in {built * 1e3:.0f} ms, "
                  f"{len(pairs) - failures['prm']}/{len(pairs)} (route {_stats(found['prm'])}); OMPL "
                  f"{len(pairs) - failures['ompl']}/{len(pairs)} (solve {_stats(found['ompl'])}); OMPL/armlab "
                  f"search {ratio:.2f}×", flush=True)
    for key, data in overall.items():
        queries_total = max(1, sum(data["queries"]))
        line_fails = sum(data["blocked"][0::2]) / max(1, sum(data["blocked"][1::2]))
        success = 1 - sum(data["failures armlab"]) / queries_total
        median = statistics.median(data["route"]) if data["route"] else float("nan")
        goal = 0.1 if key == "6-DOF" else 0.2
        print(f"{key}: straight line fails {line_fails:.1%}; armlab success {success:.1%} of {queries_total}, route "
              f"{_stats(data['route'])}, search "
              f"{_stats(data['search'])}; PRM success {1 - sum(data['failures prm']) / queries_total:.1%}, route "
              f"{_stats(data['prm'])}; OMPL success {1 - sum(data['failures ompl']) / queries_total:.1%}, solve "
              f"{_stats(data['ompl'])}; goal median ≤ {goal * 1e3:g} ms: {'met' if median <= goal else 'NOT met'}")


if __name__ == "__main__":
    main()
