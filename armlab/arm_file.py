"""What every reader of a user's arm file (:mod:`~armlab.models.read_dh`, :mod:`~armlab.models.read_urdf`) enforces.

The file is read as UTF-8 text of bounded size (:func:`read_text`); every number in it is a plain decimal
(``-0.5``, ``2``, ``1e-3``: no Python digit separators ``0_5``, no ``0x`` or ``inf``), finite and at most
:data:`MAX_FILE_NUMBER` in magnitude (:func:`file_number`); the arm has at most :data:`MAX_JOINTS` joints; a
link's centre of mass lies within reach of the arm (:func:`check_com_distance`). Violations are a one-line
``ValueError`` naming the file, the bad value and what is allowed.
"""

from __future__ import annotations

from pathlib import Path

from armlab.bounds import above
from armlab.files import read_input
from armlab.values import DECIMAL, NOT_FINITE, decimal

__all__ = ["COM_REACH", "MAX_FILE_NUMBER", "MAX_JOINTS", "check_com_distance", "file_number", "read_text"]

#: The most joints an arm may have. Serial arms have a handful; a 64-joint DH arm with masses still
#: simulates (1 s of motion in about 1 s, plus ~45 s for its 64-curve plots and replay on 2 shared
#: cores); a longer chain (a 200-row table) is refused up front instead of failing late.
MAX_JOINTS = 64

#: Largest magnitude of any number in a user's arm file (lengths, angles, masses, inertias, limits): far beyond
#: any arm, and small enough that squares and products of them stay finite (no inf or NaN downstream).
MAX_FILE_NUMBER = 1e12


#: A centre of mass farther from its link frame's origin than this many times the arm's size (plus 1 m) is refused:
#: no link's mass lies kilometres from its joint (the Robotics Toolbox's IRB 140 data has one 198 km away, a typo).
COM_REACH = 10.0


def file_number(text: str | None, what: str) -> float:
    """``text`` as a plain decimal (:func:`armlab.values.decimal`), finite and of magnitude ≤
    :data:`MAX_FILE_NUMBER`; ``what`` names it in the error."""
    try:
        value = decimal(text or "")
    except ValueError as reason:
        if DECIMAL.fullmatch((text or "").strip()):  # plain, but too large to be finite (400 digits)
            value = float("inf")
        elif str(reason) == NOT_FINITE:
            raise ValueError(f"{what} = {text!r} {reason}") from None
        else:
            raise ValueError(f"{what} = {text!r} is not a number: numbers in arm files are plain decimals "
                             "(e.g. 0.5, -2, 1e-3)") from None
    if abs(value) > MAX_FILE_NUMBER:
        raise ValueError(f"{what} = {text!r} is out of range: allowed |value| ≤ {MAX_FILE_NUMBER:g}")
    return value


def read_text(path: Path, what: str) -> str:
    """A user's file as text: a regular file of bounded size (:func:`armlab.files.read_input`), UTF-8."""
    raw = read_input(path, f"cannot read {what} {path}")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise ValueError(f"cannot read {what} {path}: it is not UTF-8 text") from None


def check_com_distance(distance: float, size: float, what: str) -> None:
    """``ValueError`` naming ``what`` if a centre of mass ``distance`` m from its link frame's origin lies beyond
    :data:`COM_REACH` × ``size`` + 1 m, ``size`` (m) the arm's own (its links' lengths summed): not physical."""
    bound = COM_REACH * size + 1.0
    if above(distance, bound):
        raise ValueError(f"{what}: the centre of mass is {distance:.6g} m from its link frame, beyond "
                         f"{bound:.6g} m ({COM_REACH:g} × the arm's size {size:.6g} m + 1 m): not physical; "
                         "check the centre of mass (m, in the link's frame)")
