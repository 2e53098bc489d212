"""A joint's motor electrics: winding resistance and inductance, torque and back-EMF constants, the drive's bus
voltage and peak current, per joint; the current loop's default tuning.

The model is a DC (or field-oriented brushless) motor's d–q equivalent, motor side, per joint::

    L di/dt = V − R i − k_e ω_m,     τ_m = k_t i,     ω_m = G q̇,     τ = G τ_m  (joint side)

with |V| ≤ V_bus (the drive's voltage limit) and the current command |i*| ≤ I_peak (its peak current). In SI a
motor's k_t (N·m/A) and k_e (V·s/rad) are the same number, and then the power balance is exact:
V i = R i² + d(½ L i²)/dt + τ_m ω_m. The gearbox is lossless in the electrical model (its efficiency η is in
:func:`armlab.drives.train.motor_torque`, the motor torque a sizing reads, not in the simulated current).

The columns of a drive file (:mod:`armlab.drives.read`), all optional as a group: ``resistance`` R (Ω),
``inductance`` L (H), ``torque_constant`` k_t (N·m/A), ``bus_voltage`` V_bus (V) — the four needed to simulate the
electrics — and ``back_emf`` k_e (V·s/rad, default k_t) and ``peak_current`` I_peak (A, default: no current limit).

The current loop's default tuning (:func:`current_gains`) cancels the winding's pole: a PI with K_p = L ω_c and
K_i = R ω_c, and the back-EMF k_e ω_m fed forward, makes i/i* = ω_c / (s + ω_c), a first-order loop of bandwidth
ω_c (rad/s) in every joint whatever its R and L.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.drives.train import joint_vector

__all__ = ["DEFAULT_CURRENT_BANDWIDTH", "ELECTRIC_COLUMNS", "REQUIRED_ELECTRIC_COLUMNS", "MotorElectrics",
           "current_gains"]

#: The electrical columns of a drive file, in :class:`MotorElectrics`' order.
ELECTRIC_COLUMNS = ("resistance", "inductance", "torque_constant", "bus_voltage", "back_emf", "peak_current")
#: The ones a drive file must give together to have electrics (``back_emf`` and ``peak_current`` have defaults).
REQUIRED_ELECTRIC_COLUMNS = ELECTRIC_COLUMNS[:4]
#: Default bandwidth of the current loop (Hz): a servo drive's current loop closes at 1–3 kHz.
DEFAULT_CURRENT_BANDWIDTH = 1000.0

_ALLOWED = {
    "resistance": ("Ω", "a positive finite number"),
    "inductance": ("H", "a positive finite number"),
    "torque_constant": ("N·m/A", "a positive finite number"),
    "bus_voltage": ("V", "a positive finite number"),
    "back_emf": ("V·s/rad", "a positive finite number"),
    "peak_current": ("A", "a positive number (inf: no current limit)"),
}


def _positive(value: ArrayLike, name: str, n: int | None, infinite: bool = False) -> NDArray[np.float64]:
    """A positive value per joint (``infinite``: inf allowed), :func:`~armlab.drives.train.joint_vector`."""
    unit, allowed_text = _ALLOWED[name]
    return joint_vector(value, f"motor {name}", n, unit, allowed_text,
                        lambda a: ~(a > 0) | (np.isnan(a) if infinite else np.isinf(a)))


@dataclass(frozen=True)
class MotorElectrics:
    """Per-joint motor electrics, each ``(n,)``, motor side (module docstring): R (Ω), L (H), k_t (N·m/A),
    V_bus (V), k_e (V·s/rad; ``None``: k_t) and I_peak (A; ``None`` or inf: no current limit)."""

    resistance: NDArray[np.float64]
    inductance: NDArray[np.float64]
    torque_constant: NDArray[np.float64]
    bus_voltage: NDArray[np.float64]
    back_emf: NDArray[np.float64] = None  # type: ignore[assignment]  # None: k_t (an array once made)
    peak_current: NDArray[np.float64] = None  # type: ignore[assignment]  # None: no limit, inf (likewise)

    def __post_init__(self) -> None:
        n = None
        for f in fields(self):
            value = getattr(self, f.name)
            if value is None:
                value = self.torque_constant if f.name == "back_emf" else np.full(n or 0, np.inf)
            a = _positive(value, f.name, n, infinite=f.name == "peak_current")
            n = a.size
            object.__setattr__(self, f.name, a)

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.resistance.size)

    @property
    def time_constant(self) -> NDArray[np.float64]:
        """The winding's electrical time constant L/R (s), ``(n,)``."""
        return self.inductance / self.resistance


def current_gains(electrics: MotorElectrics, bandwidth: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The current PI's (K_p in V/A, K_i in V/(A·s)) per joint for a first-order loop of ``bandwidth`` (Hz):
    K_p = L ω_c, K_i = R ω_c with ω_c = 2π·bandwidth (the zero K_i/K_p = R/L cancels the winding's pole)."""
    omega = 2 * np.pi * float(bandwidth)
    return electrics.inductance * omega, electrics.resistance * omega
