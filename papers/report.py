"""The report writer: ``report.md`` and a self-contained ``report.html`` of the papers beside armlab.

:func:`write_report` reads every paper folder's manifest (written by
:class:`armlab.papers.paper_output.PaperOutput`) and writes ``report.md`` and ``report.html``
(figures embedded, mathematics rendered by :mod:`armlab.papers.math_html`, no network): a summary
per paper, contents, then per paper its rows (:class:`~armlab.papers.report_rows.Row`) beside their
figures. :func:`report_math`, :func:`report_images` and :func:`embed_images` let a caller render the
mathematics and embed the figures ahead (e.g. in parallel, as each paper ends).
"""

from __future__ import annotations

import base64
import hashlib
import html
import io
import json
import numbers
from collections import Counter
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from armlab.papers.math_html import MATH_CSS, latex_html
from armlab.papers.paper_output import MANIFEST, label_parts
from armlab.papers.report_rows import DIFFERS, MATCHES, NOT_REPRODUCIBLE, VERDICT_KINDS, Row, verdict_counts
from armlab.papers.value_text import DEVIATION_DIGITS, VALUE_DIGITS, markdown_table, paper_value_text, value_text

__all__ = ["embed_images", "report_images", "report_math", "write_report"]


_CSS = """body{font-family:system-ui,sans-serif;max-width:1280px;margin:1.5em auto;padding:0 1em;color:#222;
line-height:1.35}h1{font-size:1.6em}h2{border-bottom:2px solid #1f5fa8;padding-bottom:.15em;margin-top:1.8em}
h3{margin:1.4em 0 .4em;color:#1f3f68}h4{margin:1em 0 .3em}
table{border-collapse:collapse;margin:.6em 0;font-size:.88em}th,td{border:1px solid #c8c8c8;padding:3px 6px;
text-align:left;vertical-align:top}th{background:#eef2f6}td.n{text-align:right;font-variant-numeric:tabular-nums;
white-space:nowrap}td.t{font-size:.92em}.mark{color:#666;font-size:.8em;vertical-align:super}.note{display:block;color:#666;font-size:.86em}
tr.matches td.v{color:#16692b}tr.differs td.v{color:#a15c00}tr.notrep td.v{color:#8b1a1a}
tr.matches td.v b,tr.differs td.v b,tr.notrep td.v b{display:block}
.summary td,.summary th{font-size:1.05em;padding:5px 10px}.summary a{font-weight:bold;text-decoration:none}
.c-matches{color:#16692b}.c-differs{color:#a15c00}.c-notrep{color:#8b1a1a}
.figs{display:grid;grid-template-columns:repeat(auto-fill,minmax(380px,1fr));gap:10px;margin:.5em 0}
figure{margin:0;border:1px solid #ddd;padding:4px;background:#fff;cursor:zoom-in}figure img{width:100%;height:auto}
figure.big{grid-column:1/-1;cursor:zoom-out;overflow-x:auto}figure.big img{width:auto;max-width:none;display:block;
margin:auto}figcaption{font-size:.82em;color:#555}figcaption a{margin-left:.5em;white-space:nowrap}
.toc{columns:2;font-size:.92em;background:#f6f8fa;padding:.6em 1.2em;border:1px solid #dde}
.toc ul{margin:.1em 0;padding-left:1.2em}.toc>ul{padding-left:0;list-style:none}
.scroll{max-height:560px;overflow:auto;border:1px solid #ddd;padding:.3em .6em;background:#fcfcfc}
.expr{margin:.6em 0 .9em}.expr .lhs{margin-right:.4em}.files{font-size:.88em}
.claim{border-left:4px solid #a15c00;padding:.2em .8em;background:#fffaf2;margin:.6em 0}
.index{font-size:.9em;margin:.3em 0 .5em}.index a{text-decoration:none}.index summary{cursor:pointer}
table.rows{width:100%;table-layout:fixed}table.rows th:nth-child(1){width:36%}table.rows th:nth-child(2){width:13%}
table.rows th:nth-child(3){width:15%}table.rows th:nth-child(4){width:7%}table.rows td{overflow-wrap:anywhere}
.erratum{margin:.7em 0;padding:.3em .6em;border-left:4px solid #1f5fa8;background:#f7f9fc}
.pc{display:grid;grid-template-columns:1fr 1fr;gap:.3em 1em;margin-top:.3em}.pc>div{overflow-x:auto}
.tag{display:block;font-size:.78em;color:#666;text-transform:uppercase;letter-spacing:.04em}""" + MATH_CSS


def _anchor(*parts: str) -> str:
    return "-".join(part.replace(" ", "").replace(".", "") for part in parts)


def _data_uri(path: Path) -> str:
    """The file as a data URI; a PNG re-encoded with a 256-colour palette (a quarter of the bytes, same look)."""
    if path.suffix == ".png":
        from PIL import Image

        buffer = io.BytesIO()
        with Image.open(path) as image:
            image.convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE).save(buffer, format="PNG")
        return f"data:image/png;base64,{base64.b64encode(buffer.getvalue()).decode()}"
    return f"data:image/svg+xml;base64,{base64.b64encode(path.read_bytes()).decode()}"


class _Doc:
    """Blocks rendered both as Markdown and as HTML; ``math`` holds LaTeX already rendered (LaTeX → HTML),
    ``images`` figures already embedded (path relative to the report → data URI)."""

    def __init__(self, out_dir: Path, math: Mapping[str, str] | None = None,
                 images: Mapping[str, str] | None = None) -> None:
        self.out_dir = out_dir
        self.md: list[str] = []
        self.html: list[str] = []
        self.math = math or {}
        self.images = images or {}

    def latex(self, text: str) -> str:
        """``text`` (LaTeX) as HTML: rendered already, or now (:func:`armlab.papers.math_html.latex_html`)."""
        return self.math[text] if text in self.math else latex_html(text)

    def heading(self, level: int, text: str, anchor: str = "") -> None:
        self.md.append(f"{'#' * level} {text}" + (f' <a id="{anchor}"></a>' if anchor else "") + "\n")
        ident = f' id="{anchor}"' if anchor else ""
        self.html.append(f"<h{level}{ident}>{html.escape(text)}</h{level}>")

    def para(self, text: str, html_text: str | None = None, css: str = "") -> None:
        self.md.append(text + "\n")
        cls = f' class="{css}"' if css else ""
        self.html.append(f"<p{cls}>{html_text if html_text is not None else html.escape(text)}</p>")

    def raw(self, md: str, html_text: str) -> None:
        self.md.append(md)
        self.html.append(html_text)

    def table(self, headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> None:
        self.md.append(markdown_table(headers, rows))
        body = "".join("<tr>" + "".join(f"<td>{html.escape(value_text(v))}</td>" for v in row) + "</tr>"
                       for row in rows)
        self.html.append("<table><thead><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in headers)
                         + f"</tr></thead><tbody>{body}</tbody></table>")

    def figures(self, items: Sequence[tuple[str, str]]) -> None:
        """Figures (path relative to the report, caption) in a grid, embedded in the HTML: a click shows one at its
        full size (the page scrolls sideways if it is wider), and its link opens the PNG file itself."""
        if not items:
            return
        self.md.append("".join(f"![{caption}]({src})\n\n" for src, caption in items))
        self.html.append('<div class="figs">' + "".join(
            f'<figure onclick="this.classList.toggle(\'big\')" title="click to enlarge or shrink">'
            f'<img src="{self.images.get(src) or _data_uri(self.out_dir / src)}" alt="{html.escape(caption)}">'
            f"<figcaption>{html.escape(caption)}<a href=\"{html.escape(src)}\" target=\"_blank\" "
            f"onclick=\"event.stopPropagation()\">open full size ↗</a></figcaption></figure>"
            for src, caption in items) + "</div>")


_CSS_KIND = {MATCHES: "matches", DIFFERS: "differs", NOT_REPRODUCIBLE: "notrep"}
_ROW_HEADERS = ["quantity (and where armlab's value comes from)", "paper value", "armlab value", "deviation",
                "verdict"]


def _rows_block(doc: _Doc, paper: str, numbered: Sequence[tuple[int, Row]]) -> None:
    """The rows as a table; a note several rows share is printed once under it, the rows marked [1], [2], …"""
    shared = [note for note, count in Counter(r.note for _, r in numbered if r.note).items() if count > 1]
    marks = {note: f"[{i + 1}]" for i, note in enumerate(shared)}
    if len(marks) == 1 and all(r.note in marks for _, r in numbered):  # one note for all: below, unmarked
        marks = {shared[0]: "For every row above:"}

    def note_of(r: Row) -> str:
        if r.note in marks:
            return "" if len(marks) == 1 and marks[r.note].startswith("For") else f"see {marks[r.note]}"
        return r.note

    def cell(value: Any, digits: int = VALUE_DIGITS, paper_value: bool = False) -> str:
        text = paper_value_text(value) if paper_value else value_text(value, digits)
        css = "n" if value is None or isinstance(value, numbers.Real) else "t"
        return f'<td class="{css}">{html.escape(text)}</td>'

    md_rows = [[r.quantity + (f" — {note_of(r)}" if note_of(r) else ""), paper_value_text(r.paper_value),
                value_text(r.armlab_value), value_text(r.deviation, DEVIATION_DIGITS), r.verdict] for _, r in numbered]
    body = []
    for k, r in numbered:
        kind, _, why = r.verdict.partition(": ")
        text = note_of(r)
        if text.startswith("see ["):  # a shared note's mark, on the quantity's line
            note = f' <span class="mark">{html.escape(text.removeprefix("see "))}</span>'
        else:
            note = f'<span class="note">{html.escape(text)}</span>' if text else ""
        verdict = f"<b>{html.escape(kind)}</b>{html.escape(why)}"
        body.append(f'<tr id="{_anchor("row", paper, str(k))}" class="{_CSS_KIND[r.kind]}">'
                    f"<td>{html.escape(r.quantity)}{note}</td>{cell(r.paper_value, paper_value=True)}"
                    f"{cell(r.armlab_value)}{cell(r.deviation, DEVIATION_DIGITS)}"
                    f'<td class="v">{verdict}</td></tr>')
    footnotes = [f"{mark} {note}" for note, mark in marks.items()]
    doc.raw(markdown_table(_ROW_HEADERS, md_rows) + "".join(f"\n{f}\n" for f in footnotes),
            '<table class="rows"><thead><tr>' + "".join(f"<th>{h}</th>" for h in _ROW_HEADERS) + "</tr></thead><tbody>"
            + "".join(body) + "</tbody></table>"
            + "".join(f'<p class="note">{html.escape(f)}</p>' for f in footnotes))


class _MathList(_Doc):
    """A document that renders no mathematics but lists the LaTeX its blocks would render."""

    def __init__(self) -> None:
        super().__init__(Path())
        self.pieces: list[str] = []

    def latex(self, text: str) -> str:
        self.pieces.append(text)
        return ""


def report_math(folder: Path) -> list[str]:
    """The LaTeX pieces the report renders for the paper output in ``folder`` (its expressions and errata), to
    be rendered ahead (e.g. in parallel) and handed to :func:`write_report` as ``math``."""
    manifest = json.loads((Path(folder) / MANIFEST).read_text())
    doc = _MathList()
    for text in manifest["texts"]:
        if "entries" in text:
            _expressions_block(doc, "", text)
    _errata_block(doc, manifest["errata"])
    return list(dict.fromkeys(doc.pieces))


def report_images(folder: Path) -> list[str]:
    """The PNG figures the report embeds from the paper output in ``folder`` (paths relative to the report: the
    folder's name first), to be embedded ahead with :func:`embed_images` and handed to :func:`write_report`."""
    folder = Path(folder)
    manifest = json.loads((folder / MANIFEST).read_text())
    return [f"{folder.name}/{entry['png']}" for entry in manifest["schemes"] + manifest["figures"]]


def embed_images(out_dir: Path, images: Sequence[str]) -> dict[str, str]:
    """``{path: data URI}`` of the ``images`` (paths relative to ``out_dir``), as the report embeds them."""
    return {src: _data_uri(Path(out_dir) / src) for src in images}


def _expressions_block(doc: _Doc, paper: str, text: dict[str, Any]) -> None:
    doc.para(text["intro"] + f" (LaTeX source: {paper}/{text['md']})")
    md, out = [], []
    derived = [e for e in text["entries"] if not e.get("printed", True)]
    for e in (e for e in text["entries"] if e.get("printed", True)):
        symbol, words = label_parts(e["label"])
        md.append(f"**${symbol}$**{words} — {e['source']}\n\n$$\n{e['latex']}\n$$\n\n*{e['note']}*\n")
        out.append(f'<div class="expr"><div><span class="lhs">{doc.latex(symbol)}{html.escape(words)}</span> — '
                   f"{html.escape(e['source'])}: <i>{html.escape(e['note'])}</i></div>"
                   f"<div>{doc.latex(e['latex'])}</div></div>")
    doc.raw("\n".join(md), '<div class="scroll">' + "".join(out) + "</div>")
    if derived:
        intro = f"Derived beyond the paper (not printed there), in {paper}/{text['md']}: "
        labels = [label_parts(e["label"]) for e in derived]
        doc.raw(intro + "; ".join(f"${symbol}${words} ({e['source']})" for (symbol, words), e in
                                  zip(labels, derived, strict=True)) + ".\n",
                f"<p>{html.escape(intro)}" + "; ".join(f"{doc.latex(symbol)}{html.escape(words)} "
                                                      f"({html.escape(e['source'])})"
                                                      for (symbol, words), e in zip(labels, derived, strict=True))
                + ".</p>")


def _errata_block(doc: _Doc, errata: Sequence[dict[str, str]]) -> None:
    md = "".join(f"- **{e['where']}**: {e.get('description', '')} {e['evidence']}\n  - as printed: "
                 f"${e['printed']}$\n  - corrected: ${e['corrected']}$\n" for e in errata)
    body = "".join(f'<div class="erratum"><b>{html.escape(e["where"])}</b>: {html.escape(e.get("description", ""))} '
                   f'<span class="note">{html.escape(e["evidence"])}</span><div class="pc">'
                   f'<div><span class="tag">as printed</span>{doc.latex(e["printed"])}</div>'
                   f'<div><span class="tag">corrected</span>{doc.latex(e["corrected"])}</div></div></div>'
                   for e in errata)
    doc.raw(md + "\n", body)


def _links(doc: _Doc, paper: str, files: Sequence[tuple[str, str]]) -> None:
    if not files:
        return
    doc.raw("".join(f"- {label}: [{f}]({paper}/{f})\n" for label, f in files) + "\n",
            '<ul class="files">' + "".join(
                f'<li>{html.escape(label)}: <a href="{html.escape(paper)}/{html.escape(f)}">{html.escape(f)}</a></li>'
                for label, f in files) + "</ul>")


def _paper_section(doc: _Doc, paper: str, m: dict[str, Any], rows: Sequence[Row], shown: dict[str, str]) -> None:
    """One paper: its verdict index, scheme, groups (rows beside their figures), errata, parameters, files."""
    numbered = list(enumerate(rows))
    doc.heading(2, f"Paper {paper}" + (f": {m['title']}" if m.get("title") else ""), _anchor("paper", paper))
    counts = verdict_counts(rows)
    for kind in VERDICT_KINDS:
        mine = [(k, r) for k, r in numbered if r.kind == kind]
        if not mine:
            continue
        label = f"{counts[kind]} {kind}"
        links = " · ".join(f'<a href="#{_anchor("row", paper, str(k))}">{html.escape(r.quantity)}</a>' for k, r in mine)
        opened = "" if kind == MATCHES else " open"  # the list of matches is long: folded
        doc.raw(f'- <a id="{_anchor(paper, kind)}"></a>{label}: ' + "; ".join(r.quantity for _, r in mine) + "\n",
                f'<details class="index" id="{_anchor(paper, kind)}"{opened}><summary><b class="c-{_CSS_KIND[kind]}">'
                f"{label}</b></summary>{links}</details>")
    if m.get("schemes"):
        doc.heading(3, "The arm", _anchor(paper, "arm"))
        doc.figures([(f"{paper}/{s['png']}", s["label"]) for s in m["schemes"]])
    groups = m.get("groups") or [{"title": "Results", "text": ""}]
    row_groups = m.get("row_groups") or [0] * len(rows)
    for g, group in enumerate(groups):
        doc.heading(3, group["title"], _anchor(paper, "g", str(g)))
        if group.get("text"):
            doc.para(group["text"])
        mine = [(k, r) for k, r in numbered if row_groups[k] == g]
        if mine:
            _rows_block(doc, paper, mine)
        for claim in (c for c in m["claims"] if c.get("group", 0) == g):
            doc.raw(f"**Claim: {claim['title']}.** {claim['text']}\n",
                    f'<div class="claim"><b>Claim: {html.escape(claim["title"])}.</b> {html.escape(claim["text"])}'
                    "</div>")
            if claim["headers"]:
                doc.table(claim["headers"], claim["rows"])
        for table in (t for t in m["tables"] if t.get("group", 0) == g):
            doc.heading(4, table["label"])
            doc.table(table["headers"], table["rows"])
            if table["note"]:
                doc.para(table["note"], css="note")
            _links(doc, paper, [("full precision", table["csv"])])
        doc.figures([(f"{paper}/{f['png']}", f"{f['label']}: {f['caption']}")
                     for f in m["figures"] if f.get("group", 0) == g])
        runs = [r for r in m["runs"] if r.get("group", 0) == g]
        diagrams = []
        for r in runs:
            digest = r.get("structure") or hashlib.sha1((doc.out_dir / paper / r["svg"]).read_bytes()).hexdigest()
            if digest in shown:
                doc.para(f"{r['label']}: simulated through the Systems diagram shown under “{shown[digest]}”.")
            else:
                shown[digest] = group["title"]
                diagrams.append((f"{paper}/{r['svg']}", f"Systems diagram (Drake) of {r['label']}"))
        doc.figures(diagrams)
        replays = [(r["label"], r["replay"]) for r in runs]
        replays += [(r["label"], r["replay"]) for r in m.get("replays", []) if r.get("group", 0) == g]
        _links(doc, paper, [(f"3-D replay of {label} (open in a browser)", f) for label, f in replays])
        for text in (t for t in m["texts"] if t.get("group", 0) == g):
            if "entries" in text:
                _expressions_block(doc, paper, text)
            else:  # a manifest of an earlier armlab: the expressions are in their Markdown file only
                _links(doc, paper, [(text["label"], text["md"])])
    if m["errata"]:
        doc.heading(3, f"Errata of paper {paper}: printed equations checked against Drake", _anchor(paper, "errata"))
        _errata_block(doc, m["errata"])
    if m["parameters"]:
        doc.heading(3, "Parameters armlab chose where the paper is silent", _anchor(paper, "parameters"))
        doc.table(["parameter", "value", "why"], [[c["name"], c["value"], c["why"]] for c in m["parameters"]])


def _toc(doc: _Doc, papers: Sequence[str], manifests: dict[str, dict]) -> None:
    md, out = ["## Contents\n"], ['<nav class="toc"><ul>']
    for p in papers:
        m = manifests[p]
        entries = ([("The arm", _anchor(p, "arm"))] if m.get("schemes") else [])
        entries += [(g["title"], _anchor(p, "g", str(k))) for k, g in enumerate(m.get("groups", []))]
        entries += [("Errata", _anchor(p, "errata"))] if m["errata"] else []
        entries += [("Parameters armlab chose", _anchor(p, "parameters"))] if m["parameters"] else []
        title = f"Paper {p}" + (f": {m['title']}" if m.get("title") else "")
        md.append(f"- [{title}](#{_anchor('paper', p)})\n" + "".join(f"  - [{t}](#{a})\n" for t, a in entries))
        out.append(f'<li><a href="#{_anchor("paper", p)}"><b>{html.escape(title)}</b></a><ul>'
                   + "".join(f'<li><a href="#{a}">{html.escape(t)}</a></li>' for t, a in entries) + "</ul></li>")
    out.append("</ul></nav>")
    doc.raw("".join(md) + "\n", "<h2>Contents</h2>" + "".join(out))


def _summary(doc: _Doc, papers: Sequence[str], manifests: dict[str, dict], rows: Sequence[Row]) -> None:
    headers = ["paper", "matches", "differs", "not reproducible", "errata"]
    md, out = [], []
    for p in papers:
        mine = [r for r in rows if r.paper == p]
        c = verdict_counts(mine)
        title = manifests[p].get("title") or ""
        md.append([f"[{p}](#{_anchor('paper', p)}) {title}",
                   *[f"[{c[k]}](#{_anchor(p, k)})" if c[k] else "0" for k in VERDICT_KINDS],
                   f"[{len(manifests[p]['errata'])}](#{_anchor(p, 'errata')})"])
        cells = "".join((f'<td class="n c-{_CSS_KIND[k]}"><a class="c-{_CSS_KIND[k]}" href="#{_anchor(p, k)}">'
                         f"{c[k]}</a></td>") if c[k] else '<td class="n">0</td>' for k in VERDICT_KINDS)
        out.append(f'<tr><td><a href="#{_anchor("paper", p)}">{p}</a> {html.escape(title)}</td>{cells}'
                   f'<td class="n"><a href="#{_anchor(p, "errata")}">{len(manifests[p]["errata"])}</a></td></tr>')
    doc.raw(markdown_table(headers, md), '<table class="summary"><thead><tr>'
            + "".join(f"<th>{h}</th>" for h in headers) + "</tr></thead><tbody>" + "".join(out) + "</tbody></table>")


def write_report(
    out_dir: Path,
    papers: Sequence[str],
    rows: Sequence[Row],
    elapsed: float | None = None,
    math: Mapping[str, str] | None = None,
    images: Mapping[str, str] | None = None,
) -> Path:
    """Write ``out_dir/report.md`` and the self-contained ``out_dir/report.html`` from the rows and each
    paper folder's manifest: a summary per paper, contents, then per paper its rows beside their figures.

    ``math``: LaTeX rendered ahead (:func:`report_math` lists it; LaTeX → HTML), ``images``: figures embedded
    ahead (:func:`report_images`, :func:`embed_images`); the rest is rendered and embedded here."""
    out_dir = Path(out_dir)
    counts = verdict_counts(rows)
    manifests = {p: json.loads((out_dir / p / MANIFEST).read_text()) for p in papers}
    doc = _Doc(out_dir, math, images)
    doc.heading(1, "armlab reproduce: the papers beside armlab")
    summary = (f"{len(rows)} published numbers and claims checked: {counts[MATCHES]} match, "
               f"{counts[DIFFERS]} differ, {counts[NOT_REPRODUCIBLE]} are not reproducible from what the papers print.")
    if elapsed is not None:
        summary += f" Reproduction took {elapsed:.1f} s."
    doc.para(summary)
    _summary(doc, papers, manifests, rows)
    doc.para("Paper values are the numbers the papers print, shown as printed; armlab's values are computed at run "
             f"time and shown to {VALUE_DIGITS} significant digits, deviations (armlab − paper, or the largest "
             f"absolute difference for a vector or matrix) to {DEVIATION_DIGITS}. A number matches when it lies "
             "within half of the last printed digit unless the row says otherwise; “matches: by construction” "
             "and “matches: holds for the chosen …” say what the match rests on.", css="note")
    _toc(doc, papers, manifests)
    shown: dict[str, str] = {}
    for p in papers:
        _paper_section(doc, p, manifests[p], [r for r in rows if r.paper == p], shown)

    md_path = out_dir / "report.md"
    md_path.write_text("\n".join(doc.md))
    page = ("<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
            "<meta name='viewport' content='width=device-width, initial-scale=1'><title>armlab reproduce</title>"
            f"<style>{_CSS}</style></head><body>" + "\n".join(doc.html) + "</body></html>\n")
    (out_dir / "report.html").write_text(page)
    return md_path
