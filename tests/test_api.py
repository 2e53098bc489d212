"""The Python API (``import armlab``): each function against Drake's own queries, shapes, errors, and runs."""

from __future__ import annotations

import html
import json
import re

import numpy as np
import pytest
from helpers import arm_and_plant, assert_rounding_close, data, random_q
from matplotlib.figure import Figure

import armlab
from armlab.cli import main
from armlab.presentation.plots import PLOTS

TWO_LINK_URDF = data("two_link.urdf")


def test_load_names_files_and_errors(tmp_path):
    assert armlab.load("urm6").n == 6
    assert armlab.load("urm6", theta3=0.5).parameters["theta3"] == 0.5  # exact: the parameter as given
    path = tmp_path / "two_link.urdf"
    path.write_text(TWO_LINK_URDF)
    assert armlab.load(path).joint_names == ["shoulder", "elbow"]
    with pytest.raises(ValueError, match="unknown arm 'nope'"):
        armlab.load("nope")


def test_fk_single_and_batch_equal_drake(arm_name, rng):
    arm, plant, context = arm_and_plant(arm_name)
    q = random_q(arm, rng, 20)
    T = arm.fk(q)
    assert T.shape == (20, 4, 4)
    # a single configuration and a batch go through differently vectorised numpy loops: the ~n 4×4 products
    # round apart by a few ulps of the largest entry each; 32 ulps (≈ 1e-14 m at 1.5 m)
    assert_rounding_close(arm.fk(q[3]), T[3], ulps=32)
    tool = plant.GetFrameByName(arm.tool_name)
    for k in range(0, 20, 5):
        plant.SetPositions(context, q[k])
        X = plant.CalcRelativeTransform(context, plant.world_frame(), tool).GetAsMatrix4()
        np.testing.assert_allclose(T[k], X, atol=1e-9)


def test_jacobian_and_tool_motion_equal_drake(arm_name, rng):
    from pydrake.multibody.tree import JacobianWrtVariable

    arm, plant, context = arm_and_plant(arm_name)
    q, qd, qdd = random_q(arm, rng, 8), rng.normal(size=(8, arm.n)), rng.normal(size=(8, arm.n))
    J = arm.jacobian(q)
    twist, accel = arm.tool_motion(q, qd, qdd)
    assert J.shape == (8, 6, arm.n) and twist.shape == accel.shape == (8, 6)
    tool, world = plant.GetFrameByName(arm.tool_name), plant.world_frame()
    for k in range(8):
        plant.SetPositions(context, q[k])
        plant.SetVelocities(context, qd[k])
        Jw = plant.CalcJacobianSpatialVelocity(context, JacobianWrtVariable.kV, tool, np.zeros(3), world, world)
        np.testing.assert_allclose(J[k], np.vstack([Jw[3:], Jw[:3]]), atol=1e-9)
        np.testing.assert_allclose(twist[k], J[k] @ qd[k], atol=1e-9)
        bias = plant.CalcBiasSpatialAcceleration(context, JacobianWrtVariable.kV, tool, np.zeros(3), world, world)
        classical = Jw @ qdd[k] + bias.get_coeffs()  # [ω̇; a] of the tool point, Drake's order
        np.testing.assert_allclose(accel[k], np.concatenate([classical[3:], classical[:3]]), atol=1e-9)


def test_inverse_dynamics_equals_drake_with_gravity_and_payload(arm_name, rng):
    from pydrake.multibody.tree import MultibodyForces

    from armlab.models.plant import PlantOptions, make_plant

    arm = armlab.load(arm_name)
    q, qd, qdd = random_q(arm, rng, 6), rng.normal(size=(6, arm.n)), rng.normal(size=(6, arm.n))
    tau = arm.inverse_dynamics(q, qd, qdd, payload=1.5)
    assert tau.shape == (6, arm.n)
    np.testing.assert_allclose(arm.inverse_dynamics(q[0], qd[0], qdd[0], payload=1.5), tau[0], rtol=1e-12)
    plant = make_plant(arm, PlantOptions(payload=1.5, ideal_drives=True))
    context = plant.CreateDefaultContext()
    forces = MultibodyForces(plant)
    for k in range(6):
        plant.SetPositions(context, q[k])
        plant.SetVelocities(context, qd[k])
        plant.CalcForceElementsContribution(context, forces)
        expected = plant.CalcInverseDynamics(context, qdd[k], forces)
        np.testing.assert_allclose(tau[k], expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


def test_manipulability_of_the_rr_arm_is_l1_l2_sin_theta2():
    arm = armlab.load("rr")
    theta2 = np.linspace(-3, 3, 13)
    q = np.column_stack([np.full_like(theta2, 0.3), theta2])
    L1, L2 = arm.parameters["L1"], arm.parameters["L2"]
    np.testing.assert_allclose(arm.manipulability(q), L1 * L2 * np.abs(np.sin(theta2)), atol=1e-12)
    assert arm.sigma_min([0.3, 0.0]) < 1e-12 < arm.sigma_min([0.3, 0.5])


def test_api_errors_name_the_bad_value():
    arm = armlab.load("urm6")
    with pytest.raises(ValueError, match=r"expected 6 joint values"):
        arm.fk([0, 0, 0])
    with pytest.raises(ValueError, match=r"not a finite number"):
        arm.jacobian([0, 0, np.nan, 0, 0, 0])
    with pytest.raises(ValueError, match=r"qd has shape"):
        arm.inverse_dynamics(np.zeros(6), np.zeros(5), np.zeros(6))
    with pytest.raises(ValueError, match="joint2 = 5 rad is outside its limits"):
        armlab.load("rr").fk([0, 5])
    with pytest.raises(ValueError, match=r"tf = -1 s is not allowed"):
        armlab.quintic(arm, np.zeros(6), np.ones(6), -1)
    with pytest.raises(ValueError, match=r"waypoints have shape"):
        armlab.through(arm, np.zeros(6), 1.0)


def test_motions_through_waypoints_and_constant_rate():
    arm = armlab.load("rr")
    motion = armlab.through(arm, [[0, 0.5], [1, 1], [0.5, 0.2]], [1.0, 2.0])
    assert motion.duration == 3.0 and motion.joins() == [True]  # exact: 1.0 + 2.0, integer-valued
    q, qd, _ = motion.evaluate([0.0, 1.0, 3.0])
    np.testing.assert_allclose(q, [[0, 0.5], [1, 1], [0.5, 0.2]], atol=1e-12)
    np.testing.assert_allclose(qd, 0, atol=1e-12)
    rate = armlab.constant_rate(armlab.load("rrrr"), np.zeros(4), [1, 0.1, 0.1, 0.1], 2.0)
    np.testing.assert_allclose(rate.evaluate([2.0])[0], [[2, 0.2, 0.2, 0.2]])


@pytest.mark.slow
def test_simulate_returns_a_run_whose_torques_are_the_inverse_dynamics(tmp_path):
    arm = armlab.load("rr")
    run = armlab.simulate(arm, armlab.quintic(arm, [0.0, 0.5], [1.0, 1.0], 1.0), payload=0.5)
    assert run.t.shape[0] == run.q.shape[0] == run.tau.shape[0] == 1001
    expected = arm.inverse_dynamics(run.q_ref, run.qd_ref, run.qdd_ref, payload=0.5)
    # the controller adds PD terms on tracking errors of ~1e-9 rad: equal to 1e-6 of the largest torque
    np.testing.assert_allclose(run.tau, expected, rtol=0, atol=1e-6 * np.abs(expected).max())
    assert not run.diverged and run.violations == []
    assert [d["joint"] for d in run.drives] == ["joint1", "joint2"]
    assert run.drives[0]["peak_torque"] == pytest.approx(np.abs(run.tau[:, 0]).max())
    shown = run.plot()  # figures only: nothing written
    assert list(shown) == [*PLOTS, "drives.png"] and all(isinstance(f, Figure) for f in shown.values())
    plotted = run.plot(tmp_path / "plots")
    assert sorted(p.name for p in (tmp_path / "plots").iterdir()) == sorted(plotted)
    assert all((tmp_path / "plots" / name).stat().st_size > 0 for name in plotted)
    written = run.save(tmp_path / "run")
    assert {"log.csv", "summary.json", "drives.csv", "drives.png", "replay.html"} <= set(written)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["limit_violations"] == [] and summary["diverged"] is False


def test_kinematic_arm_refuses_torques(tmp_path):
    path = tmp_path / "kin.csv"
    path.write_text("type,a,alpha,d,theta,lower,upper\nR,0.5,0,0,0,-3,3\nR,0.4,0,0,0,-3,3\n")
    arm = armlab.load(path)
    assert not arm.has_dynamics
    np.testing.assert_allclose(arm.fk([0, 0])[:3, 3], [0.9, 0, 0], atol=1e-12)
    with pytest.raises(ValueError, match="kinematic arm"):
        arm.inverse_dynamics([0, 0], [0, 0], [0, 0])
    with pytest.raises(ValueError, match="kinematic arm"):
        armlab.simulate(arm, armlab.quintic(arm, [0, 0], [1, 1], 1.0))


@pytest.mark.slow
def test_limit_violations_warn_and_strict_limits_exit_3(tmp_path, capsys):
    """A two-link URDF with a 10 kg payload in 0.3 s needs far more than its 50 N·m and 3 rad/s."""
    path = tmp_path / "two_link.urdf"
    path.write_text(TWO_LINK_URDF)
    argv = ["simulate", str(path), "--from", "0,0", "--to", "1.5,-1", "--tf", "0.3", "--payload", "10"]
    assert main([*argv, "--out", str(tmp_path / "a")]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert any(line.startswith("armlab: warning: two_link shoulder: simulated effort reaches") for line in err)
    assert any("velocity reaches" in line and "past its limit 3 rad/s" in line for line in err)
    summary = json.loads((tmp_path / "a" / "summary.json").read_text())
    effort = [v for v in summary["limit_violations"] if v["joint"] == "shoulder" and v["quantity"] == "effort"]
    assert len(effort) == 1 and abs(effort[0]["peak"]) > 50 and abs(effort[0]["limit"]) == 50
    assert 0 <= effort[0]["first_time"] < 0.3  # holding the payload level already needs ~109 N·m
    assert main([*argv, "--strict-limits", "--out", str(tmp_path / "b")]) == 3
    assert "limit violation(s) (--strict-limits)" in capsys.readouterr().err


@pytest.mark.slow
def test_open_loop_run_that_leaves_the_reference_is_diverged(tmp_path, capsys):
    """rrrr's 15 s constant-rate run in open-loop inverse dynamics drifts away (tracking error of radians)."""
    code = main(["simulate", "rrrr", "--mode", "inverse_dynamics", "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 3
    assert err[-1].startswith("armlab: error: the run diverged: ") and "left the reference at t = " in err[-1]
    summary = json.loads((tmp_path / "r" / "summary.json").read_text())
    assert summary["diverged"] is True and summary["divergence"]["max_error"] > 1
    assert 0 < summary["divergence"]["time"] < 15


def test_fk_prints_twist_manipulability_and_flags_singular(capsys):
    assert main(["fk", "rr", "--q", "0,0", "--qd", "1,0", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["singular"] is True and out["manipulability"] == pytest.approx(0, abs=1e-12)
    np.testing.assert_allclose(out["tool"]["velocity"], [0, 0.7, 0], atol=1e-12)
    assert main(["fk", "rr", "--q", "30,60", "--deg"]) == 0
    text = capsys.readouterr().out
    assert "q = +30.000000  +60.000000  (deg" in text and "SINGULAR" not in text


def test_drives_are_ideal_a_passed_effort_limit_is_reported_not_clamped():
    """Drake would clamp arm4r's actuators at the URDF's 200 N·m; the run must show the torque the motion takes."""
    arm = armlab.load("arm4r")
    run = armlab.simulate(arm, armlab.quintic(arm, np.zeros(4), [0.5, -0.5, 0.5, 0.3], 0.4), payload=2.0)
    assert np.abs(run.tau).max() > 250 and np.abs(run.q - run.q_ref).max() < 1e-6 and not run.diverged
    assert {(v["joint"], v["quantity"]) for v in run.violations} == {("joint1", "effort"), ("joint2", "effort")}


def test_the_package_exports_the_api_and_the_cli_start_loads_none_of_it():
    import subprocess
    import sys

    assert set(armlab.__all__) >= {"load", "quintic", "through", "constant_rate", "simulate", "Run", "Arm", "Motion"}
    assert all(getattr(armlab, name) is not None for name in armlab.__all__)
    code = "import sys, armlab.cli; armlab.cli.build_parser(); print(sorted(m for m in sys.modules if m in " \
           "('armlab.api', 'armlab.diagrams.run', 'pydrake', 'matplotlib', 'sympy', 'distributed')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


# ------------------------------------------------------------------------------- in a notebook
def test_an_arm_prints_short_and_shows_its_joints_in_a_notebook():
    for name in ("rr", "r2t", "urm6"):
        arm = armlab.load(name)
        text = repr(arm)
        assert len(text) < 120 and "np.float64" not in text and text.startswith(f"<Arm {name}: {arm.n} joints")
    arm = armlab.load("r2t")
    page = arm._repr_html_()
    cells = re.findall(r"<td>(.*?)</td>", page)
    assert len(cells) == 7 * arm.n
    for i, (lim, link) in enumerate(zip(arm.limits, arm.links(), strict=True)):
        row = cells[7 * i: 7 * i + 7]
        assert row[0] == arm.joint_names[i] and row[1] == ("revolute" if arm.revolute[i] else "prismatic")
        lower = float(row[2].rstrip("°m "))
        np.testing.assert_allclose(np.radians(lower) if arm.revolute[i] else lower, lim.lower, rtol=1e-4)
        np.testing.assert_allclose(float(row[6].split()[0]), link["mass"], rtol=1e-4)
    doc = armlab.Arm.__doc__
    assert doc.splitlines()[0].startswith("A serial robot arm") and "armlab.load(" in doc.split("\n\n")[1]


@pytest.mark.slow
def test_a_run_prints_short_and_shows_its_summary_and_replay_in_a_notebook():
    arm = armlab.load("rr")
    run = armlab.simulate(arm, armlab.quintic(arm, [0.0, 0.5], [1.0, 1.0], 1.0), log_period=0.01)
    text = repr(run)
    assert len(text) < 200 and "np.float64" not in text
    peak = np.abs(run.tau).max()
    assert f"peak |τ| {peak:.4g} N·m" in text and "within limits" in text
    page = run._repr_html_()
    cells = re.findall(r"<td>(.*?)</td>", page)
    np.testing.assert_allclose([float(cells[6 * i + 1].split()[0]) for i in range(2)], np.abs(run.tau).max(axis=0),
                               rtol=1e-3)
    frame = html.unescape(re.search(r'srcdoc="(.*?)"', page, re.S).group(1))
    assert frame.lstrip().startswith("<!DOCTYPE html>") and 'id="armlab-graphs"' in frame
    data = json.loads(re.search(r"const D = (\{.*?\});\n", frame).group(1))
    np.testing.assert_allclose(np.array(data["graphs"]["panels"][2]["y"]).T, run.tau, rtol=1e-5, atol=1e-9)


def test_the_scheme_is_a_figure_written_only_when_asked(tmp_path):
    arm = armlab.load("rr")
    fig = armlab.draw(arm, [0.3, -0.2])
    assert isinstance(fig, Figure) and list(tmp_path.iterdir()) == []
    assert "rr: kinematic scheme at q = (17.19°, -11.46°)" in fig.texts[0].get_text()
    armlab.draw(arm, path=tmp_path / "rr.svg")
    assert [p.name for p in tmp_path.iterdir()] == ["rr.svg"]
    with pytest.raises(ValueError, match="suffix"):
        armlab.draw(arm, path=tmp_path / "rr.gif")


def test_the_live_viewer_in_a_notebook_says_what_to_do_when_localhost_is_not_reachable():
    from armlab.presentation.view import notebook_note

    note = notebook_note("http://localhost:7001")
    assert '<iframe src="http://localhost:7001"' in note
    assert "ssh -L 7001:localhost:7001" in note and "/proxy/7001/" in note and "replay" in note


@pytest.mark.slow
def test_a_motion_and_a_fastest_timing_print_short_and_show_a_table_in_a_notebook():
    """Issue 33: ``Motion`` and ``Fastest`` showed raw dataclass dumps in Jupyter (arrays, Drake objects); now a
    one-line repr and an HTML table (a fastest timing's with its rate figure drawn)."""
    arm = armlab.load("rr")
    motion = armlab.quintic(arm, [0.0, 0.5], [1.0, 1.0], 2.0)
    text = repr(motion)
    assert text == f"<Motion {motion.description}: 2 s, 1 segment(s), 2 joints>" and len(text) < 160
    cells = re.findall(r"<td>(.*?)</td>", motion._repr_html_())
    assert cells[1:3] == ["0", "2"]
    np.testing.assert_allclose([float(v) for v in cells[3].split(", ")], [0.0, 0.5], atol=1e-12)
    np.testing.assert_allclose([float(v) for v in cells[4].split(", ")], [1.0, 1.0], rtol=1e-4)
    best = armlab.fastest(arm, motion, effort=[9.0, 3.0])
    text = repr(best)
    assert text.startswith(f"<Fastest: {best.duration:.6g} s;") and "np.float64" not in text and len(text) < 200
    page = best._repr_html_()
    cells = re.findall(r"<td>(.*?)</td>", page)
    np.testing.assert_allclose([float(cells[5 * k + 3]) for k in range(2)], [9.0, 3.0], rtol=1e-12)
    assert '<img src="data:image/png;base64,' in page


@pytest.mark.slow
def test_a_runs_plots_and_a_sizing_show_in_a_notebook():
    """Issue 33: ``run.plot()`` as a cell's value showed a dict of ``<Figure …>`` and drew nothing; a ``Sizing``
    a dataclass dump. Now the figures are drawn inline (one PNG per figure, under its name), and a sizing is one
    line and a table of the chosen drives."""
    import base64

    arm = armlab.load("rr")
    run = armlab.simulate(arm, armlab.quintic(arm, [0.0, 0.5], [1.0, 1.0], 1.0), log_period=0.01)
    shown = run.plot()
    assert isinstance(shown, dict) and repr(shown) == f"<Figures: {', '.join(shown)}>"
    page = shown._repr_html_()
    images = re.findall(r'<img src="data:image/png;base64,([^"]+)"', page)
    assert len(images) == len(shown) and all(base64.b64decode(i)[:8] == b"\x89PNG\r\n\x1a\n" for i in images)
    assert re.findall(r"<figcaption>(.*?)</figcaption>", page) == list(shown)
    import matplotlib.pyplot as plt

    for fig in shown.values():
        plt.close(fig)
    sizing = armlab.size_drives(arm)
    text = repr(sizing)
    assert text.startswith("<Sizing rr: ") and len(text) < 200 and "np.float64" not in text
    cells = re.findall(r"<td>(.*?)</td>", sizing._repr_html_())
    if sizing.feasible:
        assert f"drive mass {sizing.drive_mass:.4g} kg" in text
        assert cells[1::6] == [j.chosen.motor_name for j in sizing.joints]
        np.testing.assert_allclose([float(v) for v in cells[4::6]], [j.chosen.mass for j in sizing.joints], rtol=1e-3)
    else:
        assert "infeasible" in text and any("none feasible" in c for c in cells)
