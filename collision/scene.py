"""A scene of obstacles around an arm: a JSON file (``--scene``) of boxes, cylinders, spheres and a floor.

The format (the README's section "Collisions: the scene file")::

    {"obstacles": [
      {"name": "table", "shape": "box", "size": [0.6, 0.4, 0.05], "xyz": [0.5, 0, 0.1], "rpy": [0, 0, 0]},
      {"name": "post", "shape": "cylinder", "radius": 0.05, "length": 0.6, "xyz": [-0.3, 0.2, 0.3]},
      {"name": "ball", "shape": "sphere", "radius": 0.08, "xyz": [0, -0.4, 0.3]},
      {"name": "floor", "shape": "floor", "z": -0.05}
    ]}

Poses are in the arm's base (world) frame: ``xyz`` (m) the shape's centre, ``rpy`` (rad, roll-pitch-yaw
as a URDF ``origin``; default 0); a box's ``size`` is its full edges (m), a cylinder's axis is its own z.
The floor is the plane z = ``z`` (m, default 0), everything below it solid. Names are unique and say
which obstacle a clearance is to (at most 100 characters, no control characters). At most
:data:`MAX_OBSTACLES` obstacles, checked before any is read: Drake's scene graph registers them one by one
and its time grows faster than their count. Anything else is a one-line ``ValueError`` naming the bad value.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armlab.files import check_name, is_json_number, read_json
from armlab.kinematics.ik_target import pose
from armlab.limits import LIMITS
from armlab.values import cut, shown

__all__ = ["MAX_OBSTACLES", "SHAPES", "Obstacle", "Scene", "read_scene", "scene_from_dict"]

#: Each shape's keys beyond ``name``, ``shape``, ``xyz`` and ``rpy``.
SHAPES: dict[str, tuple[str, ...]] = {"box": ("size",), "cylinder": ("radius", "length"), "sphere": ("radius",),
                                      "floor": ("z",)}
#: The most obstacles a scene may have (1 000 spheres take about 3 s to set up).
MAX_OBSTACLES = 1000
#: The largest obstacle size or coordinate (m): :data:`~armlab.limits.LIMITS`' coordinate bound.
_LARGEST = LIMITS["coordinate"].high


@dataclass(frozen=True)
class Obstacle:
    """One obstacle: ``shape`` (a key of :data:`SHAPES`), its ``size`` (m: box (x, y, z) edges, cylinder
    (radius, length), sphere (radius,), floor ()) and its pose ``X`` in the world (4×4 nested tuples)."""

    name: str
    shape: str
    size: tuple[float, ...]
    X: tuple[tuple[float, ...], ...]

    @property
    def pose(self) -> NDArray[np.float64]:
        """The obstacle's pose in the world, ``(4, 4)``."""
        return np.array(self.X)


@dataclass(frozen=True)
class Scene:
    """The obstacles of a scene file (``source`` names it in messages)."""

    obstacles: tuple[Obstacle, ...]
    source: str = "scene"


def _number(raw: Any, what: str, positive: bool = False) -> float:
    if not is_json_number(raw) or not math.isfinite(raw) or abs(raw) > _LARGEST or (positive and raw <= 0):
        need = "a finite number > 0 (m)" if positive else f"a finite number within ±{_LARGEST:g}"
        raise ValueError(f"{what} = {shown(raw)} is not allowed: give {need}")
    return float(raw)


def _triple(raw: Any, what: str, positive: bool = False) -> NDArray[np.float64]:
    if not isinstance(raw, list) or len(raw) != 3:
        raise ValueError(f"{what} = {shown(raw)} is not allowed: give a list of 3 numbers")
    return np.array([_number(v, f"{what}[{k}]", positive) for k, v in enumerate(raw)])


def _obstacle(raw: Any, where: str) -> Obstacle:
    if not isinstance(raw, dict):
        raise ValueError(f"{where}: an obstacle is a JSON object with name, shape and pose, not {shown(raw)}")
    shape = raw.get("shape")
    if shape not in SHAPES:
        raise ValueError(f"{where}: shape {shown(shape)} is not allowed: give one of {', '.join(SHAPES)}")
    name = raw.get("name")
    if not isinstance(name, str) or not name.strip():
        raise ValueError(f"{where}: name {shown(name)} is not allowed: give each obstacle a name (text, ≤ 100 "
                         "characters)")
    check_name(name, f"{where}: name")
    where = f"{where} ({name})"
    pose_keys = ("z",) if shape == "floor" else ("xyz", "rpy")
    unknown = sorted(set(raw) - {"name", "shape", *SHAPES[shape], *pose_keys})
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {cut(', '.join(unknown))}; a {shape} takes name, shape, "
                         + ", ".join(dict.fromkeys((*SHAPES[shape], *pose_keys))))
    if shape == "floor":
        X = np.eye(4)
        X[2, 3] = _number(raw.get("z", 0.0), f"{where}: z")
        size: tuple[float, ...] = ()
    else:
        if "xyz" not in raw:
            raise ValueError(f"{where}: the pose needs xyz (m), the {shape}'s centre")
        X = pose(_triple(raw["xyz"], f"{where}: xyz"), _triple(raw.get("rpy", [0, 0, 0]), f"{where}: rpy"))
        missing = [key for key in SHAPES[shape] if key not in raw]
        if missing:
            raise ValueError(f"{where}: a {shape} needs {', '.join(missing)} (m)")
        if shape == "box":
            size = tuple(float(v) for v in _triple(raw["size"], f"{where}: size", positive=True))
        else:
            size = tuple(_number(raw[key], f"{where}: {key}", positive=True) for key in SHAPES[shape])
    return Obstacle(name, shape, size, tuple(tuple(float(v) for v in row) for row in X))


def scene_from_dict(data: Any, source: str = "scene") -> Scene:
    """The :class:`Scene` of a parsed scene file's JSON ``data``; ``ValueError`` (naming ``source``) if malformed."""
    if not isinstance(data, dict) or set(data) != {"obstacles"} or not isinstance(data["obstacles"], list):
        raise ValueError(f"{source}: a scene is a JSON object with one key, \"obstacles\", a list of obstacles")
    if len(data["obstacles"]) > MAX_OBSTACLES:
        raise ValueError(f"{source}: {len(data['obstacles']):,} obstacles, more than the {MAX_OBSTACLES:,} allowed "
                         "(armlab.collision.scene.MAX_OBSTACLES)")
    obstacles = tuple(_obstacle(raw, f"{source}: obstacle {k + 1}") for k, raw in enumerate(data["obstacles"]))
    repeated = sorted(name for name, count in Counter(o.name for o in obstacles).items() if count > 1)
    if repeated:
        raise ValueError(f"{source}: obstacle name(s) {cut(', '.join(repeated))} appear more than once: names are "
                         "unique")
    return Scene(obstacles, source)


def read_scene(path: str | Path) -> Scene:
    """The scene in the JSON file ``path`` (the module docstring gives the format); a one-line ``ValueError`` for
    what is wrong in it."""
    return scene_from_dict(read_json(path, "--scene"), f"--scene {path}")
