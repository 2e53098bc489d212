"""The arms: one module per paper arm, each citing its paper, plus users' own arms.

``get_arm(name)`` returns an :class:`~armlab.models.arm.Arm` for a paper arm's name
(see ``ARMS``), an example arm shipped with armlab (``example:arm3r``, see :func:`examples`),
a URDF file path or a DH table file (``.csv``).
"""

from __future__ import annotations

from dataclasses import fields
from importlib.resources import files
from pathlib import Path
from types import ModuleType

import numpy as np

from armlab.models import arm4r, r2t, rr, rrrr, urm6
from armlab.models.arm import Arm

__all__ = ["ARMS", "EXAMPLE", "Arm", "examples", "get_arm"]

#: Paper arms by name: their modules (each with ``Parameters``, ``build(**overrides)``, ``PAPER``).
ARMS: dict[str, ModuleType] = {"rr": rr, "rrrr": rrrr, "arm4r": arm4r, "r2t": r2t, "urm6": urm6}
#: The prefix of an example arm's name: ``example:arm3r`` is ``arm3r.csv`` of :func:`examples`.
EXAMPLE = "example:"


def examples() -> dict[str, Path]:
    """The example arms shipped with armlab (``scripts/examples/`` in the repository, ``armlab.scripts.examples``
    installed): each ``.csv`` DH table and ``.urdf`` file there by its name without suffix."""
    folder = Path(str(files("armlab.scripts.examples")))
    return {path.stem: path for path in sorted(folder.iterdir()) if path.suffix.lower() in (".csv", ".urdf")}


def get_arm(name: str, **overrides: float) -> Arm:
    """A paper arm by name (parameters overridable), an example (``example:NAME``), or a ``.urdf``/``.csv`` file."""
    if name in ARMS:
        known = [f.name for f in fields(ARMS[name].Parameters)]
        for key, value in overrides.items():
            if key not in known:
                raise ValueError(f"{name}: unknown parameter {key!r}; allowed: {', '.join(known)}")
            if not np.isfinite(value):
                raise ValueError(f"{name}: parameter {key} = {value} is not a finite number")
        return ARMS[name].build(**overrides)
    path = Path(name)
    if name.startswith(EXAMPLE):
        shipped = examples()
        if name.removeprefix(EXAMPLE) not in shipped:
            raise ValueError(f"unknown example arm {name!r}; allowed: {_names(shipped)}")
        path = shipped[name.removeprefix(EXAMPLE)]
    if path.suffix.lower() == ".urdf":
        from armlab.models.read_urdf import from_urdf

        return from_urdf(path)
    if path.suffix.lower() == ".csv":
        from armlab.models.read_dh import from_dh_csv

        return from_dh_csv(path)
    raise ValueError(f"unknown arm {name!r}; allowed: {', '.join(ARMS)}, an example ({_names(examples())}), or a "
                     ".urdf or DH .csv file")


def _names(shipped: dict[str, Path]) -> str:
    return ", ".join(EXAMPLE + stem for stem in shipped)
