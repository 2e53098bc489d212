"""Numbers as the report and the paper outputs print them: significant digits, round-off, Markdown tables."""

from __future__ import annotations

import numbers
from collections.abc import Sequence
from typing import Any

from armlab.bounds import above

__all__ = ["DEVIATION_DIGITS", "VALUE_DIGITS", "markdown_table", "paper_value_text", "value_text"]

#: Significant digits: armlab's values and table cells, and deviations (paper values are shown as printed); a
#: magnitude that is zero within the slack (:func:`armlab.bounds.above` of 0) is round-off, shown with
#: :data:`DEVIATION_DIGITS` digits.
VALUE_DIGITS = 7
DEVIATION_DIGITS = 2


def value_text(value: Any, digits: int = VALUE_DIGITS) -> str:
    """A value for the report: a number with ``digits`` significant digits, text as it is, ``None`` as —."""
    if value is None:
        return "—"
    if isinstance(value, str):
        return value
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return str(int(value))
    value = float(value) + 0.0
    if value == 0:
        return "0"
    if not above(abs(value), 0.0):  # round-off: its digits mean nothing
        digits = min(digits, DEVIATION_DIGITS)
    if abs(value) < 1e-3 or abs(value) >= 1e7:
        return f"{value:.{max(digits - 1, 0)}e}".replace("e-0", "e-").replace("e+0", "e+")
    return f"{value:.{max(digits, len(str(int(abs(value)))))}g}"  # never fewer than the integer digits (703)


def paper_value_text(value: Any) -> str:
    """A paper value as the paper prints it (up to 10 significant digits, no trailing zeros)."""
    return value_text(value, 10)


def _md_cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def markdown_table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A GitHub-flavoured Markdown table; numbers with :data:`VALUE_DIGITS` significant digits."""
    lines = ["| " + " | ".join(_md_cell(h) for h in headers) + " |", "|" + "---|" * len(headers)]
    for row in rows:
        lines.append("| " + " | ".join(_md_cell(value_text(v)) for v in row) + " |")
    return "\n".join(lines) + "\n"
