"""The graphs beside a replay's 3-D view: the run's joint angles, velocities and torques against time, with a
cursor that follows playback; a click or a drag on a graph seeks the replay to that time.

Paper 000's conclusion: "Graphs of quantities located in independent windows change with the time of the
simulation". :func:`log_graphs` picks a simulation's graphs (motor-side torques and clearances too, where the log
has them), :func:`graph_data` makes them JSON for the page, and :data:`GRAPHS_SCRIPT` draws them on canvases with
the page's own script (no library, no network) and moves the cursors from the animation's clock.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.presentation.plots import joint_names, limit_groups

if TYPE_CHECKING:
    from armlab.collision.model import Clearances
    from armlab.diagrams.simulate import SimulationLog
    from armlab.models.arm import Arm

__all__ = ["GRAPHS_PCT", "MAX_GRAPH_POINTS", "Graph", "arm_graphs", "graph_data", "log_graphs"]

#: Width of the graph column, percent of the window (the 3-D view takes the rest).
GRAPHS_PCT = 40
#: Most samples per run a graph keeps (the log is thinned by a stride; a 15 s run at 1 ms keeps every 5th).
MAX_GRAPH_POINTS = 3000


@dataclass(frozen=True)
class Graph:
    """One panel: ``values`` ``(m, k)`` against the run's time, one line per column named by ``labels`` (with its
    unit), a y-axis ``ylabel`` and horizontal ``limits`` (series index or −1 for a shared limit, label, low,
    high); ``notes`` name limits too far out to draw."""

    title: str
    ylabel: str
    labels: tuple[str, ...]
    values: NDArray[np.float64]
    limits: tuple[tuple[int, str, float, float], ...] = ()
    notes: tuple[str, ...] = ()


def _units(arm: Arm, order: int, deg: bool = False) -> list[str]:
    base = ["°" if (r and deg) else ("rad" if r else "m") for r in arm.revolute]
    return [b + ("", "/s")[order] for b in base] if order < 2 else ["N·m" if r else "N" for r in arm.revolute]


def _joint_graph(arm: Arm, title: str, symbol: str, order: int, values: ArrayLike, kind: str | None,
                 deg: bool, units: list[str] | None = None) -> Graph:
    """Graph of one value per joint (``order`` 0: positions, 1: velocities, 2: torques) with its ``kind`` limits;
    ``units``: each joint's unit (default: the joint side's of ``order``)."""
    values = np.asarray(values, dtype=float)
    units = _units(arm, order, deg) if units is None else units
    scale = np.where(np.asarray(arm.revolute) & deg, np.degrees(1.0), 1.0) if order < 2 else np.ones(arm.n)
    limits: list[tuple[int, str, float, float]] = []
    notes: list[str] = []
    if kind is not None:
        drawn, notes = limit_groups(arm, kind, values)
        for joints, low, high in drawn:
            s = float(scale[joints[0]])
            limits.append((joints[0] if len(joints) == 1 else -1, f"{joint_names(joints)} {kind} limit",
                           low * s, high * s))
    return Graph(f"{title} {symbol}", f"{symbol} [{' | '.join(sorted(set(units)))}]",
                 tuple(f"{symbol}{i + 1} [{u}]" for i, u in enumerate(units)), values * scale, tuple(limits),
                 tuple(notes))


def arm_graphs(arm: Arm, q: ArrayLike, qd: ArrayLike | None = None, tau: ArrayLike | None = None,
               deg: bool = False) -> list[Graph]:
    """The graphs of joint positions ``q``, velocities ``qd`` and torques ``tau`` ``(m, n)`` (SI; the ones given)
    with the arm's position, velocity and effort limits; ``deg``: revolute angles and rates in degrees."""
    graphs = [_joint_graph(arm, "joint angles", "q", 0, q, "position", deg)]
    if qd is not None:
        graphs.append(_joint_graph(arm, "joint velocities", "q̇", 1, qd, "velocity", deg))
    if tau is not None:
        graphs.append(_joint_graph(arm, "joint torques", "τ", 2, tau, "effort", deg))
    return graphs


def log_graphs(log: SimulationLog, deg: bool = False, clearance: Clearances | None = None) -> list[Graph]:
    """A simulation's graphs: :func:`arm_graphs` of its q, q̇, τ, then its motor-side torques (N·m at every motor,
    a prismatic joint's too; drawn without limits) if the arm has a drive train, a servo run's tracking error and
    (with electrics) its motors' currents (A) and voltages (V), then the clearance of each pair
    the run checked (``clearance``, :class:`~armlab.collision.model.Clearances` at the log's samples, m; zero drawn
    as the contact line) if it has them."""
    graphs = arm_graphs(log.arm, log.q, log.qd, log.tau, deg)
    if log.tau_motor is not None:
        graphs.append(_joint_graph(log.arm, "motor-side torques", "τm", 2, log.tau_motor, None, deg,
                                   units=["N·m"] * log.arm.n))
    if log.servo is not None:  # a servo run: its tracking error, and its motors' current and voltage
        graphs.append(_joint_graph(log.arm, "tracking error", "q−q_d", 0, log.q - log.q_ref, None, deg))
        for title, symbol, values, unit in (("motor currents", "i", log.current, "A"),
                                            ("winding voltages", "V", log.voltage, "V")):
            if values is not None:
                graphs.append(_joint_graph(log.arm, title, symbol, 2, values, None, deg, units=[unit] * log.arm.n))
    if clearance is not None and clearance.pairs:
        c = np.asarray(clearance.distance, dtype=float).reshape(log.t.size, -1)
        labels = tuple(f"{name} [m]" for name in clearance.names())
        graphs.append(Graph("clearance of each checked pair", "clearance [m]", labels, c, ((-1, "contact", 0.0, 0.0),)))
    return graphs


def _rows(run: NDArray, limit: int) -> NDArray[np.intp]:
    """The samples a graph keeps: every ``stride``-th of each run (at most ``limit`` per run) and each run's last."""
    rows = []
    for k in np.unique(run):
        index = np.nonzero(run == k)[0]
        stride = max(1, int(np.ceil(index.size / limit)))
        rows.append(np.unique(np.concatenate([index[::stride], index[-1:]])))
    return np.concatenate(rows)


def graph_data(t: ArrayLike, run: ArrayLike, graphs: list[Graph], limit: int = MAX_GRAPH_POINTS) -> dict[str, Any]:
    """The page's graph data (JSON-ready): the kept times ``t`` (s), where a new run starts (no line joins two runs)
    and per graph its title, axis label, series and limit lines, values to 6 significant digits."""
    t, run = np.asarray(t, dtype=float), np.asarray(run)
    rows = _rows(run, limit)
    starts = np.nonzero(np.diff(run[rows]))[0] + 1
    for graph in graphs:
        if graph.values.shape[0] != t.size or not np.all(np.isfinite(graph.values)):
            raise ValueError(f"replay: graph {graph.title!r} must be finite with {t.size} rows, "
                             f"got shape {graph.values.shape}")
    return {
        "t": np.round(t[rows], 6).tolist(), "starts": starts.tolist(),
        "panels": [{
            "title": g.title, "ylabel": g.ylabel, "labels": list(g.labels),
            "y": [[float(f"{v:.6g}") for v in column] for column in g.values[rows].T],
            "limits": [{"series": s, "label": label, "low": lo, "high": hi} for s, label, lo, hi in g.limits],
            "notes": list(g.notes),
        } for g in graphs],
    }


#: CSS of the graph column (``GRAPHS_PCT`` and ``BAR_PX`` are filled in by the replay page).
GRAPHS_STYLE = """
#meshcat-pane{width:calc(100vw - GRAPHS_PCTvw) !important}
body > .dg.main{right:GRAPHS_PCTvw !important}
#armlab-graphs{position:fixed;top:0;right:0;width:GRAPHS_PCTvw;height:calc(100vh - BAR_PXpx);box-sizing:border-box;
  display:flex;flex-direction:column;background:#fff;border-left:1px solid #b8bcc4;
  font:12px/1.3 Helvetica,Arial,sans-serif;color:#1d2733;z-index:10;overflow:hidden}
.armlab-panel{flex:1;min-height:0;display:flex;flex-direction:column;padding:3px 6px 0 6px}
.armlab-head{line-height:1.25}
.armlab-head b{margin-right:8px}
.armlab-key{margin-right:8px;white-space:nowrap;display:inline-block}
.armlab-swatch{display:inline-block;width:14px;height:0;border-top:2px solid;vertical-align:middle;margin-right:3px}
.armlab-plot{flex:1;min-height:0;position:relative;cursor:crosshair;touch-action:none}
.armlab-plot canvas{position:absolute;left:0;top:0;width:100%;height:100%}
.armlab-cursor{position:absolute;width:2px;margin-left:-1px;background:#d6007e;pointer-events:none}
"""

#: The graphs' script: ``ARMLAB_GRAPHS(G, toPlayback, seek)`` draws the panels of ``G`` (:func:`graph_data`)
#: into ``#armlab-graphs`` and returns ``move(t)``, which puts every cursor at run time ``t``; a click or drag
#: at run time t calls ``seek(t)``.
GRAPHS_SCRIPT = """
function ARMLAB_GRAPHS(G, seek) {
  const COLORS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"];
  const M = {left: 58, right: 10, top: 6, bottom: 30};
  const root = document.getElementById("armlab-graphs");
  const t0 = G.t[0], t1 = Math.max(G.t[G.t.length - 1], G.t[0] + 1e-9);
  function ticks(lo, hi, count) {
    const raw = (hi - lo) / count, p = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 2.5, 5, 10].map((m) => m * p).find((s) => s >= raw);
    const out = [];
    for (let v = Math.ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step) {
      out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
    }
    return out;
  }
  function label(v) {
    return Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(1) : +v.toPrecision(4) + "";
  }
  const panels = G.panels.map((P, index) => {
    const panel = document.createElement("div");
    panel.className = "armlab-panel";
    const head = document.createElement("div");
    head.className = "armlab-head";
    const key = (color, text, dash) => '<span class="armlab-key"><span class="armlab-swatch" style="border-top:2px ' +
      (dash ? "dashed " : "solid ") + color + '"></span>' + text + "</span>";
    head.innerHTML = "<b>" + P.title + "</b>" +
      P.labels.map((l, j) => key(COLORS[j % COLORS.length], l, false)).join("") +
      P.limits.map((L) => key(L.series < 0 ? "#595959" : COLORS[L.series % COLORS.length], L.label, true)).join("");
    head.title = P.notes.join("\\n");
    if (P.notes.length) head.innerHTML += '<span class="armlab-key" style="color:#666">(' + P.notes.length +
      " limit" + (P.notes.length > 1 ? "s" : "") + " off the scale: hover)</span>";
    const plot = document.createElement("div");
    plot.className = "armlab-plot";
    const canvas = document.createElement("canvas");
    const cursor = document.createElement("div");
    cursor.className = "armlab-cursor";
    plot.append(canvas, cursor);
    panel.append(head, plot);
    root.appendChild(panel);
    let lo = Infinity, hi = -Infinity;
    for (const y of P.y) for (const v of y) { if (v < lo) lo = v; if (v > hi) hi = v; }
    for (const L of P.limits) { lo = Math.min(lo, L.low); hi = Math.max(hi, L.high); }
    const pad = Math.max((hi - lo) * 0.06, Math.abs(hi) * 1e-6, 1e-9);
    const box = {plot, canvas, cursor, lo: lo - pad, hi: hi + pad, last: index === G.panels.length - 1};
    return box;
  });
  function x(box, t) { return M.left + (t - t0) / (t1 - t0) * (box.w - M.left - M.right); }
  function y(box, v) { return M.top + (box.hi - v) / (box.hi - box.lo) * (box.h - M.top - M.bottom); }
  function draw(box, P) {
    const r = window.devicePixelRatio || 1, c = box.canvas;
    box.w = box.plot.clientWidth; box.h = box.plot.clientHeight;
    c.width = Math.round(box.w * r); c.height = Math.round(box.h * r);
    const g = c.getContext("2d");
    g.setTransform(r, 0, 0, r, 0, 0);
    g.clearRect(0, 0, box.w, box.h);
    g.font = "11px Helvetica,Arial,sans-serif"; g.fillStyle = "#1d2733"; g.strokeStyle = "#e3e5e9"; g.lineWidth = 1;
    const bottom = box.h - M.bottom, right = box.w - M.right;
    g.textAlign = "right"; g.textBaseline = "middle";
    for (const v of ticks(box.lo, box.hi, Math.max(2, Math.floor((bottom - M.top) / 28)))) {
      g.beginPath(); g.moveTo(M.left, y(box, v)); g.lineTo(right, y(box, v)); g.stroke();
      g.fillText(label(v), M.left - 4, y(box, v));
    }
    g.textAlign = "center"; g.textBaseline = "top";
    for (const v of ticks(t0, t1, Math.max(2, Math.floor((right - M.left) / 60)))) {
      g.beginPath(); g.moveTo(x(box, v), M.top); g.lineTo(x(box, v), bottom); g.stroke();
      g.fillText(label(v), x(box, v), bottom + 3);
    }
    g.fillText(box.last ? "time t [s]" : "t [s]", (M.left + right) / 2, bottom + 15);
    g.save(); g.translate(11, (M.top + bottom) / 2); g.rotate(-Math.PI / 2); g.textBaseline = "middle";
    g.fillText(P.ylabel, 0, 0); g.restore();
    g.strokeStyle = "#8a9099"; g.strokeRect(M.left, M.top, right - M.left, bottom - M.top);
    g.save(); g.beginPath(); g.rect(M.left, M.top, right - M.left, bottom - M.top); g.clip();
    g.setLineDash([6, 3]); g.lineWidth = 1.2;
    for (const L of P.limits) {
      g.strokeStyle = L.series < 0 ? "#595959" : COLORS[L.series % COLORS.length];
      for (const v of [L.low, L.high]) {
        g.beginPath(); g.moveTo(M.left, y(box, v)); g.lineTo(right, y(box, v)); g.stroke();
      }
    }
    g.setLineDash([]); g.lineWidth = 1.6;
    const cuts = [0, ...G.starts, G.t.length];
    P.y.forEach((values, j) => {
      g.strokeStyle = COLORS[j % COLORS.length];
      for (let s = 0; s + 1 < cuts.length; s++) {
        g.beginPath();
        for (let i = cuts[s]; i < cuts[s + 1]; i++) {
          const px = x(box, G.t[i]), py = y(box, values[i]);
          if (i === cuts[s]) g.moveTo(px, py); else g.lineTo(px, py);
        }
        g.stroke();
      }
    });
    g.restore();
    box.cursor.style.top = M.top + "px"; box.cursor.style.height = (bottom - M.top) + "px";
    c.dataset.x0 = M.left; c.dataset.x1 = right; c.dataset.t0 = t0; c.dataset.t1 = t1;
  }
  let current = t0;
  function move(t) {
    current = t;
    for (const box of panels) box.cursor.style.left = x(box, Math.max(t0, Math.min(t1, t))) + "px";
  }
  function redraw() { panels.forEach((box, k) => draw(box, G.panels[k])); move(current); }
  for (const box of panels) {
    const at = (e) => {
      const rect = box.plot.getBoundingClientRect();
      const f = (e.clientX - rect.left - M.left) / (box.w - M.left - M.right);
      return t0 + Math.max(0, Math.min(1, f)) * (t1 - t0);
    };
    box.plot.addEventListener("pointerdown", (e) => { box.plot.setPointerCapture(e.pointerId); seek(at(e)); });
    box.plot.addEventListener("pointermove", (e) => { if (box.plot.hasPointerCapture(e.pointerId)) seek(at(e)); });
  }
  window.addEventListener("resize", redraw);
  redraw();
  return move;
}
"""
