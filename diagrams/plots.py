"""Plots of a simulation, drawn like the papers' figures (matplotlib, ``Agg`` backend).

* ``joints.png`` — joint angles, velocities, accelerations, reference and simulated (paper 000
  Figs. 5, 9; paper 001 Figs. 4–6);
* ``torques.png`` — joint torques (paper 000 Figs. 7, 10);
* ``tool_path.png`` — the tool point's path (paper 000 Figs. 3, 8, 19; paper 001 Fig. 7: x, y, z
  over time);
* ``tool_motion.png`` — the tool point's position, velocity and acceleration over time (paper 000
  Figs. 18, 28–29).

Each title names the paper figure it reproduces, where the motion is a paper's.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from armlab.diagrams.simulate import SimulationLog

__all__ = ["PLOTS", "write_plots"]

#: File names of the plots :func:`write_plots` writes.
PLOTS = ("joints.png", "torques.png", "tool_path.png", "tool_motion.png")


def _title(log: SimulationLog, what: str, figure_key: str) -> str:
    figure = log.motion.figures.get(figure_key)
    where = f"paper {figure}" if figure else "no paper figure"
    return f"{log.arm.name}: {what} ({where})"


def _by_run(ax: Axes, log: SimulationLog, x, y, **style) -> None:
    """Plot each run separately so that no line joins two runs."""
    label = style.pop("label", None)
    for k in range(len(log.run_starts)):
        rows = log.run == k
        (line,) = ax.plot(x[rows], y[rows], label=label if k == 0 else None, **style)
        style.setdefault("color", line.get_color())


def _segment_lines(ax: Axes, log: SimulationLog) -> None:
    for t in log.motion.breaks[1:-1]:
        ax.axvline(t, color="0.7", lw=0.8, ls=":")


def _limit_lines(ax: Axes, log: SimulationLog, kind: str, colors: list[str]) -> None:
    """Dashed lines at each joint's limits from ``arm.limits`` (``kind``: position, velocity or effort); an
    unknown limit (None) is not drawn."""
    for i, limits in enumerate(log.arm.limits):
        if kind == "position":
            values = () if limits.lower is None else (limits.lower, limits.upper)
        else:
            bound = getattr(limits, kind)
            values = () if bound is None else (-bound, bound)
        for k, v in enumerate(values):
            ax.axhline(v, color=colors[i % len(colors)], lw=0.9, ls="-.", alpha=0.7,
                       label=f"q{i + 1} {kind} limit" if k == 0 else None)


def _joint_unit(log: SimulationLog, i: int, order: int) -> str:
    base = "rad" if log.arm.revolute[i] else "m"
    return base + ("", "/s", "/s²")[order]


def _joints(log: SimulationLog, path: Path) -> None:
    import matplotlib.pyplot as plt

    n = log.arm.n
    fig, axes = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    names = ("position", "velocity", "acceleration")
    simulated = (log.q, log.qd, None)
    reference = (log.q_ref, log.qd_ref, log.qdd_ref)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for order, ax in enumerate(axes):
        for i in range(n):
            color = colors[i % len(colors)]
            label = f"q{i + 1} [{_joint_unit(log, i, order)}]"
            if simulated[order] is not None:
                _by_run(ax, log, log.t, simulated[order][:, i], color=color, lw=1.6, label=label)
                _by_run(ax, log, log.t, reference[order][:, i], color="k", lw=0.8, ls="--",
                        label="reference" if i == 0 else None)
            else:
                _by_run(ax, log, log.t, reference[order][:, i], color=color, lw=1.6, label=label)
        _segment_lines(ax, log)
        if order < 2:
            _limit_lines(ax, log, ("position", "velocity")[order], colors)
        units = sorted({_joint_unit(log, i, order) for i in range(n)})
        which = " (reference)" if simulated[order] is None else ""
        ax.set_ylabel(f"joint {names[order]}{which} [{' | '.join(units)}]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, ncol=min(n + 1, 4), loc="best")
    axes[0].set_title(_title(log, "joint angles, velocities, accelerations", "joints"))
    axes[-1].set_xlabel("time t [s]")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _torques(log: SimulationLog, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 4.5))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i in range(log.arm.n):
        unit = "N·m" if log.arm.revolute[i] else "N"
        _by_run(ax, log, log.t, log.tau[:, i], lw=1.6, label=f"τ{i + 1} [{unit}]", color=colors[i % len(colors)])
    _segment_lines(ax, log)
    _limit_lines(ax, log, "effort", colors)
    units = sorted({"N·m" if r else "N" for r in log.arm.revolute})
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(f"joint torque / force [{' | '.join(units)}]")
    ax.set_title(_title(log, f"joint torques, {log.mode.replace('_', ' ')}", "torques"))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _tool_path(log: SimulationLog, path: Path) -> None:
    import matplotlib.pyplot as plt

    p = log.tool[:, :3]
    planar = np.ptp(p[:, 2]) < 1e-9
    fig = plt.figure(figsize=(11, 5))
    if planar:
        ax = fig.add_subplot(1, 2, 1)
        _by_run(ax, log, p[:, 0], p[:, 1], lw=1.6, label="tool point")
        ax.plot(p[0, 0], p[0, 1], "go", ms=9, label="start")  # under the end marker: both seen on a closed path
        ax.plot(p[-1, 0], p[-1, 1], "rs", ms=5, label="end")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
    else:
        ax = fig.add_subplot(1, 2, 1, projection="3d")
        for k in range(len(log.run_starts)):
            rows = log.run == k
            ax.plot(p[rows, 0], p[rows, 1], p[rows, 2], lw=1.2, label="tool point" if k == 0 else None)
        ax.plot([p[0, 0]], [p[0, 1]], [p[0, 2]], "go", ms=9, label="start")
        ax.plot([p[-1, 0]], [p[-1, 1]], [p[-1, 2]], "rs", ms=5, label="end")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        from armlab.scripts.figures import set_equal_3d

        set_equal_3d(ax, p)
    ax.legend(fontsize=8)
    ax.set_title(_title(log, f"path of tool point {log.arm.tool_name}", "path"))
    ax2 = fig.add_subplot(1, 2, 2)
    for j, axis in enumerate("xyz"):
        _by_run(ax2, log, log.t, p[:, j], lw=1.6, label=f"{axis} [m]")
    _segment_lines(ax2, log)
    ax2.set_xlabel("time t [s]")
    ax2.set_ylabel("tool point position [m]")
    ax2.set_title("x, y, z of the tool point over time")
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _tool_motion(log: SimulationLog, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    for row, (name, unit) in enumerate((("position", "m"), ("velocity", "m/s"), ("acceleration", "m/s²"))):
        ax = axes[row]
        for j, axis in enumerate("xyz"):
            _by_run(ax, log, log.t, log.tool[:, 3 * row + j], lw=1.6, label=axis)
        _segment_lines(ax, log)
        ax.set_ylabel(f"tool {name} [{unit}]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, ncol=3)
    axes[0].set_title(_title(log, f"tool point {log.arm.tool_name} in the world frame", "path"))
    axes[-1].set_xlabel("time t [s]")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_plots(log: SimulationLog, folder: str | Path) -> list[Path]:
    """Write :data:`PLOTS` into ``folder``; returns their paths."""
    import matplotlib

    matplotlib.use("Agg")
    folder = Path(folder)
    paths = [folder / name for name in PLOTS]
    for draw, path in zip((_joints, _torques, _tool_path, _tool_motion), paths, strict=True):
        draw(log, path)
    return paths
