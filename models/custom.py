"""Users' own arms: a URDF file, or a DH table (standard or modified) turned into a URDF.

A DH table is a CSV file with a header row ``type,a,alpha,d,theta,lower,upper`` (one row
per joint; ``type`` R or T; angles in radians, lengths in metres; ``lower``/``upper`` may
be empty for an unlimited revolute joint) and an optional first line
``# convention: standard`` or ``# convention: modified`` (standard if absent).

A URDF file must describe one serial chain (fixed joints are folded into the next
joint's origin; fixed side branches become named points); its root link is the base frame
and the tool is the end of the chain (past the last joint, the first fixed child declared).
"""

from __future__ import annotations

import csv
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from armlab.kinematics.basic_movements import T_Z4, T_Z5, T_Z6
from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.locating import JointRow, LocatingTable, homogeneous
from armlab.models.arm import Arm, Forward
from armlab.models.urdf import Body, JointLimits, Point

__all__ = ["from_dh", "from_urdf", "read_dh_csv"]

_DH_COLUMNS = ("type", "a", "alpha", "d", "theta", "lower", "upper")


def _number(text: str, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{what} = {text!r} is not a number") from None
    if not np.isfinite(value):
        raise ValueError(f"{what} = {text!r} is not a finite number")
    return value


def read_dh_csv(path: str | Path) -> tuple[DHTable, list[JointLimits]]:
    """Read a DH table file (see the module docstring); errors name the bad row and column."""
    path = Path(path)
    try:
        lines = path.read_text().splitlines()
    except OSError as error:
        raise ValueError(f"cannot read DH table {path}: {error.strerror}") from None
    except UnicodeDecodeError:
        raise ValueError(f"cannot read DH table {path}: it is not UTF-8 text") from None
    convention = "standard"
    if lines and lines[0].startswith("#"):
        key, _, value = lines[0].lstrip("#").partition(":")
        if key.strip() != "convention" or value.strip() not in ("standard", "modified"):
            raise ValueError(f"{path}: first line {lines[0]!r} must be '# convention: standard' or 'modified'")
        convention = value.strip()
        lines = lines[1:]
    reader = csv.DictReader(lines)
    if reader.fieldnames is None or tuple(f.strip() for f in reader.fieldnames) != _DH_COLUMNS:
        raise ValueError(f"{path}: header {reader.fieldnames} must be {','.join(_DH_COLUMNS)}")
    rows, limits = [], []
    for number, record in enumerate(reader, start=1):
        if None in record:  # csv.DictReader keeps values beyond the header under the key None
            raise ValueError(f"{path}: row {number} has {len(_DH_COLUMNS) + len(record[None])} values; "
                             f"expected {len(_DH_COLUMNS)} ({','.join(_DH_COLUMNS)})")
        record = {k.strip(): (v or "").strip() for k, v in record.items()}
        kind = record["type"].upper()
        if kind not in ("R", "T"):
            raise ValueError(f"{path}: row {number}: type {record['type']!r} is not allowed (R or T)")
        values = {k: _number(record[k], f"{path}: row {number}: {k}") for k in ("a", "alpha", "d", "theta")}
        rows.append(DHRow(values["a"], values["alpha"], values["d"], values["theta"], kind))
        if record["lower"] == "" and record["upper"] == "":
            if kind == "T":
                raise ValueError(f"{path}: row {number}: a prismatic joint needs lower and upper limits")
            limits.append(JointLimits(None, None, effort=100.0, velocity=5.0))
        else:
            lo = _number(record["lower"], f"{path}: row {number}: lower")
            hi = _number(record["upper"], f"{path}: row {number}: upper")
            if lo >= hi:
                raise ValueError(f"{path}: row {number}: lower = {lo} must be below upper = {hi}")
            limits.append(JointLimits(lo, hi, effort=100.0, velocity=5.0))
    if not rows:
        raise ValueError(f"{path}: the DH table has no rows")
    return DHTable(tuple(rows), convention), limits


def from_dh(table: DHTable, limits: list[JointLimits], name: str = "dh_arm", link_mass: float = 1.0) -> Arm:
    """An arm from a DH table: its URDF comes from the same builder as the paper arms'."""
    locating = table.locating_table()
    n = table.n
    return Arm(
        name=name,
        paper="user DH table",
        parameters={f"{key}{i + 1}": getattr(row, key) for i, row in enumerate(table.rows)
                    for key in ("a", "alpha", "d", "theta")},
        notes={},
        table=locating,
        bodies=tuple(Body(link_mass, 0.03) for _ in range(n)),
        limits=tuple(limits),
        points=tuple(Point(f"O{i}", i, (0.0, 0.0, 0.0)) for i in range(1, n)) + (Point(f"O{n}", n + 1, (0, 0, 0)),),
        tool_name=f"O{n}",
        gravity=(0.0, 0.0, -9.81),
        forward_fn=lambda q: _dh_forward(table, q),
    )


def _dh_forward(table: DHTable, q: np.ndarray) -> Forward:
    """The DH frames' origins O1 … On; the tool is DH frame n."""
    frames = table.frames(q)
    return Forward(frames[..., -1, :, :], {f"O{i}": frames[..., i, :3, 3] for i in range(1, table.n + 1)})


def _vector(text: str | None, what: str, default: str) -> np.ndarray:
    parts = (text or default).split()
    if len(parts) != 3:
        raise ValueError(f"{what} = {text!r} must be three numbers")
    return np.array([_number(p, what) for p in parts])


def _origin(joint: ET.Element, path: Path) -> np.ndarray:
    """A URDF joint's ``<origin>`` as a 4×4 matrix (rpy: R = Rz(y)·Ry(p)·Rx(r))."""
    origin = joint.find("origin")
    name = joint.get("name")
    xyz = _vector(None if origin is None else origin.get("xyz"), f"{path}: joint {name!r} origin xyz", "0 0 0")
    rpy = _vector(None if origin is None else origin.get("rpy"), f"{path}: joint {name!r} origin rpy", "0 0 0")
    return homogeneous((T_Z6(rpy[2]) @ T_Z5(rpy[1]) @ T_Z4(rpy[0]))[:3, :3], xyz)


def from_urdf(path: str | Path) -> Arm:
    """An arm from a user's URDF file of one serial chain; errors name what is wrong."""
    path = Path(path)
    try:
        root = ET.parse(path).getroot()
    except OSError as error:
        raise ValueError(f"cannot read URDF {path}: {error.strerror}") from None
    except ET.ParseError as error:
        raise ValueError(f"{path} is not valid XML: {error}") from None
    if root.tag != "robot":
        raise ValueError(f"{path}: the root element is <{root.tag}>, a URDF needs <robot>")
    links = [link.get("name") for link in root.findall("link")]
    joints = root.findall("joint")
    children: dict[str, list[ET.Element]] = {}
    has_parent = set()
    for joint in joints:
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None or parent.get("link") not in links or child.get("link") not in links:
            raise ValueError(f"{path}: joint {joint.get('name')!r} needs a <parent> and <child> naming links")
        children.setdefault(parent.get("link"), []).append(joint)
        has_parent.add(child.get("link"))
    roots = [name for name in links if name not in has_parent]
    if len(roots) != 1:
        raise ValueError(f"{path}: a serial arm has one root link, found {roots}")
    def leads_to_motion(joint: ET.Element) -> bool:
        if joint.get("type") != "fixed":
            return True
        return any(leads_to_motion(j) for j in children.get(joint.find("child").get("link"), []))

    rows, limits, masses, points = [], [], [], []
    carried = np.eye(4)
    link = roots[0]
    while link in children:
        moving = [j for j in children[link] if leads_to_motion(j)]
        if len(moving) > 1:
            raise ValueError(
                f"{path}: link {link!r} branches into {len(moving)} moving chains; armlab takes serial arms"
            )
        # side branches of fixed joints are named points; past the last joint the first is the tool
        joint, *side = moving or children[link]
        for other in side + [j for j in children[link] if j not in moving and j is not joint]:
            T = carried @ _origin(other, path)
            points.append(Point(other.find("child").get("link"), len(rows), tuple(T[:3, 3])))
        name, kind = joint.get("name"), joint.get("type")
        T = carried @ _origin(joint, path)
        link = joint.find("child").get("link")
        if kind == "fixed":
            carried = T
            continue
        if kind not in ("revolute", "continuous", "prismatic"):
            raise ValueError(
                f"{path}: joint {name!r} has type {kind!r}; allowed: revolute, continuous, prismatic, fixed"
            )
        axis = _vector(joint.find("axis").get("xyz") if joint.find("axis") is not None else None,
                       f"joint {name!r} axis", "1 0 0")
        if np.linalg.norm(axis) < 1e-12:
            raise ValueError(f"{path}: joint {name!r} has a zero axis")
        rows.append(JointRow(name, "T" if kind == "prismatic" else "R", tuple(T[:3, 3]),
                             tuple(axis / np.linalg.norm(axis)), tuple(map(tuple, T[:3, :3]))))
        limit = joint.find("limit")
        if kind == "continuous":
            limits.append(JointLimits(None, None, 100.0, 5.0))
        elif limit is None or limit.get("lower") is None or limit.get("upper") is None:
            raise ValueError(f"{path}: {kind} joint {name!r} needs <limit lower=… upper=…>")
        else:
            lo = _number(limit.get("lower"), f"joint {name!r} lower")
            hi = _number(limit.get("upper"), f"joint {name!r} upper")
            limits.append(JointLimits(lo, hi, _number(limit.get("effort", "100"), "effort"), 5.0))
        element = root.find(f"link[@name='{link}']/inertial/mass")
        mass = 0.0 if element is None else _number(element.get("value", "0"), f"{path}: link {link!r} mass")
        if mass < 0:
            raise ValueError(f"{path}: link {link!r} mass = {mass:g} kg is not allowed: a mass is ≥ 0 kg")
        masses.append(mass)
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
        bodies=tuple(Body(m, 0.03) for m in masses),
        limits=tuple(limits),
        points=tuple(points) + (Point(link, n + 1, (0.0, 0.0, 0.0)),),
        tool_name=link,
        gravity=(0.0, 0.0, -9.81),
        urdf_file=path.resolve(),
        base_link=roots[0],
    )
