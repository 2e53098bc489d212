"""Writing a simulation run into its folder: completely or not at all.

:func:`run_folder` is an :class:`~armlab.files.OutputFolder` for a run: made before anything is
simulated (so an unwritable place is an error up front), renamed onto the requested folder only
when every file is written. A previous armlab run in that folder is replaced; any other non-empty
folder is left alone (an error).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from armlab.files import OutputFolder
from armlab.presentation.plots import PLOTS
from armlab.presentation.servo_plots import SERVO_PLOTS

if TYPE_CHECKING:
    from armlab.diagrams.simulate import SimulationLog

__all__ = ["RUN_FILES", "RUN_OUTPUTS", "SERVO_COLUMNS", "csv_header", "run_folder", "write_log_csv", "write_summary"]

#: Files that mark a folder as an armlab run (which ``--out`` may replace) …
RUN_FILES = ("log.csv", "summary.json")
#: … if it holds nothing but the files a run writes.
RUN_OUTPUTS = (*RUN_FILES, "diagram.svg", "diagram_full.svg", "diagram.dot", *PLOTS, "clearance.png", "drives.csv",
               "drives.png", "replay.html", *SERVO_PLOTS)  # clearance.png: when the run checked pairs of links for
# collisions; servo.png, bode.png: a servo run's


#: A servo run's columns of ``log.csv`` by the :class:`~armlab.diagrams.simulate.SimulationLog` field they hold:
#: the torque command (N·m or N), the measured state (rad or m, per s), elastic joints' rotor angles φ and rates
#: (joint side), the motor current (A) and voltage (V), the energies ∫V i, ∫τ q̇, ∫R i² (J).
SERVO_COLUMNS = {"tau_command": ("tau_cmd{}",), "measured": ("q{}_meas", "qd{}_meas"), "rotor": ("phi{}", "phid{}"),
                 "current": ("i{}",), "voltage": ("V{}",), "energy": ("E_el{}", "E_mech{}", "E_cu{}")}


def csv_header(n: int, motor: bool = False, servo: tuple[str, ...] = ()) -> list[str]:
    """Column names of ``log.csv`` for ``n`` joints; ``motor``: with the motor side of a drive train, the motor
    torques ``tau_m1 …`` (N·m) and speeds ``w_m1 …`` (rad/s) after the tool point's columns; ``servo``: a servo
    run's fields logged (keys of :data:`SERVO_COLUMNS`), their columns last, in that table's order."""
    cols = ["t"]
    for fmt in ("q{}_ref", "qd{}_ref", "qdd{}_ref", "q{}", "qd{}", "tau{}"):
        cols += [fmt.format(i) for i in range(1, n + 1)]
    cols += ["x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az"]
    cols += [f"{side}{i}" for side in ("tau_m", "w_m") for i in range(1, n + 1)] if motor else []
    for name in (name for name in SERVO_COLUMNS if name in servo):
        cols += [fmt.format(i) for fmt in SERVO_COLUMNS[name] for i in range(1, n + 1)]
    return cols


def write_log_csv(log: SimulationLog, path: str | Path) -> Path:
    """``log.csv``: a header row, then one row per log sample (:func:`csv_header`), SI units."""
    columns = [log.t, log.q_ref, log.qd_ref, log.qdd_ref, log.q, log.qd, log.tau, log.tool]
    tau_motor, speed = log.tau_motor, log.motor_speed
    if tau_motor is not None and speed is not None:
        columns += [tau_motor, speed]
    servo = tuple(name for name in SERVO_COLUMNS if getattr(log, name) is not None)
    columns += [getattr(log, name) for name in servo]
    np.savetxt(path, np.column_stack(columns), fmt="%.12g", delimiter=",",
               header=",".join(csv_header(log.arm.n, tau_motor is not None, servo)), comments="")
    return Path(path)


def write_summary(summary: dict[str, Any], path: str | Path) -> Path:
    """``summary.json``, indented."""
    Path(path).write_text(json.dumps(summary, indent=2, ensure_ascii=False) + "\n")
    return Path(path)


def _is_run(folder: Path) -> bool:
    names = {p.name for p in folder.iterdir()}
    return set(RUN_FILES) <= names <= set(RUN_OUTPUTS)


def run_folder(out: str | Path) -> OutputFolder:
    """``with run_folder(out) as tmp:`` write a run into ``tmp``; on success it becomes ``out``.

    An existing ``out`` is replaced only if it is empty or an earlier run: :data:`RUN_FILES` and
    nothing but :data:`RUN_OUTPUTS`.
    """
    return OutputFolder(out, _is_run, f"an armlab run folder (one with {' and '.join(RUN_FILES)} and nothing but "
                                      "the files armlab simulate writes)")
