"""SDFormat and MuJoCo MJCF files load like URDFs, through Drake's own parser, with the same checks (issue 22 §2).

tests/data/formats/two_link.sdf and two_link.xml are tests/data/two_link.urdf written in the other formats: the
arm read from each has the URDF's kinematics and dynamics (1e-9), and Drake's plant of the file itself puts the
tool frame where the arm's forward kinematics does (two ways). Bad files get the URDF's one-line refusals.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from helpers import DATA, armlab_main

import armlab
from armlab.models.plant import PlantOptions, parse_model_file

FILES = [DATA / "formats" / "two_link.sdf", DATA / "formats" / "two_link.xml"]
TOL = 1e-9


def _states(count: int = 6):
    rng = np.random.default_rng(2)
    return rng.uniform(-3, 3, (count, 2)), rng.uniform(-2, 2, (count, 2)), rng.uniform(-5, 5, (count, 2))


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.suffix)
def test_same_arm_as_the_urdf(path):
    urdf, arm = armlab.load(DATA / "two_link.urdf"), armlab.load(path, tool="tool")
    assert arm.joint_names == ["shoulder", "elbow"] and arm.tool_name == "tool"  # exact: names
    q, qd, qdd = _states()
    np.testing.assert_allclose(arm.fk(q), urdf.fk(q), atol=TOL, rtol=0)
    np.testing.assert_allclose(arm.jacobian(q), urdf.jacobian(q), atol=TOL, rtol=0)
    np.testing.assert_allclose(arm.inverse_dynamics(q, qd, qdd), urdf.inverse_dynamics(q, qd, qdd), atol=TOL,
                               rtol=TOL)
    for lim, expected in zip(arm.limits, urdf.limits, strict=True):
        np.testing.assert_allclose([lim.lower, lim.upper, lim.effort], [expected.lower, expected.upper,
                                                                         expected.effort], atol=1e-12, rtol=0)
    # Drake's plant of the file itself (not armlab's URDF of it): the same tool frame
    plant, instance = parse_model_file(path, {})
    if not plant.HasFrameNamed("tool", instance) or path.suffix == ".sdf":
        plant.WeldFrames(plant.world_frame(), plant.GetBodyByName("base", instance).body_frame())
    plant.Finalize()
    context = plant.CreateDefaultContext()
    for x in q:
        plant.SetPositions(context, x)
        np.testing.assert_allclose(plant.GetFrameByName("tool").CalcPoseInWorld(context).GetAsMatrix4(), arm.fk(x),
                                   atol=TOL, rtol=0)
    drivable = arm.make_plant(PlantOptions(ideal_drives=True))  # what simulate builds
    assert drivable.num_actuators() == 2


def test_default_tool_and_the_command_line():
    assert armlab.load(FILES[0]).tool_name == "fore"  # exact: SDF frames are not bodies; the last body
    assert armlab.load(FILES[1]).tool_name == "tool"  # exact: MJCF's tool is a body
    result = armlab_main("fk", str(FILES[1]), "--q", "0.3,-0.7")
    assert result.returncode == 0, result.stderr
    tool = armlab.load(FILES[1]).fk([0.3, -0.7])[:3, 3]
    assert f"{tool[0]:+.6f}" in result.stdout


def _write(tmp_path, name: str, text: str):
    path = tmp_path / name
    path.write_text(text)
    return path


_LINK = ('<link name="{0}"><inertial><mass>1</mass><inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz></inertia>'
         "</inertial></link>")
_REVOLUTE = ('<joint name="{0}" type="revolute"><parent>{1}</parent><child>{2}</child><axis><xyz>0 0 1</xyz></axis>'
             "</joint>")


def _sdf(body: str) -> str:
    return f'<?xml version="1.0"?><sdf version="1.9">{body}</sdf>'


def _model(name: str = "m", extra: str = "") -> str:
    return (f'<model name="{name}">' + _LINK.format("a") + _LINK.format("b") + _REVOLUTE.format("j", "a", "b")
            + extra + "</model>")


@pytest.mark.parametrize("name, text, message", [
    ("two.sdf", _sdf(_model("m1") + _model("m2")), "holds 2 models: armlab takes one serial arm per file"),
    ("free.xml", '<mujoco model="m"><worldbody><body name="a"><freejoint/><inertial pos="0 0 0" mass="1" '
                 'diaginertia="1 1 1"/></body></worldbody></mujoco>',
     "joint of body 'a' is a free joint (a floating base"),
    ("ball.xml", '<mujoco model="m"><worldbody><body name="a"><joint name="b" type="ball"/><inertial pos="0 0 0" '
                 'mass="1" diaginertia="1 1 1"/></body></worldbody></mujoco>', "joint 'b' is a ball_rpy joint"),
    ("roots.sdf", _sdf(_model(extra=_LINK.format("c"))), "a serial arm has one root body, found 2: 'a', 'c'"),
    ("branch.sdf", _sdf(_model(extra=_LINK.format("c") + _REVOLUTE.format("k", "a", "c"))),
     "body 'a' branches into 2 moving chains"),
    ("outside.sdf", _sdf(_model(extra='<link name="v"><visual name="v"><geometry><mesh><uri>../x.obj</uri></mesh>'
                                      '</geometry></visual></link>')), "x.obj lies outside"),
    ("mesh.xml", '<mujoco model="m"><asset><mesh file="/etc/hostname"/></asset><worldbody/></mujoco>',
     "'/etc/hostname' is an absolute path"),
    ("doctype.sdf", '<?xml version="1.0"?><!DOCTYPE sdf [<!ENTITY x "y">]>' + _sdf(_model()), "entity definitions"),
    # issue 36, item 2: a processing instruction holding "<!--" does not hide a DOCTYPE
    ("pi.sdf", '<?xml version="1.0"?><?note <!-- ?><!DOCTYPE sdf [<!ENTITY x "y">]><!-- -->' + _sdf(_model())[21:],
     "entity definitions"),
    ("pi.xml", '<?note <!-- ?><!DOCTYPE mujoco [<!ENTITY x "y">]><!-- --><mujoco model="&x;"><worldbody/></mujoco>',
     "entity definitions"),
    ("wrong.sdf", '<robot name="x"/>', "the root element is <robot>, an SDFormat file (.sdf) needs <sdf>"),
    ("inf.sdf", _sdf(_model().replace("<ixx>1</ixx>", "<ixx>inf</ixx>")), "not a finite number"),
])
def test_bad_files_get_one_line_refusals(tmp_path, name, text, message):
    (tmp_path / "x.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    folder = tmp_path / "robot"
    folder.mkdir()
    path = _write(folder, name, text)
    result = armlab_main("show", str(path))
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and message in result.stderr, result.stderr


def test_drake_log_lines_only_after_success_each_once(tmp_path):
    """Issue 36, item 26: Drake's warnings (attributes its MJCF parser ignores, on two joints, each said twice by
    Drake) are dropped after an error, whose line stays the only one, and shown once each after a success."""
    text = FILES[1].read_text().replace('type="hinge"', 'type="hinge" frictionloss="0.1"').replace(
        "<worldbody>", '<option integrator="RK4"/><worldbody>')
    path = _write(tmp_path, "attr.xml", text)
    run = [sys.executable, "-m", "armlab"]
    failed = subprocess.run([*run, "simulate", str(path), "--out", str(tmp_path / "run")], capture_output=True,
                            text=True, timeout=300)
    assert failed.returncode == 2 and failed.stderr.count("\n") == 1, failed.stderr
    assert failed.stderr.startswith("armlab: error: two_link has no paper motion"), failed.stderr
    shown = subprocess.run([*run, "show", str(path)], capture_output=True, text=True, timeout=300)
    assert shown.returncode == 0, shown.stderr
    lines = shown.stderr.splitlines()
    assert len(lines) == len(set(lines)) == 3, lines  # integrator; frictionloss on lines 7 and 10
    assert all("is currently unsupported and will be ignored" in line for line in lines)


def test_collision_shapes_of_the_file_are_checked(tmp_path):
    """Issue 36, "also": an SDFormat file's <collision> elements and an MJCF file's geoms are the arm's collision
    geometry for ``armlab check`` (they were ignored: "no collision geometry")."""
    sdf = FILES[0].read_text().replace(
        '<link name="upper">', '<link name="upper"><collision name="c"><pose>0.25 0 0 0 1.5707963267948966 0</pose>'
        "<geometry><capsule><radius>0.03</radius><length>0.4</length></capsule></geometry></collision>").replace(
        '<link name="fore"><pose>0.5 0 0 0 0 0</pose>', '<link name="fore"><pose>0.5 0 0 0 0 0</pose><collision '
        'name="c"><pose>0.2 0 0 0 0 0</pose><geometry><box><size>0.4 0.05 0.05</size></box></geometry></collision>')
    mjcf = FILES[1].read_text().replace(
        '<inertial pos="0.25 0 0"', '<geom type="capsule" fromto="0.05 0 0 0.45 0 0" size="0.03"/><inertial '
        'pos="0.25 0 0"').replace('<inertial pos="0.2 0 0"', '<geom type="box" pos="0.2 0 0" size="0.2 0.025 0.025"/>'
                                                             '<inertial pos="0.2 0 0"')
    scene = _write(tmp_path, "scene.json", '{"obstacles": [{"name": "ball", "shape": "sphere", "radius": 0.05, '
                                           '"xyz": [0.7, 0, 0.1]}]}')
    for name, text in (("c.sdf", sdf), ("c.xml", mjcf)):
        result = armlab_main("check", str(_write(tmp_path, name, text)), "--q", "0,0", "--scene", str(scene))
        assert result.returncode == 0, result.stderr
        lines = result.stdout.splitlines()
        assert lines[0] == "two_link: 2 pair(s) checked; none in contact; the 2 smallest clearances:"
        # the box's top at z = 0.025 m, the ball's bottom at 0.05 m; the capsule's end (0.45, 0, 0) to the ball's
        # centre √(0.25² + 0.1²) m, less both radii
        assert lines[1].split()[:2] == ["link2–ball", "+25.0000"]
        # exact: printed text, 189.25824… mm to four decimals (the fifth, 4, is far from a rounding boundary)
        assert lines[2].split()[:2] == ["link1–ball", f"{(np.hypot(0.25, 0.1) - 0.08) * 1000:+.4f}"]
