"""Drive trains from files: the per-joint drive columns of a DH table, and a drive file for any arm.

The columns (:data:`DRIVE_COLUMNS`), one value per joint, the same in a DH table (optional columns) and a
drive file, each as :class:`~armlab.drives.train.DriveTrain` has it:

* ``gear_ratio`` G (default 1), ``rotor_inertia`` J_m (kg·m², motor side, default 0), ``efficiency`` η in
  (0, 1] (default 1);
* ``viscous`` B (N·m·s/rad) and ``coulomb`` T_c (N·m), joint side (default 0), and ``coulomb_negative`` T_c−
  (N·m, ≥ 0, the friction while the joint turns backwards; default T_c: symmetric; with it, ``coulomb`` is
  T_c+) — or ``viscous_motor``, ``coulomb_motor`` and ``coulomb_negative_motor``, motor side as the Robotics
  Toolbox gives them (B_m, T_c,m and |T_c−,m|: the toolbox's Tc = [T_c+, T_c−] has T_c− negative, the column
  its magnitude; converted once by :meth:`~armlab.drives.train.DriveTrain.from_motor_side`: B = G²·B_m,
  T_c± = |G|·T_c±,m). Each friction from one side, not both (they may come from different sides);
* the motors' electrics (:data:`~armlab.drives.motor.ELECTRIC_COLUMNS`, :mod:`armlab.drives.motor`): ``resistance``
  (Ω), ``inductance`` (H), ``torque_constant`` (N·m/A) and ``bus_voltage`` (V) together, with ``back_emf``
  (V·s/rad, default the torque constant) and ``peak_current`` (A, default none) if known;
* the gearboxes' elasticity (:mod:`armlab.drives.elastic`): ``stiffness`` (N·m/rad, joint side) and optionally
  ``twist_damping`` (N·m·s/rad).

A column left out takes its default (an ideal drive); a column given needs a value in every row.

A **drive file** (``--drives FILE``, ``armlab.load(…, drives=FILE)``) is a CSV file: optional ``#`` comment
lines, a header row of drive columns and optionally ``joint`` (the arm's joint names, checked, in joint
order), then one row per joint, base to tool. It gives the arm its drive train, whatever the arm (a paper
arm, a URDF, a DH table), replacing one its own file gives.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from armlab.arm_file import file_number, read_text
from armlab.drives.elastic import ELASTIC_COLUMNS, Elasticity
from armlab.drives.motor import ELECTRIC_COLUMNS, REQUIRED_ELECTRIC_COLUMNS, MotorElectrics
from armlab.drives.train import DRIVE_FIELDS, DriveTrain
from armlab.files import csv_table
from armlab.limits import check_range

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["DRIVE_COLUMNS", "drive_train", "read_drive_file", "with_drives"]

#: The drive columns of a DH table and a drive file; the ``_motor`` ones are motor side (module docstring).
DRIVE_COLUMNS = ("gear_ratio", "rotor_inertia", "efficiency", "viscous", "coulomb", "coulomb_negative",
                 "viscous_motor", "coulomb_motor", "coulomb_negative_motor", *ELECTRIC_COLUMNS, *ELASTIC_COLUMNS)


def drive_train(cells: Mapping[str, Sequence[str]], n: int, where: str) -> DriveTrain:
    """The drive train of ``n`` joints from the text ``cells`` of the drive columns given (column → n cells).

    ``where`` (the file) starts every error: an unknown column, both sides of one friction, an empty cell,
    a cell that is not a number, or a value :class:`~armlab.drives.train.DriveTrain` does not allow (with the
    row, that is the joint, and the column).
    """
    unknown = [name for name in cells if name not in DRIVE_COLUMNS]
    if unknown:
        raise ValueError(f"{where}: unknown drive column(s) {', '.join(unknown)}; allowed: {', '.join(DRIVE_COLUMNS)}")
    for name in ("viscous", "coulomb", "coulomb_negative"):
        if name in cells and f"{name}_motor" in cells:
            raise ValueError(f"{where}: give {name} (joint side) or {name}_motor (motor side), not both")
    values = {}
    for name, column in cells.items():
        for k, text in enumerate(column):
            if text.strip() == "":
                raise ValueError(f"{where}: row {k + 1}: {name} is empty: every row needs a value when the "
                                 "column is given (leave the column out for its default)")
        values[name] = np.array([file_number(text, f"{where}: row {k + 1}: {name}") for k, text in enumerate(column)])
    electric = [name for name in ELECTRIC_COLUMNS if name in values]
    missing = [name for name in REQUIRED_ELECTRIC_COLUMNS if name not in values]
    if electric and missing:
        raise ValueError(f"{where}: the motor electrics need {', '.join(missing)} too "
                         f"(given: {', '.join(electric)}; required together: {', '.join(REQUIRED_ELECTRIC_COLUMNS)})")
    if "twist_damping" in values and "stiffness" not in values:
        raise ValueError(f"{where}: twist_damping needs the stiffness column too")
    ideal = DriveTrain.ideal(n)  # a column left out
    # each friction on its own side
    motor = [name for name in ("viscous", "coulomb", "coulomb_negative") if f"{name}_motor" in values]
    try:
        given = {name: values[name] for name in DRIVE_FIELDS if name in values}
        electrics = MotorElectrics(**{name: values[name] for name in electric}) if electric else None
        elasticity = (Elasticity(**{name: values[name] for name in ELASTIC_COLUMNS if name in values})
                      if "stiffness" in values else None)
        train = DriveTrain(**{name: getattr(ideal, name) for name in DRIVE_FIELDS[:-1]} | given,
                           electrics=electrics, elasticity=elasticity)
        if motor:
            converted = DriveTrain.from_motor_side(train.gear_ratio, train.rotor_inertia, train.efficiency,
                                                   values.get("viscous_motor", ideal.viscous),
                                                   values.get("coulomb_motor", ideal.coulomb), train.coulomb_speed,
                                                   values.get("coulomb_negative_motor"))
            train = replace(train, **{name: getattr(converted, name) for name in motor})  # T_c− left out: T_c
        check_range(train.viscous, "viscous" if "viscous" not in motor else "viscous_motor (joint side: G²·B_m)",
                    key="viscous")
        return train
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None


def read_drive_file(path: str | Path, joint_names: Sequence[str]) -> DriveTrain:
    """The drive train in the drive file ``path`` (module docstring) for an arm with joints ``joint_names``.

    ``ValueError`` (naming the file) for a row count other than the arm's joints, a ``joint`` column naming
    other joints, or a bad column or value (:func:`drive_train`).
    """
    path = Path(path)
    lines = read_text(path, "drive file").splitlines()
    while lines and (not lines[0].strip() or lines[0].lstrip().startswith("#")):
        lines.pop(0)
    header, rows = csv_table(lines, f"{path}: the drive file")  # trailing commas dropped
    if not header:
        raise ValueError(f"{path}: the drive file has no header row ({', '.join(('joint', *DRIVE_COLUMNS))})")
    body = [cells for _, cells in rows]
    repeated = sorted({name for name in header if header.count(name) > 1})
    if repeated:
        raise ValueError(f"{path}: column(s) {', '.join(repeated)} appear more than once")
    n = len(joint_names)
    if len(body) != n:
        raise ValueError(f"{path}: {len(body)} drive row(s); the arm has {n} joints ({', '.join(joint_names)}): "
                         "give one row per joint, base to tool")
    for k, row in enumerate(body):
        if len(row) != len(header):
            raise ValueError(f"{path}: row {k + 1} has {len(row)} values; expected {len(header)} ({','.join(header)})")
    columns = {name: [row[i].strip() for row in body] for i, name in enumerate(header)}
    names = columns.pop("joint", None)
    if names is not None and names != list(joint_names):
        raise ValueError(f"{path}: joint column {','.join(names)} differs from the arm's joints "
                         f"{','.join(joint_names)} (one row per joint, in that order)")
    return drive_train(columns, n, str(path))


def with_drives(arm: Arm, drives: str | Path | DriveTrain | None) -> Arm:
    """``arm`` with the drive train ``drives``: a :class:`~armlab.drives.train.DriveTrain` or a drive file's path
    (:func:`read_drive_file`); ``None``: ``arm`` as it is (its own drive train, or ideal drives)."""
    if drives is None:
        return arm
    if isinstance(drives, DriveTrain):
        return arm.with_drives(drives)
    if not isinstance(drives, str | Path):
        raise ValueError(f"drives = {drives!r} is not allowed: give a drive file's path or a DriveTrain")
    return arm.with_drives(read_drive_file(drives, arm.joint_names))
