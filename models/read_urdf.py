"""Users' own arms from a URDF file of one serial chain, as they come from ROS and robot vendors.

A **URDF file** must describe one serial chain (fixed joints are folded into the next joint's
origin; fixed side branches become named points; links rigidly attached through fixed joints are
one body); its root link is the base frame (a root link named ``world``, the ROS convention, is
Drake's world itself) and the tool is the link ``tool`` names (``--tool LINK``, ``load(…, tool=)``:
the last moving link or a link welded to it), else the end of the chain (past the last joint, the
first fixed child declared). ``package://NAME/…`` meshes are found through :func:`package_roots`: the
URDF's folder and the two above it, the folders ``package_paths`` names (``--package-path``) and
``ROS_PACKAGE_PATH``, or by a folder of that name there. A collision mesh is its convex hull (STL and
COLLADA ones read by armlab, :attr:`~armlab.models.arm.Arm.collision_hulls`); a mesh that cannot be found, or a
collision mesh with no hull, is left out with a warning (:mod:`armlab.models.meshes`). ``<mimic>`` on a fixed
joint does nothing and is ignored.
Refused with a one-line ``ValueError``: XML document-type or entity definitions (outside comments),
an empty ``<robot>``, an unexpanded xacro file, joint cycles, mimic on a moving joint, floating and
planar joints, reversed limits, a non-physical inertia or a centre of mass far beyond the arm
(:func:`~armlab.arm_file.check_com_distance`), non-finite numbers, more than
:data:`~armlab.arm_file.MAX_JOINTS` joints, and mesh files (and the files a mesh pulls in)
outside the URDF's folder and its ROS packages.

The arm's drive train (``Arm.drives``) is what the URDF says of it, as Drake reads it: each joint's
``<dynamics damping= friction=>`` (viscous B, N·m·s/rad, and Coulomb T_c, N·m, joint side) and the rotor
inertia and gear ratio of its ``<transmission>``'s ``<actuator>`` (``<drake:rotor_inertia value=>``,
``<drake:gear_ratio value=>``); ``None`` (ideal drives) if it says none of them.
"""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from armlab.arm_file import MAX_JOINTS, check_com_distance, file_number, read_text
from armlab.drives.train import DriveTrain
from armlab.kinematics.basic_movements import T_Z4, T_Z5, T_Z6
from armlab.kinematics.locating import JointRow, LocatingTable, homogeneous
from armlab.models.arm import Arm
from armlab.models.meshes import Hull, Meshes, check_meshes, listed, parse_xml
from armlab.models.write_urdf import DRAKE_NAMESPACE, Body, JointLimits, Point, check_inertia

__all__ = ["check_com_distances", "check_numbers", "from_urdf", "package_roots", "read_xml"]

#: The namespaces of xacro, the macro language ROS URDFs are often written in (expanded by ``xacro``).
_XACRO = ("{http://www.ros.org/wiki/xacro}", "{http://ros.org/wiki/xacro}", "{http://wiki.ros.org/xacro}")
#: How deep below a ``--package-path`` / ``ROS_PACKAGE_PATH`` folder packages are looked for (as ``rospack``).
_PACKAGE_DEPTH = 4

_TEXT_ATTRIBUTES = {"name", "filename", "link", "joint", "type", "version", "reference", "xmlns"}
_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed")
# the URDF handed to Drake (Arm.model_text, :func:`_drake_text`) is written back by ElementTree: its Drake tags (a
# URDF may use them undeclared) keep the prefix Drake's parser looks for (``drake:gear_ratio``, not ``ns0:gear_ratio``)
ET.register_namespace("drake", DRAKE_NAMESPACE)


def _vector(text: str | None, what: str, default: str) -> np.ndarray:
    parts = (text if text is not None else default).split()
    if len(parts) != 3:
        raise ValueError(f"{what} = {text!r} must be three numbers")
    return np.array([file_number(p, what) for p in parts])


def _pose(element: ET.Element | None, what: str) -> np.ndarray:
    """The ``<origin>`` child of ``element`` as a 4×4 matrix (rpy: R = Rz(y)·Ry(p)·Rx(r))."""
    origin = None if element is None else element.find("origin")
    xyz = _vector(None if origin is None else origin.get("xyz"), f"{what} origin xyz", "0 0 0")
    rpy = _vector(None if origin is None else origin.get("rpy"), f"{what} origin rpy", "0 0 0")
    return homogeneous((T_Z6(rpy[2]) @ T_Z5(rpy[1]) @ T_Z4(rpy[0]))[:3, :3], xyz)


def _xml(path: Path, what: str) -> ET.Element:
    """The root element of an XML file; entity and document-type definitions (entity expansion) are refused."""
    text = read_text(path, what)
    if "drake:" in text and "xmlns:drake" not in text:  # Drake's own tags, their namespace undeclared as Drake allows
        text = re.sub(r"<robot\b", f'<robot xmlns:drake="{DRAKE_NAMESPACE}"', text, count=1)
    try:
        return parse_xml(text, f"{path} ({what})")
    except ET.ParseError as error:
        raise ValueError(f"{path} is not valid XML: {error}") from None


def _parse_urdf(path: Path) -> ET.Element:
    """The URDF's root element (:func:`_xml`), with every number in it finite."""
    root = _xml(path, "URDF")
    if root.tag != "robot":
        raise ValueError(f"{path}: the root element is <{root.tag}>, a URDF needs <robot>")
    if any(element.tag.startswith(_XACRO) for element in root.iter()) or any(
            "${" in value or "$(" in value for element in root.iter() for value in element.attrib.values()):
        raise ValueError(f"{path} is an unexpanded xacro file (<xacro:…> elements or ${{…}}/$(…) expressions): "
                         "expand it first, e.g. 'xacro FILE.urdf.xacro > FILE.urdf'")
    if root.find("link") is None:
        raise ValueError(f"{path}: the <robot> has no <link> elements: an empty URDF (a URDF names its links and "
                         "the joints between them)")
    check_numbers(path, root)
    return root


def check_numbers(path: Path, root: ET.Element) -> None:
    """``ValueError`` naming the element unless every number in the XML file ``path`` (``root`` parsed), not only
    the ones armlab reads itself, is finite (Drake's parser reads the rest)."""
    for element in root.iter():
        texts = [(f"{key}={value!r}", value) for key, value in element.attrib.items() if key not in _TEXT_ATTRIBUTES]
        for where, value in texts + [("text", element.text or "")]:
            for token in value.split():
                try:
                    number = float(token)
                except ValueError:
                    continue
                if not np.isfinite(number):
                    raise ValueError(f"{path}: <{element.tag}> {where if where != 'text' else repr(value.strip())} "
                                     "has a value that is not a finite number")


def read_xml(path: Path, what: str) -> ET.Element:
    """The root element of a user's XML file ``path`` (a ``what``): bounded UTF-8 text, no document-type or
    entity definitions, every number finite."""
    root = _xml(path, what)
    check_numbers(path, root)
    return root


def _named(path: Path, elements: list[ET.Element], what: str) -> dict[str, ET.Element]:
    """``elements`` by their ``name``; a missing or repeated name is an error."""
    out: dict[str, ET.Element] = {}
    for element in elements:
        name = element.get("name")
        if not name:
            raise ValueError(f"{path}: a <{what}> has no name")
        if name in out:
            raise ValueError(f"{path}: two <{what}> elements are named {name!r}")
        out[name] = element
    return out


@dataclass(frozen=True)
class _Joint:
    """A ``<joint>`` element checked by :func:`_tree`: its name, type and the link it moves."""

    element: ET.Element
    name: str
    kind: str
    child: str


def _tree(path: Path, links: dict[str, ET.Element],
          joints: dict[str, ET.Element]) -> tuple[str, dict[str, list[_Joint]]]:
    """The root link and each link's child joints; a URDF whose joints are not one tree is an error."""
    children: dict[str, list[_Joint]] = {name: [] for name in links}
    parent_of: dict[str, str] = {}
    for name, joint in joints.items():
        kind = joint.get("type")
        if kind not in _JOINT_TYPES:
            raise ValueError(f"{path}: joint {name!r} has type {kind!r}; allowed: {', '.join(_JOINT_TYPES)}")
        mimic = joint.find("mimic")
        if mimic is not None and kind != "fixed":  # on a fixed joint it does nothing
            raise ValueError(f"{path}: joint {name!r} mimics joint {mimic.get('joint')!r}: mimic "
                             "joints are not supported (each joint of an armlab arm moves independently)")
        parent, child = joint.find("parent"), joint.find("child")
        parent_link = None if parent is None else parent.get("link")
        child_link = None if child is None else child.get("link")
        if parent_link is None or child_link is None or parent_link not in links or child_link not in links:
            raise ValueError(f"{path}: joint {name!r} needs a <parent> and <child> naming links")
        if child_link in parent_of:
            raise ValueError(f"{path}: link {child_link!r} is the child of joints "
                             f"{parent_of[child_link]!r} and {name!r}: a URDF's joints form a tree")
        parent_of[child_link] = name
        children[parent_link].append(_Joint(joint, name, kind, child_link))
    roots = [name for name in links if name not in parent_of]
    if len(roots) != 1:
        if not roots:
            raise ValueError(f"{path}: the joints form a cycle: every link has a parent, so there is no root link")
        raise ValueError(f"{path}: a serial arm has one root link, found {len(roots)}: {listed(roots)}")
    reached, stack = {roots[0]}, [roots[0]]
    while stack:
        for below in children[stack.pop()]:
            reached.add(below.child)
            stack.append(below.child)
    if len(reached) != len(links):
        cycle = sorted(set(links) - reached)
        raise ValueError(f"{path}: the joints form a cycle through link(s) {listed(cycle, 5)}, "
                         f"not connected to the root link {roots[0]!r}")
    return roots[0], children


def _moving_below(root: str, children: dict[str, list[_Joint]]) -> dict[str, bool]:
    """For each link: does a movable joint lie below it (iteratively: chains may be long)?"""
    order, stack = [], [root]
    while stack:
        link = stack.pop()
        order.append(link)
        stack.extend(j.child for j in children[link])
    below: dict[str, bool] = {}
    for link in reversed(order):
        below[link] = any(j.kind != "fixed" or below[j.child] for j in children[link])
    return below


def _link_inertial(path: Path, link: ET.Element) -> tuple[float, NDArray, NDArray]:
    """A URDF link's ``(mass, com, inertia about the com)`` in the link's frame; checked to be physical."""
    name = link.get("name")
    inertial = link.find("inertial")
    if inertial is None:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    what = f"{path}: link {name!r}"
    mass_element = inertial.find("mass")
    mass = 0.0 if mass_element is None else file_number(mass_element.get("value"), f"{what} mass")
    if mass < 0:
        raise ValueError(f"{what} mass = {mass:g} kg is not allowed: a mass is ≥ 0 kg")
    element = inertial.find("inertia")
    values = {k: 0.0 if element is None else file_number(element.get(k, "0"), f"{what} inertia {k}")
              for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    inertia = np.array([[values["ixx"], values["ixy"], values["ixz"]], [values["ixy"], values["iyy"], values["iyz"]],
                        [values["ixz"], values["iyz"], values["izz"]]])
    check_inertia(mass, inertia, what)
    X = _pose(inertial, f"{what} inertial")
    return mass, X[:3, 3], X[:3, :3] @ inertia @ X[:3, :3].T


def _rigid_body(path: Path, links: dict[str, ET.Element], children: dict[str, list[_Joint]], link: str) -> Body:
    """The mass properties of ``link`` and every link welded to it by fixed joints, in ``link``'s frame."""
    parts, stack = [], [(link, np.eye(4))]
    while stack:
        name, X = stack.pop()
        mass, com, inertia = _link_inertial(path, links[name])
        if mass > 0:
            parts.append((mass, X[:3, :3] @ com + X[:3, 3], X[:3, :3] @ inertia @ X[:3, :3].T))
        stack.extend((j.child, X @ _pose(j.element, f"{path}: joint {j.name!r}"))
                     for j in children[name] if j.kind == "fixed")
    if not parts:
        return Body(0.0, 0.03)
    mass = sum(m for m, _, _ in parts)
    com = sum(m * c for m, c, _ in parts) / mass
    inertia = sum(I + m * ((c - com) @ (c - com) * np.eye(3) - np.outer(c - com, c - com)) for m, c, I in parts)
    return Body(mass, 0.03, com=(float(com[0]), float(com[1]), float(com[2])),
                inertia=tuple(map(tuple, inertia.tolist())))


def _joint_limits(path: Path, joint: ET.Element) -> JointLimits:
    """A URDF joint's limits; effort/velocity absent or 0 (as exporters write for "none") are unknown."""
    name, kind = joint.get("name"), joint.get("type")
    limit = joint.find("limit")
    attrs = {} if limit is None else limit.attrib
    rates = []
    for key in ("effort", "velocity"):
        value = file_number(attrs[key], f"{path}: joint {name!r} {key}") if key in attrs else 0.0
        if value < 0:
            raise ValueError(f"{path}: joint {name!r} {key} = {value:g} is not allowed: a limit is ≥ 0")
        rates.append(value or None)
    if kind == "continuous":
        return JointLimits(None, None, *rates)
    if "lower" not in attrs or "upper" not in attrs:
        raise ValueError(f"{path}: {kind} joint {name!r} needs <limit lower=… upper=…>")
    lo = file_number(attrs["lower"], f"{path}: joint {name!r} lower")
    hi = file_number(attrs["upper"], f"{path}: joint {name!r} upper")
    if lo > hi:  # not a bound: a file's own limits, as given
        raise ValueError(f"{path}: joint {name!r} has lower = {lo:g} above upper = {hi:g}: the limits are reversed")
    return JointLimits(lo, hi, *rates)


def _drive_train(path: Path, root: ET.Element, joints: dict[str, ET.Element], order: list[str]) -> DriveTrain | None:
    """The drive train of the joints ``order`` (module docstring); ``None`` if the URDF gives no part of it."""
    n = len(order)
    values = {"gear_ratio": np.ones(n), "rotor_inertia": np.zeros(n), "viscous": np.zeros(n), "coulomb": np.zeros(n)}
    for k, name in enumerate(order):
        dynamics = joints[name].find("dynamics")
        for key, attribute in (("viscous", "damping"), ("coulomb", "friction")):
            if dynamics is not None and attribute in dynamics.attrib:
                values[key][k] = file_number(dynamics.get(attribute), f"{path}: joint {name!r} dynamics {attribute}")
    for transmission in root.findall("transmission"):
        joint, actuator = transmission.find("joint"), transmission.find("actuator")
        if joint is None or actuator is None or joint.get("name") not in order:
            continue
        k = order.index(str(joint.get("name")))
        for child in actuator:
            key = child.tag.rpartition("}")[2]  # <drake:gear_ratio> with the drake namespace declared
            if key in ("rotor_inertia", "gear_ratio"):
                values[key][k] = file_number(child.get("value"), f"{path}: joint {order[k]!r} transmission {key}")
    ideal = DriveTrain.ideal(n)
    if all(np.array_equal(v, getattr(ideal, key)) for key, v in values.items()):  # exact: the defaults themselves
        return None
    try:
        return DriveTrain(values["gear_ratio"], values["rotor_inertia"], np.ones(n), values["viscous"],
                          values["coulomb"])
    except ValueError as error:
        raise ValueError(f"{path}: {error} (joints in chain order: {', '.join(order)})") from None


def _tool_path(tool: str | None, base: str, children: dict[str, list[_Joint]]) -> set[str]:
    """The links from the root ``base`` to the link ``tool`` (empty for no tool)."""
    if tool is None:
        return set()
    parent = {j.child: link for link, below in children.items() for j in below}
    path, link = {tool}, tool
    while link != base:
        link = parent[link]
        path.add(link)
    return path


def _welded(link: str, children: dict[str, list[_Joint]]) -> list[str]:
    """``link`` and the links welded below it by fixed joints, depth first."""
    out, stack = [], [link]
    while stack:
        name = stack.pop()
        out.append(name)
        stack.extend(reversed([j.child for j in children[name] if j.kind == "fixed"]))
    return out


def _hulls(path: Path, root: ET.Element, meshes: Meshes) -> tuple[Hull, ...]:
    """The STL and COLLADA collision meshes :func:`~armlab.models.meshes.check_meshes` read, each on its link at its
    ``<collision>``'s origin, for the plant to register as convex hulls."""
    out = []
    for link in root.iter("link"):
        collisions = [child for child in link if child.tag == "collision"]
        for k, element in enumerate(collisions):
            if element in meshes.hulls:
                name = element.get("name") or f"{link.get('name')}_collision{k + 1}"
                pose = _pose(element, f"{path}: link {link.get('name')!r} collision")
                out.append(Hull(str(link.get("name")), tuple(map(tuple, pose.tolist())), meshes.hulls[element], name))
    return tuple(out)


def _drake_text(root: ET.Element, meshes: Meshes) -> str:
    """The URDF as Drake reads it: each kept mesh as the ``file://`` URI of its checked file, the visuals and
    collisions :func:`~armlab.models.meshes.check_meshes` left out or read as hulls (:func:`_hulls`) removed,
    ``<mimic>`` of fixed joints removed
    (Drake refuses one; it does nothing), effort and velocity limits of 0 (ROS's "none") removed. ``root`` is
    changed."""
    for mesh, file in meshes.files.items():
        mesh.set("filename", file.as_uri())
    for link in root.iter("link"):
        for element in [child for child in link if child in meshes.dropped or child in meshes.hulls]:
            link.remove(element)
    for joint in root.iter("joint"):
        for mimic in joint.findall("mimic") if joint.get("type") == "fixed" else []:
            joint.remove(mimic)
        for limit in joint.findall("limit"):  # 0, ROS's "none": unknown to armlab, so no limit for Drake either
            for key in ("effort", "velocity"):  # (Drake skips the transmission of a joint with effort 0)
                if limit.get(key) is not None and file_number(limit.get(key), key) == 0:
                    del limit.attrib[key]
    return ET.tostring(root, encoding="unicode")


def from_urdf(path: str | Path, tool: str | None = None, package_paths: Sequence[str | Path] = ()) -> Arm:
    """An arm from a user's URDF file of one serial chain; errors name what is wrong (module docstring).

    ``tool``: the tool frame's link (the last moving link or one welded to it); ``None``: the end of the chain.
    ``package_paths``: folders holding the ROS packages the URDF's ``package://`` meshes name (:func:`package_roots`).
    """
    path = Path(path)
    root = _parse_urdf(path)
    links = _named(path, root.findall("link"), "link")
    joints = _named(path, root.findall("joint"), "joint")
    movable = [name for name, joint in joints.items() if joint.get("type") != "fixed"]
    if len(movable) > MAX_JOINTS:
        raise ValueError(f"{path}: {len(movable)} movable joints: armlab takes arms of at most {MAX_JOINTS} joints")
    base, children = _tree(path, links, joints)
    if tool is not None and tool not in links:
        raise ValueError(f"{path}: tool link {tool!r} is not a link of the URDF")
    moving_below = _moving_below(base, children)
    meshes = check_meshes(path, root, package_roots(path, package_paths))
    to_tool = _tool_path(tool, base, children)

    rows: list[JointRow] = []
    limits, bodies, names, points = [], [], [], []
    carried = np.eye(4)
    link = base
    while children[link] and not (link == tool and not moving_below[link]):
        moving = [j for j in children[link] if j.kind != "fixed" or moving_below[j.child]]
        if len(moving) > 1:
            raise ValueError(
                f"{path}: link {link!r} branches into {len(moving)} moving chains; armlab takes serial arms"
            )
        # side branches of fixed joints are named points; past the last joint the first (or the tool's) is the tool
        toward_tool = [j for j in children[link] if j.child in to_tool]
        joint = (moving or toward_tool or children[link])[0]
        for other in [j for j in children[link] if j is not joint]:
            T = carried @ _pose(other.element, f"{path}: joint {other.name!r}")
            points.append(Point(other.child, len(rows), tuple(T[:3, 3])))
        name, kind = joint.name, joint.kind
        T = carried @ _pose(joint.element, f"{path}: joint {name!r}")
        link = joint.child
        if kind == "fixed":
            carried = T
            continue
        axis_element = joint.element.find("axis")
        axis = _vector(axis_element.get("xyz") if axis_element is not None else None,
                       f"{path}: joint {name!r} axis", "1 0 0")
        if np.linalg.norm(axis) < 1e-12:
            raise ValueError(f"{path}: joint {name!r} has a zero axis")
        rows.append(JointRow(name, "T" if kind == "prismatic" else "R", tuple(T[:3, 3]),
                             tuple(axis / np.linalg.norm(axis)), tuple(map(tuple, T[:3, :3]))))
        limits.append(_joint_limits(path, joint.element))
        bodies.append(_rigid_body(path, links, children, link))
        names.append(link)
        carried = np.eye(4)
    if not rows:
        raise ValueError(f"{path}: the URDF has no movable joint")
    n = len(rows)
    past_last = _welded(names[-1], children)
    if tool is not None and link != tool:
        raise ValueError(f"{path}: tool link {tool!r} is not past the last joint {rows[-1].name!r}; allowed: "
                         f"{', '.join(past_last)}")
    # the fixed children of the tool link are points on it
    points.extend(Point(j.child, n + 1, tuple(_pose(j.element, f"{path}: joint {j.name!r}")[:3, 3]))
                  for j in children[link])
    table = LocatingTable(tuple(rows), tool=carried)
    check_com_distances(path, table, bodies, limits, names)
    others = [name for name in past_last if name != link]
    return Arm(
        name=root.get("name") or path.stem,
        paper=f"user URDF {path}",
        parameters={},
        notes={},
        table=table,
        bodies=tuple(bodies),
        limits=tuple(limits),
        points=tuple(points) + (Point(link, n + 1, (0.0, 0.0, 0.0)),),
        tool_name=link,
        gravity=(0.0, 0.0, -9.81),
        urdf_file=path.resolve(),
        base_link=base,
        has_dynamics=any(body.mass > 0 for body in bodies),
        link_names=tuple(names),
        drives=_drive_train(path, root, joints, [row.name for row in rows]),
        collision_hulls=_hulls(path, root, meshes),
        model_text=_drake_text(root, meshes),
        tool_source=("chosen (tool=, --tool)" if tool is not None else
                     "the end of the chain: the first link declared past the last joint"
                     + (f"; other choices (--tool LINK): {', '.join(others)}" if others else "")),
    )


def check_com_distances(path: Path, table: LocatingTable, bodies: list[Body], limits: list[JointLimits],
                names: list[str]) -> None:
    """``ValueError`` for a link whose centre of mass lies far beyond the arm's size (its frames' offsets and its
    prismatic strokes summed): :func:`~armlab.arm_file.check_com_distance`."""
    size = sum(float(np.linalg.norm(row.P)) for row in table.rows) + float(np.linalg.norm(table.tool[:3, 3])) + sum(
        max(abs(lim.lower or 0.0), abs(lim.upper or 0.0)) for row, lim in zip(table.rows, limits, strict=True)
        if row.kind == "T")
    for body, name in zip(bodies, names, strict=True):
        if body.com is not None:
            check_com_distance(float(np.linalg.norm(body.com)), size, f"{path}: link {name!r}")


def package_roots(urdf: Path, package_paths: Sequence[str | Path] = ()) -> dict[str, Path]:
    """The ROS packages a URDF may use: ``{name: package folder}``.

    Found, the first of a name winning, by their ``package.xml``'s ``<name>``: in the URDF's folder and the two above
    it (a package's layout), then below each folder of ``package_paths`` and of ``ROS_PACKAGE_PATH``
    (``os.pathsep``-separated), as ROS's ``rospack`` and Drake's ``PackageMap`` do: a folder holding a
    ``package.xml`` is a package (not searched further), others are searched up to :data:`_PACKAGE_DEPTH` levels
    down. Then, for names no ``package.xml`` gives, by folder, as Pinocchio and other tools without ROS resolve
    ``package://NAME/…``: a folder of ``package_paths`` or ``ROS_PACKAGE_PATH`` called NAME, or a folder called NAME
    directly inside one (example-robot-data's ``package.xml`` names it ``example_robot_descriptions``, its URDFs
    say ``package://example-robot-data/…``). ``ValueError`` for a ``package_paths`` entry that is not a folder.
    """
    out: dict[str, Path] = {}
    found = [folder / "package.xml" for folder in list(Path(urdf).resolve().parents)[:3]]
    for folder in package_paths:
        if not Path(folder).is_dir():
            raise ValueError(f"package path {str(folder)!r} is not a folder: give the folder that holds ROS "
                             "packages (each a folder with a package.xml)")
    env = [Path(folder) for folder in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if folder]
    paths = [*map(Path, package_paths), *(folder for folder in env if folder.is_dir())]
    for folder in paths:
        found.extend(_packages_below(folder))
    for package_xml in found:
        if package_xml.is_file():
            name = (_xml(package_xml, "package.xml").findtext("name") or "").strip()
            if not name:
                raise ValueError(f"{package_xml}: a package.xml needs a <name>")
            out.setdefault(name, package_xml.parent.resolve())
    for folder in paths:
        for named in [folder, *sorted(child for child in folder.iterdir() if child.is_dir())]:
            if not named.name.startswith("."):
                out.setdefault(named.resolve().name if named == folder else named.name, named.resolve())
    return out


def _packages_below(folder: Path) -> list[Path]:
    """The ``package.xml`` files of the ROS packages in ``folder`` or below it (see :func:`package_roots`)."""
    out = []
    for where, subfolders, files_here in os.walk(folder):
        depth = len(Path(where).relative_to(folder).parts)
        if "package.xml" in files_here:
            out.append(Path(where) / "package.xml")
            subfolders.clear()
        elif depth >= _PACKAGE_DEPTH:
            subfolders.clear()
        subfolders[:] = sorted(name for name in subfolders if not name.startswith("."))
    return out
