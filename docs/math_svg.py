"""A Sphinx HTML math renderer that needs no network: armlab's own LaTeX → inline SVG (matplotlib's mathtext).

The site's mathematics (the notebooks', the report pages') is rendered at build time by
:func:`armlab.papers.math_html.latex_html`, as ``report.html`` renders it, so the pages show it opened from
disk, with no MathJax to fetch.
"""

from __future__ import annotations

from typing import Any

from docutils import nodes

from armlab.papers.math_html import MATH_CSS, latex_html


def _inline(self: Any, node: nodes.Element) -> None:
    self.body.append(f'<span class="math">{latex_html(node.astext())}</span>')
    raise nodes.SkipNode


def _block(self: Any, node: nodes.Element) -> None:
    self.body.append(f'<div class="math">{latex_html(node.astext())}</div>')
    raise nodes.SkipNode


def _style(app: Any, pagename: str, templatename: str, context: dict[str, Any], doctree: Any) -> None:
    """Every page carries :data:`~armlab.papers.math_html.MATH_CSS` (the report's own style for its pieces)."""
    context["metatags"] = context.get("metatags", "") + f"<style>{MATH_CSS}</style>"


def setup(app: Any) -> dict[str, bool]:
    """Register the renderer as ``html_math_renderer = "armlab"``, and its style on every page."""
    app.add_html_math_renderer("armlab", (_inline, None), (_block, None))
    app.connect("html-page-context", _style)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
