"""What every reader of a user's arm file (:mod:`~armlab.models.read_dh`, :mod:`~armlab.models.read_urdf`) enforces.

The file is read as UTF-8 text of bounded size (:func:`read_text`); every number in it is finite and at
most :data:`MAX_FILE_NUMBER` in magnitude (:func:`file_number`); the arm has at most :data:`MAX_JOINTS`
joints. Violations are a one-line ``ValueError`` naming the file, the bad value and what is allowed.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from armlab.files import read_input

__all__ = ["MAX_FILE_NUMBER", "MAX_JOINTS", "file_number", "read_text"]

#: The most joints an arm may have. Serial arms have a handful; a 64-joint DH arm with masses still
#: simulates (1 s of motion in about 1 s, plus ~45 s for its 64-curve plots and replay on 2 shared
#: cores); a longer chain (a 200-row table) is refused up front instead of failing late.
MAX_JOINTS = 64

#: Largest magnitude of any number in a user's arm file (lengths, angles, masses, inertias, limits): far beyond
#: any arm, and small enough that squares and products of them stay finite (no inf or NaN downstream).
MAX_FILE_NUMBER = 1e12


def file_number(text: str | None, what: str) -> float:
    """``text`` as a finite number of magnitude ≤ :data:`MAX_FILE_NUMBER`; ``what`` names it in the error."""
    try:
        value = float(text or "")
    except ValueError:
        raise ValueError(f"{what} = {text!r} is not a number") from None
    if not np.isfinite(value):
        raise ValueError(f"{what} = {text!r} is not a finite number")
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
