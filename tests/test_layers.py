"""The layers of armlab: rooms stacked lowest first, each importing only the rooms below it; the command line
(``armlab.cli``) sits on the library, never under it.

:data:`ROOMS` is the order (each room's ``__init__`` docstring says it: "May import: …"). Every module of every
package that pyproject.toml installs is read (ast, not imported: importing would load Drake), and each of its
imports, at module level or inside a function alike, is checked: none reaches a room above the module's own (an
import under ``if TYPE_CHECKING:`` is for annotations, never run, and is not an import of the room), and outside
``armlab.cli`` nothing imports ``argparse``. Two kinds of code are programs, not library, and are allowed their own
command lines: a module's ``if __name__ == "__main__":`` block (a paper script run alone takes its options from
:func:`armlab.cli.reproduce.run_alone`), the developer benchmarks ``scripts/bench/bench_*.py`` (``make bench`` runs
them as scripts; not installed) and the example scripts ``armlab.scripts.examples.*`` (no module imports either,
checked). Every module imports on its own in a fresh interpreter. And the CLI package's own module-level
imports pull none of the heavy libraries armlab imports lazily (:data:`armlab._lazy.LAZY_IMPORTS`), so that
``armlab --help`` stays fast. Every other import sits at its module's top, where readers and tools see the module
graph: inside a function only a lazy library, a module that imports one at module level, or an import whose comment
says ``# lazy: <reason>``.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from helpers import ROOT, is_program, package_modules

from armlab._lazy import LAZY_IMPORTS

CLI = "armlab.cli"
#: What only the CLI may import.
CLI_ONLY = (CLI, "argparse")

#: The rooms, lowest first: a module imports only modules of its own room and of rooms below it. ``base`` is the
#: ``armlab`` package's own modules (ranges, values, files: :data:`BASE`); ``api`` is ``armlab`` itself and
#: :mod:`armlab.api`.
ROOMS = ("base", "kinematics", "drives", "models", "collision", "presentation", "planning", "controllers", "diagrams",
         "sizing", "analysis", "api", "papers", "cli", "scripts")
#: The modules of the base room.
BASE = ("armlab._lazy", "armlab.limits", "armlab.bounds", "armlab.values", "armlab.files", "armlab.arm_file")


def room_of(module: str) -> str:
    """The room of the armlab module ``module`` (``armlab.kinematics.quintic`` → ``kinematics``)."""
    if module in ("armlab", "armlab.api"):
        return "api"
    if module == "armlab.__main__":
        return "cli"
    if any(_names(base, module) for base in BASE):
        return "base"
    parts = module.split(".")
    room = parts[1]
    if len(parts) == 2 and room not in ROOMS:  # a name of the package itself (``from armlab import __version__``)
        return "api"
    if room not in ROOMS:
        raise ValueError(f"{module} is in no room of ROOMS: add its package to ROOMS in order")
    return room


_modules = package_modules


def _benchmarks() -> dict[str, Path]:
    """The developer benchmarks (``scripts/bench/bench_*.py``, not installed) by a module name of their own."""
    return {f"bench.{path.stem}": path for path in sorted((ROOT / "scripts" / "bench").glob("bench_*.py"))}


def _is_main_block(node: ast.AST) -> bool:
    """``if __name__ == "__main__":``."""
    return (isinstance(node, ast.If) and isinstance(node.test, ast.Compare)
            and isinstance(node.test.left, ast.Name) and node.test.left.id == "__name__"
            and any(isinstance(c, ast.Constant) and c.value == "__main__" for c in node.test.comparators))


def imports(source: str, module: str, module_level_only: bool = False, typing: bool = True
            ) -> list[tuple[int, str]]:
    """(line, imported module) of each import in ``source`` (the module ``module``), outside its ``__main__``
    block; ``from a import b`` counts as importing ``a.b`` too (``b`` may be a module); relative imports are
    resolved against ``module``. ``module_level_only``: not those inside functions (those run when called);
    ``typing=False``: not those under ``if TYPE_CHECKING:`` (annotations only, never run)."""
    found: list[tuple[int, str]] = []

    def visit(node: ast.AST) -> None:
        for child in ast.iter_child_nodes(node):
            if _is_main_block(child) or (not typing and _is_type_checking(child)):
                continue
            if module_level_only and isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
                continue
            if isinstance(child, ast.Import):
                found.extend((child.lineno, alias.name) for alias in child.names)
            elif isinstance(child, ast.ImportFrom):
                base = child.module or ""
                if child.level:
                    parent = module.rsplit(".", child.level)[0]
                    base = f"{parent}.{base}" if base else parent
                found.append((child.lineno, base))
                found.extend((child.lineno, f"{base}.{alias.name}") for alias in child.names)
            visit(child)

    visit(ast.parse(source))
    return found


def _names(target: str, imported: str) -> bool:
    return imported == target or imported.startswith(target + ".")


def _is_cli(module: str) -> bool:
    return _names(CLI, module)


_is_program = is_program


def test_modules_are_found():
    """The walk sees the whole package (the test below would pass on an empty one), and no benchmark is installed."""
    modules = _modules()
    for name in ("armlab.api", "armlab.cli", "armlab.cli.args", "armlab.models.arm", "armlab.models.plant",
                 "armlab.analysis.sweep", "armlab.papers.reproduce", "armlab.presentation.replay",
                 "armlab.planning.timing", "armlab.sizing.select"):
        assert name in modules and modules[name].is_file(), name
    assert len(modules) > 100
    assert not [m for m in modules if "bench" in m]
    assert "bench.bench_ik" in _benchmarks()


def back_imports(modules: dict[str, Path]) -> list[str]:
    """Each import (at any depth of a module's code, not under ``if TYPE_CHECKING:``) of a module in a room above
    the importing module's own (:data:`ROOMS`)."""
    bad = {}
    for module, path in modules.items():
        own = ROOMS.index(room_of(module))
        for line, name in imports(path.read_text(), module, typing=False):
            # ``armlab`` alone is the parent package every import of a room loads, not the API's room
            if _names("armlab", name) and name != "armlab" and ROOMS.index(room_of(name)) > own:
                shown = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
                bad[f"{shown}:{line}"] = f"{module} ({room_of(module)}) imports {name} ({room_of(name)})"
    return [f"{where}: {what}" for where, what in bad.items()]  # one a line (``from a import b``: a and a.b)


def test_no_room_imports_a_room_above_it():
    """The rooms are a stack: the import graph has no edge downward from a higher room, so no cycle between rooms
    and none through a package's ``__init__``."""
    bad = back_imports(_modules())
    assert not bad, "imports of a higher room:\n" + "\n".join(bad)


@pytest.mark.parametrize(("source", "bad"), [
    ("from armlab.models.arm import Arm", 1),  # kinematics importing models
    ("def f():\n    from armlab.diagrams.run import Run", 1),  # at any depth
    ("from armlab.kinematics.batch import as_batch\nfrom armlab.limits import check_range", 0),  # its own, below
    ("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from armlab.models.arm import Arm", 0),  # annotations
    ("from armlab import api", 1),  # the API sits above every library room
    ("from .. import models", 1),  # relative imports resolved
    ("if __name__ == '__main__':\n    from armlab.cli.reproduce import run_alone", 0),
])
def test_back_imports_are_caught(tmp_path, source, bad):
    """The check sees a back-import wherever it stands, and lets through the room's own and lower ones."""
    path = tmp_path / "probe.py"
    path.write_text(source)
    assert len(back_imports({"armlab.kinematics.probe": path})) == bad


def test_every_module_is_in_a_room_and_each_room_says_what_it_may_import():
    """Each installed package is one of :data:`ROOMS` (or inside one), and each room's ``__init__`` docstring says
    which rooms it may import, as :data:`ROOMS` orders them."""
    modules = _modules()
    rooms = {room_of(module) for module in modules}
    assert rooms == set(ROOMS)
    for room in ROOMS:
        if room in ("base", "api"):
            continue
        package = "armlab.cli" if room == "cli" else f"armlab.{room}"
        doc = ast.get_docstring(ast.parse(modules[package].read_text())) or ""
        expected = f"May import: {', '.join(ROOMS[:ROOMS.index(room)])}."
        assert expected in doc.replace("\n", " "), f"{package}'s docstring should say {expected!r}"


@pytest.mark.process
def test_every_module_imports_on_its_own():
    """``python -c "import M"`` in a fresh interpreter succeeds for every module: no import cycle that only works
    when something else was imported first."""
    modules = sorted(_modules())

    def alone(module: str) -> tuple[str, str]:
        done = subprocess.run([sys.executable, "-c", f"import {module}"], capture_output=True, text=True, timeout=120)
        return module, "" if done.returncode == 0 else (done.stderr.strip().splitlines() or ["?"])[-1]

    with ThreadPoolExecutor(2) as pool:
        failed = [f"{module}: {error}" for module, error in pool.map(alone, modules) if error]
    assert not failed, "modules that do not import alone:\n" + "\n".join(failed)


@pytest.mark.process
def test_importing_the_models_imports_no_arm_module():
    """The paper arms are found on first lookup, not when ``armlab.models`` is imported."""
    code = ("import sys, armlab.models as m\n"
            "before = [k for k in sys.modules if k.rpartition('.')[2] in ('rr', 'rrrr', 'arm4r', 'r2t', 'urm6')]\n"
            "print(before, list(m.ARMS))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120)
    assert out.stdout.strip() == "[] ['rr', 'rrrr', 'arm4r', 'r2t', 'urm6']"


def test_only_the_cli_imports_the_cli_and_argparse():
    """No module outside ``armlab.cli`` imports ``armlab.cli`` or ``argparse``, at any depth of its code (a
    benchmark program may use argparse, never the CLI)."""
    bad = []
    for module, path in (_modules() | _benchmarks()).items():
        if _is_cli(module):
            continue
        forbidden = (CLI,) if _is_program(module) else CLI_ONLY
        bad += [f"{path.relative_to(ROOT)}:{line}: {module} imports {name}"
                for line, name in imports(path.read_text(), module) if any(_names(f, name) for f in forbidden)]
    assert not bad, "library modules import the command line:\n" + "\n".join(bad)


@pytest.mark.slow
def test_no_module_imports_a_program():
    """The benchmarks allowed argparse above are programs only: no module imports one."""
    modules = _modules()
    programs = [m for m in modules if _is_program(m)]
    assert programs and all(m.startswith("armlab.scripts.examples.") for m in programs)
    bad = [f"{module} imports {name}" for module, path in modules.items()
           for _, name in imports(path.read_text(), module) if name in programs]
    assert not bad


@pytest.mark.parametrize(("source", "caught"), [
    ("import argparse", ["argparse"]),
    ("def f():\n    from armlab.cli import main", ["armlab.cli", "armlab.cli.main"]),
    ("from armlab import cli", ["armlab", "armlab.cli"]),
    ("from . import cli", ["armlab", "armlab.cli"]),
    ("class A:\n    def f(self):\n        import armlab.cli.args", ["armlab.cli.args"]),
    ("if __name__ == '__main__':\n    from armlab.cli.reproduce import run_alone", []),
])
def test_imports_sees_every_import(source, caught):
    """The walk finds an import wherever it stands (and skips only a ``__main__`` block)."""
    assert [name for _, name in imports(source, "armlab.limits")] == caught


def test_cli_module_level_imports_pull_no_lazy_library():
    """Importing every module of the CLI package and building the parser (what ``armlab --help`` does) loads
    none of :data:`armlab._lazy.LAZY_IMPORTS` (in a fresh interpreter: this one has them loaded)."""
    cli = sorted(m for m in _modules() if _is_cli(m))
    assert len(cli) >= 8
    code = (f"import sys\nfor m in {cli!r}: __import__(m)\n"
            "import armlab.cli; armlab.cli.build_parser()\n"
            f"print(sorted({{m.split('.')[0] for m in sys.modules}} & set({LAZY_IMPORTS!r})))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120)
    assert out.stdout.strip() == "[]", out.stdout
    static = [f"{module}: {name}" for module in cli for _, name in imports(_modules()[module].read_text(), module,
                                                                           module_level_only=True)
              if any(_names(lazy, name) for lazy in LAZY_IMPORTS)]
    assert not static


def _is_type_checking(node: ast.AST) -> bool:
    """``if TYPE_CHECKING:`` (imports for annotations only: never run)."""
    return isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)


def _function_imports(source: str, module: str) -> list[tuple[int, list[str]]]:
    """(line, names it imports) of each import inside a function of ``source`` (resolved like :func:`imports`)."""
    found = []
    for function in ast.walk(ast.parse(source)):
        if isinstance(function, ast.FunctionDef | ast.AsyncFunctionDef):
            for node in function.body:
                for child in ast.walk(node):
                    if isinstance(child, ast.Import | ast.ImportFrom):
                        found.append((child.lineno, [name for _, name in imports(ast.unparse(child), module)]))
    return sorted(set((line, tuple(names)) for line, names in found))  # a nested function is walked twice


def _lazy_modules(modules: dict[str, Path]) -> set[str]:
    """The armlab modules that import a :data:`~armlab._lazy.LAZY_IMPORTS` library at module level (outside
    ``if TYPE_CHECKING:``): importing one of them is as heavy as the library."""
    lazy = set()
    for module, path in modules.items():
        tree = ast.parse(path.read_text())
        tree.body = [node for node in tree.body if not _is_type_checking(node)]
        if any(any(_names(lib, name) for lib in LAZY_IMPORTS)
               for _, name in imports(ast.unparse(tree), module, module_level_only=True)):
            lazy.add(module)
    return lazy


def _marked_lazy(lines: list[str], line: int) -> bool:
    """The comment block right above line ``line`` (1-based), or above the group of imports it ends, says
    ``# lazy: <reason>``."""
    above = line - 2
    while above >= 0 and lines[above].strip().startswith(("from ", "import ")):  # the group's other imports
        above -= 1
    while above >= 0 and lines[above].strip().startswith("#"):
        if lines[above].strip().startswith("# lazy:"):
            return True
        above -= 1
    return False


def function_level_violations(modules: dict[str, Path]) -> list[str]:
    """Each import inside a function that is neither of a lazy library, nor of an armlab module importing one at
    module level, nor marked ``# lazy: <reason>`` (a cycle, the CLI's start-up order …)."""
    heavy = _lazy_modules(modules)
    bad = []
    for module, path in modules.items():
        source = path.read_text()
        lines = source.splitlines()
        for line, names in _function_imports(source, module):
            if any(_names(lib, name) for lib in (*LAZY_IMPORTS, *heavy) for name in names):
                continue
            if not _marked_lazy(lines, line):
                shown = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
                bad.append(f"{shown}:{line}: {module} imports {names[-1]} inside a function")
    return bad


def test_imports_are_at_module_level():
    """Readers and tools see the module graph: an import sits inside a function only if it is of a lazy library
    (or of a module that imports one), or says why (``# lazy: <reason>``)."""
    modules = _modules()
    assert {"armlab.kinematics.symbolic", "armlab.diagrams.tool_point"} <= _lazy_modules(modules)
    bad = function_level_violations(modules)
    assert not bad, "imports inside functions:\n" + "\n".join(bad)


@pytest.mark.parametrize(("source", "bad"), [
    ("def f():\n    import json", 1),
    ("def f():\n    if True:\n        from armlab.limits import check_range", 1),
    ("class A:\n    def f(self):\n        def g():\n            import os", 1),
    ("def f():\n    import pydrake.all", 0),
    ("def f():\n    from armlab.kinematics.symbolic import arm_kinematics", 0),
    ("def f():\n    # lazy: a cycle\n    import json", 0),
    ("def f():\n    # lazy: a cycle, told on\n    # two lines\n    import json", 0),
    ("def f():\n    # a comment, no reason\n    import json", 1),
    ("def f():\n    # lazy: a group\n    import json\n    import os", 0),
    ("def f():\n    # lazy: a cycle\n    import json\n\n    import os", 1),
    ("def f():\n    # lazy: a cycle\n    x = 1\n    import os", 1),
    ("import json", 0),
])
def test_function_level_violations_are_caught(tmp_path, source, bad):
    """The check sees an import inside a function at any depth, and lets through only the three kinds above."""
    path = tmp_path / "probe.py"
    path.write_text(source)
    modules = {m: p for m, p in _modules().items() if m in ("armlab.kinematics.symbolic", "armlab.diagrams.tool_point")}
    modules["armlab.probe"] = path
    assert len(function_level_violations(modules)) == bad
