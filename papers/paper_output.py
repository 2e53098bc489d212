"""One paper's outputs: the figures, tables, notes and rows a paper script writes into its folder.

A paper script (``papers/paper_NNN.py``) writes its figures, tables and notes through a
:class:`PaperOutput`, which prints one progress line per item and records it in the
folder's ``manifest.json``; :meth:`PaperOutput.group` starts a group (a figure or table of the
paper), and the rows (:class:`~armlab.papers.report_rows.Row`), figures, tables, claims, runs and
replays that follow belong to it, so the report (:func:`armlab.papers.report.write_report`, which
reads every paper folder's manifest) shows each figure beside the rows it supports.

Every CSV armlab writes goes through :func:`armlab.files.csv_text`: numbers as plain decimal text (never
the ``repr`` of a numpy scalar), so ``numpy.loadtxt`` and ``csv`` read them back.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

from armlab.files import write_csv
from armlab.papers.errata import ERRATA, check
from armlab.papers.report_rows import Row
from armlab.papers.value_text import markdown_table, value_text
from armlab.presentation.draw import draw_arm
from armlab.presentation.figures import save
from armlab.presentation.graphviz import fig6_dot, render
from armlab.presentation.replay import write_replay

__all__ = ["MANIFEST", "PaperOutput", "errata_checked", "label_parts", "load_rows"]

#: The file in each paper folder that records what the paper's script wrote (:meth:`PaperOutput.finish`).
MANIFEST = "manifest.json"


def label_parts(label: str) -> tuple[str, str]:
    """An expression's label "x_{0M}, DH form" as its symbol (LaTeX, "x_{0M}") and its words (" (DH form)", plain
    text: in math mode their spaces would be lost, "x0M,DHform")."""
    symbol, _, words = label.partition(", ")
    return symbol, f" ({words})" if words else ""


@dataclass
class PaperOutput:
    """Collects one paper's rows and writes its figures, tables and notes into ``folder``.

    Everything recorded after :meth:`group` belongs to that group (its ``"group"`` index in the
    manifest; ``"row_groups"`` holds each row's).
    """

    paper: str
    folder: Path
    progress: Callable[[str], Any] = print
    title: str = ""
    rows: list[Row] = field(default_factory=list)
    manifest: dict[str, Any] = field(
        default_factory=lambda: {"title": "", "groups": [], "row_groups": [], "figures": [], "tables": [],
                                 "texts": [], "claims": [], "parameters": [], "runs": [], "replays": [],
                                 "schemes": [], "errata": []}
    )

    def __post_init__(self) -> None:
        self.folder = Path(self.folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.manifest["title"] = self.title

    def _say(self, what: str, files: Sequence[str]) -> None:
        self.progress(f"[{self.paper}] {what} → {', '.join(files)}")

    def _group_index(self) -> int:
        if not self.manifest["groups"]:
            self.group("Other results")
        return len(self.manifest["groups"]) - 1

    def _record(self, kind: str, entry: dict[str, Any]) -> None:
        self.manifest[kind].append({**entry, "group": self._group_index()})

    def group(self, title: str, text: str = "") -> None:
        """Start a group (one figure or table of the paper, or one claim): what follows belongs to it."""
        self.manifest["groups"].append({"title": title, "text": text})

    def add(self, *rows: Row) -> None:
        """Append report rows (to the current group)."""
        index = self._group_index()
        self.rows.extend(rows)
        self.manifest["row_groups"].extend([index] * len(rows))

    def figure(self, fig: Any, stem: str, label: str, caption: str) -> None:
        """Save a matplotlib figure as ``stem.png`` (120 dpi) and ``stem.svg`` and close it."""
        files = save(fig, self.folder / stem)
        self._record("figures", {"label": label, "caption": caption, "png": f"{stem}.png", "svg": f"{stem}.svg"})
        self._say(label, [p.name for p in files])

    def scheme(self, arm: Any, q: Any, stem: str, label: str) -> None:
        """The arm's kinematic scheme at ``q`` (:func:`armlab.presentation.draw.draw_arm`) as ``stem.png``."""
        draw_arm(arm, q, self.folder / f"{stem}.png")
        self.manifest["schemes"].append({"label": label, "png": f"{stem}.png"})
        self._say(label, [f"{stem}.png"])

    def table(self, stem: str, label: str, headers: Sequence[str], rows: Sequence[Sequence[Any]],
              note: str = "") -> None:
        """Write a table as ``stem.csv`` (full precision, :func:`~armlab.files.csv_text`) and ``stem.md``."""
        write_csv(self.folder / f"{stem}.csv", headers, rows)
        text = f"# {label}\n\n" + markdown_table(headers, rows) + (f"\n{note}\n" if note else "")
        (self.folder / f"{stem}.md").write_text(text)
        self._record("tables", {"label": label, "csv": f"{stem}.csv", "md": f"{stem}.md", "headers": list(headers),
                                "rows": [[value_text(v) for v in r] for r in rows], "note": note})
        self._say(label, [f"{stem}.csv", f"{stem}.md"])

    def expressions(self, stem: str, label: str, title: str, intro: str, entries: Sequence[tuple[Any, str]],
                    beyond: Sequence[str] = ()) -> None:
        """Write printed expressions as ``stem.md``: per entry (a :class:`~armlab.kinematics.symbolic.LatexItem`
        and a note whether it matches the paper's printed form) a heading, the LaTeX and the note. The
        report renders them, except those whose labels are in ``beyond`` (derived, not printed by the
        paper: named there, with a pointer to ``stem.md``)."""
        lines = [f"# {title}", "", intro, ""]
        for item, note in entries:
            symbol, words = label_parts(item.label)
            lines += [f"## ${symbol}${words} — {item.source}", "", f"$$\n{item.latex}\n$$", "", f"*{note}*", ""]
        (self.folder / f"{stem}.md").write_text("\n".join(lines))
        self._record("texts", {"label": label, "md": f"{stem}.md", "intro": intro, "entries": [
            {"label": item.label, "source": item.source, "latex": item.latex, "note": note,
             "printed": item.label not in beyond} for item, note in entries]})
        self._say(label, [f"{stem}.md"])

    def simulated_run(self, log: Any, stem: str, label: str) -> None:
        """A simulated run's Systems diagram as ``diagram_<stem>.svg`` (the Fig. 6 view,
        :func:`armlab.presentation.graphviz.fig6_dot`) and its 3-D replay as ``replay_<stem>.html``."""
        svg, replay = f"diagram_{stem}.svg", f"replay_{stem}.html"
        dot = fig6_dot(log.diagram_dot)
        (self.folder / svg).write_bytes(render(dot, "svg"))
        write_replay(log.arm, log.t, log.q, self.folder / replay, tool_path=log.tool[:, :3])
        # the diagram's structure, whatever order Drake lists its connections in: the report shows each once
        structure = hashlib.sha1("\n".join(sorted(dot.splitlines())).encode()).hexdigest()
        self._record("runs", {"label": label, "svg": svg, "replay": replay, "structure": structure})
        self._say(f"{label}: Systems diagram and 3-D replay", [svg, replay])

    def replay(self, arm: Any, t: Any, q: Any, stem: str, label: str) -> None:
        """A kinematic motion ``q(t)`` of ``arm`` as the 3-D replay ``replay_<stem>.html`` (no simulation)."""
        name = f"replay_{stem}.html"
        write_replay(arm, t, q, self.folder / name)
        self._record("replays", {"label": label, "replay": name})
        self._say(f"{label}: 3-D replay", [name])

    def claim(self, title: str, text: str, headers: Sequence[str] = (), rows: Sequence[Sequence[Any]] = (),
              figures: Sequence[str] = ()) -> None:
        """A claim of the paper that the numbers contradict (or qualify), with evidence (``figures``: PNG names
        of figures recorded in this paper, shown with the claim)."""
        self._record("claims", {"title": title, "text": text, "headers": list(headers),
                                "rows": [[value_text(v) for v in r] for r in rows], "figures": list(figures)})

    def chosen(self, name: str, value: str, why: str) -> None:
        """A parameter armlab chose where the paper is silent."""
        self.manifest["parameters"].append({"name": name, "value": value, "why": why})

    def errata(self, samples: int = 20) -> None:
        """Record this paper's errata (:data:`armlab.papers.errata.ERRATA`) with their errors against Drake."""
        mine = [e for e in ERRATA if e.paper == self.paper]
        checked = {}
        if any(e.evaluable for e in mine):
            checked = {id(e): (printed, corrected) for e, printed, corrected in errata_checked(samples, self.paper)}
        for e in mine:
            if id(e) in checked:
                printed, corrected = checked[id(e)]
                evidence = (f"Against Drake at {samples} random configurations: printed form off by up to "
                            f"{value_text(printed, 3)}, corrected form by {value_text(corrected, 2)}.")
            else:
                evidence = "Not evaluable against Drake: a printing or naming error, no quantity to compare."
            self.manifest["errata"].append({"where": f"{e.paper} {e.equation}", "description": e.description,
                                            "printed": e.printed_form, "corrected": e.corrected_form,
                                            "evidence": evidence})

    def chosen_parameters(self, arm: Any, keys: Sequence[str]) -> None:
        """Record the arm parameters ``keys`` that its model file marks as chosen, with the reason given there."""
        prefix = "chosen, not from the paper: "
        for key in keys:
            self.chosen(f"{arm.name} {key}", f"{arm.parameters[key]:g}", arm.notes[key].removeprefix(prefix))

    def finish(self) -> list[Row]:
        """Record the paper's errata, write ``rows.csv`` and ``manifest.json``; return the rows."""
        self.errata()
        write_csv(self.folder / "rows.csv", ["paper", "quantity", "paper_value", "armlab_value", "deviation",
                                             "verdict", "note"], [list(asdict(row).values()) for row in self.rows])
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
def errata_checked(samples: int, paper: str) -> list[tuple[Any, float, float]]:
    """:func:`armlab.papers.errata.check` of ``paper``'s errata, once per process (it queries Drake)."""
    return check(samples, paper=paper)
