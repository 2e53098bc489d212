"""The layers of armlab: the command line (``armlab.cli``) sits on the library, never under it.

Every module of every package that pyproject.toml installs is read (ast, not imported: importing would load
Drake), and each of its imports, at module level or inside a function alike, is checked: outside ``armlab.cli``
nothing imports ``armlab.cli`` or ``argparse``. Two kinds of code are programs, not library, and are allowed
their own command lines: a module's ``if __name__ == "__main__":`` block (a paper script run alone takes its
options from :func:`armlab.cli.reproduce.run_alone`) and the developer benchmarks ``scripts/bench_*.py``
(``make bench`` runs them as scripts) and the example scripts ``armlab.scripts.examples.*`` (no module imports
either, checked). And the CLI package's own module-level
imports pull none of the heavy libraries armlab imports lazily (:data:`armlab._lazy.LAZY_IMPORTS`), so that
``armlab --help`` stays fast. Every other import sits at its module's top, where readers and tools see the module
graph: inside a function only a lazy library, a module that imports one at module level, or an import whose comment
says ``# lazy: <reason>``.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import ROOT, is_program, package_modules

from armlab._lazy import LAZY_IMPORTS

CLI = "armlab.cli"
#: What only the CLI may import.
CLI_ONLY = (CLI, "argparse")


_modules = package_modules


def _is_main_block(node: ast.AST) -> bool:
    """``if __name__ == "__main__":``."""
    return (isinstance(node, ast.If) and isinstance(node.test, ast.Compare)
            and isinstance(node.test.left, ast.Name) and node.test.left.id == "__name__"
            and any(isinstance(c, ast.Constant) and c.value == "__main__" for c in node.test.comparators))


def imports(source: str, module: str, module_level_only: bool = False) -> list[tuple[int, str]]:
    """(line, imported module) of each import in ``source`` (the module ``module``), outside its ``__main__``
    block; ``from a import b`` counts as importing ``a.b`` too (``b`` may be a module); relative imports are
    resolved against ``module``. ``module_level_only``: not those inside functions (those run when called)."""
    found: list[tuple[int, str]] = []

    def visit(node: ast.AST) -> None:
        for child in ast.iter_child_nodes(node):
            if _is_main_block(child):
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
    """The walk sees the whole package (the test below would pass on an empty one)."""
    modules = _modules()
    for name in ("armlab.api", "armlab.cli", "armlab.cli.args", "armlab.models.arm", "armlab.diagrams.plant",
                 "armlab.analysis.sweep", "armlab.scripts.reproduce", "armlab.scripts.bench_ik"):
        assert name in modules and modules[name].is_file(), name
    assert len(modules) > 60


def test_only_the_cli_imports_the_cli_and_argparse():
    """No module outside ``armlab.cli`` imports ``armlab.cli`` or ``argparse``, at any depth of its code (a
    benchmark program may use argparse, never the CLI)."""
    bad = []
    for module, path in _modules().items():
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
    assert programs
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
