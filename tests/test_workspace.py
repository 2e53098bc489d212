"""Workspaces: tool positions, areas against closed forms and integration, convergence, singular loci, CLI."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest
from helpers import armlab_main

from armlab.analysis.singular import SINGULAR_TOL, task_sigma
from armlab.analysis.workspace import joint_box, sample_joints, workspace, workspace_plane
from armlab.models import get_arm

ARMLAB = str(Path(__file__).resolve().parents[1] / ".venv" / "bin" / "armlab")
RR_AREA = np.pi * (0.7**2 - 0.1**2)  # annulus L1 ± L2 of paper 000's RR arm


def test_unlimited_revolute_joints_cover_a_full_turn() -> None:
    lower, upper = joint_box(get_arm("urm6"))
    np.testing.assert_array_equal(lower, -np.pi)  # exact: ±π for an unlimited joint
    np.testing.assert_array_equal(upper, np.pi)  # exact: as above
    lower, upper = joint_box(get_arm("rr"))  # limits ±3π/2 (models/rr.py)
    np.testing.assert_allclose(upper, 1.5 * np.pi)


@pytest.mark.slow
def test_rr_area_is_the_annulus() -> None:
    ws = workspace(get_arm("rr"), 2_000_000, jacobians=False)
    assert ws.dim == 2 and ws.volume_unit == "m²"
    # exact: coordinate axes chosen
    np.testing.assert_array_equal(ws.basis, np.eye(3)[:2])  # the plane z = 0, spanned by x and y
    assert abs(ws.volume - RR_AREA) < 0.01 * RR_AREA
    assert abs(ws.reach - 0.7) < 1e-6
    np.testing.assert_allclose(ws.bbox, [[-0.7, -0.7, 0.0], [0.7, 0.7, 0.0]], atol=1e-4)


def limited_2r_area(L1: float, L2: float) -> float:
    """Area reached by a 2R arm with θ1, θ2 ∈ [−π/2, π/2], by integration over the radius.

    At radius r the elbow angle is ±θ2(r) (law of cosines; |θ2| ≤ π/2 means r ≥ √(L1² + L2²)); the
    polar angle is θ1 ± β with β = atan2(L2 sin θ2, L1 + L2 cos θ2), so the reached arc is the union of
    two arcs of length π offset by 2β: π + 2β (2β < π here). Area = ∫ r (π + 2β(r)) dr.
    """
    r = np.linspace(np.hypot(L1, L2), L1 + L2, 200_001)
    theta2 = np.arccos(np.clip((r**2 - L1**2 - L2**2) / (2 * L1 * L2), -1, 1))
    beta = np.arctan2(L2 * np.sin(theta2), L1 + L2 * np.cos(theta2))
    return float(np.trapezoid(r * (np.pi + 2 * beta), r))


@pytest.mark.slow
def test_limited_2r_area_against_integration() -> None:
    arm = get_arm("rr", theta_max=np.pi / 2)
    ws = workspace(arm, 2_000_000, jacobians=False)
    expected = limited_2r_area(0.4, 0.3)
    assert abs(ws.volume - expected) < 0.01 * expected, (ws.volume, expected)
    assert ws.volume < 0.6 * RR_AREA  # the limits matter


@pytest.mark.slow
def test_volume_converges_as_samples_grow() -> None:
    ws = workspace(get_arm("rr"), 2_000_000, jacobians=False)
    # the checkpoints whose cells are filled (the first ones are None: their extrapolation would be negative)
    measured = [(k, x) for k, x in zip(ws.convergence["samples"], ws.convergence["volume_vs_samples"], strict=True)
                if x is not None]
    n, v = np.array(measured).T
    assert n[-1] == 2_000_000 and np.all(np.diff(n) > 0) and v[-1] == ws.volume  # exact: the same number, stored twice
    errors = np.abs(v - RR_AREA) / RR_AREA
    assert np.all(np.diff(errors) < 0)  # every doubling of the samples comes closer
    assert errors[-1] < 0.002 and errors[0] > 0.5
    h, vh = np.array(ws.convergence["resolution"]), np.array(ws.convergence["volume_vs_resolution"])
    assert h[0] == ws.resolution and vh[0] == ws.volume_voxels and ws.volume == 2 * vh[0] - vh[1]
    assert np.all(np.diff(vh) > 0)  # coarser cells overcount the boundary
    assert abs(vh[0] - RR_AREA) > 5 * abs(ws.volume - RR_AREA)  # the extrapolation removes most of it


def test_same_seed_same_volume_and_seed_matters() -> None:
    arm = get_arm("urm6")
    a, b = workspace(arm, 50_000, jacobians=False), workspace(arm, 50_000, jacobians=False)
    c = workspace(arm, 50_000, seed=1, jacobians=False)
    assert a.volume == b.volume and a.volume != c.volume


@pytest.mark.slow
def test_rr_singular_loci_are_det_j_zero() -> None:
    arm = get_arm("rr")
    ws = workspace(arm, 100_000)
    loci = ws.singular["loci"]
    assert ws.singular["depends_on"] == ["joint2"] and loci["independent_of_other_joints"]
    # det J = L1 L2 sin θ2 (paper 000 eqs. 1-2 differentiated) vanishes at θ2 = kπ within ±3π/2
    np.testing.assert_allclose(loci["values"], [-np.pi, 0.0, np.pi], atol=1e-9)
    q = sample_joints(arm, 1000, 7)
    w, s = task_sigma(arm, q)
    np.testing.assert_allclose(w, 0.4 * 0.3 * np.abs(np.sin(q[:, 1])), atol=1e-12)  # Yoshikawa = |det J|
    assert np.all(s <= w / s + 1e-12)


def test_limited_2r_singular_only_stretched() -> None:
    ws = workspace(get_arm("rr", theta_max=np.pi / 2), 50_000)
    np.testing.assert_allclose(ws.singular["loci"]["values"], [0.0], atol=1e-9)


@pytest.mark.slow
def test_listed_singular_configurations_are_singular() -> None:
    arm = get_arm("urm6")
    ws = workspace(arm, 100_000)
    found = ws.singular["configurations"]
    assert found and ws.singular["rows"].startswith("all")
    q = np.array([f["q"] for f in found])
    assert np.all(task_sigma(arm, q)[1] < SINGULAR_TOL)
    assert np.median(ws.sigma_min) > 1e3 * SINGULAR_TOL  # a typical configuration is not singular


@pytest.mark.slow
def test_r2t_has_no_singularity_within_its_limits() -> None:
    ws = workspace(get_arm("r2t"), 50_000)
    assert ws.singular["loci"]["values"] == []
    assert ws.sigma_min.min() > 0.1


def test_workspace_plane_of_a_tilted_plane() -> None:
    rng = np.random.default_rng(0)
    u, v = np.array([1.0, 1.0, 0.0]) / np.sqrt(2), np.array([0.0, 0.0, 1.0])
    pts = np.array([0.1, 0.2, 0.3]) + rng.random((500, 1)) * u + rng.random((500, 1)) * v
    origin, basis = workspace_plane(pts)
    assert basis.shape == (2, 3)
    np.testing.assert_allclose((origin - pts[0]) @ np.cross(u, v), 0, atol=1e-12)  # the origin is in the plane
    np.testing.assert_allclose(np.abs(basis @ np.cross(u, v)), 0, atol=1e-12)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"samples": 10}, "samples 10 is not allowed: give a whole number 1000 … 1e9"),
    ({"samples": 1500.5}, "whole number 1000 … 1e9"),
    ({"samples": 10**11}, "samples 1e11 is not allowed"),
    ({"resolution": -1.0}, "resolution -1 is out of range: allowed 1e-6 ≤ h ≤ 100 m"),
    ({"resolution": 1e308}, "resolution 1e308 is out of range"),
    ({"resolution": 1e-6}, "too fine"),
    ({"seed": -1}, "seed -1 is not allowed: give a whole number 0 … 4294967295"),
    ({"seed": 2**32}, "seed 4294967296 is not allowed"),
])
def test_bad_arguments_are_one_line_errors(kwargs: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        workspace(get_arm("urm6"), **({"samples": 5000} | kwargs), jacobians=False)


@pytest.mark.slow
def test_cli_writes_every_file_and_prints_json(tmp_path: Path) -> None:
    out = tmp_path / "ws"
    run = armlab_main("workspace", "rr", "--samples", "200000", "--out", str(out), "--json")
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    assert {"arm", "samples", "volume", "volume_unit", "reach", "bbox", "resolution"} <= set(summary)
    assert summary["arm"] == "rr" and summary["volume_unit"] == "m²" and summary["samples"] == 200000
    assert json.loads((out / "workspace.json").read_text()) == summary
    assert sorted(p.name for p in out.iterdir()) == sorted(
        ["workspace.json", "slices.png", "convergence.png", "singular.png", "workspace.html"])
    html = (out / "workspace.html").read_text()
    assert "<script" in html and 'src="http' not in html  # self-contained
    legend = re.search(r'<div id="armlab-legend".*?</div></div>', html, re.S).group(0)  # the colour legend
    assert "colour = Yoshikawa manipulability w = √det(J Jᵀ)" in legend and "linear-gradient" in legend
    ticks = [float(v) for v in re.findall(r'translateX\(-50%\)">([^<]+)</span>', legend)]
    assert len(ticks) == 5 and np.all(np.diff(ticks) > 0)
    again = armlab_main("workspace", "rr", "--samples", "100000", "--out", str(out))
    assert again.returncode == 0 and "singular where joint2 = -180, 0, 180 deg" in again.stdout


def test_cli_help_states_the_ranges() -> None:
    run = subprocess.run([ARMLAB, "workspace", "--help"], capture_output=True, text=True, timeout=60)
    text = " ".join(run.stdout.split())
    for fragment in ("joint-space samples, 1000 … 1e9 (default 1e6)", "1e-6 ≤ h ≤ 100 m", "0 … 4294967295"):
        assert fragment in text


def test_cli_bad_input(tmp_path: Path) -> None:
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "notes.txt").write_text("mine")
    for args, message in ((["rr", "--samples", "5"], "--samples 5 is not allowed"),
                          (["rr", "--resolution", "0"], "--resolution 0 is out of range"),
                          (["nope"], "unknown arm"),
                          (["rr", "--out", str(tmp_path / "other")], "is not an armlab workspace folder")):
        run = subprocess.run([ARMLAB, "workspace", *args], capture_output=True, text=True, timeout=120)
        assert run.returncode == 2, (args, run.stderr)
        assert run.stderr.startswith("armlab: error:") and message in run.stderr and "Traceback" not in run.stderr
    assert (tmp_path / "other" / "notes.txt").read_text() == "mine"


def test_a_slider_s_workspace_is_its_stroke(tmp_path: Path) -> None:
    (tmp_path / "slider.csv").write_text("type,a,alpha,d,theta,lower,upper\nT,0,0,0,0,0,0.5\n")
    ws = workspace(get_arm(str(tmp_path / "slider.csv")), 20_000, jacobians=False)
    assert ws.dim == 1 and ws.measure == "length" and abs(ws.volume - 0.5) < 1e-3


def test_a_curved_surface_has_no_volume(tmp_path: Path) -> None:
    """A spatial 2R arm's tool point sweeps a torus patch: 3-D positions, 2 directions of motion, volume 0."""
    (tmp_path / "arm.csv").write_text("# units: deg\ntype,a,alpha,d,theta,lower,upper\nR,0.5,90,0,0,-90,90\n"
                                      "R,0.3,0,0,0,,\n")
    ws = workspace(get_arm(str(tmp_path / "arm.csv")), 50_000, jacobians=False)
    # exact: a surface's volume is set to 0
    assert ws.dim == 3 and ws.motions == 2 and ws.volume == 0.0 and "curved surface" in ws.summary()["note"]
    assert ws.volume_voxels > 0  # the shell of voxels the surface crosses


def test_point_cloud_legend_counts_the_points_drawn_and_ticks_its_colour_scale(tmp_path: Path) -> None:
    """With manipulability, the cloud draws the points it was computed for (fewer than those kept): the legend says
    that number, and its ticks are the colour scale's values at evenly spaced shades (its inverse)."""
    from armlab.analysis.cloud import LEGEND_TICKS, write_point_cloud
    from armlab.analysis.plots import manipulability_norm

    ws = workspace(get_arm("rr"), 100_000)
    assert ws.manipulability is not None and len(ws.manipulability) < len(ws.points)
    html = write_point_cloud(get_arm("rr"), ws, tmp_path / "cloud.html").read_text()
    legend = re.search(r'<div id="armlab-legend".*?</div></div>', html, re.S).group(0)
    assert f"{len(ws.manipulability)} tool points" in legend
    ticks = [float(v) for v in re.findall(r'translateX\(-50%\)">([^<]+)</span>', legend)]
    norm = manipulability_norm(ws.manipulability)
    np.testing.assert_allclose(norm(np.array(ticks)), np.linspace(0.0, 1.0, LEGEND_TICKS), atol=2e-3)  # 3 digits


def test_no_negative_area_in_the_convergence_or_the_result(capsys) -> None:
    """Issue 33: ``armlab workspace rr`` printed a negative area at its first checkpoints (2·V(h) − V(2h) with the
    cells not yet filled): those are "not filled", never negative."""
    from armlab.cli import main

    assert main(["workspace", "rr", "--samples", "15625"]) == 0
    row = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("area vs samples"))
    values = [v.split()[0] for v in row.split(": ")[2:]]
    assert "— (cells not filled)" in row and all(v == "—" or float(v) > 0 for v in values)


def test_the_default_resolution_of_the_most_samples_fits_the_grid() -> None:
    """Issue 36 item 28: ``armlab workspace urm6 --samples 1e9`` (the documented maximum) was refused by its own
    default resolution (more than MAX_CELLS cells): the default edge is no finer than the grid allows."""
    from armlab.analysis.workspace import (
        MAX_CELLS,
        MAX_SAMPLES,
        _Occupancy,
        default_resolution,
        reach_bound,
        tool_positions,
    )

    arm = get_arm("urm6")
    q = sample_joints(arm, 1 << 16, np.random.default_rng(0))
    points = tool_positions(arm, q)
    origin, basis = workspace_plane(points)
    bound = reach_bound(arm) + float(np.linalg.norm(origin))
    h = default_resolution((points - origin) @ basis.T, MAX_SAMPLES, bound)
    grid = _Occupancy(h, bound, basis.shape[0])  # refused before the fix: "resolution … is too fine"
    assert grid.cells ** basis.shape[0] <= MAX_CELLS
