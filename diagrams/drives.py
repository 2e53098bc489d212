"""What a run asks of the arm's drives: limits checked, divergence found, drives sized.

* :func:`limit_violations` — every joint's position, velocity and effort limit checked along
  the run, for the reference and the simulated values: one entry per (joint, quantity, source)
  whose peak passes its limit, with the first time it does.
* :func:`divergence` — the first time the tracking error |q − q_d| passes a threshold (an
  open-loop run, or gains too low, leaving the reference), or ``None``.
* :func:`drive_table`, :func:`write_drives_csv` and :func:`drives_figure` — per joint peak |τ|, RMS τ, peak |q̇| and peak
  mechanical power |τ q̇|, against the effort and velocity limits: ``drives.csv`` and
  ``drives.png`` (each joint's torque–speed operating points inside its limit box, the picture an
  engineer takes to a motor catalogue).

Limits come from the arm (:class:`~armlab.models.write_urdf.JointLimits`); a limit the arm's file does
not give (``None``) is not checked.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armlab.files import write_csv
from armlab.limits import check_positive

if TYPE_CHECKING:
    from armlab.diagrams.simulate import SimulationLog

__all__ = [
    "DIVERGENCE_TOLERANCE",
    "beyond",
    "check_tolerance",
    "divergence",
    "drive_table",
    "drives_figure",
    "format_violation",
    "limit_violations",
    "torque_stats",
    "write_drives_csv",
]

#: Tracking error (rad for revolute joints, m for prismatic ones) past which a run has left its
#: reference: far above what the computed-torque loop leaves (≤ 1e-6 at the default accuracy).
DIVERGENCE_TOLERANCE = 1e-2

#: Slack (relative to the limit) under which a value on its limit counts as within it.
_SLACK = 1e-9


def _units(log: SimulationLog) -> dict[str, list[str]]:
    revolute = log.arm.revolute
    return {
        "position": ["rad" if r else "m" for r in revolute],
        "velocity": ["rad/s" if r else "m/s" for r in revolute],
        "effort": ["N·m" if r else "N" for r in revolute],
    }


def beyond(values: NDArray, bound: NDArray | float) -> NDArray[np.bool_]:
    """Where ``values`` pass ``bound`` (upward: values > bound) by more than the slack 1e-9·max(1, |bound|): the one
    rule by which a computed value on its bound counts as within it (limits, saturations)."""
    bound = np.asarray(bound, dtype=float)
    return values > bound + _SLACK * np.maximum(1.0, np.abs(bound))


def _first_exceeding(t: NDArray, values: NDArray, lower: float, upper: float) -> tuple[float, float, float] | None:
    """(peak value past the limit, the limit it passes, first time) for samples outside [lower, upper]."""
    above = beyond(values, upper)
    below = beyond(-values, -lower)
    if not (above.any() or below.any()):
        return None
    first = float(t[np.argmax(above | below)])
    over_upper = float(values.max() - upper) if above.any() else -np.inf
    under_lower = float(lower - values.min()) if below.any() else -np.inf
    if over_upper >= under_lower:
        return float(values.max()), upper, first
    return float(values.min()), lower, first


def limit_violations(log: SimulationLog) -> list[dict[str, Any]]:
    """Every passed limit: ``[{"joint", "quantity", "source", "peak", "limit", "unit", "first_time"}]``.

    ``quantity`` is ``"position"`` (against [lower, upper]), ``"velocity"`` (|q̇| against the velocity
    limit) or ``"effort"`` (|τ| against the effort limit); ``source`` is ``"reference"`` (the motion
    asked for it) or ``"simulated"`` (the arm did it). ``peak`` is the signed extreme value, ``limit``
    the bound it passes, ``first_time`` the first sample time (s) outside. Empty when none.
    """
    units = _units(log)
    out = []
    for i, (name, lim) in enumerate(zip(log.arm.joint_names, log.arm.limits, strict=True)):
        checks: list[tuple[str, str, NDArray, float, float]] = []
        if lim.lower is not None and lim.upper is not None:
            checks += [("position", "reference", log.q_ref[:, i], lim.lower, lim.upper),
                       ("position", "simulated", log.q[:, i], lim.lower, lim.upper)]
        if lim.velocity is not None:
            checks += [("velocity", "reference", log.qd_ref[:, i], -lim.velocity, lim.velocity),
                       ("velocity", "simulated", log.qd[:, i], -lim.velocity, lim.velocity)]
        if lim.effort is not None:
            checks.append(("effort", "simulated", log.tau[:, i], -lim.effort, lim.effort))
        for quantity, source, values, lower, upper in checks:
            found = _first_exceeding(log.t, values, lower, upper)
            if found is not None:
                peak, limit, first = found
                out.append({"joint": name, "quantity": quantity, "source": source, "peak": peak, "limit": limit,
                            "unit": units[quantity][i], "first_time": first})
    return out


def format_violation(v: dict[str, Any]) -> str:
    """One line for a violation: joint, quantity, peak, limit, first time, each with its unit."""
    return (f"{v['joint']}: {v['source']} {v['quantity']} reaches {v['peak']:.6g} {v['unit']}, past its limit "
            f"{v['limit']:.6g} {v['unit']}, first at t = {v['first_time']:.4g} s")


def check_tolerance(tolerance: float) -> float:
    """The divergence tolerance (rad or m) as a float; ``ValueError`` unless positive and finite."""
    return check_positive(tolerance, "divergence tolerance", "", "give a positive finite tracking error (rad or m)")


def divergence(log: SimulationLog, tolerance: float = DIVERGENCE_TOLERANCE) -> dict[str, Any] | None:
    """Where the run first left its reference: ``{"joint", "time", "max_error", "tolerance", "unit"}``, or None.

    ``time`` is the first sample time (s) at which a joint's tracking error |q − q_d| exceeds
    ``tolerance`` (rad or m), ``joint`` the joint whose error is largest then; ``max_error`` the
    largest tracking error of the run on that joint.
    """
    tolerance = check_tolerance(tolerance)
    error = np.abs(log.q - log.q_ref)
    error = np.where(np.isfinite(error), error, np.inf)  # a NaN state has left the reference too
    outside = error > tolerance
    if not outside.any():
        return None
    first = int(np.argmax(outside.any(axis=1)))
    joint = int(np.argmax(error[first]))
    return {"joint": log.arm.joint_names[joint], "time": float(log.t[first]),
            "max_error": float(error[:, joint].max()), "tolerance": tolerance,
            "unit": _units(log)["position"][joint]}


def torque_stats(tau: NDArray[np.float64], qd: NDArray[np.float64]) -> dict[str, Any]:
    """Per joint peak |τ| and RMS τ (N·m or N, ``(n,)``) and the peak mechanical power max_t |Σ τ_i q̇_i| (W) of
    torques ``tau`` and rates ``qd`` sampled along a motion ``(m, n)``."""
    return {"max_abs_torque": np.max(np.abs(tau), axis=0), "rms_torque": np.sqrt(np.mean(tau**2, axis=0)),
            "peak_power": float(np.max(np.abs(np.sum(tau * qd, axis=1))))}


def drive_table(log: SimulationLog) -> list[dict[str, Any]]:
    """Per joint: peak |τ|, RMS τ, peak |q̇|, peak |τ q̇| (W) and the effort and velocity limits (None: unknown);
    with a drive train, its motor side too: the gear ratio, peak |τ_m| and RMS τ_m (N·m), peak |ω_m| (rad/s)."""
    return _drive_rows(log, log.tau_motor, log.motor_speed)


def _drive_rows(log: SimulationLog, tau_motor: NDArray[np.float64] | None,
                speed: NDArray[np.float64] | None) -> list[dict[str, Any]]:
    """:func:`drive_table` of the log's motor torques ``tau_motor`` and speeds ``speed`` ``(m, n)`` (``None``:
    ideal drives), evaluated once by the caller."""
    units = _units(log)
    joint = torque_stats(log.tau, log.qd)
    power = np.abs(log.tau * log.qd)
    rows = [{
        "joint": name,
        "peak_torque": float(joint["max_abs_torque"][i]),
        "rms_torque": float(joint["rms_torque"][i]),
        "torque_unit": units["effort"][i],
        "peak_speed": float(np.max(np.abs(log.qd[:, i]))),
        "speed_unit": units["velocity"][i],
        "peak_power": float(np.max(power[:, i])),
        "effort_limit": lim.effort,
        "velocity_limit": lim.velocity,
    } for i, (name, lim) in enumerate(zip(log.arm.joint_names, log.arm.limits, strict=True))]
    drives = log.arm.drives
    if drives is not None and tau_motor is not None and speed is not None:
        motor = torque_stats(tau_motor, speed)
        for i, row in enumerate(rows):
            row.update(gear_ratio=float(drives.gear_ratio[i]), peak_motor_torque=float(motor["max_abs_torque"][i]),
                       rms_motor_torque=float(motor["rms_torque"][i]),
                       peak_motor_speed=float(np.max(np.abs(speed[:, i]))))
    return rows


def write_drives_csv(log: SimulationLog, path: str | Path) -> Path:
    """``drives.csv``: :func:`drive_table`, one row per joint, empty cells for unknown limits."""
    rows = drive_table(log)
    return write_csv(path, list(rows[0]), [list(row.values()) for row in rows])


#: A value below this share of the largest of its kind (or of 1 in its unit) is round-off: printed as 0.
ROUND_OFF = 1e-9


def _value(value: float, largest: float) -> str:
    """``value`` to 4 significant digits, or ``0`` when it is round-off (:data:`ROUND_OFF` of ``largest``)."""
    return "0" if abs(value) <= ROUND_OFF * max(largest, 1.0) else f"{value:.4g}"


def drives_figure(log: SimulationLog) -> Any:
    """Each joint's torque against its speed along the run, inside its effort/speed limit box, with its peak and
    RMS points (a matplotlib figure; the caller closes it)."""
    # lazy: armlab --help loads armlab.diagrams.drives but not this (start-up time)
    from armlab.presentation.figures import new_figure

    tau_motor, motor_speed = log.tau_motor, log.motor_speed  # evaluated once, for the table and the panels
    rows = _drive_rows(log, tau_motor, motor_speed)
    n = log.arm.n
    cols = min(n, 3)
    per_side = (n + cols - 1) // cols  # rows of panels per side
    sides = 1 if tau_motor is None else 2
    title = f"{log.arm.name}: drive operating points (torque against speed) and limits"
    fig, axes = new_figure(title + (", joint side (top) and motor side (bottom)" if sides == 2 else ""),
                           per_side * sides, cols, size=(3.3 * cols, 3.0 * per_side * sides + 0.6))
    speeds = max(row["peak_speed"] for row in rows)
    torques = max(row["peak_torque"] for row in rows)
    axes = np.atleast_1d(axes).ravel()
    motor_axes = axes[per_side * cols:]
    if tau_motor is not None and motor_speed is not None:
        for i, (row, ax) in enumerate(zip(rows, motor_axes, strict=False)):
            for k in range(len(log.run_starts)):
                rows_k = log.run == k
                ax.plot(motor_speed[rows_k, i], tau_motor[rows_k, i], color="#2e8b57", lw=1.2,
                        label="motor operating points (ω_m, τ_m)" if k == 0 else None)
            ax.set_title(f"{row['joint']} motor, G = {row['gear_ratio']:.4g}:\npeak |τ_m| "
                         f"{row['peak_motor_torque']:.4g} N·m, peak |ω_m| {row['peak_motor_speed']:.3g} rad/s",
                         fontsize=8)
            ax.set_xlabel(f"ω_m{i + 1} [rad/s]")
            ax.set_ylabel(f"τ_m{i + 1} [N·m]")
        for ax in motor_axes[n:]:
            ax.set_visible(False)
        axes = axes[:per_side * cols]
    for i, (row, ax) in enumerate(zip(rows, axes, strict=False)):
        for k in range(len(log.run_starts)):
            rows_k = log.run == k
            ax.plot(log.qd[rows_k, i], log.tau[rows_k, i], color="#1f5fa8", lw=1.2,
                    label="operating points (q̇, τ)" if k == 0 else None)
        ax.plot(log.qd[[0, -1], i], log.tau[[0, -1], i], "o", color="#1f5fa8", ms=3)
        w, e = row["velocity_limit"], row["effort_limit"]
        if w is not None and e is not None:
            ax.plot([-w, w, w, -w, -w], [-e, -e, e, e, -e], color="#c0392b", lw=1.2, label="speed and effort limits")
        elif w is not None:
            ax.axvline(-w, color="#c0392b", lw=1.2, label="speed limits (effort limit unknown)")
            ax.axvline(w, color="#c0392b", lw=1.2)
        elif e is not None:
            ax.axhline(-e, color="#c0392b", lw=1.2, label="effort limits (speed limit unknown)")
            ax.axhline(e, color="#c0392b", lw=1.2)
        rms_speed = float(np.sqrt(np.mean(log.qd[:, i] ** 2)))
        ax.plot([rms_speed], [row["rms_torque"]], "*", ms=13, mfc="none", mec="#e67e22", mew=1.5, zorder=5,
                label="RMS point (RMS q̇, RMS τ): the continuous duty")
        still = row["peak_speed"] <= ROUND_OFF * max(speeds, 1.0)
        if still:  # round-off, not motion: a readable axis around zero instead of ±1e-15
            span = w if w is not None else 1.0
            ax.set_xlim(-span * 1.1, span * 1.1)
        speed = "0 (at rest)" if still else f"{row['peak_speed']:.3g} {row['speed_unit']}"
        ax.set_title(f"{row['joint']}: peak |τ| {_value(row['peak_torque'], torques)} {row['torque_unit']}, "
                     f"RMS τ {_value(row['rms_torque'], torques)}\npeak |q̇| {speed}", fontsize=8)
        ax.set_xlabel(f"q̇{i + 1} [{row['speed_unit']}]")
        ax.set_ylabel(f"τ{i + 1} [{row['torque_unit']}]")
    for ax in axes[n:]:
        ax.set_visible(False)
    shown = [*axes[:n], *(motor_axes[:n] if sides == 2 else [])]
    legend = {label: handle for ax in shown for handle, label in zip(*ax.get_legend_handles_labels(), strict=True)}
    fig.legend(legend.values(), legend.keys(), loc="outside lower center", ncols=len(legend), fontsize=8)
    return fig
