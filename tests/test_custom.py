"""Users' own arms: DH tables (standard and modified) and URDF files, and their errors."""

from __future__ import annotations

import numpy as np
import pytest

from armlab.kinematics.dh import DHRow, DHTable
from armlab.models import get_arm
from armlab.models.custom import from_dh, from_urdf

PUMA_LIKE = """# convention: standard
type,a,alpha,d,theta,lower,upper
R,0,1.5707963267948966,0.3,0,-3,3
R,0.4,0,0,0,,
T,0,0,0.1,0,0,0.5
R,0.1,-1.5707963267948966,0,0.2,-2,2
"""


def _drake_tool(arm, q):
    plant = arm.make_plant()
    ctx = plant.CreateDefaultContext()
    out = []
    for qk in q:
        plant.SetPositions(ctx, qk)
        X = plant.CalcRelativeTransform(ctx, plant.world_frame(), plant.GetFrameByName(arm.tool_name))
        out.append(X.GetAsMatrix4())
    return np.array(out)


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_dh_csv_arm_matches_drake(tmp_path, convention):
    path = tmp_path / "my_arm.csv"
    path.write_text(PUMA_LIKE.replace("standard", convention))
    arm = get_arm(str(path))
    assert arm.n == 4 and arm.name == "my_arm"
    assert [j["type"] for j in arm.joints()] == ["revolute", "revolute", "prismatic", "revolute"]
    q = np.random.default_rng(3).uniform([-3, -6, 0, -2], [3, 6, 0.5, 2], size=(100, 4))
    dh_pose = arm.forward(q).tool  # the DH chain (000 eq. 9 / 001 eq. 1)
    np.testing.assert_allclose(dh_pose, _drake_tool(arm, q), atol=1e-9)
    np.testing.assert_allclose(arm.table_forward(q).tool, dh_pose, atol=1e-12)


def test_rrrr_dh_table_equals_basic_movements():
    rrrr = get_arm("rrrr")
    from armlab.models.rrrr import Parameters, dh_table

    q = np.random.default_rng(4).uniform(-3, 3, (100, 4))
    np.testing.assert_allclose(dh_table(Parameters()).end_pose(q), rrrr.forward(q).tool, atol=1e-14)


def test_user_urdf_round_trip(tmp_path):
    """A paper arm's URDF read back as a user arm gives the same kinematics (fixed joints folded)."""
    source = get_arm("urm6")
    path = tmp_path / "copy.urdf"
    path.write_text(source.urdf())
    arm = from_urdf(path)
    assert arm.n == 6 and arm.base_link == "base_link"
    q = np.random.default_rng(5).uniform(-6, 6, (100, 6))
    np.testing.assert_allclose(arm.forward(q).tool, source.forward(q).tool, atol=1e-9)
    np.testing.assert_allclose(arm.forward(q).tool, _drake_tool(arm, q), atol=1e-9)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("type,a,alpha,d,theta,lower,upper\nX,0,0,0,0,,\n", "type 'X' is not allowed"),
        ("type,a,alpha,d,theta,lower,upper\nR,zero,0,0,0,,\n", "row 1: a = 'zero' is not a number"),
        ("type,a,alpha,d,theta,lower,upper\nR,nan,0,0,0,,\n", "not a finite number"),
        ("type,a,alpha,d,theta,lower,upper\nT,0,0,0,0,,\n", "prismatic joint needs lower and upper"),
        ("type,a,alpha,d,theta,lower,upper\nR,0,0,0,0,2,1\n", "lower = 2.0 must be below upper = 1.0"),
        ("a,b\n1,2\n", "header"),
        ("type,a,alpha,d,theta,lower,upper\n", "no rows"),
        ("# convention: weird\ntype,a,alpha,d,theta,lower,upper\nR,0,0,0,0,,\n", "convention"),
        ("type,a,alpha,d,theta,lower,upper\nR,0.4,0,0,0,-3,3,9\n", "row 1 has 8 values; expected 7"),
    ],
)
def test_malformed_dh_tables(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        get_arm(str(path))


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("<robot", "not valid XML"),
        ("<model/>", "needs <robot>"),
        ('<robot name="r"><link name="a"/></robot>', "no movable joint"),
        ('<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="ball"><parent link="a"/>'
         '<child link="b"/></joint></robot>', "type 'ball'"),
        ('<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/>'
         '<child link="b"/></joint></robot>', "needs <limit"),
        ('<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
         '<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>'
         '<joint name="k" type="continuous"><parent link="a"/><child link="c"/></joint></robot>',
         "branches into 2 moving chains"),
        ('<robot name="r"><link name="a"/><joint name="j" type="continuous"><parent link="a"/>'
         '<child link="zz"/></joint></robot>', "naming links"),
        ('<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="continuous"><parent link="a"/>'
         '<child link="b"/><origin xyz="1 2"/></joint></robot>', "must be three numbers"),
        ('<robot name="r"><link name="a"/><link name="b"><inertial><mass value="-1"/></inertial></link>'
         '<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint></robot>',
         "link 'b' mass = -1 kg is not allowed"),
    ],
)
def test_malformed_urdf(tmp_path, text, message):
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        get_arm(str(path))


def test_files_that_are_not_text(tmp_path):
    for name in ("bad.csv", "bad.urdf"):
        (tmp_path / name).write_bytes(b"\xff\xfe\x00garbage")
        with pytest.raises(ValueError, match=name):
            get_arm(str(tmp_path / name))


def two_link_urdf(mass2: float = 0.5, mesh: str | None = None) -> str:
    """A planar two-link arm as users write them: no <transmission>, optionally a mesh on link 2."""
    visual = f'<visual><geometry><mesh filename="{mesh}"/></geometry></visual>' if mesh else ""
    inertial = ("" if mass2 == 0 else f'<inertial><origin xyz="0.15 0 0"/><mass value="{mass2}"/>'
                '<inertia ixx="1e-4" ixy="0" ixz="0" iyy="4e-3" iyz="0" izz="4e-3"/></inertial>')
    return f"""<robot name="two">
  <link name="base"/>
  <link name="upper"><inertial><origin xyz="0.2 0 0"/><mass value="1"/>
    <inertia ixx="1e-4" ixy="0" ixz="0" iyy="1.4e-2" iyz="0" izz="1.4e-2"/></inertial></link>
  <link name="fore">{inertial}{visual}</link>
  <link name="hand"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.4 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="wrist" type="fixed"><parent link="fore"/><child link="hand"/><origin xyz="0.3 0 0"/></joint>
</robot>
"""


def armlab_cli(*argv: str) -> int:
    from armlab.cli import main

    return main(list(argv))


def test_user_urdf_without_transmissions_simulates(tmp_path, capsys):
    """Every joint gets an actuator; the run tracks and its torques are Drake's inverse dynamics."""
    from armlab.controllers.inverse_dynamics import joint_torques

    path = tmp_path / "two.urdf"
    path.write_text(two_link_urdf())
    out = tmp_path / "run"
    assert armlab_cli("simulate", str(path), "--from", "0,0.5", "--to", "1,-0.5", "--dt", "0.01", "--out",
                      str(out)) == 0
    table = np.loadtxt(out / "log.csv", delimiter=",", skiprows=1)
    q_ref, qd_ref, qdd_ref, q, tau = (table[:, 1 + 2 * k: 3 + 2 * k] for k in (0, 1, 2, 3, 5))
    assert np.abs(q - q_ref).max() < 1e-6
    arm = get_arm(str(path))
    np.testing.assert_allclose(tau, joint_torques(arm, q_ref, qd_ref, qdd_ref), atol=1e-6)
    np.testing.assert_allclose(table[:, -9:-6], arm.forward(q).tool[:, :3, 3], atol=1e-9)


def test_user_urdf_that_cannot_be_simulated_says_why(tmp_path, capsys):
    path = tmp_path / "limp.urdf"
    path.write_text(two_link_urdf(mass2=0))  # the forearm moves no mass: the mass matrix is singular
    assert armlab_cli("simulate", str(path), "--from", "0,0", "--to", "1,1", "--out", str(tmp_path / "run")) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "mass matrix is singular (joint(s) elbow move no mass" in err[0]
    assert not (tmp_path / "run").exists()


def test_user_urdf_meshes_from_its_ros_package(tmp_path, capsys):
    """package://NAME/… resolves through the package.xml above the URDF (a ROS package); an unknown
    package is a one-line error, not a traceback."""
    package = tmp_path / "my_robot"
    (package / "urdf").mkdir(parents=True)
    (package / "meshes").mkdir()
    (package / "package.xml").write_text('<?xml version="1.0"?><package format="2"><name>my_robot</name>'
                                         "<version>0.1.0</version><description>d</description>"
                                         '<maintainer email="a@b.c">a</maintainer><license>MIT</license></package>')
    (package / "meshes" / "fore.obj").write_text(
        "v 0 -0.02 -0.02\nv 0.3 -0.02 -0.02\nv 0.3 0.02 -0.02\nv 0 0.02 -0.02\nv 0 0 0.02\nv 0.3 0 0.02\n"
        "f 1 2 3\nf 1 3 4\nf 1 2 6\nf 1 6 5\nf 4 3 6\nf 4 6 5\nf 1 4 5\nf 2 3 6\n")
    path = package / "urdf" / "two.urdf"
    path.write_text(two_link_urdf(mesh="package://my_robot/meshes/fore.obj"))
    arm = get_arm(str(path))
    q = np.random.default_rng(6).uniform(-3, 3, (20, 2))
    np.testing.assert_allclose(arm.forward(q).tool, _drake_tool(arm, q), atol=1e-9)
    from armlab.diagrams.replay import build_scene, start_meshcat

    scene = build_scene(arm, start_meshcat())  # with a scene graph, so the mesh is loaded
    assert len(scene.plant.GetVisualGeometriesForBody(scene.plant.GetBodyByName("fore"))) == 1
    out = tmp_path / "ok"
    assert armlab_cli("simulate", str(path), "--from", "0,0", "--to", "1,1", "--dt", "0.05", "--out", str(out)) == 0
    assert (out / "replay.html").exists()

    path.write_text(two_link_urdf(mesh="package://elsewhere/fore.obj"))
    assert armlab_cli("simulate", str(path), "--from", "0,0", "--to", "1,1", "--out", str(tmp_path / "run")) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "names package 'elsewhere'" in err[-1] and "declare 'my_robot'" in err[-1]


def test_missing_file():
    with pytest.raises(ValueError, match="cannot read"):
        get_arm("/nonexistent/arm.urdf")


def test_dh_rows_validate():
    with pytest.raises(ValueError, match="not a finite number"):
        DHRow(float("inf"), 0, 0, 0)
    with pytest.raises(ValueError, match="convention"):
        DHTable((DHRow(1, 0, 0, 0),), "craig")
    arm = from_dh(DHTable((DHRow(1.0, 0, 0, 0),)), [])  # limits count mismatch is caught by the URDF builder
    with pytest.raises(ValueError, match="need 1 bodies and 1 joint limits"):
        arm.urdf()
