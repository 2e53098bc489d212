"""The arms: one module per paper arm, each citing its paper, the library arms, users' own arms, and their plant.
May import: base, kinematics, drives.

``get_arm(name)`` returns an :class:`~armlab.models.arm.Arm` for a paper arm's name
(see ``ARMS``), an example arm shipped with armlab (``example:arm3r``, see :func:`examples`),
a URDF file path or a DH table file (``.csv``).

The paper arms are found, not listed: every module of this package with its URDF beside it,
``build``, ``PAPER`` and ``Parameters`` is one, named after its module (``rr.py`` builds ``rr``,
committed as ``rr.urdf``), and ``ARMS`` holds them in the order of their ``PAPER`` citations (the
paper's number first: paper 000's Fig. 1 arm rr before its Figs. 11-25 arm rrrr, then arm4r, r2t,
urm6). So a new paper arm is its module and its URDF, nothing else; what only it has (closed-form
IK, paper motion, scheme) are fields its ``build`` sets (:mod:`armlab.models.extras`). An arm module
outside this package (a plug-in, the tests' own arm) calls :func:`register` when it is imported; it
follows the package's arms.
"""

from __future__ import annotations

import importlib
import math
import pkgutil
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import fields
from importlib.resources import files
from pathlib import Path
from types import ModuleType

from armlab.arm_file import MAX_FILE_NUMBER
from armlab.limits import real_number
from armlab.models.arm import MODELS_DIR, Arm
from armlab.values import shown

__all__ = ["ARMS", "EXAMPLE", "Arm", "examples", "get_arm", "paper_arms", "register", "unregister"]


def _is_arm_module(module: ModuleType) -> bool:
    """An arm module: ``build(**overrides)``, ``PAPER`` (its citation) and ``Parameters`` (a dataclass)."""
    return all(hasattr(module, name) for name in ("build", "PAPER", "Parameters"))


def _package_arms() -> dict[str, ModuleType]:
    """This package's arm modules by name (the module's), in the order of their ``PAPER`` citations.

    Only a module with its committed URDF beside it (``rr.py`` and ``rr.urdf``) is imported to be checked, so
    the helpers (``custom``, ``urdf``, …) stay unimported until used.
    """
    names = (info.name for info in pkgutil.iter_modules(__path__) if (MODELS_DIR / f"{info.name}.urdf").is_file())
    modules = (importlib.import_module(f"{__name__}.{name}") for name in names)
    found = sorted((module for module in modules if _is_arm_module(module)), key=lambda module: module.PAPER)
    return {module.__name__.rpartition(".")[2]: module for module in found}


class _Arms(Mapping[str, ModuleType]):
    """The paper arms by name, found on first lookup (:func:`_package_arms`), not when :mod:`armlab.models` is
    imported: importing the package imports no arm module. Registered arms (:func:`register`) follow."""

    def __init__(self) -> None:
        self._found: dict[str, ModuleType] | None = None
        self._registered: dict[str, ModuleType] = {}

    def _arms(self) -> dict[str, ModuleType]:
        if self._found is None:
            self._found = _package_arms()
        return self._found | self._registered

    def __getitem__(self, name: str) -> ModuleType:
        return self._arms()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._arms())

    def __len__(self) -> int:
        return len(self._arms())

    def add(self, name: str, module: ModuleType) -> None:
        """Register ``module`` as the arm ``name``, after the arms found."""
        self._registered[name] = module

    def remove(self, name: str) -> None:
        """Take the registered arm ``name`` back; ``ValueError`` for a name not registered (a package arm's too)."""
        if name not in self._registered:
            raise ValueError(f"arm {name!r} was not registered")
        del self._registered[name]


#: Paper arms by name: their modules (each with ``Parameters``, ``build(**overrides)``, ``PAPER``), found on first
#: lookup.
ARMS = _Arms()


def register(module: ModuleType) -> None:
    """Add the arm module ``module`` (``build``, ``PAPER``, ``Parameters``) to :data:`ARMS` under its module's
    name, after the arms there; ``ValueError`` if it is not an arm module or its name is taken."""
    name = module.__name__.rpartition(".")[2]
    if not _is_arm_module(module):
        raise ValueError(f"module {module.__name__} is not an arm module: it needs build, PAPER and Parameters")
    if name in ARMS and ARMS[name] is not module:
        raise ValueError(f"arm {name!r} is registered already (by {ARMS[name].__name__})")
    ARMS.add(name, module)


def unregister(name: str) -> None:
    """Take back the arm ``name`` that :func:`register` added (a plug-in unloaded, a test's arm)."""
    ARMS.remove(name)


def paper_arms() -> list[Arm]:
    """Every paper arm of :data:`ARMS`, built with its default parameters, in order."""
    return [module.build() for module in ARMS.values()]


#: The prefix of an example arm's name: ``example:arm3r`` is ``arm3r.csv`` of :func:`examples`.
EXAMPLE = "example:"


def examples() -> dict[str, Path]:
    """The example arms shipped with armlab (``scripts/examples/`` in the repository, ``armlab.scripts.examples``
    installed): each ``.csv`` DH table and ``.urdf`` file there by its name without suffix."""
    folder = Path(str(files("armlab.scripts.examples")))
    return {path.stem: path for path in sorted(folder.iterdir()) if path.suffix.lower() in (".csv", ".urdf")}


def get_arm(name: str, tool: str | None = None, package_paths: Sequence[str | Path] = (), /,
            **overrides: float) -> Arm:
    """A paper arm by name (parameters overridable), a library arm (:data:`armlab.models.library.LIBRARY`:
    ``puma560``, ``ur5``, …), an example (``example:NAME``), or a ``.urdf``, ``.sdf``, MJCF ``.xml`` or DH ``.csv``
    file.

    ``tool`` (a link name) and ``package_paths`` (folders of ROS packages) are for URDF, SDFormat and MJCF files
    (:func:`armlab.models.read_urdf.from_urdf`, :func:`armlab.models.read_sdf.from_model_file`); ``ValueError``
    if given for another arm.
    """
    known = [f.name for f in fields(ARMS[name].Parameters)] if name in ARMS else []
    if overrides and not known:
        takes = ", ".join(arm for arm, module in ARMS.items() if fields(module.Parameters))
        raise ValueError(f"{name}: takes no parameters (got {', '.join(overrides)}): only a paper arm's can be "
                         f"overridden ({takes}); write a DH table to change its numbers")
    path = Path(name)
    if path.suffix.lower() not in (".urdf", ".sdf", ".xml") or name in ARMS:
        given = [f"{option} = {shown(value if isinstance(value, str) else [str(v) for v in value])}"
                 for option, value in (("--tool (tool=)", tool), ("--package-path (package_paths=)", package_paths))
                 if value]
        if given:
            raise ValueError(f"{' and '.join(given)}: {'these options are' if len(given) > 1 else 'the option is'} "
                             f"for an arm from a URDF, SDFormat or MJCF file, and {shown(name)} is not one: give "
                             "the arm's file, or leave the option out")
    if name in ARMS:
        for key, value in overrides.items():
            if key not in known:
                raise ValueError(f"{name}: unknown parameter {key!r}; allowed: {', '.join(known)}")
            real_number(value, f"{name}: parameter {key} = {shown(value)}")
            if not (math.isfinite(value) and abs(value) <= MAX_FILE_NUMBER):
                raise ValueError(f"{name}: parameter {key} = {value:g} is out of range: allowed |{key}| ≤ "
                                 f"{MAX_FILE_NUMBER:g} (m, rad or kg, like the numbers of an arm file)")
        return ARMS[name].build(**overrides)
    if name.startswith(EXAMPLE):
        shipped = examples()
        if name.removeprefix(EXAMPLE) not in shipped:
            raise ValueError(f"unknown example arm {name!r}; allowed: {_names(shipped)}")
        path = shipped[name.removeprefix(EXAMPLE)]
    if path.suffix.lower() == ".urdf":
        # lazy: armlab --help loads armlab.models but not this (start-up time)
        from armlab.models.read_urdf import from_urdf

        return from_urdf(path, tool, package_paths)
    if path.suffix.lower() in (".sdf", ".xml"):
        # lazy: armlab --help loads armlab.models but not this (start-up time)
        from armlab.models.read_sdf import from_model_file

        return from_model_file(path, tool, package_paths)
    if path.suffix.lower() == ".csv":
        # lazy: armlab --help loads armlab.models but not this (start-up time)
        from armlab.models.read_dh import from_dh_csv

        return from_dh_csv(path)
    # lazy: armlab --help loads armlab.models but not the library's list (start-up time)
    from armlab.models.library import LIBRARY, library_arm

    if name in LIBRARY:
        return library_arm(name)
    raise ValueError(f"unknown arm {name!r}; allowed: a paper arm ({', '.join(ARMS)}), a library arm "
                     f"({', '.join(LIBRARY)}), an example ({_names(examples())}), or a .urdf, .sdf, MJCF .xml or "
                     "DH .csv file")


def _names(shipped: dict[str, Path]) -> str:
    return ", ".join(EXAMPLE + stem for stem in shipped)
