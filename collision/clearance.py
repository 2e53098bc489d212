"""Clearances by pair: of one configuration (``armlab check``, ``armlab.clearance``) and along a motion (simulate).

A clearance is a pair's signed distance (m): positive apart, negative in contact, −clearance the penetration
depth. Along a motion, a pair whose clearance drops below zero is a *collision*, reported like a passed joint
limit (:func:`collisions`): the pair, the first time and the deepest penetration.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import below
from armlab.collision.model import Clearances, CollisionModel, NoGeometryError
from armlab.collision.scene import Scene, read_scene

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = [
    "as_scene",
    "clearance",
    "collisions",
    "contacts",
    "format_collision",
    "motion_clearance",
    "pair_minima",
]


def as_scene(scene: Scene | str | Path | None) -> Scene | None:
    """A :class:`Scene`, or the one in the file ``scene`` names (:func:`armlab.collision.scene.read_scene`)."""
    return scene if scene is None or isinstance(scene, Scene) else read_scene(scene)


def clearance(arm: Arm, q: ArrayLike, scene: Scene | str | Path | None = None) -> list[dict[str, Any]]:
    """Every checked pair's clearance at ``q`` ``(n,)`` (rad, m), smallest first.

    Each ``{"pair": "A–B", "a", "b", "distance" (m), "depth" (m, > 0 in contact, else 0), "point_a",
    "point_b" (m, world: the closest points on A and B)}``. ``ValueError`` for a ``q`` outside the limits,
    a bad scene, or an arm without collision geometry.
    """
    q = arm.check_q(q)
    if q.ndim != 1:
        raise ValueError(f"q has shape {q.shape}: give one configuration of {arm.n} joint values")
    found = CollisionModel(arm, as_scene(scene)).distances(q)
    rows = [{"pair": name, "a": a, "b": b, "distance": float(d), "depth": float(max(0.0, -d)),
             "point_a": pa.tolist(), "point_b": pb.tolist()}
            for name, (a, b), d, pa, pb in zip(found.names(), found.pairs, found.distance, found.point_a,
                                               found.point_b, strict=True)]
    return sorted(rows, key=lambda row: row["distance"])


def contacts(arm: Arm, q: ArrayLike, scene: Scene | str | Path | None = None) -> list[tuple[list[str], float | None]]:
    """Per configuration of ``q`` ``(m, n)`` (rad, m; e.g. the IK solutions of one target): the pairs in contact
    (their names, "A–B") and the smallest clearance (m; ``None`` where the arm has no pair to check).
    ``ValueError`` as :func:`clearance`."""
    found = CollisionModel(arm, as_scene(scene)).distances(np.asarray(q, dtype=float).reshape(-1, arm.n))
    return [([name for name, d in zip(found.names(), row, strict=True) if below(d, 0.0)],
             float(row.min()) if row.size else None) for row in found.distance]


def pair_minima(t: NDArray[np.float64], found: Clearances) -> list[dict[str, Any]]:
    """Each pair's smallest clearance over the samples at times ``t`` ``(N,)`` (s) and when: ``{"pair",
    "min_clearance" (m), "time" (s)}``, in the model's pair order."""
    at = np.argmin(found.distance, axis=0) if len(t) else np.zeros(len(found.pairs), dtype=int)
    return [{"pair": name, "min_clearance": float(found.distance[k, j]), "time": float(t[k])}
            for j, (name, k) in enumerate(zip(found.names(), at, strict=True))]


def collisions(t: NDArray[np.float64], found: Clearances) -> list[dict[str, Any]]:
    """The pairs in contact at some sample: ``{"pair", "first_time" (s), "depth" (m, the deepest), "time_deepest"
    (s)}`` in the order they first touch."""
    out = []
    for j, name in enumerate(found.names()):
        touching = np.flatnonzero(below(found.distance[:, j], 0.0))
        if len(touching):
            deepest = int(np.argmin(found.distance[:, j]))
            out.append({"pair": name, "first_time": float(t[touching[0]]), "depth": float(-found.distance[deepest, j]),
                        "time_deepest": float(t[deepest])})
    return sorted(out, key=lambda c: c["first_time"])


def motion_clearance(arm: Arm, t: ArrayLike, q: ArrayLike, scene: Scene | str | Path | None = None
                     ) -> tuple[dict[str, Any], Clearances | None]:
    """Clearances along a motion sampled at ``t`` ``(N,)`` (s) with joint values ``q`` ``(N, n)``.

    ``({"collision_check": what was checked, "collisions": [...], "min_clearance": [pair minima]}, clearances)``
    (see :func:`collisions`, :func:`pair_minima`). An arm without collision geometry and no scene: not checked,
    said in ``collision_check``, ``collisions`` and ``min_clearance`` ``None`` (never "no collision"); with a scene
    it is a ``ValueError``.
    """
    t = np.asarray(t, dtype=float)
    scene = as_scene(scene)
    model = CollisionModel.optional(arm, scene)
    if model is None:
        return {"collision_check": f"not checked: {NoGeometryError.of(arm)}", "collisions": None,
                "min_clearance": None}, None
    found = model.distances(q)
    where = "itself" if scene is None else f"itself and the {len(scene.obstacles)} obstacle(s) of {scene.source}"
    return ({"collision_check": f"{len(found.pairs)} pair(s) checked: the arm against {where}",
             "collisions": collisions(t, found), "min_clearance": pair_minima(t, found)}, found)


def format_collision(c: dict[str, Any]) -> str:
    """One line for a collision: the pair, the first time, the deepest penetration and when."""
    return (f"collision {c['pair']}: first at t = {c['first_time']:.4g} s, penetration up to "
            f"{c['depth'] * 1e3:.4g} mm (t = {c['time_deepest']:.4g} s)")
