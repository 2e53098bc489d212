"""Motions planned around obstacles (issue 30, item 2): ``armlab.plan_path`` and ``armlab plan ARM to``.

The check of the issue: a query whose straight joint path hits a box; the planned, timed motion clears it by the
asked margin at every sample, by Drake's ``SceneGraph`` query (not the numpy capsules the planner certifies with),
and in simulation. Seeded reproducibility, the one-line errors, the CLI's lines and exit codes."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import RECOMPUTED_ATOL, RECOMPUTED_RTOL, armlab_main

import armlab
from armlab.collision.model import CollisionModel
from armlab.collision.scene import scene_from_dict
from armlab.planning.planner import NoPathError, Planner

#: A box in front of the Panda, and the floor: the straight joint path between START and GOAL swings through it.
SCENE = {"obstacles": [{"name": "box", "shape": "box", "size": [0.3, 0.6, 0.5], "xyz": [0.55, 0, 0.25]},
                       {"name": "floor", "shape": "floor", "z": 0}]}
START = [-1.2, 0.4, 0.0, -1.6, 0.0, 2.0, 0.8]
GOAL = [1.2, 0.4, 0.0, -1.6, 0.0, 2.0, 0.8]
MARGIN = 0.02


@pytest.fixture(scope="module")
def planned():
    arm = armlab.load("panda")
    scene = scene_from_dict(SCENE)
    return arm, scene, armlab.plan_path(arm, START, GOAL, scene, clearance=MARGIN, seed=1)


def test_the_straight_path_hits_the_box_the_timed_plan_clears_it(planned):
    """Drake's query: the straight joint line passes through the box; the timed plan, sampled every millisecond of
    its duration, keeps every pair at least MARGIN apart, and the plan's reported minimum is Drake's own."""
    arm, scene, plan = planned
    drake = CollisionModel(arm, scene)
    line = np.linspace(START, GOAL, 201)
    straight = drake.drake(line)
    assert straight.distance.min() < 0 and any("box" in name for name in
                                               np.array(straight.names())[(straight.distance < 0).any(axis=0)])
    t = np.arange(0.0, plan.duration, 1e-3)
    q = plan.motion.evaluate(t, 1)[0]
    found = drake.drake(q)
    assert found.distance.min() >= MARGIN, (found.names()[int(np.argmin(found.distance.min(axis=0)))],
                                            found.distance.min())
    # the ends are the query's, at rest
    np.testing.assert_allclose(q[0], START, rtol=0, atol=1e-9)
    np.testing.assert_allclose(plan.motion.evaluate(np.array([plan.duration]), 1)[0][0], GOAL, rtol=0, atol=1e-9)
    np.testing.assert_allclose(plan.motion.evaluate(np.array([0.0, plan.duration]), 2)[1], 0.0, rtol=0, atol=1e-9)
    assert plan.min_clearance >= MARGIN and found.distance.min() >= plan.min_clearance - 5e-3
    # within Franka's velocity limits at Toppra's grid points (what fastest holds: q'(s)·ṡ there), by the path's own
    # derivative; between grid points the timing may pass them by a little (0.2 % here), Toppra's discretisation
    velocity = np.array([lim.velocity for lim in arm.limits])
    slope = np.array([plan.path.EvalDerivative(float(v), 1)[:, 0] for v in plan.timed.s])
    assert np.all(np.abs(slope * plan.timed.sd[:, None]) <= velocity * (1 + 1e-6))


def test_numpy_certificate_agrees_with_drake_along_the_smooth_path(planned):
    """The planner's numpy clearances (capsules against the box and the floor, in closed form) and Drake's query
    on the same 400 configurations of the smooth path: Drake's GJK never below the exact ones, within 1 mm."""
    arm, scene, plan = planned
    model = CollisionModel(arm, scene)
    s = np.linspace(plan.path.start_time(), plan.path.end_time(), 400)
    q = np.array([plan.path.value(v)[:, 0] for v in s])
    exact, drake = model.numpy(q), model.drake(q)
    assert exact.distance.min() >= MARGIN
    assert np.all(drake.distance >= exact.distance - 1e-9) and np.all(drake.distance <= exact.distance + 1.5e-3)


def test_the_same_seed_gives_the_same_plan(planned):
    arm, scene, plan = planned
    again = armlab.plan_path(arm, START, GOAL, scene, clearance=MARGIN, seed=1)
    # exact: the same code on the same input
    np.testing.assert_array_equal(again.waypoints, plan.waypoints)  # exact: the same seeded computation
    assert again.duration == plan.duration


def test_a_certified_edge_is_free_between_its_samples():
    """The certificate's claim, by brute force: an edge the planner calls free, sampled 20 000 times, never comes
    within the clearance; an edge it calls blocked has a sample that does (UR5 around a ball)."""
    arm = armlab.load("ur5")
    scene = scene_from_dict({"obstacles": [{"name": "post", "shape": "sphere", "radius": 0.15,
                                            "xyz": [0.0, -0.3, 0.7]}]})
    planner = Planner(arm, scene, clearance=0.01)
    rng = np.random.default_rng(5)
    verdicts = []
    for _ in range(12):
        a, b = rng.uniform(-np.pi, np.pi, (2, 6)) * 0.6 + np.array([0, -np.pi / 2, 0, -np.pi / 2, 0, 0])
        if not planner.free(np.stack([a, b])).all():
            continue
        free = planner.edge_free(a, b)
        dense = planner.clearances(np.linspace(a, b, 20000)).min()
        verdicts.append(free)
        assert (dense >= 0.01) if free else (dense < 0.01 + 1e-3), (free, dense)
    assert True in verdicts and False in verdicts


def test_bad_queries_are_one_line_errors():
    arm = armlab.load("panda")
    scene = scene_from_dict(SCENE)
    inside = [0.0, 0.5, 0.0, -1.2, 0.0, 1.7, 0.8]  # the hand down in the box
    with pytest.raises(ValueError, match=r"^the goal is in contact: link\d–box at -"):
        armlab.plan_path(arm, START, inside, scene)
    with pytest.raises(ValueError, match=r"joint4 = 0\.5 rad is outside its limits"):
        armlab.plan_path(arm, START, [0, 0, 0, 0.5, 0, 1, 0], scene)
    with pytest.raises(ValueError, match=r"clearance = -0\.1 is not allowed"):
        armlab.plan_path(arm, START, GOAL, scene, clearance=-0.1)
    with pytest.raises(NoPathError, match="no collision-free path found within the time budget"):
        armlab.plan_path(arm, START, GOAL, scene, budget=1e-4)


def test_cli_plan_to(tmp_path):
    """armlab plan panda to: the lines the issue asks for; the JSON's numbers are the API's; exit 3 without a path,
    2 for a goal in the box."""
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(SCENE))
    argv = ["plan", "panda", "to", "--from", ",".join(map(str, START)), "--to", ",".join(map(str, GOAL)),
            "--scene", str(scene), "--clearance", str(MARGIN), "--seed", "1"]
    result = armlab_main(*argv)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].startswith("panda: a path around itself and the obstacles of ")
    assert lines[1].startswith("smallest clearance: ") and "asked 20 mm" in lines[1]
    assert lines[2].startswith("path length: ") and lines[3].startswith("planning time: ")
    assert lines[4].startswith("timed as fast as the limits allow (Toppra): ")
    data = json.loads(armlab_main(*argv, "--json").stdout)
    plan = armlab.plan_path(armlab.load("panda"), START, GOAL, str(scene), clearance=MARGIN, seed=1)
    assert data["duration"] == plan.duration and data["min_clearance"] == plan.min_clearance
    assert data["min_clearance"] >= MARGIN
    result = armlab_main(*argv, "--budget", "0.0001")
    assert result.returncode == 3 and result.stderr.count("\n") == 1 and "time budget" in result.stderr
    result = armlab_main("plan", "panda", "to", "--to", "0,0.5,0,-1.2,0,1.7,0.8", "--scene", str(scene))
    assert result.returncode == 2 and "the goal is in contact" in result.stderr  # --from: the Panda's home


@pytest.mark.slow
def test_the_simulated_plan_keeps_its_clearance(planned):
    """The timed plan simulated through the Drake diagram (Franka's torque limits, the arm's own controller):
    the reference at every logged sample clears MARGIN by Drake's query; the simulated arm, which lags its
    reference by the tracking error e, by at least MARGIN − L·|e| (L: the collision model's motion bound), by the
    run's own numpy clearances."""
    arm, scene, plan = planned
    run = armlab.simulate(arm, plan.motion, scene=scene)
    drake = CollisionModel(arm, scene)
    assert drake.drake(run.q_ref).distance.min() >= MARGIN
    lag = np.abs(run.q - run.q_ref).max(axis=0)
    assert run.clearance is not None
    assert run.clearance.distance.min() >= MARGIN - 2 * drake.motion_bound() @ lag
    assert run.collisions == []


def test_segments_file_plan_segment(tmp_path, planned):
    """A segments file's "plan" segment (its scene beside the file) is plan_path's timed motion, then a quintic on."""
    arm, _, plan = planned
    (tmp_path / "box.json").write_text(json.dumps(SCENE))
    path = tmp_path / "run.json"
    path.write_text(json.dumps({"segments": [
        {"from": START, "to": GOAL, "plan": {"scene": "box.json", "clearance": MARGIN, "seed": 1}, "label": "around"},
        {"to": START, "tf": 2.0}]}))
    motion = armlab.read_segments(arm, path)
    assert motion.labels == ["around", "2"]
    np.testing.assert_allclose(motion.breaks[1], plan.duration, rtol=1e-12)
    q = motion.evaluate(np.linspace(0, plan.duration, 50), 1)[0]
    np.testing.assert_allclose(q, plan.motion.evaluate(np.linspace(0, plan.duration, 50), 1)[0], rtol=0, atol=1e-12)
    for bad, message in (({"scene": "box.json", "radius": 1}, r"\"plan\" = .* is not allowed"),
                         ({"scene": 3}, "plan scene = 3 must be a scene file's name")):
        path.write_text(json.dumps({"segments": [{"from": START, "to": GOAL, "plan": bad}]}))
        with pytest.raises(ValueError, match=message):
            armlab.read_segments(arm, path)
    path.write_text(json.dumps({"segments": [{"from": START, "to": GOAL, "plan": {"scene": "box.json"}, "tf": 1}]}))
    with pytest.raises(ValueError, match="takes no \"tf\""):
        armlab.read_segments(arm, path)


def test_a_roadmap_serves_many_queries_in_one_scene():
    """Lazy PRM: UR5 around a ball, five queries whose straight lines hit it, through one roadmap: each smooth path
    clears the ball by the margin by Drake's query; the edges checked for one query are remembered for the next
    (the same query again checks no roadmap edge anew)."""
    from armlab.planning.planner import Roadmap

    arm = armlab.load("ur5")
    scene = scene_from_dict({"obstacles": [{"name": "ball", "shape": "sphere", "radius": 0.15,
                                            "xyz": [0.0, -0.3, 0.7]}]})
    planner = Planner(arm, scene, clearance=0.01)
    roadmap = Roadmap(planner, nodes=300, neighbours=8, seed=2)
    rng = np.random.default_rng(8)
    drake = CollisionModel(arm, scene)
    planned = 0
    while planned < 5:
        a, b = rng.uniform(-np.pi, np.pi, (2, 6)) * 0.6 + np.array([0, -np.pi / 2, 0, -np.pi / 2, 0, 0])
        if not planner.free(np.stack([a, b])).all() or planner.edge_free(a, b):
            continue
        route = planner.route(a, b, roadmap=roadmap)
        s = np.linspace(route.path.start_time(), route.path.end_time(), 300)
        found = drake.drake(np.array([route.path.value(v)[:, 0] for v in s]))
        assert found.distance.min() >= 0.01
        np.testing.assert_allclose(route.path.value(route.path.end_time())[:, 0], b, rtol=0, atol=1e-12)
        planned += 1
    remembered = roadmap.verdicts
    assert remembered and not all(remembered.values())  # some edges were found blocked
    again = roadmap.path(a, b)
    assert roadmap.verdicts == remembered and len(again) >= 3
    with pytest.raises(ValueError, match="nodes = 1 is not allowed"):
        Roadmap(planner, nodes=1)


@pytest.mark.slow
@pytest.mark.cluster
def test_many_queries_on_a_dask_cluster_are_the_routes_planned_here(tmp_path):
    """A benchmark set on a real LocalCluster of two worker processes: each query's route is the one this process
    plans with the same seed (the same computation in another process: equal up to rounding); a goal in the box is
    refused before any worker starts."""
    from armlab.analysis.plans import plan_queries

    scene = tmp_path / "box.json"
    scene.write_text(json.dumps(SCENE))
    queries = np.array([[START, GOAL], [GOAL, START], [START, [0.0, 0.0, 0.0, -1.6, 0.0, 2.0, 0.8]]])
    results = plan_queries("panda", queries, scene, clearance=MARGIN, seed=4, workers=2)
    planner = Planner(armlab.load("panda"), scene_from_dict(SCENE), MARGIN)
    for k, (result, (a, b)) in enumerate(zip(results, queries, strict=True)):
        assert result["found"]
        here = planner.route(a, b, seed=4 + k)
        np.testing.assert_allclose(np.array(result["waypoints"]), here.waypoints, rtol=RECOMPUTED_RTOL,
                                   atol=RECOMPUTED_ATOL)
        assert result["nodes"] == here.nodes and result["checked"] == here.checked
    with pytest.raises(ValueError, match="query 1's goal is in contact"):
        plan_queries("panda", [[START, [0.0, 0.5, 0.0, -1.2, 0.0, 1.7, 0.8]]], scene, workers=1)


def test_cli_plan_options_of_the_other_kind_are_refused():
    """plan ARM to takes no tool-path timing options; plan ARM line takes no scene: one line each, exit 2."""
    result = armlab_main("plan", "panda", "to", "--to", ",".join(map(str, GOAL)), "--tf", "2")
    assert result.returncode == 2 and "--tf: not an option of 'plan ARM to'" in result.stderr
    result = armlab_main("plan", "rr", "line", "--from", "0.5,0.3", "--to", "0.3,0.5", "--tf", "2", "--clearance",
                         "0.01")
    assert result.returncode == 2 and "--clearance: not an option of 'plan ARM line'" in result.stderr
