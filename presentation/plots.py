"""Plots of a simulation, drawn like the papers' figures in the reproduction's style
(:mod:`armlab.presentation.figures`: matplotlib, ``Agg`` backend).

* ``joints.png`` — joint angles, velocities (simulated, with the reference dashed) and the
  reference accelerations (paper 000 Figs. 5, 9; paper 001 Figs. 4–6), with each joint's
  position and velocity limits;
* ``torques.png`` — joint torques (paper 000 Figs. 7, 10), with each joint's effort limit;
* ``tool_path.png`` — the tool point's path (paper 000 Figs. 3, 8, 19; paper 001 Fig. 7: x, y, z
  over time), a 3-D path to scale;
* ``tool_motion.png`` — the tool point's position, velocity and acceleration over time (paper 000
  Figs. 18, 28–29).

Each title names the paper figure it reproduces, where the motion is a paper's. A limit is drawn
only where the arm knows it (``JointLimits`` fields that are ``None`` are unknown); one far outside
the motion is written as a note with the share of it the motion uses (:data:`OFF_SCALE`).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armlab.presentation.draw import write_figure
from armlab.presentation.figures import new_figure, set_equal_3d

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from armlab.collision.model import Clearances
    from armlab.diagrams.simulate import SimulationLog
    from armlab.models.arm import Arm

__all__ = ["PLOTS", "clearance_figure", "figures", "save_figures", "write_plots"]

#: File names of the plots :func:`write_plots` writes.
PLOTS = ("joints.png", "torques.png", "tool_path.png", "tool_motion.png")
_LIMIT_STYLE: dict[str, Any] = {"lw": 1.0, "ls": (0, (6, 3)), "alpha": 0.75}


def _title(log: SimulationLog, what: str, figure_key: str) -> str:
    figure = log.motion.figures.get(figure_key)
    where = f"paper {figure}" if figure else "no paper figure"
    return f"{log.arm.name}: {what} ({where})"


def _colors() -> list[str]:
    import matplotlib.pyplot as plt

    return plt.rcParams["axes.prop_cycle"].by_key()["color"]


def _by_run(ax: Axes, log: SimulationLog, x, y, **style) -> None:
    """Plot each run separately so that no line joins two runs."""
    label = style.pop("label", None)
    for k in range(len(log.run_starts)):
        rows = log.run == k
        (line,) = ax.plot(x[rows], y[rows], label=label if k == 0 else None, **style)
        style.setdefault("color", line.get_color())


def _segment_lines(ax: Axes, log: SimulationLog, named: bool = False) -> None:
    """The motion's segment boundaries as dotted lines; ``named``: each segment's label above the panel, at its
    middle (a motion of one segment has neither)."""
    breaks = log.motion.breaks
    for t in breaks[1:-1]:
        ax.axvline(t, color="0.6", lw=0.8, ls=":")
    if named and len(breaks) > 2:
        top = ax.secondary_xaxis("top")
        top.set_xticks((breaks[:-1] + breaks[1:]) / 2, [f"segment {label}" for label in log.motion.labels],
                       fontsize=7, color="0.35")
        top.tick_params(length=0, pad=2)


def _legend(ax: Axes, **options: Any) -> None:
    """The panel's legend outside it, to the right: it covers no curve and no limit line."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, **options)


def limit_values(arm: Arm, kind: str) -> list[tuple[float, float] | None]:
    """Per joint, the (low, high) ``kind`` limit (position, velocity or effort; velocity and effort
    symmetric), or None where the arm does not know it."""
    out: list[tuple[float, float] | None] = []
    for limits in arm.limits:
        if kind == "position":
            out.append(None if limits.lower is None or limits.upper is None
                       else (float(limits.lower), float(limits.upper)))
        else:
            bound = getattr(limits, kind)
            out.append(None if bound is None else (-float(bound), float(bound)))
    return out


#: A limit farther out than this many times the largest value plotted is noted, not drawn (it would
#: squash the curves into a thin band).
OFF_SCALE = 3.0


def limit_groups(arm: Arm, kind: str, values: np.ndarray) -> tuple[list[tuple[list[int], float, float]], list[str]]:
    """The arm's known ``kind`` limits for the curves ``values`` (m, n) of one panel: the ones to draw, as
    (joints sharing the limit, low, high), and notes for those more than :data:`OFF_SCALE` times the largest
    |value| out (with the share of them the motion uses). Used by the PNGs and by the replay's graphs."""
    groups: dict[tuple[float, float], list[int]] = {}
    for i, limits in enumerate(limit_values(arm, kind)):
        if limits is not None:
            groups.setdefault(limits, []).append(i)
    unit = {"position": "", "velocity": "/s", "effort": ""}[kind]
    drawn, notes = [], []
    for (low, high), joints in groups.items():
        units = sorted({("N·m" if arm.revolute[i] else "N") if kind == "effort"
                        else ("rad" if arm.revolute[i] else "m") + unit for i in joints})
        peak = float(np.max(np.abs(values[:, joints])))
        scale = OFF_SCALE * max(peak, float(np.max(np.abs(values))), 1e-12)
        if max(abs(low), abs(high)) <= scale:  # not a bound: a figure's layout (draw the limits, or note them)
            drawn.append((joints, low, high))
        else:
            used = peak / max(abs(low), abs(high))
            notes.append(f"{joint_names(joints)} {kind} limits [{low:.4g}, {high:.4g}] {'|'.join(units)}: off the "
                         f"scale (the motion uses {used:.0%} of them)")
    return drawn, notes


def joint_names(joints: list[int]) -> str:
    """``q1, q3`` for the joints [0, 2]."""
    return ", ".join(f"q{i + 1}" for i in joints)


def _limit_lines(ax: Axes, log: SimulationLog, kind: str, values: np.ndarray) -> list[str]:
    """Each joint's known ``kind`` limits (:func:`limit_groups`) as horizontal lines (joints sharing a limit: one
    grey line); the limits off the scale in a note at the panel's foot. Returns the notes written."""
    colors = _colors()
    drawn, notes = limit_groups(log.arm, kind, values)
    for joints, low, high in drawn:
        color = colors[joints[0] % len(colors)] if len(joints) == 1 else "0.35"
        for k, v in enumerate((low, high)):
            ax.axhline(v, color=color, label=f"{joint_names(joints)} {kind} limit" if k == 0 else None, **_LIMIT_STYLE)
    if notes:  # below the curves: the panel grows downwards by a line per note
        low, high = ax.get_ylim()
        ax.set_ylim(low - 0.09 * len(notes) * (high - low), high)
        ax.text(0.01, 0.02, "\n".join(notes), transform=ax.transAxes, fontsize=7, color="0.3", va="bottom",
                ha="left", zorder=5, bbox={"fc": "white", "ec": "0.8", "alpha": 0.85, "boxstyle": "round,pad=0.2"})
    return notes


def _joint_unit(log: SimulationLog, i: int, order: int) -> str:
    base = "rad" if log.arm.revolute[i] else "m"
    return base + ("", "/s", "/s²")[order]


def _joints(log: SimulationLog) -> Any:
    n = log.arm.n
    fig, axes = new_figure(_title(log, "joint angles, velocities, accelerations", "joints"), nrows=3,
                           size=(9.0, 9.0), sharex=True)
    names = ("position", "velocity", "acceleration")
    simulated = (log.q, log.qd, None)
    reference = (log.q_ref, log.qd_ref, log.qdd_ref)
    colors = _colors()
    for order, ax in enumerate(axes[:, 0]):
        sim = simulated[order]
        for i in range(n):
            color = colors[i % len(colors)]
            label = f"q{i + 1} [{_joint_unit(log, i, order)}]"
            if sim is not None:
                _by_run(ax, log, log.t, sim[:, i], color=color, lw=1.6, label=label)
                _by_run(ax, log, log.t, reference[order][:, i], color="k", lw=0.8, ls="--",
                        label="reference" if i == 0 else None)
            else:
                _by_run(ax, log, log.t, reference[order][:, i], color=color, lw=1.6, label=label)
        _segment_lines(ax, log, named=order == 0)
        if sim is not None:  # position and velocity (no acceleration limits)
            _limit_lines(ax, log, names[order], sim)
        units = sorted({_joint_unit(log, i, order) for i in range(n)})
        shown = "simulated (reference dashed)" if sim is not None else "reference"
        ax.set_ylabel(f"joint {names[order]} [{' | '.join(units)}]")
        ax.set_title(f"{names[order]}: {shown}", loc="left", fontsize=9)
        _legend(ax)
    axes[-1, 0].set_xlabel("time t [s]")
    return fig


def _torques(log: SimulationLog) -> Any:
    fig, ax = new_figure(_title(log, f"joint torques, {log.mode.replace('_', ' ')}", "torques"), size=(9.0, 4.5))
    colors = _colors()
    for i in range(log.arm.n):
        unit = "N·m" if log.arm.revolute[i] else "N"
        _by_run(ax, log, log.t, log.tau[:, i], lw=1.6, label=f"τ{i + 1} [{unit}]", color=colors[i % len(colors)])
    _segment_lines(ax, log, named=True)
    _limit_lines(ax, log, "effort", log.tau)
    units = sorted({"N·m" if r else "N" for r in log.arm.revolute})
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(f"joint torque / force [{' | '.join(units)}]")
    _legend(ax)
    return fig


def _ends(ax: Axes, p: np.ndarray) -> None:
    """Start and end markers, the start larger and drawn first, so both show when the path is closed."""
    ax.plot(*(p[:1].T), "o", color="#2e8b57", ms=10, label="start", zorder=5)
    ax.plot(*(p[-1:].T), "s", color="#c0392b", ms=5, label="end", zorder=6)


def _tool_path(log: SimulationLog) -> Any:
    p = log.tool[:, :3]
    planar = np.ptp(p[:, 2]) < 1e-9
    fig, axes = new_figure(_title(log, f"path of tool point {log.arm.tool_name}", "path"), ncols=2,
                           size=(11.0, 5.0))
    ax, ax2 = axes[0]
    if planar:
        _by_run(ax, log, p[:, 0], p[:, 1], lw=1.6, label="tool point")
        _ends(ax, p[:, :2])
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        centre, half = (p[:, :2].max(axis=0) + p[:, :2].min(axis=0)) / 2, max(float(np.ptp(p[:, :2])) / 2, 1e-3)
        ax.set_xlim(centre[0] - 1.1 * half, centre[0] + 1.1 * half)  # a tool that stands still: a 2 mm window
        ax.set_ylim(centre[1] - 1.1 * half, centre[1] + 1.1 * half)
        ax.set_aspect("equal", adjustable="box")
    else:
        spec = ax.get_subplotspec()
        ax.remove()
        ax = fig.add_subplot(spec, projection="3d")
        for k in range(len(log.run_starts)):
            rows = log.run == k
            ax.plot(p[rows, 0], p[rows, 1], p[rows, 2], lw=1.4, color=_colors()[0],
                    label="tool point" if k == 0 else None)
        _ends(ax, p)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        set_equal_3d(ax, p)
        from matplotlib.ticker import MaxNLocator

        for axis in (ax.xaxis, ax.yaxis, ax.zaxis):  # tick labels that do not run into each other
            axis.set_major_locator(MaxNLocator(4))
    ax.legend()
    for j, axis in enumerate("xyz"):
        _by_run(ax2, log, log.t, p[:, j], lw=1.6, label=f"{axis} [m]")
    _segment_lines(ax2, log, named=True)
    ax2.set_xlabel("time t [s]")
    ax2.set_ylabel("tool point position [m]")
    ax2.set_title("x, y, z of the tool point over time", fontsize=9)
    ax2.legend()
    return fig


def _tool_motion(log: SimulationLog) -> Any:
    fig, axes = new_figure(_title(log, f"tool point {log.arm.tool_name} in the world frame", "path"), nrows=3,
                           size=(9.0, 9.0), sharex=True)
    for row, (name, unit) in enumerate((("position", "m"), ("velocity", "m/s"), ("acceleration", "m/s²"))):
        ax = axes[row, 0]
        for j, axis in enumerate("xyz"):
            _by_run(ax, log, log.t, log.tool[:, 3 * row + j], lw=1.6, label=axis)
        _segment_lines(ax, log, named=row == 0)
        ax.set_ylabel(f"tool {name} [{unit}]")
        _legend(ax)
    axes[-1, 0].set_xlabel("time t [s]")
    return fig


def figures(log: SimulationLog) -> dict[str, Any]:
    """The matplotlib figures of :data:`PLOTS`, by file name (the caller closes them)."""
    return {name: draw(log) for name, draw in zip(PLOTS, (_joints, _torques, _tool_path, _tool_motion), strict=True)}


def save_figures(shown: Mapping[str, Any], folder: str | Path) -> list[Path]:
    """Write each ``file name → figure`` of ``shown`` into ``folder`` (made if missing) in the format of its suffix,
    at the reproduction's resolution, each file completely or not at all
    (:func:`~armlab.presentation.draw.write_figure`);
    returns their paths."""
    return [write_figure(fig, Path(folder) / name) for name, fig in shown.items()]


def write_plots(log: SimulationLog, folder: str | Path) -> list[Path]:
    """Write :data:`PLOTS` into ``folder`` (PNG, the reproduction's resolution, :func:`save_figures`); returns their
    paths."""
    import matplotlib.pyplot as plt

    shown = figures(log)
    try:
        return save_figures(shown, folder)
    finally:
        for fig in shown.values():
            plt.close(fig)


def clearance_figure(arm: Arm, t: NDArray[np.float64], found: Clearances) -> Any:
    """Each pair's clearance (mm) over the run, the contact line at 0 (a matplotlib figure; the caller closes it)."""
    fig, ax = new_figure(f"{arm.name}: clearance of each checked pair along the run (below 0: in contact)",
                         size=(8.0, 4.8))
    order = np.argsort(found.distance.min(axis=0)) if len(t) else np.arange(len(found.pairs))
    for j in order:
        ax.plot(t, found.distance[:, j] * 1e3, lw=1.2, label=found.names()[j])
    ax.axhline(0.0, color="black", lw=0.8, ls="--", label="contact (clearance 0)")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("clearance [mm]")
    ax.legend(fontsize=7, ncols=2, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return fig
