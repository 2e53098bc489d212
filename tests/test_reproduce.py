"""``armlab reproduce``: every paper reproduced (fast settings), the report's rows, files and exit codes."""

from __future__ import annotations

import csv
import json
import re

import numpy as np
import pytest

from armlab.scripts.report import MATCHES, Row, compare, verdict_counts
from armlab.scripts.reproduce import MARKER, PAPERS, output_folder, reproduce


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """One fast reproduction of every paper: (output folder, result, progress lines)."""
    out = tmp_path_factory.mktemp("reproduce") / "out"
    lines: list[str] = []
    result = reproduce(out, fast=True, progress=lines.append)
    return out, result, lines


def rows_of(result, paper: str) -> dict[str, Row]:
    return {row.quantity: row for row in result.rows if row.paper == paper}


# The published numbers of ../shared/PAPERS.md, each of which needs a row (quantity as the scripts name it).
EXPECTED = {
    "000": [f"§4 quintic coefficient {c}" for c in ("a1", "a2", "a3", "b1", "b2", "b3")]
    + [f"Fig. 2/3 {p} {a} [m]" for p in ("M0", "M_fin") for a in "xy"]
    + [f"§4 peak torque τ{j} of Fig. 7 [N·m]" for j in (1, 2)]
    + [f"Table 2 {s} {n} [deg]" for s in ("A-B", "B-C", "C-D", "D-A") for n in ("θ10", "θ20", "θ1tf", "θ2tf")]
    + [f"Table 3 {s} τ{j}max [N·m]" for s in ("A-B", "B-C", "C-D", "D-A") for j in (1, 2)]
    + [f"Fig. 8 claim: M on the circle through A-D, max radial deviation on {s} [m]"
       for s in ("A-B", "B-C", "C-D", "D-A")],
    "001": ["eq. (6): T04 at θ = 0", "§3: start (2, 0, 0)", "§3: target (1, 1, 1.4)"],
    "003": ["eq. (20): ⁰₄[R]", "eqs. (22)-(23): α_x", "eqs. (22)-(23): β_y", "eqs. (22)-(23): γ_z",
            "eqs. (19), (21) (misprint)"],
    "004": [f"Table 2, p{k} {a} [mm]" for k in range(1, 8) for a in "xyz"],
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
    for prefix in EXPECTED["000"][:10]:  # coefficients, M0, M_fin
        assert find(r000, prefix).verdict == MATCHES
    for segment, names in (("A-B", ("θ20", "θ1tf", "θ2tf")), ("B-C", ("θ10", "θ20", "θ2tf")),
                           ("C-D", ("θ10", "θ20", "θ1tf", "θ2tf")), ("D-A", ("θ10", "θ20", "θ1tf", "θ2tf"))):
        for name in names:
            assert find(r000, f"Table 2 {segment} {name}").verdict == MATCHES
    for segment in ("C-D", "D-A"):  # θ1 stays 0: exact arcs
        assert find(r000, f"Fig. 8 claim: M on the circle through A-D, max radial deviation on {segment}").verdict \
            == MATCHES
    for paper in ("001", "004"):
        for prefix in EXPECTED[paper]:
            assert find(rows_of(result, paper), prefix).verdict == MATCHES, prefix
    for prefix in EXPECTED["003"][:4]:
        assert find(rows_of(result, "003"), prefix).verdict == MATCHES, prefix


def test_rows_that_should_not_match_say_why(run):
    _, result, _ = run
    r000 = rows_of(result, "000")
    for prefix in ("Table 2 A-B θ10", "Table 2 B-C θ1tf"):
        row = find(r000, prefix)
        assert row.verdict.startswith("differs: the paper rounds")
        assert abs(abs(row.armlab_value) - 73.7398) < 5e-5
    for prefix in ("A-B", "B-C"):
        row = find(r000, f"Fig. 8 claim: M on the circle through A-D, max radial deviation on {prefix}")
        assert row.verdict.startswith("differs:") and row.armlab_value > 1e-3
    torques = [row for row in r000.values() if "torque" in row.quantity or row.quantity.startswith("Table 3")]
    assert len(torques) == 10
    assert all(row.verdict == "not reproducible: mass properties not published (no masses, inertias or gravity "
                              "direction)" for row in torques)
    assert find(rows_of(result, "003"), "eqs. (19), (21) (misprint)").verdict.startswith("differs: misprint")
    for row in result.rows:
        assert row.verdict == MATCHES or re.match(r"^(differs|not reproducible): \S", row.verdict), row


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
                "fig09_abcd_joints", "fig10_abcd_torques", "fig18_rrrr_components", "fig19_rrrr_planes",
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
        assert sorted(f["png"] for f in manifest["figures"]) == sorted(f"{s}.png" for s in figures[paper])
    for paper in ("000", "003"):
        text = (out / paper / "symbolic.md").read_text()
        assert "$$" in text and "matches the paper's printed form" in text
    assert "differs from the printed form (erratum)" in (out / "003" / "symbolic.md").read_text()
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
    for heading in ("## Published numbers", "## Errata", "## What the papers claim", "## Parameters armlab chose"):
        assert heading in report
    assert report.count("\n| 0") >= len(result.rows)  # one table row per report row (paper column first)
    assert "eqs. (19), (21)" in report and "Fig. 16, T04 entry (2, 3)" in report  # errata of 003 and 000
    html = (out / "report.html").read_text()
    assert html.count("<img ") >= 22 and 'src="000/fig08_abcd_path.png"' in html
    assert 'href="000/replay_abcd.html"' in html and "(001/replay_motion.html)" in report
    assert any("Fig. 8" in line for line in lines) and any("Table 2" in line for line in lines)


def test_compare_and_row_validation():
    assert compare("x", "q", 1.0, 1.0 + 1e-10, 1e-9).verdict == MATCHES
    assert compare("x", "q", 1.0, 1.1, 1e-9, reason="rounded").verdict == "differs: rounded"
    with pytest.raises(ValueError, match="verdict"):
        Row("x", "q", 1.0, 1.0, 0.0, "close enough")


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


def test_one_paper_again_keeps_the_others(run, tmp_path):
    import shutil

    out, result, _ = run
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    lines: list[str] = []
    again = reproduce(copy, ("004",), fast=True, progress=lines.append)
    assert sorted(p.name for p in copy.iterdir() if p.is_dir()) == list(PAPERS)
    assert [row.quantity for row in again.rows] == [row.quantity for row in result.rows]
    assert again.counts == result.counts
    assert sum(line.startswith(("[000] kept", "[001] kept", "[003] kept")) for line in lines) == 3
    report = (copy / "report.md").read_text()
    assert all(f"### Paper {paper} (" in report for paper in PAPERS)
    assert (copy / "000" / "replay_abcd.html").exists()


def test_a_failed_reproduction_leaves_the_previous_one(tmp_path, monkeypatch):
    out = tmp_path / "out"
    reproduce(out, ("004",), fast=True, progress=lambda line: None)
    before = sorted(p.relative_to(out) for p in out.rglob("*"))

    def broken(*args, **kwargs):
        raise ValueError("boom")

    monkeypatch.setattr("armlab.scripts.report.write_report", broken)
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
    assert re.match(r"report: .*report\.md  \(22 rows: 22 matches, 0 differs, 0 not reproducible; [\d.]+ s\)$",
                    printed[-1])
    assert sorted(p.name for p in out.iterdir()) == sorted([MARKER, "004", "report.md", "report.html"])
    assert main(["reproduce", "--paper", "004", "--out", str(out)]) == 0  # an earlier reproduction is replaced
    blocker = tmp_path / "file.txt"
    blocker.write_text("x")
    assert main(["reproduce", "--out", str(blocker / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot write in" in err[0]
    assert main(["reproduce", "--paper", "002", "--out", str(out)]) == 2


def test_paper_script_runs_alone(tmp_path):
    import subprocess
    import sys

    out = tmp_path / "004"
    done = subprocess.run([sys.executable, "-m", "armlab.scripts.paper_004", "--out", str(out), "--fast"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "22 rows: 22 matches" in done.stdout and (out / "fig04_arm_3d.png").exists()


def test_reproduced_replay_shows_the_arm_moving_in_chromium(run, tmp_path):
    """The A-B-C-D-A run's replay (three simulated runs, one file) as a person sees it."""
    from test_replay import assert_shows_arm_moving, screenshots

    out, _, _ = run
    assert_shows_arm_moving(*screenshots(out / "000" / "replay_abcd.html", (1.0, 5.0), tmp_path))
