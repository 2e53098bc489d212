"""The replay's collision layer (issue 21): the arm's and the scene's collision shapes, a toggle, and the pair in
contact drawn in the contact colour at exactly the frames where it touches — checked in headless Chromium against
Drake's own signed distances at each frame's pose."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from helpers import two_link_urdf
from replay_pictures import WINDOW, chromium, image

from armlab.api import quintic
from armlab.cli import main
from armlab.collision.model import CollisionModel
from armlab.collision.scene import read_scene
from armlab.models import get_arm
from armlab.presentation.replay import replay_page, write_replay

#: rrrr folded (q2 = 100°, q3 = 150°) turning q4 0 → 60° in 2 s: link 4 reaches the column (link 1) after 1.5 s
#: (tests/test_collision.py checks that contact), and a ball put where the tool point is at 0.6 s.
FROM, TO, TF, BALL_AT = (0, 100, 150, 0), (0, 100, 150, 60), 2.0, 0.6
#: A shape's state in the page: shown (it and every ancestor visible) and its materials' colours (linear RGB).
STATE = """((path) => { let node = viewer.scene_tree;
  for (const p of path.split("/").filter(Boolean)) { node = node.children[p]; if (!node) return null; }
  let shown = true; for (let o = node.object; o; o = o.parent) shown = shown && o.visible;
  const colors = []; node.object.traverse((o) => { if (o.material) colors.push(o.material.color.toArray()); });
  return {shown, colors}; })"""
ANIMATION_TIME = "viewer.animator.actions.reduce((m, x) => Math.max(m, x.time), 0)"
NEXT_FRAMES = "new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(() => done(true))))"
#: Frames this close to contact (m) are not judged: Drake's capsule distances (GJK) are up to 2e-4 m above the
#: exact ones the replay computes, and the page's q is rounded.
MARGIN = 1e-3


def _red(pixels: np.ndarray) -> int:
    """How many pixels of the 3-D view are the contact red (over white or over the faded visuals)."""
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    return int(np.count_nonzero((r > 0.6) & (g < 0.35) & (b < 0.35) & (r > 2.2 * g)))


def _stand_run(tmp_path):
    """``armlab simulate rrrr`` of the folded motion with the ball's scene: its folder, the scene and its arm."""
    arm = get_arm("rrrr")
    q_ball = quintic(arm, np.radians(FROM), np.radians(TO), TF).evaluate(np.array([BALL_AT]), 1)[0][0]
    ball = arm.forward(q_ball).tool[:3, 3]
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps({"obstacles": [
        {"name": "ball", "shape": "sphere", "radius": 0.015, "xyz": ball.tolist()},
        {"name": "post", "shape": "box", "size": [0.05, 0.05, 0.3], "xyz": [-0.6, -0.6, 0.15]}]}))
    out = tmp_path / "run"
    code = main(["simulate", "rrrr", "--from", ",".join(map(str, FROM)), "--to", ",".join(map(str, TO)), "--deg",
                 "--tf", str(TF), "--dt", "0.005", "--scene", str(scene), "--out", str(out)])
    assert code == 0
    return out, read_scene(scene), arm


@pytest.mark.slow
def test_the_replay_draws_the_collision_layer_and_colours_the_pair_in_contact(tmp_path):
    """The replay of a run that hits a ball of its scene, then its own column: the layer is off by default and the
    box shows it (the pixels change); at every frame the shapes of exactly the pairs Drake finds in contact at the
    frame's pose are the contact red, the others the layer's colour; the post, never touched, is drawn; the page
    asks for nothing outside itself."""
    from browser import Page

    out, scene, arm = _stand_run(tmp_path)
    summary = json.loads((out / "summary.json").read_text())
    assert {c["pair"] for c in summary["collisions"]} == {"link4–ball", "link4–link1"}
    html = out / "replay.html"
    data = json.loads(re.search(r"const D = (\{.*?\});\n", html.read_text()).group(1))
    layer = data["collision"]
    assert set(layer["owners"]) == {"link1", "link2", "link3", "link4", "ball", "post"}
    # Drake's signed distance (SceneGraph's queries, not the numpy path the replay takes) at each frame's pose
    q = np.radians(np.array(data["q"]))
    model = CollisionModel(arm, scene)
    drake = model.drake(q)
    assert drake.pairs == tuple(tuple(p.split("–")) for p in layer["pairs"])
    sure = np.all(np.abs(drake.distance) > MARGIN, axis=1)
    touching = [set(np.flatnonzero(row)) for row in drake.distance < 0]
    assert all(set(layer["touching"][i]) == touching[i] for i in np.flatnonzero(sure))
    index = {name: j for j, name in enumerate(layer["pairs"])}
    frames = {
        "ball": [i for i in np.flatnonzero(sure) if touching[i] == {index["link4–ball"]}],
        "column": [i for i in np.flatnonzero(sure) if touching[i] == {index["link4–link1"]}],
        "apart": [i for i in np.flatnonzero(sure) if not touching[i]],
    }
    assert all(len(v) > 3 for v in frames.values()), {k: len(v) for k, v in frames.items()}
    with Page(chromium(), html, WINDOW) as page:
        page.wait_for(f"window.armlab && viewer.animator.actions.length > 0 && {ANIMATION_TIME} > 0.05")
        box = "document.getElementById('armlab-collision')"
        assert page.evaluate(f"{box}.offsetParent !== null && !{box}.checked")  # shown, off by default

        def state(i: int) -> dict[str, list[tuple[bool, bool]]]:
            """Each owner's shapes at frame i: (shown, red) in the collision layer and in the contact layer."""
            page.evaluate(f"viewer.animator.pause(), viewer.animator.seek({(i + data['first'] + 0.25) / data['fps']}),"
                          " viewer.set_dirty(), true")
            page.evaluate(NEXT_FRAMES)
            found = {}
            for owner, tails in layer["owners"].items():
                shapes = []
                for path in (f"{root}/{tail}" for tail in tails for root in layer["layers"]):
                    s = page.evaluate(f"{STATE}({json.dumps(path)})")
                    assert s is not None and s["colors"], path
                    r, g, b = s["colors"][0]
                    shapes.append((s["shown"], r > 4 * g and r > 4 * b))
                found[owner] = shapes
            return found

        shots = {}
        for kind in ("ball", "column", "apart"):
            i = frames[kind][len(frames[kind]) // 2]
            before = state(i)
            assert not any(shown for shapes in before.values() for shown, _ in shapes)  # the layer is off
            page.screenshot(tmp_path / f"{kind}-off.png")
            page.evaluate(f"{box}.click(), true")  # on
            after = state(i)
            page.screenshot(tmp_path / f"{kind}-on.png")
            page.evaluate(f"{box}.click(), true")  # off again
            in_contact = {o for j in touching[i] for o in drake.pairs[j]}
            for owner, shapes in after.items():
                shown = [red for visible, red in shapes if visible]
                assert shown == [owner in in_contact] * len(layer["owners"][owner]), (kind, owner, shapes)
            shots[kind] = _red(image(tmp_path / f"{kind}-on.png")) - _red(image(tmp_path / f"{kind}-off.png"))
        requests = page.requests
    assert shots["ball"] > 100 and shots["column"] > 100 and shots["apart"] < 20, shots  # the red is on screen
    assert all(url == html.absolute().as_uri() or url.startswith(("data:", "blob:")) for url in requests), requests


def test_an_arm_without_collision_geometry_has_no_layer(tmp_path):
    """A URDF without <collision> elements: the replay has no layer (and says nothing of contact); with a scene it
    is the run's error, not a replay that cannot show what it was asked to."""
    (tmp_path / "two.urdf").write_text(two_link_urdf())
    arm = get_arm(str(tmp_path / "two.urdf"))
    t = np.linspace(0.0, 1.0, 11)
    page = write_replay(arm, t, np.zeros((11, arm.n)), tmp_path / "replay.html").read_text()
    assert json.loads(re.search(r"const D = (\{.*?\});\n", page).group(1))["collision"] is None
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps({"obstacles": [{"name": "ball", "shape": "sphere", "radius": 0.1, "xyz": [1, 1, 1]}]}))
    with pytest.raises(ValueError, match="no collision geometry"):
        replay_page(arm, t, np.zeros((11, arm.n)), scene=read_scene(scene))


def test_a_floor_in_the_scene_is_said_once(tmp_path, caplog):
    """Issue 33: with a floor in the scene, Drake said "Meshcat does not display HalfSpace geometry" once per
    collision layer (twice a run); now once. The page still records (its collision layer holds the floor's pair)."""
    import logging

    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps({"obstacles": [{"name": "floor", "shape": "floor", "z": -0.5}]}))
    arm = get_arm("rr")
    t = np.linspace(0.0, 1.0, 11)
    with caplog.at_level(logging.WARNING, logger="drake"):
        page = replay_page(arm, t, np.tile([0.3, 0.5], (11, 1)), scene=read_scene(scene))
    said = [r for r in caplog.records if r.name == "drake" and "HalfSpace" in r.getMessage()]
    assert len(said) == 1
    assert json.loads(re.search(r"const D = (\{.*?\});\n", page).group(1))["collision"] is not None
