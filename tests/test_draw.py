"""``armlab draw``: the kinematic scheme shows the arm's own frames and joint axes.

What the scheme draws is checked against Drake's plant of the same arm (built from the URDF, an
independent path from the DH / locating tables the scheme uses): every joint axis drawn is the
plant's joint axis, every frame chain ends at the plant's tool frame.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import ARM_NAMES, arm_and_plant, random_q
from matplotlib.image import imread

from armlab.models import get_arm
from armlab.presentation.draw import _view, default_q, draw_arm, scheme, write_figure


def drake_axes(name: str, q: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, str]]:
    """(point on the axis, unit axis, "R"/"T") of each joint in the world, from Drake's plant."""
    arm, plant, context = arm_and_plant(name)
    positions = np.zeros(plant.num_positions())
    for i, joint_name in enumerate(arm.joint_names):
        positions[plant.GetJointByName(joint_name).position_start()] = q[i]
    plant.SetPositions(context, positions)
    out = []
    for joint_name in arm.joint_names:
        joint = plant.GetJointByName(joint_name)
        X_WF = joint.frame_on_parent().CalcPoseInWorld(context)
        X_WM = joint.frame_on_child().CalcPoseInWorld(context)
        if joint.type_name() == "revolute":
            out.append((X_WM.translation(), X_WF.rotation().matrix() @ joint.revolute_axis(), "R"))
        else:
            out.append((X_WM.translation(), X_WF.rotation().matrix() @ joint.translation_axis(), "T"))
    return out


@pytest.mark.parametrize("name", ARM_NAMES)
def test_scheme_axes_and_frames_are_drakes(name):
    arm = get_arm(name)
    for q in random_q(arm, np.random.default_rng(7), 5):
        s = scheme(arm, q)
        assert len(s.joints) == arm.n
        for (origin, axis, kind), (p, k, drake_kind) in zip(s.joints, drake_axes(name, q), strict=True):
            assert kind == drake_kind
            k = k / np.linalg.norm(k)
            assert abs(abs(axis @ k) - 1) < 1e-9, (axis, k)  # parallel
            if kind == "R":  # the drawn axis is Drake's axis line, not just a parallel one
                assert np.linalg.norm(np.cross(origin - p, k)) < 1e-9
        _, _, context = arm_and_plant(name)
        tool = arm_and_plant(name)[1].GetFrameByName(arm.tool_name).CalcPoseInWorld(context).GetAsMatrix4()
        assert np.allclose(s.chain[-1], tool[:3, 3], atol=1e-9)
        assert any(np.allclose(T, tool, atol=1e-9) for label, T in s.frames if "tool" in label)
        labels = [label.split(" =")[0] for label, _ in s.frames]
        assert labels[: arm.n + 1] == [f"{{{i}}}" for i in range(arm.n + 1)]


def test_dh_arms_show_the_dh_table_and_locating_arms_theirs():
    assert scheme(get_arm("rrrr"), np.zeros(4)).table_title.startswith("standard DH")
    assert scheme(get_arm("arm4r"), np.zeros(4)).table_title.startswith("modified DH")
    urm6 = scheme(get_arm("urm6"), np.zeros(6))
    assert urm6.table_title.startswith("locating table")
    assert "R: 15° about (0, 1, 0)" in urm6.table[1]  # the module's fixed bend θ2


@pytest.mark.slow
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_a_users_dh_table_is_drawn_in_its_own_convention(tmp_path, convention):
    csv = tmp_path / "my_arm.csv"
    csv.write_text(f"# convention: {convention}\ntype,a,alpha,d,theta,lower,upper\n"
                   "R,0.1,1.5707963267948966,0.3,0,-3,3\nR,0.5,0,0,0,-3,3\nT,0.2,0,0.1,0,0,0.4\n")
    arm = get_arm(str(csv))
    s = scheme(arm, np.array([0.4, -0.7, 0.2]))
    assert s.table_title.startswith(convention)
    assert np.allclose(s.chain[-1], arm.fk(np.array([0.4, -0.7, 0.2]))[:3, 3], atol=1e-9)
    assert s.joints[2][2] == "T"
    expected = {"standard": ["d1 = 0.3, a1 = 0.1", "a2 = 0.5", "d3 = 0.1, a3 = 0.2"],  # row i: d_i, a_i
                "modified": ["d1 = 0.3, a0 = 0.1", "a1 = 0.5", "d3 = 0.1, a2 = 0.2"]}  # row i: d_i, a_{i-1}
    assert [text for text, _ in s.link_labels] == expected[convention]
    draw_arm(arm, np.array([0.4, -0.7, 0.2]), tmp_path / "my_arm.svg")
    assert "my_arm" in (tmp_path / "my_arm.svg").read_text()


def test_planar_arm_is_seen_face_on_and_a_spatial_one_obliquely():
    assert _view(scheme(get_arm("rr"), np.array([0.3, 0.5])))[0] == pytest.approx(90.0)
    elevation, _ = _view(scheme(get_arm("rrrr"), np.array([0.3, 0.5, 0.2, 0.1])))
    assert 10 < elevation < 60


@pytest.mark.slow
@pytest.mark.parametrize("name", ARM_NAMES)
def test_draw_writes_a_picture_of_every_paper_arm(tmp_path, name):
    arm = get_arm(name)
    q = random_q(arm, np.random.default_rng(3), 1)[0]
    path = draw_arm(arm, q, tmp_path / f"{name}.png")
    image = imread(path)[..., :3]
    drawn = np.abs(image - 1.0).max(axis=-1) > 0.1
    assert 0.03 < drawn.mean() < 0.6
    red = (image[..., 0] > 0.7) & (image[..., 1] < 0.3) & (image[..., 2] < 0.3)  # x axes of the triads
    green_or_blue = (np.maximum(image[..., 1], image[..., 2]) > 0.5) & (image[..., 0] < 0.3)  # y, z axes
    assert red.sum() > 30 and green_or_blue.sum() > 30
    assert [p.name for p in tmp_path.iterdir()] == [f"{name}.png"]


@pytest.mark.slow
def test_draw_command_and_its_errors(tmp_path):
    from armlab.cli import main

    assert main(["draw", "rr", "--q", "30,-60", "--deg", "--out", str(tmp_path / "rr.pdf")]) == 0
    assert (tmp_path / "rr.pdf").read_bytes().startswith(b"%PDF")
    assert main(["draw", "rr", "--out", str(tmp_path / "rr.jpg")]) == 2
    assert main(["draw", "arm4r", "--q", "0,200,0,0", "--deg", "--out", str(tmp_path / "a.png")]) == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rr.pdf"]


def test_a_path_ending_in_a_slash_is_refused_and_nothing_is_written(tmp_path):
    import matplotlib.pyplot as plt

    fig = plt.figure()
    try:
        with pytest.raises(ValueError, match="ends with '/', a folder"):
            write_figure(fig, f"{tmp_path / 'b.png'}/")
    finally:
        plt.close(fig)
    with pytest.raises(ValueError, match="ends with '/', a folder"):
        draw_arm(get_arm("rr"), [0.0, 0.0], f"{tmp_path / 'rr.svg'}/")
    assert list(tmp_path.iterdir()) == []


def test_without_q_a_paper_arm_is_drawn_at_its_paper_motions_start():
    np.testing.assert_allclose(default_q(get_arm("rr")), np.radians([-38.0, 98.0]), atol=1e-12)
    np.testing.assert_allclose(get_arm("arm4r").fk(default_q(get_arm("arm4r")))[:3, 3], [2.0, 0.0, 0.0], atol=1e-9)
