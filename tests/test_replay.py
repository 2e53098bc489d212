"""The 3-D replay and the live viewer, checked as a person would see them.

The replay HTML that ``armlab simulate`` writes is opened from disk by headless Chromium (no
server, no network) and screenshotted at two playback times: the arm must be visible and large
in both, in two different poses. Negative controls (a blank page, a page whose scene data is cut off, a run
that does not move) must fail the same checks. The live viewer is served on localhost: its
page must answer, its sliders must move the arm, and Drake's tool position it shows must
equal the paper's forward kinematics.
"""

from __future__ import annotations

import argparse
import io
import json
import re
import socket
import urllib.request

import numpy as np
import pytest
from helpers import ARM_NAMES, data
from replay_pictures import assert_shows_arm_moving, image, screenshots, solid

from armlab.cli.view import register
from armlab.models import get_arm
from armlab.presentation.replay import JOIN_PAUSE, MAX_FPS, MAX_FRAMES, display_rotation, replay_log, write_replay
from armlab.presentation.view import Viewer, open_meshcat, run_view


def sweep(arm, times: np.ndarray) -> np.ndarray:
    """A motion over a good part of every joint's range (unlimited joints: ±0.6π)."""
    lo, hi = arm.limit_arrays(unlimited=np.pi)
    s = np.sin(np.pi * times[:, None] / times[-1] - np.pi / 2 + 0.3 * np.arange(arm.n))
    return (lo + hi) / 2 + 0.6 * (hi - lo) / 2 * s


# ---------------------------------------------------------------------------------- replay file
def test_replay_file_is_self_contained_and_written_atomically(tmp_path):
    arm = get_arm("urm6")
    t = np.linspace(0.0, 2.0, 101)
    path = write_replay(arm, t, sweep(arm, t), tmp_path / "run" / "replay.html")
    assert path == tmp_path / "run" / "replay.html"
    html = path.read_text()
    assert html.lstrip().startswith("<!DOCTYPE html>")
    scripts = re.findall(r"<script\b[^>]*>", html)
    assert scripts and not any("src=" in tag for tag in scripts), scripts  # three.js is inlined
    assert not re.search(r"""<(?:link|img|iframe)\b[^>]*(?:href|src)\s*=\s*["']https?:""", html)
    assert [p.name for p in path.parent.iterdir()] == ["replay.html"]  # no temporary file left behind


def test_long_runs_are_capped_in_frames_and_size(tmp_path):
    arm = get_arm("urm6")

    def size(duration: float) -> int:
        t = np.linspace(0.0, duration, 2001)
        return write_replay(arm, t, sweep(arm, t), tmp_path / f"{duration}.html").stat().st_size

    per_frame = (size(4.0) - size(2.0)) / (2.0 * MAX_FPS)  # bytes per frame at the full rate
    assert per_frame > 0
    hour = size(3600.0)  # 108 000 frames at the full rate: capped at MAX_FRAMES
    assert hour < size(2.0) + 1.05 * (MAX_FRAMES - 2.0 * MAX_FPS) * per_frame


@pytest.mark.parametrize(
    ("times", "q", "message"),
    [
        (np.array([0.0, 1.0]), np.zeros((2, 5)), "shape"),
        (np.array([0.0, 1.0]), np.array([[0.0] * 6, [np.nan] + [0.0] * 5]), "finite"),
        (np.array([1.0, 0.5]), np.zeros((2, 6)), "non-decreasing"),
        (np.array([-1.0, 0.5]), np.zeros((2, 6)), "≥ 0"),
        (np.array([]), np.zeros((0, 6)), "non-empty"),
    ],
)
def test_replay_rejects_bad_runs(tmp_path, times, q, message):
    with pytest.raises(ValueError, match=message):
        write_replay(get_arm("urm6"), times, q, tmp_path / "replay.html")
    assert not (tmp_path / "replay.html").exists()


def test_replay_refuses_a_path_ending_in_a_slash(tmp_path):
    t = np.linspace(0, 1, 5)
    with pytest.raises(ValueError, match="ends with '/', a folder"):
        write_replay(get_arm("rr"), t, np.zeros((5, 2)), f"{tmp_path / 'x.html'}/")
    with pytest.raises(ValueError, match="ends with '/', a folder"):
        replay_log(None, f"{tmp_path / 'y.html'}/")  # refused before the log is read
    assert list(tmp_path.iterdir()) == []


def test_motor_side_torques_are_in_newton_metres_at_every_joint_a_prismatic_ones_too():
    """:func:`~armlab.drives.train.motor_torque` is a motor's torque (N·m) for every joint: the graph says so where
    the joint side of a prismatic joint is a force (N)."""
    import dataclasses
    import types

    from armlab.drives.train import DriveTrain, motor_torque
    from armlab.presentation.replay_graphs import log_graphs

    arm = get_arm("r2t")  # joints 2 and 3 prismatic
    drives = DriveTrain(np.array([50.0, 100.0, 200.0]), np.zeros(3), np.array([0.9, 0.8, 0.7]), np.zeros(3),
                        np.zeros(3))
    arm = dataclasses.replace(arm, drives=drives)
    t = np.linspace(0.0, 1.0, 5)
    q, qd, tau = sweep(arm, t), np.ones((5, 3)), np.ones((5, 3))
    log = types.SimpleNamespace(arm=arm, t=t, q=q, qd=qd, tau=tau, tau_motor=motor_torque(drives, tau, qd),
                                servo=None)
    joint, motor = (next(g for g in log_graphs(log) if g.title.startswith(title))
                    for title in ("joint torques", "motor-side torques"))
    assert joint.labels == ("τ1 [N·m]", "τ2 [N]", "τ3 [N]")
    assert motor.labels == ("τm1 [N·m]", "τm2 [N·m]", "τm3 [N·m]") and motor.ylabel == "τm [N·m]"
    np.testing.assert_allclose(motor.values, tau / (drives.gear_ratio * drives.efficiency), rtol=1e-15)
    bare = types.SimpleNamespace(arm=get_arm("r2t"), t=t, q=q, qd=qd, tau=tau, tau_motor=None, servo=None)
    assert not [g for g in log_graphs(bare) if g.title.startswith("motor")]


def test_replay_rejects_a_bad_tool_path(tmp_path):
    t = np.linspace(0, 1, 5)
    with pytest.raises(ValueError, match="tool_path"):
        write_replay(get_arm("rr"), t, np.zeros((5, 2)), tmp_path / "replay.html", tool_path=np.zeros((4, 3)))


# ------------------------------------------------------------------------ what a person sees
@pytest.mark.parametrize("name", ARM_NAMES)
def test_simulate_replay_in_chromium_shows_the_arm_in_two_poses(simulated, tmp_path, name):
    """What ``armlab simulate ARM --out DIR`` writes (exit 0; the session's run, see conftest.py), opened from disk
    as a user would."""
    extra = ("--tf", "2") if name == "rrrr" else ()  # the paper's 15 s run, shortened
    run = simulated(name, "--dt", "0.01", *extra)
    assert_shows_arm_moving(*screenshots(run / "replay.html", (0.3, 1.7), tmp_path))


def test_the_checks_fail_on_a_blank_a_broken_and_a_still_page(tmp_path):
    arm = get_arm("rrrr")
    blank = tmp_path / "blank.html"
    blank.write_text("<!DOCTYPE html><html><body></body></html>")
    (png,) = screenshots(blank, (0.3,), tmp_path)
    with pytest.raises(AssertionError, match="drawn"):
        assert_shows_arm_moving(png, png)

    t = np.linspace(0.0, 2.0, 41)
    good = write_replay(arm, t, sweep(arm, t), tmp_path / "good.html").read_text()
    broken = tmp_path / "broken.html"  # the scene data never reaches the viewer
    broken.write_text(good.replace("buffer => viewer.handle_command_bytearray(", "buffer => void ("))
    (png,) = screenshots(broken, (0.3,), tmp_path)
    with pytest.raises(AssertionError, match="white background"):
        assert_shows_arm_moving(png, png)

    still = write_replay(arm, t, np.repeat(sweep(arm, t)[:1], t.size, axis=0), tmp_path / "still.html")
    with pytest.raises(AssertionError, match="look the same"):
        assert_shows_arm_moving(*screenshots(still, (0.3, 1.7), tmp_path))


def test_playback_time_is_the_runs_time_even_when_a_long_run_is_thinned(tmp_path):
    arm = get_arm("arm4r")
    times = np.array([0.0, 59.9, 60.1, 120.0])  # 120 s: fewer than MAX_FPS frames per second
    assert 120.0 * MAX_FPS > MAX_FRAMES
    q = np.array([[0.0, -0.3, 0.6, 0.0], [0.0, -0.3, 0.6, 0.0], [1.5, -1.8, 1.8, 0.5], [1.5, -1.8, 1.8, 0.5]])
    path = write_replay(arm, times, q, tmp_path / "step.html")
    before, also_before, after = screenshots(path, (10.0, 50.0, 70.0), tmp_path)
    assert_shows_arm_moving(also_before, after)  # the pose changes at 60 s of playback …
    with pytest.raises(AssertionError, match="look the same"):
        assert_shows_arm_moving(before, also_before)  # … and not before


# ----------------------------------------------------------------------------------- viewer
def test_viewer_serves_the_page_and_its_sliders_move_the_tool():
    arm = get_arm("arm4r")
    q0 = np.array([0.3123456789, -0.8, 0.9, 0.2])  # not on the sliders' step: shown exactly all the same
    viewer = Viewer(arm, q0)
    try:
        with urllib.request.urlopen(viewer.url, timeout=10) as response:
            assert response.status == 200 and b"meshcat" in response.read().lower()
        assert re.fullmatch(r"http://localhost:\d+", viewer.url)
        assert viewer.step() and np.array_equal(viewer.q, q0)  # exact: the viewer keeps q0 as given
        np.testing.assert_allclose(viewer.tool_position(), arm.forward(q0).tool[:3, 3], atol=1e-9)
        assert not viewer.step()  # sliders untouched: nothing to redraw
        viewer.meshcat.SetSliderValue("joint2", -1.2)
        assert viewer.step()
        q1 = np.array([0.3123456789, -1.2, 0.9, 0.2])
        np.testing.assert_allclose(viewer.q, q1, atol=1e-3)  # joint 1 now as the slider has it (its step)
        assert viewer.q[1] == -1.2  # exact: the slider value set
        np.testing.assert_allclose(viewer.tool_position(), arm.forward(viewer.q).tool[:3, 3], atol=1e-9)
        assert len(viewer.trail) == 2
    finally:
        viewer.close()


def test_viewer_rejects_joint_values_outside_the_limits():
    with pytest.raises(ValueError, match="joint2 = 2 rad is outside its limits"):
        Viewer(get_arm("arm4r"), np.array([0.0, 2.0, 0.0, 0.0]))


def test_a_busy_port_moves_on_to_the_next_or_says_so():
    with socket.socket() as busy:
        busy.bind(("localhost", 0))
        busy.listen()
        port = busy.getsockname()[1]
        out = io.StringIO()
        _, guard = open_meshcat(port, out=out)
        assert guard.port != port and f"port {port} is in use" in out.getvalue()
        guard.close()
        with pytest.raises(ValueError, match=f"ports {port} … {port} are all in use"):
            open_meshcat(port, tries=1, out=io.StringIO())
    with pytest.raises(ValueError, match="--port: 80 is not allowed"):
        open_meshcat(80)


def test_run_view_prints_the_url_and_stops_after_its_duration():
    out = io.StringIO()
    assert run_view(get_arm("rr"), np.array([0.5, -0.5]), duration=0.3, out=out) == 0
    lines = out.getvalue().splitlines()
    assert re.search(r"open http://localhost:\d+ in a browser", lines[0])
    assert lines[1].startswith("q = +0.5000 rad  -0.5000 rad   tool M = (")


def test_run_view_ends_cleanly_on_ctrl_c(monkeypatch):
    def interrupt(_seconds):
        raise KeyboardInterrupt

    monkeypatch.setattr("armlab.presentation.view.time.sleep", interrupt)
    out = io.StringIO()
    assert run_view(get_arm("rr"), out=out) == 0
    assert out.getvalue().splitlines()[-1] == "stopped"


def parse_view(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="armlab")
    register(parser.add_subparsers(dest="command", required=True))
    return parser.parse_args(["view", *argv])


def test_view_subcommand_rejects_an_unknown_arm_and_bad_q():
    args = parse_view("nosucharm")
    with pytest.raises(ValueError, match="unknown arm 'nosucharm'"):
        args.func(args)
    args = parse_view("rr", "--q", "1,2,3")
    with pytest.raises(ValueError, match="rr has 2 joints, got 3 values"):
        args.func(args)
    args = parse_view("arm4r", "--q", "0,200,0,0", "--deg")
    with pytest.raises(ValueError, match="outside its limits"):
        args.func(args)
    args = parse_view("rr", "--duration", "-1")
    with pytest.raises(ValueError, match="--duration"):
        args.func(args)


# ------------------------------------------------------------------ controls, joins, gravity
def test_replay_has_visible_controls_and_a_readout_in_the_users_units(tmp_path):
    arm = get_arm("rr")
    t = np.linspace(0.0, 2.0, 41)
    q = sweep(arm, t)
    path = write_replay(arm, t, q, tmp_path / "r.html", tau=np.ones_like(q), deg=True)
    html = path.read_text()
    for element in ('id="armlab-play"', 'id="armlab-loop" checked', 'id="armlab-slider"', 'id="armlab-readout"'):
        assert element in html
    data = json.loads(re.search(r"const D = (\{.*?\});\n", html).group(1))
    np.testing.assert_allclose(np.radians(data["q"][0]), q[0], atol=1e-6)  # degrees, first frame = start
    assert data["q_units"] == ["°", "°"] and data["tau_units"] == ["N·m", "N·m"] and data["joins"] == []


def test_a_branch_switch_pauses_with_a_banner_and_never_interpolates(tmp_path):
    arm = get_arm("rr")
    times = np.array([0.0, 1.0, 1.0, 2.0])
    q = np.array([[0.0, 0.5], [0.3, 0.5], [1.2, -0.5], [1.5, -0.5]])
    path = write_replay(arm, times, q, tmp_path / "j.html", run=np.array([0, 0, 1, 1]))
    data = json.loads(re.search(r"const D = (\{.*?\});\n", path.read_text()).group(1))
    (join,) = data["joins"]
    # exact: the time given, through repr and JSON
    assert join["t"] == 1.0 and join["to"] - join["from"] >= JOIN_PAUSE - 0.05
    frames = np.array(data["q"])
    # Every frame is a pose of one run or the other, never a blend of the two across the join.
    assert np.all((np.abs(frames[:, 1] - 0.5) < 1e-9) | (np.abs(frames[:, 1] + 0.5) < 1e-9))
    paused, jump, after = screenshots(path, ((join["from"] + join["to"]) / 2, join["to"] - 0.5 / data["fps"],
                                             join["to"] + 0.2), tmp_path)
    assert_shows_arm_moving(paused, after)
    # The arm's joints and base are dark (the banner, the world axes and the floor are not): none is drawn
    # in the frame where the pose jumps, where three.js would blend the two poses link by link.
    dark = [solid(image(png).max(axis=-1) < 0.3).mean() for png in (paused, jump)]
    assert dark[0] > 0.002 and dark[1] < 0.0002, f"dark arm parts: {dark[0]:.2%} paused, {dark[1]:.2%} at the jump"


def test_the_view_is_turned_so_gravity_points_down():
    for name in ARM_NAMES:
        arm = get_arm(name)
        g = np.asarray(arm.gravity) / np.linalg.norm(arm.gravity)
        np.testing.assert_allclose(display_rotation(arm) @ g, [0.0, 0.0, -1.0], atol=1e-12)


def test_view_deg_shows_degree_sliders_that_move_the_arm():
    arm = get_arm("r2t")  # revolute and prismatic joints
    q0 = np.array([0.5, 0.1, 0.2])
    viewer = Viewer(arm, q0, deg=True)
    try:
        assert viewer.slider_names == ["joint1 [deg]", "joint2 [m]", "joint3 [m]"]
        assert viewer.step() and np.array_equal(viewer.q, q0)  # exact: the viewer keeps q0 as given
        assert viewer.meshcat.GetSliderValue("joint1 [deg]") == pytest.approx(np.degrees(0.5), abs=0.05)
        viewer.meshcat.SetSliderValue("joint1 [deg]", -60.0)
        viewer.meshcat.SetSliderValue("joint3 [m]", 0.25)
        assert viewer.step()
        np.testing.assert_allclose(viewer.q, [np.radians(-60.0), viewer.q[1], 0.25], atol=1e-12)
        np.testing.assert_allclose(viewer.tool_position(), arm.forward(viewer.q).tool[:3, 3], atol=1e-9)
    finally:
        viewer.close()
    out = io.StringIO()
    assert run_view(arm, q0, deg=True, duration=0.2, out=out) == 0
    assert "q = +28.6479 deg  +0.1000 m  +0.2000 m" in out.getvalue()


BARE_URDF = data("bare.urdf")


def test_a_urdf_without_materials_is_coloured_and_a_payload_is_drawn(tmp_path):
    (tmp_path / "bare.urdf").write_text(BARE_URDF)
    arm = get_arm(str(tmp_path / "bare.urdf"))
    t = np.linspace(0.0, 1.0, 11)
    q = np.column_stack([np.linspace(-0.5, -1.0, 11), np.linspace(0.8, 1.2, 11)])
    bare = write_replay(arm, t, q, tmp_path / "bare.html")
    loaded = write_replay(arm, t, q, tmp_path / "loaded.html", payload=2.0)
    (png_bare,) = screenshots(bare, (0.5,), tmp_path)
    (png_loaded,) = screenshots(loaded, (0.5,), tmp_path)
    rgb = image(png_bare)
    orange = (rgb[..., 0] > 0.6) & (rgb[..., 1] > 0.25) & (rgb[..., 1] < 0.65) & (rgb[..., 2] < 0.35)
    assert solid(orange).mean() > 0.003, f"only {solid(orange).mean():.2%} of the view shows the coloured links"
    dark = [solid(image(png).max(axis=-1) < 0.3).sum() for png in (png_bare, png_loaded)]
    assert dark[1] > dark[0] + 200, dark  # the payload: a dark sphere at the tool point


def test_the_rr_arms_plane_is_seen_face_on_and_a_spatial_arm_from_above_the_horizon():
    from armlab.presentation.replay import frame_camera, reach_points, start_meshcat

    meshcat = start_meshcat()
    rr = get_arm("rr")
    t = np.linspace(0.0, 2.0, 21)
    shown = reach_points(rr, sweep(rr, t)) @ display_rotation(rr).T
    camera, target = frame_camera(meshcat, shown)
    view = (camera - target) / np.linalg.norm(camera - target)
    np.testing.assert_allclose(view, [0.0, -1.0, 0.0], atol=1e-9)  # along the joint axes, x to the right
    urm6 = get_arm("urm6")
    camera, target = frame_camera(meshcat, reach_points(urm6, sweep(urm6, t)))
    elevation = np.degrees(np.arcsin((camera - target)[2] / np.linalg.norm(camera - target)))
    assert 10 < elevation < 50


# ------------------------------------------------------------------------------- the graphs
#: The JavaScript that reads, per graph, its plot area (page px), its time axis and where its cursor is drawn.
GRAPH_BOXES = """[...document.querySelectorAll('.armlab-plot')].map((p) => {
  const c = p.querySelector('canvas'), r = p.getBoundingClientRect();
  const k = p.querySelector('.armlab-cursor').getBoundingClientRect();
  return {left: r.left, top: r.top, height: r.height, x0: +c.dataset.x0, x1: +c.dataset.x1, t0: +c.dataset.t0,
          t1: +c.dataset.t1, cursor: (k.left + k.right) / 2 - r.left};
})"""
#: Playback time of the replay's 3-D animation, as its animator has it.
ANIMATION_TIME = "viewer.animator.actions.reduce((m, x) => Math.max(m, x.time), 0)"
NEXT_FRAMES = "new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(() => done(true))))"


def graph_x(box: dict, t: float) -> float:
    """Page x (CSS px) of run time ``t`` on the graph ``box``: its time axis drawn across its plot area."""
    return box["left"] + box["x0"] + (t - box["t0"]) / (box["t1"] - box["t0"]) * (box["x1"] - box["x0"])


def cursor_columns(png, box: dict) -> np.ndarray:
    """Page x of the pixels in the middle row band of graph ``box`` drawn in the cursor's magenta (#d6007e)."""
    rgb = image_full(png)
    rows = slice(int(box["top"] + 0.3 * box["height"]), int(box["top"] + 0.7 * box["height"]))
    band = rgb[rows, int(box["left"]):, :]
    magenta = (band[..., 0] > 0.7) & (band[..., 1] < 0.12) & (band[..., 2] > 0.35) & (band[..., 2] < 0.65)
    return np.nonzero(magenta.any(axis=0))[0] + int(box["left"])


def image_full(png) -> np.ndarray:
    from matplotlib.image import imread

    return imread(png)[..., :3]


def test_replay_graphs_follow_playback_and_a_click_or_drag_seeks(simulated, tmp_path):
    """``armlab simulate rr``'s replay opened from disk: the graphs hold the run's q, q̇, τ; their cursors stand at
    the time played (read from the page and found in its pixels) at two moments; a click and a drag on a graph
    seek the 3-D animation there; the page asks for nothing outside itself."""
    from browser import Page
    from replay_pictures import WINDOW, chromium

    run = simulated("rr", "--dt", "0.01")
    html = run / "replay.html"
    data = json.loads(re.search(r"const D = (\{.*?\});\n", html.read_text()).group(1))
    graphs = data["graphs"]
    assert [p["title"] for p in graphs["panels"]] == ["joint angles q", "joint velocities q̇", "joint torques τ"]
    log = np.genfromtxt(run / "log.csv", delimiter=",", names=True)
    rows = np.searchsorted(log["t"], graphs["t"])
    np.testing.assert_allclose(log["t"][rows], graphs["t"], atol=1e-6)
    tau = np.array(graphs["panels"][2]["y"]).T
    np.testing.assert_allclose(tau, np.stack([log[f"tau{i + 1}"][rows] for i in range(2)], axis=-1),
                               rtol=1e-5, atol=1e-9)
    dt = 1.0 / data["fps"]
    with Page(chromium(), html, WINDOW) as page:
        # loaded and playing (it plays on opening): a seek before that would be undone by the start
        page.wait_for(f"window.armlab && viewer.animator.actions.length > 0 && {ANIMATION_TIME} > 0.05")
        xs = []
        for k, t in enumerate((0.4, 1.3)):
            page.evaluate(f"viewer.animator.pause(), viewer.animator.seek({t}), true")
            page.evaluate(NEXT_FRAMES)
            boxes = page.evaluate(GRAPH_BOXES)
            assert len(boxes) == 3
            png = tmp_path / f"graphs-{k}.png"
            page.screenshot(png)
            for box in boxes:
                px = (box["t1"] - box["t0"]) / (box["x1"] - box["x0"])  # seconds per pixel
                at = box["t0"] + (box["cursor"] - box["x0"]) * px
                assert abs(at - t) < dt + px, f"cursor at t = {at:.3f} s, playback at {t} s"
                drawn = cursor_columns(png, box)
                assert drawn.size and abs(drawn.mean() - graph_x(box, t)) < 2.0, (t, drawn, graph_x(box, t))
            xs.append(boxes[0]["cursor"])
        assert xs[1] - xs[0] > 100  # the cursor moved with playback
        box = boxes[1]
        y = box["top"] + box["height"] / 2
        page.mouse("mousePressed", graph_x(box, 1.1), y)
        page.mouse("mouseReleased", graph_x(box, 1.1), y, buttons=0)
        page.evaluate(NEXT_FRAMES)
        px = (box["t1"] - box["t0"]) / (box["x1"] - box["x0"])
        assert abs(page.evaluate(ANIMATION_TIME) - 1.1) < px + 1e-6
        assert not page.evaluate("viewer.animator.playing")
        assert abs(float(page.evaluate("document.getElementById('armlab-time').textContent")[4:-2]) - 1.1) < dt
        page.mouse("mousePressed", graph_x(box, 0.3), y)  # a drag: the replay follows the pointer
        page.mouse("mouseMoved", graph_x(box, 1.0), y)
        assert abs(page.evaluate(ANIMATION_TIME) - 1.0) < px + 1e-6
        page.mouse("mouseMoved", graph_x(box, 1.7), y)
        page.mouse("mouseReleased", graph_x(box, 1.7), y, buttons=0)
        assert abs(page.evaluate(ANIMATION_TIME) - 1.7) < px + 1e-6
        page.evaluate(NEXT_FRAMES)
        assert abs(page.evaluate(GRAPH_BOXES)[0]["cursor"] + box["left"] - graph_x(box, 1.7)) < 1.5
        requests = page.requests
    assert html.absolute().as_uri() in requests  # the recording saw the page itself …
    assert all(url == html.absolute().as_uri() or url.startswith(("data:", "blob:")) for url in requests), requests


def test_a_software_renderer_draws_the_replay_without_multisampling_on_a_plain_white_clear(simulated):
    """Headless Chromium renders WebGL in software (SwiftShader): the replay's context is made without
    multisampling there (the script runs before Meshcat's), and Meshcat's hidden background texture is replaced by
    a white clear colour, also after Meshcat updates its background; the view's corner pixel stays white. The same
    script leaves a GPU's context alone: the renderer's name decides (checked with the names of both kinds)."""
    from browser import Page
    from replay_pictures import WINDOW, chromium

    from armlab.presentation.replay import SOFTWARE_GL

    html = simulated("rr", "--dt", "0.01") / "replay.html"
    text = html.read_text()
    assert text.index(SOFTWARE_GL) < text.index("MeshCat")  # before the viewer makes its context
    state = """(() => { const gl = viewer.renderer.getContext(), px = new Uint8Array(4);
      viewer.render(); gl.readPixels(2, 2, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
      const ext = gl.getExtension("WEBGL_debug_renderer_info");
      return {renderer: gl.getParameter(ext.UNMASKED_RENDERER_WEBGL), antialias: gl.getContextAttributes().antialias,
              background: viewer.scene.background === null, corner: [...px]}; })()"""
    with Page(chromium(), html, WINDOW) as page:
        page.wait_for("window.armlab && viewer.animator.actions.length > 0")
        shown = page.evaluate(state)
        assert "SwiftShader" in shown["renderer"]
        assert shown["antialias"] is False
        assert shown["background"] is True and shown["corner"] == [255, 255, 255, 255]
        page.evaluate("viewer.update_background(), true")  # e.g. what a camera change does
        assert page.evaluate(state)["background"] is True
        rule = re.search(r"if \(!(/.*?/i)\.test", SOFTWARE_GL).group(1)
        for name, software in (("ANGLE (NVIDIA, NVIDIA GeForce RTX 3060 Direct3D11 vs_5_0 ps_5_0)", False),
                               ("ANGLE (Intel, Mesa Intel(R) UHD Graphics 620 (KBL GT2), OpenGL 4.6)", False),
                               ("llvmpipe (LLVM 15.0.7, 256 bits)", True), (shown["renderer"], True)):
            assert page.evaluate(f"{rule}.test({json.dumps(name)})") is software, name
