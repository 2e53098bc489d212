"""Users' own arms: DH tables (standard and modified) and URDF files, and their errors."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import arm_and_plant, data, rnea_in_dh_frames, two_link_urdf

from armlab.kinematics.dh import DHRow, DHTable
from armlab.models import get_arm
from armlab.models.read_dh import from_dh
from armlab.models.read_urdf import from_urdf
from armlab.models.write_urdf import JointLimits

PUMA_LIKE = data("puma_like_dh.csv")


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


def test_files_that_are_not_text(tmp_path):
    for name in ("bad.csv", "bad.urdf"):
        (tmp_path / name).write_bytes(b"\xff\xfe\x00garbage")
        with pytest.raises(ValueError, match=name):
            get_arm(str(tmp_path / name))


def armlab_cli(*argv: str) -> int:
    from armlab.cli import main

    return main(list(argv))


@pytest.mark.slow
def test_user_urdf_without_transmissions_simulates(tmp_path, capsys):
    """Every joint gets an actuator; the run tracks and its torques are Drake's inverse dynamics."""
    path = tmp_path / "two.urdf"
    path.write_text(two_link_urdf())
    out = tmp_path / "run"
    assert armlab_cli("simulate", str(path), "--from", "0,0.5", "--to", "1,-0.5", "--dt", "0.01", "--out",
                      str(out)) == 0
    table = np.loadtxt(out / "log.csv", delimiter=",", skiprows=1)
    q_ref, qd_ref, qdd_ref, q, tau = (table[:, 1 + 2 * k: 3 + 2 * k] for k in (0, 1, 2, 3, 5))
    assert np.abs(q - q_ref).max() < 1e-6
    arm = get_arm(str(path))
    np.testing.assert_allclose(tau, arm.inverse_dynamics(q_ref, qd_ref, qdd_ref), atol=1e-6)
    np.testing.assert_allclose(table[:, -9:-6], arm.forward(q).tool[:, :3, 3], atol=1e-9)


def test_user_urdf_that_cannot_be_simulated_says_why(tmp_path, capsys):
    path = tmp_path / "limp.urdf"
    path.write_text(two_link_urdf(mass2=0))  # the forearm moves no mass: the mass matrix is singular
    assert armlab_cli("simulate", str(path), "--from", "0,0", "--to", "1,1", "--out", str(tmp_path / "run")) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "mass matrix is singular (joint(s) elbow move no mass" in err[0]
    assert not (tmp_path / "run").exists()


@pytest.mark.slow  # a simulate run with its replay, for the mesh paths (no number of its own)
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
    from armlab.presentation.replay import build_scene, start_meshcat

    scene = build_scene(arm, start_meshcat())  # with a scene graph, so the mesh is loaded
    assert len(scene.plant.GetVisualGeometriesForBody(scene.plant.GetBodyByName("fore"))) == 1
    out = tmp_path / "ok"
    assert armlab_cli("simulate", str(path), "--from", "0,0", "--to", "1,1", "--dt", "0.05", "--out", str(out)) == 0
    assert (out / "replay.html").exists()

    # a package that cannot be found: its mesh is left out with one warning (issue 22: as ROS files come), the run made
    path.write_text(two_link_urdf(mesh="package://elsewhere/fore.obj"))
    capsys.readouterr()
    assert armlab_cli("simulate", str(path), "--from", "0,0", "--to", "1,1", "--dt", "0.05",
                      "--out", str(tmp_path / "run")) == 0
    err = [line for line in capsys.readouterr().err.splitlines() if line.startswith("armlab: warning:")]
    assert len(err) == 1 and "'package://elsewhere/fore.obj'" in err[0] and "--package-path DIR" in err[0]


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


# --------------------------------------------------------------------------- dynamics from a DH table
def _random_links(rng, n):
    """Physical mass properties: masses, centres of mass and rotated principal inertias (triangle inequality)."""
    out = []
    for _ in range(n):
        moments = rng.uniform(0.01, 0.1, 3)
        moments[2] = rng.uniform(abs(moments[0] - moments[1]), moments[0] + moments[1])
        Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        out.append((rng.uniform(0.5, 3.0), rng.uniform(-0.2, 0.2, 3), Q @ np.diag(moments) @ Q.T))
    return out


def _table_with_masses(convention, rows, links, deg=False):
    """A DH .csv with the optional columns, in a shuffled order, ``# units: deg`` if ``deg``."""
    head = ["# units: deg"] if deg else []
    head += [f"# convention: {convention}",
             "type,a,alpha,d,theta,lower,upper,Izz,cz,mass,Ixx,cx,Iyy,cy,Ixy,Iyz,Ixz,effort"]
    for (kind, a, alpha, d, theta), (m, r, inertia) in zip(rows, links, strict=True):
        ang = np.degrees if deg else (lambda x: x)
        lo, hi = ((-170.0, 170.0) if deg else (-3.0, 3.0)) if kind == "R" else (0.0, 0.5)
        values = [kind, a, ang(alpha), d, ang(theta), lo, hi, inertia[2, 2], r[2], m, inertia[0, 0], r[0],
                  inertia[1, 1], r[1], inertia[0, 1], inertia[1, 2], inertia[0, 2], 40]
        head.append(",".join(v if isinstance(v, str) else repr(float(v)) for v in values))
    return "\n".join(head) + "\n"


@pytest.mark.parametrize(("convention", "deg"), [("standard", False), ("modified", True)])
def test_dh_masses_give_drakes_inverse_dynamics(tmp_path, convention, deg):
    """The plant built from a DH table with masses (moved from the DH frames into the URDF's link frames)
    has the inverse dynamics of a Newton–Euler recursion written in the DH frames themselves."""
    from pydrake.multibody.tree import MultibodyForces

    rng = np.random.default_rng(11 if deg else 10)
    rows = [("R", 0.1, np.pi / 2, 0.35, 0.3), ("R", 0.45, 0.2, 0.05, -0.4), ("T", 0.05, -np.pi / 2, 0.1, 0.6),
            ("R", 0.0, np.pi / 3, 0.2, 0.0), ("R", 0.12, -0.7, 0.0, 1.1)]
    links = _random_links(rng, len(rows))
    path = tmp_path / "massive.csv"
    path.write_text(_table_with_masses(convention, rows, links, deg))
    arm = get_arm(str(path))
    assert arm.has_dynamics and arm.table.n == 5 and all(lim.effort == 40 for lim in arm.limits)
    plant = arm.make_plant()
    ctx = plant.CreateDefaultContext()
    index = [plant.GetJointByName(name).position_start() for name in arm.joint_names]
    assert index == list(range(arm.n))
    for _ in range(25):
        q = rng.uniform([-3, -3, 0, -3, -3], [3, 3, 0.5, 3, 3])
        qd, qdd = rng.normal(size=5) * 2, rng.normal(size=5) * 5
        plant.SetPositions(ctx, q)
        plant.SetVelocities(ctx, qd)
        forces = MultibodyForces(plant)
        plant.CalcForceElementsContribution(ctx, forces)  # gravity
        tau_drake = plant.CalcInverseDynamics(ctx, qdd, forces)
        tau = rnea_in_dh_frames(rows, convention, links, q, qd, qdd, arm.gravity)
        np.testing.assert_allclose(tau_drake, tau, rtol=0, atol=1e-9 * np.abs(tau).max())
    masses, _, _ = arm.mass_properties()
    np.testing.assert_allclose(masses, [m for m, _, _ in links], rtol=1e-15)
    assert [link["mass"] for link in arm.links()] == pytest.approx(masses.tolist())


def test_dh_table_without_masses_is_kinematic(tmp_path, capsys):
    """No mass column: no invented masses; kinematics still work (Drake needs no inertia for them)."""
    path = tmp_path / "bare.csv"
    path.write_text(PUMA_LIKE)
    arm = get_arm(str(path))
    assert not arm.has_dynamics and "<inertial>" not in arm.urdf()
    assert all(link["mass"] is None and link["com"] is None for link in arm.links())
    assert all(lim.effort is None and lim.velocity is None for lim in arm.limits)
    with pytest.raises(ValueError, match="kinematic arm"):
        arm.mass_properties()
    q = np.random.default_rng(7).uniform([-3, -6, 0, -2], [3, 6, 0.5, 2], size=(20, 4))
    np.testing.assert_allclose(arm.forward(q).tool, _drake_tool(arm, q), atol=1e-9)
    for argv in (["simulate", str(path), "--out", str(tmp_path / "run")],):
        assert armlab_cli(*argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "kinematic arm" in err[0] and "mass" in err[0], err
    assert not (tmp_path / "run").exists()
    assert armlab_cli("fk", str(path), "--q", "0.1,0.2,0.3,0.4") == 0
    assert armlab_cli("show", str(path)) == 0


def test_dh_degrees_and_radians_tables_are_the_same_arm(tmp_path):
    rad = tmp_path / "rad.csv"
    deg = tmp_path / "deg.csv"
    rad.write_text("type,a,alpha,d,theta,lower,upper,velocity,effort\nR,0.3,1.5707963267948966,0.2,0.5,-2,2,3,50\n"
                   "T,0,0,0.1,0,0,0.4,0.5,\n")
    deg.write_text(f"# units: deg\n# convention: standard\ntype,a,alpha,d,theta,lower,upper,velocity,effort\n"
                   f"R,0.3,90,0.2,{np.degrees(0.5)},{np.degrees(-2)},{np.degrees(2)},{np.degrees(3)},50\n"
                   "T,0,0,0.1,0,0,0.4,0.5,\n")
    a, b = get_arm(str(rad)), get_arm(str(deg))
    q = np.random.default_rng(8).uniform([-2, 0], [2, 0.4], (30, 2))
    np.testing.assert_allclose(a.forward(q).tool, b.forward(q).tool, atol=1e-14)
    for x, y in zip(a.limits, b.limits, strict=True):
        assert (x.lower, x.upper, x.effort) == pytest.approx((y.lower, y.upper, y.effort))
        assert x.velocity == pytest.approx(y.velocity)
    assert a.limits[1] == b.limits[1] == JointLimits(0.0, 0.4, None, 0.5)  # prismatic: m and m/s, not degrees


def test_urdf_mass_properties_and_limits_are_the_files(tmp_path):
    """Links welded by fixed joints are one body (as in Drake); the inertial's rpy is applied; limits are read."""
    from pydrake.multibody.tree import BodyIndex

    text = two_link_urdf().replace(
        '<link name="hand"/>',
        '<link name="hand"><inertial><origin xyz="0.02 0.01 0" rpy="0.3 -0.2 0.5"/><mass value="0.25"/>'
        '<inertia ixx="2e-4" ixy="1e-5" ixz="0" iyy="3e-4" iyz="-2e-5" izz="4e-4"/></inertial></link>'
    ).replace('effort="10" velocity="5"/></joint>\n  <joint name="elbow"',
              'effort="10"/></joint>\n  <joint name="elbow"')
    path = tmp_path / "two.urdf"
    path.write_text(text)
    arm = get_arm(str(path))
    assert arm.has_dynamics and arm.link_names == ("upper", "fore")
    assert arm.limits[0] == JointLimits(-3.0, 3.0, 10.0, None) and arm.limits[1] == JointLimits(-3.0, 3.0, 10.0, 5.0)
    plant = arm.make_plant()
    ctx = plant.CreateDefaultContext()
    plant.SetPositions(ctx, [0.4, -1.1])
    masses, coms, inertias = arm.mass_properties()
    groups = [["upper"], ["fore", "hand"]]
    for i, names in enumerate(groups):
        frame = plant.GetFrameByName(names[0])
        M = plant.CalcSpatialInertia(ctx, frame, [BodyIndex(int(plant.GetBodyByName(b).index())) for b in names])
        assert M.get_mass() == pytest.approx(masses[i], rel=1e-14)
        np.testing.assert_allclose(M.get_com(), coms[i], atol=1e-14)
        c = coms[i]
        about_origin = inertias[i] + masses[i] * (c @ c * np.eye(3) - np.outer(c, c))
        np.testing.assert_allclose(M.CalcRotationalInertia().CopyToFullMatrix3(), about_origin, atol=1e-15)


def test_paper_arms_mass_properties_are_the_plants(arm_name):
    from pydrake.multibody.tree import BodyIndex

    arm, plant, ctx = arm_and_plant(arm_name)
    masses, coms, inertias = arm.mass_properties()
    for i in range(arm.n):
        body = plant.GetBodyByName(f"link{i + 1}")
        M = plant.CalcSpatialInertia(ctx, body.body_frame(), [BodyIndex(int(body.index()))])
        assert M.get_mass() == pytest.approx(masses[i], rel=1e-14)
        np.testing.assert_allclose(M.get_com(), coms[i], atol=1e-15)
        c = coms[i]
        about_origin = inertias[i] + masses[i] * (c @ c * np.eye(3) - np.outer(c, c))
        np.testing.assert_allclose(M.CalcRotationalInertia().CopyToFullMatrix3(), about_origin, atol=1e-14)
    assert arm.has_dynamics and all(lim.effort and lim.velocity for lim in arm.limits)


def test_a_urdf_without_mass_is_kinematic(tmp_path):
    path = tmp_path / "light.urdf"
    text = two_link_urdf(mass2=0)
    path.write_text(text[:text.index('  <link name="upper">')] + '  <link name="upper"/>'
                    + text[text.index('  <link name="fore">'):])
    arm = get_arm(str(path))
    assert not arm.has_dynamics and arm.links()[0]["mass"] is None
    with pytest.raises(ValueError, match="two is a kinematic arm"):
        arm.require_dynamics("simulate")


def test_link_name_with_a_quote_loads(tmp_path):
    path = tmp_path / "quote.urdf"
    path.write_text(two_link_urdf().replace('"fore"', "\"fo're\""))
    arm = get_arm(str(path))
    assert arm.link_names == ("upper", "fo're") and arm.links()[1]["mass"] == 0.5  # exact: the URDF's mass="0.5"


_H = "type,a,alpha,d,theta,lower,upper"


#: Bad DH tables and the error each gives.
_DH_CASES = [
    ("type,a,alpha,d,theta,lower,upper\nX,0,0,0,0,,\n", "type 'X' is not allowed"),
    ("type,a,alpha,d,theta,lower,upper\nR,zero,0,0,0,,\n", "row 1: a = 'zero' is not a number"),
    ("type,a,alpha,d,theta,lower,upper\nR,nan,0,0,0,,\n", "not a finite number"),
    ("type,a,alpha,d,theta,lower,upper\nT,0,0,0,0,,\n", "prismatic joint needs lower and upper"),
    ("type,a,alpha,d,theta,lower,upper\nR,0,0,0,0,2,1\n", "lower = 2.0 must be below upper = 1.0"),
    ("a,b\n1,2\n", "header"),
    ("type,a,alpha,d,theta,lower,upper\n", "no rows"),
    ("# convention: weird\ntype,a,alpha,d,theta,lower,upper\nR,0,0,0,0,,\n", "convention"),
    ("type,a,alpha,d,theta,lower,upper\nR,0.4,0,0,0,-3,3,9\n", "row 1 has 8 values; expected 7"),
    (f"{_H},weight\nR,0,0,0,0,,,1\n", "unknown column.s. weight; allowed after"),
    (f"{_H},cx\nR,0,0,0,0,,,0.1\n", r"column\(s\) cx need the mass column"),
    (f"{_H},mass,Mass\nR,0,0,0,0,,,1,1\n", "mass appear more than once"),
    (f"{_H},mass\nR,0,0,0,0,,,\n", "row 1: mass is empty"),
    (f"{_H},mass,Ixx\nR,0,0,0,0,,,1,-0.1\n", "row 1: Ixx = -0.1 kg·m² is negative"),
    (f"{_H},mass,Ixx,Iyy,Izz\nR,0,0,0,0,,,1,0.1,0.1,0.5\n", "row 1: the inertia is not physical.*triangle"),
    (f"{_H},mass,Ixx\nR,0,0,0,0,,,0,0.1\n", "mass 0 kg with a nonzero inertia"),
    (f"{_H},effort\nR,0,0,0,0,,,-5\n", "row 1: effort = -5 is not allowed"),
    (f"{_H}\nR,0.4,90,0,0,,\n", r"alpha = 90 is beyond ±2π rad.*'# units: deg'"),
    (f"{_H}\nR,0.4,0,0,400,,\n", "theta = 400 is beyond"),
    (f"# unit: degrees\n{_H}\nR,0,0,0,0,,\n", "write it once as '# units: rad' or '# units: deg'"),
    (f"# units: deg\n# units: deg\n{_H}\nR,0,0,0,0,,\n", "write it once"),
    (f"# Units = degrees\n{_H}\nR,0,0,0,0,,\n", "write it once as '# units: rad'"),
    (f"# conventions: craig\n{_H}\nR,0,0,0,0,,\n", "'# convention: standard' or"),
    (f"# convention: weird\n{_H}\nR,0,0,0,0,,\n", "'# convention: standard' or '# convention: modified'"),
    (f"{_H}\n" + "R,0.1,0,0,0,,\n" * 65, "more than 64 rows: armlab takes arms of at most 64 joints"),
    (f"{_H},mass\nR,0,0,0,0,,,inf\n", "mass = 'inf' is not a finite number"),
    ("", "header '' must start with type,a,alpha"),
]


def test_dh_table_comments_and_a_byte_order_mark(tmp_path):
    path = tmp_path / "ok.csv"
    path.write_text(f"\ufeff# my PUMA, from the catalogue (units and convention below)\n# Units: DEG\n"
                    f"# convention: modified\n{_H}\nR,0,90,0,0,,\n")
    arm = get_arm(str(path))
    assert arm.dh.convention == "modified" and arm.dh.rows[0].alpha == pytest.approx(np.pi / 2)
    assert get_arm(str(path)).n == 1


def _urdf(joints: str, links: str = "a b", extra: str = "") -> str:
    return ('<robot name="r">' + "".join(f'<link name="{name}"/>' for name in links.split()) + joints + extra
            + "</robot>")


def _joint(name: str, parent: str, child: str, kind: str = "continuous", inner: str = "") -> str:
    return f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>{inner}</joint>'


#: Bad URDFs and the error each gives.
_URDF_CASES = [
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
    (_urdf(_joint("j", "a", "b") + _joint("k", "b", "c", "fixed") + _joint("l", "c", "b", "fixed"), "a b c"),
     "link 'b' is the child of joints 'j' and 'l'"),
    (_urdf(_joint("j", "a", "b") + _joint("k", "b", "a")), "the joints form a cycle: every link has a parent"),
    (_urdf(_joint("j", "a", "b") + _joint("k", "c", "c", "fixed"), "a b c"),
     "cycle through link.s. 'c', not connected to the root link 'a'"),
    (_urdf(_joint("j", "a", "b") + _joint("k", "b", "c", inner='<mimic joint="j"/>'), "a b c"),
     "joint 'k' mimics joint 'j': mimic joints are not supported"),
    (_urdf(_joint("j", "a", "b", "floating")), "joint 'j' has type 'floating'; allowed: revolute"),
    (_urdf(_joint("j", "a", "b", "planar")), "joint 'j' has type 'planar'"),
    (_urdf(_joint("j", "a", "b", "revolute", '<limit lower="1" upper="-1"/>')),
     "joint 'j' has lower = 1 above upper = -1: the limits are reversed"),
    (_urdf(_joint("j", "a", "b", "revolute", '<limit lower="-1" upper="1" effort="-3"/>')),
     "joint 'j' effort = -3 is not allowed"),
    (_urdf(_joint("j", "a", "b"), "a").replace('<link name="a"/>', '<link name="a"/><link name="b"><inertial>'
                                                '<mass value="1"/><inertia ixx="-1" iyy="1" izz="1"/>'
                                                '</inertial></link>'),
     "link 'b': Ixx = -1 kg·m² is negative"),
    (_urdf(_joint("j", "a", "b"), "a").replace('<link name="a"/>', '<link name="a"/><link name="b"><inertial>'
                                                  '<mass value="1"/><inertia ixx="1" iyy="1" izz="3"/>'
                                                  '</inertial></link>'),
     "link 'b': the inertia is not physical.*triangle inequality"),
    ('<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;">]>'
     + _urdf(_joint("j", "a", "b")), "document-type or entity definitions"),
    (_urdf(_joint("j", "a", "b", inner='<origin xyz="nan 0 0"/>')), "not a finite number"),
    (_urdf(_joint("j", "a", "b"), extra='<link name="d"><visual><geometry><box size="1 inf 1"/></geometry>'
                                         '</visual></link>' + _joint("k", "b", "d", "fixed")),
     "<box> size='1 inf 1' has a value that is not a finite number"),
    (_urdf(_joint("j", "a", "b"), extra='<transmission name="t"><joint name="j"/><actuator name="m">'
                                        '<mechanicalReduction>NaN</mechanicalReduction></actuator></transmission>'),
     "<mechanicalReduction> 'NaN' has a value that is not a finite number"),
    (_urdf(_joint("j", "a", "b") + _joint("j", "b", "c"), "a b c"), "two <joint> elements are named 'j'"),
    (_urdf(_joint("j", "a", "b"), "a b b"), "two <link> elements are named 'b'"),
    (_urdf("".join(_joint(f"j{i}", f"l{i}", f"l{i + 1}") for i in range(70)), " ".join(f"l{i}" for i in range(71))),
     "70 movable joints: armlab takes arms of at most 64 joints"),
]


@pytest.mark.parametrize(("name", "text", "message"), [("bad.csv", *case) for case in _DH_CASES]
                         + [("bad.urdf", *case) for case in _URDF_CASES])
def test_malformed_files(tmp_path, name, text, message):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        get_arm(str(path))


@pytest.mark.slow
def test_a_long_fixed_chain_needs_no_recursion(tmp_path):
    """10,000 fixed joints after the last joint (the tool at their end) load without a RecursionError."""
    names = " ".join(["a", "b"] + [f"f{i}" for i in range(10_000)])
    fixed = "".join(_joint(f"w{i}", "b" if i == 0 else f"f{i - 1}", f"f{i}", "fixed", '<origin xyz="0.001 0 0"/>')
                    for i in range(10_000))
    path = tmp_path / "long.urdf"
    path.write_text(_urdf(_joint("j", "a", "b") + fixed, names))
    arm = get_arm(str(path))
    np.testing.assert_allclose(arm.forward([0.0]).tool[:3, 3], [10.0, 0, 0], atol=1e-9)
