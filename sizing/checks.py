"""The checks the vendors' sizing tools add to torque and speed: the motor's electrics, its winding's temperature,
the drive's current, its DC link and braking resistor, the holding brake, the gearbox's life and the inertia ratio.

Each check is run only with the catalogue values it needs (:data:`REQUIRES`); a pair whose motor or gearbox
lacks one is "not checked (no column X)" for that check (its ratio NaN), never passed. With the motor torque
τ_m (N·m, :func:`~armlab.sizing.select.motor_side`, times the safety factor S: every torque, hence every
current, is S times the cycle's) and the motor speed ω (rad/s) at every sample, I = S·τ_m/K_t (A RMS, signed):

* ``inertia ratio``: (J_load/G² + J_g)/J_m — the load at the motor (the arm's M_kk(q), the gearbox's own input
  inertia) over the rotor's — at most ``max_inertia_ratio`` (default :data:`INERTIA_RATIO`), every sample;
* ``voltage``: the line-to-line voltage a three-phase motor needs (q-axis current, sinusoidal, the star
  equivalent of the datasheet's line-to-line values), V = √((K_e·ω + (√3/2)·R_hot·I)² + ((√3/2)·p·ω·L·I)²),
  at most what the drive makes from its bus, V_bus/√2 (space-vector modulation), every sample: the
  voltage-limited torque–speed envelope at the bus voltage (:attr:`Conditions.bus_voltage` or the catalogue's);
  R_hot = R_25·(1 + α_Cu·(T_max − 25 °C)), the resistance at the winding's limit (α_Cu = :data:`ALPHA_CU`);
* ``current peak`` max |I| ≤ the drive's peak current; ``current RMS`` √⟨I²⟩ ≤ its continuous current;
* ``I²t``: the drive's overload monitor, a first-order filter x' = (I² − x)/τ_d whose time constant makes the
  peak current I_p last the datasheet's t_p from cold, τ_d = −t_p/ln(1 − I_c²/I_p²); √max x over the periodic
  cycle ≤ I_c;
* ``winding temperature``: the lumped winding → housing → ambient model, C_w·θ_w' = P − (θ_w − θ_h)/R_th1,
  C_h·θ_h' = (θ_w − θ_h)/R_th1 − θ_h/R_th2 (θ over the ambient :attr:`Conditions.ambient`; C_w = τ_w/R_th1,
  C_h = τ_m/R_th2) with the copper losses P = (3/2)·R_hot·I² (three phases of R/2 each), the cycle repeated until
  periodic (:func:`armlab.sizing.periodic.lag_periodic`, exact in its two modes); the peak winding temperature
  ≤ the limit (margin on the rise over ambient). The duty type the motor sees (IEC 60034-1; :func:`duty_type`):
  S1 (constant losses), S3 (periods de-energised: duty factor = time energised / cycle), S6 (energised
  throughout with a varying load: duty factor = time in motion / cycle);
* ``regeneration``: the power the drive takes from its bus, p = S·τ_m·ω + (3/2)·R_25·I² (the losses at 25 °C,
  the least, so the most energy comes back; without K_t and R none), stores
  :func:`~armlab.sizing.periodic.bus_energy` at its peak; the DC-link capacitors hold E_cap =
  ½·C·(V_max² − V_bus²). If they do not, a braking resistor must take the rest: its mean power (the energy above
  E_cap per cycle, :func:`~armlab.sizing.periodic.resistor_energy`, over the cycle's duration) ≤
  ``braking_resistor_W`` and the peak regenerated power ≤ V_max²/``braking_resistor_ohm``; without a resistor's
  columns the check fails, saying what resistor is needed;
* ``brake``: the holding brake's T_H ≥ K·T_static/|G|, T_static the largest joint-side gravity torque
  |τ_g(q)| along the cycle (payload held where the cycle holds it), K = :attr:`Conditions.brake_factor`;
* ``gearbox life``: with n the input speed |ω| and T the output torque S·|τ_L| over the cycle,
  n_av = ⟨n⟩ and T_av = (⟨n·T³⟩/⟨n⟩)^⅓; strain-wave gearing (Harmonic Drive's rule):
  L50 = L_n·(n_N/n_av)·(T_N/T_av)³, L10 = L50/5 ≥ the required life :attr:`Conditions.required_life`; a
  ``rating`` gearbox (planetary: the catalogue's rated life L_n at T_N and n_N): T_av ≤ T_N, n_av ≤ n_N and
  L_n ≥ the required life.

Comparisons of computed values with limits go through :func:`within` (one slack rule).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armlab.bounds import above, below
from armlab.sizing.catalogue import LIFE_BASES, Gearboxes, Motors
from armlab.sizing.periodic import bus_energy, energy_steps, lag, lag_periodic, resistor_energy, within_zero

if TYPE_CHECKING:
    from armlab.sizing.select import JointTask

__all__ = ["ALPHA_CU", "DRIVE_CHECKS", "DRIVE_STATS", "INERTIA_RATIO", "MARGIN_SHOWN",
           "REQUIRES", "RESISTANCE_AT",
           "SCREEN_ALLOWANCE", "Conditions", "DriveRows", "drive_checks", "duty_type", "missing_column", "number",
           "percent", "screen_bounds",
           "thermal_modes", "winding_temperature", "within"]

#: The checks of this module, in the order they are reported (after the torque and speed checks).
DRIVE_CHECKS = ("inertia ratio", "voltage", "current peak", "current RMS", "I²t", "winding temperature",
                "regeneration", "brake", "gearbox life")
#: The figures :func:`drive_checks` adds with ``describe`` (name → ``(L, C)``; NaN where not computed): the voltage
#: check's worst speed (rad/s); the winding's periodic peak and its steady temperature under the mean losses (°C),
#: the mean copper losses (W), the cycles from cold to within :data:`PERIODIC_WITHIN` of periodic; the DC link's
#: peak stored energy, the capacitors' capacity, the energy returned per cycle (J), the peak returned power (W),
#: the braking resistor's energy per cycle (J) and mean power (W), whether the drive has one (1/0) and what the
#: check compared (0 the capacitors' energy, 1 the resistor's mean power, 2 its peak power), the net energy a
#: cycle returns (J; > 0: the link fills in the end whatever its capacitors, +inf stored); the brake's
#: static torque (N·m, joint side); the gearbox's life (h: L10, or a rating's L_n), T_av (N·m), n_av (rad/s), its
#: basis (:data:`~armlab.sizing.catalogue.LIFE_BASES`) and a rating's binding limit (0 T_N, 1 n_N, 2 L_n; −1 none).
DRIVE_STATS = ("voltage_speed", "winding_peak_C", "winding_mean_loss_C", "copper_loss_W", "cycles_to_periodic",
               "bus_energy_peak_J", "capacitor_J", "bus_regenerated_J", "regen_power_peak_W", "resistor_energy_J",
               "resistor_power_W", "resistor_fitted", "regeneration_basis", "bus_net_J", "static_torque", "life_h",
               "life_T_av_Nm", "life_n_av", "life_basis", "life_binding")
#: Copper's temperature coefficient of resistance (1/K, at 20–25 °C; IEC 60228's 0.00393).
ALPHA_CU = 0.00393
#: The temperature (°C) a catalogue's resistance is given at.
RESISTANCE_AT = 25.0
#: The largest inertia ratio when the catalogue gives none (a servo's usual rule).
INERTIA_RATIO = 10.0
#: How close (K) the winding's temperature from cold must come to the periodic one to count as there.
PERIODIC_WITHIN = 0.1

#: The catalogue values each check needs: (catalogue, field) pairs (``bus_voltage`` unless the conditions give one).
REQUIRES: dict[str, tuple[tuple[str, str], ...]] = {
    "inertia ratio": (),
    "voltage": tuple(("motor", f) for f in ("torque_constant", "back_emf", "resistance", "inductance", "pole_pairs",
                                            "max_winding_temperature", "bus_voltage")),
    "current peak": (("motor", "torque_constant"), ("motor", "drive_peak_current")),
    "current RMS": (("motor", "torque_constant"), ("motor", "drive_continuous_current")),
    "I²t": tuple(("motor", f) for f in ("torque_constant", "drive_continuous_current", "drive_peak_current",
                                        "drive_peak_time")),
    "winding temperature": tuple(("motor", f) for f in (
        "torque_constant", "resistance", "thermal_resistance_winding", "thermal_resistance_housing",
        "time_constant_winding", "time_constant_motor", "max_winding_temperature")),
    "regeneration": (("motor", "bus_capacitance"), ("motor", "bus_voltage"), ("motor", "bus_max_voltage")),
    "brake": (("motor", "brake_torque"),),
    "gearbox life": (("gearbox", "life_basis"), ("gearbox", "rated_life"), ("gearbox", "rated_input_speed")),
}


def number(x: float, digits: int = 3) -> str:
    """``x`` rounded to ``digits`` significant digits, plainly written (``1.09``, ``17300``, ``0.0371``, ``0.5``;
    ``1.2e+07`` and ``3.4e-05`` outside [10⁻³, 10⁶); ``inf``, ``nan`` as such)."""
    text = f"{float(x):.{digits}g}"  # plain below 10^digits (trailing zeros dropped), else with an exponent
    if "e" not in text:
        return text
    x = float(text)
    return f"{x:.0f}" if 1e-3 <= abs(x) < 1e6 else text


#: A margin at least this (1000 %: a limit 11 times the value) is shown as "≫ 100 %".
MARGIN_SHOWN = 10.0


def percent(margin: float) -> str:
    """A margin (limit/value − 1) as a percentage to 3 significant digits; "≫ 100 %" from :data:`MARGIN_SHOWN`;
    "∞" without a value (nothing to compare); "not checked" for NaN."""
    if math.isnan(margin):
        return "not checked"
    if math.isinf(margin):
        return "∞" if margin > 0 else "−∞"  # not a bound: the sign shown
    if margin >= MARGIN_SHOWN:  # not a bound: where the text is capped
        return "≫ 100 %"
    return f"{number(100 * margin)} %"


def within(value: NDArray[np.float64] | float, bound: NDArray[np.float64] | float) -> NDArray[np.bool_]:
    """Whether ``value`` ≤ ``bound`` by the one boundary rule (:func:`armlab.bounds.above`; False for NaN)."""
    return np.logical_not(above(value, bound))


@dataclass(frozen=True)
class Conditions:
    """What the drives are sized for beyond the cycle: the ``ambient`` temperature (°C; IEC 60034-1's reference
    coolant temperature 40 °C by default), the DC ``bus_voltage`` (V; ``None``: each drive's catalogue value),
    the holding brake's safety factor ``brake_factor`` K (1.5–3 as makers advise; 2 by default) and the gearbox's
    ``required_life`` (h, its L10; 20 000 h by default). ``ValueError`` for a value outside those ranges."""

    ambient: float = 40.0
    bus_voltage: float | None = None
    brake_factor: float = 2.0
    required_life: float = 20000.0

    def __post_init__(self) -> None:
        checks = (("ambient", self.ambient, -60.0, 150.0, "°C", "a temperature in [−60, 150] °C"),
                  ("brake_factor", self.brake_factor, 1.0, 10.0, "", "a number in [1, 10] (makers advise 1.5–3)"),
                  ("required_life", self.required_life, 1e-6, 1e7, "h", "a life in (0, 1e7] h"))
        for name, value, low, high, unit, text in checks:
            v = _number(value)
            if not (low <= v <= high):  # not a bound: a value the user gave, against its range
                raise ValueError(f"{name} {value!r}{' ' + unit if unit else ''} is not allowed: {text}")
            object.__setattr__(self, name, v)
        if self.bus_voltage is not None:
            v = _number(self.bus_voltage)
            if not (0 < v <= 1e5):
                raise ValueError(f"bus voltage {self.bus_voltage!r} V is not allowed: a DC voltage in (0, 1e5] V")
            object.__setattr__(self, "bus_voltage", v)


def _number(value: object) -> float:
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return math.nan
    return v if not isinstance(value, bool) else math.nan


def missing_column(check: str, motors: Motors, gearboxes: Gearboxes, motor: int, gearbox: int,
                   conditions: Conditions) -> str:
    """The first catalogue column ``check`` needs that the pair's rows leave empty ("" if none)."""
    for kind, name in REQUIRES[check]:
        if name == "bus_voltage" and conditions.bus_voltage is not None:
            continue
        table, row = (motors, motor) if kind == "motor" else (gearboxes, gearbox)
        if np.isnan(getattr(table, name)[row]):
            return table.column(name)
    return ""


def _has(check: str, motors: Motors, gearboxes: Gearboxes, im: NDArray[np.intp], ig: NDArray[np.intp],
         conditions: Conditions) -> NDArray[np.bool_]:
    """Whether each candidate has every value ``check`` needs ``(C,)``."""
    ok = np.ones(im.size, dtype=bool)
    for kind, name in REQUIRES[check]:
        if name == "bus_voltage" and conditions.bus_voltage is not None:
            continue
        ok &= ~np.isnan(getattr(motors, name)[im] if kind == "motor" else getattr(gearboxes, name)[ig])
    return ok


def thermal_modes(motors: Motors, index: NDArray[np.intp]) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """The winding model's two modes (module docstring) of motors ``index`` ``(C,)``: rates λ₁ < λ₂ < 0 (1/s) and
    weights w₁, w₂ (K/J) with θ_w = w₁·y₁ + w₂·y₂, y_i' = λ_i·y_i + P."""
    r1, r2 = motors.thermal_resistance_winding[index], motors.thermal_resistance_housing[index]
    tw, tm = motors.time_constant_winding[index], motors.time_constant_motor[index]
    cw = tw / r1
    a, b, g = 1 / tw, r2 / (r1 * tm), 1 / tm  # 1/(R1·C_w), 1/(R1·C_h), 1/(R2·C_h)
    s = a + b + g
    lam1 = -(s + np.sqrt(s * s - 4 * a * g)) / 2  # the fast mode
    lam2 = a * g / lam1  # λ₁·λ₂ = a·g: no cancellation
    w1 = (a + lam2) / (cw * (lam2 - lam1))
    w2 = -(a + lam1) / (cw * (lam2 - lam1))
    return lam1, lam2, w1, w2


def winding_temperature(motors: Motors, index: NDArray[np.intp], loss: NDArray[np.float64], t: NDArray[np.float64],
                        ambient: float, cycles: int = 1) -> NDArray[np.float64]:
    """The winding temperature (°C) of motors ``index`` ``(C,)`` with copper losses ``loss`` ``(..., C, K)`` (W) at
    the knots ``t`` ``(K,)`` of a cycle repeated ``cycles`` times from cold (the ambient): ``(..., C, cycles, K)``,
    cycle m's knots at t + m·T (:func:`armlab.sizing.periodic.lag`; the start of cycle m in each mode is
    (1 − e^{mλT})·y_0*)."""
    lam1, lam2, w1, w2 = thermal_modes(motors, index)
    period = t[-1] - t[0]
    out = np.zeros(loss.shape[:-1] + (cycles, t.size))
    m = np.arange(cycles)
    for lam, w in ((lam1, w1), (lam2, w2)):
        cold = lag(lam, loss, t)  # (..., C, K)
        start = cold[..., -1] / -np.expm1(lam * period)  # the periodic start y_0* (..., C)
        begins = -np.expm1(np.multiply.outer(lam * period, m)) * start[..., None]  # (..., C, cycles)
        decay = np.exp(np.multiply.outer(lam, t - t[0]))  # (C, K)
        y = cold[..., None, :] + begins[..., None] * decay[:, None, :]
        out += w[:, None, None] * y
    return ambient + out


def duty_type(current: NDArray[np.float64], speed: NDArray[np.float64], weight: NDArray[np.float64]
              ) -> tuple[str, float]:
    """IEC 60034-1's duty type of one candidate in one load case (module docstring) and its duty factor (0–1):
    ``current`` ``(T,)`` A, ``speed`` ``(T,)`` rad/s, ``weight`` ``(T,)`` s."""
    loss = current**2
    top = float(loss.max())
    total = float(weight.sum())
    if top == 0 or within(top, float(loss.min()) * (1 + 1e-6)):
        return "S1", 1.0
    off = ~(loss > 1e-12 * top)  # de-energised: no current to speak of
    if off.any():
        return "S3", float(weight[~off].sum() / total)
    return "S6", float(weight[speed != 0].sum() / total)


@dataclass(frozen=True)
class DriveRows:
    """The checks of :data:`DRIVE_CHECKS` for candidates ``C``: ``rows`` check → (value, limit), each ``(L, C)``
    (ratio limit/value; NaN where not checked), and the figures ``stats`` name → ``(L, C)`` (with ``describe``)."""

    rows: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]]
    stats: dict[str, NDArray[np.float64]]


def _knot_weights(task: JointTask) -> NDArray[np.float64]:
    """Per sample ``(T,)`` the trapezoid weights (s) of its knots: Σ_s trap_s·f_s is the trapezoid rule of f over
    the knots, which bounds ∫f from above for an f convex between the knots (as |P − P̄| and max(−p, 0) are)."""
    h = np.diff(task.knot_time)
    per_knot = np.zeros(task.knot_time.size)
    per_knot[:-1] += h / 2
    per_knot[1:] += h / 2
    return np.bincount(task.knot_sample, per_knot, minlength=task.weight.size)


def _bus(motors: Motors, m: NDArray[np.intp], conditions: Conditions) -> NDArray[np.float64]:
    """The DC bus voltage (V) of motors ``m``' drives: the conditions', else each catalogue's."""
    return np.full(m.size, conditions.bus_voltage) if conditions.bus_voltage is not None else motors.bus_voltage[m]


def _capacity(motors: Motors, m: NDArray[np.intp], bus: NDArray[np.float64]) -> NDArray[np.float64]:
    """What the DC-link capacitors of motors ``m``' drives hold (J) from the bus voltage to V_max: ½C(V_max² − V²)
    (nothing for a bus at or above V_max)."""
    return np.maximum(0.5 * motors.bus_capacitance[m] * (motors.bus_max_voltage[m] ** 2 - bus**2), 0.0)


def _cols(a: NDArray, c: NDArray[np.intp]) -> NDArray:
    """``a[..., c]``, without a copy when ``c`` is every column in order (most pairs pass the torque checks)."""
    if c.size == a.shape[-1] and (c.size == 0 or (c[0] == 0 and c[-1] == c.size - 1)):
        return a
    return a[..., c]


def _ratio(limit: NDArray, value: NDArray) -> NDArray:
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(value > 0, limit / value, np.inf)


def drive_checks(task: JointTask, motors: Motors, gearboxes: Gearboxes, im: NDArray[np.intp], ig: NDArray[np.intp],
                 tau_m: NDArray[np.float64], speed: NDArray[np.float64], safety: float, conditions: Conditions,
                 active: NDArray[np.bool_], describe: bool, peak_torque: NDArray[np.float64],
                 rms_torque: NDArray[np.float64], floor: NDArray[np.float64] | None = None) -> DriveRows:
    """Every check of the module for candidates (``im``, ``ig``) ``(C,)`` with motor torques ``tau_m``
    ``(L, T, C)`` (without the safety factor; their peak and RMS |τ_m| ``(L, C)``) and motor speeds ``speed``
    ``(T, C)``; only the ``active`` ones ``(C,)`` are computed (the others are NaN: a pair already failing a
    torque or speed check).

    Without ``describe`` (the selection's pass, which needs each pair's margin only) and with ``floor`` ``(C,)``
    the smallest ratio of the checks made before, the I²t, winding and DC-link checks are first bounded: a lag
    y' = λy + u repeated has the periodic solution y(t) = ∫₀ᵀ k(s)·u(t − s)ds with k(s) = e^{λs}/(1 − e^{λT}),
    whose mean is ū/(−λ) and, since max k − min k = 1, |y − ȳ| ≤ ½∫₀ᵀ|u − ū|dt: the winding's rise is at most
    (R_th1 + R_th2)·P̄ + ½(|w₁| + |w₂|)·∫|P − P̄|, the I²t filter at most ⟨I²⟩ + ½∫|I² − ⟨I²⟩|/τ_d (both P and I²
    are τ_m² times a constant of the candidate), the DC link's peak energy at most ∫max(−S·τ_m·ω, 0) (the losses
    only lower it); the integrals by the trapezoid rule over the knots, an upper bound for these pieces, convex
    between the knots. Where the ratio of such a bound is at least the ``floor`` (the ratios before, and of the
    cheap checks here) it cannot be the smallest, and the bound stands in for the check (its ratio a lower bound of
    the exact one); elsewhere, and with ``describe`` always, the check is exact."""
    L, C = task.tau.shape[0], im.size
    rows: dict[str, tuple[NDArray, NDArray]] = {check: (np.full((L, C), np.nan), np.full((L, C), np.nan))
                                                for check in DRIVE_CHECKS}
    stats: dict[str, NDArray] = {name: np.full((L, C), np.nan) for name in DRIVE_STATS} if describe else {}
    sink = stats if describe else None
    has = {check: active & _has(check, motors, gearboxes, im, ig, conditions) for check in DRIVE_CHECKS}
    G, Jm, Jg = gearboxes.ratio[ig], motors.rotor_inertia[im], gearboxes.input_inertia[ig]
    limit = np.where(np.isnan(motors.max_inertia_ratio[im]), INERTIA_RATIO, motors.max_inertia_ratio[im])
    # (J_load/G² + J_g)/J_m is monotone in J_load: its extremes are at M_kk's
    rows["inertia ratio"] = ((task.inertia.max(axis=1)[:, None] / G**2 + Jg) / Jm, np.broadcast_to(limit, (L, C)))
    if describe:
        stats["inertia_ratio_min"] = (task.inertia.min(axis=1)[:, None] / G**2 + Jg) / Jm
        stats["inertia_ratio_max"] = rows["inertia ratio"][0]
    kt = motors.torque_constant[im]

    def put(check: str, c: NDArray[np.intp], value: NDArray, limit: NDArray) -> None:
        rows[check][0][:, c], rows[check][1][:, c] = value, limit

    # exact and cheap: the currents' peak and RMS are the torques' over K_t, the brake's a static torque
    for check, torque, drive in (("current peak", peak_torque, motors.drive_peak_current),
                                 ("current RMS", rms_torque, motors.drive_continuous_current)):
        c = np.flatnonzero(has[check])
        put(check, c, safety * torque[:, c] / kt[c], drive[im[c]])
    c = np.flatnonzero(has["brake"])
    static = np.abs(task.static).max(axis=1)[:, None]  # (L, 1) N·m, joint side
    put("brake", c, conditions.brake_factor * static / np.abs(G[c]), motors.brake_torque[im[c]])
    if describe:
        stats["static_torque"][:, c] = static
    c = np.flatnonzero(has["gearbox life"])
    if c.size:
        _life(task, gearboxes, ig[c], c, safety, conditions, *rows["gearbox life"], sink)
    bounded = ("voltage", "I²t", "winding temperature", "regeneration")
    todo = {check: np.flatnonzero(has[check]) for check in bounded}
    bounding = not describe and floor is not None
    if bounding:
        assert floor is not None
        floor = floor.copy()
        for check in DRIVE_CHECKS:
            if check not in bounded:
                floor = np.fmin(floor, _ratio(rows[check][1], rows[check][0]).min(axis=0))
        # the voltage at most √((K_e·ω_max + (√3/2)·R_hot·I_max)² + ((√3/2)·p·L·ω_max·I_max)²) (triangle inequality)
        c = todo["voltage"]
        m = im[c]
        omega_max, current_max = np.abs(_cols(speed, c)).max(axis=0), safety * peak_torque[:, c] / kt[c]
        r_hot = motors.resistance[m] * (1 + ALPHA_CU * (motors.max_winding_temperature[m] - RESISTANCE_AT))
        top = np.hypot(motors.back_emf[m] * omega_max + np.sqrt(3) / 2 * r_hot * current_max,
                       np.sqrt(3) / 2 * motors.pole_pairs[m] * motors.inductance[m] * omega_max * current_max)
        bus = _bus(motors, m, conditions)
        sure = np.all(_ratio(bus / np.sqrt(2), top) >= floor[c], axis=0)
        put("voltage", c[sure], top[:, sure], np.broadcast_to(bus[sure] / np.sqrt(2), (L, int(sure.sum()))))
        todo["voltage"] = c[~sure]
    c = todo["voltage"]
    if c.size:
        _voltage(motors, im[c], c, tau_m, speed, safety, conditions, *rows["voltage"], sink)
    if bounding:
        assert floor is not None
        floor = np.fmin(floor, _ratio(rows["voltage"][1], rows["voltage"][0]).min(axis=0))
        trap = _knot_weights(task)
        period = trap.sum()
        need = np.flatnonzero(has["I²t"] | has["winding temperature"] | has["regeneration"])
        squares = np.full((L, C), np.nan)  # ∫τ_m² over the knots' trapezoids, (N·m)²·s
        squares[:, need] = np.einsum("ltc,ltc,t->lc", _cols(tau_m, need), _cols(tau_m, need), trap)

        def upper(check: str, c: NDArray[np.intp], half: NDArray) -> tuple[NDArray, NDArray]:
            """The bound of ``check`` for candidates ``c`` given ½∫|τ_m² − ⟨τ_m²⟩| (or a bound of it) ``half``."""
            m, mean, scale = im[c], squares[:, c] / period, (safety / kt[c]) ** 2  # ⟨τ_m²⟩; τ_m² → I²
            if check == "I²t":
                i_c, i_p, t_p = (motors.drive_continuous_current[m], motors.drive_peak_current[m],
                                 motors.drive_peak_time[m])
                overload = ~within(i_p, i_c * (1 + 1e-12))
                with np.errstate(divide="ignore", invalid="ignore"):
                    tau_d = -t_p / np.log1p(-(i_c / i_p) ** 2)
                return np.where(overload, np.sqrt(scale * (mean + half / tau_d)),
                                safety * peak_torque[:, c] / kt[c]), i_c
            r_hot = motors.resistance[m] * (1 + ALPHA_CU * (motors.max_winding_temperature[m] - RESISTANCE_AT))
            _, _, w1, w2 = thermal_modes(motors, m)
            gain = motors.thermal_resistance_winding[m] + motors.thermal_resistance_housing[m]
            return (1.5 * r_hot * scale * (gain * mean + (np.abs(w1) + np.abs(w2)) * half),
                    motors.max_winding_temperature[m] - conditions.ambient)

        for check in ("I²t", "winding temperature"):
            # first ½∫|u − ū| ≤ ½∫(u + ū) = ∫u (u = τ_m² ≥ 0: no pass over the samples), then the exact integral
            for tight in (False, True):
                c = todo[check]
                if not c.size:
                    break
                if tight:
                    squared = _cols(tau_m, c) ** 2
                    half = 0.5 * np.einsum("ltc,t->lc", np.abs(squared - squares[:, None, c] / period), trap)
                else:
                    half = squares[:, c]
                value, lim = upper(check, c, half)
                sure = np.all(_ratio(lim, value) >= floor[c], axis=0)
                put(check, c[sure], value[:, sure], lim[sure])
                todo[check] = c[~sure]
        c = todo["regeneration"]
        if c.size:  # from the mechanical power S·τ_m·ω, whose returns bound those with the copper losses
            m = im[c]
            bus = _bus(motors, m, conditions)
            capacity = _capacity(motors, m, bus)
            torque = _cols(tau_m, c)
            mechanical = torque * _cols(speed, c)[None]  # (L, T, c) W / S
            back = safety * np.einsum("ltc,t->lc", np.maximum(-mechanical, 0.0), trap)  # what comes back, at most
            peak_need = safety * np.maximum(-mechanical, 0.0).max(axis=1)  # the most power coming back, at most
            copper = np.nan_to_num(1.5 * motors.resistance[m] * (safety / kt[c]) ** 2)  # W per (N·m)², 0 without
            net = -safety * np.einsum("ltc,t->lc", mechanical, trap) - copper * squares[:, c]
            charging = ~within_zero(net, back)  # the cycle returns net energy: the link fills, whatever its size
            resistor = ~np.isnan(motors.braking_resistor_power[m]) & ~np.isnan(motors.braking_resistance[m])
            # a resistor's ratio is at least its ratings over ∫max(−p, 0)/T (mean) and over max(−p) (peak)
            mean_need = back / trap.sum()
            mean_rating = motors.braking_resistor_power[m]
            peak_rating = motors.bus_max_voltage[m] ** 2 / motors.braking_resistance[m]
            by_peak = _ratio(peak_rating, peak_need) < _ratio(mean_rating, mean_need)  # not a bound: which binds
            need = np.where(by_peak, peak_need, mean_need)
            rating = np.where(by_peak, peak_rating, mean_rating)
            value = np.where(charging, np.where(resistor, need, np.inf), back)  # no resistor: the link overflows
            limit = np.where(charging & resistor, rating, capacity)
            low = _ratio(limit, value)  # (L, c): a lower bound of the check's ratio
            # sure: the bound cannot bind, or the link fills and no resistor takes it (it fails whatever the rest)
            sure = np.all(~below(low, floor[c]), axis=0) | np.any(charging & ~resistor, axis=0)
            put("regeneration", c[sure], value[:, sure], limit[:, sure])
            todo["regeneration"] = c[~sure]
    c = todo["I²t"]
    if c.size:
        _i2t(task, motors, im[c], c, tau_m, safety, *rows["I²t"])
    c = todo["winding temperature"]
    if c.size:
        _winding(task, motors, im[c], c, safety * _cols(tau_m, c) / kt[c], conditions, *rows["winding temperature"],
                 sink)
    c = todo["regeneration"]
    if c.size:
        _regeneration(task, motors, im[c], c, tau_m, speed, safety, conditions, *rows["regeneration"], sink)
    return DriveRows(rows, stats)


def _voltage(motors: Motors, m: NDArray[np.intp], c: NDArray[np.intp], tau_m: NDArray, speed: NDArray,
             safety: float, conditions: Conditions, value: NDArray, bound: NDArray,
             stats: dict[str, NDArray] | None) -> None:
    bus = _bus(motors, m, conditions)
    r_hot = motors.resistance[m] * (1 + ALPHA_CU * (motors.max_winding_temperature[m] - RESISTANCE_AT))
    current = safety * _cols(tau_m, c) / motors.torque_constant[m]  # (L, T, c) A, signed
    omega = _cols(speed, c)
    real = motors.back_emf[m] * omega + np.sqrt(3) / 2 * r_hot * current
    quadrature = (np.sqrt(3) / 2 * motors.pole_pairs[m] * motors.inductance[m]) * omega * current
    squared = real * real + quadrature * quadrature
    value[:, c], bound[:, c] = np.sqrt(squared.max(axis=1)), bus / np.sqrt(2)
    if stats is not None:
        worst = squared.argmax(axis=1)  # (L, c)
        stats["voltage_speed"][:, c] = np.take_along_axis(np.broadcast_to(omega, squared.shape), worst[:, None],
                                                          axis=1)[:, 0]


def _i2t(task: JointTask, motors: Motors, m: NDArray[np.intp], c: NDArray[np.intp], tau_m: NDArray, safety: float,
         value: NDArray, bound: NDArray) -> None:
    i_c, i_p, t_p = motors.drive_continuous_current[m], motors.drive_peak_current[m], motors.drive_peak_time[m]
    current = safety * _cols(tau_m, c) / motors.torque_constant[m]  # (L, T, c) A
    overload = ~within(i_p, i_c * (1 + 1e-12))  # a drive with a peak above its continuous current
    filtered = np.abs(current).max(axis=1)  # without an overload range: the peak against I_c
    if overload.any():
        k = np.flatnonzero(overload)
        tau_d = -t_p[k] / np.log1p(-(i_c[k] / i_p[k]) ** 2)
        squared = np.moveaxis(current[:, task.knot_sample][:, :, k] ** 2, 1, -1) / tau_d[:, None]  # (L, k, K)
        x, _ = lag_periodic(-1 / tau_d, squared, task.knot_time)  # the rate per candidate, the input per case too
        filtered[:, k] = np.sqrt(x.max(axis=-1))
    value[:, c], bound[:, c] = filtered, i_c


def _winding(task: JointTask, motors: Motors, m: NDArray[np.intp], c: NDArray[np.intp], current: NDArray,
             conditions: Conditions, value: NDArray, bound: NDArray, stats: dict[str, NDArray] | None) -> None:
    t_max = motors.max_winding_temperature[m]
    r_hot = motors.resistance[m] * (1 + ALPHA_CU * (t_max - RESISTANCE_AT))
    loss = 1.5 * r_hot[:, None] * np.moveaxis(current[:, task.knot_sample], 1, -1) ** 2  # (L, c, K) W
    lam1, lam2, w1, w2 = thermal_modes(motors, m)
    y1, s1 = lag_periodic(lam1, loss, task.knot_time)  # rates (c,) against losses (L, c, K)
    y2, s2 = lag_periodic(lam2, loss, task.knot_time)
    rise = w1[:, None] * y1 + w2[:, None] * y2  # (L, c, K) K over the ambient
    value[:, c], bound[:, c] = rise.max(axis=-1), t_max - conditions.ambient
    if stats is None:
        return
    w = task.weight
    mean_loss = 1.5 * r_hot * np.einsum("ltc,ltc,t->lc", current, current, w) / w.sum()
    r_total = motors.thermal_resistance_winding[m] + motors.thermal_resistance_housing[m]
    stats["winding_peak_C"][:, c] = conditions.ambient + rise.max(axis=-1)
    stats["winding_mean_loss_C"][:, c] = conditions.ambient + mean_loss * r_total
    stats["copper_loss_W"][:, c] = mean_loss
    # from cold the deviation from periodic is Σ w_i·s_i·e^{λ_i t} ≤ (Σ|w_i·s_i|)·e^{λ₂ t} (λ₂ the slow mode)
    spread = np.abs(w1 * s1) + np.abs(w2 * s2)
    period = task.knot_time[-1] - task.knot_time[0]
    with np.errstate(divide="ignore"):
        cycles = np.ceil(np.maximum(np.log(spread / PERIODIC_WITHIN), 0.0) / (-lam2 * period))
    stats["cycles_to_periodic"][:, c] = cycles


def _bus_power(motors: Motors, m: NDArray[np.intp], torque: NDArray, omega: NDArray) -> NDArray[np.float64]:
    """The power (W) a drive draws from its bus for motor torques ``torque`` (N·m, × the safety factor) at speeds
    ``omega`` (rad/s), broadcast with the motors ``m`` on the last axis: τ·ω + (3/2)·R_25·(τ/K_t)² (no losses
    without K_t and R)."""
    power = torque * omega
    losses = ~np.isnan(motors.torque_constant[m]) & ~np.isnan(motors.resistance[m])
    if losses.any():
        copper = 1.5 * motors.resistance[m] * (torque / motors.torque_constant[m]) ** 2
        power = power + np.where(losses, np.nan_to_num(copper), 0.0)
    return power


def _regeneration(task: JointTask, motors: Motors, m: NDArray[np.intp], c: NDArray[np.intp], tau_m: NDArray,
                  speed: NDArray, safety: float, conditions: Conditions, value: NDArray, bound: NDArray,
                  stats: dict[str, NDArray] | None) -> None:
    knots, t = task.knot_sample, task.knot_time
    bus = _bus(motors, m, conditions)
    power = np.moveaxis(_bus_power(motors, m, safety * _cols(tau_m, c), _cols(speed, c)[None])[:, knots], 1, -1)
    stored, net = bus_energy(power, t)  # (L, c); power (L, c, K) at the knots
    v_max = motors.bus_max_voltage[m]
    capacity = _capacity(motors, m, bus)  # (c,)
    peak_regen = np.maximum((-power).max(axis=-1), 0.0)  # (L, c) W: the most power coming back
    value[:, c], bound[:, c] = stored, np.broadcast_to(capacity, stored.shape)
    resistor = ~np.isnan(motors.braking_resistor_power[m]) & ~np.isnan(motors.braking_resistance[m])
    full = ~within(stored, capacity)  # (L, c): the capacitors do not hold it, a braking resistor must
    over = full & (resistor[None, :] | (stats is not None))  # the resistor needed, for the report too
    burnt = np.zeros_like(stored)
    basis = np.zeros_like(stored)  # 0 the capacitors, 1 the resistor's mean power, 2 its peak
    if over.any():
        k = np.flatnonzero(over.any(axis=0))
        burnt[:, k] = resistor_energy(power[:, k], t, np.broadcast_to(capacity[k], (power.shape[0], k.size)))
    fitted = full & resistor[None, :]
    if fitted.any():
        k = np.flatnonzero(fitted.any(axis=0))
        mean_power = burnt[:, k] / (t[-1] - t[0])
        peak_rating = v_max[k] ** 2 / motors.braking_resistance[m][k]
        with np.errstate(divide="ignore"):
            by_resistor = motors.braking_resistor_power[m][k] / mean_power
            use_peak = peak_rating / peak_regen[:, k] < by_resistor  # not a bound: which of the two binds
        cols, on = c[k], fitted[:, k]
        value[:, cols] = np.where(on, np.where(use_peak, peak_regen[:, k], mean_power), value[:, cols])
        bound[:, cols] = np.where(on, np.where(use_peak, peak_rating, motors.braking_resistor_power[m][k]),
                                  bound[:, cols])
        basis[:, k] = np.where(on, np.where(use_peak, 2.0, 1.0), 0.0)
    if stats is None:
        return
    regenerated = np.maximum(energy_steps(power, t), 0.0)  # exact for the piecewise-linear power
    for name, figure in (("bus_energy_peak_J", stored), ("capacitor_J", np.broadcast_to(capacity, stored.shape)),
                         ("bus_regenerated_J", regenerated.sum(axis=-1)), ("regen_power_peak_W", peak_regen),
                         ("resistor_energy_J", burnt), ("resistor_power_W", burnt / (t[-1] - t[0])),
                         ("resistor_fitted", np.broadcast_to(resistor.astype(float), stored.shape)),
                         ("regeneration_basis", basis), ("bus_net_J", net)):
        stats[name][:, c] = figure


def _life(task: JointTask, gearboxes: Gearboxes, g: NDArray[np.intp], c: NDArray[np.intp] | slice, safety: float,
          conditions: Conditions, value: NDArray, bound: NDArray, stats: dict[str, NDArray] | None) -> None:
    """The gearbox life of gearboxes ``g`` into the columns ``c`` of ``value``, ``bound`` (and ``stats``): with the
    input speed n = |G·q̇|, n_av = |G|·⟨|q̇|⟩ and T_av = (⟨|q̇|·T³⟩/⟨|q̇|⟩)^⅓, which does not depend on G."""
    w = task.weight
    speed = np.abs(task.qd)  # (T,) joint speed: the gearbox's input is |G| times it
    torque = safety * np.abs(task.tau)  # (L, T) output torque
    travel = float(w @ speed)
    G = np.abs(gearboxes.ratio[g])
    n_av = G * travel / w.sum()  # (g,)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_av = (np.cbrt(torque**3 @ (w * speed) / travel) if travel > 0 else np.zeros(torque.shape[0]))[:, None]
        t_av = t_av * np.ones(G.size)  # (L, g)
        t_n, n_n, l_n = gearboxes.rated_torque[g], gearboxes.rated_input_speed[g], gearboxes.rated_life[g]
        l10 = l_n * (n_n / n_av) * (t_n / t_av) ** 3 / 5 if travel > 0 else np.full(t_av.shape, np.inf)
        # a rating: the binding one of T_av ≤ T_N, n_av ≤ n_N, required ≤ L_n (as value, limit)
        ratios = np.stack(np.broadcast_arrays(t_n / t_av, n_n / n_av, l_n / conditions.required_life + 0 * t_av))
    strain = gearboxes.life_basis[g] == LIFE_BASES["strain-wave"]
    required = conditions.required_life
    which = np.nan_to_num(ratios, nan=np.inf).argmin(axis=0)  # (L, g)
    pairs: list[tuple[NDArray | float, NDArray]] = [(t_av, t_n), (n_av, n_n), (required, l_n)]
    rating_value = np.choose(which, [np.broadcast_to(np.asarray(v), t_av.shape) for v, _ in pairs])
    rating_limit = np.choose(which, [np.broadcast_to(lim, t_av.shape) for _, lim in pairs])
    value[:, c] = np.where(strain, required, rating_value)
    bound[:, c] = np.where(strain, l10, rating_limit)
    if stats is not None:
        for name, figure in (("life_h", np.where(strain, l10, l_n + 0 * t_av)),
                             ("life_T_av_Nm", t_av), ("life_n_av", np.broadcast_to(n_av, t_av.shape)),
                             ("life_basis", np.broadcast_to(gearboxes.life_basis[g], t_av.shape)),
                             ("life_binding", np.where(strain, -1.0, which).astype(float))):
            stats[name][:, c] = figure


#: The screen's allowance for its winding bound: the mean losses it takes from Simpson's rule on the samples,
#: the exact model from the knots' piecewise-linear losses (trapezoids), which differ by far less than this share.
SCREEN_ALLOWANCE = 1e-3


def screen_bounds(task: JointTask, motors: Motors, gearboxes: Gearboxes, safety: float, conditions: Conditions,
                  rms_low: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """Upper bounds ``(M, B)`` of the ratios of this module's checks for every pair, for the selection's screen
    (:func:`armlab.sizing.select.screen`), given a lower bound ``rms_low`` ``(M, B)`` of each pair's RMS motor
    torque: exact for the inertia ratio, the brake and the gearbox life (they need no motor torque); the currents'
    and the winding's from ``rms_low`` (the peak current is at least the RMS one, the winding's peak rise at least
    that of the mean losses, less :data:`SCREEN_ALLOWANCE`). A check without its data: no bound (+inf)."""
    G, J_g = gearboxes.ratio[None, :], gearboxes.input_inertia[None, :]
    limit = np.where(np.isnan(motors.max_inertia_ratio), INERTIA_RATIO, motors.max_inertia_ratio)[:, None]
    inertia = (task.inertia.max() / G**2 + J_g) / motors.rotor_inertia[:, None]
    brake = _ratio(motors.brake_torque[:, None], conditions.brake_factor * np.abs(task.static).max() / np.abs(G))
    B = len(gearboxes)
    value, bound = np.full((task.tau.shape[0], B), np.nan), np.full((task.tau.shape[0], B), np.nan)
    _life(task, gearboxes, np.arange(B), slice(None), safety, conditions, value, bound, None)
    rated = ~np.isnan(gearboxes.life_basis) & ~np.isnan(gearboxes.rated_life) & ~np.isnan(gearboxes.rated_input_speed)
    life = np.where(rated, _ratio(bound, value).min(axis=0), np.inf)[None, :]
    current = safety * rms_low / motors.torque_constant[:, None]  # a lower bound of the RMS current (A)
    r_hot = motors.resistance * (1 + ALPHA_CU * (motors.max_winding_temperature - RESISTANCE_AT))
    gain = motors.thermal_resistance_winding + motors.thermal_resistance_housing
    rise = (gain * 1.5 * r_hot)[:, None] * current**2 * (1 - SCREEN_ALLOWANCE)
    bounds = [_ratio(limit, inertia), brake, life, _ratio(motors.drive_continuous_current[:, None], current),
              _ratio(motors.drive_peak_current[:, None], current),
              _ratio((motors.max_winding_temperature - conditions.ambient)[:, None], rise)]
    return [np.nan_to_num(np.broadcast_to(b, inertia.shape), nan=np.inf, posinf=np.inf) for b in bounds]
