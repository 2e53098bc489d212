"""Users' own arms: a URDF file, or a DH table (standard or modified) turned into a URDF.

A **DH table** is a CSV file (the README's section "Your own arm: the DH table format"):

* optional header comment lines, in any order: ``# convention: standard`` or ``# convention: modified``
  (standard if absent) and ``# units: rad`` or ``# units: deg`` (rad if absent); ``deg`` means
  ``alpha``, ``theta`` and a revolute joint's ``lower``, ``upper`` (and ``velocity``, deg/s) are in
  degrees. Other ``#`` lines at the top are free comments.
* a header row starting ``type,a,alpha,d,theta,lower,upper`` (one row per joint; ``type`` R or T;
  lengths in metres; ``lower``/``upper`` empty for an unlimited revolute joint), then, in any order,
  the optional columns of the Robotics Toolbox's ``RevoluteDH(m=, r=, I=)``, per link in the link's
  own DH frame: ``mass`` (kg), ``cx,cy,cz`` (centre of mass, m), ``Ixx,Iyy,Izz,Ixy,Ixz,Iyz``
  (kg·m² about the centre of mass), ``effort`` (N·m or N) and ``velocity`` (rad/s or m/s) limits.

A table without the ``mass`` column is a *kinematic* arm (``Arm.has_dynamics`` False): no masses
are invented. Missing effort/velocity limits are unknown (``None``).

A **URDF file** must describe one serial chain (fixed joints are folded into the next joint's
origin; fixed side branches become named points; links rigidly attached through fixed joints are
one body); its root link is the base frame and the tool is the end of the chain (past the last
joint, the first fixed child declared). Refused with a one-line ``ValueError``: XML document-type
or entity definitions, joint cycles, mimic, floating and planar joints, reversed limits, a
non-physical inertia, non-finite numbers, more than :data:`MAX_JOINTS` joints, and mesh files
(and the files a mesh pulls in) outside the URDF's folder or its ROS package.
"""

from __future__ import annotations

import csv
import json
import re
import struct
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import unquote

import numpy as np
from numpy.typing import NDArray

from armlab.files import read_input
from armlab.kinematics.basic_movements import T_Z4, T_Z5, T_Z6
from armlab.kinematics.batch import chain_points
from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.locating import JointRow, LocatingTable, homogeneous
from armlab.models.arm import Arm, Forward
from armlab.models.urdf import Body, JointLimits, Point, check_inertia

__all__ = ["MAX_JOINTS", "DHInertial", "from_dh", "from_dh_csv", "from_urdf", "package_roots", "read_dh_csv"]

#: The most joints an arm may have. Serial arms have a handful; a 64-joint DH arm with masses still
#: simulates (1 s of motion in about 1 s, plus ~45 s for its 64-curve plots and replay on 2 shared
#: cores); a longer chain (a 200-row table) is refused up front instead of failing late.
MAX_JOINTS = 64

_DH_COLUMNS = ("type", "a", "alpha", "d", "theta", "lower", "upper")
_COM_COLUMNS = ("cx", "cy", "cz")
_INERTIA_COLUMNS = ("Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz")
_OPTIONAL_COLUMNS = ("mass", *_COM_COLUMNS, *_INERTIA_COLUMNS, "effort", "velocity")
_DIRECTIVES = {"convention": ("standard", "modified"), "units": ("rad", "deg")}


@dataclass(frozen=True)
class DHInertial:
    """One link's mass properties in its own DH frame i (the Robotics Toolbox's ``RevoluteDH(m=, r=, I=)``).

    ``mass`` kg; ``com`` (m) the centre of mass in DH frame i; ``inertia`` (kg·m², 3×3) about the
    centre of mass, axes of DH frame i. DH frame i is at the distal end of link i (standard DH)
    or at joint i (modified DH).
    """

    mass: float
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: tuple[tuple[float, float, float], ...] = field(default=((0.0,) * 3,) * 3)


#: Largest magnitude of any number in a user's arm file (lengths, angles, masses, inertias, limits): far beyond
#: any arm, and small enough that squares and products of them stay finite (no inf or NaN downstream).
MAX_FILE_NUMBER = 1e12


def _number(text: str | None, what: str) -> float:
    try:
        value = float(text or "")
    except ValueError:
        raise ValueError(f"{what} = {text!r} is not a number") from None
    if not np.isfinite(value):
        raise ValueError(f"{what} = {text!r} is not a finite number")
    if abs(value) > MAX_FILE_NUMBER:
        raise ValueError(f"{what} = {text!r} is out of range: allowed |value| ≤ {MAX_FILE_NUMBER:g}")
    return value


def _read_text(path: Path, what: str) -> str:
    """A user's file as text: a regular file of bounded size (:func:`armlab.files.read_input`), UTF-8."""
    raw = read_input(path, f"cannot read {what} {path}")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise ValueError(f"cannot read {what} {path}: it is not UTF-8 text") from None


# --------------------------------------------------------------------------- DH tables
def _header_comments(path: Path, lines: list[str]) -> tuple[dict[str, str], list[str]]:
    """The ``# convention:`` / ``# units:`` settings of the leading ``#`` lines, and the lines after them."""
    settings: dict[str, str] = {}
    while lines and lines[0].lstrip().startswith("#"):
        line = lines.pop(0)
        key, colon, value = line.lstrip().lstrip("#").partition(":")
        key, value = key.strip().lower(), value.strip().lower()
        mentioned = [name for name in _DIRECTIVES  # a line starting "# unit…:" or "# convention… =" is a setting
                     if re.match(rf"\s*#\s*{name.rstrip('s')}\w*\s*[:=]", line.lower())]
        if colon and key in _DIRECTIVES and value in _DIRECTIVES[key] and key not in settings:
            settings[key] = value
        elif mentioned:  # a misspelt or repeated setting must not be ignored silently
            name = mentioned[0]
            raise ValueError(f"{path}: header line {line.strip()!r}: write it once as "
                             + " or ".join(f"'# {name}: {v}'" for v in _DIRECTIVES[name]))
    return settings, lines


def _columns(path: Path, fieldnames: Sequence[str] | None) -> list[str]:
    """The header's column names (optional ones spelt as documented); errors name what is wrong."""
    names = [f.strip() for f in fieldnames or []]
    if tuple(names[:7]) != _DH_COLUMNS:
        raise ValueError(f"{path}: header {','.join(names)!r} must start with {','.join(_DH_COLUMNS)}")
    known = {c.lower(): c for c in _OPTIONAL_COLUMNS}
    extra = names[7:]
    unknown = [c for c in extra if c.lower() not in known]
    if unknown:
        raise ValueError(f"{path}: unknown column(s) {', '.join(unknown)}; allowed after "
                         f"{','.join(_DH_COLUMNS)}: {','.join(_OPTIONAL_COLUMNS)}")
    extra = [known[c.lower()] for c in extra]
    repeated = sorted({c for c in extra if extra.count(c) > 1})
    if repeated:
        raise ValueError(f"{path}: column(s) {', '.join(repeated)} appear more than once")
    orphans = [c for c in extra if c in _COM_COLUMNS + _INERTIA_COLUMNS and "mass" not in extra]
    if orphans:
        raise ValueError(f"{path}: column(s) {', '.join(orphans)} need the mass column")
    return list(_DH_COLUMNS) + extra


def _angle(value: float, deg: bool, what: str) -> float:
    """``value`` in radians; in a radian table, a value that can only be degrees is an error."""
    if deg:
        return float(np.radians(value))
    if abs(value) > 2 * np.pi + 1e-9:
        raise ValueError(f"{what} = {value:g} is beyond ±2π rad: angles are radians unless the file "
                         "has the line '# units: deg' (add it if the table is in degrees)")
    return value


def _positive_or_none(text: str, what: str) -> float | None:
    if text == "":
        return None
    value = _number(text, what)
    if value <= 0:
        raise ValueError(f"{what} = {value:g} is not allowed: a limit is > 0 (leave it empty if unknown)")
    return value


def read_dh_csv(path: str | Path) -> tuple[DHTable, list[JointLimits], list[DHInertial] | None]:
    """Read a DH table file (see the module docstring): the table (radians), limits (SI) and mass data.

    The mass data is ``None`` when the file has no ``mass`` column (a kinematic arm). Errors name the
    bad row and column.
    """
    path = Path(path)
    settings, lines = _header_comments(path, _read_text(path, "DH table").splitlines())
    deg = settings.get("units") == "deg"
    reader = csv.reader(lines)
    columns = _columns(path, next(reader, None))
    rows, limits, inertials = [], [], []
    for number, values in enumerate(reader, start=1):
        if not values:
            continue
        if len(values) != len(columns):
            raise ValueError(f"{path}: row {number} has {len(values)} values; expected {len(columns)} "
                             f"({','.join(columns)})")
        if number > MAX_JOINTS:
            raise ValueError(f"{path}: more than {MAX_JOINTS} rows: armlab takes arms of at most {MAX_JOINTS} "
                             "joints (its plots, replay and numerical IK are not made for longer chains)")
        record = {k: v.strip() for k, v in zip(columns, values, strict=True)}
        where = f"{path}: row {number}"
        kind = record["type"].upper()
        if kind not in ("R", "T"):
            raise ValueError(f"{where}: type {record['type']!r} is not allowed (R or T)")
        a, alpha, d, theta = (_number(record[k], f"{where}: {k}") for k in ("a", "alpha", "d", "theta"))
        rows.append(DHRow(a, _angle(alpha, deg, f"{where}: alpha"), d, _angle(theta, deg, f"{where}: theta"), kind))
        velocity = _positive_or_none(record.get("velocity", ""), f"{where}: velocity")
        if velocity is not None and deg and kind == "R":
            velocity = float(np.radians(velocity))
        effort = _positive_or_none(record.get("effort", ""), f"{where}: effort")
        if record["lower"] == "" and record["upper"] == "":
            if kind == "T":
                raise ValueError(f"{where}: a prismatic joint needs lower and upper limits")
            limits.append(JointLimits(None, None, effort, velocity))
        else:
            lo, hi = (_number(record[k], f"{where}: {k}") for k in ("lower", "upper"))
            if kind == "R":
                lo, hi = _angle(lo, deg, f"{where}: lower"), _angle(hi, deg, f"{where}: upper")
            if lo >= hi:
                raise ValueError(f"{where}: lower = {lo} must be below upper = {hi}")
            limits.append(JointLimits(lo, hi, effort, velocity))
        if "mass" in record:
            inertials.append(_dh_inertial(record, where))
    if not rows:
        raise ValueError(f"{path}: the DH table has no rows")
    table = DHTable(tuple(rows), settings.get("convention", "standard"))
    return table, limits, inertials if "mass" in columns else None


def _dh_inertial(record: dict[str, str], where: str) -> DHInertial:
    """A row's mass properties (empty centre-of-mass and inertia cells are 0), checked to be physical."""
    if record["mass"] == "":
        raise ValueError(f"{where}: mass is empty: every row needs a mass (kg) when the mass column is given")
    mass = _number(record["mass"], f"{where}: mass")
    c = [_number(record[k], f"{where}: {k}") if record.get(k) else 0.0 for k in _COM_COLUMNS]
    ixx, iyy, izz, ixy, ixz, iyz = (_number(record[k], f"{where}: {k}") if record.get(k) else 0.0
                                    for k in _INERTIA_COLUMNS)
    inertia = ((ixx, ixy, ixz), (ixy, iyy, iyz), (ixz, iyz, izz))
    check_inertia(mass, np.array(inertia), where)
    return DHInertial(mass, (c[0], c[1], c[2]), inertia)


def from_dh(
    table: DHTable,
    limits: Sequence[JointLimits],
    inertials: Sequence[DHInertial] | None = None,
    name: str = "dh_arm",
) -> Arm:
    """An arm from a DH table: its URDF comes from the same builder as the paper arms'.

    ``inertials`` (one per link, in the links' DH frames) are moved into the URDF's link frames {i};
    ``None`` or all masses 0 gives a kinematic arm (``has_dynamics`` False, no ``<inertial>``).
    """
    locating = table.locating_table()
    n = table.n
    has_dynamics = inertials is not None and any(body.mass > 0 for body in inertials)
    bodies = tuple(Body(0.0, 0.03) for _ in range(n))
    if has_dynamics:
        if len(inertials) != n:
            raise ValueError(f"{name}: need {n} link inertials, got {len(inertials)}")
        # link i carries both its DH frame i and the URDF's frame {i}: X = T_{0,{i}}⁻¹ · T_{0,i}, constant in q
        zero = np.zeros(n)
        urdf_frames, dh_frames = locating.frames(zero)[1:n + 1], table.frames(zero)[1:]
        bodies = tuple(_moved(body, np.linalg.solve(F, D)) for body, F, D in
                       zip(inertials, urdf_frames, dh_frames, strict=True))
    return Arm(
        name=name,
        paper="user DH table",
        parameters={f"{key}{i + 1}": getattr(row, key) for i, row in enumerate(table.rows)
                    for key in ("a", "alpha", "d", "theta")},
        notes={},
        table=locating,
        bodies=bodies,
        limits=tuple(limits),
        points=tuple(Point(f"O{i}", i, (0.0, 0.0, 0.0)) for i in range(1, n)) + (Point(f"O{n}", n + 1, (0, 0, 0)),),
        tool_name=f"O{n}",
        gravity=(0.0, 0.0, -9.81),
        forward_fn=lambda q: _dh_forward(table, q),
        has_dynamics=has_dynamics,
        dh=table,
    )


def _moved(body: DHInertial, X: NDArray) -> Body:
    """``body`` (in DH frame i) as a :class:`Body` in the link frame {i}, where DH frame i is ``X`` in {i}."""
    R = X[:3, :3]
    com = R @ np.asarray(body.com) + X[:3, 3]
    inertia = R @ np.asarray(body.inertia) @ R.T
    return Body(body.mass, 0.03, com=tuple(map(float, com)), inertia=tuple(map(tuple, inertia.tolist())))


def from_dh_csv(path: str | Path) -> Arm:
    """An arm from a DH table file (:func:`read_dh_csv`), named after the file."""
    return from_dh(*read_dh_csv(path), name=Path(path).stem)


def _dh_forward(table: DHTable, q: np.ndarray) -> Forward:
    """The DH frames' origins O1 … On; the tool is DH frame n."""
    tool, points = chain_points(q, table.steps, {f"O{i}": (i, (0.0, 0.0, 0.0)) for i in range(1, table.n + 1)})
    return Forward(tool, points)


# --------------------------------------------------------------------------- URDF files
_TEXT_ATTRIBUTES = {"name", "filename", "link", "joint", "type", "version", "reference", "xmlns"}
_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed")


def _vector(text: str | None, what: str, default: str) -> np.ndarray:
    parts = (text if text is not None else default).split()
    if len(parts) != 3:
        raise ValueError(f"{what} = {text!r} must be three numbers")
    return np.array([_number(p, what) for p in parts])


def _pose(element: ET.Element | None, what: str) -> np.ndarray:
    """The ``<origin>`` child of ``element`` as a 4×4 matrix (rpy: R = Rz(y)·Ry(p)·Rx(r))."""
    origin = None if element is None else element.find("origin")
    xyz = _vector(None if origin is None else origin.get("xyz"), f"{what} origin xyz", "0 0 0")
    rpy = _vector(None if origin is None else origin.get("rpy"), f"{what} origin rpy", "0 0 0")
    return homogeneous((T_Z6(rpy[2]) @ T_Z5(rpy[1]) @ T_Z4(rpy[0]))[:3, :3], xyz)


def _xml(path: Path, what: str) -> ET.Element:
    """The root element of an XML file; entity and document-type definitions (entity expansion) are refused."""
    text = _read_text(path, what)
    if "<!DOCTYPE" in text or "<!ENTITY" in text:
        raise ValueError(f"{path}: XML document-type or entity definitions (<!DOCTYPE, <!ENTITY) are not "
                         f"allowed in a {what}")
    try:
        return ET.fromstring(text)
    except ET.ParseError as error:
        raise ValueError(f"{path} is not valid XML: {error}") from None


def _parse_urdf(path: Path) -> ET.Element:
    """The URDF's root element (:func:`_xml`), with every number in it finite."""
    root = _xml(path, "URDF")
    if root.tag != "robot":
        raise ValueError(f"{path}: the root element is <{root.tag}>, a URDF needs <robot>")
    for element in root.iter():  # every number in the file, not only the ones armlab reads itself
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


def _tree(path: Path, links: dict[str, ET.Element], joints: dict[str, ET.Element]) -> tuple[str, dict]:
    """The root link and each link's child joints; a URDF whose joints are not one tree is an error."""
    children: dict[str, list[ET.Element]] = {name: [] for name in links}
    parent_of: dict[str, str] = {}
    for name, joint in joints.items():
        kind = joint.get("type")
        if kind not in _JOINT_TYPES:
            raise ValueError(f"{path}: joint {name!r} has type {kind!r}; allowed: {', '.join(_JOINT_TYPES)}")
        if joint.find("mimic") is not None:
            raise ValueError(f"{path}: joint {name!r} mimics joint {joint.find('mimic').get('joint')!r}: mimic "
                             "joints are not supported (each joint of an armlab arm moves independently)")
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None or parent.get("link") not in links or child.get("link") not in links:
            raise ValueError(f"{path}: joint {name!r} needs a <parent> and <child> naming links")
        if child.get("link") in parent_of:
            raise ValueError(f"{path}: link {child.get('link')!r} is the child of joints "
                             f"{parent_of[child.get('link')]!r} and {name!r}: a URDF's joints form a tree")
        parent_of[child.get("link")] = name
        children[parent.get("link")].append(joint)
    roots = [name for name in links if name not in parent_of]
    if len(roots) != 1:
        if not roots:
            raise ValueError(f"{path}: the joints form a cycle: every link has a parent, so there is no root link")
        raise ValueError(f"{path}: a serial arm has one root link, found {roots}")
    reached, stack = {roots[0]}, [roots[0]]
    while stack:
        for joint in children[stack.pop()]:
            reached.add(joint.find("child").get("link"))
            stack.append(joint.find("child").get("link"))
    if len(reached) != len(links):
        cycle = sorted(set(links) - reached)
        raise ValueError(f"{path}: the joints form a cycle through link(s) {', '.join(map(repr, cycle[:5]))}, "
                         f"not connected to the root link {roots[0]!r}")
    return roots[0], children


def _moving_below(root: str, children: dict[str, list[ET.Element]]) -> dict[str, bool]:
    """For each link: does a movable joint lie below it (iteratively: chains may be long)?"""
    order, stack = [], [root]
    while stack:
        link = stack.pop()
        order.append(link)
        stack.extend(j.find("child").get("link") for j in children[link])
    below: dict[str, bool] = {}
    for link in reversed(order):
        below[link] = any(j.get("type") != "fixed" or below[j.find("child").get("link")] for j in children[link])
    return below


def _link_inertial(path: Path, link: ET.Element) -> tuple[float, NDArray, NDArray]:
    """A URDF link's ``(mass, com, inertia about the com)`` in the link's frame; checked to be physical."""
    name = link.get("name")
    inertial = link.find("inertial")
    if inertial is None:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    what = f"{path}: link {name!r}"
    mass_element = inertial.find("mass")
    mass = 0.0 if mass_element is None else _number(mass_element.get("value"), f"{what} mass")
    if mass < 0:
        raise ValueError(f"{what} mass = {mass:g} kg is not allowed: a mass is ≥ 0 kg")
    element = inertial.find("inertia")
    values = {k: 0.0 if element is None else _number(element.get(k, "0"), f"{what} inertia {k}")
              for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    inertia = np.array([[values["ixx"], values["ixy"], values["ixz"]], [values["ixy"], values["iyy"], values["iyz"]],
                        [values["ixz"], values["iyz"], values["izz"]]])
    check_inertia(mass, inertia, what)
    X = _pose(inertial, f"{what} inertial")
    return mass, X[:3, 3], X[:3, :3] @ inertia @ X[:3, :3].T


def _rigid_body(path: Path, links: dict[str, ET.Element], children: dict, link: str) -> Body:
    """The mass properties of ``link`` and every link welded to it by fixed joints, in ``link``'s frame."""
    parts, stack = [], [(link, np.eye(4))]
    while stack:
        name, X = stack.pop()
        mass, com, inertia = _link_inertial(path, links[name])
        if mass > 0:
            parts.append((mass, X[:3, :3] @ com + X[:3, 3], X[:3, :3] @ inertia @ X[:3, :3].T))
        stack.extend((j.find("child").get("link"), X @ _pose(j, f"{path}: joint {j.get('name')!r}"))
                     for j in children[name] if j.get("type") == "fixed")
    if not parts:
        return Body(0.0, 0.03)
    mass = sum(m for m, _, _ in parts)
    com = sum(m * c for m, c, _ in parts) / mass
    inertia = sum(I + m * ((c - com) @ (c - com) * np.eye(3) - np.outer(c - com, c - com)) for m, c, I in parts)
    return Body(mass, 0.03, com=tuple(map(float, com)), inertia=tuple(map(tuple, inertia.tolist())))


def _joint_limits(path: Path, joint: ET.Element) -> JointLimits:
    """A URDF joint's limits; effort/velocity absent or 0 (as exporters write for "none") are unknown."""
    name, kind = joint.get("name"), joint.get("type")
    limit = joint.find("limit")
    attrs = {} if limit is None else limit.attrib
    rates = []
    for key in ("effort", "velocity"):
        value = _number(attrs[key], f"{path}: joint {name!r} {key}") if key in attrs else 0.0
        if value < 0:
            raise ValueError(f"{path}: joint {name!r} {key} = {value:g} is not allowed: a limit is ≥ 0")
        rates.append(value or None)
    if kind == "continuous":
        return JointLimits(None, None, *rates)
    if "lower" not in attrs or "upper" not in attrs:
        raise ValueError(f"{path}: {kind} joint {name!r} needs <limit lower=… upper=…>")
    lo = _number(attrs["lower"], f"{path}: joint {name!r} lower")
    hi = _number(attrs["upper"], f"{path}: joint {name!r} upper")
    if lo > hi:
        raise ValueError(f"{path}: joint {name!r} has lower = {lo:g} above upper = {hi:g}: the limits are reversed")
    return JointLimits(lo, hi, *rates)


def from_urdf(path: str | Path) -> Arm:
    """An arm from a user's URDF file of one serial chain; errors name what is wrong (module docstring)."""
    path = Path(path)
    root = _parse_urdf(path)
    links = _named(path, root.findall("link"), "link")
    joints = _named(path, root.findall("joint"), "joint")
    movable = [name for name, joint in joints.items() if joint.get("type") != "fixed"]
    if len(movable) > MAX_JOINTS:
        raise ValueError(f"{path}: {len(movable)} movable joints: armlab takes arms of at most {MAX_JOINTS} joints")
    base, children = _tree(path, links, joints)
    moving_below = _moving_below(base, children)
    check_meshes(path, root)

    rows, limits, bodies, names, points = [], [], [], [], []
    carried = np.eye(4)
    link = base
    while children[link]:
        moving = [j for j in children[link] if j.get("type") != "fixed" or moving_below[j.find("child").get("link")]]
        if len(moving) > 1:
            raise ValueError(
                f"{path}: link {link!r} branches into {len(moving)} moving chains; armlab takes serial arms"
            )
        # side branches of fixed joints are named points; past the last joint the first is the tool
        joint, *side = moving or children[link]
        for other in side + [j for j in children[link] if j not in moving and j is not joint]:
            T = carried @ _pose(other, f"{path}: joint {other.get('name')!r}")
            points.append(Point(other.find("child").get("link"), len(rows), tuple(T[:3, 3])))
        name, kind = joint.get("name"), joint.get("type")
        T = carried @ _pose(joint, f"{path}: joint {name!r}")
        link = joint.find("child").get("link")
        if kind == "fixed":
            carried = T
            continue
        axis = _vector(joint.find("axis").get("xyz") if joint.find("axis") is not None else None,
                       f"{path}: joint {name!r} axis", "1 0 0")
        if np.linalg.norm(axis) < 1e-12:
            raise ValueError(f"{path}: joint {name!r} has a zero axis")
        rows.append(JointRow(name, "T" if kind == "prismatic" else "R", tuple(T[:3, 3]),
                             tuple(axis / np.linalg.norm(axis)), tuple(map(tuple, T[:3, :3]))))
        limits.append(_joint_limits(path, joint))
        bodies.append(_rigid_body(path, links, children, link))
        names.append(link)
        carried = np.eye(4)
    if not rows:
        raise ValueError(f"{path}: the URDF has no movable joint")
    n = len(rows)
    return Arm(
        name=root.get("name") or path.stem,
        paper=f"user URDF {path}",
        parameters={},
        notes={},
        table=LocatingTable(tuple(rows), tool=carried),
        bodies=tuple(bodies),
        limits=tuple(limits),
        points=tuple(points) + (Point(link, n + 1, (0.0, 0.0, 0.0)),),
        tool_name=link,
        gravity=(0.0, 0.0, -9.81),
        urdf_file=path.resolve(),
        base_link=base,
        has_dynamics=any(body.mass > 0 for body in bodies),
        link_names=tuple(names),
    )


# --------------------------------------------------------------------------- mesh files
def package_roots(urdf: Path) -> dict[str, Path]:
    """The ROS packages a URDF may use: ``{name: package.xml}`` in its folder or the two above it."""
    out: dict[str, Path] = {}
    for folder in list(Path(urdf).resolve().parents)[:3]:
        package_xml = folder / "package.xml"
        if package_xml.is_file():
            name = (_xml(package_xml, "package.xml").findtext("name") or "").strip()
            if not name:
                raise ValueError(f"{package_xml}: a package.xml needs a <name>")
            out.setdefault(name, package_xml)
    return out


def _inside(path: Path, folders: Sequence[Path], what: str) -> Path:
    """``path`` with symlinks and ``..`` resolved, if it lies inside one of ``folders``; else an error."""
    real = path.resolve()
    if not any(real.is_relative_to(folder) for folder in folders):
        shown = str(real) if path.is_symlink() or ".." in path.parts else str(path)
        raise ValueError(f"{what}: {shown} lies outside the URDF's folder and its ROS package "
                         f"({', '.join(map(str, folders))}): armlab reads no files from elsewhere")
    return real


def _reference(reference: str, base: Path, packages: dict[str, Path], folders: Sequence[Path], what: str) -> Path:
    """A file named by a URDF mesh (``package://`` or relative to ``base``), checked to lie inside ``folders``."""
    if reference.startswith("package://"):
        package, _, rest = reference[len("package://"):].partition("/")
        if package not in packages:
            raise ValueError(f"{what}: {reference!r} names package {package!r}, but the URDF's folder and the two "
                             f"above it declare {', '.join(map(repr, packages)) or 'no package (package.xml)'}")
        return _inside(packages[package].parent / rest, folders, what)
    if "://" in reference or reference.startswith(("/", "\\")) or Path(reference).is_absolute():
        raise ValueError(f"{what}: {reference!r} is an absolute path or URL: name files relative to the URDF's "
                         "folder or as package://NAME/… of its ROS package")
    return _inside(base / reference, folders, what)


def _pulled_in(mesh: Path) -> list[str]:
    """The files a mesh file names: a glTF's buffer and image URIs, an OBJ's material libraries, an MTL's maps."""
    suffix = mesh.suffix.lower()
    if not mesh.is_file() or suffix not in (".gltf", ".glb", ".obj", ".mtl"):
        return []
    if suffix in (".gltf", ".glb"):
        data = mesh.read_bytes()
        if suffix == ".glb":  # header (magic, version, length), then the JSON chunk (length, type, data)
            if len(data) < 20 or data[:4] != b"glTF":
                raise ValueError(f"{mesh}: not a binary glTF file")
            (length,) = struct.unpack_from("<I", data, 12)
            data = data[20:20 + length]
        try:
            document = json.loads(data)
            uris = [item["uri"] for key in ("buffers", "images") for item in document.get(key, []) if "uri" in item]
        except (ValueError, TypeError, AttributeError, KeyError):
            raise ValueError(f"{mesh}: not a glTF file (its JSON cannot be read)") from None
        if not all(isinstance(uri, str) for uri in uris):
            raise ValueError(f"{mesh}: a glTF uri is not a string")
        return [unquote(uri) for uri in uris if not uri.startswith("data:")]
    names = []
    with mesh.open(encoding="utf-8", errors="replace") as lines:
        for line in lines:
            words = line.split()
            if suffix == ".obj" and words[:1] == ["mtllib"]:
                names.extend(words[1:])
            elif suffix == ".mtl" and words and words[0].lower().startswith(("map_", "bump", "disp", "decal", "refl",
                                                                             "norm")):
                names.extend(words[-1:])
    return names


def check_meshes(path: Path, root: ET.Element) -> None:
    """``ValueError`` naming the file unless every mesh of the URDF, and every file those meshes name,
    lies inside the URDF's folder or its declared ROS package (no absolute paths, URLs, ``..`` or
    symlinks leading elsewhere): replaying someone else's URDF must not embed a file from elsewhere."""
    packages = package_roots(path)
    folders = [path.resolve().parent] + [xml.parent.resolve() for xml in packages.values()]
    for mesh in root.iter("mesh"):
        what = f"{path}: mesh {mesh.get('filename')!r}"
        pending = [_reference(mesh.get("filename") or "", path.resolve().parent, packages, folders, what)]
        seen: set[Path] = set()
        while pending:
            file = pending.pop()
            if file in seen:
                continue
            seen.add(file)
            pending.extend(_reference(name, file.parent, {}, folders, f"{path}: {file.name} names {name!r}")
                           for name in _pulled_in(file))
