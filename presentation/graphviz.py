"""Graphviz export of a diagram: DOT text always, SVG, PNG and PDF through graphviz's ``dot`` program.

Two pictures of one Drake diagram:

* Drake's own graph (``Diagram.GetGraphvizString``): every system with every port, connected or
  not — complete, but a plant shows some twenty unused ports;
* the **Fig. 6 view** (:func:`fig6_dot`): paper 000's Fig. 6 drawn from the same graph, every
  system as one box, only the connected ports, left to right from the trajectory source through
  the inverse dynamics and the plant to the loggers (Simulink's scopes), each connection labelled
  with the signal it carries (q, q̇, q̈, τ, state). Nothing is typed in: the systems and the
  connections are read from Drake's graph (:func:`parse_drake_dot`); the signal names come from
  the ports' names. Each edge of the Fig. 6 SVG carries the connection it draws as its ``id``
  (``"log_state.data<-MultibodyPlant.state"``), so a test can compare the picture with the
  diagram's ``connection_map()``.

``dot`` is not a Python package: without it a run's pictures are skipped with a
:class:`DotMissingWarning` (:func:`write_pictures`), and a picture asked for by name is an error
(:func:`require_dot`).
"""

from __future__ import annotations

import html
import re
import shutil
import subprocess
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from armlab.files import suffix_format, write_file

__all__ = ["FORMATS", "Connection", "DotMissingWarning", "DrakeGraph", "fig6_dot", "parse_drake_dot", "render",
           "require_dot", "write_graph", "write_pictures"]

#: Output formats by file suffix.
FORMATS = ("dot", "svg", "png", "pdf")
#: How to get graphviz's ``dot`` (a system package, not a Python one; ``make run-deps`` in a clone does this).
_INSTALL = "install graphviz (apt-get install graphviz)"


class DotMissingWarning(UserWarning):
    """graphviz's ``dot`` is not installed: the pictures that need it were skipped, everything else was written."""


def require_dot() -> str:
    """Path of graphviz's ``dot``, or ``ValueError`` saying how to install it."""
    dot = shutil.which("dot")
    if dot is None:
        raise ValueError(f"graphviz's 'dot' program is needed for SVG/PNG/PDF diagrams and was not found: {_INSTALL}, "
                         "or write a .dot file")
    return dot


def render(dot_text: str, fmt: str) -> bytes:
    """``dot_text`` as ``fmt`` (``dot``, ``svg``, ``png`` or ``pdf``) bytes; the others by ``dot -T<fmt>``."""
    if fmt not in FORMATS:
        raise ValueError(f"diagram format {fmt!r} is not allowed; allowed: {', '.join(FORMATS)}")
    if fmt == "dot":
        return dot_text.encode()
    result = subprocess.run([require_dot(), f"-T{fmt}"], input=dot_text.encode(), capture_output=True, check=False)
    if result.returncode != 0:
        raise ValueError(f"dot -T{fmt} failed: {result.stderr.decode(errors='replace').strip()}")
    return _subscripts(result.stdout.decode()).encode() if fmt == "svg" else result.stdout


#: One piece of a label in graphviz's SVG: a ``<text>`` of its own, at the x graphviz measured for it.
_PIECE = re.compile(r'<text text-anchor="start" x="(-?[\d.]+)" y="(-?[\d.]+)" font-family="([^"]*)"'
                    r'( baseline-shift="sub")? font-size="([\d.]+)">(.*?)</text>')


def _subscripts(svg: str) -> str:
    """Graphviz's labels with subscripts (``x<SUB>d</SUB>``) in ``svg`` drawn as one text each.

    Graphviz writes each piece as a ``<text>`` of its own at the x its font metrics give and a subscript with
    ``baseline-shift="sub"``, which browsers ignore on ``<text>``: "x d = (q  d, …)" at full size with gaps. The
    pieces of one line (same y, one after the other) become ``<tspan>``s of one ``<text>``, laid out by the
    browser, the subscripts at 70 % of the size and lowered by 30 % of it.
    """
    lines, out, k = svg.split("\n"), [], 0
    while k < len(lines):
        run: list[re.Match[str]] = []
        while k + len(run) < len(lines) and (m := _PIECE.fullmatch(lines[k + len(run)].strip())) and (
                not run or m.group(2) == run[0].group(2)):
            run.append(m)
        if not any(m.group(4) for m in run):
            out.append(lines[k])
            k += 1
            continue
        first = run[0]
        spans, low = [], False
        for m in run:
            size = float(m.group(5))
            shift = (0.3 * size if m.group(4) and not low else -0.3 * size if low and not m.group(4) else 0.0)
            low = bool(m.group(4))
            dy = f' dy="{shift:.2f}"' if shift else ""
            spans.append(f'<tspan{dy} font-size="{0.7 * size if low else size:.2f}">{m.group(6)}</tspan>')
        out.append(f'<text text-anchor="start" x="{first.group(1)}" y="{first.group(2)}" '
                   f'font-family="{first.group(3)}" xml:space="preserve">{"".join(spans)}</text>')
        k += len(run)
    return "\n".join(out)


def graph_format(path: str | Path) -> str:
    """The format :func:`write_graph` writes for ``path`` (its suffix); ``ValueError`` for any other suffix."""
    return suffix_format(path, FORMATS)


def write_graph(dot_text: str, path: str | Path) -> Path:
    """Write ``dot_text`` to ``path`` in the format its suffix names, atomically (:func:`~armlab.files.write_file`)."""
    return write_file(path, render(dot_text, graph_format(path)))


def write_pictures(pictures: Mapping[str, str], folder: str | Path) -> list[str]:
    """Render each ``file name → DOT text`` of ``pictures`` into ``folder`` in the format its suffix names.

    Returns the names written: all of them, or none and one :class:`DotMissingWarning` naming them and how
    to get them when graphviz's ``dot`` is not installed (the caller's other files do not need it).
    """
    if shutil.which("dot") is None:
        warnings.warn(DotMissingWarning(f"graphviz's dot is not installed: {', '.join(pictures)} skipped; {_INSTALL} "
                                        "for them"), stacklevel=2)
        return []
    for name, dot_text in pictures.items():
        (Path(folder) / name).write_bytes(render(dot_text, graph_format(name)))
    return list(pictures)


# --------------------------------------------------------------------------- Drake's graph, read
@dataclass(frozen=True)
class Connection:
    """One connection of a diagram: output port ``source.output`` feeds input port ``target.input``."""

    source: str  # system name
    output: str  # output port name
    target: str
    input: str

    @property
    def id(self) -> str:
        """``"target.input<-source.output"``: unique in a diagram (an input port has one source)."""
        return f"{self.target}.{self.input}<-{self.source}.{self.output}"


@dataclass
class DrakeGraph:
    """A diagram as ``GetGraphvizString`` draws it: its name, its systems (name → class) and connections."""

    name: str
    systems: dict[str, str]
    connections: list[Connection]


_NODE = re.compile(r'^(s\d+) \[shape=none, border=0, label=<\n(.*?)\n>\];$', re.M | re.S)
_HEAD = re.compile(r"<B>(.*?)</B><BR/>\s*name=(.*?)\s*</TD>", re.S)
_PORT = re.compile(r'<TD PORT="([uy]\d+)"[^>]*>(?:<FONT[^>]*>)?([^<]*)')
_EDGE = re.compile(r"^(s\d+):(y\d+):e -> (s\d+):(u\d+):w$", re.M)
_TITLE = re.compile(r"<B>Diagram</B><BR/>\s*name=(.*?)\s*</TD>", re.S)


def parse_drake_dot(dot_text: str) -> DrakeGraph:
    """The systems and connections of a diagram from its ``GetGraphvizString(max_depth=1)`` text.

    ``ValueError`` if the text is not such a graph (no systems found, or an edge naming an unknown port).
    """
    title = _TITLE.search(dot_text)
    systems: dict[str, tuple[str, str]] = {}
    ports: dict[tuple[str, str], str] = {}
    for node, body in _NODE.findall(dot_text):
        head = _HEAD.search(body)
        if head is None:
            continue
        systems[node] = (html.unescape(head.group(2)), html.unescape(head.group(1)))
        ports.update({(node, port): html.unescape(name) for port, name in _PORT.findall(body)})
    if not systems:
        raise ValueError("not a Drake diagram's graphviz text: no systems found")
    connections = []
    for src, out, dst, inp in _EDGE.findall(dot_text):
        if (src, out) not in ports or (dst, inp) not in ports:
            raise ValueError(f"Drake graph edge {src}:{out} -> {dst}:{inp} names a port that is not drawn")
        connections.append(Connection(systems[src][0], ports[src, out], systems[dst][0], ports[dst, inp]))
    return DrakeGraph(html.unescape(title.group(1)) if title else "", dict(systems.values()), connections)


# --------------------------------------------------------------------------- the Fig. 6 view
#: Signal carried by an output port, by port name (HTML-like Graphviz labels).
_SIGNALS = {
    "state": "x = (q, q̇)",
    "generalized_acceleration": "q̈",
    "actuation": "τ",
    "generalized_force": "τ",
    "tool_pva": "p, v, a of the tool point",
    "friction": "±T<SUB>c</SUB>·tanh(q̇/v<SUB>s</SUB>)",  # armlab.drives.friction.CoulombFriction
    "sum": "τ",  # the drives' torque: the controller's and its friction compensation (an Adder)
}
#: Signal into an input port fed by the reference split, by input port name.
_REFERENCE_SIGNALS = {
    "desired_state": "x<SUB>d</SUB> = (q<SUB>d</SUB>, q̇<SUB>d</SUB>)",
    "estimated_state": "x<SUB>d</SUB> = (q<SUB>d</SUB>, q̇<SUB>d</SUB>)",
    "desired_acceleration": "q̈<SUB>d</SUB>",
    "state": "x<SUB>d</SUB> = (q<SUB>d</SUB>, q̇<SUB>d</SUB>)",  # the friction compensation of open loop
}
_REFERENCE = "q<SUB>d</SUB>, q̇<SUB>d</SUB>, q̈<SUB>d</SUB>"
#: Column of each kind of system, left to right (by class; anything else goes in the middle).
_COLUMNS = {"TrajectorySource": 0, "Demultiplexer": 1, "InverseDynamicsController": 2, "InverseDynamics": 2,
            "MultibodyPlant": 3, "VectorLogSink": 5}
#: Box colours by column: reference, control, plant, derived signals, scopes.
_FILL = {0: "#e8f0fe", 1: "#e8f0fe", 2: "#fdecea", 3: "#e6f4ea", 4: "#fef7e0", 5: "#f1f3f4"}
#: A servo loop's stages (armlab.diagrams.servo), by the prefix of their systems' names: (cluster label, column,
#: fill). Each stage is one group of boxes in the picture, the way a Simulink model groups a drive's subsystems.
_STAGES = {
    "reference_sampling": ("", 1, "#e8f0fe"),
    "servo_": ("position controller", 2, "#fdecea"), "computed_torque": ("position controller", 2, "#fdecea"),
    "joint_inertia": ("position controller", 2, "#fdecea"), "feedforward": ("position controller", 2, "#fdecea"),
    "torque_saturation": ("position controller", 2, "#fdecea"),
    "current_": ("drives: current loops and motor windings", 2.5, "#f3e8fd"),
    "voltage_saturation": ("drives: current loops and motor windings", 2.5, "#f3e8fd"),
    "motor": ("drives: current loops and motor windings", 2.5, "#f3e8fd"),
    "drive_output": ("elastic joints: rotors and gearbox springs", 2.75, "#f3e8fd"),
    "elastic_": ("elastic joints: rotors and gearbox springs", 2.75, "#f3e8fd"),
    "joint_positions": ("sensors", 4, "#fef7e0"), "encoder": ("sensors", 4, "#fef7e0"),
    "noise": ("sensors", 4, "#fef7e0"), "noisy_position": ("sensors", 4, "#fef7e0"),
    "sensor_": ("sensors", 4, "#fef7e0"),
    "energy_": ("energy meter", 4, "#fef7e0"),
}
#: Signals of the servo loop's outputs, by (system, output port): what each block puts out.
_STAGE_SIGNALS = {
    "reference_sampling": "held q<SUB>d</SUB>, q̇<SUB>d</SUB>, q̈<SUB>d</SUB>",
    "sensor_sampling": "x<SUB>m</SUB> = (q<SUB>m</SUB>, q̇<SUB>m</SUB>)", "joint_positions": "q",
    "encoder_angle": "θ = a·q", "encoders": "θ quantised", "encoder_position": "q quantised", "noise_source": "w",
    "noise": "σ·w", "noisy_position": "q<SUB>s</SUB>", "sensor_inputs": "(q<SUB>s</SUB>, x)",
    "servo_signal": "(x<SUB>d</SUB>, q̈<SUB>d</SUB>, x<SUB>m</SUB>)", "servo_pid_gains": "P·e",
    "servo_pid_integral_inputs": "(e, τ, τ*)", "servo_pid_integral": "z", "servo_pid_sum": "a",
    "computed_torque": "τ*", "joint_inertia": "τ* = J a", "feedforward_reference": "x<SUB>d</SUB> | q̈<SUB>d</SUB>",
    "feedforward": "τ<SUB>ff</SUB>", "servo_torque": "τ*", "torque_saturation": "τ",
    "current_command": "i*", "current_signal": "(i*, i, x)", "current_sampling": "held (i*, i, x)",
    "current_pi_gains": "P·e", "current_pi_integral_inputs": "(e, V, V*)", "current_pi_integral": "z",
    "current_pi_sum": "V*", "voltage_saturation": "V", "motor_inputs": "(V, x)", "motors": "(i, τ)",
    "energy_inputs": "(V, i, τ, x)", "drive_output": "τ (drive)", "elastic_inputs": "(τ, x)",
    "elastic_rotors": "x<SUB>r</SUB> = (φ, φ̇)", "elastic_twist": "(x<SUB>r</SUB>, x)",
    "elastic_spring": "τ<SUB>s</SUB> = K (φ − q) + D (φ̇ − q̇)", "energy_meter": "E = (∫V i, ∫τ q̇, ∫R i²)",
}
_STAGE_PORTS = {("motor_outputs", "y0"): "i", ("motor_outputs", "y1"): "τ = G k<SUB>t</SUB> i"}


def _stage(name: str) -> tuple[str, float, str] | None:
    """The servo stage (label, column, fill) of a system by its name, or ``None``."""
    return next((stage for prefix, stage in _STAGES.items() if name.startswith(prefix)), None)


def _short_class(cls: str) -> str:
    return cls.rsplit(".", 1)[-1]


def _signal(graph: DrakeGraph, c: Connection) -> str:
    """The signal a connection carries, named from its ports (and the source's class, or its servo stage)."""
    if (c.source, c.output) in _STAGE_PORTS:
        return _STAGE_PORTS[c.source, c.output]
    if c.source in _STAGE_SIGNALS:
        return _STAGE_SIGNALS[c.source]
    source_class = _short_class(graph.systems[c.source])
    if source_class == "TrajectorySource":
        return _REFERENCE
    if source_class == "Demultiplexer":
        return _REFERENCE_SIGNALS.get(c.input, html.escape(c.output))
    return _SIGNALS.get(c.output, html.escape(c.output))


def _q(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _column(graph: DrakeGraph, name: str) -> float:
    """A system's column, left to right: its servo stage's, else its class's (anything else: the middle)."""
    stage = _stage(name)
    return stage[1] if stage is not None else _COLUMNS.get(_short_class(graph.systems[name]), 4)


def fig6_dot(dot_text: str, title: str | None = None) -> str:
    """Paper 000's Fig. 6 view of the diagram whose ``GetGraphvizString`` is ``dot_text``, as DOT.

    Every system of the diagram that takes part in a connection is one box (name, Drake class);
    every connection is one edge labelled with its signal; unconnected ports are left out. Boxes
    flow left to right: trajectory source → reference split → inverse dynamics → plant → tool
    point → loggers ("scopes"). A servo loop's systems (:mod:`armlab.diagrams.servo`) are grouped by
    stage — position controller, drives (current loops and windings), sensors, energy meter — each a
    labelled box of its own. ``title`` (default: the diagram's name) is drawn above, clear of
    every edge. Each edge's SVG ``id`` is its :attr:`Connection.id`.
    """
    graph = parse_drake_dot(dot_text)
    used = {name for c in graph.connections for name in (c.source, c.target)}
    lines = [
        "digraph fig6 {",
        "rankdir=LR; newrank=true; nodesep=0.35; ranksep=0.7; splines=spline;",
        f"labelloc=t; fontname=Helvetica; fontsize=16; label={_q(title if title is not None else graph.name)};",
        'node [shape=box, style="rounded,filled", fontname=Helvetica, fontsize=12, penwidth=1.2];',
        "edge [fontname=Helvetica, fontsize=11, penwidth=1.2, arrowsize=0.8];",
    ]
    columns: dict[float, list[str]] = {}
    stages: dict[str, list[str]] = {}
    for name, cls in graph.systems.items():
        if name not in used:
            continue
        short = _short_class(cls)
        stage = _stage(name)
        column = _column(graph, name)
        if stage is not None and stage[0]:
            stages.setdefault(stage[0], []).append(name)
        else:
            columns.setdefault(column, []).append(name)
        kind = "" if short == name else f"<BR/><FONT POINT-SIZE='9' COLOR='#555555'>{html.escape(short)}</FONT>"
        group = ", group=main" if column <= 3 and stage is None else ""  # the forward chain drawn as one line
        fill = stage[2] if stage is not None else _FILL[int(column)]
        lines.append(f'{_q(name)} [id={_q("system:" + name)}, label=<<B>{html.escape(name)}</B>{kind}>, '
                     f'fillcolor="{fill}"{group}];')
    for column in sorted(columns):
        members = " ".join(_q(n) for n in columns[column])
        if column == _COLUMNS["VectorLogSink"]:  # Simulink's scopes: one labelled group
            lines.append(f'subgraph cluster_scopes {{label="loggers (scopes)"; labeljust=l; fontsize=11; '
                         f'style="rounded,dashed"; color="#9aa0a6"; rank=same; {members}}}')
        else:
            lines.append(f"{{rank=same; {members}}}")
    for k, (label, names) in enumerate(stages.items()):  # a servo stage: its blocks flow inside its own box
        lines.append(f'subgraph cluster_stage{k} {{label={_q(label)}; labeljust=l; fontsize=11; style="rounded"; '
                     f'color="#9aa0a6"; {" ".join(_q(n) for n in names)}}}')
    for c in graph.connections:
        same_stage = _stage(c.source) is not None and _stage(c.source) == _stage(c.target)
        backward = not same_stage and _column(graph, c.target) <= _column(graph, c.source)
        style = ", constraint=false, style=dashed" if backward else ""  # feedback: drawn, not ranked
        lines.append(f"{_q(c.source)} -> {_q(c.target)} [id={_q(c.id)}, label=<{_signal(graph, c)}>, "
                     f"tooltip={_q(c.id)}{style}];")
    lines.append("}")
    return "\n".join(lines) + "\n"
