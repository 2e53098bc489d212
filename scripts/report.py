"""Rows of the paper-vs-armlab report, each paper's outputs, and the report writer (Markdown + HTML).

A paper script (``scripts/paper_NNN.py``) writes its figures, tables and notes through a
:class:`PaperOutput`, which prints one progress line per item and records it in the
folder's ``manifest.json``. :func:`write_report` then reads every paper folder's manifest
and writes ``report.md`` and ``report.html`` (figures inline) beside them.

Every :class:`Row` compares one number (or printed expression) the paper publishes with
the value armlab computes at run time. Its verdict is exactly one of

* ``"matches"``;
* ``"differs: <reason>"``;
* ``"not reproducible: <what the paper leaves out>"``.
"""

from __future__ import annotations

import csv
import html
import json
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

__all__ = [
    "MATCHES",
    "PaperOutput",
    "Row",
    "compare",
    "differs",
    "load_rows",
    "markdown_table",
    "not_reproducible",
    "verdict_counts",
    "write_report",
]

MATCHES = "matches"
DIFFERS = "differs"
NOT_REPRODUCIBLE = "not reproducible"
VERDICT_KINDS = (MATCHES, DIFFERS, NOT_REPRODUCIBLE)
MANIFEST = "manifest.json"

Value = float | str | None


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
        if self.verdict != MATCHES and not any(self.verdict.startswith(f"{k}: ") for k in VERDICT_KINDS[1:]):
            raise ValueError(f"verdict {self.verdict!r} is not allowed: "
                             "'matches', 'differs: …' or 'not reproducible: …'")

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
    """A numeric row: ``"matches"`` when |armlab − paper| ≤ ``tol``, else ``"differs: <reason>"``.

    ``tol`` is the resolution of the paper's printed value (half its last digit) unless
    ``note`` says otherwise; the default reason quotes the deviation and the tolerance.
    """
    deviation = float(armlab_value) - float(paper_value)
    if abs(deviation) <= tol:
        verdict = MATCHES
    else:
        verdict = differs(reason or f"|deviation| {abs(deviation):.3g} exceeds the tolerance {tol:.3g}")
    return Row(paper, quantity, float(paper_value), float(armlab_value), deviation, verdict, note)


def verdict_counts(rows: Sequence[Row]) -> dict[str, int]:
    """Number of rows per verdict kind (every kind present, possibly 0)."""
    counts = Counter(row.kind for row in rows)
    return {kind: counts.get(kind, 0) for kind in VERDICT_KINDS}


def _fmt(value: Value, digits: int = 10) -> str:
    if value is None:
        return "—"
    if isinstance(value, str):
        return value
    if value == 0:
        return "0"
    if abs(value) < 1e-3 or abs(value) >= 1e6:
        return f"{value:.3e}"
    return f"{value:.{digits}g}"


def _md_cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def markdown_table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A GitHub-flavoured Markdown table; floats printed with 10 significant digits."""
    lines = ["| " + " | ".join(_md_cell(h) for h in headers) + " |", "|" + "---|" * len(headers)]
    for row in rows:
        lines.append("| " + " | ".join(_md_cell(_fmt(v) if not isinstance(v, str) else v) for v in row) + " |")
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------- one paper's outputs
@dataclass
class PaperOutput:
    """Collects one paper's rows and writes its figures, tables and notes into ``folder``."""

    paper: str
    folder: Path
    progress: Callable[[str], Any] = print
    rows: list[Row] = field(default_factory=list)
    manifest: dict[str, list] = field(
        default_factory=lambda: {"figures": [], "tables": [], "texts": [], "claims": [], "parameters": [],
                                 "runs": [], "errata": []}
    )

    def __post_init__(self) -> None:
        self.folder = Path(self.folder)
        self.folder.mkdir(parents=True, exist_ok=True)

    def _say(self, what: str, files: Sequence[str]) -> None:
        self.progress(f"[{self.paper}] {what} → {', '.join(files)}")

    def add(self, *rows: Row) -> None:
        """Append report rows."""
        self.rows.extend(rows)

    def figure(self, fig: Any, stem: str, label: str, caption: str) -> None:
        """Save a matplotlib figure as ``stem.png`` (120 dpi) and ``stem.svg`` and close it."""
        from armlab.scripts.figures import save

        files = save(fig, self.folder / stem)
        self.manifest["figures"].append({"label": label, "caption": caption, "png": f"{stem}.png",
                                         "svg": f"{stem}.svg"})
        self._say(label, [p.name for p in files])

    def table(self, stem: str, label: str, headers: Sequence[str], rows: Sequence[Sequence[Any]],
              note: str = "") -> None:
        """Write a table as ``stem.csv`` (full precision) and ``stem.md``."""
        with open(self.folder / f"{stem}.csv", "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(headers)
            writer.writerows([[repr(v) if isinstance(v, float) else v for v in row] for row in rows])
        text = f"# {label}\n\n" + markdown_table(headers, rows) + (f"\n{note}\n" if note else "")
        (self.folder / f"{stem}.md").write_text(text)
        self.manifest["tables"].append({"label": label, "csv": f"{stem}.csv", "md": f"{stem}.md",
                                        "headers": list(headers), "rows": [[_fmt(v) for v in r] for r in rows],
                                        "note": note})
        self._say(label, [f"{stem}.csv", f"{stem}.md"])

    def expressions(self, stem: str, label: str, title: str, intro: str, entries: Sequence[tuple[Any, str]]) -> None:
        """Write printed expressions as ``stem.md``: per entry (a :class:`~armlab.kinematics.symbolic.LatexItem`
        and a note whether it matches the paper's printed form) a heading, the LaTeX and the note."""
        lines = [f"# {title}", "", intro, ""]
        for item, note in entries:
            lines += [f"## {item.label} — {item.source}", "", f"$$\n{item.latex}\n$$", "", f"*{note}*", ""]
        (self.folder / f"{stem}.md").write_text("\n".join(lines))
        self.manifest["texts"].append({"label": label, "md": f"{stem}.md"})
        self._say(label, [f"{stem}.md"])

    def simulated_run(self, log: Any, stem: str, label: str) -> None:
        """A simulated run's Systems diagram as ``diagram_<stem>.svg`` (graphviz's ``dot``) and its 3-D
        replay as ``replay_<stem>.html`` (:func:`armlab.diagrams.replay.write_replay`)."""
        from armlab.diagrams.graphviz import render
        from armlab.diagrams.replay import write_replay

        svg, replay = f"diagram_{stem}.svg", f"replay_{stem}.html"
        (self.folder / svg).write_bytes(render(log.diagram_dot, "svg"))
        write_replay(log.arm, log.t, log.q, self.folder / replay, tool_path=log.tool[:, :3])
        self.manifest["runs"].append({"label": label, "svg": svg, "replay": replay})
        self._say(f"{label}: Systems diagram and 3-D replay", [svg, replay])

    def claim(self, title: str, text: str, headers: Sequence[str] = (), rows: Sequence[Sequence[Any]] = (),
              figures: Sequence[str] = ()) -> None:
        """A claim of the paper that the numbers contradict (or qualify), with evidence."""
        self.manifest["claims"].append({"title": title, "text": text, "headers": list(headers),
                                        "rows": [[_fmt(v) for v in r] for r in rows], "figures": list(figures)})

    def chosen(self, name: str, value: str, why: str) -> None:
        """A parameter armlab chose where the paper is silent."""
        self.manifest["parameters"].append({"name": name, "value": value, "why": why})

    def errata(self, samples: int = 20) -> None:
        """Record this paper's errata (:data:`armlab.kinematics.errata.ERRATA`) with their errors against Drake."""
        from armlab.kinematics.errata import ERRATA

        mine = [e for e in ERRATA if e.paper == self.paper]
        checked = {}
        if any(e.evaluable for e in mine):
            checked = {id(e): (printed, corrected) for e, printed, corrected in _errata_checked(samples)}
        for e in mine:
            if id(e) in checked:
                printed, corrected = checked[id(e)]
                evidence = (f"{e.description} Against Drake at {samples} random configurations: printed form off by "
                            f"up to {printed:.3g}, corrected form by {corrected:.1e}.")
            else:
                evidence = f"{e.description} (not evaluable: a printing or naming error)"
            self.manifest["errata"].append({"where": f"{e.paper} {e.equation}", "printed": e.printed_form,
                                            "corrected": e.corrected_form, "evidence": evidence})

    def chosen_parameters(self, arm: Any, keys: Sequence[str]) -> None:
        """Record the arm parameters ``keys`` that its model file marks as chosen, with the reason given there."""
        prefix = "chosen, not from the paper: "
        for key in keys:
            self.chosen(f"{arm.name} {key}", f"{arm.parameters[key]:g}", arm.notes[key].removeprefix(prefix))

    def finish(self) -> list[Row]:
        """Record the paper's errata, write ``rows.csv`` and ``manifest.json``; return the rows."""
        self.errata()
        with open(self.folder / "rows.csv", "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(["paper", "quantity", "paper_value", "armlab_value", "deviation", "verdict", "note"])
            for row in self.rows:
                writer.writerow([repr(v) if isinstance(v, float) else ("" if v is None else v)
                                 for v in asdict(row).values()])
        self.manifest["rows"] = [asdict(row) for row in self.rows]
        (self.folder / MANIFEST).write_text(json.dumps(self.manifest, indent=1, ensure_ascii=False))
        return self.rows


def load_rows(folder: Path) -> list[Row] | None:
    """The report rows a paper folder's ``manifest.json`` recorded, or ``None`` if it has none."""
    try:
        manifest = json.loads((Path(folder) / MANIFEST).read_text())
    except (OSError, ValueError):
        return None
    rows = manifest.get("rows") if isinstance(manifest, dict) else None
    return None if rows is None else [Row(**row) for row in rows]


# --------------------------------------------------------------------------- errata
@cache
def _errata_checked(samples: int) -> list[tuple[Any, float, float]]:
    """:func:`armlab.kinematics.errata.check` once per process (it queries Drake for every paper)."""
    from armlab.kinematics.errata import check

    return check(samples)


# --------------------------------------------------------------------------- the report
class _Doc:
    """Blocks rendered both as Markdown and as HTML."""

    def __init__(self) -> None:
        self.md: list[str] = []
        self.html: list[str] = []

    def heading(self, level: int, text: str) -> None:
        self.md.append(f"{'#' * level} {text}\n")
        self.html.append(f"<h{level}>{html.escape(text)}</h{level}>")

    def para(self, text: str, html_text: str | None = None) -> None:
        self.md.append(text + "\n")
        self.html.append(f"<p>{html_text if html_text is not None else html.escape(text)}</p>")

    def table(self, headers: Sequence[str], rows: Sequence[Sequence[Any]], classes: Sequence[str] = ()) -> None:
        self.md.append(markdown_table(headers, rows))
        out = ["<table><thead><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in headers) + "</tr></thead><tbody>"]
        for i, row in enumerate(rows):
            css = f' class="{classes[i]}"' if i < len(classes) and classes[i] else ""
            out.append(f"<tr{css}>" + "".join(f"<td>{html.escape(_fmt(v))}</td>" for v in row) + "</tr>")
        out.append("</tbody></table>")
        self.html.append("".join(out))

    def image(self, src: str, caption: str) -> None:
        self.md.append(f"![{caption}]({src})\n")
        self.html.append(f'<figure><img src="{html.escape(src)}" alt="{html.escape(caption)}">'
                         f"<figcaption>{html.escape(caption)}</figcaption></figure>")


_CSS = """body{font-family:system-ui,sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;margin:1em 0;font-size:0.9em}th,td{border:1px solid #bbb;padding:3px 6px;
text-align:left;vertical-align:top}th{background:#eee}tr.matches td:nth-child(6){color:#16692b}
tr.differs td:nth-child(6){color:#a15c00}tr.notrep td:nth-child(6){color:#7a1f1f}
figure{display:inline-block;margin:0.5em;max-width:100%}img{max-width:100%;border:1px solid #ddd}
figcaption{font-size:0.85em;color:#555}code,pre{background:#f6f6f6}"""


def write_report(
    out_dir: Path,
    papers: Sequence[str],
    rows: Sequence[Row],
    elapsed: float | None = None,
) -> Path:
    """Write ``out_dir/report.md`` and ``out_dir/report.html`` from the rows and each paper folder's manifest."""
    out_dir = Path(out_dir)
    counts = verdict_counts(rows)
    manifests = {p: json.loads((out_dir / p / MANIFEST).read_text()) for p in papers}
    doc = _Doc()
    doc.heading(1, "armlab reproduce: the papers beside armlab")
    summary = (f"{len(rows)} published numbers and claims checked: {counts[MATCHES]} match, "
               f"{counts[DIFFERS]} differ, {counts[NOT_REPRODUCIBLE]} are not reproducible from what the papers print.")
    if elapsed is not None:
        summary += f" Reproduction took {elapsed:.1f} s."
    doc.para(summary)
    doc.para("Every armlab value below is computed at run time; paper values are the papers' printed numbers. "
             "Deviation = armlab − paper (or the largest absolute difference for a vector or matrix).")

    doc.heading(2, "Published numbers")
    headers = ["paper", "quantity", "paper value", "armlab value", "deviation", "verdict", "note"]
    css = {MATCHES: "matches", DIFFERS: "differs", NOT_REPRODUCIBLE: "notrep"}
    for paper in papers:
        mine = [r for r in rows if r.paper == paper]
        c = verdict_counts(mine)
        doc.heading(3, f"Paper {paper} ({c[MATCHES]} match, {c[DIFFERS]} differ, "
                       f"{c[NOT_REPRODUCIBLE]} not reproducible)")
        doc.table(headers, [[r.paper, r.quantity, r.paper_value, r.armlab_value, r.deviation, r.verdict, r.note]
                            for r in mine], [css[r.kind] for r in mine])

    doc.heading(2, "Errata: printed equations that disagree with Drake")
    errata = [e for p in papers for e in manifests[p]["errata"]]
    if errata:
        doc.para("Printed and corrected forms are LaTeX; the evidence evaluates both against Drake's plant.")
        doc.table(["where", "as printed", "corrected", "evidence"],
                  [[e["where"], e["printed"], e["corrected"], e["evidence"]] for e in errata])
    else:
        doc.para("No errata among the papers reproduced here.")

    doc.heading(2, "What the papers claim, and what the numbers say")
    for paper in papers:
        for claim in manifests[paper]["claims"]:
            doc.heading(3, f"{paper}: {claim['title']}")
            doc.para(claim["text"])
            if claim["headers"]:
                doc.table(claim["headers"], claim["rows"])
            for fig in claim["figures"]:
                doc.image(f"{paper}/{fig}", fig)

    doc.heading(2, "Parameters armlab chose where the papers are silent")
    doc.table(["paper", "parameter", "value", "why"],
              [[p, c["name"], c["value"], c["why"]] for p in papers for c in manifests[p]["parameters"]])

    doc.heading(2, "Figures, tables, expressions, diagrams and 3-D replays")
    for paper in papers:
        m = manifests[paper]
        doc.heading(3, f"Paper {paper}")
        links = [(t["label"], [t["csv"], t["md"]]) for t in m["tables"]]
        links += [(t["label"], [t["md"]]) for t in m["texts"]]
        links += [(r["label"], [r["svg"], r["replay"]]) for r in m["runs"]]
        if links:
            doc.md.append("".join(f"- {label}: " + ", ".join(f"[{f}]({paper}/{f})" for f in files) + "\n"
                                  for label, files in links))
            doc.html.append("<ul>" + "".join(
                f"<li>{html.escape(label)}: "
                + ", ".join(f'<a href="{html.escape(paper)}/{html.escape(f)}">{html.escape(f)}</a>' for f in files)
                + "</li>" for label, files in links) + "</ul>")
        for table in m["tables"]:
            doc.heading(4, table["label"])
            doc.table(table["headers"], table["rows"])
            if table["note"]:
                doc.para(table["note"])
        for fig in m["figures"]:
            doc.image(f"{paper}/{fig['png']}", f"{fig['label']}: {fig['caption']}")
        for r in m["runs"]:
            doc.image(f"{paper}/{r['svg']}", f"{r['label']}: Systems diagram (3-D replay: {r['replay']})")

    md_path = out_dir / "report.md"
    md_path.write_text("\n".join(doc.md))
    page = ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>armlab reproduce</title>"
            f"<style>{_CSS}</style></head><body>" + "\n".join(doc.html) + "</body></html>\n")
    (out_dir / "report.html").write_text(page)
    return md_path
