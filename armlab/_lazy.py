"""The heavy libraries armlab imports only where it uses them, never at a module's top that the CLI loads.

Each costs a large part of a second or more to import (Drake most), so ``armlab --help`` and the commands that do
not need them stay fast. tests/test_layers.py checks that the CLI package's module-level imports pull none of them,
and that every other import sits at its module's top: inside a function stand only imports of these libraries, of
the armlab modules that import one at module level, and imports marked ``# lazy: <reason>`` (a cycle, the CLI's
start-up).
"""

#: Top-level package names, imported lazily (inside the functions that need them).
LAZY_IMPORTS = ("pydrake", "matplotlib", "mpl_toolkits", "cycler", "sympy", "distributed", "dask", "tqdm", "PIL",
                "tornado", "msgpack")
