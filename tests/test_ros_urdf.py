"""Users' URDFs as they come from ROS and robot vendors (issue 22 §3, issue 24 items 11, 15, 22).

tests/data/ros/robots/ur_like.urdf is ours, shaped like the stock UR5 of ROS (and Pinocchio's example-robot-data):
root link ``world``, ``package://`` meshes of a package that lives elsewhere (tests/data/ros/pkgs), ``.stl``
collision meshes, one visual mesh missing, and two frames past the last joint (``ee_link`` first, ``tool0``).
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import DATA, armlab_main, two_link_urdf

import armlab
from armlab.models.meshes import MeshWarning
from armlab.models.plant import PlantOptions, add_arm_plant

UR = DATA / "ros" / "robots" / "ur_like.urdf"
PACKAGES = DATA / "ros" / "pkgs"
MESHES = PACKAGES / "armlab_test_description" / "meshes"


def _ur(**options) -> armlab.Arm:
    with pytest.warns(MeshWarning):
        return armlab.load(UR, package_paths=[PACKAGES], **options)


def test_package_meshes_found_through_package_path_and_ros_package_path(monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    with pytest.warns(MeshWarning) as caught:
        found = armlab.load(UR, package_paths=[PACKAGES])
    messages = [str(w.message) for w in caught]
    assert any("1 mesh(es) not found" in m and "missing.dae" in m for m in messages), messages
    assert found.model_text is not None and (MESHES / "link.obj").resolve().as_uri() in found.model_text
    assert "missing.dae" not in found.model_text and "<collision" not in found.model_text
    monkeypatch.setenv("ROS_PACKAGE_PATH", f"/nonexistent:{PACKAGES.parent}")  # found 2 levels down
    with pytest.warns(MeshWarning):
        assert armlab.load(UR).model_text == found.model_text  # exact: the same text from the same files
    monkeypatch.delenv("ROS_PACKAGE_PATH")
    with pytest.warns(MeshWarning, match=r"15 mesh\(es\) not found.*--package-path DIR or ROS_PACKAGE_PATH"):
        alone = armlab.load(UR)  # without its package: every mesh is dropped, the arm is the same
    q = np.linspace(-0.5, 0.5, 6)
    np.testing.assert_allclose(alone.fk(q), found.fk(q), atol=1e-12, rtol=0)
    with pytest.raises(ValueError, match="package path '/nonexistent' is not a folder"):
        armlab.load(UR, package_paths=["/nonexistent"])


@pytest.mark.slow
def test_world_root_simulates_and_drake_agrees():
    """A root link named world (ROS) is Drake's world: the plant builds, with its scene graph, and simulates."""
    arm = _ur(tool="tool0")
    assert arm.base_link == "world"  # exact: a name
    from pydrake.systems.framework import DiagramBuilder

    builder = DiagramBuilder()
    plant, scene_graph = add_arm_plant(builder, arm, PlantOptions(geometry=True))
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    scene_graph.get_query_output_port().Eval(scene_graph.GetMyContextFromRoot(context))  # .stl collisions: gone
    q = np.array([0.3, -0.8, 1.1, -0.4, 0.6, 0.2])
    plant_context = plant.GetMyContextFromRoot(context)
    plant.SetPositions(plant_context, q)
    tool = plant.GetFrameByName("tool0").CalcPoseInWorld(plant_context).GetAsMatrix4()
    np.testing.assert_allclose(tool, arm.fk(q), atol=1e-12, rtol=0)
    run = armlab.simulate(arm, armlab.quintic(arm, np.zeros(6), q, 0.5))  # crashed: no Frame named 'world'
    np.testing.assert_allclose(run.q, run.q_ref, atol=1e-6, rtol=0)
    expected = arm.inverse_dynamics(run.q_ref, run.qd_ref, run.qdd_ref)  # simulation vs inverse dynamics
    np.testing.assert_allclose(run.tau, expected, rtol=0, atol=1e-6 * np.abs(expected).max())


@pytest.mark.parametrize("command", [["diagram", "--out", "{tmp}/d.dot"], ["fk", "--q", "0,0,0,0,0,0"]])
def test_world_root_from_the_command_line(command, tmp_path):
    argv = [part.format(tmp=tmp_path) for part in command]
    result = armlab_main(argv[0], str(UR), "--tool", "tool0", "--package-path", str(PACKAGES), *argv[1:])
    assert result.returncode == 0, result.stderr
    assert all(line.startswith("armlab: warning: ") for line in result.stderr.splitlines())


def test_tool_frame_is_the_users_choice():
    default, tool0 = _ur(), _ur(tool="tool0")
    assert default.tool_name == "ee_link" and tool0.tool_name == "tool0"  # exact: names
    assert "other choices (--tool LINK): wrist_3_link, tool0" in default.tool_source
    q = np.array([0.1, -0.2, 0.3, 0.4, -0.5, 0.6])
    # both hang 0.0823 m along wrist_3_link's y, turned differently: ee_link = Rz(90°), tool0 = Rx(-90°)
    wrist = _ur(tool="wrist_3_link").fk(q)
    for arm, R in ((default, [[0, -1, 0], [1, 0, 0], [0, 0, 1]]), (tool0, [[1, 0, 0], [0, 0, 1], [0, -1, 0]])):
        local = np.eye(4)
        local[:3, :3], local[:3, 3] = R, (0, 0.0823, 0)
        np.testing.assert_allclose(arm.fk(q), wrist @ local, atol=1e-12, rtol=0)
    with pytest.raises(ValueError, match="tool link 'forearm_link' is not past the last joint 'wrist_3_joint'; "
                                         "allowed: wrist_3_link, ee_link, tool0"):
        _ur(tool="forearm_link")
    with pytest.raises(ValueError, match="tool link 'nope' is not a link of the URDF"):
        armlab.load(UR, tool="nope")  # before the meshes are looked at
    with pytest.raises(ValueError, match=r"^--tool \(tool=\) = 'x' and --package-path \(package_paths=\) = \['\.'\]: "
                                         "these options are for an arm from a URDF, SDFormat or MJCF file, and 'rr' "
                                         "is not one"):
        armlab.load("rr", tool="x", package_paths=["."])


def test_show_says_which_tool_frame_and_why():
    result = armlab_main("show", str(UR), "--package-path", str(PACKAGES))
    assert result.returncode == 0, result.stderr
    assert ("tool frame: ee_link (the end of the chain: the first link declared past the last joint; other "
            "choices (--tool LINK): wrist_3_link, tool0)") in result.stdout
    chosen = armlab_main("show", str(UR), "--package-path", str(PACKAGES), "--tool", "tool0")
    assert "tool frame: tool0 (chosen (tool=, --tool))" in chosen.stdout


def _write(tmp_path, text: str, name: str = "arm.urdf"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_mimic_on_a_fixed_joint_does_nothing(tmp_path):
    text = two_link_urdf().replace('<joint name="wrist" type="fixed">',
                                   '<joint name="wrist" type="fixed"><mimic joint="elbow"/>')
    arm = armlab.load(_write(tmp_path, text))
    assert "mimic" not in arm.model_text
    plant = arm.make_plant()  # Drake refuses a mimic on a fixed joint: armlab gives it the file without
    assert plant.num_positions() == 2
    moving = two_link_urdf().replace('<joint name="elbow" type="revolute">',
                                     '<joint name="elbow" type="revolute"><mimic joint="shoulder"/>')
    with pytest.raises(ValueError, match="joint 'elbow' mimics joint 'shoulder': mimic joints are not supported"):
        armlab.load(_write(tmp_path, moving))


def test_doctype_in_a_comment_is_only_a_comment(tmp_path):
    commented = two_link_urdf().replace("<robot", "<!-- converted; the old file began <!DOCTYPE robot> -->\n<robot")
    assert armlab.load(_write(tmp_path, commented)).n == 2
    real = '<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY a "b">]>\n' + two_link_urdf()
    with pytest.raises(ValueError, match="document-type or entity definitions"):
        armlab.load(_write(tmp_path, real))
    # issue 36, item 2: a processing instruction holding "<!--" before the DOCTYPE, a comment after it
    hidden = two_link_urdf().replace("<robot", '<?note <!-- ?><!DOCTYPE robot [<!ENTITY inj "Injected">]><!-- -->'
                                     "\n<robot").replace('"upper"', '"l&inj;"')
    with pytest.raises(ValueError, match="document-type or entity definitions"):
        armlab.load(_write(tmp_path, hidden))


@pytest.mark.parametrize("text, message", [
    ('<?xml version="1.0"?>\n<robot name="ur3"/>\n', "the <robot> has no <link> elements: an empty URDF"),
    ('<robot name="x" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:include filename="ur.xacro"/>'
     '<xacro:ur_robot prefix=""/></robot>', "unexpanded xacro file"),
    ('<robot name="x"><link name="${prefix}base"/></robot>', "unexpanded xacro file"),
])
def test_empty_and_xacro_files_are_said_to_be_so(tmp_path, text, message):
    with pytest.raises(ValueError, match=message) as error:
        armlab.load(_write(tmp_path, text))
    assert "cycle" not in str(error.value)


def test_missing_mesh_is_a_warning_before_any_work(tmp_path):
    result = armlab_main("fk", str(_write(tmp_path, two_link_urdf(mesh="gone.obj"))), "--q", "0,0")
    assert result.returncode == 0
    assert result.stderr.startswith("armlab: warning: ") and "'gone.obj'" in result.stderr


def _collada(image: str) -> str:
    return ('<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">'
            f'<library_images><image id="t"><init_from>{image}</init_from></image></library_images></COLLADA>')


@pytest.mark.parametrize("image, refused", [
    ("../secret.png", "secret.png lies outside the URDF's folder"),
    ("/etc/hostname", "'/etc/hostname' is an absolute path or URL"),
    ("file:///etc/hostname", "absolute path or URL"),
    ("texture.png", None),
])
def test_dae_texture_paths_are_confined(tmp_path, image, refused):
    folder = tmp_path / "robot"
    folder.mkdir()
    (tmp_path / "secret.png").write_bytes(b"secret")
    (folder / "texture.png").write_bytes(b"png")
    (folder / "fore.dae").write_text(_collada(image))
    path = _write(folder, two_link_urdf(mesh="fore.dae"))
    if refused is None:
        assert armlab.load(path).n == 2
        return
    with pytest.raises(ValueError, match=refused):
        armlab.load(path)


def test_com_far_from_its_joint_is_refused(tmp_path):
    far = two_link_urdf().replace('<origin xyz="0.2 0 0"/><mass value="1"/>',
                                  '<origin xyz="198000 0 0"/><mass value="1"/>')
    with pytest.raises(ValueError, match=r"link 'upper': the centre of mass is 198000 m from its link frame, "
                                         r"beyond 8 m \(10 × the arm's size 0.7 m \+ 1 m\): not physical"):
        armlab.load(_write(tmp_path, far))
