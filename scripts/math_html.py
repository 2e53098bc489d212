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
import io
import re
from functools import cache
from itertools import pairwise

__all__ = ["latex_html", "math_svg", "to_mathtext"]

#: Visual characters (commands, braces, sub/superscript marks not counted) per rendered line, and per line
#: of a matrix cell.
LINE_CHARS = 80
CELL_CHARS = 40
FONT_SIZE = 11.0

#: What matplotlib's SVG holds besides the drawing: its metadata (with the time it was made) and comments.
_METADATA = re.compile(rb"\s*<metadata>.*?</metadata>|\s*<!--.*?-->", re.S)
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


@cache
def math_svg(mathtext: str) -> str:
    """``mathtext`` (no ``$``) as an ``<img>`` holding its SVG (glyphs as paths: no fonts needed)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import rc_context
    from matplotlib.font_manager import FontProperties
    from matplotlib.mathtext import math_to_image

    buffer = io.BytesIO()
    try:
        with rc_context({"svg.fonttype": "path", "mathtext.fontset": "dejavuserif", "savefig.transparent": True}):
            math_to_image(f"${mathtext}$", buffer, prop=FontProperties(size=FONT_SIZE), format="svg")
    except ValueError as error:
        raise ValueError(f"mathtext cannot render {mathtext!r}: {str(error).splitlines()[0]}") from None
    svg = _METADATA.sub(b"", buffer.getvalue())  # the same image whenever and wherever it is made, and smaller
    data = base64.b64encode(svg).decode()
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
