"""Users' own arms from a DH table (standard or modified), turned into a URDF by the one builder.

A **DH table** is a CSV file (the README's section "Your own arm: the DH table format"):

* optional header comment lines, in any order: ``# convention: standard`` or ``# convention: modified``
  (standard if absent) and ``# units: rad`` or ``# units: deg`` (rad if absent); ``deg`` means
  ``alpha``, ``theta`` and a revolute joint's ``lower``, ``upper`` (and ``velocity``, deg/s) are in
  degrees. Other ``#`` lines at the top are free comments.
* a header row starting ``type,a,alpha,d,theta,lower,upper`` (one row per joint; ``type`` R or T;
  lengths in metres; ``lower``/``upper`` empty for an unlimited revolute joint), then, in any order,
  the optional columns of the Robotics Toolbox's ``RevoluteDH(m=, r=, I=)``, per link in the link's
  own DH frame: ``mass`` (kg), ``cx,cy,cz`` (centre of mass, m), ``Ixx,Iyy,Izz,Ixy,Ixz,Iyz``
  (kg·m² about the centre of mass), ``effort`` (N·m or N) and ``velocity`` (rad/s or m/s) limits, and
  ``radius`` (m, > 0): the link's collision capsule along the offset to the next joint (:mod:`armlab.collision`);
  a table without it has no collision geometry.

A table without the ``mass`` column is a *kinematic* arm (``Arm.has_dynamics`` False): no masses
are invented. Missing effort/velocity limits are unknown (``None``). At most
:data:`~armlab.models.arm_file.MAX_JOINTS` rows; every number bounded (:mod:`armlab.models.arm_file`).
"""

from __future__ import annotations

import csv
import re
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Literal, TypeGuard

import numpy as np
from numpy.typing import NDArray

from armlab.kinematics.batch import chain_points
from armlab.kinematics.dh import DHRow, DHTable
from armlab.models.arm import Arm, Forward
from armlab.models.arm_file import MAX_JOINTS, file_number, read_text
from armlab.models.write_urdf import Body, JointLimits, Point, check_inertia

__all__ = ["DHInertial", "from_dh", "from_dh_csv", "read_dh_csv"]

_DH_COLUMNS = ("type", "a", "alpha", "d", "theta", "lower", "upper")
_COM_COLUMNS = ("cx", "cy", "cz")
_INERTIA_COLUMNS = ("Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz")
_OPTIONAL_COLUMNS = ("mass", *_COM_COLUMNS, *_INERTIA_COLUMNS, "effort", "velocity", "radius")
_DIRECTIVES = {"convention": ("standard", "modified"), "units": ("rad", "deg")}
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


def _is_kind(text: str) -> TypeGuard[Literal["R", "T"]]:
    """Is ``text`` a joint type of the table (R revolute, T prismatic)?"""
    return text in _KINDS


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
    value = file_number(text, what)
    if value <= 0:
        raise ValueError(f"{what} = {value:g} is not allowed: a limit is > 0 (leave it empty if unknown)")
    return value


def read_dh_csv(path: str | Path) -> tuple[DHTable, list[JointLimits], list[DHInertial] | None]:
    """Read a DH table file (see the module docstring): the table (radians), limits (SI) and mass data.

    The mass data is ``None`` when the file has no ``mass`` column (a kinematic arm). Errors name the
    bad row and column.
    """
    return _read_dh(path)[:3]


def _read_dh(path: str | Path) -> tuple[DHTable, list[JointLimits], list[DHInertial] | None, list[float] | None]:
    """:func:`read_dh_csv` and the links' collision radii (m; ``None`` without the ``radius`` column)."""
    path = Path(path)
    settings, lines = _header_comments(path, read_text(path, "DH table").splitlines())
    deg = settings.get("units") == "deg"
    reader = csv.reader(lines)
    columns = _columns(path, next(reader, None))
    rows, limits, inertials, radii = [], [], [], []
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
            if kind == "R":
                lo, hi = _angle(lo, deg, f"{where}: lower"), _angle(hi, deg, f"{where}: upper")
            if lo >= hi:
                raise ValueError(f"{where}: lower = {lo} must be below upper = {hi}")
            limits.append(JointLimits(lo, hi, effort, velocity))
        if "mass" in record:
            inertials.append(_dh_inertial(record, where))
        if "radius" in record:
            radii.append(_radius(record["radius"], f"{where}: radius"))
    if not rows:
        raise ValueError(f"{path}: the DH table has no rows")
    # _header_comments let only "standard" or "modified" through; absent is standard
    table = DHTable(tuple(rows), "modified" if settings.get("convention") == "modified" else "standard")
    return table, limits, inertials if "mass" in columns else None, radii if "radius" in columns else None


def _radius(text: str, what: str) -> float:
    """A link's collision radius (m) from its cell: a finite number > 0."""
    value = file_number(text, what) if text else -1.0
    if not value > 0:
        raise ValueError(f"{what} = {text or '(empty)'} is not allowed: a collision radius is a number > 0 m")
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


def from_dh(
    table: DHTable,
    limits: Sequence[JointLimits],
    inertials: Sequence[DHInertial] | None = None,
    radii: Sequence[float] | None = None,
    name: str = "dh_arm",
) -> Arm:
    """An arm from a DH table: its URDF comes from the same builder as the paper arms'.

    ``inertials`` (one per link, in the links' DH frames) are moved into the URDF's link frames {i};
    ``None`` or all masses 0 gives a kinematic arm (``has_dynamics`` False, no ``<inertial>``). ``radii``
    (m, one per link): each link's collision capsule; ``None``: the arm has no collision geometry.
    """
    locating = table.locating_table()
    n = table.n
    inertials = inertials or ()  # None: a kinematic arm
    has_dynamics = any(body.mass > 0 for body in inertials)
    bodies = tuple(Body(0.0, 0.03) for _ in range(n))
    if has_dynamics:
        if len(inertials) != n:
            raise ValueError(f"{name}: need {n} link inertials, got {len(inertials)}")
        # link i carries both its DH frame i and the URDF's frame {i}: X = T_{0,{i}}⁻¹ · T_{0,i}, constant in q
        zero = np.zeros(n)
        urdf_frames, dh_frames = locating.frames(zero)[1:n + 1], table.frames(zero)[1:]
        bodies = tuple(_moved(body, np.linalg.solve(F, D)) for body, F, D in
                       zip(inertials, urdf_frames, dh_frames, strict=True))
    if radii is not None:
        if len(radii) != n:
            raise ValueError(f"{name}: need {n} link radii, got {len(radii)}")
        bodies = tuple(replace(body, radius=float(r), collides=True) for body, r in zip(bodies, radii, strict=True))
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
    return Body(body.mass, 0.03, com=(float(com[0]), float(com[1]), float(com[2])),
                inertia=tuple(map(tuple, inertia.tolist())))


def from_dh_csv(path: str | Path) -> Arm:
    """An arm from a DH table file (:func:`read_dh_csv`), named after the file."""
    return from_dh(*_read_dh(path), name=Path(path).stem)


def _dh_forward(table: DHTable, q: np.ndarray) -> Forward:
    """The DH frames' origins O1 … On; the tool is DH frame n."""
    tool, points = chain_points(q, table.steps, {f"O{i}": (i, (0.0, 0.0, 0.0)) for i in range(1, table.n + 1)})
    return Forward(tool, points)
