"""LaTeX as self-contained HTML: matplotlib's mathtext rendered to inline SVG, no network, no TeX.

mathtext understands a subset of LaTeX. :func:`to_mathtext` rewrites what it does not
(``\\texttt``, ``\\left(``…``\\right)`` around long factors, ``\\sqrt`` of long radicands as
``(…)^{1/2}``, as Matlab prints it); :func:`latex_html` lays out what mathtext cannot at all:
sympy's ``\\begin{matrix}`` as an HTML grid between brackets, and long sums broken into lines at
their top-level ``+``/``−``. Every piece is parsed by mathtext; one it cannot parse raises
``ValueError`` naming it (the report tests render every expression).
"""

from __future__ import annotations

import base64
import html
import re
from functools import cache
from itertools import pairwise
from typing import Any

import numpy as np

__all__ = ["MATH_CSS", "latex_html", "math_svg", "to_mathtext"]

#: The style :func:`latex_html`'s pieces need wherever they are shown (the report, the documentation site): the
#: SVGs at their own size (a page's ``img{max-width:100%}`` in a narrow matrix cell shrinks them unreadably), a
#: long sum's lines stacked, a matrix a bracketed grid.
MATH_CSS = """
.math img.m{vertical-align:middle;max-width:none;height:auto}
.ml{display:inline-flex;flex-direction:column;vertical-align:middle}.ml>span:not(:first-child){padding-left:2em}
table.mat{display:inline-table;width:auto;border:none;border-left:2px solid #333;border-right:2px solid #333;
vertical-align:middle;margin:0 .3em}table.mat td{border:none;padding:2px 8px;vertical-align:middle;white-space:nowrap}
div.math{overflow-x:auto}
"""

#: Visual characters (commands, braces, sub/superscript marks not counted) per rendered line, and per line
#: of a matrix cell.
LINE_CHARS = 80
CELL_CHARS = 40
FONT_SIZE = 11.0

#: matplotlib's path codes and the SVG path commands they become.
_MOVE, _CLOSE = 1, 79
_LETTER = {1: "M", 2: "L", 3: "Q", 4: "C"}
_MATRIX = re.compile(r"\[\\begin\{matrix\}(.*?)\\end\{matrix\}\]", re.S)  # after to_mathtext


def _texttt(match: re.Match) -> str:
    body = match.group(1).replace(" ", r"\ ").replace("%", r"\%")
    return r"\mathtt{" + body + "}"


def _braced(text: str, start: int) -> int:
    """Index just past the ``{…}`` group opening at ``text[start]``."""
    depth = 0
    for i in range(start, len(text)):
        depth += {"{": 1, "}": -1}.get(text[i], 0)
        if depth == 0:
            return i + 1
    raise ValueError(f"unbalanced braces in {text!r}")


def _long_roots(text: str) -> str:
    r"""``\sqrt{X}`` with a long ``X`` → ``(X)^{1/2}`` (a line break inside ``\sqrt`` cannot be drawn)."""
    out, i = [], 0
    while (k := text.find(r"\sqrt{", i)) >= 0:
        end = _braced(text, k + 5)
        body = text[k + 6:end - 1]
        out.append(text[i:k])
        out.append(f"({_long_roots(body)})^{{1/2}}" if _visual(body) > LINE_CHARS else text[k:end])
        i = end
    return "".join(out) + text[i:]


def to_mathtext(latex: str) -> str:
    """``latex`` rewritten into the subset mathtext parses (see the module doc); no ``$`` delimiters."""
    text = re.sub(r"\\texttt\{([^{}]*)\}", _texttt, latex)
    text = re.sub(r"\\left\s*([(\[|])", r"\1", text)
    text = re.sub(r"\\right\s*([)\]|])", r"\1", text)
    text = text.replace(r"\dots", r"\ldots")
    return _long_roots(text)


def _visual(text: str) -> int:
    return len(re.sub(r"\\[a-zA-Z]+|[{}_^ ]", "", text))


def _split_sum(text: str, width: int = LINE_CHARS) -> list[str]:
    """``text`` broken before top-level (brace depth 0) ``+``/``−`` into lines of about ``width`` characters."""
    cuts, depth = [0], 0
    for i, ch in enumerate(text):
        depth += {"{": 1, "}": -1}.get(ch, 0)
        if depth == 0 and i > 0 and text[i - 1:i + 2] in (" + ", " - "):
            cuts.append(i)
    cuts.append(len(text))
    lines, current = [], ""
    for a, b in pairwise(cuts):
        piece = text[a:b]
        if current and _visual(current + piece) > width:
            lines.append(current.strip())
            current = piece
        else:
            current += piece
    lines.append(current.strip())
    return [line for line in lines if line]


def _path_data(vertices: Any, codes: Any) -> str:
    """An SVG path's ``d`` from matplotlib path ``vertices`` (N, 2) and ``codes`` (N,): a command letter where
    the kind of segment changes (SVG repeats the last one), ``z`` closing a contour."""
    out, previous = [], 0
    for (x, y), code in zip(np.round(vertices, 2).tolist(), codes.tolist(), strict=True):
        if code == _CLOSE:
            out.append("z")
            previous = 0
            continue
        if code != previous or code == _MOVE:
            out.append(_LETTER[code])
            previous = code
        out.append(f"{x:g} {y:g}")
    return " ".join(out)


@cache
def _glyph_path(glyph: str) -> str:
    """The ``d`` of a glyph outline loaded by :data:`matplotlib.textpath.text_to_path` (at its font scale)."""

    vertices, codes = _GLYPHS[glyph]
    return _path_data(np.asarray(vertices, dtype=float), np.asarray(codes)) if len(codes) else ""


#: Glyph outlines loaded so far, by matplotlib's name for them (shared by every expression of the process).
_GLYPHS: dict[str, Any] = {}


@cache
def math_svg(mathtext: str) -> str:
    """``mathtext`` (no ``$``) as an ``<img>`` holding its SVG: the glyph outlines as paths (no fonts needed).

    Laid out by matplotlib's mathtext once, at the font scale of :data:`matplotlib.textpath.text_to_path`,
    and drawn as matplotlib's SVG backend draws text as paths (one ``<path>`` per glyph, a ``<use>`` per
    occurrence), scaled to :data:`FONT_SIZE` pt.
    """
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import text_to_path

    text, scale = f"${mathtext}$", FONT_SIZE / text_to_path.FONT_SCALE
    prop = FontProperties(size=text_to_path.FONT_SCALE, math_fontfamily="dejavuserif")
    try:
        width, height, depth, _, _ = text_to_path.mathtext_parser.parse(text, text_to_path.DPI, prop)
        glyphs, loaded, rects = text_to_path.get_glyphs_mathtext(prop, text, glyph_map=_GLYPHS or None)  # same parse
    except ValueError as error:
        raise ValueError(f"mathtext cannot render {mathtext!r}: {str(error).splitlines()[0]}") from None
    _GLYPHS.update(loaded)
    ids = {glyph: f"g{k}" for k, glyph in enumerate(dict.fromkeys(g[0] for g in glyphs))}
    defs = "".join(f'<path id="{ids[glyph]}" d="{_glyph_path(glyph)}"/>' for glyph in ids)
    uses = "".join(f'<use xlink:href="#{ids[glyph]}" transform="translate({x:.6g} {y:.6g}) scale({size:.6g})"/>'
                   for glyph, x, y, size in glyphs)
    bars = "".join(f'<path d="{_path_data(np.asarray(v, dtype=float), np.asarray(c))}"/>' for v, c in rects)
    w, h, d = width * scale, height * scale, depth * scale
    svg = (f'<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="{w:.6g}pt" '
           f'height="{h:.6g}pt" viewBox="0 0 {w:.6g} {h:.6g}"><defs>{defs}</defs>'
           f'<g transform="translate(0 {h - d:.6g}) scale({scale:.6g} {-scale:.6g})">{uses}{bars}</g></svg>')
    data = base64.b64encode(svg.encode()).decode()
    return f'<img class="m" alt="{html.escape(mathtext)}" src="data:image/svg+xml;base64,{data}">'


def _lines_html(text: str, width: int = LINE_CHARS) -> str:
    lines = _split_sum(text, width)
    if len(lines) == 1:
        return math_svg(lines[0])
    return '<span class="ml">' + "".join(f"<span>{math_svg(line)}</span>" for line in lines) + "</span>"


def latex_html(latex: str) -> str:
    """``latex`` as HTML: mathtext pieces as SVG images, matrices as bracketed grids, long sums on several lines."""
    text = to_mathtext(latex)
    parts, i = [], 0
    for match in _MATRIX.finditer(text):
        before = text[i:match.start()].strip()
        if before:
            parts.append(_lines_html(before))
        rows = [row.split("&") for row in re.split(r"\\\\", match.group(1)) if row.strip()]
        cells = "".join("<tr>" + "".join(f"<td>{_lines_html(c.strip(), CELL_CHARS)}</td>" for c in row) + "</tr>"
                        for row in rows)
        parts.append(f'<table class="mat"><tbody>{cells}</tbody></table>')
        i = match.end()
    rest = text[i:].strip()
    if rest:
        parts.append(_lines_html(rest))
    return '<span class="math">' + "".join(parts) + "</span>"
