"""Sphinx configuration of armlab's documentation site (``make docs``; built offline from the repository).

Sphinx, because the API reference comes from the docstrings as they are written (autodoc imports the installed
package, so the lazy exports of ``armlab`` and the ``package-dir`` layout resolve as users see them), MyST reads
the README's Markdown and the report's pages unchanged, and MyST-NB executes and renders the notebooks in the
same build. The generated pages (API reference, one page per paper from a fresh reproduction, the notebooks)
are written by :mod:`pages` into ``_generated/`` before the build reads any source.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from jupyter_client.connect import ConnectionFileMixin

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import pages  # noqa: E402  (docs/pages.py, beside this file)

project = "armlab"
author = "the armlab developers"
copyright = "the armlab developers (MIT licence)"
release = version = pages.armlab_version()

extensions = ["myst_nb", "sphinx.ext.autodoc", "math_svg"]
# the mathematics as inline SVG made at build time (docs/math_svg.py): the pages need no network
html_math_renderer = "armlab"
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 4
exclude_patterns = ["_build", "_generated/reproduction"]
suppress_warnings = [
    "myst.header",  # the report's pages start at level 2 below a level-1 title
    # a name exported from ``armlab`` and from its module (armlab.Arm, armlab.models.arm.Arm) is one object with
    # two entries: a type hint that names it links to either, both right
    "ref.python",
]

# The notebooks run once in the build (their outputs are never committed); any error fails the build. Their kernels
# talk over IPC (socket files), not TCP: no port is opened, and ipykernel does not warn once per notebook of a kernel
# "running over TCP without encryption". MyST-NB gives its kernel manager no options, so the default of the trait
# every jupyter_client kernel manager reads is set.
ConnectionFileMixin.class_traits()["transport"].default_value = "ipc"
nb_execution_mode = "force"
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_execution_show_tb = True

autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
autodoc_member_order = "bysource"
# a class's entry opens with its docstring (what a user does with it), not its constructor's fields (Arm: 25);
# the constructor is what armlab.load and the API functions call
autodoc_class_signature = "separated"
autodoc_typehints = "signature"
autodoc_preserve_defaults = True

html_theme = "alabaster"
html_title = f"armlab {release}"
html_static_path: list[str] = []
html_theme_options = {"description": "serial robot arms modelled, checked and simulated with Drake",
                      "page_width": "1180px", "sidebar_width": "250px"}


def plain_bars(app: object, what: str, name: str, obj: object, options: object, lines: list[str]) -> None:
    """A docstring's ``|x|`` is an absolute value or a norm, as ``help()`` shows it, not an RST substitution:
    its bars are escaped (the lines of an RST grid table, which start and end with ``|`` or ``+``, are left alone)."""
    for k, line in enumerate(lines):
        text = line.strip()
        if not (text[:1] in "|+" and text[-1:] in "|+" and len(text) > 1):
            lines[k] = line.replace("|", "\\|")


def setup(app: Any) -> None:
    """Write the generated pages before Sphinx reads the sources; escape the docstrings' bars."""
    pages.write_all(HERE / "_generated")
    app.connect("autodoc-process-docstring", plain_bars)
