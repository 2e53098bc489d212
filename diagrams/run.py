"""A simulation run as the Python API and ``armlab simulate`` hand it over: arrays, summary, checks, files.

:class:`Run` wraps the :class:`~armlab.diagrams.simulate.SimulationLog` of one simulation with what
a user asks of it next: the summary (``summary.json``), the limit violations and whether the run
diverged (:mod:`armlab.diagrams.drives`), the drive-sizing table, and :meth:`Run.save` writing
every output into a folder completely or not at all.
"""

from __future__ import annotations

import html
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armlab.collision.clearance import motion_clearance
from armlab.diagrams.drives import (
    DIVERGENCE_TOLERANCE,
    divergence,
    drive_table,
    drives_figure,
    format_violation,
    limit_violations,
    write_drives_csv,
)
from armlab.diagrams.servo import LoopResponse, frequency_response
from armlab.diagrams.simulate import SimulationOptions, summarize
from armlab.presentation.figures import Figures
from armlab.presentation.graphviz import fig6_dot, write_pictures
from armlab.presentation.output import run_folder, write_log_csv, write_summary
from armlab.presentation.plots import clearance_figure, figures, save_figures
from armlab.presentation.replay import log_page, replay_log
from armlab.presentation.servo_plots import bode_figure, servo_figure
from armlab.values import shown as shown_value

if TYPE_CHECKING:
    from armlab.collision.model import Clearances
    from armlab.collision.scene import Scene
    from armlab.diagrams.simulate import SimulationLog

__all__ = ["Run"]


@dataclass(repr=False)
class Run:
    """One simulated motion. Arrays are one row per log sample: ``t`` ``(m,)``, joints ``(m, n)`` (SI units).

    ``run.plot()`` gives its figures, ``run.save(folder)`` writes every output (the replay, the plots, the
    log, the summary); in Jupyter a run shows its summary and its 3-D replay with graphs.

    ``summary`` is ``summary.json``: the run's maxima (torques N·m or N, tracking errors rad or m, power W),
    per segment, the setup, and ``limit_violations`` (a list, empty when none), ``diverged`` and
    ``divergence`` (where the tracking error first passed ``divergence_tolerance``); ``collisions`` (the pairs
    that touched, each with its first time and deepest penetration, m), ``min_clearance`` (each checked pair's
    smallest clearance, m, and when) and ``collision_check`` (what was checked: the arm against itself and the
    obstacles of ``scene``; an arm without collision geometry is said to be not checked). A servo run's summary has
    ``servo`` (:func:`~armlab.diagrams.simulate.servo_stats`); ``options`` are the run's (what
    :meth:`frequency_response` linearises).
    """

    log: SimulationLog
    divergence_tolerance: float = DIVERGENCE_TOLERANCE
    scene: Scene | None = None
    options: SimulationOptions | None = None
    summary: dict[str, Any] = field(init=False)
    clearance: Clearances | None = field(init=False)
    _replay: str | None = field(init=False, default=None)  # the inline replay, made when Jupyter first shows it

    def __post_init__(self) -> None:
        summary = summarize(self.log)
        summary["tracking_error_units"] = summary["joint_units"]
        summary["limit_violations"] = limit_violations(self.log)
        left = divergence(self.log, self.divergence_tolerance)
        summary["diverged"] = left is not None
        summary["divergence"] = left
        summary["drives"] = drive_table(self.log)
        checked, self.clearance = motion_clearance(self.log.arm, self.log.t, self.log.q, self.scene)
        summary.update(checked)
        self.summary = summary

    # ------------------------------------------------------------------ the arrays
    @property
    def t(self) -> NDArray[np.float64]:
        """Sample times, s ``(m,)``; a join between runs appears twice."""
        return self.log.t

    @property
    def q(self) -> NDArray[np.float64]:
        """Simulated joint positions ``(m, n)``, rad or m."""
        return self.log.q

    @property
    def qd(self) -> NDArray[np.float64]:
        """Simulated joint velocities ``(m, n)``, rad/s or m/s."""
        return self.log.qd

    @property
    def tau(self) -> NDArray[np.float64]:
        """Joint torques (forces) the controller applied ``(m, n)``, N·m or N."""
        return self.log.tau

    @property
    def q_ref(self) -> NDArray[np.float64]:
        """Reference joint positions ``(m, n)``."""
        return self.log.q_ref

    @property
    def qd_ref(self) -> NDArray[np.float64]:
        """Reference joint velocities ``(m, n)``."""
        return self.log.qd_ref

    @property
    def qdd_ref(self) -> NDArray[np.float64]:
        """Reference joint accelerations ``(m, n)``, rad/s² or m/s²."""
        return self.log.qdd_ref

    @property
    def tool(self) -> NDArray[np.float64]:
        """The tool point ``(m, 9)``: x y z (m), vx vy vz (m/s), ax ay az (m/s²) in the world frame."""
        return self.log.tool

    # ------------------------------------------------------------------ the checks
    @property
    def violations(self) -> list[dict[str, Any]]:
        """The limits the run passed (see :func:`~armlab.diagrams.drives.limit_violations`)."""
        return self.summary["limit_violations"]

    @property
    def collisions(self) -> list[dict[str, Any]]:
        """The pairs that touched along the run (see :func:`~armlab.collision.clearance.collisions`); empty when
        none or not checked (``summary["collision_check"]`` says which)."""
        return self.summary["collisions"] or []

    @property
    def diverged(self) -> bool:
        """True if the tracking error passed :attr:`divergence_tolerance` (the run left its reference)."""
        return self.summary["diverged"]

    @property
    def drives(self) -> list[dict[str, Any]]:
        """Per joint peak |τ|, RMS τ, peak |q̇|, peak power and the effort/velocity limits."""
        return self.summary["drives"]

    # ------------------------------------------------------------------ what a person sees
    def __repr__(self) -> str:
        log = self.log
        drive = max(self.drives, key=lambda d: d["peak_torque"])
        checks = f"{len(self.violations)} limit violation(s)" if self.violations else "within limits"
        return (f"<Run {log.arm.name}: {log.motion.description}; {log.t[-1] - log.t[0]:g} s, {log.t.size} samples, "
                f"{log.mode}; peak |τ| {drive['peak_torque']:.4g} {drive['torque_unit']} ({drive['joint']}); "
                f"{checks}{', DIVERGED' if self.diverged else ''}>")

    def _repr_html_(self) -> str:
        """Jupyter's view: the summary (one row per joint: peak and RMS τ, peak q̇, limits), the limit violations,
        and the replay with its graphs inline (an iframe of the self-contained page: no server needed)."""
        if self._replay is None:
            self._replay = log_page(self.log, clearance=self.clearance, scene=self.scene)

        def cell(v: Any, unit: str) -> str:
            return "—" if v is None else f"{v:.4g} {unit}"

        rows = "".join(
            f"<tr><td>{html.escape(d['joint'])}</td><td>{cell(d['peak_torque'], d['torque_unit'])}</td>"
            f"<td>{cell(d['rms_torque'], d['torque_unit'])}</td><td>{cell(d['peak_speed'], d['speed_unit'])}</td>"
            f"<td>{cell(d['effort_limit'], d['torque_unit'])}</td><td>{cell(d['velocity_limit'], d['speed_unit'])}</td>"
            "</tr>" for d in self.drives)
        problems = [format_violation(v) for v in self.violations]
        if self.diverged:
            problems.append("the run left its reference (diverged)")
        checks = "".join(f"<li>{html.escape(p)}</li>" for p in problems) or "<li>within every known limit</li>"
        return (f"<div><b>{html.escape(repr(self)[1:-1])}</b>"
                "<table><tr><th>joint</th><th>peak |τ|</th><th>RMS τ</th><th>peak |q̇|</th><th>effort limit</th>"
                f"<th>speed limit</th></tr>{rows}</table><ul>{checks}</ul>"
                f'<iframe srcdoc="{html.escape(self._replay, quote=True)}" style="width:100%;height:560px;'
                'border:1px solid #ccc" title="3-D replay with graphs"></iframe></div>')

    def frequency_response(self, q: Any = None, frequency: Any = None) -> LoopResponse:
        """The run's servo loop, continuous, linearised about the pose ``q`` at rest (default: the motion's start)
        by Drake's ``Linearize``: q_i/q_d,i per joint at ``frequency`` (Hz; default 0.01 Hz … 1 kHz), its −3 dB
        bandwidth and the tuning rule's (:func:`armlab.diagrams.servo.frequency_response`)."""
        options = SimulationOptions() if self.options is None else self.options
        pose = self.log.motion.segments[0].q_start if q is None else q
        return frequency_response(self.log.arm, options, pose, frequency)

    # ------------------------------------------------------------------ the files
    def plot(self, folder: str | Path | None = None) -> Figures:
        """The run's matplotlib figures by file name: joints, torques, tool path and motion (:data:`PLOTS`),
        ``clearance.png`` (when the run checked pairs for collisions), ``drives.png`` and, for a servo run,
        ``servo.png`` and ``bode.png`` (:mod:`armlab.presentation.servo_plots`: its loop linearised about the start
        pose); written into ``folder`` (PNG) only if one is given. A :class:`~armlab.presentation.figures.Figures`
        (a ``dict``): as a Jupyter cell's value it draws them. Close them with ``plt.close``."""
        shown = Figures({**figures(self.log), "drives.png": drives_figure(self.log)})
        if self.clearance is not None and self.clearance.pairs:
            shown["clearance.png"] = clearance_figure(self.log.arm, self.log.t, self.clearance)
        if self.log.servo is not None:
            shown["servo.png"] = servo_figure(self.log)
            response = self.frequency_response()
            rate = self.log.servo["rate_hz"]
            shown["bode.png"] = bode_figure(
                f"{self.log.arm.name}: {self.log.servo['controller']} position loop linearised at the start pose"
                + ("" if rate is None else f" (continuous; the {rate:g} Hz samples add their lag)"),
                self.log.arm.joint_names, response.frequency, response.response, response.bandwidth, response.design)
        if folder is not None:
            save_figures(shown, folder)
        return shown

    def save(self, out: str | Path, deg: bool = False) -> list[str]:
        """Write every output of the run (:meth:`write`) into folder ``out``, completely or not at all.

        ``out`` may be new, empty or an earlier run (which is replaced); ``ValueError`` otherwise.
        Returns the names written; ``deg``: the replay shows revolute angles in degrees. ``TypeError`` naming
        ``out`` if it is not a folder's name (a ``str`` or a path).
        """
        if not isinstance(out, str | os.PathLike):
            raise TypeError(f"out: expected a folder's name (a str or a pathlib.Path), got {type(out).__name__} "
                            f"{shown_value(out)}")
        with run_folder(out) as folder:
            return self.write(folder, deg)

    def write(self, folder: str | Path, deg: bool = False) -> list[str]:
        """Write every output of the run into the existing ``folder``; the names written.

        ``log.csv``, ``summary.json``, ``drives.csv``, ``diagram.svg`` (the Fig. 6 view), ``diagram_full.svg``
        and ``diagram.dot`` (Drake's whole graph), the plots, ``drives.png`` and ``replay.html`` (the run as a
        3-D animation with its time slider and a readout of t, q — in degrees with ``deg`` — and τ). The two
        SVGs need graphviz's ``dot``: without it they are skipped with a
        :class:`~armlab.presentation.graphviz.DotMissingWarning`, and everything else is written.
        """
        log, folder = self.log, Path(folder)
        write_log_csv(log, folder / "log.csv")
        write_summary(self.summary, folder / "summary.json")
        (folder / "diagram.dot").write_text(log.diagram_dot)
        pictures = write_pictures({"diagram.svg": fig6_dot(log.diagram_dot), "diagram_full.svg": log.diagram_dot},
                                  folder)
        drives = write_drives_csv(log, folder / "drives.csv")
        # lazy: matplotlib is loaded by what plots (armlab._lazy)
        import matplotlib.pyplot as plt

        shown = self.plot(folder)  # the plots, clearance.png (pairs checked) and drives.png, written
        for fig in shown.values():
            plt.close(fig)
        replay_log(log, folder / "replay.html", deg=deg, clearance=self.clearance, scene=self.scene)
        return ["log.csv", "summary.json", *pictures, "diagram.dot", *(name for name in shown if name != "drives.png"),
                drives.name, "drives.png", "replay.html"]
