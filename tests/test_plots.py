"""The pictures of a run: the Fig. 6 view of the diagram and the plots of ``armlab simulate``.

The Fig. 6 picture is checked against the built Drake diagram itself: every edge drawn is a real
connection (``Diagram.connection_map()``) and no connection is missing.
"""

from __future__ import annotations

import dataclasses
import functools
import html
import re
from pathlib import Path

import numpy as np
import pytest

import armlab
from armlab.diagrams.build import build_diagram
from armlab.diagrams.simulate import SimulationOptions, simulate
from armlab.models import get_arm
from armlab.planning.motions import paper_motion
from armlab.presentation.graphviz import fig6_dot, parse_drake_dot, render
from armlab.presentation.plots import PLOTS, figures, limit_values, write_plots


def connections(diagram) -> set[str]:
    """Every connection of ``diagram`` as ``"target.input<-source.output"``, from ``connection_map()``."""
    ids = set()
    for (target, in_index), (source, out_index) in diagram.connection_map().items():
        ids.add(f"{target.get_name()}.{target.get_input_port(in_index).get_name()}"
                f"<-{source.get_name()}.{source.get_output_port(out_index).get_name()}")
    return ids


def svg_ids(svg: str, kind: str) -> set[str]:
    return {html.unescape(i) for i in re.findall(rf'<g id="([^"]*)" class="{kind}"', svg)}


@pytest.mark.parametrize(("name", "mode"), [("rr", "controller"), ("urm6", "inverse_dynamics"),
                                            ("r2t", "controller")])
def test_fig6_draws_exactly_the_diagrams_connections(name, mode):
    arm = get_arm(name)
    run = build_diagram(arm, paper_motion(arm).runs()[0][1], SimulationOptions(mode=mode))
    dot = run.diagram.GetGraphvizString(max_depth=1)
    svg = render(fig6_dot(dot), "svg").decode()
    expected = connections(run.diagram)
    assert len(expected) >= 10
    assert svg_ids(svg, "edge") == expected
    connected = {part.split(".")[0] for c in expected for part in c.split("<-")}
    assert svg_ids(svg, "node") == {f"system:{s}" for s in connected}
    # Only the connected ports: none of the plant's ~20 unused ones is named in the picture.
    for unused in ("contact_results", "geometry_query", "body_poses", "reaction_forces", "net_actuation"):
        assert unused not in svg
    assert "τ" in svg and "q̈" in svg and "x = (q, q̇)" in svg  # signals named
    # Drake's graph does hold those unused ports: the parser reads what is there, not a fixed list.
    graph = parse_drake_dot(dot)
    assert "contact_results" in dot and {c.id for c in graph.connections} == expected


def test_fig6_reads_left_to_right_from_source_to_loggers():
    arm = get_arm("rr")
    run = build_diagram(arm, paper_motion(arm).runs()[0][1])
    svg = render(fig6_dot(run.diagram.GetGraphvizString(max_depth=1)), "svg").decode()

    def x(system: str) -> float:
        block = svg.split(f'<g id="system:{system}" class="node">', 1)[1].split("</g>", 1)[0]
        return float(re.search(r'<text[^>]* x="([-\d.]+)"', block).group(1))

    chain = ["TrajectorySource", "reference_split", "InverseDynamicsController", "MultibodyPlant", "log_state"]
    positions = [x(s) for s in chain]
    assert positions == sorted(positions) and len(set(positions)) == len(positions), chain


def test_parse_rejects_text_that_is_not_a_drake_graph():
    with pytest.raises(ValueError, match="no systems"):
        parse_drake_dot("digraph g { a -> b }")


def test_diagram_command_writes_pdf_and_the_full_graph(tmp_path):
    from armlab.cli import main

    assert main(["diagram", "rr", "--out", str(tmp_path / "fig6.pdf")]) == 0
    assert (tmp_path / "fig6.pdf").read_bytes().startswith(b"%PDF")
    assert main(["diagram", "rr", "--full", "--out", str(tmp_path / "full.svg")]) == 0
    assert main(["diagram", "rr", "--out", str(tmp_path / "fig6.svg")]) == 0
    full, fig6 = (tmp_path / "full.svg").read_text(), (tmp_path / "fig6.svg").read_text()
    assert "contact_results" in full and "contact_results" not in fig6
    assert main(["diagram", "rr", "--out", str(tmp_path / "fig6.jpg")]) == 2
    assert not (tmp_path / "fig6.jpg").exists()



# ---------------------------------------------------------------------------------- simulate's plots
@functools.cache
def rr_log():
    arm = get_arm("rr")
    return simulate(arm, paper_motion(arm, "abcd"), SimulationOptions(log_period=0.01))


def hlines(ax) -> set[tuple[float, str]]:
    """The horizontal lines of ``ax``: (y, colour)."""
    out = set()
    for line in ax.get_lines():
        x, y = line.get_xdata(), line.get_ydata()
        if len(y) == 2 and y[0] == y[1] and list(x) == [0, 1]:  # axhline: axes-fraction x
            out.add((round(float(y[0]), 9), line.get_color()))
    return out


def shown_limits(ax, log, kind: str, values: np.ndarray) -> list[str]:
    """How each joint's known ``kind`` limit is shown in ``ax``: "drawn" (lines at both values) or
    "noted" (the off-scale note names the joint, the limits and the share the motion uses of them)."""
    ys = {y for y, _ in hlines(ax)}
    notes = [line for t in ax.texts for line in t.get_text().splitlines()]
    out = []
    for i, (low, high) in enumerate(limit_values(log.arm, kind)):
        drawn = round(low, 9) in ys and round(high, 9) in ys
        mine = [n for n in notes
                if f"q{i + 1}" in n.split(f" {kind}")[0].split(", ") and f"[{low:.4g}, {high:.4g}]" in n]
        assert drawn != bool(mine), (kind, i, drawn, mine)  # shown, and only one way
        if mine:
            share = float(re.search(r"uses (\d+)%", mine[0]).group(1)) / 100
            joints = [int(name[1:]) - 1 for name in mine[0].split(f" {kind}")[0].split(", ")]
            assert share == pytest.approx(np.abs(values[:, joints]).max() / max(abs(low), abs(high)), abs=0.006)
        out.append("drawn" if drawn else "noted")
    return out


@pytest.mark.slow
def test_plots_show_every_known_limit_drawn_or_noted_off_the_scale():
    import matplotlib.pyplot as plt

    log = rr_log()
    figs = figures(log)
    try:
        position, velocity, acceleration = figs["joints.png"].axes
        # rr: the position limits ±270° are within reach of the motion; ±10 rad/s and ±100 N·m are not.
        assert shown_limits(position, log, "position", log.q) == ["drawn", "drawn"]
        assert shown_limits(velocity, log, "velocity", log.qd) == ["noted", "noted"]
        (torques,) = figs["torques.png"].axes
        assert shown_limits(torques, log, "effort", log.tau) == ["noted", "noted"]
        assert hlines(acceleration) == set() and len(acceleration.texts) == 0
        assert "reference" in acceleration.get_title(loc="left")
        assert "simulated" in position.get_title(loc="left")
    finally:
        for fig in figs.values():
            plt.close(fig)
    # Limits within reach are drawn: the same run against an arm with 2 rad/s and 12 N·m drives.
    arm = dataclasses.replace(log.arm, limits=tuple(dataclasses.replace(lim, velocity=2.0, effort=12.0)
                                                    for lim in log.arm.limits))
    tight = dataclasses.replace(log, arm=arm)
    joints, torques = figures(tight)["joints.png"], figures(tight)["torques.png"]
    assert shown_limits(joints.axes[1], tight, "velocity", log.qd) == ["drawn", "drawn"]
    assert shown_limits(torques.axes[0], tight, "effort", log.tau) == ["drawn", "drawn"]
    plt.close("all")
    # An unknown effort limit (None) is neither drawn nor noted.
    arm = dataclasses.replace(log.arm, limits=tuple(dataclasses.replace(lim, effort=None) for lim in log.arm.limits))
    unknown = dataclasses.replace(log, arm=arm)
    assert limit_values(unknown.arm, "effort") == [None, None]
    ax = figures(unknown)["torques.png"].axes[0]
    assert hlines(ax) == set() and len(ax.texts) == 0
    plt.close("all")


@pytest.mark.slow
def test_closed_path_shows_start_and_end_and_3d_paths_are_to_scale(tmp_path):
    import matplotlib.pyplot as plt

    log = rr_log()
    assert np.allclose(log.tool[0, :3], log.tool[-1, :3], atol=1e-6)  # A → … → A is closed
    ax = figures(log)["tool_path.png"].axes[0]
    markers = {line.get_label(): line for line in ax.get_lines()}
    assert markers["start"].get_markersize() > markers["end"].get_markersize()  # the start ring shows around the end
    assert markers["end"].get_zorder() > markers["start"].get_zorder()
    plt.close("all")
    arm = get_arm("arm4r")
    log3 = simulate(arm, paper_motion(arm), SimulationOptions(log_period=0.01))
    ax3 = next(a for a in figures(log3)["tool_path.png"].axes if a.name == "3d")
    spans = [np.ptp(lim) for lim in (ax3.get_xlim3d(), ax3.get_ylim3d(), ax3.get_zlim3d())]
    box = np.asarray(ax3.get_box_aspect())
    np.testing.assert_allclose(np.array(spans) / box, spans[0] / box[0], rtol=1e-9)  # a metre as long on every axis
    plt.close("all")
    assert [p.name for p in write_plots(log, tmp_path)] == list(PLOTS)


@pytest.mark.slow
def test_a_tool_standing_still_plots_without_warnings(tmp_path):
    """A hold (zero-extent tool path, constant curves) used to warn 'identical low and high ylims'."""
    import warnings

    from armlab.kinematics.quintic import Motion, QuinticSegment

    arm = get_arm("rr")
    log = simulate(arm, Motion((QuinticSegment(np.array([1.5, 0.0]), np.array([1.5, 0.0]), 0.5, "hold"),)))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        paths = write_plots(log, tmp_path)
    assert [p.name for p in paths] == list(PLOTS)


def test_fig6_subscripts_are_drawn_as_subscripts():
    """Graphviz writes x<SUB>d</SUB> as separate <text>s with baseline-shift, which browsers ignore: the labels
    are one <text> each, with the subscripts smaller and lowered, and back on the line after them."""
    arm = get_arm("rr")
    run = build_diagram(arm, paper_motion(arm).runs()[0][1])
    svg = render(fig6_dot(run.diagram.GetGraphvizString(max_depth=1)), "svg").decode()
    assert "baseline-shift" not in svg
    labels = re.findall(r"<text[^>]*>((?:<tspan[^>]*>[^<]*</tspan>)+)</text>", svg)
    texts = ["".join(re.findall(r">([^<]*)</tspan>", label)) for label in labels]
    assert "xd = (qd, q̇d)" in texts and "qd, q̇d, q̈d" in texts
    for label in labels:
        spans = re.findall(r'<tspan(?: dy="(-?[\d.]+)")? font-size="([\d.]+)">([^<]*)</tspan>', label)
        level = 0.0
        for dy, size, text in spans:
            level += float(dy or 0)
            if text == "d":  # a subscript: below the line, 70 % of the size
                assert level > 0 and float(size) < 0.75 * float(spans[0][1]), label
            else:
                assert abs(level) < 1e-9 and float(size) == pytest.approx(float(spans[0][1]), abs=1e-9), label


@pytest.mark.slow
def test_legends_cover_no_curve_and_segments_are_named():
    import matplotlib.pyplot as plt

    log = rr_log()
    figs = figures(log)
    try:
        for name in ("joints.png", "torques.png", "tool_motion.png"):
            fig = figs[name]
            fig.canvas.draw()
            for ax in (a for a in fig.axes if a.get_legend() is not None):
                box, legend = ax.get_window_extent(), ax.get_legend().get_window_extent()
                assert legend.x0 >= box.x1, (name, legend, box)  # beside the panel, not over it
        top = figs["joints.png"].axes[0].child_axes[0]
        assert [t.get_text() for t in top.get_xticklabels()] == [f"segment {s}" for s in log.motion.labels]
        np.testing.assert_allclose(top.get_xticks(), [1.0, 3.0, 5.0, 7.0], atol=1e-12)  # the middles, 2 s each
    finally:
        for fig in figs.values():
            plt.close(fig)


def test_drives_show_round_off_as_rest_and_mark_the_rms_point():
    from armlab.diagrams.drives import drives_figure
    from armlab.kinematics.quintic import Motion, QuinticSegment

    arm = get_arm("rr")
    log = simulate(arm, Motion((QuinticSegment(np.array([1.5, 0.0]), np.array([1.5, 0.5]), 0.5, "elbow"),)),
                   SimulationOptions(log_period=0.01))
    assert 0 < np.abs(log.qd[:, 0]).max() < 1e-9  # joint 1 holds: its rate is round-off
    fig = drives_figure(log)
    first, second = fig.axes[:2]
    assert "peak |q̇| 0 (at rest)" in first.get_title() and "e-" not in first.get_title()
    assert f"peak |q̇| {np.abs(log.qd[:, 1]).max():.3g} rad/s" in second.get_title()
    for i, ax in enumerate((first, second)):
        (star,) = [line for line in ax.get_lines() if line.get_marker() == "*"]
        rms = np.sqrt(np.mean(log.qd[:, i] ** 2)), np.sqrt(np.mean(log.tau[:, i] ** 2))
        np.testing.assert_allclose([star.get_xdata()[0], star.get_ydata()[0]], rms, rtol=1e-12)
        assert f"RMS τ {rms[1]:.4g}" in ax.get_title()


def test_fig6_draws_a_servo_loop_grouped_by_stage():
    """A servo run's diagram: every connection drawn once, each stage's blocks in a labelled box of their own, every
    signal named (no Drake port name such as y0 left as a label)."""
    arm = armlab.load("rr", drives=Path(__file__).parents[1] / "scripts" / "examples" / "drives" / "rr_motors.csv")
    options = SimulationOptions(controller="pd+feedforward", rate=1000.0, encoder=4096, noise=1e-4,
                                velocity="difference", saturate=True, electrics=True, current_rate=10000.0)
    run = build_diagram(arm, paper_motion(arm), options)
    text = fig6_dot(run.diagram.GetGraphvizString(max_depth=1))
    svg = render(text, "svg").decode()
    assert svg_ids(svg, "edge") == connections(run.diagram)
    clusters = dict(re.findall(r'subgraph cluster_stage\d+ \{label="([^"]+)";[^}]*?; ([^}]*)\}', text))
    assert set(clusters) == {"position controller", "drives: current loops and motor windings", "sensors",
                             "energy meter"}
    for stage, member in (("position controller", "servo_pid_gains"), ("position controller", "feedforward"),
                          ("sensors", "encoders"), ("sensors", "sensor_sampling"), ("energy meter", "energy_meter"),
                          ("drives: current loops and motor windings", "motors")):
        assert f'"{member}"' in clusters[stage].split(), (stage, member)
    assert not re.search(r"label=<y\d*>", text)
    assert "held q<SUB>d</SUB>" in text and "V*" in text and "i*" in text
