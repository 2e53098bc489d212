"""Many planning queries at once, on the sweep's Dask cluster: a benchmark set's routes in parallel.

:func:`plan_queries` sends each query (a start and a goal) to a worker of a ``LocalCluster`` (or the cluster at
``scheduler``: :func:`armlab.analysis.sweep.dask_client`, the sweep's), which plans its route with
:meth:`armlab.planning.planner.Planner.route`: the arm (a name or a file, loaded on the worker) and its collision
model are built once per worker process and scene. The routes are the ones planned in this process (the same
seed, the same computation): query k takes seed ``seed + k``.
"""

from __future__ import annotations

import functools
import json
from contextlib import ExitStack
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from armlab.analysis.sweep import dask_client, default_workers
from armlab.collision.scene import read_scene, scene_from_dict
from armlab.models import get_arm
from armlab.planning.planner import NoPathError, Planner

__all__ = ["plan_queries"]


@functools.lru_cache(maxsize=8)
def _planner(arm: str, scene: str | None, clearance: float) -> Planner:
    """A worker's planner of ``arm`` (a name or a file) in ``scene`` (a scene's JSON text, or ``None``), built once."""
    return Planner(get_arm(arm), None if scene is None else scene_from_dict(json.loads(scene), "scene"), clearance)


def _route(arm: str, scene: str | None, clearance: float, q0: list[float], qf: list[float], seed: int,
           budget: float) -> dict[str, Any]:
    """One query's route on a worker: its waypoints, times (s), tree size and checks, or why none was found."""
    planner = _planner(arm, scene, clearance)
    try:
        route = planner.route(q0, qf, seed=seed, budget=budget)
    except NoPathError as error:
        return {"found": False, "error": str(error)}
    return {"found": True, "waypoints": route.waypoints.tolist(), "planning_time": route.planning_time,
            "search_time": route.search_time, "nodes": route.nodes, "checked": route.checked}


def plan_queries(arm: str | Path, queries: ArrayLike, scene: str | Path | None = None, clearance: float = 0.0,
                 seed: int = 0, budget: float = 5.0, workers: int | None = None,
                 scheduler: str | None = None) -> list[dict[str, Any]]:
    """The routes of ``queries`` ``(m, 2, n)`` (each a start and a goal, rad and m) for ``arm`` (a name or a file)
    among ``scene``'s obstacles (a scene file) by ``clearance`` (m), on a Dask cluster: a new ``LocalCluster`` of
    ``workers`` processes (default one per core) or the one at ``scheduler``. One dict per query, in order:
    ``found``, and ``waypoints`` (``(k, n)`` lists), ``planning_time``, ``search_time`` (s), ``nodes``, ``checked``,
    or the ``error`` saying why none was found within ``budget`` s (query k's seed: ``seed + k``). A bad start or
    goal is a ``ValueError`` raised here, before the cluster starts."""
    q = np.asarray(queries, dtype=float)
    if q.ndim != 3 or q.shape[1] != 2:
        raise ValueError(f"queries has shape {q.shape}: give (m, 2, n), a start and a goal per query")
    if scene is not None:
        read_scene(scene)  # checked here: a one-line error before any worker starts
    text = None if scene is None else Path(scene).read_text(encoding="utf-8")
    planner = _planner(str(arm), text, float(clearance))  # the queries checked here first: one-line errors
    for k, (start, goal) in enumerate(q):
        planner.endpoint(start, f"query {k + 1}'s start")
        planner.endpoint(goal, f"query {k + 1}'s goal")
    with ExitStack() as stack:
        client = dask_client(stack, workers or (None if scheduler else default_workers()), scheduler)
        futures = [client.submit(_route, str(arm), text, float(clearance), start.tolist(), goal.tolist(), seed + k,
                                 budget, pure=False) for k, (start, goal) in enumerate(q)]
        return [future.result() for future in futures]
