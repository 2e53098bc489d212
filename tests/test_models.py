"""The arms' URDF files, plants and parameters."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest
from helpers import arm_and_plant, assert_same_numbers

from armlab.models import ARMS, get_arm


def test_committed_urdf_is_what_the_builder_writes(arm_name):
    arm = get_arm(arm_name)
    # the shipped file was written on another machine: its numbers up to another CPU's rounding, the rest exactly
    assert_same_numbers(arm.urdf(), arm.urdf_file.read_text(), where=f"regenerate {arm.urdf_file.name}")


def test_urdf_has_transmissions_limits_inertia_and_visuals(arm_name):
    arm = get_arm(arm_name)
    root = ET.parse(arm.urdf_path).getroot()
    moving = [j for j in root.findall("joint") if j.get("type") != "fixed"]
    assert [j.get("name") for j in moving] == arm.joint_names
    transmitted = {t.find("joint").get("name") for t in root.findall("transmission")}
    assert transmitted == set(arm.joint_names)
    for joint, lim in zip(moving, arm.limits, strict=True):
        limit = joint.find("limit")
        assert float(limit.get("effort")) > 0
        if lim.lower is None:
            assert joint.get("type") == "continuous"
        else:
            assert float(limit.get("lower")) == lim.lower and float(limit.get("upper")) == lim.upper
    for i in range(1, arm.n + 1):
        link = root.find(f"link[@name='link{i}']")
        assert float(link.find("inertial/mass").get("value")) > 0
        assert link.findall("visual")


def test_plant_is_finalized_continuous_welded_and_actuated(arm_name):
    arm, plant, ctx = arm_and_plant(arm_name)
    assert plant.is_finalized()
    assert plant.time_step() == 0.0  # exact: a continuous plant's constant 0
    assert plant.num_positions() == plant.num_velocities() == plant.num_actuators() == arm.n
    # the base is welded with no offset: base_link's pose is the identity for any q
    plant.SetPositions(ctx, np.full(arm.n, 0.3))
    X = plant.EvalBodyPoseInWorld(ctx, plant.GetBodyByName("base_link")).GetAsMatrix4()
    np.testing.assert_array_equal(X, np.eye(4))  # exact: products of identity entries
    np.testing.assert_allclose(plant.gravity_field().gravity_vector(), arm.gravity)
    for name, lim in zip(arm.joint_names, arm.limits, strict=True):
        joint = plant.GetJointByName(name)
        lower, upper = joint.position_lower_limits()[0], joint.position_upper_limits()[0]
        assert (lower, upper) == ((-np.inf, np.inf) if lim.lower is None else (lim.lower, lim.upper))


def test_rr_moves_in_the_xy_plane():
    arm = get_arm("rr")
    fk = arm.forward(np.random.default_rng(1).uniform(-3, 3, (50, 2)))
    np.testing.assert_array_equal(fk.points["M"][:, 2], 0.0)  # exact: a planar arm's z
    np.testing.assert_array_equal(arm.table.rows[0].k, (0, 0, 1))  # exact: the axis as built


def test_parameters_are_the_papers_names_and_overridable():
    assert {"L1", "L2"} <= set(get_arm("rr").parameters)
    assert {"L1", "L2", "L3", "L4"} <= set(get_arm("rrrr").parameters)
    assert {"a2", "a3", "d2"} <= set(get_arm("arm4r").parameters)
    assert {f"l{i}" for i in range(1, 6)} <= set(get_arm("r2t").parameters)
    assert {f"r{i}" for i in range(1, 8)} | {f"theta{i}" for i in range(2, 8)} <= set(get_arm("urm6").parameters)
    longer = get_arm("rr", L1=0.5)
    assert longer.urdf_file is None and longer.urdf_key.startswith("sha256:")  # built in memory, no file
    with pytest.raises(ValueError, match="generated in memory"):
        longer.urdf_path  # noqa: B018
    np.testing.assert_allclose(longer.forward(np.zeros(2)).points["M"], [0.8, 0, 0])
    plant = longer.make_plant()
    ctx = plant.CreateDefaultContext()
    np.testing.assert_allclose(
        plant.CalcRelativeTransform(ctx, plant.world_frame(), plant.GetFrameByName("M")).translation(), [0.8, 0, 0]
    )


def test_arm4r_keeps_its_own_dh_table_with_its_overrides():
    """arm4r's forward runs on the DH table made once when the arm is built (not again at every call): with
    overrides it is the overridden table's, and the tool point is the plant's (its URDF made from the same table)."""
    from armlab.models.arm4r import Parameters, dh_table

    q = np.random.default_rng(4).uniform(-1.5, 1.5, (20, 4))
    default, other = get_arm("arm4r"), get_arm("arm4r", a2=0.7, a3=1.3, d2=0.1)
    table = other.forward_fn.keywords["table"]
    assert table == dh_table(Parameters(a2=0.7, a3=1.3, d2=0.1)) != default.forward_fn.keywords["table"]
    assert other.forward_fn.keywords["table"] is table  # the same object at every call: its steps made once
    np.testing.assert_allclose(other.forward(q).tool, table.frames(q)[:, -1], atol=1e-12)
    np.testing.assert_allclose(other.forward(np.zeros(4)).points["O4"], [2.0, 0.1, 0.0], atol=1e-12)
    plant = other.make_plant()
    ctx = plant.CreateDefaultContext()
    for row in q[:5]:
        plant.SetPositions(ctx, row)
        pose = plant.CalcRelativeTransform(ctx, plant.world_frame(), plant.GetFrameByName("O4")).GetAsMatrix4()
        np.testing.assert_allclose(other.forward(row).tool, pose, atol=1e-12)


def test_mass_properties_are_made_once_and_handed_out_as_copies():
    arm = get_arm("arm4r")
    mass, com, inertia = arm.mass_properties()
    mass[:], com[:], inertia[:] = 0.0, 0.0, 0.0  # a caller changing its arrays changes nothing of the arm's
    again = arm.mass_properties()
    np.testing.assert_allclose(again[0], [4.0, 3.0, 2.0, 0.5], rtol=1e-15)  # the parameters as given
    assert np.all(np.linalg.eigvalsh(again[2]) > 0)
    heavier = get_arm("arm4r", m4=1.5)
    np.testing.assert_allclose(heavier.mass_properties()[0], [4.0, 3.0, 2.0, 1.5], rtol=1e-15)


def test_chosen_values_are_marked():
    for name in ARMS:
        notes = get_arm(name).notes
        assert all(note.startswith(("paper:", "chosen, not from the paper:")) for note in notes.values()), name
    assert get_arm("arm4r").notes["a2"].startswith("chosen, not from the paper")
    assert get_arm("rr").notes["L1"].startswith("paper:")


@pytest.mark.parametrize("bad", [{"L9": 1.0}, {"L1": float("nan")}])
def test_bad_parameter_overrides(bad):
    with pytest.raises(ValueError, match=r"L9|nan"):
        get_arm("rr", **bad)


def test_unknown_arm():
    with pytest.raises(ValueError, match="unknown arm 'puma'"):
        get_arm("puma")


def test_models_readme_lists_every_parameter_and_its_source():
    from armlab.models.arm import MODELS_DIR

    readme = (MODELS_DIR / "README.md").read_text()
    for name in ARMS:
        arm = get_arm(name)
        for key, value in arm.parameters.items():
            assert f"| {key} | {value:.6g} | {arm.notes[key]} |" in readme, (name, key)


def test_models_readme_gives_every_drive_limit():
    """Each paper arm's section says its effort and velocity limits (chosen: the papers give none)."""
    from armlab.models.arm import MODELS_DIR

    sections = (MODELS_DIR / "README.md").read_text().split("\n## `")[1:]
    for name in ARMS:
        (section,) = [s for s in sections if s.startswith(f"{name}`")]
        (line,) = [s for s in section.splitlines() if s.startswith("Drive limits:")]
        assert "chosen, not from the paper" in line
        for lim in get_arm(name).limits:
            assert f"{lim.effort:g} N" in line and f"{lim.velocity:g} " in line, (name, lim, line)
