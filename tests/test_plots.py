"""The pictures of a run: the Fig. 6 view of the diagram and the plots of ``armlab simulate``.

The Fig. 6 picture is checked against the built Drake diagram itself: every edge drawn is a real
connection (``Diagram.connection_map()``) and no connection is missing.
"""

from __future__ import annotations

import html
import re

import pytest

from armlab.diagrams.build import build_diagram
from armlab.diagrams.graphviz import fig6_dot, parse_drake_dot, render
from armlab.diagrams.motions import paper_motion
from armlab.models import get_arm


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
    run = build_diagram(arm, paper_motion(arm).runs()[0][1], mode=mode)
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

