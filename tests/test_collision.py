"""Collision geometry, scenes and clearances (issue 21): numpy against a closed form written here and against Drake,
known cases (a box at a known distance, the floor, the RRRR tool driven into its stand), adjacency, bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import random_q, three_link_urdf
from numpy.testing import assert_allclose

from armlab.analysis.workspace import workspace
from armlab.api import quintic, simulate
from armlab.cli import main
from armlab.collision.capsules import segment_box
from armlab.collision.clearance import clearance, motion_clearance
from armlab.collision.model import CollisionModel
from armlab.collision.scene import read_scene, scene_from_dict
from armlab.models import ARMS, get_arm

#: Drake's capsule and box distances come from GJK with a hard-coded precision (drake#14731): they are never below
#: the exact distance and at most this much (m) above it: 2.1e-4 m at most measured on urm6 and every paper arm.
GJK_EXCESS = 5e-4


def _point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    d = b - a
    s = 0.0 if d @ d == 0 else float(np.clip((p - a) @ d / (d @ d), 0.0, 1.0))
    return float(np.linalg.norm(p - (a + s * d)))


def segment_distance(P0: np.ndarray, P1: np.ndarray, Q0: np.ndarray, Q1: np.ndarray) -> float:
    """The closed form, by its own route: the interior stationary point of |P(s) − Q(t)|² if it lies in the unit
    square, else the least over the square's four edges (each a point-to-segment distance)."""
    d1, d2, r = P1 - P0, Q1 - Q0, P0 - Q0
    M = np.array([[d1 @ d1, -(d1 @ d2)], [-(d1 @ d2), d2 @ d2]])
    candidates = [_point_segment(P0, Q0, Q1), _point_segment(P1, Q0, Q1), _point_segment(Q0, P0, P1),
                  _point_segment(Q1, P0, P1)]
    if abs(np.linalg.det(M)) > 1e-12:
        s, t = np.linalg.solve(M, [-(d1 @ r), d2 @ r])
        if 0 <= s <= 1 and 0 <= t <= 1:
            candidates.append(float(np.linalg.norm(P0 + s * d1 - Q0 - t * d2)))
    return min(candidates)


def _world_segment(arm, q, part):
    F = arm.table.frames(q)[part.frame]
    return F[:3, :3] @ part.a + F[:3, 3], F[:3, :3] @ part.b + F[:3, 3]


@pytest.mark.parametrize("name", ["rrrr", "urm6", "arm4r", "r2t"])
def test_numpy_clearance_is_the_segment_closed_form(name):
    """Each capsule pair's numpy clearance is the segment distance less both radii, by the test's closed form."""
    arm = get_arm(name)
    model = CollisionModel(arm)
    q = random_q(arm, np.random.default_rng(7), 40)
    found = model.numpy(q)
    for k in range(len(q)):
        for j, (a, b) in enumerate(model._geometry_pairs):
            A, B = model._parts[a], model._parts[b]
            expected = segment_distance(*_world_segment(arm, q[k], A), *_world_segment(arm, q[k], B))
            assert_allclose(found.distance[k, j], expected - A.radius - B.radius, rtol=0, atol=1e-9)
            # the closest points lie on the two surfaces, the clearance apart
            assert_allclose(np.linalg.norm(found.point_b[k, j] - found.point_a[k, j]), abs(found.distance[k, j]),
                            rtol=0, atol=1e-9)


@pytest.mark.parametrize("name", ARMS)
def test_numpy_against_drake(name):
    """Spheres (closed form in Drake too) and floors agree to 1e-9 m; capsules and boxes: Drake's GJK value is never
    below numpy's exact one and within GJK_EXCESS above it."""
    scene = scene_from_dict({"obstacles": [
        {"name": "floor", "shape": "floor", "z": -0.05},
        {"name": "ball", "shape": "sphere", "radius": 0.1, "xyz": [0.1, 0.4, 0.3]},
        {"name": "crate", "shape": "box", "size": [0.3, 0.4, 0.1], "xyz": [0.5, 0.1, 0.3], "rpy": [0.3, 0.2, 0.1]}]})
    arm = get_arm(name)
    model = CollisionModel(arm, scene)
    assert model.numpy_ready
    q = random_q(arm, np.random.default_rng(3), 60)
    drake, ours = model.drake(q), model.numpy(q)
    for j, (a, b) in enumerate(model.pairs):
        if b in ("ball", "floor"):
            assert_allclose(ours.distance[:, j], drake.distance[:, j], rtol=0, atol=1e-9, err_msg=f"{a}–{b}")
            assert_allclose(ours.point_a[:, j], drake.point_a[:, j], rtol=0, atol=1e-9, err_msg=f"{a}–{b}")
        else:
            excess = drake.distance[:, j] - ours.distance[:, j]
            assert excess.min() > -1e-9 and excess.max() < GJK_EXCESS, (a, b, excess.min(), excess.max())


def test_segment_box_against_dense_sampling():
    """The segment–box closest points: their distance is never above a dense sampling's and within its spacing."""
    rng = np.random.default_rng(0)
    P0, P1, half = rng.uniform(-2, 2, (300, 3)), rng.uniform(-2, 2, (300, 3)), rng.uniform(0.1, 1, (300, 3))
    CS, CB = segment_box(P0, P1, half)
    assert_allclose(CB, np.clip(CB, -half, half), rtol=0, atol=1e-15)  # on (in) the box
    s = np.linspace(0, 1, 20001)
    points = P0[:, None] + s[None, :, None] * (P1 - P0)[:, None]
    sampled = np.linalg.norm(points - np.clip(points, -half[:, None], half[:, None]), axis=-1).min(axis=1)
    distance = np.linalg.norm(CS - CB, axis=-1)
    assert np.all(distance <= sampled + 1e-12)
    assert_allclose(distance, sampled, rtol=0, atol=np.linalg.norm(P1 - P0, axis=1).max() * 1e-4)


def test_straight_arm_next_to_a_box_and_the_floor():
    """rrrr at q = 0 lies along x at z = L1 = 0.2 m: a box 0.1 m above link 3's surface, the floor 0.05 m below
    the base: the clearances are known to the last digit."""
    arm = get_arm("rrrr")
    scene = scene_from_dict({"obstacles": [
        {"name": "box", "shape": "box", "size": [0.1, 0.1, 0.1], "xyz": [0.55, 0.0, 0.2 + 0.025 + 0.1 + 0.05]},
        {"name": "floor", "shape": "floor", "z": -0.05}]})
    rows = {row["pair"]: row for row in clearance(arm, np.zeros(4), scene)}
    assert_allclose(rows["link3–box"]["distance"], 0.1, rtol=0, atol=1e-9)
    x, y, z = rows["link3–box"]["point_b"]  # on the box's bottom face, over link 3 (the face is parallel to it)
    assert_allclose([y, z], [0.0, 0.325], rtol=0, atol=1e-9)
    assert 0.5 - 1e-9 <= x <= 0.6 + 1e-9
    assert_allclose(rows["link2–floor"]["distance"], 0.2 + 0.05 - 0.03, rtol=0, atol=1e-9)
    assert "link1–floor" not in rows  # joint 1's link turns on the stand that stands on the floor
    assert all(row["depth"] == 0 for row in rows.values())  # exact: 0.0 is max(0, −d) of a positive d


@pytest.mark.parametrize("name", ARMS)
def test_adjacent_links_never_count(name):
    """No pair of links joined by a joint (nor the base and link 1) is checked."""
    arm = get_arm(name)
    links = ["base_link", *[f"link{i}" for i in range(1, arm.n + 1)]]
    pairs = CollisionModel(arm).pairs
    for a, b in pairs:
        assert abs(links.index(a) - links.index(b)) > 1, (a, b)
    assert set(arm.collision_filters).isdisjoint(pairs)


def _stand_motion():
    """rrrr folded (q2 = 100°, q3 = 150°) turning q4 0 → 60° in 2 s: link 4 reaches the column (link 1) and
    stops 9.8 mm short of link 2."""
    arm = get_arm("rrrr")
    return arm, quintic(arm, np.radians([0, 100, 150, 0]), np.radians([0, 100, 150, 60]), 2.0)


def _first_contact(arm, motion) -> float:
    """When link 4 first touches link 1 on the reference motion, by the test's own segment distance (bisection:
    the clearance falls through zero once), to 1e-15 s."""
    model = CollisionModel(arm)
    (j,) = [k for k, pair in enumerate(model._geometry_pairs) if model.pairs[k] == ("link4", "link1")]
    A, B = (model._parts[g] for g in model._geometry_pairs[j])

    def clearance(t: float) -> float:
        q = motion.evaluate(np.array([t]), 1)[0][0]
        return segment_distance(*_world_segment(arm, q, A), *_world_segment(arm, q, B)) - A.radius - B.radius

    lo, hi = 0.0, 2.0
    for _ in range(60):
        lo, hi = (lo, (lo + hi) / 2) if clearance((lo + hi) / 2) < 0 else ((lo + hi) / 2, hi)
    return hi


def test_rrrr_tool_driven_into_its_stand_along_the_motion():
    """The reference motion sampled every 5 ms: the collision is link4–link1 alone, first at the first sample past
    the contact time."""
    arm, motion = _stand_motion()
    t = np.arange(0, 401) * 0.005
    checked, _ = motion_clearance(arm, t, motion.evaluate(t, 1)[0])
    (collision,) = checked["collisions"]
    touch = _first_contact(arm, motion)
    assert collision["pair"] == "link4–link1" and touch <= collision["first_time"] < touch + 0.005
    minima = {m["pair"]: m["min_clearance"] for m in checked["min_clearance"]}
    assert minima["link4–link2"] > 0 > minima["link4–link1"]


@pytest.mark.slow
def test_rrrr_tool_driven_into_its_stand_in_simulation(tmp_path):
    """The simulated run (its log, not the reference) reports the same pair and first time, and its files the plot."""
    arm, motion = _stand_motion()
    run = simulate(arm, motion, log_period=0.005)
    (collision,) = run.collisions
    touch = _first_contact(arm, motion)
    assert collision["pair"] == "link4–link1" and touch <= collision["first_time"] < touch + 0.005 + 1e-9
    assert run.summary["collisions"] == run.collisions and collision["depth"] > 0.01
    assert "clearance.png" in run.save(tmp_path / "run")
    page = (tmp_path / "run" / "replay.html").read_text()  # the replay's graphs show each checked pair's clearance
    assert "clearance of each checked pair" in page and "link4–link1 [m]" in page


def test_cli_check_and_strict_exit(tmp_path, capsys):
    assert main(["check", "rrrr", "--q", "0,80,160,60", "--deg", "--top", "1"]) == 3  # in contact
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "rrrr: 3 pair(s) checked; 2 in contact; the 1 smallest clearances:"
    assert out[1].split()[:2] == ["link4–link1", "-60.0000"]
    assert main(["check", "rrrr", "--q", "0,0,0,0", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert not data["in_contact"] and data["clearances"][0]["pair"] == "link4–link2"


def test_cli_check_reads_a_urdf_with_its_tool_option(tmp_path, capsys):
    """``armlab check`` takes the URDF options of every arm command (--tool, --package-path)."""
    urdf = tmp_path / "rrrr.urdf"
    urdf.write_text(get_arm("rrrr").urdf())
    assert main(["check", str(urdf), "--tool", "link4", "--package-path", str(tmp_path), "--q", "0,80,160,60",
                 "--deg", "--top", "1"]) == 3
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "rrrr: 3 pair(s) checked; 2 in contact; the 1 smallest clearances:"
    assert out[1].split()[:2] == ["link4–link1", "-60.0000"]
    assert main(["check", "rrrr", "--tool", "link4", "--q", "0,0,0,0"]) == 2
    # issue 36, item 27: the option and its value named, in a sentence
    assert ("armlab: error: --tool (tool=) = 'link4': the option is for an arm from a URDF, SDFormat or MJCF file, "
            "and 'rrrr' is not one: give the arm's file, or leave the option out\n") == capsys.readouterr().err


def _scene_file(tmp_path, text: str):
    path = tmp_path / "scene.json"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("text, message", [
    ('{"obstacles": [', "not valid JSON"),
    ('{"obstacles": [{"name": "b", "shape": "sphere", "radius": -0.1, "xyz": [0, 0, 0]}]}',
     "radius = -0.1 is not allowed"),
    ('{"obstacles": [{"name": "b", "shape": "box", "size": [1, 1, 1], "xyz": [NaN, 0, 0]}]}',
     "xyz[0] = nan is not allowed"),
    ('{"obstacles": [{"name": "c", "shape": "cone", "xyz": [0, 0, 0]}]}', "shape 'cone' is not allowed"),
    ('{"obstacles": [{"name": "b", "shape": "sphere", "xyz": [0, 0, 0]}]}', "a sphere needs radius"),
    ('{"obstacles": [{"name": "f", "shape": "floor", "z": 0, "colour": 1}]}', "unknown key(s) colour"),
    ('{"walls": []}', 'one key, "obstacles"'),
    # issue 36 item 7: a documented maximum, checked before any obstacle is read (10 000 took > 60 s)
    (json.dumps({"obstacles": [{"name": f"s{k}", "shape": "sphere", "radius": 0.01, "xyz": [5, 5, 0.03 * k]}
                               for k in range(1001)]}), "1,001 obstacles, more than the 1,000 allowed"),
    # issue 36 item 25: a name prints on one line, and not whole when it is long
    ('{"obstacles": [{"name": "a\\nb", "shape": "sphere", "radius": 0.1, "xyz": [5, 5, 5]}]}',
     "name 'a\\nb' is not allowed: a name holds no control characters"),
    (json.dumps({"obstacles": [{"name": "x" * 100_000, "shape": "sphere", "radius": 0.1, "xyz": [5, 5, 5]}]}),
     "(100,000 characters) is not allowed: at most 100"),
])
def test_bad_scene_is_one_line_exit_2(tmp_path, capsys, text, message):
    path = _scene_file(tmp_path, text)
    with pytest.raises(ValueError, match=r"^--scene "):
        read_scene(path)
    assert main(["check", "urm6", "--q", "0,0,0,0,0,0", "--scene", path]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("armlab: error: --scene ") and message in err, err
    assert len(err) < 400, err


def test_dh_radius_column(tmp_path, capsys):
    """A DH table's radius column gives each link a capsule; without it the arm says it has no geometry."""
    head = "type,a,alpha,d,theta,lower,upper"
    rows = ["R,0.4,0,0,0,-3,3", "R,0.3,0,0,0,-3,3", "R,0.3,0,0,0,-3,3"]
    good = tmp_path / "planar3.csv"
    good.write_text("\n".join([head + ",radius"] + [r + ",0.02" for r in rows]) + "\n")
    (row,) = clearance(get_arm(str(good)), [0.0, 0.0, 0.0])
    # link 3 runs from x = 0.7 to 1.0, link 1 from 0 to 0.4: 0.3 m apart, less two radii
    assert row["pair"] == "link3–link1" and abs(row["distance"] - 0.26) < 1e-9
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join([head + ",radius"] + [r + ",-0.01" for r in rows]) + "\n")
    assert main(["check", str(bad), "--q", "0,0,0"]) == 2
    assert "row 1: radius = -0.01 is not allowed" in capsys.readouterr().err
    bare = tmp_path / "bare.csv"
    bare.write_text("\n".join([head, *rows]) + "\n")
    assert main(["check", str(bare), "--q", "0,0,0"]) == 2
    assert "bare has no collision geometry" in capsys.readouterr().err


def _free_area_2r(center: np.ndarray, radius: float, cells: int = 1400) -> tuple[float, float]:
    """The test's own area of rr's workspace and of the part a collision-free pose reaches, around a disc obstacle
    (``center``, ``radius``) in the arm's plane: a grid of ``cells``² points, each reached by one of the two
    elbow branches of the closed-form inverse kinematics (rr's ±3π/2 limits allow every angle) whose two links
    (capsules of 25 and 20 mm about O–E and E–p) stay off the disc."""
    L1, L2, r1, r2 = 0.4, 0.3, 0.025, 0.02
    edge = 2 * 0.7 / cells
    x, y = np.meshgrid(*(2 * [(np.arange(cells) + 0.5) * edge - 0.7]), indexing="ij")
    r = np.hypot(x, y)
    inside = (r > L1 - L2) & (r < L1 + L2)
    x, y, r = x[inside], y[inside], r[inside]
    free = np.zeros(x.shape, dtype=bool)
    for sign in (1.0, -1.0):
        theta2 = sign * np.arccos(np.clip((r**2 - L1**2 - L2**2) / (2 * L1 * L2), -1, 1))
        theta1 = np.arctan2(y, x) - np.arctan2(L2 * np.sin(theta2), L1 + L2 * np.cos(theta2))
        elbow = L1 * np.stack([np.cos(theta1), np.sin(theta1)], axis=-1)
        tip = np.stack([x, y], axis=-1)

        def off(a: np.ndarray, b: np.ndarray, reach: float) -> np.ndarray:  # the disc beyond reach of a–b
            d = b - a
            s = np.clip(np.einsum("ij,ij->i", center - a, d) / np.einsum("ij,ij->i", d, d), 0, 1)
            return np.linalg.norm(a + s[:, None] * d - center, axis=1) >= radius + reach

        free |= off(np.zeros_like(elbow), elbow, r1) & off(elbow, tip, r2)
    return inside.sum() * edge**2, free.sum() * edge**2


@pytest.mark.slow
def test_collision_free_workspace_of_the_2r_arm_around_a_disc():
    """rr's collision-free area around a disc of 0.1 m at (0.4, 0.3): the workspace's voxel estimate from 10⁶
    samples against the test's grid, both the raw area and the area lost, within 1 % of the raw area."""
    center, radius = np.array([0.4, 0.3]), 0.1
    scene = scene_from_dict({"obstacles": [{"name": "post", "shape": "sphere", "radius": radius,
                                            "xyz": [*center, 0.0]}]})
    ws = workspace(get_arm("rr"), 1_000_000, jacobians=False, scene=scene)
    raw, free = _free_area_2r(center, radius)
    assert abs(ws.volume - raw) < 0.01 * raw
    assert ws.collision_free_volume is not None
    assert abs((ws.volume - ws.collision_free_volume) - (raw - free)) < 0.01 * raw
    assert 0 < raw - free and 0.9 < ws.collision_free_fraction < 1


def test_ik_marks_and_drops_colliding_branches(tmp_path, capsys):
    """rr's two elbow branches to (0.4, 0.3) m with a disc on the elbow-down branch's upper arm: that one collides."""
    disc = _scene_file(tmp_path, '{"obstacles": [{"name": "post", "shape": "sphere", "radius": 0.05, '
                                 '"xyz": [0.2, 0, 0]}]}')
    assert main(["ik", "rr", "--target", "0.4,0.3", "--all", "--deg", "--scene", disc]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 2 and sum("colliding: link1–post" in line for line in lines) == 1
    assert sum("collision-free (clearance" in line for line in lines) == 1
    assert main(["ik", "rr", "--target", "0.4,0.3", "--all", "--deg", "--scene", disc, "--collision-free",
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    (q,) = data["solutions"]
    assert data["colliding_pairs"] == [[]] and data["min_clearance"][0] > 0
    rows = clearance(get_arm("rr"), q, disc)
    assert_allclose(min(row["distance"] for row in rows), data["min_clearance"][0], rtol=0, atol=1e-12)


def test_sweep_objectives_collision_free_volume_and_min_clearance():
    """urm6 with every bend at 120° folds onto itself: its collision-free volume is below the raw one and its
    smallest clearance negative; at Table 1's bends none of the samples touches."""
    from armlab.analysis.study import evaluate, parse_study

    def objectives(bend: float) -> dict[str, float]:
        study = parse_study({"arm": "urm6", "vary": {f"theta{k}": {"values": [bend], "unit": "deg"}
                                                      for k in range(2, 7)},
                             "evaluate": ["workspace_volume", "collision_free_volume", "min_clearance"],
                             "samples": 20000})
        return evaluate(study, study.candidates[0])

    folded = objectives(120.0)
    assert folded["collision_free_volume"] < 0.99 * folded["workspace_volume"] and folded["min_clearance"] < 0
    straight = objectives(15.0)
    assert_allclose(straight["collision_free_volume"], straight["workspace_volume"], rtol=1e-12)
    assert straight["min_clearance"] > 0


@pytest.mark.parametrize("name", ARMS)
def test_models_readme_gives_every_collision_radius(name):
    """Each paper arm's section says its collision shapes: every link's radius (mm), chosen and why."""
    from armlab.models.arm import MODELS_DIR

    sections = (MODELS_DIR / "README.md").read_text().split("\n## `")[1:]
    (section,) = [s for s in sections if s.startswith(f"{name}`")]
    (line,) = [s for s in section.splitlines() if s.startswith("Collision geometry:")]
    assert "chosen, not from the paper" in line
    for body in get_arm(name).bodies:
        assert body.collides and f"{body.radius * 1e3:g}" in line, (name, body.radius)


@pytest.mark.parametrize("fore", ['<mesh filename="part.obj"/>', '<cylinder radius="0.03" length="0.3"/>'])
def test_user_urdf_mesh_and_cylinder_against_the_floor(tmp_path, fore):
    """A URDF's own mesh (its convex hull) and cylinder against the floor, through Drake: the lowest point of the
    link tilted by the elbow, by the test's own formula (centre height less half its extent along z)."""
    arm = get_arm(three_link_urdf(tmp_path, fore))
    floor = scene_from_dict({"obstacles": [{"name": "floor", "shape": "floor", "z": -0.05}]})
    for q2 in (0.0, 0.5, -1.0):
        rows = {row["pair"]: row["distance"] for row in clearance(arm, [0.0, q2, 0.0], floor)}
        # joints about +y turn x towards −z: fore's axis is (cos q2, 0, −sin q2) from the elbow at (0.4, 0, 0.1)
        centre_z = 0.1 - 0.15 * np.sin(q2)
        extent = (0.15 * abs(np.sin(q2)) + 0.02 * abs(np.cos(q2)) if "mesh" in fore
                  else 0.15 * abs(np.sin(q2)) + 0.03 * abs(np.cos(q2)))
        assert_allclose(rows["fore–floor"], centre_z - extent + 0.05, rtol=0, atol=1e-9)
        assert "upper–floor" not in rows  # joint 1's link stands on the floor
    # a collision mesh Drake cannot make a hull of is left out, said before any work (issue 24 item 11): the
    # clearances are those of the geometry that is left, fore's pairs gone
    (tmp_path / "part.stl").write_bytes(b"solid x\nendsolid x\n")
    with pytest.warns(UserWarning, match=r"collision mesh\(es\) left out"):
        stl = get_arm(three_link_urdf(tmp_path, '<mesh filename="part.stl"/>'))
    pairs = {row["pair"] for row in clearance(stl, [0.0, 0.0, 0.0], floor)}
    assert "hand–floor" in pairs and not any("fore" in pair for pair in pairs)


@pytest.mark.slow
def test_cli_simulate_warns_of_a_collision_and_strict_limits_exit_3(tmp_path, capsys):
    """The stand motion from the command line, against a scene: the warnings name each pair with its first time,
    summary.json lists them, --strict-limits exits 3; a bad scene is refused before the run (exit 2, no folder)."""
    scene = _scene_file(tmp_path, '{"obstacles": [{"name": "ball", "shape": "sphere", "radius": 0.05, '
                                  '"xyz": [-0.176, 0, 0.474]}]}')
    argv = ["simulate", "rrrr", "--from", "0,100,150,0", "--to", "0,100,150,60", "--deg", "--tf", "2", "--dt",
            "0.005", "--scene", scene, "--strict-limits", "--out", str(tmp_path / "run")]
    assert main(argv) == 3
    err = capsys.readouterr().err.splitlines()
    warned = [line.split(":")[2].strip() for line in err[:-1]]
    assert warned == ["rrrr collision link3–ball", "rrrr collision link4–link1"]
    assert err[-1] == "armlab: error: 2 collision(s) (--strict-limits)"
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert [c["pair"] for c in summary["collisions"]] == ["link3–ball", "link4–link1"]
    assert "and the 1 obstacle(s) of --scene" in summary["collision_check"]
    bad = _scene_file(tmp_path, '{"obstacles": [{"name": "ball", "shape": "sphere", "radius": 0, "xyz": [0, 0, 0]}]}')
    assert main([*argv[:-3], "--scene", bad, "--out", str(tmp_path / "bad")]) == 2
    assert not (tmp_path / "bad").exists()


def test_contacts_name_the_pairs_in_contact_per_configuration():
    """armlab.collision.clearance.contacts (what ``armlab ik --collision-free`` marks each solution with): the pairs
    in contact and the smallest clearance of each configuration, the same as ``armlab.clearance`` gives one by one."""
    from armlab.collision.clearance import contacts

    arm = get_arm("rrrr")
    q = np.radians([[0.0, 100.0, 150.0, 60.0], [0.0, 30.0, 30.0, 30.0]])
    (touching, smallest), (free, least) = contacts(arm, q)
    assert "link4–link1" in touching and smallest is not None and smallest < 0
    assert free == [] and least is not None and least > 0
    for (_, got), row in zip(contacts(arm, q), q, strict=True):
        np.testing.assert_allclose(got, clearance(arm, row)[0]["distance"], atol=1e-12)  # the same Drake query
