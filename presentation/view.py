"""``armlab view ARM``: the arm in Meshcat with a slider per joint, the tool position shown live.

Paper 001 drives its arm with a slider per joint in a 3-D figure (the Robotics Toolbox "teach");
here Drake's ``JointSliders`` (or, with ``--deg``, degree sliders) move the arm's plant in a Meshcat
page served on localhost behind a guard that admits only that page and its own events
(:mod:`armlab.presentation.view_guard`). The
tool position — Drake's pose of the arm's tool frame — is shown on the page (a line of the
control panel and the tool point's trail drawn as a line) and printed in the terminal when it
changes. The scene is set up as in the replay (:mod:`armlab.presentation.replay`): white background,
gravity down the screen, floor grid and world axes, the camera framing everything the arm can reach.
"""

from __future__ import annotations

import html
import sys
import time
from typing import TYPE_CHECKING, Any, TextIO

import numpy as np
from numpy.typing import NDArray

from armlab.presentation.replay import TOOL_PATH, build_scene, frame_camera, reach_points, style_scene

if TYPE_CHECKING:
    from pydrake.geometry import Meshcat

    from armlab.models.arm import Arm
    from armlab.presentation.view_guard import Guard

__all__ = ["PORT_TRIES", "Viewer", "notebook_note", "open_meshcat", "run_view"]

#: How many consecutive ports ``--port P`` tries (P, P+1, …) before giving up.
PORT_TRIES = 10
#: Slider range of a joint without limits (rad): one turn either way.
_UNLIMITED = 2 * np.pi
_TRAIL = 2000  # most points kept in the tool's trail
_STOP = "Stop viewer"


def open_meshcat(port: int | None = None, tries: int = PORT_TRIES, out: TextIO = sys.stdout,
                 log: TextIO = sys.stderr) -> tuple[Meshcat, Guard]:
    """Drake's Meshcat and the viewer's :class:`~armlab.presentation.view_guard.Guard` in front of it on localhost
    (loopback only): on ``port`` or, if it is in use, the next free one of ``tries`` consecutive ports;
    ``port=None``: the first free one from 7000. The guard's refusals go to ``log``, one line each.

    Raises ``ValueError`` for a port outside 1024 … 65535 or when every port tried is in use.
    """
    from armlab.presentation.view_guard import Guard, start_hidden_meshcat  # lazy: tornado, msgpack

    if port is not None and not 1024 <= port <= 65535 - tries + 1:
        raise ValueError(f"--port: {port} is not allowed (use 1024 … {65535 - tries + 1})")
    meshcat = start_hidden_meshcat()
    for candidate in range(7000, 8000) if port is None else range(port, port + tries):
        try:
            return meshcat, Guard(meshcat, candidate, log=log)
        except OSError:
            if port is not None:
                print(f"port {candidate} is in use, trying {candidate + 1}", file=out)
    if port is None:
        raise ValueError("--port: no free port in 7000 … 7999 for the viewer; choose one with --port")
    raise ValueError(f"--port: ports {port} … {port + tries - 1} are all in use; choose another --port")


class Viewer:
    """The arm's plant in Meshcat, posed by a slider per joint.

    In radians (and metres) the sliders are Drake's ``JointSliders``, named after the joints; with
    ``deg=True`` a revolute joint's slider reads degrees (``"joint1 [deg]"``, step 0.1°) and a
    prismatic joint's metres (``"joint2 [m]"``). :meth:`step` reads the sliders and, when they moved,
    poses the arm, extends the tool's trail and updates the tool position on the page.
    """

    def __init__(self, arm: Arm, q0: NDArray[np.float64] | None = None, port: int | None = None,
                 out: TextIO = sys.stdout, deg: bool = False, log: TextIO = sys.stderr) -> None:
        from pydrake.multibody.meshcat import JointSliders

        self.arm = arm
        self.deg = deg
        q0 = np.clip(np.zeros(arm.n), *self.arm.limit_arrays(_UNLIMITED)) if q0 is None else arm.check_q(q0, "--q")
        self.meshcat, self.guard = open_meshcat(port, out=out, log=log)
        lower, upper = self.arm.limit_arrays(_UNLIMITED)
        lowest, highest = np.minimum(lower, q0), np.maximum(upper, q0)
        steps = np.where(arm.revolute, 0.1 if deg else 1e-3, 1e-4)  # the sliders' steps (°, rad; m)
        holder: dict[str, Any] = {}

        def add_sliders(builder: Any, plant: Any) -> None:
            if deg:
                return
            holder["sliders"] = builder.AddSystem(JointSliders(  # the plant's positions are in joint order
                self.meshcat, plant, initial_value=q0, lower_limit=lowest, upper_limit=highest,
                step=steps,
            ))

        self.scene = build_scene(arm, self.meshcat, extra=add_sliders)
        self.sliders = holder.get("sliders")
        self._sliders_context = None if self.sliders is None else self.sliders.GetMyContextFromRoot(self.scene.context)
        scale = np.where(arm.revolute & deg, 180 / np.pi, 1.0)
        for name, lo, hi, step, value in zip(self.slider_names, lowest * scale, highest * scale, steps, q0 * scale,
                                             strict=True):
            if deg:
                self.meshcat.AddSlider(name, float(lo), float(hi), float(step), float(value))
            self.guard.allow_slider(name, lo, hi, step)  # the only values the page may send
        plant = self.scene.plant
        self._tool = plant.GetFrameByName(arm.tool_name)
        reach = reach_points(arm, self._reach_samples())
        R = style_scene(self.meshcat, arm, reach)
        radius = max(body.radius for body in arm.bodies)
        frame_camera(self.meshcat, reach @ R.T, margin=2.5 * radius)
        self.meshcat.AddButton(_STOP, "Escape")
        self.guard.allow_button(_STOP)
        self._q0 = np.asarray(q0, dtype=float)
        self._reading: NDArray[np.float64] | None = None  # the sliders' values at the last step
        self.q: NDArray[np.float64] | None = None  # the pose shown
        self.trail: list[NDArray[np.float64]] = []
        self._label = ""

    def _repr_html_(self) -> str:
        """Jupyter's view: the page in a frame, its address, and what to do when the frame stays blank."""
        return notebook_note(self.url)

    @property
    def slider_names(self) -> list[str]:
        """The sliders' names on the page, in joint order."""
        if not self.deg:
            return list(self.arm.joint_names)
        return [f"{name} [{'deg' if r else 'm'}]" for name, r in zip(self.arm.joint_names, self.arm.revolute,
                                                                      strict=True)]

    def _read_sliders(self) -> NDArray[np.float64]:
        """The sliders' values as joint values q (rad, m), in joint order."""
        if self.sliders is not None:  # radians: Drake's JointSliders (None with deg)
            return np.asarray(self.sliders.get_output_port().Eval(self._sliders_context))
        values = np.array([self.meshcat.GetSliderValue(name) for name in self.slider_names])
        return np.where(self.arm.revolute, np.radians(values), values)

    @property
    def url(self) -> str:
        """The page's address, ``http://localhost:PORT`` (the guard's; Drake's own server is not for browsers)."""
        return self.guard.url

    @property
    def stop_requested(self) -> bool:
        """True once the page's stop button (or Escape) was pressed."""
        return self.meshcat.GetButtonClicks(_STOP) > 0

    def _reach_samples(self, count: int = 512) -> NDArray[np.float64]:
        """Configurations spread over the joint ranges (seeded), to frame everything the arm can reach."""
        lower, upper = self.arm.limit_arrays(_UNLIMITED)
        return np.random.default_rng(0).uniform(lower, upper, size=(count, self.arm.n))

    def tool_position(self) -> NDArray[np.float64]:
        """Position of the tool frame in the world (Drake's pose of the arm's tool frame), metres."""
        context = self.scene.plant.GetMyContextFromRoot(self.scene.context)
        return np.asarray(self._tool.CalcPoseInWorld(context).translation())

    def step(self) -> bool:
        """Read the sliders; if they moved, pose the arm and update the tool's trail and readout.

        Returns True when the pose changed.
        """
        reading = self._read_sliders()
        if self._reading is not None and np.array_equal(reading, self._reading):
            return False
        # The sliders round to their step; the first pose is the initial q exactly.
        q = self._q0 if self._reading is None else reading
        self._reading = reading.copy()
        self.q = q.copy()
        self.scene.show(q)
        p = self.tool_position()
        self.trail = (self.trail + [p])[-_TRAIL:]
        if len(self.trail) > 1:
            self.meshcat.SetLine(TOOL_PATH, np.array(self.trail).T.copy(), line_width=3.0)
        label = f"tool {self.arm.tool_name} [m]: " + "  ".join(f"{c} {v:+.4f}" for c, v in zip("xyz", p, strict=True))
        if self._label:
            self.meshcat.DeleteButton(self._label)
        self.meshcat.AddButton(label)  # a line of the control panel that reads the tool position
        self._label = label
        return True

    def close(self) -> None:
        """Remove the controls from the page and stop serving it."""
        self.meshcat.DeleteAddedControls()
        self.guard.close()


def notebook_note(url: str) -> str:
    """HTML for a notebook cell: the live viewer at ``url`` (``http://localhost:PORT``) in a frame, and what to do
    when the browser cannot reach that address — the notebook runs on another machine (a remote hub, a
    container): ``localhost`` is then the browser's machine, not the kernel's."""
    port = url.rsplit(":", 1)[-1].strip("/")
    tips = (f"If the frame stays blank, the notebook's kernel runs on another machine than your browser (a remote "
            f"JupyterHub, a container, Colab), and {url} names your own machine. Then: forward the port — "
            f"<code>ssh -L {port}:localhost:{port} USER@HOST</code> and reload; or, with jupyter-server-proxy "
            f"installed on the hub, open <code>…/proxy/{port}/</code> beside the notebook's address; or use the "
            "self-contained replay instead, which needs no server: <code>run = armlab.simulate(...)</code> and "
            "show <code>run</code> (or <code>run.save(folder)</code> and open <code>replay.html</code>).")
    return (f'<div><iframe src="{html.escape(url)}" style="width:100%;height:480px;border:1px solid #ccc" '
            f'title="armlab live viewer"></iframe><br>armlab live viewer: <a href="{html.escape(url)}" '
            f'target="_blank">{html.escape(url)}</a><br><small>{tips}</small></div>')


def run_view(arm: Arm, q0: NDArray[np.float64] | None = None, port: int | None = None, deg: bool = False,
             duration: float | None = None, out: TextIO = sys.stdout, poll: float = 0.05) -> int:
    """Serve the arm with joint sliders until Ctrl-C, the page's stop button, or ``duration`` seconds.

    Prints the page's URL, then the joints and tool position whenever the sliders move. Returns 0.
    """
    if duration is not None and not (np.isfinite(duration) and duration > 0):
        raise ValueError(f"--duration: {duration} is not a positive number of seconds")
    viewer = Viewer(arm, q0, port, out=out, deg=deg)
    unit = [("deg" if deg else "rad") if r else "m" for r in arm.revolute]
    scale = np.where(arm.revolute & deg, 180 / np.pi, 1.0)
    print(f"armlab view {arm.name}: open {viewer.url} in a browser (Ctrl-C or the page's "
          f"'{_STOP}' button to stop)", file=out, flush=True)
    end = None if duration is None else time.monotonic() + duration
    try:
        while not viewer.stop_requested and (end is None or time.monotonic() < end):
            if viewer.step():
                p = viewer.tool_position()
                joints = "  ".join(f"{v:+.4f} {u}" for v, u in zip(viewer.q * scale, unit, strict=True))
                print(f"q = {joints}   tool {arm.tool_name} = ({p[0]:+.4f}, {p[1]:+.4f}, {p[2]:+.4f}) m",
                      file=out, flush=True)
            time.sleep(poll)
    except KeyboardInterrupt:
        print("stopped", file=out)
    finally:
        viewer.close()
    return 0
