"""Graphviz export of a diagram: DOT text always, SVG and PNG through graphviz's ``dot`` program."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from armlab.files import write_file

__all__ = ["FORMATS", "render", "require_dot", "write_graph"]

#: Output formats by file suffix.
FORMATS = ("dot", "svg", "png")


def require_dot() -> str:
    """Path of graphviz's ``dot``, or ``ValueError`` saying how to install it."""
    dot = shutil.which("dot")
    if dot is None:
        raise ValueError("graphviz's 'dot' program is needed for SVG/PNG diagrams and was not found: install graphviz "
                         "(apt-get install graphviz, or run 'make run-deps'), or write a .dot file")
    return dot


def render(dot_text: str, fmt: str) -> bytes:
    """``dot_text`` as ``fmt`` (``dot``, ``svg`` or ``png``) bytes; SVG and PNG by ``dot -T<fmt>``."""
    if fmt not in FORMATS:
        raise ValueError(f"diagram format {fmt!r} is not allowed; allowed: {', '.join(FORMATS)}")
    if fmt == "dot":
        return dot_text.encode()
    result = subprocess.run([require_dot(), f"-T{fmt}"], input=dot_text.encode(), capture_output=True, check=False)
    if result.returncode != 0:
        raise ValueError(f"dot -T{fmt} failed: {result.stderr.decode(errors='replace').strip()}")
    return result.stdout


def write_graph(dot_text: str, path: str | Path) -> Path:
    """Write ``dot_text`` to ``path`` in the format its suffix names, atomically (:func:`~armlab.files.write_file`)."""
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in FORMATS:
        raise ValueError(f"--out {path}: the suffix must be one of {', '.join('.' + f for f in FORMATS)}")
    return write_file(path, render(dot_text, fmt))
