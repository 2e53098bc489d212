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
    ],
)
def test_malformed_urdf(tmp_path, text, message):
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        get_arm(str(path))


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
