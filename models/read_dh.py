"""Users' own arms from a DH table (standard or modified), turned into a URDF by the one builder.

A **DH table** is a CSV file (the README's section "Your own arm: the DH table format"):

* optional header comment lines, in any order: ``# convention: standard`` or ``# convention: modified``
  (standard if absent) and ``# units: rad`` or ``# units: deg`` (rad if absent); ``deg`` means
  ``alpha``, ``theta`` and a revolute joint's ``lower``, ``upper`` (and ``velocity``, deg/s) are in
  degrees. A radian table's ``alpha`` or ``theta`` beyond ±2π can only be degrees and is refused; joint
  limits may go beyond (a wrist turning ±400°). ``# base: x y z roll pitch yaw`` places DH frame 0 in the
  arm's base (world) frame and ``# tool: x y z roll pitch yaw`` the tool frame in DH frame n (the Robotics
  Toolbox's ``base=`` and ``tool=``; m, and angles in the table's units, R = Rz(yaw)·Ry(pitch)·Rx(roll) as
  in URDF; identity if absent). Other ``#`` lines at the top are free comments.
* a header row starting ``type,a,alpha,d,theta,lower,upper`` (one row per joint; ``type`` R or T;
  lengths in metres; ``lower``/``upper`` empty for an unlimited revolute joint), then, in any order,
  the optional columns of the Robotics Toolbox's ``RevoluteDH(m=, r=, I=)``, per link in the link's
  own DH frame: ``mass`` (kg), ``cx,cy,cz`` (centre of mass, m), ``Ixx,Iyy,Izz,Ixy,Ixz,Iyz``
  (kg·m² about the centre of mass), ``effort`` (N·m or N) and ``velocity`` (rad/s or m/s) limits, the
  drive train's columns (:data:`armlab.drives.read.DRIVE_COLUMNS`: ``gear_ratio``, ``rotor_inertia``,
  ``efficiency``, ``viscous``, ``coulomb`` or motor side ``viscous_motor``, ``coulomb_motor``), which give the
  arm its ``drives`` (:mod:`armlab.drives.read`), and ``radius`` (m): the link's collision capsules along its
  offsets d and a to the next joint (:mod:`armlab.collision`; 0: the link has no shape, it is never checked); a
  table without it has no collision geometry.

A table without the ``mass`` column is a *kinematic* arm (``Arm.has_dynamics`` False): no masses
are invented. Missing effort/velocity limits are unknown (``None``). At most
:data:`~armlab.arm_file.MAX_JOINTS` rows; every number bounded (:mod:`armlab.arm_file`).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Literal, TypeGuard

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.arm_file import MAX_JOINTS, check_com_distance, file_number, read_text
from armlab.drives.read import DRIVE_COLUMNS, drive_train
from armlab.files import csv_table
from armlab.kinematics.basic_movements import T_Z4, T_Z5, T_Z6
from armlab.kinematics.batch import ZStep, chain_points
from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.locating import JointRow, LocatingTable, homogeneous
from armlab.models.arm import Arm, Forward
from armlab.models.write_urdf import Body, JointLimits, Point, check_inertia

__all__ = ["DHInertial", "dh_base_tool", "dh_inertials", "from_dh", "from_dh_csv", "read_dh_csv"]

_DH_COLUMNS = ("type", "a", "alpha", "d", "theta", "lower", "upper")
_COM_COLUMNS = ("cx", "cy", "cz")
_INERTIA_COLUMNS = ("Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz")
_OPTIONAL_COLUMNS = ("mass", *_COM_COLUMNS, *_INERTIA_COLUMNS, "effort", "velocity", *DRIVE_COLUMNS, "radius")
_DIRECTIVES = {"convention": ("standard", "modified"), "units": ("rad", "deg")}
#: The header lines that place the chain: ``# base: x y z roll pitch yaw`` and ``# tool: …``.
_POSES = ("base", "tool")
_KINDS: tuple[Literal["R", "T"], ...] = ("R", "T")


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


def _header_comments(path: Path, lines: list[str]) -> tuple[dict[str, str], list[str]]:
    """The ``# convention:`` / ``# units:`` settings and the ``# base:`` / ``# tool:`` texts of the leading ``#``
    lines, and the lines after them."""
    settings: dict[str, str] = {}
    while lines and lines[0].lstrip().startswith("#"):
        line = lines.pop(0)
        key, colon, value = line.lstrip().lstrip("#").partition(":")
        key, value = key.strip().lower(), value.strip().lower()
        mentioned = [name for name in (*_DIRECTIVES, *_POSES)  # a line starting "# unit…:" or "# tool… =" is a setting
                     if re.match(rf"\s*#\s*{name.rstrip('s')}\w*\s*[:=]", line.lower())]
        if colon and key in _POSES and key not in settings:
            settings[key] = value
        elif mentioned and mentioned[0] in _POSES:
            raise ValueError(f"{path}: header line {line.strip()!r}: write it once as "
                             f"'# {mentioned[0]}: x y z roll pitch yaw'")
        elif colon and key in _DIRECTIVES and value in _DIRECTIVES[key] and key not in settings:
            settings[key] = value
        elif mentioned:  # a misspelt or repeated setting must not be ignored silently
            name = mentioned[0]
            raise ValueError(f"{path}: header line {line.strip()!r}: write it once as "
                             + " or ".join(f"'# {name}: {v}'" for v in _DIRECTIVES[name]))
    return settings, lines


def _columns(path: Path, names: list[str]) -> list[str]:
    """The header's column names (:func:`~armlab.files.csv_table`'s; optional ones spelt as documented); errors name
    what is wrong."""
    lowered = [name.lower() for name in names]
    repeated = sorted({name for name, low in zip(names, lowered, strict=True)
                       if lowered.count(low) > 1})  # not a bound: a count of names
    if repeated:
        raise ValueError(f"{path}: column(s) {', '.join(repeated)} appear more than once in the header")
    if tuple(names[:7]) != _DH_COLUMNS:
        raise ValueError(f"{path}: header {','.join(names)!r} must start with {','.join(_DH_COLUMNS)}")
    known = {c.lower(): c for c in _OPTIONAL_COLUMNS}
    extra = names[7:]
    unknown = [c or "''" for c in extra if c.lower() not in known]  # an empty name (a,,b) shown as ''
    if unknown:
        raise ValueError(f"{path}: unknown column(s) {', '.join(unknown)}; allowed after "
                         f"{','.join(_DH_COLUMNS)}: {','.join(_OPTIONAL_COLUMNS)}")
    extra = [known[c.lower()] for c in extra]
    orphans = [c for c in extra if c in _COM_COLUMNS + _INERTIA_COLUMNS and "mass" not in extra]
    if orphans:
        raise ValueError(f"{path}: column(s) {', '.join(orphans)} need the mass column")
    return list(_DH_COLUMNS) + extra


def _is_kind(text: str) -> TypeGuard[Literal["R", "T"]]:
    """Is ``text`` a joint type of the table (R revolute, T prismatic)?"""
    return text in _KINDS


def _angle(value: float, deg: bool, what: str) -> float:
    """A DH angle (α or θ) in radians; in a radian table, one beyond ±2π can only be degrees: an error.

    Joint limits are not held to ±2π (a wrist may turn ±400°): :func:`read_dh_csv` converts them with ``# units``.
    """
    if deg:
        return float(np.radians(value))
    if abs(value) > 2 * np.pi + 1e-9:
        raise ValueError(f"{what} = {value:g} is beyond ±2π rad: angles are radians unless the file "
                         "has the line '# units: deg' (add it if the table is in degrees)")
    return value


def _positive_or_none(text: str, what: str) -> float | None:
    if text == "":
        return None
    value = file_number(text, what)
    if value <= 0:
        raise ValueError(f"{what} = {value:g} is not allowed: a limit is > 0 (leave it empty if unknown)")
    return value


def read_dh_csv(path: str | Path) -> tuple[DHTable, list[JointLimits], list[DHInertial] | None]:
    """Read a DH table file (see the module docstring): the table (radians), limits (SI) and mass data.

    The mass data is ``None`` when the file has no ``mass`` column (a kinematic arm). Errors name the
    bad row and column. (The drive columns are read by :func:`from_dh_csv`.)
    """
    return _read(Path(path))[:3]


def _read(path: Path) -> tuple[DHTable, list[JointLimits], list[DHInertial] | None, dict[str, list[str]],
                              list[float] | None, NDArray | None, NDArray | None]:
    """:func:`read_dh_csv`'s three, the text cells of the drive columns given (column → one cell per row), the
    links' collision radii (m; ``None`` without the ``radius`` column) and the ``# base:`` and ``# tool:`` header
    lines as 4×4 poses (``None`` where absent)."""
    settings, lines = _header_comments(path, read_text(path, "DH table").splitlines())
    deg = settings.get("units") == "deg"
    base, tool = (_pose(path, key, settings[key], deg) if key in settings else None for key in _POSES)
    header, records = csv_table(lines, f"{path}: the DH table")  # trailing commas dropped
    columns = _columns(path, header)
    rows: list[DHRow] = []
    limits, inertials, radii = [], [], []
    drive_cells: dict[str, list[str]] = {name: [] for name in columns if name in DRIVE_COLUMNS}
    for number, values in records:
        if len(values) != len(columns):
            raise ValueError(f"{path}: row {number} has {len(values)} values; expected {len(columns)} "
                             f"({','.join(columns)})")
        if len(rows) == MAX_JOINTS:
            raise ValueError(f"{path}: more than {MAX_JOINTS} rows: armlab takes arms of at most {MAX_JOINTS} "
                             "joints (its plots, replay and numerical IK are not made for longer chains)")
        record = {k: v.strip() for k, v in zip(columns, values, strict=True)}
        where = f"{path}: row {number}"
        kind = record["type"].upper()
        if not _is_kind(kind):
            raise ValueError(f"{where}: type {record['type']!r} is not allowed (R or T)")
        a, alpha, d, theta = (file_number(record[k], f"{where}: {k}") for k in ("a", "alpha", "d", "theta"))
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
            lo, hi = (file_number(record[k], f"{where}: {k}") for k in ("lower", "upper"))
            if kind == "R" and deg:
                lo, hi = float(np.radians(lo)), float(np.radians(hi))
            if lo >= hi:  # not a bound: a file's own limits, as given
                raise ValueError(f"{where}: lower = {lo} must be below upper = {hi}")
            limits.append(JointLimits(lo, hi, effort, velocity))
        if "mass" in record:
            inertials.append(_dh_inertial(record, where))
        for name, cells in drive_cells.items():
            cells.append(record[name])
        if "radius" in record:
            radii.append(_radius(record["radius"], f"{where}: radius"))
    if not rows:
        raise ValueError(f"{path}: the DH table has no rows")
    # _header_comments let only "standard" or "modified" through; absent is standard
    table = DHTable(tuple(rows), "modified" if settings.get("convention") == "modified" else "standard")
    return (table, limits, inertials if "mass" in columns else None, drive_cells,
            radii if "radius" in columns else None, base, tool)


def _radius(text: str, what: str) -> float:
    """A link's collision radius (m) from its cell: a finite number ≥ 0 (0: the link has no shape)."""
    value = file_number(text, what) if text else -1.0
    if not value >= 0:
        raise ValueError(f"{what} = {text or '(empty)'} is not allowed: a collision radius is a number > 0 m, or 0 "
                         "for a link with no collision shape")
    return value


def _dh_inertial(record: dict[str, str], where: str) -> DHInertial:
    """A row's mass properties (empty centre-of-mass and inertia cells are 0), checked to be physical."""
    if record["mass"] == "":
        raise ValueError(f"{where}: mass is empty: every row needs a mass (kg) when the mass column is given")
    mass = file_number(record["mass"], f"{where}: mass")
    c = [file_number(record[k], f"{where}: {k}") if record.get(k) else 0.0 for k in _COM_COLUMNS]
    ixx, iyy, izz, ixy, ixz, iyz = (file_number(record[k], f"{where}: {k}") if record.get(k) else 0.0
                                    for k in _INERTIA_COLUMNS)
    inertia = ((ixx, ixy, ixz), (ixy, iyy, iyz), (ixz, iyz, izz))
    check_inertia(mass, np.array(inertia), where)
    return DHInertial(mass, (c[0], c[1], c[2]), inertia)


def _pose(path: Path, key: str, text: str, deg: bool) -> NDArray:
    """The ``# base:`` / ``# tool:`` header text ``x y z roll pitch yaw`` (commas allowed) as a 4×4 pose."""
    parts = text.replace(",", " ").split()
    if len(parts) != 6:
        raise ValueError(f"{path}: '# {key}: {text}' needs six numbers x y z roll pitch yaw (m, then the table's "
                         "angle units)")
    x, y, z, *angles = (file_number(part, f"{path}: {key}") for part in parts)
    roll, pitch, yaw = np.radians(angles) if deg else angles
    return homogeneous((T_Z6(yaw) @ T_Z5(pitch) @ T_Z4(roll))[:3, :3], np.array([x, y, z]))


def _axes(table: DHTable, locating: LocatingTable, base: NDArray, limits: Sequence[JointLimits]
          ) -> list[tuple[tuple[float, float, float], ...]]:
    """Each link's collision axis along its DH offsets, in its link frame {i} (m): a standard link runs d_i along
    z_{i−1}, then a_i along x_i; a modified link a_i along x_i, then d_{i+1} along z_{i+1} (its capsules follow
    the offsets, not the shortcut between its joints). A prismatic link (a boom) reaches back from its joint's
    origin by its upper stroke: at full stroke it still spans from the joint to its end."""
    zero = np.zeros(table.n)
    dh = base @ table.frames(zero)  # DH frames 0 … n in the base frame, (n+1, 4, 4)
    links = locating.frames(zero)[1:table.n + 2]  # link frames {1} … {n} and the tool
    out = []
    for i in range(1, table.n + 1):
        row = table.rows[i - 1]
        if table.convention == "standard":
            start, corner = dh[i - 1, :3, 3], dh[i - 1, :3, 3] + row.d * dh[i - 1, :3, 2]
        else:
            start = dh[i, :3, 3]
            corner = dh[i, :3, 3] + (table.rows[i].a * dh[i, :3, 0] if i < table.n else 0.0)
        to_link = np.linalg.inv(links[i - 1])
        points = [to_link[:3, :3] @ p + to_link[:3, 3] for p in (start, corner)] + [links[i][:3, 3] @ to_link[:3, :3].T
                                                                                    + to_link[:3, 3]]
        upper = limits[i - 1].upper
        if row.kind == "T" and upper is not None and upper > 0:  # not a bound: a file's own limit, as given
            points.insert(0, points[0] - upper * np.array([0.0, 0.0, 1.0]))
        out.append(tuple((float(p[0]), float(p[1]), float(p[2])) for p in points))
    return out


def _dh_in_links(table: DHTable, locating: LocatingTable, base: NDArray) -> list[NDArray]:
    """Each DH frame i in the URDF's link frame {i} (``base``: DH frame 0 in the base frame): X = T_{{i}}⁻¹ · T_i,
    constant in q, both in the base frame."""
    zero = np.zeros(table.n)
    urdf_frames, dh_frames = locating.frames(zero)[1:table.n + 1], base @ table.frames(zero)[1:]
    return [np.linalg.solve(F, D) for F, D in zip(urdf_frames, dh_frames, strict=True)]


def from_dh(
    table: DHTable,
    limits: Sequence[JointLimits],
    inertials: Sequence[DHInertial] | None = None,
    radii: Sequence[float] | None = None,
    name: str = "dh_arm",
    base: NDArray | None = None,
    tool: NDArray | None = None,
) -> Arm:
    """An arm from a DH table: its URDF comes from the same builder as the paper arms'.

    ``inertials`` (one per link, in the links' DH frames) are moved into the URDF's link frames {i};
    ``None`` or all masses 0 gives a kinematic arm (``has_dynamics`` False, no ``<inertial>``). ``radii``
    (m, one per link): each link's collision capsules, along its offsets (0: the link has no shape); ``None``: the
    arm has no collision geometry. ``base``
    (4×4) is DH frame 0 in the arm's base frame and ``tool`` (4×4) the tool frame in DH frame n
    (``None``: the identity; :func:`dh_base_tool` gives them back).
    """
    base_pose = np.eye(4) if base is None else np.asarray(base, dtype=float)
    tool_pose = None if tool is None else np.asarray(tool, dtype=float)
    plain = table.locating_table()
    first = plain.rows[0]
    T0 = base_pose @ first.T_fixed  # the base pose goes into the first row: no transform is added in code
    placed = JointRow(first.name, first.kind, tuple(T0[:3, 3]), first.k, tuple(map(tuple, T0[:3, :3])))
    locating = LocatingTable((placed, *plain.rows[1:]),
                             tool=plain.tool if tool_pose is None else plain.tool @ tool_pose)
    n = table.n
    inertials = inertials or ()  # None: a kinematic arm
    has_dynamics = any(body.mass > 0 for body in inertials)
    bodies = tuple(Body(0.0, 0.03) for _ in range(n))
    if has_dynamics:
        if len(inertials) != n:
            raise ValueError(f"{name}: need {n} link inertials, got {len(inertials)}")
        size = sum(abs(row.a) + abs(row.d) for row in table.rows) + sum(
            max(abs(lim.lower or 0.0), abs(lim.upper or 0.0)) for row, lim in zip(table.rows, limits, strict=True)
            if row.kind == "T")
        for i, body in enumerate(inertials, start=1):
            check_com_distance(float(np.linalg.norm(body.com)), size, f"{name}: link {i}")
        # link i carries both its DH frame i and the URDF's frame {i}
        bodies = tuple(_moved(body, X) for body, X in
                       zip(inertials, _dh_in_links(table, locating, base_pose), strict=True))
    points = tuple(Point(f"O{i}", i, (0.0, 0.0, 0.0)) for i in range(1, n))
    if tool_pose is None:  # the tool is DH frame n
        points += (Point(f"O{n}", n + 1, (0.0, 0.0, 0.0)),)
    else:
        on = np.linalg.solve(tool_pose, np.array([0.0, 0.0, 0.0, 1.0]))[:3]  # DH frame n's origin, in the tool frame
        points += (Point(f"O{n}", n + 1, (float(on[0]), float(on[1]), float(on[2]))), Point("tool", n + 1, (0, 0, 0)))
    if radii is not None:
        if len(radii) != n:
            raise ValueError(f"{name}: need {n} link radii, got {len(radii)}")
        bodies = tuple(replace(body, radius=float(r), collides=True, axis=axis) if r > 0 else body
                       for body, r, axis in zip(bodies, radii, _axes(table, locating, base_pose, limits), strict=True))
    return Arm(
        name=name,
        paper="user DH table",
        parameters={f"{key}{i + 1}": getattr(row, key) for i, row in enumerate(table.rows)
                    for key in ("a", "alpha", "d", "theta")},
        notes={},
        table=locating,
        bodies=bodies,
        limits=tuple(limits),
        points=points,
        tool_name=f"O{n}" if tool_pose is None else "tool",
        gravity=(0.0, 0.0, -9.81),
        forward_fn=lambda q: _dh_forward(table, base_pose, tool_pose, q),
        has_dynamics=has_dynamics,
        dh=table,
        tool_source="DH frame n" if tool_pose is None else "DH frame n moved by the table's '# tool:' pose",
    )


def _moved(body: DHInertial, X: NDArray) -> Body:
    """``body`` (in DH frame i) as a :class:`Body` in the link frame {i}, where DH frame i is ``X`` in {i}."""
    R = X[:3, :3]
    com = R @ np.asarray(body.com) + X[:3, 3]
    inertia = R @ np.asarray(body.inertia) @ R.T
    return Body(body.mass, 0.03, com=(float(com[0]), float(com[1]), float(com[2])),
                inertia=tuple(map(tuple, inertia.tolist())))


def from_dh_csv(path: str | Path) -> Arm:
    """An arm from a DH table file (:func:`read_dh_csv`), named after the file, placed by its ``# base:`` and
    ``# tool:`` lines, with the drive train of its drive columns (:func:`armlab.drives.read.drive_train`; none:
    ideal drives) and the collision capsules of its ``radius`` column."""
    table, limits, inertials, drive_cells, radii, base, tool = _read(Path(path))
    arm = from_dh(table, limits, inertials, radii, name=Path(path).stem, base=base, tool=tool)
    return arm.with_drives(drive_train(drive_cells, arm.n, str(path)) if drive_cells else None)


def dh_base_tool(arm: Arm) -> tuple[NDArray, NDArray]:
    """A DH arm's base (DH frame 0 in the base frame) and tool (the tool frame in DH frame n) poses, 4×4 each."""
    if arm.dh is None:
        raise ValueError(f"{arm.name} has no DH table")
    plain = arm.dh.locating_table()
    base = arm.table.rows[0].T_fixed @ np.linalg.inv(plain.rows[0].T_fixed)
    return base, np.linalg.solve(plain.tool, arm.table.tool)


def dh_inertials(arm: Arm) -> list[DHInertial] | None:
    """A DH arm's link mass properties in the links' DH frames, as its table gives them (``None``: a kinematic arm).

    The inverse of :func:`from_dh`'s move into the URDF's link frames: a centre of mass typed as ``cy = −0.2``
    in DH frame i comes back as −0.2 (to rounding), whatever frame {i} the URDF uses.
    """
    if arm.dh is None:
        raise ValueError(f"{arm.name} has no DH table")
    if not arm.has_dynamics:
        return None
    out = []
    masses, coms, inertias = arm.mass_properties()
    for mass, com, inertia, X in zip(masses, coms, inertias, _dh_in_links(arm.dh, arm.table, dh_base_tool(arm)[0]),
                                     strict=True):
        R = X[:3, :3]
        c, I = _rounded(R.T @ (com - X[:3, 3])), _rounded(R.T @ inertia @ R)
        out.append(DHInertial(float(mass), (float(c[0]), float(c[1]), float(c[2])), tuple(map(tuple, I.tolist()))))
    return out


def _rounded(values: NDArray) -> NDArray:
    """``values`` with the round-off of a frame change (below 1e-14 of the largest, e.g. 2e-35) set to 0."""
    return np.where(np.abs(values) < 1e-14 * np.abs(values).max(initial=0.0), 0.0, values)


def _dh_forward(table: DHTable, base: NDArray, tool: NDArray | None, q: np.ndarray) -> Forward:
    """The DH frames' origins O1 … On (and the tool point, with a tool pose), in the base frame; the tool frame
    is DH frame n (times ``tool``)."""
    first, *rest = table.steps
    steps = (ZStep(base if first.pre is None else base @ first.pre, first.revolute, first.post), *rest)
    named: dict[str, tuple[int, ArrayLike]] = {f"O{i}": (i, (0.0, 0.0, 0.0)) for i in range(1, table.n + 1)}
    if tool is not None:
        named["tool"] = (table.n, tool[:3, 3])
    pose, points = chain_points(q, steps, named, tool)
    return Forward(pose, points)
