"""The one builder of the arm's Drake ``MultibodyPlant``: IK, errata, simulation, replay and viewer all use it.

:func:`add_arm_plant` adds the plant to a ``DiagramBuilder`` (with a ``SceneGraph`` when the options ask
for geometry, as Drake's ``AddMultibodyPlantSceneGraph``); :func:`make_plant` gives one outside a diagram.
Both go through the one function that parses the arm's URDF, welds its base to the world, gives every
joint an actuator, sets gravity, adds the payload and finalizes. What a plant holds beyond the bare arm
is said by a frozen :class:`PlantOptions`, validated when it is made:

* ``gravity`` — the arm's own (rr: −y, the vertical plane of paper 000's Adams model; the others −z),
  ``"off"``, a base axis or three numbers (:func:`resolve_gravity`);
* ``payload`` — a point mass (kg) welded to the tool frame, its centre of mass at the tool point: paper
  000's basket at the RR arm's tool (Fig. 26), paper 003's ~20 kg R2T payload. It is added before
  ``Finalize``, so the simulated plant and the controller's model of it are the same model;
* ``ideal_drives`` — the plant is driven by joint torques and simulated: effort limits off, one
  actuator per joint in joint order, a positive-definite mass matrix (checked);
* ``geometry`` — the arm's visual and collision geometry registered with a ``SceneGraph`` (Meshcat, the
  clearance queries of :mod:`armlab.collision`);
* ``scene`` — obstacles (:class:`armlab.collision.scene.Scene`) registered as collision geometry of the world
  (implies ``geometry``); the floor is not checked against joint 1's link, which turns on the stand on it;
* ``time_step`` — 0 (continuous, the default) or a discrete period (s).

The arm's drive train (``Arm.drives``, :mod:`armlab.drives.train`; ideal when it has none) is always in its
plant, whatever the options: each joint's rotor inertia and gear ratio on its Drake ``JointActuator`` (the
reflected inertia G²·J_m on the mass matrix's diagonal) and its viscous friction as the joint's damping (so a
drive file's value replaces the URDF's ``<dynamics damping>``). Its Coulomb friction is not a plant element:
the diagram applies it (:func:`armlab.controllers.inverse_dynamics.add_coulomb_friction`).

Joint order, one rule: the plant's generalized positions and velocities are in the arm's joint order
(joint1 … jointN, what the URDF's serial chain gives), checked once here, so every caller wires
arm-ordered vectors (q, q̇, sliders, trajectories) to the plant directly, with no index map.
"""

from __future__ import annotations

import logging
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.drives.train import DriveTrain
from armlab.files import native_call
from armlab.limits import check_positive
from armlab.values import check_payload, gravity_vector

if TYPE_CHECKING:
    from pydrake.geometry import SceneGraph
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.systems.framework import DiagramBuilder

    from armlab.collision.scene import Obstacle, Scene
    from armlab.models.arm import Arm

__all__ = ["PlantOptions", "add_arm_plant", "check_time_step", "default_context", "make_plant", "parse_model_file",
           "quiet_drake"]

def check_time_step(time_step: float) -> float:
    """A plant's time step (s) as a float; ``ValueError`` unless 0 (continuous) or a positive finite period."""
    if time_step == 0:
        return 0.0

    return check_positive(time_step, "time step", "s", "give 0 (a continuous plant) or a positive finite period")


@dataclass(frozen=True)
class PlantOptions:
    """What a plant of an arm holds beyond the bare arm; each field is checked once, when the options are made.

    ``gravity``: ``None`` (the arm's own), ``"off"``, ``"+x"`` … ``"-z"`` or (gx, gy, gz) m/s²; kept as
    the resolved ``(gx, gy, gz)`` tuple, or ``None`` (:func:`gravity_vector`). ``payload``: a point mass (kg)
    at the tool point (:func:`check_payload`). ``ideal_drives``: the plant is driven by joint torques and
    simulated: no actuator is clamped at its effort limit (a run shows the torque its motion takes, and
    passing a limit is reported by :func:`armlab.diagrams.drives.limit_violations`, never silently turned into
    a lagging arm), every joint has one actuator in joint order and the mass matrix is positive definite
    (checked; the arm needs mass data). ``geometry``: the arm's visual and collision geometry in a ``SceneGraph``
    (only in a diagram: :func:`add_arm_plant`). ``time_step``: 0 (continuous) or a discrete period (s).
    ``scene``: obstacles registered as the world's collision geometry (sets ``geometry``).

    The arm's drive train is not an option: it comes with the arm (``Arm.drives``, see the module docstring).
    What comes next (collision geometry, a payload with an inertia of its own) is one more field here, checked in
    ``__post_init__``, and one more step of the builder.
    """

    gravity: str | ArrayLike | None = None
    payload: float = 0.0
    ideal_drives: bool = False
    geometry: bool = False
    time_step: float = 0.0
    scene: Scene | None = None

    def __post_init__(self) -> None:
        if self.scene is not None:
            object.__setattr__(self, "geometry", True)
        g = gravity_vector(self.gravity)
        object.__setattr__(self, "gravity", None if g is None else tuple(float(v) for v in g))
        object.__setattr__(self, "payload", check_payload(self.payload))
        object.__setattr__(self, "time_step", check_time_step(self.time_step))

    def gravity_of(self, arm: Arm) -> NDArray[np.float64]:
        """The gravity vector (m/s², ``(3,)``) of ``arm``'s plant: the options' own, or the arm's."""
        return np.asarray(arm.gravity if self.gravity is None else self.gravity, dtype=float)


@contextmanager
def quiet_drake(below: int = logging.WARNING) -> Iterator[None]:
    """Silence Drake's log lines below ``below`` (default: INFO, e.g. "Meshcat listening for connections at …")
    inside the block."""
    logger = logging.getLogger("drake")
    level = logger.level
    logger.setLevel(below)
    try:
        yield
    finally:
        logger.setLevel(level)


@contextmanager
def drake_once() -> Iterator[None]:
    """Each distinct Drake log line at most once inside the block (a replay's two collision layers each say that
    Meshcat does not draw a scene's floor, a half space: one line says it)."""
    seen: set[str] = set()

    def first(record: logging.LogRecord) -> bool:
        text = record.getMessage()
        new = text not in seen
        seen.add(text)
        return new

    logger = logging.getLogger("drake")
    logger.addFilter(first)
    try:
        yield
    finally:
        logger.removeFilter(first)


def default_context(diagram: Any) -> Any:
    """``diagram.CreateDefaultContext()`` without Drake's warning that deformable contact ignores a scene's floor
    (a half space; armlab has no deformable bodies)."""
    with quiet_drake(logging.ERROR):
        return diagram.CreateDefaultContext()


def add_arm_plant(
    builder: DiagramBuilder, arm: Arm, options: PlantOptions | None = None
) -> tuple[MultibodyPlant, SceneGraph | None]:
    """Add ``arm``'s finalized plant to ``builder``; ``(plant, scene_graph)``, the scene graph ``None`` unless
    ``options.geometry`` (then both come from Drake's ``AddMultibodyPlantSceneGraph``, connected)."""
    from pydrake.multibody.plant import AddMultibodyPlantSceneGraph, MultibodyPlant

    options = PlantOptions() if options is None else options
    if options.geometry:
        plant, scene_graph = AddMultibodyPlantSceneGraph(builder, options.time_step)
    else:
        plant, scene_graph = builder.AddSystem(MultibodyPlant(options.time_step)), None
    floors = _build(plant, arm, options)
    if floors and scene_graph is not None:
        _floor_filter(plant, scene_graph, floors)
    return plant, scene_graph


def make_plant(arm: Arm, options: PlantOptions | None = None) -> MultibodyPlant:
    """``arm``'s finalized plant outside a diagram (for queries: kinematics, inverse dynamics, energies).

    ``ValueError`` for ``options.geometry``: a scene graph lives in a diagram (:func:`add_arm_plant`).
    """
    from pydrake.multibody.plant import MultibodyPlant

    options = PlantOptions() if options is None else options
    if options.geometry:
        raise ValueError("PlantOptions(geometry=True) needs a SceneGraph in a diagram: use add_arm_plant(builder, …)")
    plant = MultibodyPlant(options.time_step)
    _build(plant, arm, options)
    return plant


def _build(plant: MultibodyPlant, arm: Arm, options: PlantOptions) -> list[Any]:
    """Parse ``arm``'s URDF into the empty ``plant``, weld its base, add the actuators with the arm's drive train,
    gravity, the payload, the scene and the drives of ``options``, finalize, and check the joint order (and, for
    ideal drives, what simulation needs). Returns the geometry ids of the scene's floors (empty without a scene)."""
    from pydrake.multibody.tree import JointActuatorIndex, RotationalInertia, SpatialInertia

    if options.ideal_drives:
        arm.require_dynamics("simulate")
    instance = _add_model(plant, arm)
    _set_drive_train(plant, arm, instance)
    floors = [] if options.scene is None else _add_scene(plant, options.scene.obstacles)
    if options.payload > 0:
        body = plant.AddRigidBody("payload", instance, SpatialInertia.MakeFromCentralInertia(
            options.payload, np.zeros(3), RotationalInertia(0, 0, 0)))
        plant.WeldFrames(plant.GetFrameByName(arm.tool_name, instance), body.body_frame())
    plant.mutable_gravity_field().set_gravity_vector(options.gravity_of(arm))
    if options.ideal_drives:
        for index in range(plant.num_actuators()):  # the plant holds the arm alone
            plant.get_mutable_joint_actuator(JointActuatorIndex(index)).set_effort_limit(np.inf)
    plant.Finalize()
    order = [plant.GetJointByName(name, instance) for name in arm.joint_names]
    if [j.position_start() for j in order] != list(range(arm.n)) or [j.velocity_start() for j in order] != list(
        range(arm.n)
    ):
        raise ValueError(f"{arm.name}: the plant's joint order differs from {', '.join(arm.joint_names)}")
    if options.ideal_drives:
        _check_drivable(plant, arm)
    return floors


def _add_scene(plant: MultibodyPlant, obstacles: tuple[Obstacle, ...]) -> list[Any]:
    """Register each obstacle as collision geometry of the world body, named as in the scene file; the floors' ids."""
    from pydrake.geometry import Box, Cylinder, HalfSpace, ProximityProperties, Sphere
    from pydrake.math import RigidTransform

    shapes = {"box": Box, "cylinder": Cylinder, "sphere": Sphere, "floor": HalfSpace}
    floors = []
    for obstacle in obstacles:
        shape = shapes[obstacle.shape](*obstacle.size)
        geometry = plant.RegisterCollisionGeometry(plant.world_body(), RigidTransform(obstacle.pose), shape,
                                                   obstacle.name, ProximityProperties())
        if obstacle.shape == "floor":
            floors.append(geometry)
    return floors


def _floor_filter(plant: MultibodyPlant, scene_graph: SceneGraph, floors: list[Any]) -> None:
    """The floors are not checked against the bodies jointed to the world's (joint 1's link turns on the stand)."""
    from pydrake.geometry import CollisionFilterDeclaration, GeometrySet
    from pydrake.multibody.tree import JointIndex

    anchored = {body.index() for body in plant.GetBodiesWeldedTo(plant.world_body())}
    joints = (plant.get_joint(JointIndex(i)) for i in range(plant.num_joints()))
    on_stand = [j.child_body() for j in joints
                if j.parent_body().index() in anchored and j.child_body().index() not in anchored]
    geometries = [g for body in on_stand for g in plant.GetCollisionGeometriesForBody(body)]
    scene_graph.collision_filter_manager().Apply(
        CollisionFilterDeclaration().ExcludeBetween(GeometrySet(floors), GeometrySet(geometries)))


def _add_model(plant: MultibodyPlant, arm: Arm) -> Any:
    """Parse the URDF into ``plant``, weld its root link to the world (no offset); returns the model instance.

    A generated URDF is parsed from its text in memory (never through a file), and so is a user's URDF: its
    text as checked (:attr:`~armlab.models.arm.Arm.model_text`: meshes as ``file://`` URIs of the files found,
    ``package://`` ones through :func:`armlab.models.read_urdf.package_roots`). A root link named ``world``
    (the ROS convention) is Drake's world body itself: nothing to weld. A joint without a ``<transmission>``
    gets an actuator of its own. ``ValueError`` if Drake cannot load the URDF.
    """
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.tree import JointActuatorIndex

    parser = Parser(plant)
    parser.SetAutoRenaming(True)
    try:
        if arm.model_text is not None:
            (instance,) = parser.AddModelsFromString(arm.model_text, "urdf")
        elif arm.urdf_file is None:
            (instance,) = parser.AddModelsFromString(arm.urdf(), "urdf")
        else:
            (instance,) = parser.AddModels(file_name=str(arm.urdf_file))
    except RuntimeError as error:
        source = arm.urdf_file or f"{arm.name}'s generated URDF"
        raise ValueError(f"{source}: Drake cannot load it: {str(error).strip().splitlines()[0]}") from None
    if arm.base_link != "world":  # Drake's URDF parser makes a link named world the world body
        plant.WeldFrames(plant.world_frame(), plant.GetFrameByName(arm.base_link, instance))
    _add_hulls(plant, arm, instance)
    actuators = (plant.get_joint_actuator(JointActuatorIndex(i)) for i in range(plant.num_actuators()))
    actuated = {a.joint().name() for a in actuators if a.model_instance() == instance}
    for name in arm.joint_names:
        if name not in actuated:
            plant.AddJointActuator(f"{name}_actuator", plant.GetJointByName(name, instance))
    return instance


def _add_hulls(plant: MultibodyPlant, arm: Arm, instance: Any) -> None:
    """Register the arm's STL and COLLADA collision meshes (:attr:`~armlab.models.arm.Arm.collision_hulls`) as
    Drake ``Convex`` shapes of their vertices (Drake makes the hull) on their links, and an SDFormat or MJCF file's
    collision shapes (:attr:`~armlab.models.arm.Arm.collision_shapes`), before ``Finalize``; a plant without a
    scene graph has no geometry to add them to."""
    from pydrake.geometry import Box, Capsule, Convex, Cylinder, Ellipsoid, ProximityProperties, Sphere
    from pydrake.math import RigidTransform

    def body(link: str) -> Any:
        return (plant.world_body() if link == "world" and arm.base_link == "world"
                else plant.GetBodyByName(link, instance))

    if not plant.geometry_source_is_registered():
        return
    for hull in arm.collision_hulls:
        plant.RegisterCollisionGeometry(body(hull.link), RigidTransform(np.array(hull.pose)),
                                        Convex(np.asfortranarray(hull.points.T), hull.name), hull.name,
                                        ProximityProperties())
    for shape in arm.collision_shapes:
        made = (Convex(str(shape.file), np.array(shape.size)) if shape.kind == "convex" else
                {"box": Box, "sphere": Sphere, "cylinder": Cylinder, "capsule": Capsule,
                 "ellipsoid": Ellipsoid}[shape.kind](*shape.size))
        plant.RegisterCollisionGeometry(body(shape.link), RigidTransform(np.array(shape.pose)), made, shape.name,
                                        ProximityProperties())


def _set_drive_train(plant: MultibodyPlant, arm: Arm, instance: Any) -> None:
    """Give each joint of ``arm`` (in ``plant``'s model ``instance``, before ``Finalize``) its drive train's rotor
    inertia (kg·m²) and gear ratio on its actuator and its viscous friction (N·m·s/rad) as its damping; an arm
    without a drive train gets ideal drives (none of either, whatever its URDF says)."""
    from pydrake.multibody.tree import JointActuatorIndex

    train = DriveTrain.ideal(arm.n) if arm.drives is None else arm.drives
    actuators = (plant.get_mutable_joint_actuator(JointActuatorIndex(i)) for i in range(plant.num_actuators()))
    by_joint = {a.joint().name(): a for a in actuators if a.model_instance() == instance}
    for k, name in enumerate(arm.joint_names):
        by_joint[name].set_default_rotor_inertia(float(train.rotor_inertia[k]))
        by_joint[name].set_default_gear_ratio(float(train.gear_ratio[k]))
        plant.GetMutableJointByName(name, instance).set_default_damping_vector(train.viscous[k:k + 1])


def _check_drivable(plant: MultibodyPlant, arm: Arm) -> None:
    """``ValueError`` unless every joint has one actuator, in joint order, and the mass matrix is positive definite
    (at q = 0; else the simulation could not solve for the accelerations)."""
    if plant.num_actuators() != arm.n or not np.array_equal(plant.MakeActuationMatrix(), np.eye(arm.n)):
        raise ValueError(f"{arm.name}: every joint needs one actuator, in joint order ({', '.join(arm.joint_names)}): "
                         "declare the URDF's <transmission> elements in that order, or none")
    mass_matrix = plant.CalcMassMatrix(plant.CreateDefaultContext())
    eigenvalues = np.linalg.eigvalsh(mass_matrix)
    if np.any(eigenvalues <= 1e-12 * max(1.0, np.abs(mass_matrix).max())):
        diagonal = np.diag(mass_matrix)
        still = [name for name, m in zip(arm.joint_names, diagonal, strict=True) if m <= 1e-12]
        if not still and eigenvalues[0] > 1e-12:  # every joint moves mass, but on scales far apart
            heavy = arm.joint_names[int(np.argmax(diagonal))]
            raise ValueError(f"{arm.name}: the mass matrix is too ill-conditioned to simulate: its eigenvalues span "
                             f"{eigenvalues[0]:.3g} … {eigenvalues[-1]:.3g} (a ratio beyond 1e12; {heavy} moves by "
                             "far the most mass); check the link masses and inertias")
        raise ValueError(f"{arm.name}: the mass matrix is singular (joint(s) {', '.join(still) or 'together'} move "
                         "no mass or inertia): to simulate, every moving link needs an <inertial> with mass > 0 and "
                         "inertia")


def parse_model_file(path: Path, packages: dict[str, Path], scene_graph: Any = None) -> tuple[MultibodyPlant, Any]:
    """A user's SDFormat (``.sdf``) or MuJoCo MJCF (``.xml``) file parsed by Drake's own parser into a new plant,
    not finalized (:mod:`armlab.models.read_sdf` reads the arm out of it); ``(plant, model instance)``.

    ``packages``: ``{name: package folder}`` for ``package://`` URIs (:func:`armlab.models.read_urdf.package_roots`).
    ``scene_graph``: a ``SceneGraph`` the plant registers its geometry with (the file's collision shapes), or none.
    ``ValueError`` (one line) if Drake cannot load the file or it holds more than one model.
    """
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    plant = MultibodyPlant(0.0)
    if scene_graph is not None:
        plant.RegisterAsSourceForSceneGraph(scene_graph)
    parser = Parser(plant)
    for name, folder in packages.items():
        if not parser.package_map().Contains(name):
            parser.package_map().Add(name, str(folder))
    try:
        with native_call():  # a stop signal ends the process even if Drake's parser never returns
            instances = parser.AddModels(file_name=str(path))
    except RuntimeError as error:
        raise ValueError(f"{path}: Drake cannot load it: {str(error).strip().splitlines()[0]}") from None
    if len(instances) != 1:
        raise ValueError(f"{path} holds {len(instances)} models: armlab takes one serial arm per file")
    return plant, instances[0]
