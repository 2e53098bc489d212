"""A run of an arm as a standalone 3-D replay: one HTML file that plays the motion in any browser.

Paper 000 shows its arm moving in the Adams postprocessor (an .avi); armlab records the run with
Drake's ``MeshcatVisualizer`` into a Meshcat animation and saves ``Meshcat.StaticHtml()``, which
inlines the three.js viewer and every frame, so the file needs no server and no network.

The scene is styled for a classroom projector (:func:`style_scene`): a plain white background, the
arm turned so that gravity points down the screen, a floor grid and the world axes, the camera
framing everything the arm occupies (:func:`frame_camera`; a planar arm face-on), and the path of
the tool point drawn as a line. Below the view, the page has play/pause, loop and a time slider and
reads out t, q and τ; a motion of several runs (a branch switch) pauses at each join under a banner
(:func:`write_replay`). :mod:`armlab.presentation.view` (``armlab view``) shares the scene set-up.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import below
from armlab.files import file_path, write_file
from armlab.presentation.replay_graphs import (
    GRAPHS_PCT,
    GRAPHS_SCRIPT,
    GRAPHS_STYLE,
    Graph,
    arm_graphs,
    graph_data,
    log_graphs,
)

if TYPE_CHECKING:
    from pydrake.geometry import Meshcat

    from armlab.collision.model import Clearances, CollisionModel
    from armlab.collision.scene import Scene as Obstacles
    from armlab.diagrams.simulate import SimulationLog
    from armlab.models.arm import Arm

__all__ = [
    "MAX_FPS",
    "MAX_FRAMES",
    "SOFTWARE_GL",
    "Scene",
    "build_scene",
    "frame_camera",
    "log_page",
    "reach_points",
    "replay_page",
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
#: Width / height of a replay's 3-D view, which shares the window with the graphs (:data:`GRAPHS_PCT` of its
#: width): a 1000 × 800 window's view is 600 × 696 px; wider windows show the arm with more room around it.
REPLAY_ASPECT = 0.85
#: Meshcat path of the arm's scene (Drake's visualizer draws under ``/drake/visualizer``); turned so
#: that gravity points down (:func:`display_rotation`).
SCENE = "/drake"
#: Path of the tool-path line in the Meshcat scene tree.
TOOL_PATH = f"{SCENE}/tool_path"
#: Path of the payload sphere and of the floor grid.
PAYLOAD = f"{SCENE}/payload"
FLOOR = "/floor"
#: Paths of the collision layer: the arm's and the scene's collision geometry (Drake's proximity role) drawn by a
#: second ``MeshcatVisualizer``, and the same shapes again in :data:`CONTACT_RGBA` by a third, each shape shown in
#: one of the two at every frame: in the contact colour where it touches (:func:`_collision_layer`).
COLLISION = f"{SCENE}/collision"
CONTACT = f"{SCENE}/contact"
#: Colour of the collision layer (semi-transparent: the visuals stay visible) and of a shape in contact.
COLLISION_RGBA = (0.55, 0.25, 0.85, 0.5)
CONTACT_RGBA = (0.95, 0.05, 0.05, 0.85)
#: Opacity of the visuals while the collision layer is shown (the shapes often coincide with them).
VISUAL_OPACITY_UNDER_LAYER = 0.3
#: Playback seconds the replay holds at a join of two runs (a branch switch), before the next run.
JOIN_PAUSE = 1.5
_PATH_RGBA = (0.0, 0.5, 0.1, 1.0)
#: Colour of a body whose URDF gives it no material (Drake's default, light grey, vanishes on white).
DEFAULT_RGBA = (0.85, 0.45, 0.12, 1.0)


@dataclass
class Scene:
    """A built diagram of the arm's plant (in the arm's joint order), scene graph and Meshcat visualizer, with a
    context; ``layers``: the visualizers of the collision layer (:data:`COLLISION`, :data:`CONTACT`), if drawn."""

    diagram: Any
    plant: Any
    visualizer: Any
    context: Any
    scene_graph: Any = None
    layers: tuple[Any, ...] = ()

    def show(self, q: NDArray[np.float64], time: float = 0.0) -> None:
        """Set the arm's joints to ``q`` (arm joint order, the plant's) at ``time`` and publish to Meshcat."""
        self.context.SetTime(time)
        self.plant.SetPositions(self.plant.GetMyMutableContextFromRoot(self.context), q)
        for visualizer in (self.visualizer, *self.layers):
            visualizer.ForcedPublish(visualizer.GetMyContextFromRoot(self.context))


def start_meshcat(port: int | None = 0) -> Meshcat:
    """A Meshcat server on localhost only, without Drake's "listening" log line.

    ``port=0``: any free port; ``None``: Meshcat's own choice, the first free one from 7000.
    Raises ``RuntimeError`` when the port is in use.
    """
    from pydrake.geometry import Meshcat, MeshcatParams

    # lazy: armlab --help loads armlab.presentation.replay but not this (start-up time)
    from armlab.models.plant import quiet_drake

    params = MeshcatParams(host="localhost", show_stats_plot=False)
    if port is not None:
        params.port = port
    with quiet_drake():  # "Meshcat listening for connections at …"
        return Meshcat(params)


def build_scene(arm: Arm, meshcat: Meshcat, publish_period: float = 1 / MAX_FPS, extra: Any = None,
                obstacles: Obstacles | None = None, collision: bool = False) -> Scene:
    """The arm's plant with its geometry in a SceneGraph (:func:`~armlab.models.plant.add_arm_plant`) and a
    ``MeshcatVisualizer`` on ``meshcat``.

    ``extra(builder, plant)`` may add systems (e.g. joint sliders) before the diagram is built.
    ``obstacles``: a scene's obstacles registered too (collision geometry of the world). ``collision``: two more
    visualizers of the proximity role draw the collision geometry at :data:`COLLISION` (:data:`COLLISION_RGBA`)
    and at :data:`CONTACT` (:data:`CONTACT_RGBA`), both hidden until the page's toggle shows them.
    Gravity is irrelevant: the plant is only posed, never simulated.
    """
    from pydrake.geometry import MeshcatVisualizer, MeshcatVisualizerParams, Role
    from pydrake.systems.framework import DiagramBuilder

    # lazy: armlab --help loads armlab.presentation.replay but not this (start-up time)
    from armlab.models.plant import PlantOptions, add_arm_plant, default_context

    builder = DiagramBuilder()
    plant, scene_graph = add_arm_plant(builder, arm, PlantOptions(geometry=True, scene=obstacles))
    assert scene_graph is not None, "add_arm_plant makes a scene graph for PlantOptions(geometry=True)"
    visualizer = MeshcatVisualizer.AddToBuilder(
        builder, scene_graph, meshcat,
        MeshcatVisualizerParams(publish_period=publish_period, default_color=_rgba(DEFAULT_RGBA)),
    )
    layers = tuple(MeshcatVisualizer.AddToBuilder(builder, scene_graph, meshcat, MeshcatVisualizerParams(
        publish_period=publish_period, role=Role.kProximity, prefix=path.rsplit("/", 1)[1], default_color=_rgba(rgba),
        visible_by_default=False, delete_on_initialization_event=False))
        for path, rgba in ((COLLISION, COLLISION_RGBA), (CONTACT, CONTACT_RGBA)) if collision)
    if extra is not None:
        extra(builder, plant)
    diagram = builder.Build()
    return Scene(diagram, plant, visualizer, default_context(diagram), scene_graph, layers)


def display_rotation(arm: Arm) -> NDArray[np.float64]:
    """The rotation R (3×3) under which the arm is shown: R·ĝ = −z, so gravity points down the screen.

    Meshcat's camera keeps its up vector along the root's +z; the arm's scene (``/drake``) is turned
    by R. For rr (gravity −y) that is Rx(90°): its plane becomes the vertical x-z plane.
    """
    g = np.asarray(arm.gravity, dtype=float)
    if not np.any(g):
        return np.eye(3)
    g = g / np.linalg.norm(g)
    down = np.array([0.0, 0.0, -1.0])
    axis = np.cross(g, down)
    s, c = np.linalg.norm(axis), float(g @ down)
    if s < 1e-12:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])  # already down, or up: a half turn about x
    k = axis / s
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + s * K + (1 - c) * K @ K  # Rodrigues


def style_scene(meshcat: Meshcat, arm: Arm, points: ArrayLike) -> NDArray[np.float64]:
    """A plain white background, the arm turned so that gravity points down (:func:`display_rotation`),
    a floor grid under ``points`` (M, 3) (what the arm occupies, world frame) and the world axes.

    Meshcat's own grid and axes are hidden (they would be in the turned frame's place, 10 m wide);
    the floor drawn instead is perpendicular to gravity, just below the lowest point, with 0.1 m,
    0.25 m or 1 m squares. The world axes are red, green, blue cylinders (x, y, z) at the world origin.
    (Meshcat's gradient background is hidden rather than recoloured: seen from steeply above, its
    texture leaves a wedge of a different colour at the window's edge.) Returns the rotation.
    """
    from pydrake.geometry import Cylinder
    from pydrake.math import RigidTransform, RotationMatrix

    meshcat.SetProperty("/Background", "visible", False)
    meshcat.SetProperty("/Grid", "visible", False)
    meshcat.SetProperty("/Axes", "visible", False)
    R = display_rotation(arm)
    meshcat.SetTransform(SCENE, RigidTransform(RotationMatrix(R), np.zeros(3)))
    shown = np.asarray(points, dtype=float).reshape(-1, 3) @ R.T
    lo, hi = shown.min(axis=0), shown.max(axis=0)
    size = max(float(np.ptp(shown[:, :2], axis=0).max()), float(np.ptp(shown[:, 2])), 0.1)
    step = 0.1 if size < 1.5 else (0.25 if size < 4 else 1.0)
    half = np.ceil(0.75 * size / step) * step
    centre = np.round((lo + hi)[:2] / 2 / step) * step
    ticks = np.arange(-half, half + step / 2, step)
    z = min(lo[2], 0.0) - 1e-3
    x, y = centre
    starts = [(x + v, y - half, z) for v in ticks] + [(x - half, y + v, z) for v in ticks]
    ends = [(x + v, y + half, z) for v in ticks] + [(x + half, y + v, z) for v in ticks]
    # The grid lives in the root (display) frame: it is the floor whatever way the arm is turned.
    meshcat.SetLineSegments(FLOOR, np.array(starts).T.copy(), np.array(ends).T.copy(), 1.0,
                            _rgba((0.72, 0.74, 0.78, 1.0)))
    length, radius = 0.15 * size, 0.006 * size
    for j, (axis, color) in enumerate(zip("xyz", ((0.85, 0.1, 0.1, 1.0), (0.1, 0.65, 0.1, 1.0),
                                                   (0.1, 0.3, 0.9, 1.0)), strict=True)):
        direction = np.eye(3)[j]
        # Meshcat's cylinder runs along its z: turn z onto the axis, centre it half-way along.
        turn = RotationMatrix.MakeFromOneVector(direction, 2)
        meshcat.SetObject(f"{SCENE}/world_axes/{axis}", Cylinder(radius, length), _rgba(color))
        meshcat.SetTransform(f"{SCENE}/world_axes/{axis}", RigidTransform(turn, direction * length / 2))
    return R


def reach_points(arm: Arm, q: ArrayLike) -> NDArray[np.float64]:
    """Origins of every frame of the arm (base, links, tool, named points) over the batch ``q``, shape (M, 3).

    The links are drawn between these origins (:mod:`armlab.models.write_urdf`), so their bounding box is
    the space the arm occupies.
    """
    q = np.asarray(q, dtype=float).reshape(-1, arm.n)
    frames = arm.table.frames(q)[..., :3, 3].reshape(-1, 3)
    named = [p.reshape(-1, 3) for p in arm.forward(q).points.values()]
    return np.concatenate([frames, *named])


def _view_directions() -> NDArray[np.float64]:
    """Candidate directions from the target to the camera, most customary first.

    Azimuths every 30° and elevations 15° … 45° (gravity, −z on the display, points down the
    screen), ordered by how far they are from the usual front-right three-quarter view
    (azimuth −60°, elevation 30°).
    """
    az, el = np.meshgrid(np.arange(-180.0, 180.0, 30.0), np.array([15.0, 20.0, 30.0, 45.0]), indexing="ij")
    az, el = az.ravel(), el.ravel()
    order = np.argsort(np.abs((az + 60.0 + 180.0) % 360.0 - 180.0) / 30.0 + np.abs(el - 30.0) / 15.0, kind="stable")
    az, el = np.radians(az[order]), np.radians(el[order])
    return np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], axis=-1)


def _fit(rel: NDArray, d: NDArray, margin: float, aspect: float) -> tuple[NDArray, NDArray, NDArray]:
    """For each view direction ``d`` (K, 3): the camera distance at which every point ``rel`` (M, 3)
    (relative to the target, grown by ``margin``) is inside the perspective view, the fraction of
    the ``aspect`` (width / height) window the points' screen bounding box then fills, and that box's centre in
    window units.
    """
    right = np.cross(np.array([0.0, 0.0, 1.0]), d)
    right /= np.linalg.norm(right, axis=1, keepdims=True)
    up = np.cross(d, right)
    x, y, z = rel @ right.T, rel @ up.T, rel @ d.T  # (M, K): screen right, screen up, toward the camera
    tan_y = np.tan(np.radians(CAMERA_FOV_DEG) / 2)
    tan_x = tan_y * aspect
    distance = np.maximum(z + (np.abs(x) + margin) / tan_x, z + (np.abs(y) + margin) / tan_y).max(axis=0) + margin
    sx = x / ((distance - z) * tan_x)  # window coordinates, −1 … 1 across the view
    sy = y / ((distance - z) * tan_y)
    fill = (sx.max(axis=0) - sx.min(axis=0)) * (sy.max(axis=0) - sy.min(axis=0)) / 4
    centre = np.stack([(sx.max(axis=0) + sx.min(axis=0)) / 2, (sy.max(axis=0) + sy.min(axis=0)) / 2], axis=-1)
    shift = centre[:, :1] * distance[:, None] * tan_x * right + centre[:, 1:] * distance[:, None] * tan_y * up
    return distance, fill, shift


def _face_on(points: NDArray) -> NDArray | None:
    """The view direction (1, 3) that sees planar ``points`` face-on, if their plane is vertical.

    Of the plane's two normals, the one that puts the display's x axis to the right (or y, when
    the plane is x = const). ``None`` if the points are not in one vertical plane.
    """
    centred = points - points.mean(axis=0)
    _, sv, vt = np.linalg.svd(centred, full_matrices=False)
    normal = vt[-1]
    if sv[0] == 0 or sv[-1] > 1e-6 * sv[0] or abs(normal[2]) > 1e-6:
        return None
    right = np.cross(np.array([0.0, 0.0, 1.0]), normal)
    if right[0] < -1e-9 or (abs(right[0]) <= 1e-9 and right[1] < 0):
        normal = -normal
    return normal[None, :]


def frame_camera(meshcat: Meshcat, points: ArrayLike, margin: float = 0.0, aspect: float = CAMERA_ASPECT
                 ) -> tuple[NDArray, NDArray]:
    """Place Meshcat's camera so that ``points`` (M, 3) — the arm's reach — fill the view.

    ``points`` are in the display frame (gravity −z). Points in one vertical plane (a planar arm
    turned so that gravity is down) are seen face-on. Otherwise, of a set of oblique view directions,
    the most customary one (front-right three-quarter view first) whose view of the points fills at
    least 80 % as much of an ``aspect`` (width / height) window as the best one is chosen, and the
    camera is moved as close as the perspective view allows with every point, grown by ``margin``
    metres, inside. Returns (camera, target) in Drake's world frame.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if pts.size == 0 or not np.all(np.isfinite(pts)):
        raise ValueError("frame_camera: points must be a non-empty array of finite (x, y, z)")
    target = (pts.min(axis=0) + pts.max(axis=0)) / 2
    d = _face_on(pts)
    if d is None:
        d = _view_directions()
        _, fill, _ = _fit(pts - target, d, margin, aspect)
        d = d[int(np.argmax(fill >= 0.8 * fill.max()))][None, :]
    for _ in range(2):  # centre the picture: aim at the middle of the points' screen bounding box
        distance, _, shift = _fit(pts - target, d, margin, aspect)
        target = target + shift[0]
    distance, _, _ = _fit(pts - target, d, margin, aspect)
    camera = target + max(float(distance[0]), 1e-3) * d[0]
    meshcat.SetCameraPose(camera, target)
    return camera, target


def _frames(times: NDArray[np.float64], run: NDArray[np.intp]) -> tuple[float, NDArray[np.int64], NDArray, NDArray]:
    """Frame rate, frame numbers, run times and runs of a replay's frames.

    The rate is :data:`MAX_FPS`, lowered so that a long run has at most :data:`MAX_FRAMES` frames.
    Frame k plays at k / fps. Within a run the frames sample the run's time uniformly (the first
    run starts at frame floor(t0 · fps), so a one-run replay plays in the run's time); after each
    run but the last the replay holds the run's end for :data:`JOIN_PAUSE` s, then the next run
    starts: playback time = run time + the pauses before it.
    """
    runs = np.unique(run)
    duration = times[-1] - times[0] + JOIN_PAUSE * (len(runs) - 1)
    budget = MAX_FRAMES - 2 - 2 * len(runs)  # each run may round up by a frame
    fps = MAX_FPS if duration * MAX_FPS <= budget else budget / duration
    t_parts, run_parts = [], []
    for k in runs:
        t0, t1 = times[run == k][[0, -1]]
        local = np.clip(t0 + np.arange(int(np.ceil((t1 - t0) * fps - 1e-9)) + 1) / fps, t0, t1)
        if k != runs[-1]:
            local = np.concatenate([local, np.full(round(JOIN_PAUSE * fps), t1)])
        t_parts.append(local)
        run_parts.append(np.full(local.size, k))
    t, frame_run = np.concatenate(t_parts), np.concatenate(run_parts)
    first = int(np.floor(times[0] * fps + 1e-9))
    return fps, first + np.arange(t.size, dtype=np.int64), t, frame_run


def _interpolate(t: NDArray, frame_run: NDArray, times: NDArray, run: NDArray, values: NDArray) -> NDArray:
    """``values`` (N, k) sampled at ``times`` in runs ``run``, linearly interpolated onto ``t`` within each run
    (never across a join of two runs)."""
    out = np.empty((t.size, values.shape[1]))
    for k in np.unique(frame_run):
        rows, frames = run == k, frame_run == k
        out[frames] = np.stack([np.interp(t[frames], times[rows], column) for column in values[rows].T], axis=-1)
    return out


def _check_run(arm: Arm, times: ArrayLike, q: ArrayLike, tool_path: ArrayLike | None
               ) -> tuple[NDArray, NDArray, NDArray | None]:
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


def write_replay(arm: Arm, times: NDArray, q: NDArray, path: str | Path, **options: Any) -> Path:
    """:func:`replay_page` of the run ``q(times)`` (N, n) of ``arm`` (``options``: its keywords) saved as one
    self-contained HTML file at ``path``, atomically (:func:`~armlab.files.write_file`)."""
    path = file_path(path)  # before the page is made
    return write_file(path, replay_page(arm, times, q, **options))


def replay_page(
    arm: Arm, times: NDArray, q: NDArray, tool_path: NDArray | None = None, tau: NDArray | None = None,
    run: NDArray | None = None, payload: float = 0.0, deg: bool = False, title: str | None = None,
    graphs: list[Graph] | None = None, scene: Obstacles | None = None,
) -> str:
    """Record the run ``q(times)`` (N, n) of ``arm`` as one self-contained HTML page (its text).

    The motion is resampled to uniform frames (≤ :data:`MAX_FPS` fps), posed in a Drake plant and
    recorded by ``MeshcatVisualizer`` into a Meshcat animation that plays and loops on opening
    (playback time = the run's time). The page has a control bar (play/pause, loop, a time slider)
    and a readout of t, q (degrees for revolute joints if ``deg``, else rad; m) and τ (N·m, N;
    ``tau`` (N, n) if given). ``tool_path`` (N, 3), the tool point's positions, is drawn as a line;
    by default it is the arm's forward kinematics of ``q``. ``payload`` > 0 kg is drawn as a sphere
    at the tool point. ``run`` (N,) numbers the continuous runs of a motion made of several (e.g.
    a branch switch): the replay never interpolates across a join — it holds the end of one run
    for :data:`JOIN_PAUSE` s under a banner saying what happens, and the arm is hidden for the one
    frame in which it changes pose. The arm is turned so that gravity points down the screen, on a
    floor grid, with the world axes; the camera frames everything the arm occupies during the run.
    ``title`` (default: the arm's name) heads the control bar. Beside the 3-D view, ``graphs``
    (:class:`~armlab.presentation.replay_graphs.Graph`, one row per sample of ``times``; default: q and, if given,
    τ with the arm's limits) are drawn against the run's time with a cursor at the time played; a click or a
    drag on a graph seeks the replay there.

    The arm's collision geometry and the obstacles of ``scene`` are a layer the page's "collision geometry" box
    shows (off by default; semi-transparent), posed with the arm at every frame; the shapes of a pair in contact
    in the frame's pose (its clearance < 0, :class:`~armlab.collision.model.CollisionModel`) are drawn in the
    contact colour at that frame (:func:`_collision_layer`). An arm without collision geometry has no layer
    (with a ``scene``: a ``ValueError``, as a run's check).
    """
    # lazy: armlab --help loads armlab.presentation.replay but not this (start-up time)
    from armlab.collision.model import CollisionModel
    from armlab.models.plant import drake_once

    times, q, tool_path = _check_run(arm, times, q, tool_path)
    tau = None if tau is None else np.asarray(tau, dtype=float)
    if tau is not None and (tau.shape != q.shape or not np.all(np.isfinite(tau))):
        raise ValueError(f"replay: tau must be finite with shape {q.shape}, got {tau.shape}")
    run = np.zeros(times.size, dtype=np.intp) if run is None else np.asarray(run)
    if run.shape != times.shape or np.any(np.diff(run) < 0):
        raise ValueError(f"replay: run must be non-decreasing run numbers of shape {times.shape}")
    if not (np.isfinite(payload) and payload >= 0):
        raise ValueError(f"replay: payload = {payload} kg must be a finite mass ≥ 0")
    if tool_path is None:
        tool_path = arm.forward(q).tool[:, :3, 3]
    graphs = arm_graphs(arm, q, tau=tau, deg=deg) if graphs is None else graphs
    shown = graph_data(times, run, graphs)
    fps, k, t, frame_run = _frames(times, run)
    frames_q = _interpolate(t, frame_run, times, run, q)
    frames_tau = None if tau is None else _interpolate(t, frame_run, times, run, tau)
    model = CollisionModel.optional(arm, scene)

    with drake_once():  # a floor in the scene: Drake's "Meshcat does not display HalfSpace" once, not per layer
        return _recorded_page(arm, tool_path, run, payload, title, shown, fps, k, t, frame_run, frames_q, frames_tau,
                              deg, scene, model)


def _recorded_page(arm: Arm, tool_path: NDArray, run: NDArray, payload: float, title: str | None, shown: Any,
                   fps: float, k: NDArray, t: NDArray, frame_run: NDArray, frames_q: NDArray,
                   frames_tau: NDArray | None, deg: bool, scene: Obstacles | None, model: CollisionModel | None) -> str:
    """:func:`replay_page`'s recording, its input checked and resampled to frames."""
    meshcat = start_meshcat()
    shown_scene = build_scene(arm, meshcat, publish_period=1 / fps, obstacles=scene, collision=model is not None)
    reach = np.concatenate([reach_points(arm, frames_q), tool_path])
    R = style_scene(meshcat, arm, reach)
    radius = max(body.radius for body in arm.bodies)
    frame_camera(meshcat, reach @ R.T, margin=2.5 * radius, aspect=REPLAY_ASPECT)
    for k_run in np.unique(run):  # one line per run: no segment joins two runs
        rows = run == k_run
        meshcat.SetLine(f"{TOOL_PATH}/{k_run}", tool_path[rows].T.copy(), line_width=3.0, rgba=_rgba(_PATH_RGBA))
    tool = arm.forward(frames_q).tool
    if payload > 0:
        from pydrake.geometry import Sphere

        meshcat.SetObject(PAYLOAD, Sphere(1.3 * radius), _rgba((0.25, 0.25, 0.3, 1.0)))
    shown_scene.visualizer.StartRecording(set_transforms_while_recording=False)
    # The recording files a publish at time τ under frame floor(τ · fps); publishing half a frame
    # late keeps rounding from putting two samples in one frame.
    for frame, q_frame in zip(k, frames_q, strict=True):
        shown_scene.show(q_frame, (frame + 0.5) / fps)
    shown_scene.visualizer.StopRecording()
    recording = shown_scene.visualizer.get_mutable_recording()
    recording.set_repetitions(2**31 - 1)  # loops; the page's "loop" box turns it off
    # Hidden while the pose jumps at a join (no broken arm); a visibility track holds its first value
    # before its first key, so the first frame says "visible".
    moving = np.append(np.diff(frame_run) == 0, True)  # False: the frame before a join, when the arm is hidden
    _visibility(meshcat, k, f"{SCENE}/visualizer", moving)
    layer = None if model is None else _collision_layer(shown_scene, model, meshcat, k, frames_q, moving)
    if payload > 0:
        from pydrake.math import RigidTransform

        for frame, T in zip(k, tool, strict=True):
            recording.SetTransform(int(frame), PAYLOAD, RigidTransform(T[:3, 3]))
        meshcat.SetTransform(PAYLOAD, RigidTransform(tool[0, :3, 3]))
    shown_scene.show(frames_q[0], float(t[0]))  # the static scene (before playback) shows the first pose
    shown_scene.visualizer.PublishRecording()
    html = meshcat.StaticHtml()
    data = _page_data(arm, fps, k, t, frame_run, frames_q, frames_tau, deg)
    data["title"] = arm.name if title is None else title
    data["graphs"] = shown
    data["collision"] = layer
    end = html.rfind("</body>")
    return _with_software_gl(html[:end] + _controls(data) + html[end:])


#: A script run before Meshcat's viewer makes its WebGL context: on a software renderer (SwiftShader, as in
#: headless Chromium or a browser without a GPU; Mesa's llvmpipe) the context is made without multisampling,
#: which there doubles the time of every frame (rrrr's 15 s replay in headless Chromium: 49 → 24 ms a frame,
#: 600 × 696 px); a GPU keeps its antialiasing, which costs it next to nothing.
SOFTWARE_GL = """<script>
(function () {
  const probe = document.createElement("canvas").getContext("webgl");
  const info = probe && probe.getExtension("WEBGL_debug_renderer_info");
  const name = probe ? String(probe.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : probe.RENDERER)) : "";
  const lose = probe && probe.getExtension("WEBGL_lose_context");
  if (lose) lose.loseContext();  // a browser keeps ~16 contexts: the probe's is given back at once
  if (!/swiftshader|llvmpipe|softpipe|software/i.test(name)) return;
  const getContext = HTMLCanvasElement.prototype.getContext;
  HTMLCanvasElement.prototype.getContext = function (kind, options) {
    if (/webgl/.test(String(kind))) options = Object.assign({}, options, {antialias: false});
    return getContext.call(this, kind, options);
  };
})();
</script>"""


def _with_software_gl(html: str) -> str:
    """``html`` (a Meshcat page) with :data:`SOFTWARE_GL` first in its head."""
    head = html.index("<head>") + len("<head>")
    return html[:head] + SOFTWARE_GL + html[head:]


def log_page(log: SimulationLog, deg: bool = False, clearance: Clearances | None = None,
             scene: Obstacles | None = None) -> str:
    """:func:`replay_page` of a simulation: its q, τ, tool path, runs and payload, and its graphs
    (:func:`~armlab.presentation.replay_graphs.log_graphs`; ``clearance``: the pairs the run checked, at its samples),
    with the obstacles of the ``scene`` it was checked against in its collision layer."""
    payload = f", payload {log.payload:g} kg" if log.payload else ""
    return replay_page(log.arm, log.t, log.q, tool_path=log.tool[:, :3], tau=log.tau, run=log.run,
                       payload=log.payload, deg=deg, title=f"{log.arm.name}: {log.motion.description}{payload}",
                       graphs=log_graphs(log, deg, clearance), scene=scene)


def replay_log(log: SimulationLog, path: str | Path, deg: bool = False, clearance: Clearances | None = None,
               scene: Obstacles | None = None) -> Path:
    """:func:`log_page` written to ``path`` (atomically)."""
    path = file_path(path)  # before the page is made
    return write_file(path, log_page(log, deg, clearance, scene))


def _visibility(meshcat: Meshcat, k: NDArray[np.int64], path: str, visible: NDArray[np.bool_]) -> None:
    """Show the Meshcat object at ``path`` at the frames ``k`` where ``visible`` (both ``(F,)``): unchanging, as a
    static property (a one-key track is a clip of no length, whose action's time three.js makes NaN, stopping the
    whole animation); else keys at the first frame (a track holds its first value before its first key) and at
    every change."""
    changes = np.flatnonzero(np.diff(visible)) + 1
    if changes.size == 0:
        meshcat.SetProperty(path, "visible", bool(visible[0]))
        return
    recording = meshcat.get_mutable_recording()
    for f in np.concatenate([[0], changes]):
        recording.SetProperty(int(k[f]), path, "visible", bool(visible[f]))


def _collision_layer(scene: Scene, model: CollisionModel, meshcat: Meshcat, k: NDArray[np.int64],
                     frames_q: NDArray[np.float64], moving: NDArray[np.bool_]) -> dict[str, Any]:
    """Key which shapes of the collision layer are in contact at each frame ``k`` (poses ``frames_q`` (F, n)).

    A pair's clearance at a frame's pose (``model``, the run's check) below zero puts both owners' shapes (a link's,
    or an obstacle's) in contact: each of their shapes is shown at :data:`CONTACT` instead of :data:`COLLISION`
    at that frame. The arm's shapes are hidden where ``moving`` is False (a join's jump), the obstacles never.
    Returns the page's data: the two layers' paths, the visuals' path and opacity under the layer, the pairs, those
    in contact at each frame (indices) and each owner's shapes (``{"owner": [path under the layer, …]}``).
    """
    # lazy: armlab --help loads armlab.presentation.replay but not this (start-up time)
    from armlab.collision.model import geometry_owner

    inspector = scene.scene_graph.model_inspector()
    found = model.distances(frames_q)
    touching = below(found.distance, 0.0)  # (F, P)
    owners: dict[str, list[str]] = {}
    world = inspector.world_frame_id()
    for g in inspector.GetAllGeometryIds():
        if inspector.GetProximityProperties(g) is None:
            continue
        frame = inspector.GetFrameId(g)
        # MeshcatVisualizer's path of a geometry: its frame's name and its own, each "::" turned into "/"
        tail = (("" if frame == world else inspector.GetName(frame) + "/") + inspector.GetName(g)).replace("::", "/")
        owner = geometry_owner(scene.plant, inspector, g)
        owners.setdefault(owner, []).append(tail)
        if not (meshcat.HasPath(f"{COLLISION}/{tail}") and meshcat.HasPath(f"{CONTACT}/{tail}")):
            raise RuntimeError(f"replay: Drake's MeshcatVisualizer did not draw {owner}'s shape at {tail}")
        hit = touching[:, [owner in pair for pair in found.pairs]].any(axis=1)
        shown = moving if frame != world else np.ones(len(k), dtype=bool)
        _visibility(meshcat, k, f"{COLLISION}/{tail}", shown & ~hit)
        _visibility(meshcat, k, f"{CONTACT}/{tail}", shown & hit)
    return {"layers": [COLLISION, CONTACT], "visuals": f"{SCENE}/visualizer",
            "visual_opacity": VISUAL_OPACITY_UNDER_LAYER, "owners": owners, "pairs": found.names(),
            "touching": [np.flatnonzero(row).tolist() for row in touching]}


def _page_data(arm: Arm, fps: float, k: NDArray, t: NDArray, frame_run: NDArray, q: NDArray,
               tau: NDArray | None, deg: bool) -> dict[str, Any]:
    """What the page's readout shows, per frame (JSON-ready)."""
    shown = np.where(arm.revolute, np.degrees(q), q) if deg else q
    joins = []
    for j in np.nonzero(np.diff(frame_run))[0]:
        held = np.nonzero((frame_run == frame_run[j]) & (t == t[j]))[0]
        joins.append({"from": float(k[held[0]] / fps), "to": float(k[j + 1] / fps), "t": float(t[j]),
                      "text": f"t = {t[j]:.4g} s: run {int(frame_run[j]) + 1} ends, run {int(frame_run[j + 1]) + 1} "
                              "starts in another pose (e.g. another IK branch). The arm is not simulated between "
                              "the two poses: the replay jumps."})
    return {
        "fps": fps, "first": int(k[0]), "t": np.round(t, 6).tolist(),
        "q": np.round(shown, 6).tolist(), "tau": None if tau is None else np.round(tau, 6).tolist(),
        "q_units": ["°" if (r and deg) else ("rad" if r else "m") for r in arm.revolute],
        "tau_units": ["N·m" if r else "N" for r in arm.revolute], "joins": joins,
    }


def _controls(data: dict[str, Any]) -> str:
    """The page's control bar, readout and join banner (HTML, CSS and a script driving ``viewer.animator``)."""
    page = _CONTROLS.replace("/*GRAPHS_STYLE*/", GRAPHS_STYLE).replace("/*GRAPHS_SCRIPT*/", GRAPHS_SCRIPT)
    sizes = page.replace("BAR_PX", str(BAR_HEIGHT)).replace("BANNER_PX", str(BAR_HEIGHT + 12))
    return sizes.replace("GRAPHS_PCT", str(GRAPHS_PCT)).replace("/*DATA*/null", json.dumps(data, ensure_ascii=False))


#: Height (px) of the control bar below the 3-D view of the replay page.
BAR_HEIGHT = 104
_CONTROLS = """
<style>
html,body{margin:0;overflow:hidden}
#meshcat-pane{height:calc(100vh - BAR_PXpx) !important}
#armlab-bar{position:relative;height:BAR_PXpx;box-sizing:border-box;padding:8px 14px;
  background:#f4f5f7;border-top:1px solid #b8bcc4;font:15px/1.4 Helvetica,Arial,sans-serif;color:#1d2733;z-index:20}
#armlab-row{display:flex;gap:14px;align-items:center}
#armlab-play{font-size:16px;min-width:96px;padding:3px 8px;cursor:pointer}
#armlab-track{flex:1;position:relative}
#armlab-slider{width:100%;height:22px;cursor:pointer;margin:0}
#armlab-time{font-family:monospace;min-width:150px;text-align:right}
#armlab-readout{font-family:monospace;font-size:14px;white-space:nowrap;overflow:hidden;margin-top:2px}
#armlab-title{font-weight:bold;font-size:14px;white-space:nowrap;overflow:hidden;text-overflow:ellipsis;margin-top:4px}
#armlab-banner{position:fixed;left:50%;bottom:BANNER_PXpx;transform:translateX(-50%);max-width:70%;display:none;
  background:#b03a2e;color:#fff;padding:9px 16px;border-radius:6px;font:15px/1.4 Helvetica,Arial,sans-serif;z-index:20}
/*GRAPHS_STYLE*/</style>
<div id="armlab-banner"></div>
<div id="armlab-graphs"></div>
<div id="armlab-bar"><div id="armlab-row">
  <button id="armlab-play" title="play / pause (space)">&#9208; Pause</button>
  <label><input type="checkbox" id="armlab-loop" checked> loop</label>
  <label id="armlab-collision-box" style="display:none" title="the collision shapes; red: a pair in contact"><input
    type="checkbox" id="armlab-collision"> collision geometry</label>
  <div id="armlab-track"><input type="range" id="armlab-slider" min="0" max="1" step="0.001" value="0"
    title="playback time"></div>
  <span id="armlab-time"></span></div>
  <div id="armlab-title"></div><div id="armlab-readout"></div></div>
<script>
/*GRAPHS_SCRIPT*/
(function () {
  const D = /*DATA*/null;
  const $ = (id) => document.getElementById(id);
  const play = $("armlab-play"), loop = $("armlab-loop"), slider = $("armlab-slider");
  function now(a) { return a.actions.reduce((m, x) => Math.max(m, x.time), 0); }
  function frame(time) { return Math.max(0, Math.min(D.t.length - 1, Math.round(time * D.fps) - D.first)); }
  function playback(t) {  // the playback time at which the replay shows run time t (the first, at a join)
    let lo = 0, hi = D.t.length - 1;
    if (t <= D.t[0]) return (D.first) / D.fps;
    if (t >= D.t[hi]) return (hi + D.first) / D.fps;
    while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (D.t[mid] < t) lo = mid; else hi = mid; }
    const f = D.t[hi] > D.t[lo] ? (t - D.t[lo]) / (D.t[hi] - D.t[lo]) : 1;
    return (lo + f + D.first) / D.fps;
  }
  function runTime(time) {  // the run time shown at playback time ``time`` (between two frames: interpolated)
    const f = Math.max(0, Math.min(D.t.length - 1, time * D.fps - D.first)), i = Math.floor(f);
    if (i + 1 >= D.t.length) return D.t[D.t.length - 1];
    return D.t[i] + (f - i) * (D.t[i + 1] - D.t[i]);
  }
  function fmt(v) { return (v >= 0 ? "+" : "") + v.toFixed(3); }
  function show(time) {
    const i = frame(time);
    $("armlab-time").textContent = "t = " + D.t[i].toFixed(3) + " s";
    const unit = (u) => (u === "°" ? u : " " + u);
    let text = "q = (" + D.q[i].map((v, j) => fmt(v) + unit(D.q_units[j])).join(", ") + ")";
    if (D.tau) text += "    \u03c4 = (" + D.tau[i].map((v, j) => fmt(v) + " " + D.tau_units[j]).join(", ") + ")";
    if (D.collision && D.collision.touching[i].length)
      text += "    contact: " + D.collision.touching[i].map((j) => D.collision.pairs[j]).join(", ");
    $("armlab-readout").textContent = text;
    const join = D.joins.find((j) => time >= j.from - 1e-9 && time < j.to);
    $("armlab-banner").style.display = join ? "block" : "none";
    if (join) $("armlab-banner").textContent = "Branch switch \u2014 " + join.text;
  }
  function start(a) {
    // Meshcat's hidden background is a white texture drawn over the whole view every frame (a quarter of a
    // frame's time in software rendering); the same white as the clear colour costs nothing.
    const background = viewer.update_background.bind(viewer);
    viewer.update_background = () => { background(); viewer.scene.background = null; };
    viewer.update_background();
    viewer.renderer.setClearColor(0xffffff, 1);
    $("armlab-title").textContent = D.title;
    $("armlab-title").title = D.title;
    slider.max = a.duration;
    const repeat = () => a.actions.forEach((x) => { x.repetitions = loop.checked ? Infinity : 1; });
    loop.onchange = repeat;
    repeat();
    if (D.collision) {  // the collision layer: hidden until the box is ticked
      const layer = $("armlab-collision");
      $("armlab-collision-box").style.display = "";
      layer.onchange = () => {
        for (const path of D.collision.layers)
          viewer.handle_command({type: "set_property", path, property: "visible", value: layer.checked});
        viewer.handle_command({type: "set_property", path: D.collision.visuals, property: "modulated_opacity",
                               value: layer.checked ? D.collision.visual_opacity : 1});
        if (viewer.set_dirty) viewer.set_dirty();
      };
    }
    play.onclick = () => {
      if (a.playing) { a.pause(); return; }
      if (now(a) >= a.duration - 1e-6 || a.actions.every((x) => !x.enabled || x.paused)) a.reset();
      a.actions.forEach((x) => { x.paused = false; x.enabled = true; });
      a.play();
    };
    document.addEventListener("keydown", (e) => { if (e.code === "Space") { e.preventDefault(); play.onclick(); } });
    slider.oninput = () => { a.pause(); a.seek(+slider.value); show(+slider.value); };
    const seek = (t) => {  // what a click or a drag on a graph at run time t does
      const time = playback(t);
      a.pause(); a.seek(time); slider.value = time; show(time); move(runTime(time));
      if (viewer.set_dirty) viewer.set_dirty();
    };
    const move = ARMLAB_GRAPHS(D.graphs, seek);
    window.armlab = {playback, runTime, seek};  // for scripts and the benchmark (scripts/bench/bench_replay.py)
    for (const j of D.joins) {  // the joins marked on the slider
      const mark = document.createElement("div");
      mark.title = "branch switch at t = " + j.t + " s";
      mark.style.cssText = "position:absolute;top:-4px;width:4px;height:30px;pointer-events:none;" +
        "background:#b03a2e;left:" + (100 * j.from / a.duration).toFixed(2) + "%";
      $("armlab-track").appendChild(mark);
    }
    (function tick() {
      const time = now(a);
      if (document.activeElement !== slider) slider.value = time;
      play.innerHTML = a.playing ? "&#9208; Pause" : "&#9654; Play";
      show(time);
      move(runTime(time));
      requestAnimationFrame(tick);
    })();
  }
  (function wait() {
    const a = window.viewer && viewer.animator;
    if (!a || a.actions.length === 0) { setTimeout(wait, 20); return; }
    start(a);
  })();
})();
</script>
"""


def _rgba(values: tuple[float, float, float, float]) -> Any:
    from pydrake.geometry import Rgba

    return Rgba(*values)
