"""Users' arms from SDFormat (``.sdf``) and MuJoCo MJCF (``.xml``) files, read by Drake's own parser.

The file is checked first as a URDF is (:mod:`armlab.models.read_urdf`): UTF-8 text of bounded size, no
document-type or entity definitions, every number finite, and every file it names (an SDFormat ``<uri>``, an
MJCF ``file=`` of a mesh, texture, height field or ``<include>``, below the ``<compiler>``'s ``meshdir``,
``texturedir`` or ``assetdir``) inside its folder or its ROS packages (:func:`~armlab.models.read_urdf.package_roots`,
``package://`` and ``model://``), and existing. Then Drake's parser loads it
(:func:`armlab.models.plant.parse_model_file`) and the arm is read out of Drake's plant:

* one model; its joints revolute, prismatic or fixed (welds): a floating base (MJCF's ``<freejoint/>`` or
  ``type="free"``, found in the file: Drake leaves such a body free, with no joint), ball,
  planar or universal joint is refused, as in a URDF; one root body, welded to the world where the file leaves
  it free (as a URDF's root link) or attached to the world by the file's own joint; no body branching into two
  moving chains; at most :data:`~armlab.arm_file.MAX_JOINTS` moving joints; a closed loop is refused by
  Drake (its one-line error);
* link frame {i} is joint i's frame at q = 0 and row i of the matrix of nominal geometry is its pose in {i−1},
  with the joint's axis: the arm's URDF (:meth:`armlab.models.arm.Arm.urdf`, drawn visuals, not the file's
  meshes) has the file's kinematics;
* link i's body is the joint's child with every body welded to it, their spatial inertia combined by Drake
  (``CalcSpatialInertia``) about {i}, checked physical (:func:`~armlab.models.write_urdf.check_inertia`) and
  its centre of mass within reach of the arm (:func:`~armlab.arm_file.check_com_distance`);
* limits from the joints (infinite: none), effort limits from their actuators (MJCF ``<motor ctrlrange>``);
* the tool frame: ``tool`` (a body or frame of the file on the last moving link or welded to it), else the
  last body reached from the last moving link through welds (the first declared at each step).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from armlab.arm_file import MAX_JOINTS
from armlab.kinematics.locating import JointRow, LocatingTable
from armlab.models.arm import Arm
from armlab.models.meshes import Shape, check_references, listed
from armlab.models.read_urdf import check_com_distances, package_roots, read_xml
from armlab.models.write_urdf import Body, JointLimits, Point, check_inertia

__all__ = ["FORMATS", "from_model_file"]

#: The formats by file suffix: (the format's name, its root element).
FORMATS = {".sdf": ("SDFormat", "sdf"), ".xml": ("MJCF", "mujoco")}
#: The most files one SDFormat or MJCF file may ``<include>``, all levels together, and how deep includes may nest
#: (a file that includes itself, or one that includes it, is refused whatever the count).
MAX_INCLUDES = 64
MAX_INCLUDE_DEPTH = 8
_ALLOWED_JOINTS = ("revolute", "prismatic", "weld")


def _references(root: ET.Element, suffix: str) -> list[str]:
    """The files an SDFormat (``<uri>``) or MJCF (``file=``, below the compiler's folders) file names."""
    if suffix == ".sdf":
        return [uri.text.strip().replace("model://", "package://", 1) for uri in root.iter("uri")
                if uri.text and uri.text.strip()]
    compiler = root.find("compiler")
    folders = {} if compiler is None else compiler.attrib
    out = []
    for element in root.iter():
        name = element.get("file")
        if name is None:
            continue
        folder = {"mesh": "meshdir", "texture": "texturedir", "hfield": "assetdir", "skin": "assetdir"}.get(
            element.tag)
        prefix = folders.get(folder or "", folders.get("assetdir", "")) if folder else ""
        out.append(f"{prefix.rstrip('/')}/{name}" if prefix else name)
    return out


def _check_files(path: Path, root: ET.Element, packages: dict[str, Path]) -> None:
    """``ValueError`` unless every file ``path`` (``root`` parsed) names, and every file the files it include
    name, recursively, lies inside its folder or its ``packages`` (:func:`~armlab.models.meshes.check_references`):
    each included file read as the file itself is (:func:`~armlab.models.read_urdf.read_xml`), before Drake parses
    anything; a file included by itself or by one it includes (Drake's parsers recurse without end), more than
    :data:`MAX_INCLUDES` included files or nesting deeper than :data:`MAX_INCLUDE_DEPTH` are refused. An SDFormat
    file's ``<uri>`` is relative to the file naming it, its includes ``.sdf`` files; an MJCF ``<include file=>`` is
    replaced in ``root`` by the included file's elements (as MuJoCo does), whose files are then relative to
    ``path``'s folder and its ``<compiler>``'s."""
    suffix = path.suffix.lower()
    kind, tag = FORMATS[suffix]
    count = 0

    def visit(file: Path, tree: ET.Element, chain: tuple[Path, ...]) -> None:
        nonlocal count
        for parent in list(tree.iter()):
            for include in [child for child in parent if child.tag == "include"]:
                name = ((include.get("file") if tag == "mujoco" else include.findtext("uri")) or "").strip()
                what = f"{file}: <include> {name!r}"
                if not name:
                    raise ValueError(f"{file}: an <include> names no file")
                if tag == "sdf":
                    name = name.replace("model://", "package://", 1)
                base = path if tag == "mujoco" else file
                (target,) = check_references(path, [name], packages, base=base)
                typed = target if name.startswith("package://") else base.parent / name  # for messages
                if target.resolve() in chain:
                    itself = "itself" if target.resolve() == chain[-1] else f"{target.name}, which includes it"
                    raise ValueError(f"{what} includes {itself}: recursive includes are not allowed")
                if tag == "sdf" and target.suffix.lower() != ".sdf":
                    raise ValueError(f"{what}: an SDFormat <include> names an SDFormat file (.sdf)")
                count += 1
                if count > MAX_INCLUDES or len(chain) > MAX_INCLUDE_DEPTH:
                    raise ValueError(f"{what}: more than {MAX_INCLUDES} included files or includes nested more than "
                                     f"{MAX_INCLUDE_DEPTH} deep are not allowed")
                included = read_xml(typed, f"{kind} file")
                if included.tag != tag:
                    raise ValueError(f"{what}: its root element is <{included.tag}>, an {kind} file needs <{tag}>")
                visit(typed, included, (*chain, target.resolve()))
                if tag == "mujoco":  # the include's place takes the included file's elements
                    at = list(parent).index(include)
                    parent.remove(include)
                    for k, child in enumerate(included):
                        parent.insert(at + k, child)
        if tag == "sdf":
            check_references(path, _references(tree, suffix), packages, base=file)

    visit(path, root, (path.resolve(),))
    if tag == "mujoco":
        check_references(path, _references(root, suffix), packages)


def _shapes(plant: Any, inspector: Any, context: Any, groups: list[tuple[str, list[Any], Any]]) -> tuple[Shape, ...]:
    """The collision shapes of each link's bodies (``groups``: the link's name in the arm's URDF, its bodies, its
    frame's pose in the world at q = 0, 4×4), in the link's frame: boxes, spheres, cylinders, capsules, ellipsoids
    and the convex hulls of meshes read from files (another shape, such as a half space on a body, left out)."""
    from pydrake.geometry import Box, Capsule, Convex, Cylinder, Ellipsoid, Mesh, Sphere

    out: list[Shape] = []
    for name, bodies, X_WL in groups:
        for index in bodies:
            body = plant.get_body(index)
            X_WB = plant.EvalBodyPoseInWorld(context, body).GetAsMatrix4()
            for geometry in plant.GetCollisionGeometriesForBody(body):
                shape = inspector.GetShape(geometry)
                size: tuple[float, ...]
                file = None
                if isinstance(shape, Box):
                    kind, size = "box", (shape.width(), shape.depth(), shape.height())
                elif isinstance(shape, Sphere):
                    kind, size = "sphere", (shape.radius(),)
                elif isinstance(shape, Cylinder | Capsule):
                    kind, size = type(shape).__name__.lower(), (shape.radius(), shape.length())
                elif isinstance(shape, Ellipsoid):
                    kind, size = "ellipsoid", (shape.a(), shape.b(), shape.c())
                elif isinstance(shape, Convex | Mesh) and shape.source().is_path():
                    kind, size, file = "convex", tuple(map(float, shape.scale3())), str(shape.source().path())
                else:
                    continue
                pose = np.linalg.solve(X_WL, X_WB @ inspector.GetPoseInFrame(geometry).GetAsMatrix4())
                out.append(Shape(name, tuple(map(tuple, pose.tolist())), kind, tuple(map(float, size)),
                                 f"{name}_{inspector.GetName(geometry).rpartition('::')[2]}_{len(out) + 1}", file))
    return tuple(out)


def _group(joints_below: dict[Any, list[Any]], body: Any) -> list[Any]:
    """``body`` and every body welded to it below, not past a moving joint."""
    out, stack = [], [body]
    while stack:
        index = stack.pop()
        out.append(index)
        stack.extend(j.child_body().index() for j in joints_below.get(index, []) if j.type_name() == "weld")
    return out


def from_model_file(path: str | Path, tool: str | None = None, package_paths: Sequence[str | Path] = ()) -> Arm:
    """An arm from a user's SDFormat or MJCF file of one serial chain (module docstring); ``ValueError`` naming
    what is wrong."""
    from pydrake.geometry import SceneGraph
    from pydrake.multibody.tree import JointActuatorIndex

    # lazy: the arm readers sit below armlab.diagrams (its plant module imports armlab.models.arm's package)
    from armlab.models.plant import parse_model_file

    path = Path(path)
    kind, tag = FORMATS[path.suffix.lower()]
    root = read_xml(path, f"{kind} file")
    if root.tag != tag:
        raise ValueError(f"{path}: the root element is <{root.tag}>, an {kind} file ({path.suffix}) needs <{tag}>")
    packages = package_roots(path, package_paths)
    _check_files(path, root, packages)  # MJCF: its includes expanded into ``root``
    if tag == "sdf" and len(models := root.findall("model") + root.findall("world/model")) != 1:
        raise ValueError(f"{path} holds {len(models)} models: armlab takes one serial arm per file")
    free = [repr(element.get("name")) if element.get("name") else f"of body {body.get('name')!r}"
            for body in root.iter("body") for element in body
            if element.tag == "freejoint" or (element.tag == "joint" and element.get("type") == "free")]
    if free:  # Drake leaves such a body free, with no joint to see
        raise ValueError(f"{path}: joint {free[0]} is a free joint (a floating base: armlab's arms stand on their "
                         "base); allowed: hinge, slide and fixed")
    scene_graph = SceneGraph()
    plant, instance = parse_model_file(path, packages, scene_graph)

    joints = [plant.get_joint(index) for index in plant.GetJointIndices(instance)]
    for joint in joints:
        if joint.type_name() not in _ALLOWED_JOINTS:
            floating = (" (a floating base: armlab's arms stand on their base)" if "floating" in joint.type_name()
                        else "")
            raise ValueError(f"{path}: joint {joint.name()!r} is a {joint.type_name()} joint{floating}; allowed: "
                             "revolute, prismatic and fixed")
    moving_count = sum(joint.type_name() != "weld" for joint in joints)
    if moving_count > MAX_JOINTS:
        raise ValueError(f"{path}: {moving_count} movable joints: armlab takes arms of at most {MAX_JOINTS} joints")
    world = plant.world_body().index()
    children = {joint.child_body().index() for joint in joints}
    roots = [plant.get_body(index) for index in plant.GetBodyIndices(instance) if index not in children]
    on_world = any(joint.parent_body().index() == world for joint in joints)
    if len(roots) + on_world != 1:
        names = [body.name() for body in roots] + (["world"] if on_world else [])
        raise ValueError(f"{path}: a serial arm has one root body, found {len(names)}: {listed(names)}")
    if roots:
        plant.WeldFrames(plant.world_frame(), roots[0].body_frame())  # as a URDF's root link: the base
    try:
        plant.Finalize()
    except RuntimeError as error:
        raise ValueError(f"{path}: Drake cannot build it: {str(error).strip().splitlines()[0]}") from None
    context = plant.CreateDefaultContext()
    plant.SetPositions(context, np.zeros(plant.num_positions()))
    below: dict[Any, list[Any]] = {}  # BodyIndex → the joints whose parent it is
    for joint in joints:
        below.setdefault(joint.parent_body().index(), []).append(joint)
    moving_below: dict[Any, bool] = {}

    def moves(body: Any) -> bool:  # a movable joint lies below ``body`` (memoised; the tree is finite)
        if body not in moving_below:
            moving_below[body] = any(j.type_name() != "weld" or moves(j.child_body().index())
                                     for j in below.get(body, []))
        return moving_below[body]

    actuated = {}
    for index in range(plant.num_actuators()):
        actuator = plant.get_joint_actuator(JointActuatorIndex(index))
        actuated[actuator.joint().name()] = actuator.effort_limit()
    rows: list[JointRow] = []
    limits: list[JointLimits] = []
    bodies: list[Body] = []
    link = roots[0].index() if roots else world
    frame = np.eye(4) if not roots else roots[0].body_frame().CalcPoseInWorld(context).GetAsMatrix4()
    groups = [] if not roots else [("base_link", _group(below, link), frame)]  # each link's bodies, its frame
    last_group: list[Any] = []
    while True:
        moving = [j for j in below.get(link, []) if j.type_name() != "weld" or moves(j.child_body().index())]
        if len(moving) > 1:
            raise ValueError(f"{path}: body {plant.get_body(link).name()!r} branches into {len(moving)} moving "
                             "chains; armlab takes serial arms")
        if not moving:
            break
        joint = moving[0]
        link = joint.child_body().index()
        if joint.type_name() == "weld":
            continue
        X = joint.frame_on_parent().CalcPoseInWorld(context).GetAsMatrix4()  # = the child's frame M at q = 0
        T = np.linalg.solve(frame, X)
        revolute = joint.type_name() == "revolute"
        axis = joint.revolute_axis() if revolute else joint.translation_axis()
        rows.append(JointRow(joint.name(), "R" if revolute else "T", tuple(T[:3, 3]), tuple(axis),
                             tuple(map(tuple, T[:3, :3]))))
        limits.append(_limits(joint, actuated.get(joint.name())))
        last_group = _group(below, link)
        groups.append((f"link{len(rows)}", last_group, X))
        inertia = plant.CalcSpatialInertia(context, joint.frame_on_child(), last_group)
        bodies.append(_body(inertia, f"{path}: link {plant.get_body(link).name()!r}"))
        frame = X
    if not rows:
        raise ValueError(f"{path}: the {kind} file has no movable joint")
    tool_frame = _tool(plant, instance, tool, below, link, last_group, path)
    table = LocatingTable(tuple(rows), tool=np.linalg.solve(frame, tool_frame.CalcPoseInWorld(context).GetAsMatrix4()))
    names = [f"link{i}" for i in range(1, len(rows) + 1)]
    check_com_distances(path, table, bodies, limits, names)
    n = len(rows)
    tool_name = tool_frame.name()
    return Arm(
        name=plant.GetModelInstanceName(instance) or path.stem,
        paper=f"user {kind} file {path}",
        parameters={},
        notes={},
        table=table,
        bodies=tuple(bodies),
        limits=tuple(limits),
        points=(Point(tool_name, n + 1, (0.0, 0.0, 0.0)),),
        tool_name=tool_name,
        gravity=(0.0, 0.0, -9.81),
        has_dynamics=any(body.mass > 0 for body in bodies),
        tool_source="chosen (tool=, --tool)" if tool is not None else "the last body welded past the last joint",
        collision_shapes=_shapes(plant, scene_graph.model_inspector(), context, groups),
    )


def _limits(joint: Any, effort: float | None) -> JointLimits:
    """A Drake joint's position and velocity limits and its actuator's effort limit (infinite: none)."""
    def finite(value: float) -> float | None:
        return float(value) if np.isfinite(value) else None

    lower, upper = finite(joint.position_lower_limits()[0]), finite(joint.position_upper_limits()[0])
    if (lower is None) != (upper is None):  # one-sided: armlab's joints are limited both ways or not at all
        lower, upper = None, None
    return JointLimits(lower, upper, None if effort is None else finite(effort),
                       finite(joint.velocity_upper_limits()[0]))


def _body(inertia: Any, what: str) -> Body:
    """Drake's spatial inertia about {i} (expressed in {i}) as a :class:`Body`, checked physical."""
    mass = float(inertia.get_mass())
    if mass == 0:
        return Body(0.0, 0.03)
    com = np.asarray(inertia.get_com())
    central = inertia.Shift(com).CalcRotationalInertia().CopyToFullMatrix3()
    check_inertia(mass, central, what)
    return Body(mass, 0.03, com=(float(com[0]), float(com[1]), float(com[2])), inertia=tuple(map(tuple, central)))


def _tool(plant: Any, instance: Any, tool: str | None, below: dict[Any, list[Any]], link: Any, group: list[Any],
          path: Path) -> Any:
    """The tool frame: ``tool`` (a frame or body of the model on the last link's welded group), else the last body
    reached from the last moving link through welds (the first declared at each step)."""
    if tool is None:
        while welds := [j for j in below.get(link, []) if j.type_name() == "weld"]:
            link = welds[0].child_body().index()
        return plant.get_body(link).body_frame()
    if not plant.HasFrameNamed(tool, instance):
        raise ValueError(f"{path}: tool frame {tool!r} is not a frame or body of the model")
    frame = plant.GetFrameByName(tool, instance)
    if frame.body().index() not in group:
        allowed = ", ".join(plant.get_body(index).name() for index in group)
        raise ValueError(f"{path}: tool frame {tool!r} is not on the last moving link; allowed: frames of {allowed}")
    return frame
