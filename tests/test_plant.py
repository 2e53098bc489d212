"""The one plant builder (armlab.models.plant): its options, the joint order rule, payload, drives, scene graph."""

from __future__ import annotations

import dataclasses
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest
from helpers import ARM_NAMES

from armlab.diagrams.simulate import SimulationOptions
from armlab.models import get_arm
from armlab.models.arm import Arm
from armlab.models.plant import PlantOptions, add_arm_plant, make_plant

ROOT = Path(__file__).resolve().parents[1]
#: The one module that makes a MultibodyPlant, adds one with a SceneGraph or parses a URDF.
BUILDER = ROOT / "models" / "plant.py"
#: Every folder pyproject.toml installs a package from.
SOURCE_DIRS = tuple(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-dir"].values())


def _two_link(transmissions: tuple[str, ...] = ()) -> str:
    """A planar two-link arm whose file declares the elbow before the shoulder, with ``<transmission>``s for
    ``transmissions`` in that order."""
    actuated = "".join(f'<transmission name="{j}_t"><type>transmission_interface/SimpleTransmission</type>'
                       f'<joint name="{j}"><hardwareInterface>EffortJointInterface</hardwareInterface></joint>'
                       f'<actuator name="{j}_motor"><mechanicalReduction>1</mechanicalReduction></actuator>'
                       "</transmission>" for j in transmissions)
    inertia = '<inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-2" iyz="0" izz="1e-2"/>'
    return f"""<robot name="two">
  <link name="base"/>
  <link name="upper"><inertial><origin xyz="0.2 0 0"/><mass value="1"/>{inertia}</inertial></link>
  <link name="fore"><inertial><origin xyz="0.15 0 0"/><mass value="0.5"/>{inertia}</inertial></link>
  <link name="hand"/>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.4 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="wrist" type="fixed"><parent link="fore"/><child link="hand"/><origin xyz="0.3 0 0"/></joint>
  {actuated}
</robot>
"""


def _user_arm(tmp_path: Path, transmissions: tuple[str, ...] = ()) -> Arm:
    path = tmp_path / "two.urdf"
    path.write_text(_two_link(transmissions))
    return get_arm(str(path))


# ------------------------------------------------------------------------------------------- the options
@pytest.mark.parametrize(("options", "message"), [
    ({"payload": -1}, "payload -1 is out of range: allowed 0 ≤ payload ≤ 1000 kg"),
    ({"payload": "heavy"}, "payload 'heavy' is not allowed: a payload is a mass, 0 ≤ payload ≤ 1000 kg"),
    ({"gravity": "up"}, "'up' is not a number .*; or one of default, off, \\+x"),
    ({"gravity": [1, 2]}, r"gravity \[1.0, 2.0\] is not allowed: give 3 finite numbers gx,gy,gz"),
    ({"gravity": (0, 0, 1e3)}, r"gravity 0,0,1000 \(\|g\| = 1000\) is out of range: allowed 0 ≤ \|g\| ≤ 100"),
    ({"time_step": -1e-3}, "time step = -0.001 s is not allowed: give 0 .* or a positive finite period"),
    ({"time_step": np.nan}, "time step = nan s is not allowed"),
])
def test_plant_options_are_checked_when_made(options, message):
    with pytest.raises(ValueError, match=message):
        PlantOptions(**options)


def test_plant_options_keep_the_resolved_values_and_are_frozen():
    rr = get_arm("rr")
    assert PlantOptions().gravity is None  # the arm's own
    assert PlantOptions("default").gravity is None
    # exact: constants and copies, no arithmetic that could round
    np.testing.assert_array_equal(PlantOptions().gravity_of(rr), [0, -9.81, 0])  # exact (see above)
    assert PlantOptions("off").gravity == (0.0, 0.0, 0.0)  # exact: constants and copies, no arithmetic that could round
    assert PlantOptions("+x").gravity == (9.81, 0.0, 0.0)  # exact: constants and copies, no arithmetic that could round
    # exact: constants and copies, no arithmetic that could round
    assert PlantOptions("1,2,-3.5").gravity == (1.0, 2.0, -3.5)  # exact (see above)
    assert PlantOptions(np.array([0.0, 0.0, -9.81])) == PlantOptions("-z")  # exact: -z is −G, the literal given
    assert PlantOptions(payload=2).payload == 2.0  # exact: constants and copies, no arithmetic that could round
    with pytest.raises(dataclasses.FrozenInstanceError):
        PlantOptions().payload = 1.0


@pytest.mark.parametrize(("options", "message"), [
    ({"mode": "open"}, "mode 'open' is not allowed; allowed: controller, inverse_dynamics"),
    ({"sampling": "sparse"}, "sampling 'sparse' is not allowed; allowed: dense, periodic"),
    ({"log_period": 0}, "log period = 0 s is not allowed: give a positive finite number of seconds"),
    ({"accuracy": 1.0}, "accuracy 1 is out of range: allowed 1e-12 ≤ accuracy ≤ 0.1"),
    ({"kp": -1.0}, "kp -1 is out of range: allowed 0 ≤ kp ≤ 1e6"),
    ({"kd": [1.0, 1e9]}, "kd 1e9 is out of range"),
    ({"ki": np.nan}, "ki"),
    ({"divergence_tolerance": 0}, "divergence tolerance = 0 is not allowed: give a positive finite tracking error"),
    ({"plant": PlantOptions(payload=1.0)}, r"a simulated plant is driven by its joint torques: give "
                                           r"PlantOptions\(ideal_drives=True"),
])
def test_simulation_options_are_checked_when_made(options, message):
    with pytest.raises(ValueError, match=message):
        SimulationOptions(**options)


def test_simulation_options_are_frozen_and_hold_immutable_gains():
    options = SimulationOptions(kp=np.array([100.0, 50.0]), kd=20)
    # exact: constants and copies, no arithmetic that could round
    assert options.kp == (100.0, 50.0) and options.kd == 20.0 and options.plant.ideal_drives  # exact (see above)
    assert hash(options) == hash(SimulationOptions(kp=(100, 50)))  # a value: usable as a key
    with pytest.raises(dataclasses.FrozenInstanceError):
        options.mode = "inverse_dynamics"


def test_the_api_checks_its_keywords_with_the_options_messages():
    import armlab

    arm = armlab.load("rr")
    motion = armlab.paper_motion(arm)
    for keywords, message in (({"payload": -1}, "payload -1 is out of range"), ({"mode": "open"}, "mode 'open'"),
                              ({"kp": -1}, "kp -1 is out of range"), ({"accuracy": 1}, "accuracy 1 is out of range"),
                              ({"divergence_tolerance": -1}, "divergence tolerance = -1 is not allowed")):
        with pytest.raises(ValueError, match=message):
            armlab.simulate(arm, motion, **keywords)


# ------------------------------------------------------------------------------------------- the plant
@pytest.mark.parametrize("name", ARM_NAMES)
def test_every_plant_is_in_the_arms_joint_order(name):
    arm = get_arm(name)
    plant = arm.make_plant()
    assert plant.num_positions() == plant.num_velocities() == arm.n
    joints = [plant.GetJointByName(j) for j in arm.joint_names]
    assert [j.position_start() for j in joints] == list(range(arm.n))
    assert [j.velocity_start() for j in joints] == list(range(arm.n))
    # exact: constants and copies, no arithmetic that could round
    np.testing.assert_array_equal(plant.gravity_field().gravity_vector(), arm.gravity)  # exact (see above)


def test_a_file_listing_its_joints_out_of_order_still_gives_the_chains_order(tmp_path):
    """The elbow is declared first; the plant (and the arm) follow the chain, base to tool."""
    arm = _user_arm(tmp_path)
    assert arm.joint_names == ["shoulder", "elbow"]
    plant = arm.make_plant(PlantOptions(ideal_drives=True))
    assert [plant.GetJointByName(j).position_start() for j in arm.joint_names] == [0, 1]
    # exact: constants and copies, no arithmetic that could round
    np.testing.assert_array_equal(plant.MakeActuationMatrix(), np.eye(2))  # exact (see above)


def test_a_plant_whose_order_differs_from_the_arms_is_refused(monkeypatch):
    """The joint order rule is checked in the builder, for every plant (here the arm claims the reverse order)."""
    arm = get_arm("rr")
    monkeypatch.setattr(Arm, "joint_names", property(lambda self: ["joint2", "joint1"]))
    with pytest.raises(ValueError, match=r"^rr: the plant's joint order differs from joint2, joint1$"):
        arm.make_plant()


def test_ideal_drives_need_one_actuator_per_joint_in_joint_order(tmp_path):
    """Transmissions declared elbow first: fine for kinematics, refused for a simulated plant."""
    arm = _user_arm(tmp_path, ("elbow", "shoulder"))
    plant = arm.make_plant()  # IK, errata: the actuators do not matter
    assert plant.num_actuators() == 2
    with pytest.raises(ValueError, match=r"two: every joint needs one actuator, in joint order \(shoulder, elbow\): "
                                         "declare the URDF's <transmission> elements in that order, or none"):
        arm.make_plant(PlantOptions(ideal_drives=True))
    in_order = _user_arm(tmp_path, ("shoulder", "elbow")).make_plant(PlantOptions(ideal_drives=True))
    # exact: constants and copies, no arithmetic that could round
    np.testing.assert_array_equal(in_order.MakeActuationMatrix(), np.eye(2))  # exact (see above)


def test_ideal_drives_lift_the_effort_limits_and_need_mass_data():
    from pydrake.multibody.tree import JointActuatorIndex

    arm = get_arm("r2t")
    limits = [lim.effort for lim in arm.limits]
    assert all(e is not None for e in limits)
    for options, expected in ((None, limits), (PlantOptions(ideal_drives=True), [np.inf] * arm.n)):
        plant = arm.make_plant(options)
        efforts = [plant.get_joint_actuator(JointActuatorIndex(i)).effort_limit() for i in range(arm.n)]
        np.testing.assert_array_equal(efforts, expected)  # exact: constants and copies, no arithmetic that could round
    kinematic = dataclasses.replace(arm, has_dynamics=False)
    assert kinematic.make_plant().num_positions() == arm.n
    with pytest.raises(ValueError, match=r"r2t is a kinematic arm .*: simulate needs mass data"):
        kinematic.make_plant(PlantOptions(ideal_drives=True))


def test_the_payload_is_a_point_mass_at_the_tool_point():
    from pydrake.multibody.tree import JacobianWrtVariable

    arm = get_arm("urm6")
    bare, loaded = arm.make_plant(), arm.make_plant(PlantOptions(payload=3.0))
    q = np.linspace(0.1, 0.6, arm.n)
    contexts = [p.CreateDefaultContext() for p in (bare, loaded)]
    for plant, context in zip((bare, loaded), contexts, strict=True):
        plant.SetPositions(context, q)
    # Drake sums the bodies' masses: the arm's links plus 3 kg (sums in a different order: 1e-12)
    np.testing.assert_allclose(loaded.CalcTotalMass(contexts[1]) - bare.CalcTotalMass(contexts[0]), 3.0, atol=1e-12)
    body = loaded.GetBodyByName("payload")
    tool = loaded.GetFrameByName(arm.tool_name).CalcPoseInWorld(contexts[1]).translation()
    np.testing.assert_allclose(body.EvalPoseInWorld(contexts[1]).translation(), tool, atol=1e-12)
    inertia = body.default_rotational_inertia().CopyToFullMatrix3()
    np.testing.assert_array_equal(inertia, np.zeros((3, 3)))  # exact: a point mass's zero inertia, no arithmetic
    # a point mass at the tool point adds m Jᵀ J to the mass matrix (two Drake computations: 1e-9 of its size)
    J = bare.CalcJacobianTranslationalVelocity(contexts[0], JacobianWrtVariable.kV, bare.GetFrameByName(arm.tool_name),
                                               np.zeros(3), bare.world_frame(), bare.world_frame())
    extra = loaded.CalcMassMatrix(contexts[1]) - bare.CalcMassMatrix(contexts[0])
    np.testing.assert_allclose(extra, 3.0 * J.T @ J, rtol=0, atol=1e-9 * np.abs(extra).max())


def test_options_set_gravity_and_the_time_step():
    arm = get_arm("arm4r")
    plant = arm.make_plant(PlantOptions(gravity="+x", time_step=1e-3))
    # exact: constants and copies, no arithmetic that could round
    np.testing.assert_array_equal(plant.gravity_field().gravity_vector(), [9.81, 0, 0])  # exact (see above)
    # exact: constants and copies, no arithmetic that could round
    assert plant.time_step() == 1e-3 and plant.num_discrete_state_groups() == 1  # exact: the period set; discrete
    assert arm.make_plant().time_step() == 0.0  # exact: constants and copies, no arithmetic that could round


def test_the_scene_graph_variant_registers_the_arms_geometry():
    from pydrake.systems.framework import DiagramBuilder

    arm = get_arm("rrrr")
    builder = DiagramBuilder()
    plant, scene_graph = add_arm_plant(builder, arm, PlantOptions(geometry=True))
    assert scene_graph is not None and plant.geometry_source_is_registered()
    for i in range(1, arm.n + 1):
        assert len(plant.GetVisualGeometriesForBody(plant.GetBodyByName(f"link{i}"))) >= 1
    builder.Build()  # the plant and scene graph are connected: the diagram builds
    builder = DiagramBuilder()
    plant, scene_graph = add_arm_plant(builder, arm)
    assert scene_graph is None and not plant.geometry_source_is_registered()
    with pytest.raises(ValueError, match=r"PlantOptions\(geometry=True\) needs a SceneGraph in a diagram"):
        make_plant(arm, PlantOptions(geometry=True))


def test_the_scene_poses_the_plant_in_the_arms_joint_order():
    """build_scene wires arm-ordered q straight to the plant: Drake's tool pose is the arm's forward kinematics."""
    from armlab.presentation.replay import build_scene, start_meshcat

    arm = get_arm("urm6")
    scene = build_scene(arm, start_meshcat())
    q = np.linspace(-0.5, 0.7, arm.n)
    scene.show(q)
    context = scene.plant.GetMyContextFromRoot(scene.context)
    pose = scene.plant.GetFrameByName(arm.tool_name).CalcPoseInWorld(context).GetAsMatrix4()
    np.testing.assert_allclose(pose, arm.forward(q).tool, atol=1e-12)  # Drake against the paper's equations


def test_only_the_builder_makes_plants_or_parses_urdfs():
    """No module but models/plant.py constructs a MultibodyPlant, calls AddMultibodyPlantSceneGraph or uses Drake's
    parser (the CLI's argparse ``Parser`` is another thing)."""
    pattern = re.compile(r"(?<!\w)(MultibodyPlant\(|AddMultibodyPlantSceneGraph|pydrake\.multibody\.parsing)")
    found = sorted(str(path.relative_to(ROOT)) for d in SOURCE_DIRS for path in (ROOT / d).rglob("*.py")
                   if pattern.search(path.read_text()))
    assert found == [str(BUILDER.relative_to(ROOT))]
