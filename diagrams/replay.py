"""A run of an arm as a standalone 3-D replay: one HTML file that plays the motion in any browser.

Paper 000 shows its arm moving in the Adams postprocessor (an .avi); armlab records the run with
Drake's ``MeshcatVisualizer`` into a Meshcat animation and saves ``Meshcat.StaticHtml()``, which
inlines the three.js viewer and every frame, so the file needs no server and no network.

The scene is styled so that the arm is what one sees: a plain white background without the floor
grid, the camera placed to frame the arm's reach (:func:`frame_camera`), and the path of the tool
point drawn as a line. :mod:`armlab.diagrams.view` (``armlab view``) shares the scene set-up.
"""

from __future__ import annotations

import logging
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.files import write_file

if TYPE_CHECKING:
    from pydrake.geometry import Meshcat

    from armlab.models.arm import Arm

__all__ = [
    "MAX_FPS",
    "MAX_FRAMES",
    "Scene",
    "build_scene",
    "frame_camera",
    "reach_points",
    "start_meshcat",
    "style_scene",
    "write_replay",
]

#: Highest frame rate of a replay (frames per second); long runs get fewer (see :data:`MAX_FRAMES`).
MAX_FPS = 30.0
#: Most frames in one replay: a run longer than ``MAX_FRAMES / MAX_FPS`` seconds is sampled more sparsely.
MAX_FRAMES = 1800
#: Vertical field of view of Meshcat's default perspective camera (three.js, degrees).
CAMERA_FOV_DEG = 75.0
#: Width / height the camera framing assumes (a landscape browser window is at least this wide).
CAMERA_ASPECT = 1.25
#: Path of the tool-path line in the Meshcat scene tree.
TOOL_PATH = "/tool_path"
_PATH_RGBA = (0.0, 0.5, 0.1, 1.0)


@dataclass
class Scene:
    """A built diagram of the arm's plant, scene graph and Meshcat visualizer, with a context."""

    diagram: Any
    plant: Any
    visualizer: Any
    context: Any
    position_index: NDArray[np.intp]  # arm joint k → index in the plant's position vector

    def show(self, q: NDArray[np.float64], time: float = 0.0) -> None:
        """Set the arm's joints to ``q`` (arm joint order) at ``time`` and publish to Meshcat."""
        self.context.SetTime(time)
        positions = np.empty(len(self.position_index))
        positions[self.position_index] = q
        self.plant.SetPositions(self.plant.GetMyMutableContextFromRoot(self.context), positions)
        self.visualizer.ForcedPublish(self.visualizer.GetMyContextFromRoot(self.context))


@contextmanager
def _quiet_drake() -> Iterator[None]:
    """Silence Drake's INFO lines (e.g. "Meshcat listening for connections at …") inside the block."""
    logger = logging.getLogger("drake")
    level = logger.level
    logger.setLevel(logging.WARNING)
    try:
        yield
    finally:
        logger.setLevel(level)


def start_meshcat(port: int | None = 0) -> Meshcat:
    """A Meshcat server on localhost only, without Drake's "listening" log line.

    ``port=0``: any free port; ``None``: Meshcat's own choice, the first free one from 7000.
    Raises ``RuntimeError`` when the port is in use.
    """
    from pydrake.geometry import Meshcat, MeshcatParams

    params = MeshcatParams(host="localhost", show_stats_plot=False)
    if port is not None:
        params.port = port
    with _quiet_drake():
        return Meshcat(params)


def build_scene(arm: Arm, meshcat: Meshcat, publish_period: float = 1 / MAX_FPS, extra: Any = None) -> Scene:
    """Plant + SceneGraph from ``arm.add_to_plant`` and a ``MeshcatVisualizer`` on ``meshcat``.

    ``extra(builder, plant)`` may add systems (e.g. joint sliders) before the diagram is built.
    Gravity is irrelevant: the plant is only posed, never simulated.
    """
    from pydrake.geometry import MeshcatVisualizer, MeshcatVisualizerParams
    from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
    from pydrake.systems.framework import DiagramBuilder

    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, 0.0)
    arm.add_to_plant(plant)
    plant.Finalize()
    visualizer = MeshcatVisualizer.AddToBuilder(
        builder, scene_graph, meshcat, MeshcatVisualizerParams(publish_period=publish_period)
    )
    if extra is not None:
        extra(builder, plant)
    diagram = builder.Build()
    index = np.array([plant.GetJointByName(name).position_start() for name in arm.joint_names], dtype=np.intp)
    return Scene(diagram, plant, visualizer, diagram.CreateDefaultContext(), index)


def style_scene(meshcat: Meshcat) -> None:
    """A plain white background and no floor grid or world axes, so the arm stands out.

    (Meshcat's gradient background is hidden rather than recoloured: seen from steeply above,
    its texture leaves a wedge of a different colour at the window's edge.)
    """
    meshcat.SetProperty("/Background", "visible", False)
    meshcat.SetProperty("/Grid", "visible", False)
    meshcat.SetProperty("/Axes", "visible", False)


def reach_points(arm: Arm, q: ArrayLike) -> NDArray[np.float64]:
    """Origins of every frame of the arm (base, links, tool, named points) over the batch ``q``, shape (M, 3).

    The links are drawn between these origins (:mod:`armlab.models.urdf`), so their bounding box is
    the space the arm occupies.
    """
    q = np.asarray(q, dtype=float).reshape(-1, arm.n)
    frames = arm.table.frames(q)[..., :3, 3].reshape(-1, 3)
    named = [p.reshape(-1, 3) for p in arm.forward(q).points.values()]
    return np.concatenate([frames, *named])


def _view_directions() -> NDArray[np.float64]:
    """Candidate directions from the target to the camera, most customary first.

    Azimuths every 30° and elevations 20° … 70°, ordered by how far they are from the usual
    front-right three-quarter view (azimuth −60°, elevation 30°).
    """
    az, el = np.meshgrid(np.arange(-180.0, 180.0, 30.0), np.array([20.0, 30.0, 45.0, 60.0, 70.0]), indexing="ij")
    az, el = az.ravel(), el.ravel()
    order = np.argsort(np.abs((az + 60.0 + 180.0) % 360.0 - 180.0) / 30.0 + np.abs(el - 30.0) / 15.0, kind="stable")
    az, el = np.radians(az[order]), np.radians(el[order])
    return np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], axis=-1)


def _fit(rel: NDArray, d: NDArray, margin: float) -> tuple[NDArray, NDArray, NDArray]:
    """For each view direction ``d`` (K, 3): the camera distance at which every point ``rel`` (M, 3)
    (relative to the target, grown by ``margin``) is inside the perspective view, the fraction of
    the window the points' screen bounding box then fills, and that box's centre in window units.
    """
    right = np.cross(np.array([0.0, 0.0, 1.0]), d)
    right /= np.linalg.norm(right, axis=1, keepdims=True)
    up = np.cross(d, right)
    x, y, z = rel @ right.T, rel @ up.T, rel @ d.T  # (M, K): screen right, screen up, toward the camera
    tan_y = np.tan(np.radians(CAMERA_FOV_DEG) / 2)
    tan_x = tan_y * CAMERA_ASPECT
    distance = np.maximum(z + (np.abs(x) + margin) / tan_x, z + (np.abs(y) + margin) / tan_y).max(axis=0) + margin
    sx = x / ((distance - z) * tan_x)  # window coordinates, −1 … 1 across the view
    sy = y / ((distance - z) * tan_y)
    fill = (sx.max(axis=0) - sx.min(axis=0)) * (sy.max(axis=0) - sy.min(axis=0)) / 4
    centre = np.stack([(sx.max(axis=0) + sx.min(axis=0)) / 2, (sy.max(axis=0) + sy.min(axis=0)) / 2], axis=-1)
    shift = centre[:, :1] * distance[:, None] * tan_x * right + centre[:, 1:] * distance[:, None] * tan_y * up
    return distance, fill, shift


def frame_camera(meshcat: Meshcat, points: ArrayLike, margin: float = 0.0) -> tuple[NDArray, NDArray]:
    """Place Meshcat's camera so that ``points`` (M, 3) — the arm's reach — fill the view.

    Of a set of oblique view directions, the most customary one (front-right three-quarter view
    first) whose view of the points fills at least 80 % as much of a :data:`CAMERA_ASPECT` window
    as the best one is chosen — so a planar arm is seen from above its plane, not edge-on — and the
    camera is moved as close as the perspective view allows with every point, grown by ``margin``
    metres, inside. Returns (camera, target) in Drake's world frame.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if pts.size == 0 or not np.all(np.isfinite(pts)):
        raise ValueError("frame_camera: points must be a non-empty array of finite (x, y, z)")
    target = (pts.min(axis=0) + pts.max(axis=0)) / 2
    d = _view_directions()
    _, fill, _ = _fit(pts - target, d, margin)
    d = d[int(np.argmax(fill >= 0.8 * fill.max()))][None, :]
    for _ in range(2):  # centre the picture: aim at the middle of the points' screen bounding box
        distance, _, shift = _fit(pts - target, d, margin)
        target = target + shift[0]
    distance, _, _ = _fit(pts - target, d, margin)
    camera = target + max(float(distance[0]), 1e-3) * d[0]
    meshcat.SetCameraPose(camera, target)
    return camera, target


def _frames(times: NDArray[np.float64]) -> tuple[float, NDArray[np.int64], NDArray[np.float64]]:
    """Frame rate, frame numbers k and sample times (k / fps clipped to the run) of a replay.

    The rate is :data:`MAX_FPS`, lowered so that a long run has at most :data:`MAX_FRAMES` frames.
    Frame k plays at time k / fps, so playback time is the run's time.
    """
    duration = times[-1] - times[0]
    fps = MAX_FPS if duration * MAX_FPS <= MAX_FRAMES - 2 else (MAX_FRAMES - 2) / duration
    k = np.arange(np.floor(times[0] * fps), np.ceil(times[-1] * fps) + 1).astype(np.int64)
    return fps, k, np.clip(k / fps, times[0], times[-1])


def _interpolate(t: NDArray, times: NDArray, values: NDArray) -> NDArray:
    """Column-wise linear interpolation of ``values`` (N, k) sampled at ``times`` onto ``t``."""
    return np.stack([np.interp(t, times, column) for column in values.T], axis=-1)


def _check_run(arm: Arm, times: ArrayLike, q: ArrayLike, tool_path: ArrayLike | None) -> tuple[NDArray, ...]:
    times = np.asarray(times, dtype=float)
    q = np.asarray(q, dtype=float)
    if times.ndim != 1 or times.size == 0:
        raise ValueError(f"replay: times must be a non-empty 1-D array, got shape {times.shape}")
    if q.shape != (times.size, arm.n):
        raise ValueError(f"replay: q must have shape ({times.size}, {arm.n}) for {arm.name}, got {q.shape}")
    if not (np.all(np.isfinite(times)) and np.all(np.isfinite(q))):
        raise ValueError("replay: times and q must be finite (found NaN or inf)")
    if times[0] < 0 or np.any(np.diff(times) < 0):
        raise ValueError(f"replay: times must start at ≥ 0 s and be non-decreasing (first: {times[0]:g} s)")
    if tool_path is not None:
        tool_path = np.asarray(tool_path, dtype=float)
        if tool_path.shape != (times.size, 3) or not np.all(np.isfinite(tool_path)):
            raise ValueError(f"replay: tool_path must be finite with shape ({times.size}, 3), got {tool_path.shape}")
    return times, q, tool_path


def write_replay(
    arm: Arm, times: NDArray, q: NDArray, path: Path, tool_path: NDArray | None = None
) -> Path:
    """Record the run ``q(times)`` (N, n) of ``arm`` and save it as one self-contained HTML file at ``path``.

    The motion is resampled to uniform frames (≤ :data:`MAX_FPS` fps), posed in a Drake plant and
    recorded by ``MeshcatVisualizer`` into a Meshcat animation that plays on opening (playback time
    = the run's time). ``tool_path`` (N, 3), the tool point's positions, is drawn as a line; by
    default it is the arm's forward kinematics of ``q``. The camera frames everything the arm
    occupies during the run. The file is written atomically (:func:`~armlab.files.write_file`).
    """
    times, q, tool_path = _check_run(arm, times, q, tool_path)
    if tool_path is None:
        tool_path = arm.forward(q).tool[:, :3, 3]
    path = Path(path)
    fps, k, t = _frames(times)
    frames_q = _interpolate(t, times, q)

    meshcat = start_meshcat()
    scene = build_scene(arm, meshcat, publish_period=1 / fps)
    style_scene(meshcat)
    radius = max(body.radius for body in arm.bodies)
    frame_camera(meshcat, np.concatenate([reach_points(arm, frames_q), tool_path]), margin=2.5 * radius)
    meshcat.SetLine(TOOL_PATH, tool_path.T.copy(), line_width=3.0, rgba=_rgba(_PATH_RGBA))
    scene.visualizer.StartRecording(set_transforms_while_recording=False)
    # The recording files a publish at time τ under frame floor(τ · fps); publishing half a frame
    # late keeps rounding from putting two samples in one frame.
    for frame, q_frame in zip(k, frames_q, strict=True):
        scene.show(q_frame, (frame + 0.5) / fps)
    scene.visualizer.StopRecording()
    scene.show(frames_q[0], float(t[0]))  # the static scene (before playback) shows the first pose
    scene.visualizer.PublishRecording()
    html = meshcat.StaticHtml()
    write_file(path, html)
    return path


def _rgba(values: tuple[float, float, float, float]) -> Any:
    from pydrake.geometry import Rgba

    return Rgba(*values)
