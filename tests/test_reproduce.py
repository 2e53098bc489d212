"""``armlab reproduce``: every paper reproduced (fast settings), the report's rows, files and exit codes."""

from __future__ import annotations

import csv
import json
import re

import numpy as np
import pytest
from helpers import assert_same_file_contents, assert_same_numbers

from armlab.papers.report_rows import MATCHES, Row, compare, matches, verdict_counts
from armlab.papers.reproduce import MARKER, PAPERS, output_folder, reproduce


@pytest.fixture
def run(reproduction):
    """The session's one fast reproduction of every paper (conftest.py): (output folder, result, progress lines)."""
    return reproduction


def rows_of(result, paper: str) -> dict[str, Row]:
    return {row.quantity: row for row in result.rows if row.paper == paper}


# The published numbers of ../shared/PAPERS.md, each of which needs a row (quantity as the scripts name it).
EXPECTED = {
    "000": [f"§4 quintic coefficient {c}" for c in ("a1", "a2", "a3", "b1", "b2", "b3")]
    + [f"§4 peak torque τ{j} of Fig. 7 [N·m]" for j in (1, 2)]
    + [f"Table 2 {s} {n} [deg]" for s in ("A-B", "B-C", "C-D", "D-A") for n in ("θ10", "θ20", "θ1tf", "θ2tf")]
    + [f"Table 3 {s} τ{j}max [N·m]" for s in ("A-B", "B-C", "C-D", "D-A") for j in (1, 2)]
    + [f"Fig. 8 claim: M on the circle through A-D, max radial deviation on {s} [m]"
       for s in ("A-B", "B-C", "C-D", "D-A")],
    "001": ["eq. (6): T04 at θ = 0", "§3: start (2, 0, 0)", "§3: target (1, 1, 1.4)", "Fig. 4 claim"],
    "003": ["eq. (20): ⁰₄[R]", "eqs. (22)-(23): α_x", "eqs. (22)-(23): β_y", "eqs. (22)-(23): γ_z",
            "eqs. (19), (21) (misprint)", "eqs. (62), (64) (misprint)", "eq. (22) (misprint)"],
    "004": [f"Table 2, p{k} {a} [mm]" for k in range(1, 8) for a in "xyz"] + ["eq. (7) (misprint)",
                                                                              "eq. (22) (misprint)"],
}


def find(rows: dict[str, Row], prefix: str) -> Row:
    matches = [row for quantity, row in rows.items() if quantity.startswith(prefix)]
    assert len(matches) == 1, f"{prefix!r}: {len(matches)} rows"
    return matches[0]


def test_every_published_number_has_a_row(run):
    _, result, _ = run
    for paper, prefixes in EXPECTED.items():
        rows = rows_of(result, paper)
        for prefix in prefixes:
            find(rows, prefix)


def test_rows_that_should_match_do(run):
    _, result, _ = run
    r000 = rows_of(result, "000")
    for prefix in EXPECTED["000"][:6]:  # the quintic's coefficients
        assert find(r000, prefix).verdict == MATCHES
    for segment in ("A-B", "B-C", "C-D", "D-A"):  # Table 2 prints whole degrees: within half a degree
        for name in ("θ10", "θ20", "θ1tf", "θ2tf"):
            row = find(r000, f"Table 2 {segment} {name}")
            assert row.verdict == MATCHES
            if round(row.armlab_value) == row.paper_value and abs(row.paper_value) != 74:  # 0°, ±90°, ±180°: exact
                assert abs(row.deviation) <= 1e-9, row  # also at B = (0.7, 0) and D, on the workspace's rims
    assert not any(quantity.startswith("Fig. 2/3") for quantity in r000)  # no number the paper does not print
    for segment in ("C-D", "D-A"):  # θ1 stays 0: exact arcs
        assert find(r000, f"Fig. 8 claim: M on the circle through A-D, max radial deviation on {segment}").verdict \
            == MATCHES
    for prefix in EXPECTED["004"][:21]:
        assert find(rows_of(result, "004"), prefix).verdict == MATCHES, prefix
    r001 = rows_of(result, "001")
    assert find(r001, "eq. (6)").verdict.startswith("matches: holds for the chosen lengths")
    assert find(r001, "§3: start").verdict.startswith("matches: by construction")
    assert find(r001, "§3: target").kind == MATCHES
    for prefix in EXPECTED["003"][:4]:
        assert find(rows_of(result, "003"), prefix).verdict == MATCHES, prefix


def test_rows_that_should_not_match_say_why(run):
    _, result, _ = run
    r000 = rows_of(result, "000")
    for prefix in ("Table 2 A-B θ10", "Table 2 B-C θ1tf"):  # ∓74° printed, ∓73.74° exact: within half a degree
        row = find(r000, prefix)
        assert row.verdict == MATCHES and 0.25 < abs(row.deviation) < 0.5
        assert abs(abs(row.armlab_value) - 73.7398) < 5e-5
    fig4 = find(rows_of(result, "001"), "Fig. 4 claim")
    assert fig4.verdict.startswith("not reproducible: the paper prints neither the link lengths")
    assert "a2 = 0.1335 m" in fig4.verdict and "a2 = 1.9637 m" in fig4.verdict
    for prefix in ("A-B", "B-C"):
        row = find(r000, f"Fig. 8 claim: M on the circle through A-D, max radial deviation on {prefix}")
        assert row.verdict.startswith("differs:") and row.armlab_value > 1e-3
    torques = [row for row in r000.values() if "torque" in row.quantity or row.quantity.startswith("Table 3")]
    assert len(torques) == 10
    assert all(row.verdict == "not reproducible: mass properties not published (no masses, inertias or gravity "
                              "direction)" for row in torques)
    for paper, prefix in (("003", "eqs. (19), (21) (misprint)"), ("003", "eqs. (62), (64) (misprint)"),
                          ("003", "eq. (22) (misprint)"), ("004", "eq. (7) (misprint)"),
                          ("004", "eq. (22) (misprint)")):
        assert find(rows_of(result, paper), prefix).verdict.startswith("differs: misprint"), prefix
    for row in result.rows:
        assert row.verdict == MATCHES or re.match(r"^(matches|differs|not reproducible): \S", row.verdict), row


def test_armlab_values_are_computed_not_copied(run):
    """Spot checks by independent routes: 004's p7 by eq. (22), 000's a1 from the closed form 6Δθ/t_f⁵."""
    from armlab.kinematics.urm import position_vectors_homogeneous
    from armlab.models import get_arm

    _, result, _ = run
    p = get_arm("urm6").parameters
    r = np.array([p[f"r{k}"] for k in range(1, 8)])
    theta = np.array([p[f"theta{k}"] for k in range(2, 8)])
    p7 = position_vectors_homogeneous(np.radians([15, 30, 50, 130, 230, 340]), theta, r)[6] * 1e3
    r004 = rows_of(result, "004")
    for axis, value in zip("xyz", p7, strict=True):
        assert find(r004, f"Table 2, p7 {axis}").armlab_value == pytest.approx(value, abs=1e-9)
    assert find(rows_of(result, "000"), "§4 quintic coefficient a1").armlab_value == pytest.approx(
        6 * np.radians(100) / 2**5, abs=1e-12)


def test_files(run):
    out, _, _ = run
    assert (out / MARKER).exists() and (out / "report.md").exists() and (out / "report.html").exists()
    figures = {
        "000": ["fig03_trajectory", "fig04_workspace", "fig05_joint_courses", "fig07_torques", "fig08_abcd_path",
                "fig08_arc_joints", "fig08_fastest_circle", "fig09_abcd_joints", "fig10_abcd_torques",
                "fig18_rrrr_components", "fig19_rrrr_planes",
                "fig24_rrrr_components", "fig25_rrrr_planes", "fig28_tool_position", "fig29_tool_velocity"],
        "001": ["fig03_arm_3d", "fig04_joint_displacement", "fig05_joint_velocity", "fig06_joint_acceleration",
                "fig07_end_point", "torques"],
        "003": ["fig_end_effector", "fig_end_effector_own_frame", "fig_links"],
        "004": ["fig04_arm_3d"],
    }
    tables = {"000": ["quintic_coefficients", "table2_ik_angles", "table3_peak_torques"], "001": ["ik_solutions"],
              "003": [], "004": ["table2_position_vectors"]}
    for paper in PAPERS:
        folder = out / paper
        for stem in figures[paper]:
            png, svg = folder / f"{stem}.png", folder / f"{stem}.svg"
            assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and "<svg" in svg.read_text()[:2000], stem
        for stem in tables[paper]:
            with open(folder / f"{stem}.csv") as handle:
                assert len(list(csv.reader(handle))) >= 2
            assert (folder / f"{stem}.md").read_text().count("|") > 10
        manifest = json.loads((folder / "manifest.json").read_text())
        ours = [f["png"] for f in manifest["figures"] if not f["png"].startswith("beyond_")]  # papers/beyond.py's
        assert sorted(ours) == sorted(f"{s}.png" for s in figures[paper])
    for paper in ("000", "003"):
        text = (out / paper / "symbolic.md").read_text()
        assert "$$" in text and "matches the paper's printed form" in text
    assert "differs from the printed form (erratum)" in (out / "003" / "symbolic.md").read_text()
    schemes = {"000": ["scheme_rr.png", "scheme_rrrr.png"], "001": ["scheme_arm4r.png"], "003": ["scheme_r2t.png"],
               "004": ["scheme_urm6.png"]}
    replays = {"000": ["replay_rrrr.html"], "001": [], "003": ["replay_demo.html"], "004": ["replay_demo.html"]}
    for paper in PAPERS:  # every paper arm: its kinematic scheme and a 3-D replay
        manifest = json.loads((out / paper / "manifest.json").read_text())
        assert [s["png"] for s in manifest["schemes"]] == schemes[paper]
        assert [r["replay"] for r in manifest["replays"]] == replays[paper]
        for name in schemes[paper]:
            assert (out / paper / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        for name in replays[paper]:
            assert (out / paper / name).read_text().lstrip().startswith("<!DOCTYPE html>")
    runs = {"000": ["fig07", "fig28", "abcd"], "001": ["motion"], "003": [], "004": []}
    for paper, stems in runs.items():  # every simulated run: its Systems diagram and its 3-D replay
        manifest = json.loads((out / paper / "manifest.json").read_text())
        assert [(r["svg"], r["replay"]) for r in manifest["runs"]] == [
            (f"diagram_{stem}.svg", f"replay_{stem}.html") for stem in stems]
        for stem in stems:
            assert "<svg" in (out / paper / f"diagram_{stem}.svg").read_text()
            assert "TrajectorySource" in (out / paper / f"diagram_{stem}.svg").read_text()
            assert (out / paper / f"replay_{stem}.html").read_text().lstrip().startswith("<!DOCTYPE html>")


def test_report(run):
    out, result, lines = run
    report = (out / "report.md").read_text()
    counts = result.counts
    assert counts == verdict_counts(result.rows) and sum(counts.values()) == len(result.rows)
    assert f"{counts['matches']} match, {counts['differs']} differ, {counts['not reproducible']} are not" in report
    assert "## Contents" in report
    for paper in PAPERS:
        assert f"## Paper {paper}: " in report and f"### Errata of paper {paper}" in report
    assert sum(report.count(row.quantity) >= 1 for row in result.rows) == len(result.rows)
    assert "eqs. (19), (21)" in report and "Fig. 16, T04 entry (2, 3)" in report  # errata of 003 and 000
    html = (out / "report.html").read_text()
    assert 'href="000/replay_abcd.html"' in html and "(001/replay_motion.html)" in report
    for paper, replay in (("000", "rrrr"), ("003", "demo"), ("004", "demo")):
        assert f'href="{paper}/replay_{replay}.html"' in html
    assert any("Fig. 8" in line for line in lines) and any("Table 2" in line for line in lines)


def test_report_html_is_self_contained_with_a_linked_summary(run):
    """One file: every image embedded (no src outside it, nothing from the network); the summary's counts link to
    their rows; each figure sits in the group of the rows it supports; the same Systems diagram is shown once."""
    out, result, _ = run
    html = (out / "report.html").read_text()
    sources = re.findall(r'\ssrc="([^"]*)"', html)
    assert len(sources) >= 40 and all(s.startswith("data:image/") for s in sources)
    assert "http://" not in html and "https://" not in html
    ids = set(re.findall(r'\sid="([^"]+)"', html))
    links = re.findall(r'href="#([^"]+)"', html)
    assert links and all(link in ids for link in links)
    summary = html[html.index('<table class="summary">'):html.index("</table>", html.index('<table class="summary">'))]
    for paper in PAPERS:
        c = verdict_counts([r for r in result.rows if r.paper == paper])
        for kind in ("matches", "differs", "not reproducible"):
            if c[kind]:
                assert f'href="#{paper}-{kind.replace(" ", "")}">{c[kind]}</a>' in summary
    body = html[html.index("</nav>"):]  # after the contents
    table2 = body.index("Table 2: joint angles at A, B, C and D</h3>")
    fig8 = body.index("Fig. 8: is the path A→B→C→D→A a circle?</h3>")
    assert table2 < fig8 < body.index('alt="Fig. 8: ') < body.index("Table 3, Figs. 9 and 10")  # beside its rows
    assert body.index("Fig. 8 claim: M on the circle", fig8) < body.index('alt="Fig. 8: ')
    assert html.count('alt="Systems diagram (Drake) of') == 2  # rr's Fig. 6 diagram once (3 runs), arm4r's once
    assert html.count('class="math"') >= 60 and "begin{matrix}" not in html


@pytest.mark.slow  # renders every expression of the report (pictures, no number)
def test_every_expression_renders_with_mathtext():
    """Every erratum's printed and corrected form and every symbolic expression becomes SVG images (no raw LaTeX)."""
    from armlab.kinematics.symbolic import latex_table
    from armlab.papers.errata import ERRATA
    from armlab.papers.math_html import latex_html, to_mathtext

    texts = [form for e in ERRATA for form in (e.printed_form, e.corrected_form)]
    items = latex_table(include_accelerations=False)
    texts += [item.latex for item in items] + [item.label for item in items]
    for text in texts:
        rendered = latex_html(text)
        assert rendered.count("<img") >= 1 and "begin{matrix}" not in rendered, text
    assert to_mathtext(r"\texttt{a b}") == r"\mathtt{a\ b}"
    with pytest.raises(ValueError, match="mathtext cannot render"):
        latex_html(r"\frac{1}")


def test_math_images_are_what_matplotlib_draws(tmp_path):
    """Each report equation image (one mathtext parse, glyph outlines written as paths) looks as matplotlib's own
    ``math_to_image`` draws the same mathtext: in headless Chromium, the same ink box (±1 px) and the same ink."""
    import base64
    import io

    from browser import screenshot
    from matplotlib import rc_context
    from matplotlib.font_manager import FontProperties
    from matplotlib.mathtext import math_to_image
    from PIL import Image
    from replay_pictures import chromium

    from armlab.papers.math_html import FONT_SIZE, math_svg

    texts = [r"\sqrt{x^{2} + y^{2}} = \frac{a_{1}}{b^{2}}", r"{}^4\overline{\omega}_4 = (0, 0, -\dot{q}_1)^T",
             r"L_{2} \cos{(q_{1})} \cos{(q_{2})} - L_{3} \sin{(q_{2})} \sin{(q_{3})} \cos{(q_{1})}"]
    cells = []
    for text in texts:
        buffer = io.BytesIO()
        with rc_context({"svg.fonttype": "path"}):  # glyphs as paths whatever an earlier test set (figures: "none")
            math_to_image(f"${text}$", buffer, prop=FontProperties(size=FONT_SIZE, math_fontfamily="dejavuserif"),
                          format="svg")
        theirs = base64.b64encode(buffer.getvalue().replace(b"fill: #ffffff", b"fill: none")).decode()
        cells.append((math_svg(text), f'<img class="m" src="data:image/svg+xml;base64,{theirs}">'))
    rows = "".join(f"<tr><td>{mine}</td><td>{theirs}</td></tr>" for mine, theirs in cells)
    page = tmp_path / "math.html"  # four times enlarged (the images are vector graphics): geometry, not pixels
    page.write_text("<!DOCTYPE html><html><body style='margin:0;background:#fff'><table style='border-spacing:0;"
                    f"zoom:4'>{rows}</table></body></html>".replace("<td>", "<td style='width:400px;height:50px;"
                                                                        "padding:0'>"))
    png = tmp_path / "math.png"
    screenshot(chromium(), [page], [png], (3200, 600), budget_ms=2000)
    ink = np.asarray(Image.open(png).convert("L"), dtype=float) < 128

    def near(mask):  # the pixels within one pixel of ``mask``'s ink
        out = np.zeros_like(mask)
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                out |= np.roll(mask, (dy, dx), axis=(0, 1))
        return out

    for k, text in enumerate(texts):
        mine, theirs = (ink[200 * k:200 * (k + 1), 1600 * column:1600 * (column + 1)] for column in range(2))
        assert mine.sum() > 1000, text  # drawn
        # the two images' boxes differ by rounding (< 1 pt): theirs moved by up to half a pixel at 11 pt (2 px here),
        # every ink pixel of each is within a quarter pixel at 11 pt (1 px here) of the other's: the same glyphs, in
        # the same places
        agree = max(min((mine & near(moved)).sum() / mine.sum(), (moved & near(mine)).sum() / moved.sum())
                    for dy in range(-2, 3) for dx in range(-2, 3)
                    for moved in [np.roll(theirs, (dy, dx), axis=(0, 1))])
        assert agree >= 0.99, (text, agree)


def test_report_renders_in_chromium(run, tmp_path):
    """The report's top in headless Chromium: the summary table and an equation are drawn (not blank)."""
    from browser import screenshot
    from PIL import Image
    from replay_pictures import chromium

    from armlab.papers.math_html import latex_html

    out, _, _ = run
    page = tmp_path / "equation.html"
    page.write_text("<!DOCTYPE html><html><body style='margin:0;background:#fff'>"
                    + latex_html(r"{}^4\overline{\omega}_4 = (0, 0, -\dot{q}_1)^T") + "</body></html>")
    pages = [out / "report.html", page]
    pngs = [tmp_path / f"{html_file.stem}.png" for html_file in pages]
    screenshot(chromium(), pages, pngs, (1280, 900), budget_ms=2000)
    top, equation = (np.asarray(Image.open(png).convert("L"), dtype=float) / 255 for png in pngs)
    assert (top[:300] < 0.5).mean() > 0.01  # title, summary text and table drawn
    ink = equation[:60, :400] < 0.5
    assert 0.01 < ink.mean() < 0.5 and np.ptp(np.nonzero(ink)[1]) > 80  # the equation drawn, ~100 px wide


def _numbers(path) -> list[list[str]]:
    """The cells of a CSV file below its header; every cell that is not text must read as a float."""
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    assert len(rows) >= 2, path
    return rows[1:]


def test_every_csv_loads_as_plain_numbers(run, tmp_path):
    """Every CSV of a reproduction and of a simulate run: numeric columns load with numpy.loadtxt, and no cell is
    the repr of a numpy scalar ("np.float64(…)")."""
    from armlab.cli import main

    out, _, _ = run
    sim = tmp_path / "sim"
    assert main(["simulate", "rr", "--tf", "0.2", "--dt", "0.01", "--out", str(sim)]) == 0
    files = sorted(out.rglob("*.csv")) + sorted(sim.rglob("*.csv"))
    assert len(files) >= 10 and sim / "log.csv" in files
    for path in files:
        text = path.read_text()
        assert "np." not in text and "float64" not in text, path
        rows = _numbers(path)
        numeric = 0
        for row in rows:
            for cell in row:
                try:
                    float(cell)
                    numeric += 1
                except ValueError:  # text (a label, a verdict, a vector), never a number in some other notation
                    parts = [x for x in re.split(r"[,\s\[\]()]+", cell) if x]
                    assert cell == "" or re.search(r"[A-Za-z\u0370-\u03ff]", cell) or (
                        len(parts) > 1 and all(float(x) == float(x) for x in parts)
                    ), (path, cell)
        if numeric == sum(len(row) for row in rows):  # an all-number table: numpy reads it whole
            assert np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2).shape == (len(rows), len(rows[0]))
    log = np.loadtxt(sim / "log.csv", delimiter=",", skiprows=1)
    assert log.ndim == 2 and log.shape[0] >= 10 and np.isfinite(log).all()
    table = np.loadtxt(out / "004" / "table2_position_vectors.csv", delimiter=",", skiprows=1, usecols=range(1, 11))
    assert table.shape == (7, 10) and abs(table[1, 0] - 62.5) < 1e-9


def test_csv_cells():
    from armlab.files import csv_cell, csv_text

    assert csv_cell(np.float64(62.49999999999999)) == "62.49999999999999" and csv_cell(np.int64(3)) == "3"
    assert csv_cell(-0.0) == "0.0" and csv_cell(None) == "" and csv_cell(True) == "yes" and csv_cell("a,b") == "a,b"
    assert csv_text(["x", "y"], [[np.float32(0.5), "a,b"]]) == 'x,y\n0.5,"a,b"\n'
    with pytest.raises(ValueError, match="CSV cell"):
        csv_cell(np.zeros(2))


def test_001_fig4_splits_put_the_tool_on_the_target():
    """The lengths with which Fig. 4's claim holds (a2 + a3 = 2): found by root-finding, checked by armlab's forward
    kinematics and Drake's plant of the arm with those lengths."""
    from armlab.models import get_arm
    from armlab.papers.errata import drake_sample
    from armlab.papers.paper_001 import PAPER_TARGET, fig4_splits

    splits = fig4_splits(PAPER_TARGET, 2.0)
    assert len(splits) >= 2
    a2 = splits[:, 0]
    assert np.any(np.abs(a2 - 0.1335) < 5e-5) and np.any(np.abs(a2 - 1.9637) < 5e-5)
    theta1 = np.arctan2(PAPER_TARGET[1], PAPER_TARGET[0])
    for length, theta in splits:
        arm = get_arm("arm4r", a2=float(length), a3=float(2.0 - length), d2=0.0)
        q = np.array([theta1, theta, theta, theta1])
        np.testing.assert_allclose(arm.forward(q).tool[:3, 3], PAPER_TARGET, atol=1e-9)
        np.testing.assert_allclose(drake_sample(arm, q[None]).pose[0, -1, :3, 3], PAPER_TARGET, atol=1e-9)
    arm = get_arm("arm4r")  # a2 = a3 = 1 is not among them
    assert np.all(np.abs(a2 - arm.parameters["a2"]) > 0.5)


def test_report_of_a_manifest_from_an_earlier_armlab(tmp_path):
    """A paper kept from an earlier reproduction (no groups, expressions only as Markdown, errata without a
    description) still reports its rows and links its files."""
    from dataclasses import asdict

    from armlab.papers.report import write_report

    row = compare("004", "Table 2, p1 z [mm]", 300.0, 300.0, 2e-4)
    (tmp_path / "004").mkdir()
    (tmp_path / "004" / "manifest.json").write_text(json.dumps({
        "figures": [], "tables": [], "texts": [{"label": "old expressions", "md": "symbolic.md"}], "claims": [],
        "parameters": [], "runs": [], "rows": [asdict(row)],
        "errata": [{"where": "004 eq. (7)", "printed": "p_{i+1}", "corrected": "p_1", "evidence": "old"}]}))
    write_report(tmp_path, ["004"], [row])
    html = (tmp_path / "report.html").read_text()
    assert "Table 2, p1 z [mm]" in html and 'href="004/symbolic.md"' in html and "004 eq. (7)" in html


def test_compare_and_row_validation():
    assert compare("x", "q", 1.0, 1.0 + 1e-10, 1e-9).verdict == MATCHES
    assert compare("x", "q", 1.0, 1.1, 1e-9, reason="rounded").verdict == "differs: rounded"
    with pytest.raises(ValueError, match="verdict"):
        Row("x", "q", 1.0, 1.0, 0.0, "close enough")
    row = Row("x", "q", 1.0, 1.0, 0.0, matches("by construction"))
    assert row.kind == MATCHES and row.verdict == "matches: by construction" and matches() == MATCHES


def test_out_dir_checks(tmp_path):
    blocker = tmp_path / "file.txt"
    blocker.write_text("x")
    with pytest.raises(ValueError, match="cannot write in"):
        output_folder(blocker / "out")
    with pytest.raises(ValueError, match="exists and is not a folder"):
        output_folder(blocker)
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match="exists and is not an earlier armlab reproduction"):
        reproduce(foreign, ("004",))
    assert (foreign / "notes.txt").read_text() == "mine" and sorted(p.name for p in tmp_path.iterdir()) == [
        "file.txt", "foreign"]  # nothing written before the check


def test_one_paper_again_keeps_the_others_and_one_process_writes_what_the_workers_do(run, tmp_path):
    """Paper 004 again, in this process (``jobs=1``), into a copy of the session's reproduction (two worker
    processes, the report's mathematics rendered by them): the other papers are kept, and 004's files are those the
    workers wrote — the same rows, tables and manifest, the same rendered errata in the report."""
    import shutil

    out, result, _ = run
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    lines: list[str] = []
    again = reproduce(copy, ("004",), fast=True, progress=lines.append, jobs=1)
    assert sorted(p.name for p in copy.iterdir() if p.is_dir()) == list(PAPERS)
    assert [row.quantity for row in again.rows] == [row.quantity for row in result.rows]
    assert again.counts == result.counts
    assert sum(line.startswith(("[000] kept", "[001] kept", "[003] kept")) for line in lines) == 3
    report = (copy / "report.md").read_text()
    assert all(f"## Paper {paper}: " in report for paper in PAPERS)
    assert (copy / "000" / "replay_abcd.html").exists()

    assert_same_numbers([row for row in again.rows if row.paper == "004"],
                        [row for row in result.rows if row.paper == "004"])
    mine, theirs = copy / "004", out / "004"
    assert sorted(p.name for p in mine.iterdir()) == sorted(p.name for p in theirs.iterdir())
    for name in ("manifest.json", "rows.csv", "table2_position_vectors.csv", "beyond_bend_angles.md"):
        assert_same_file_contents(mine / name, theirs / name)  # the workers' numbers, up to another process's rounding

    def errata(folder):
        html = (folder / "report.html").read_text()
        section = html[html.index('id="paper-004"'):]
        return re.findall(r'<div class="erratum">.*?</div></div></div>', section)

    assert len(errata(out)) == 2
    assert_same_numbers(errata(copy), errata(out))  # rendered by the workers: any coordinates up to rounding


def test_a_failed_reproduction_leaves_the_previous_one(run, tmp_path, monkeypatch):
    import shutil

    out = tmp_path / "out"
    shutil.copytree(run[0], out)  # the previous reproduction (a copy of the session's)
    before = sorted(p.relative_to(out) for p in out.rglob("*"))

    def broken(*args, **kwargs):
        raise ValueError("boom")

    monkeypatch.setattr("armlab.papers.report.write_report", broken)
    with pytest.raises(ValueError, match="boom"):
        reproduce(out, ("004",), fast=True, progress=lambda line: None)
    assert sorted(p.relative_to(out) for p in out.rglob("*")) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]  # no temporary folder left


def test_cli_single_paper_and_unwritable_out(tmp_path, capsys):
    from armlab.cli import main

    out = tmp_path / "out"
    assert main(["reproduce", "--paper", "004", "--out", str(out), "--fast"]) == 0
    printed = capsys.readouterr().out.strip().splitlines()
    assert any(line.startswith("[004] Table 2") for line in printed)
    assert re.match(r"report: .*report\.md  \(24 rows: 22 matches, 2 differs, 0 not reproducible; [\d.]+ s\)$",
                    printed[-1])
    assert sorted(p.name for p in out.iterdir()) == sorted([MARKER, "004", "report.md", "report.html"])
    assert main(["reproduce", "--paper", "004", "--out", str(out)]) == 0  # an earlier reproduction is replaced
    blocker = tmp_path / "file.txt"
    blocker.write_text("x")
    assert main(["reproduce", "--out", str(blocker / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot write in" in err[0]
    assert main(["reproduce", "--paper", "002", "--out", str(out)]) == 2
    capsys.readouterr()
    for jobs, why in (("0", "'0' is not a whole number ≥ 1"),
                      ("two", "'two' is not a number (a plain decimal, e.g. 0.5, -2, 1e-3)")):
        assert main(["reproduce", "--jobs", jobs, "--out", str(out)]) == 2
        assert capsys.readouterr().err.strip().splitlines() == [f"armlab: error: argument --jobs: {why}"]


def test_paper_script_runs_alone(tmp_path):
    import subprocess
    import sys

    out = tmp_path / "004"
    done = subprocess.run([sys.executable, "-m", "armlab.papers.paper_004", "--out", str(out), "--fast"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "24 rows: 22 matches, 2 differs" in done.stdout and (out / "fig04_arm_3d.png").exists()


def test_reproduced_replay_shows_the_arm_moving_in_chromium(run, tmp_path):
    """The A-B-C-D-A run's replay (three simulated runs, one file) as a person sees it."""
    from replay_pictures import assert_shows_arm_moving, screenshots

    out, _, _ = run
    assert_shows_arm_moving(*screenshots(out / "000" / "replay_abcd.html", (1.0, 5.0), tmp_path))


def _task_that_warns(k: int, progress) -> int:
    import warnings

    progress(f"task {k} working")
    warnings.warn(f"task {k}: careful", UserWarning, stacklevel=1)
    return k * k


def _task_that_fails(k: int, progress) -> int:
    raise ValueError(f"task {k}: bad input")


@pytest.mark.parametrize("jobs", [1, 2])
def test_workers_pass_on_progress_values_warnings_and_errors(jobs):
    """The reproduction's pool: every task's value, each progress line (through the workers' pipes), each warning
    raised again in the caller; a task's error raised in the caller (from a worker: its traceback there as the
    cause), the workers then stopped."""
    import multiprocessing

    from armlab.papers.reproduce import _Pool

    lines: list[str] = []
    with pytest.warns(UserWarning) as caught, _Pool(jobs, lines.append) as pool:
        for k in range(4):
            pool.submit(k, _task_that_warns, k)
        values = dict(pool.done())
    assert values == {k: k * k for k in range(4)}
    assert sorted(lines) == [f"task {k} working" for k in range(4)]
    assert sorted(str(w.message) for w in caught) == [f"task {k}: careful" for k in range(4)]
    with pytest.raises(ValueError, match="task 3: bad input") as failed, _Pool(jobs, lines.append) as pool:
        pool.submit(3, _task_that_fails, 3)
        list(pool.done())
    remote = 'in _task_that_fails\n    raise ValueError(f"task {k}: bad input")'
    assert jobs == 1 or remote in str(failed.value.__cause__)
    assert multiprocessing.active_children() == []


def test_without_worker_processes_the_tasks_run_here(monkeypatch):
    """Where worker processes cannot be made (no pipes or processes left, say), the tasks run in this process; a
    worker started before is stopped."""
    import multiprocessing

    from armlab.papers.reproduce import _Pool

    spawn = multiprocessing.get_context("spawn")

    class SecondPipeFails:
        pipes = 0

        def Pipe(self):
            self.pipes += 1
            if self.pipes == 2:
                raise OSError("[Errno 24] Too many open files")
            return spawn.Pipe()

        def Process(self, **kwargs):
            return spawn.Process(**kwargs)

    monkeypatch.setattr(multiprocessing, "get_context", lambda method: SecondPipeFails())
    lines: list[str] = []
    with pytest.warns(UserWarning), _Pool(2, lines.append) as pool:
        assert multiprocessing.active_children() == []
        pool.submit(0, _task_that_warns, 5)
        assert dict(pool.done()) == {0: 25}
    assert lines == ["worker processes are not available here ([Errno 24] Too many open files); working in "
                     "this process", "task 5 working"]


def test_an_expressions_label_keeps_its_words_out_of_math_mode(tmp_path):
    """Issue 33: the site showed "x0M,DHform": a label "x_{0M}, DH form" went into math mode whole (MyST's $…$),
    where its spaces are lost. The symbol is math, the words plain text, in the report's Markdown, its HTML and the
    paper's expressions file."""
    from armlab.kinematics.symbolic import LatexItem
    from armlab.papers.paper_output import PaperOutput
    from armlab.papers.report import _Doc, _expressions_block

    out = PaperOutput("000", tmp_path)
    out.expressions("expr", "Fig. 15", "Fig. 15", "the tool point", [(LatexItem(r"x_{0M}, DH form", "000 §7", "L_2"),
                                                                      "as printed")])
    text = out.manifest["texts"][0]
    doc = _Doc(tmp_path, math={"x_{0M}": "<svg>x</svg>", "L_2": "<svg>L</svg>"})
    _expressions_block(doc, "000", text)
    md, page = "".join(doc.md), "".join(doc.html)
    assert "**$x_{0M}$** (DH form)" in md and "DH form$" not in md
    assert '<span class="lhs"><svg>x</svg> (DH form)</span>' in page
    assert "## $x_{0M}$ (DH form) — 000 §7" in (tmp_path / "expr.md").read_text()


def test_the_report_and_the_site_share_one_math_style():
    """Issue 33: the report's style for its mathematics (the SVGs at their size, matrices as grids) is the one the
    documentation site's renderer puts on every page (docs/math_svg.py), not a copy."""
    from armlab.papers import report
    from armlab.papers.math_html import MATH_CSS

    assert report._CSS.endswith(MATH_CSS) and "max-width:none" in MATH_CSS
