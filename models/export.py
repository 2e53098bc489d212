"""An arm leaving armlab: its URDF (any arm) and its DH table (an arm made from one), for ROS, Drake, Pinocchio, MuJoCo.

``export(arm, urdf=FILE)`` writes the arm's URDF from the one builder (:meth:`armlab.models.arm.Arm.urdf`):
joint i's origin and axis are the arm's matrix of nominal geometry, each link's inertial its mass, centre of
mass and inertia in the URDF's link frame {i}, the drive train (if the arm carries one) as Drake's own tags
(:mod:`armlab.models.write_urdf`); an unknown effort or velocity limit as 0, ROS's "none" (ROS's parser, and
so Pinocchio's, needs both; armlab reads 0 as unknown and gives Drake none). A URDF arm leaves with armlab's
link names (``link1`` … ``linkN``) and drawn visuals, not its meshes. ``export(arm, dh=FILE)`` writes the DH
table of an arm made from one, in the format :mod:`armlab.models.read_dh` reads (radians, the link mass data
back in the DH frames (:func:`~armlab.models.read_dh.dh_inertials`), its base and tool poses as header
lines, its drive train as the joint-side drive columns (:meth:`armlab.drives.train.DriveTrain.fields`) and its
collision capsules as the ``radius`` column), every number as the shortest decimal that reads back to the same
float. Both files read back to the same arm (tests/test_export.py: forward kinematics, Jacobian and inverse
dynamics equal to 1e-9, through Drake and through Pinocchio; the DH table's drive train and radii too).

Every path is checked before anything is written (:func:`check_output`), and each file is written completely
or not at all (:func:`armlab.files.write_file`). A URDF MuJoCo will not load (a kinematic arm, a moving link
without mass or rotational inertia, principal moments off the triangle inequality A + B ≥ C:
:func:`mujoco_refusal`) is still written, for the programs that read it, with a one-line
:class:`MujocoWarning` saying why.
"""

from __future__ import annotations

import os
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from armlab.bounds import above, below
from armlab.drives.train import COULOMB_SPEED
from armlab.files import write_file
from armlab.kinematics.locating import orientation_angles
from armlab.models.meshes import parse_xml
from armlab.models.read_dh import dh_base_tool, dh_inertials
from armlab.values import shown

if TYPE_CHECKING:
    from armlab.drives.train import DriveTrain
    from armlab.models.arm import Arm

__all__ = ["MUJOCO_MINVAL", "MujocoWarning", "check_output", "dh_text", "export", "mujoco_refusal"]

#: MuJoCo's mjMINVAL: the mass (kg) and principal moments of inertia (kg·m²) every moving body must exceed.
MUJOCO_MINVAL = 1e-15


class MujocoWarning(UserWarning):
    """An exported URDF that MuJoCo will not load, and why (Drake, Pinocchio and ROS read it)."""


def mujoco_refusal(urdf: str) -> str | None:
    """Why MuJoCo will not load the URDF text ``urdf``, in one phrase, or ``None``: a moving link (the child of a
    joint that is not fixed) whose mass or smallest principal moment of inertia is not above
    :data:`MUJOCO_MINVAL` (no ``<inertial>``: a kinematic arm, whose file MuJoCo refuses or, where the link has
    collision geometry, reads with masses it infers from that geometry, not the arm's; a point mass), or whose
    principal moments A ≤ B ≤ C break A + B ≥ C (beyond the slack of :mod:`armlab.bounds`; a value on it MuJoCo
    may take either way by round-off: a correction keeps a margin, as the UR10's)."""

    robot = ET.fromstring(urdf)
    moving = [str(j.find("child").get("link"))  # type: ignore[union-attr]  # URDF: a joint has a child
              for j in robot.findall("joint") if j.get("type") != "fixed"]
    links = {str(link.get("name")): link for link in robot.findall("link")}
    massless: list[str] = []
    points: list[str] = []
    broken: list[str] = []
    for name in moving:
        inertial = links[name].find("inertial")
        mass_tag = None if inertial is None else inertial.find("mass")
        mass = 0.0 if mass_tag is None else float(mass_tag.get("value", "0"))
        tag = None if inertial is None else inertial.find("inertia")
        if not above(mass, MUJOCO_MINVAL):
            massless.append(name)
            continue
        i = {k: float("0" if tag is None else tag.get(k, "0")) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
        a, b, c = np.linalg.eigvalsh([[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]],
                                     [i["ixz"], i["iyz"], i["izz"]]])
        if not above(a, MUJOCO_MINVAL):
            points.append(name)
        elif below(a + b, c):
            broken.append(name)
    reasons = ([f"{', '.join(massless)} without mass"] if massless else []) + (
        [f"{', '.join(points)} without rotational inertia (point masses)"] if points else []) + (
        [f"{', '.join(broken)} off the triangle inequality of the principal moments"] if broken else [])
    return "; ".join(reasons) or None


def check_output(path: str | Path, suffix: str, what: str) -> Path:
    """``path`` as a Path if a file ending in ``suffix`` can be written there; else a ``ValueError`` naming ``what``
    (the option): a folder or a name ending in ``/``, another suffix, or a folder that cannot be written."""
    text = str(path)
    out = Path(path)
    if not text.strip() or text.endswith(("/", os.sep)) or out.is_dir():
        raise ValueError(f"{what} {text!r} is a folder: give a file name ending in {suffix}")
    if out.suffix.lower() != suffix:
        raise ValueError(f"{what} {text!r} must end in {suffix}")
    if out.exists() and not out.is_file():
        raise ValueError(f"{what} {text!r} exists and is not a regular file")
    folder = next(parent for parent in out.absolute().parents if parent.exists())
    if not folder.is_dir() or not os.access(folder, os.W_OK | os.X_OK):
        raise ValueError(f"{what} {text!r}: cannot write in {folder}")
    return out


def _number(value: float) -> str:
    """The shortest decimal that reads back to ``value`` (``0`` for zero, also −0)."""
    return repr(float(value)) if value != 0 else "0"


def dh_text(arm: Arm) -> str:
    """The DH table file of ``arm`` (made from a DH table: ``arm.dh``), in :mod:`armlab.models.read_dh`'s format.

    The drive train (``arm.drives``, if any) leaves as the columns :meth:`~armlab.drives.train.DriveTrain.fields`
    (joint side, as :func:`armlab.drives.read.drive_train` reads them), the collision capsules (if any link
    collides) as ``radius`` (m; 0 for a link without a shape). ``ValueError`` for an arm without a DH description
    (its geometry is a URDF's or a paper's matrix), and for what a DH table cannot hold: a drive train's Coulomb
    speed other than :data:`~armlab.drives.train.COULOMB_SPEED`.
    """
    table = arm.dh
    if table is None:
        raise ValueError(f"{arm.name} has no DH description (its geometry is not a DH table): export it with --urdf")
    drives = arm.drives
    if drives is not None and drives.coulomb_speed != COULOMB_SPEED:  # exact: the default is the one a table reads
        raise ValueError(f"{arm.name}: its drive train's coulomb_speed = {drives.coulomb_speed:g} rad/s cannot be "
                         f"written in a DH table (it reads {COULOMB_SPEED:g} rad/s): export it with --urdf")
    colliding = [body.collides for body in arm.bodies]
    base, tool = dh_base_tool(arm)
    lines = [" ".join(f"# {arm.name}: exported by armlab from {arm.paper}".splitlines()),  # one line, whatever the name
             f"# convention: {table.convention}", "# units: rad"]
    for key, pose in (("base", base), ("tool", tool)):
        if np.abs(pose - np.eye(4)).max() > 0:
            values = [*pose[:3, 3], *orientation_angles(pose[:3, :3])]
            lines.append(f"# {key}: {' '.join(map(_number, values))}")
    inertials = dh_inertials(arm)
    header = ["type", "a", "alpha", "d", "theta", "lower", "upper"]
    if inertials is not None:
        header += ["mass", "cx", "cy", "cz", "Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz"]
    header += ["effort", "velocity"]
    if drives is not None:
        header += drives.fields()
    if any(colliding):
        header.append("radius")
    lines.append(",".join(header))
    for i, (row, lim) in enumerate(zip(table.rows, arm.limits, strict=True)):
        cells = [row.kind, *map(_number, (row.a, row.alpha, row.d, row.theta))]
        cells += ["" if value is None else _number(value) for value in (lim.lower, lim.upper)]
        if inertials is not None:
            body = inertials[i]
            inertia = np.asarray(body.inertia)
            cells += [_number(body.mass), *map(_number, body.com),
                      *(_number(inertia[j, k]) for j, k in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)))]
        cells += ["" if value is None else _number(value) for value in (lim.effort, lim.velocity)]
        if drives is not None:
            cells += [_number(drives.per_joint(name)[i]) for name in drives.fields()]
        if any(colliding):
            cells.append(_number(arm.bodies[i].radius if colliding[i] else 0.0))
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


def _check_names(text: str, arm: Arm, path: str | Path) -> None:
    """``ValueError`` naming the URDF file ``path`` unless the URDF ``text`` of ``arm`` is XML without a document type
    (:func:`armlab.models.meshes.parse_xml`) that reads back the arm's name and joint names as they are (a name of
    characters XML cannot hold is refused before anything is written)."""
    try:
        robot = parse_xml(text, f"URDF file {path}")
    except ET.ParseError as error:
        raise ValueError(f"URDF file {path}: a name of the arm {shown(arm.name)} or of its joints cannot be written "
                         f"as XML ({error}): rename it") from None
    names = [robot.get("name"), *(joint.get("name") for joint in robot.findall("joint")
                                  if joint.get("type") != "fixed")]
    if names != [arm.name, *arm.joint_names]:
        raise ValueError(f"URDF file {path}: a name of the arm {shown(arm.name)} or of its joints does not read back "
                         "from the URDF as it is: rename it")


def export(arm: Arm, urdf: str | Path | None = None, dh: str | Path | None = None,
           drives: DriveTrain | None = None) -> list[Path]:
    """Write ``arm``'s URDF to ``urdf`` and/or its DH table to ``dh`` (module docstring); the files written.

    ``drives``: the drive train written into both files (the URDF's Drake tags, the DH table's drive columns);
    ``None``: the arm's own, if it carries one. Both paths are checked (and the DH description's existence)
    before anything is written. A :class:`MujocoWarning` when MuJoCo will not load the URDF
    (:func:`mujoco_refusal`).
    """
    if urdf is None and dh is None:
        raise ValueError("nothing to export: give a URDF file (urdf=, --urdf) or a DH table file (dh=, --dh)")
    texts = []
    if urdf is not None:
        check_output(urdf, ".urdf", "URDF file")
    if dh is not None:
        check_output(dh, ".csv", "DH table file")
    train = drives if drives is not None else arm.drives
    if dh is not None:
        texts.append((dh, dh_text(arm.with_drives(train))))
    if urdf is not None:
        texts.insert(0, (urdf, arm.urdf(train, ros_limits=True, upright=True)))
    if urdf is not None:
        _check_names(texts[0][1], arm, urdf)
    written = [write_file(path, text) for path, text in texts]
    for path, text in zip(written, (text for _, text in texts), strict=True):  # read back before saying "wrote"
        if path.read_bytes() != text.encode():
            raise ValueError(f"{path}: the file reads back other than it was written")
    refusal = None if urdf is None else mujoco_refusal(texts[0][1])
    if refusal is not None:
        warnings.warn(MujocoWarning(f"MuJoCo will not load {urdf} as it is: {arm.name}'s {refusal}, and MuJoCo needs "
                                    "mass and inertia on every moving link (it refuses the file, or infers masses from "
                                    "the collision geometry, not the arm's; Drake, Pinocchio and ROS read it)"),
                      stacklevel=2)
    return written
