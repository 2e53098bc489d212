"""A workspace as a self-contained 3-D point cloud: one HTML file (Meshcat's ``StaticHtml``).

The tool points are a Drake ``PointCloud`` coloured by manipulability (viridis) in a Meshcat scene
with the arm itself at q = 0 (:mod:`armlab.diagrams.replay`'s scene, turned so that gravity points
down, and camera), saved with
``Meshcat.StaticHtml()``, which inlines the three.js viewer: no server, no network needed.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from armlab.diagrams.replay import SCENE, build_scene, frame_camera, start_meshcat, style_scene
from armlab.files import write_file

if TYPE_CHECKING:
    from armlab.analysis.workspace import Workspace
    from armlab.models.arm import Arm

__all__ = ["write_point_cloud"]


def write_point_cloud(arm: Arm, ws: Workspace, path: Path) -> Path:
    """Write ``ws``'s kept tool points (coloured by manipulability where known) and the arm as ``path``."""
    import matplotlib
    from pydrake.geometry import Rgba
    from pydrake.perception import BaseField, Fields, PointCloud

    pts = ws.points if ws.manipulability is None else ws.points[: len(ws.manipulability)]
    if ws.manipulability is None:
        rgb = np.tile(np.array([31, 95, 168], dtype=np.uint8), (len(pts), 1))
    else:
        w = ws.manipulability
        shade = matplotlib.colors.PowerNorm(0.5, vmin=float(w.min()), vmax=float(w.max()))(w)  # as slices.png
        rgb = (matplotlib.colormaps["viridis"](shade)[:, :3] * 255).astype(np.uint8)
    cloud = PointCloud(len(pts), Fields(BaseField.kXYZs | BaseField.kRGBs))
    cloud.mutable_xyzs()[:] = pts.T
    cloud.mutable_rgbs()[:] = rgb.T
    meshcat = start_meshcat()
    scene = build_scene(arm, meshcat)
    R = style_scene(meshcat, arm, pts)  # the arm's scene turned so that gravity points down
    scene.show(np.clip(np.zeros(arm.n), *arm.limit_arrays()))
    meshcat.SetObject(f"{SCENE}/workspace", cloud, point_size=max(ws.reach / 250, 1e-3), rgba=Rgba(1, 1, 1, 1))
    frame_camera(meshcat, pts @ R.T, margin=0.05 * ws.reach)
    return write_file(path, meshcat.StaticHtml())
