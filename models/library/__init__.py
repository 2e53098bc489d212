"""Well-known arms by name (issue 22): ``armlab.load("puma560")``, ``"ur5"``, ``"ur10"``, ``"panda"``, ``"stanford"``,
``"irb140"``, ``"kr5"``.

Each is one module of this package named after the arm, with ``SOURCE`` (its citation, what ``armlab list`` and
``armlab show`` print) and ``build() -> Arm``; every number in it is cited where it is written, and where a source's
number is not physical the module says how armlab handles it. They are found, not listed: a module of this package
with ``build`` and ``SOURCE`` is one (:data:`LIBRARY`, without importing them: start-up time). Unlike a paper arm
(:data:`armlab.models.ARMS`) they take no parameter overrides (their numbers are the sources') and have no committed
URDF (it is generated in memory, like a DH table's).
"""

from __future__ import annotations

import importlib
import pkgutil

from armlab.models.arm import Arm

__all__ = ["LIBRARY", "library_arm"]

#: The library arms' names, sorted (their modules, imported when first built).
LIBRARY: tuple[str, ...] = tuple(sorted(info.name for info in pkgutil.iter_modules(__path__)
                                        if not info.name.startswith("_")))


def library_arm(name: str) -> Arm:
    """The library arm ``name`` (one of :data:`LIBRARY`), built from its module's cited numbers."""
    if name not in LIBRARY:
        raise ValueError(f"unknown library arm {name!r}; allowed: {', '.join(LIBRARY)}")
    return importlib.import_module(f"{__name__}.{name}").build()
