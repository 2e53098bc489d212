"""A Sphinx HTML math renderer that needs no network: armlab's own LaTeX → inline SVG (matplotlib's mathtext).

The site's mathematics (the notebooks', the report pages') is rendered at build time by
:func:`armlab.papers.math_html.latex_html`, as ``report.html`` renders it, so the pages show it opened from
disk, with no MathJax to fetch.
"""

from __future__ import annotations

from typing import Any

from docutils import nodes

from armlab.papers.math_html import latex_html


def _inline(self: Any, node: nodes.Element) -> None:
    self.body.append(f'<span class="math">{latex_html(node.astext())}</span>')
    raise nodes.SkipNode


def _block(self: Any, node: nodes.Element) -> None:
    self.body.append(f'<div class="math">{latex_html(node.astext())}</div>')
    raise nodes.SkipNode


def setup(app: Any) -> dict[str, bool]:
    """Register the renderer as ``html_math_renderer = "armlab"``."""
    app.add_html_math_renderer("armlab", (_inline, None), (_block, None))
    return {"parallel_read_safe": True, "parallel_write_safe": True}
