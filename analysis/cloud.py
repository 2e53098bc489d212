"""A workspace as a self-contained 3-D point cloud: one HTML file (Meshcat's ``StaticHtml``).

The tool points are a Drake ``PointCloud`` coloured by manipulability (viridis) in a Meshcat scene
with the arm itself at q = 0 (:mod:`armlab.presentation.replay`'s scene, turned so that gravity points
down, and camera), saved with
``Meshcat.StaticHtml()``, which inlines the three.js viewer: no server, no network needed.
"""

from __future__ import annotations

import html
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from armlab.analysis.plots import manipulability_norm
from armlab.files import write_file
from armlab.presentation.replay import SCENE, build_scene, frame_camera, start_meshcat, style_scene

if TYPE_CHECKING:
    from armlab.analysis.workspace import Workspace
    from armlab.models.arm import Arm

__all__ = ["colour_legend", "write_point_cloud"]


def write_point_cloud(arm: Arm, ws: Workspace, path: Path) -> Path:
    """Write ``ws``'s kept tool points (coloured by manipulability where known) and the arm as ``path``."""
    import matplotlib
    from pydrake.geometry import Rgba
    from pydrake.perception import BaseField, Fields, PointCloud

    pts = ws.points if ws.manipulability is None else ws.points[: len(ws.manipulability)]
    if ws.manipulability is None:
        rgb = np.tile(np.array([31, 95, 168], dtype=np.uint8), (len(pts), 1))
    else:
        shade = manipulability_norm(ws.manipulability)(ws.manipulability)
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
    page = meshcat.StaticHtml()
    end = page.rfind("</body>")
    return write_file(path, page[:end] + colour_legend(arm, ws, len(pts)) + page[end:])


#: Ticks on the colour legend of the point cloud.
LEGEND_TICKS = 5


def colour_legend(arm: Arm, ws: Workspace, shown: int) -> str:
    """The point cloud's colour legend (HTML, over the view's top-left corner), of its ``shown`` points: a bar of
    the colours from the least to the most manipulable point with :data:`LEGEND_TICKS` values of w = √det(J Jᵀ)
    under it (the colour scale :func:`~armlab.analysis.plots.manipulability_norm`, a square root: its ticks are
    evenly spaced in colour, not in w); or, without manipulability, what the one colour means."""
    import matplotlib

    head = f"<b>{html.escape(arm.name)}: workspace, {shown} tool points</b><br>"
    style = ("position:fixed;left:12px;top:12px;z-index:20;background:rgba(255,255,255,.92);padding:8px 12px;"
             "border:1px solid #b8bcc4;border-radius:4px;font:13px/1.4 Helvetica,Arial,sans-serif;color:#1d2733")
    if ws.manipulability is None:
        return (f'<div id="armlab-legend" style="{style}">{head}<span style="color:#1f5fa8">●</span> a tool point '
                "(one colour: manipulability not computed)</div>")
    stops = ", ".join(matplotlib.colors.to_hex(matplotlib.colormaps["viridis"](s)) for s in np.linspace(0, 1, 11))
    shades = np.linspace(0.0, 1.0, LEGEND_TICKS)
    values = np.atleast_1d(manipulability_norm(ws.manipulability).inverse(shades))
    ticks = "".join(f'<span style="position:absolute;left:{100 * s:.0f}%;transform:translateX(-50%)">{v:.3g}</span>'
                    for s, v in zip(shades, values, strict=True))
    return (f'<div id="armlab-legend" style="{style}">{head}colour = Yoshikawa manipulability w = √det(J Jᵀ)'
            f'<div style="width:260px;height:14px;margin:6px 28px 0;'
            f'background:linear-gradient(to right, {stops})"></div><div style="position:relative;width:260px;'
            f'height:18px;margin:0 28px;font-size:12px">{ticks}</div></div>')
