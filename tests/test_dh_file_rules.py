"""The rules of a DH table file that users and spreadsheets trip on (issue 22 §3, issue 24 items 8, 11, 17, 22).

Numbers are plain decimals; blank lines and a spreadsheet's trailing commas are not rows or columns; a repeated
column is named as such; a cell too long for csv is one line; joint limits may pass ±2π (α and θ may not); a
centre of mass far beyond the arm is refused; ``# base:`` / ``# tool:`` place the chain, checked against Drake's
plant of the arm's URDF and against the DH product; ``show`` echoes the mass data in the frames the user wrote.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import DATA, armlab_main

import armlab
from armlab.kinematics.basic_movements import T_Z4, T_Z5, T_Z6
from armlab.kinematics.locating import homogeneous
from armlab.models.read_dh import read_dh_csv

HEADER = "type,a,alpha,d,theta,lower,upper"


def _file(tmp_path, text: str):
    path = tmp_path / "arm.csv"
    path.write_text(text)
    return path


@pytest.mark.parametrize("cell", ["0_5", "1_000", "0x10", "5.", "١"])
def test_numbers_are_plain_decimals(tmp_path, cell):
    text = f"{HEADER}\nR,{cell},0,0,0,,\nR,0.4,0,0,0,,\n"
    if cell == "5.":  # a plain decimal: read as 5
        assert read_dh_csv(_file(tmp_path, text))[0].rows[0].a == 5.0  # exact: "5." is 5
        return
    with pytest.raises(ValueError, match=rf"row 1: a = '{cell}' is not a number: numbers in arm files are plain "
                                         "decimals"):
        read_dh_csv(_file(tmp_path, text))


def test_blank_and_whitespace_lines_are_not_rows(tmp_path):
    rows = "".join(f"R,0.01,0,0,0,,\n{'   ' if i % 10 == 0 else ''}\n" if i % 10 == 0 else "R,0.01,0,0,0,,\n"
                   for i in range(60))
    table, limits, _ = read_dh_csv(_file(tmp_path, f"{HEADER}\n{rows}\n\t\n ,  , \n"))
    assert table.n == 60 and len(limits) == 60
    with pytest.raises(ValueError, match="more than 64 rows"):
        read_dh_csv(_file(tmp_path, f"{HEADER}\n" + "R,0.01,0,0,0,,\n" * 65))


def test_a_cell_longer_than_csvs_limit_is_one_line(tmp_path):
    with pytest.raises(ValueError, match=r"cannot be read as CSV: field larger than field limit .*a cell holds one "
                                         "number"):
        read_dh_csv(_file(tmp_path, f"{HEADER}\nR,{'1' * 131073},0,0,0,,\n"))


def test_repeated_column_and_trailing_commas(tmp_path):
    with pytest.raises(ValueError, match=r"column\(s\) a appear more than once in the header"):
        read_dh_csv(_file(tmp_path, f"{HEADER},a\nR,0.4,0,0,0,,,0.4\n"))
    with pytest.raises(ValueError, match=r"column\(s\) Mass, mass appear more than once"):
        read_dh_csv(_file(tmp_path, f"{HEADER},mass,Mass\nR,0.4,0,0,0,,,1,1\n"))
    excel = f"{HEADER},mass,,,\r\nR,0.4,0,0,0,,,1,,,\r\nR,0.3,0,0,0,-1,1,2,\r\n,,,,,,,,,,\r\n"
    table, _, inertials = read_dh_csv(_file(tmp_path, excel))
    assert table.n == 2 and [b.mass for b in inertials] == [1.0, 2.0]  # exact: typed masses
    with pytest.raises(ValueError, match=r"unknown column\(s\) ''; allowed after"):
        read_dh_csv(_file(tmp_path, f"{HEADER},,mass\nR,0.4,0,0,0,,,,1\n"))


def test_limits_beyond_two_pi_are_legal_angles_are_not(tmp_path):
    rad = read_dh_csv(_file(tmp_path, f"{HEADER}\nR,0.4,0,0,0,-6.9813,6.9813\n"))[1][0]
    np.testing.assert_allclose([rad.lower, rad.upper], [-6.9813, 6.9813], rtol=0, atol=1e-15)
    deg = read_dh_csv(_file(tmp_path, f"# units: deg\n{HEADER}\nR,0.4,0,0,0,-400,400\n"))[1][0]
    np.testing.assert_allclose([deg.lower, deg.upper], np.radians([-400, 400]), rtol=1e-15, atol=0)
    with pytest.raises(ValueError, match=r"alpha = 90 is beyond ±2π rad"):
        read_dh_csv(_file(tmp_path, f"{HEADER}\nR,0.4,90,0,0,,\n"))


def test_com_kilometres_away_is_refused(tmp_path):
    text = f"{HEADER},mass,cx,cy,cz\nR,0.4,0,0,0,,,1,0,0,0.1\nR,0.3,0,0,0,,,1,198000,0,0\n"
    with pytest.raises(ValueError, match=r"link 2: the centre of mass is 198000 m from its link frame, beyond 8 m "
                                         r"\(10 × the arm's size 0.7 m \+ 1 m\): not physical"):
        armlab.load(_file(tmp_path, text))


def _rpy(x, y, z, roll, pitch, yaw):
    """The pose x y z roll pitch yaw as URDF writes it: R = Rz(yaw)·Ry(pitch)·Rx(roll)."""
    return homogeneous((T_Z6(yaw) @ T_Z5(pitch) @ T_Z4(roll))[:3, :3], np.array([x, y, z]))


def test_base_and_tool_header_lines_place_the_chain():
    arm = armlab.load(DATA / "dh_base_tool.csv")
    base, tool = _rpy(0, 0, 0.5, 0, 0, np.pi / 2), _rpy(0, 0, 0.1, 0, np.pi / 2, 0)
    q = np.array([0.4, -1.2, 0.15])
    expected = base @ arm.dh.end_pose(q) @ tool  # the DH product (000 eq. 9), then the header's poses
    np.testing.assert_allclose(arm.fk(q), expected, atol=1e-12, rtol=0)
    plant = arm.make_plant()  # Drake's plant of the arm's URDF: the same tool frame
    context = plant.CreateDefaultContext()
    plant.SetPositions(context, q)
    np.testing.assert_allclose(plant.GetFrameByName("tool").CalcPoseInWorld(context).GetAsMatrix4(), expected,
                               atol=1e-12, rtol=0)
    assert arm.tool_source == "DH frame n moved by the table's '# tool:' pose"  # exact: text


@pytest.mark.parametrize("line, message", [
    ("# base: 0 0 0.5", "needs six numbers x y z roll pitch yaw"),
    ("# tool: 0 0 0 0 0 0\n# tool: 0 0 0 0 0 0", "write it once as '# tool: x y z roll pitch yaw'"),
    ("# tools = 0 0 0 0 0 0", "write it once as '# tool: x y z roll pitch yaw'"),
    ("# base: 0 0 0_5 0 0 0", "base = '0_5' is not a number"),
])
def test_bad_base_and_tool_lines(tmp_path, line, message):
    with pytest.raises(ValueError, match=message):
        armlab.load(_file(tmp_path, f"{line}\n{HEADER}\nR,0.4,0,0,0,,\n"))


def test_show_echoes_mass_data_in_the_frames_the_user_wrote(tmp_path):
    path = _file(tmp_path, f"{HEADER},mass,cx,cy,cz,Ixx,Iyy,Izz\nR,0.4,1.5707963267948966,0,0,,,2,0,-0.2,0,"
                           "0.01,0.02,0.03\nR,0.3,0,0,0,,,1,-0.15,0,0,0.001,0.002,0.002\n")
    result = armlab_main("show", str(path))
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    start = lines.index("links: mass [kg], centre of mass [m] and inertia diagonal [kg·m²], in DH frame i, as the "
                        "table gives them (standard DH: at the link's far end; modified: at joint i)")
    assert lines[start + 1].split() == ["link1", "2", "com", "(+0,", "-0.2,", "+0)", "I", "(0.01,", "0.02,", "0.03)"]
    assert lines[start + 2].split() == ["link2", "1", "com", "(-0.15,", "+0,", "+0)", "I", "(0.001,", "0.002,",
                                        "0.002)"]
    assert lines[start + 3].startswith("links: mass [kg], centre of mass [m] and inertia diagonal [kg·m²], in link "
                                       "frame {i} of the arm's URDF")
    urdf_frame = lines[start + 4].split()  # the same link in {1}: the com moved by the DH frame's pose in {1}
    assert urdf_frame[:3] == ["link1", "2", "com"] and urdf_frame[3:6] != ["(+0,", "-0.2,", "+0)"]
