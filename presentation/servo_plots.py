"""The pictures of a servo run (:mod:`armlab.diagrams.servo`): what the loop did, and its frequency response.

* ``servo.png`` (:func:`servo_figure`) — per joint against time: the tracking error q − q_d, the torque command τ*
  against the torque applied (the saturation's limit drawn), and with the motors' electrics their current and
  voltage (the peak current and the bus voltage drawn);
* ``bode.png`` (:func:`bode_figure`) — the linearised closed loop's q_i/q_d,i per joint, magnitude (dB) and phase
  (°) against frequency (Hz), the −3 dB line and each joint's bandwidth against the tuning rule's design value.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armlab.presentation.figures import new_figure

if TYPE_CHECKING:
    from armlab.diagrams.simulate import SimulationLog

__all__ = ["SERVO_PLOTS", "bode_figure", "servo_figure"]

#: File names of a servo run's pictures.
SERVO_PLOTS = ("servo.png", "bode.png")
_COLORS = ["#1f5fa8", "#c0392b", "#2e8b57", "#8e44ad", "#d68910", "#5d6d7e", "#17a2b8"]


def _by_run(ax: Any, log: SimulationLog, y: NDArray[np.float64], **style: Any) -> None:
    """``y`` against t, one line per run (no line joins two runs)."""
    for k in range(len(log.run_starts)):
        rows = log.run == k
        ax.plot(log.t[rows], y[rows], **(style if k == 0 else {**style, "label": None}))


def servo_figure(log: SimulationLog) -> Any:
    """The servo run's tracking errors, torques and (with electrics) currents and voltages per joint (a matplotlib
    figure; the caller closes it)."""
    servo = log.servo or {}
    electric = log.current is not None and log.voltage is not None
    rows = 4 if electric else 2
    rate = servo.get("rate_hz")
    title = (f"{log.arm.name}: {servo.get('controller', log.mode)} "
             f"{'continuous' if rate is None else f'at {rate:g} Hz'}: tracking, torque"
             + (", current and voltage" if electric else ""))
    fig, axes = new_figure(title, rows, 1, size=(9.0, 2.6 * rows + 0.6), sharex=True)
    axes = axes[:, 0]
    limit = servo.get("torque_limit")
    loop = servo.get("current_loop") or {}
    for i, name in enumerate(log.arm.joint_names):
        color = _COLORS[i % len(_COLORS)]
        unit = "rad" if log.arm.revolute[i] else "m"
        _by_run(axes[0], log, 1e3 * (log.q[:, i] - log.q_ref[:, i]), color=color, label=f"{name} [m{unit}]")
        if log.tau_command is not None:
            _by_run(axes[1], log, log.tau_command[:, i], color=color, lw=0.9, ls="--",
                    label=f"{name} command τ*" if i == 0 else None)
        _by_run(axes[1], log, log.tau[:, i], color=color, label=f"{name} applied τ")
        if limit is not None and limit[i] is not None:
            for sign in (-1, 1):
                axes[1].axhline(sign * limit[i], color=color, lw=0.8, ls=":",
                                label=f"{name} limit ±{limit[i]:.4g}" if sign > 0 else None)
        if electric:
            assert log.current is not None and log.voltage is not None
            _by_run(axes[2], log, log.current[:, i], color=color, label=f"{name} i")
            peak = loop.get("peak_current", [None] * log.arm.n)[i]
            if peak is not None:
                for sign in (-1, 1):
                    axes[2].axhline(sign * peak, color=color, lw=0.8, ls=":",
                                    label=f"{name} peak current ±{peak:.3g} A" if sign > 0 else None)
            _by_run(axes[3], log, log.voltage[:, i], color=color, label=f"{name} V")
            bus = loop["bus_voltage"][i]
            for sign in (-1, 1):
                axes[3].axhline(sign * bus, color=color, lw=0.8, ls=":",
                                label=f"{name} bus ±{bus:.3g} V" if sign > 0 else None)
    labels = ["tracking error q − q_d [mrad | mm]", "joint torque [N·m | N]", "motor current i [A]",
              "winding voltage V [V]"]
    for ax, label in zip(axes, labels, strict=False):
        ax.set_ylabel(label, fontsize=8)
        ax.legend(fontsize=7, ncols=2, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[-1].set_xlabel("time t [s]")
    return fig


def bode_figure(title: str, joints: Sequence[str], frequency: NDArray[np.float64], response: NDArray[np.complex128],
                bandwidth: NDArray[np.float64], design: NDArray[np.float64]) -> Any:
    """Bode plot of ``response`` ``(k, n)`` (q_i/q_d,i) at ``frequency`` (Hz, ``(k,)``), one line per joint of
    ``joints``, with each joint's −3 dB ``bandwidth`` found and the ``design`` bandwidth (Hz, ``(n,)``) marked."""
    fig, axes = new_figure(title, 2, 1, size=(8.5, 6.5), sharex=True)
    mag, phase = axes[0, 0], axes[1, 0]
    for i, name in enumerate(joints):
        color = _COLORS[i % len(_COLORS)]
        mag.semilogx(frequency, 20 * np.log10(np.abs(response[:, i])), color=color,
                     label=f"{name}: −3 dB at {bandwidth[i]:.4g} Hz (design {design[i]:.4g} Hz)")
        phase.semilogx(frequency, np.degrees(np.unwrap(np.angle(response[:, i]))), color=color, label=name)
        if np.isfinite(bandwidth[i]):
            mag.plot([bandwidth[i]], [-10 * np.log10(2.0)], "o", color=color, ms=5)
        mag.axvline(design[i], color=color, lw=0.8, ls=":")
    mag.axhline(-10 * np.log10(2.0), color="k", lw=0.8, ls="--", label="−3 dB")
    mag.set_ylabel("|q / q_d| [dB]")
    phase.set_ylabel("phase [°]")
    phase.set_xlabel("frequency f [Hz]")
    mag.legend(fontsize=7, loc="lower left")
    phase.legend(fontsize=7, loc="lower left")
    return fig
