"""Rows of the paper-vs-armlab report: one published number beside armlab's value, and its verdict.

Every :class:`Row` compares one number (or printed expression) the paper publishes with
the value armlab computes at run time. Its verdict is exactly one of

* ``"matches"``, or ``"matches: <qualifier>"`` when the match holds only by construction or
  for armlab's chosen parameters (:func:`matches`);
* ``"differs: <reason>"``;
* ``"not reproducible: <what the paper leaves out>"``.

A paper script records its rows through :class:`armlab.papers.paper_output.PaperOutput`;
:func:`armlab.papers.report.write_report` shows them.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

from armlab.bounds import within

__all__ = [
    "DIFFERS",
    "MATCHES",
    "NOT_REPRODUCIBLE",
    "VERDICT_KINDS",
    "Row",
    "Value",
    "compare",
    "differs",
    "matches",
    "not_reproducible",
    "verdict_counts",
]

MATCHES = "matches"
DIFFERS = "differs"
NOT_REPRODUCIBLE = "not reproducible"
VERDICT_KINDS = (MATCHES, DIFFERS, NOT_REPRODUCIBLE)

Value = float | str | None


def matches(qualifier: str = "") -> str:
    """``"matches"``, or ``"matches: <qualifier>"`` (e.g. "by construction", "holds for the chosen lengths")."""
    return f"{MATCHES}: {qualifier}" if qualifier else MATCHES


def differs(reason: str) -> str:
    """The verdict ``"differs: <reason>"``."""
    return f"{DIFFERS}: {reason}"


def not_reproducible(what: str) -> str:
    """The verdict ``"not reproducible: <what the paper leaves out>"``."""
    return f"{NOT_REPRODUCIBLE}: {what}"


@dataclass(frozen=True)
class Row:
    """One published number beside armlab's value. ``deviation`` is armlab − paper (or a norm)."""

    paper: str
    quantity: str
    paper_value: Value
    armlab_value: Value
    deviation: Value
    verdict: str
    note: str = ""

    def __post_init__(self) -> None:
        if self.verdict != MATCHES and not any(self.verdict.startswith(f"{k}: ") for k in VERDICT_KINDS):
            raise ValueError(f"verdict {self.verdict!r} is not allowed: "
                             "'matches', 'matches: …', 'differs: …' or 'not reproducible: …'")

    @property
    def kind(self) -> str:
        """``"matches"``, ``"differs"`` or ``"not reproducible"``."""
        return self.verdict.split(":", 1)[0]


def compare(
    paper: str,
    quantity: str,
    paper_value: float,
    armlab_value: float,
    tol: float,
    note: str = "",
    reason: str | None = None,
) -> Row:
    """A numeric row: ``"matches"`` when armlab's value is within [paper − ``tol``, paper + ``tol``]
    (:func:`armlab.bounds.within`: a deviation of exactly half a printed digit matches on every machine), else
    ``"differs: <reason>"``.

    ``tol`` is the resolution of the paper's printed value (half its last digit) unless
    ``note`` says otherwise; the default reason quotes the deviation and the tolerance.
    """
    deviation = float(armlab_value) - float(paper_value)
    if within(float(armlab_value), float(paper_value) - tol, float(paper_value) + tol):
        verdict = MATCHES
    else:
        verdict = differs(reason or f"|deviation| {abs(deviation):.3g} exceeds the tolerance {tol:.3g}")
    return Row(paper, quantity, float(paper_value), float(armlab_value), deviation, verdict, note)


def verdict_counts(rows: Sequence[Row]) -> dict[str, int]:
    """Number of rows per verdict kind (every kind present, possibly 0)."""
    counts = Counter(row.kind for row in rows)
    return {kind: counts.get(kind, 0) for kind in VERDICT_KINDS}
