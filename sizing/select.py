"""Choosing one joint's motor and gearbox from catalogues: a fast screen of every pair, full checks of the survivors.

A candidate is a motor × gearbox pair. With the gearbox's ratio G, efficiency η and input inertia J_g and the
motor's rotor inertia J_m, the drive train is :func:`candidate_train` (G, J = J_m + J_g, η, no friction of
its own), so the joint-side torque is τ_L + G²·J·q̈ and the motor torque and speed are
:func:`~armlab.drives.train.motor_torque` and :func:`~armlab.drives.train.motor_speed` of it, for every sample
of the cycle and every load case, vectorised over the candidates. A pair is **feasible** when, with the safety
factor S on every torque (speeds as they are) and for every load case:

* ``RMS``: S·RMS(τ_m) ≤ the motor's rated torque; ``RMS speed``: mean |ω_m| ≤ its rated speed (the RMS point
  lies in the continuous region);
* ``peak``: S·max |τ_m| ≤ its peak torque; ``envelope``: S·|τ_m| ≤ the torque–speed envelope at every
  operating point (:meth:`~armlab.sizing.catalogue.Motors.envelope`); ``speed``: max |ω_m| ≤ its maximum speed;
* ``gearbox RMS`` / ``gearbox peak``: S·RMS(τ_L), S·max |τ_L| ≤ the gearbox's rated / peak output torque;
  ``gearbox speed``: max |ω_m| ≤ its maximum input speed;
* the checks of :mod:`armlab.sizing.checks` (inertia ratio, voltage at the bus voltage, the drive's current and
  I²t, winding temperature, regeneration, brake, gearbox life) where the catalogues give what they need; a check
  without its data is "not checked (no column X)" (its ratio NaN), never passed.

Each check's ratio limit / value; a pair's **margin** is the smallest ratio of the checks made minus 1 (≥ 0:
feasible); the check with that ratio **binds**. The checks of :mod:`~armlab.sizing.checks` are computed for the
pairs that pass the torque and speed checks (the others fail already) and, for the pairs reported, for all.

The screen (Giberti, Cinquemani & Legnani, *Mechatronics* 2010's accelerating factor) bounds the RMS motor
torque from below without the samples: |τ_m| ≥ η·|τ_L + G²J q̈|/G whichever way power flows, so
RMS(τ_m)² ≥ (η/G)²·(b + 2G²J·c + G⁴J²·a) with the cycle's moments a = ⟨q̈²⟩, b = ⟨τ_L²⟩, c = ⟨q̈ τ_L⟩. That
has a ratio G meeting S·RMS ≤ T_rated only if the accelerating factor α = T_e²/J (T_e = T_rated/(S·η)) is at
least the load factor β = 2(c + √(ab)), and then only G² between the roots of J²a x² + (2Jc − T_e²) x + b.
Stage 1 drops the motors whose α with the most favourable gearbox is below β; stage 2 applies the bound, the
speed checks (exact: G·max|q̇|, G·mean|q̇|) and the gearbox's torque checks (exact: they need only τ_L) to each
pair. The screen never drops a pair the full check accepts (tests/test_drives_select.py, against brute force).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armlab.bounds import above, below
from armlab.drives.train import DriveTrain, motor_speed, motor_torque
from armlab.limits import LIMITS, allowed
from armlab.sizing.checks import DRIVE_CHECKS, Conditions, drive_checks, missing_column, number, screen_bounds, within
from armlab.values import shown

if TYPE_CHECKING:
    from armlab.sizing.catalogue import Gearboxes, Motors
    from armlab.sizing.duty import CycleSamples
    from armlab.sizing.loads import Loads

__all__ = ["CHECKS", "RANKS", "STATS", "TORQUE_CHECKS", "Candidate", "CheckResult", "Evaluation", "JointSelection",
           "JointTask", "candidate_train", "check_rank", "check_safety_factor", "evaluate", "motor_side", "screen",
           "select_joint"]

#: The checks, in the order they are reported: torque and speed, then :data:`armlab.sizing.checks.DRIVE_CHECKS`.
TORQUE_CHECKS = ("RMS", "RMS speed", "peak", "envelope", "speed", "gearbox RMS", "gearbox peak", "gearbox speed")
CHECKS = TORQUE_CHECKS + DRIVE_CHECKS
#: How feasible pairs can be ranked: lightest first, largest margin first, smallest inertia ratio first.
RANKS = ("mass", "margin", "inertia")
#: Candidates fully checked at a time (bounds the working arrays: load cases × samples × CHUNK).
CHUNK = 512
#: Pairs in the first batch of full checks (the next ones double, up to :data:`CHUNK`).
FIRST = 64
#: How many of the nearest infeasible pairs are reported.
NEAREST = 5


def check_safety_factor(value: float) -> float:
    """The safety factor as a float; ``ValueError`` unless a number in :data:`~armlab.limits.LIMITS`' range
    (1 … 100)."""
    try:
        s = float(value)
    except (TypeError, ValueError):
        s = float("nan")
    limit = LIMITS["safety_factor"]
    if not (np.isfinite(s) and limit.low <= s <= limit.high):  # not a bound: a user's value, against its range
        raise ValueError(f"safety factor {shown(value)} is not allowed: {allowed('safety_factor')} (1: no "
                         "oversizing)")
    return s


def check_rank(rank: str) -> str:
    """``rank`` if it is one of :data:`RANKS`; ``ValueError`` otherwise."""
    if rank not in RANKS:
        raise ValueError(f"rank {rank!r} is not allowed: one of {', '.join(RANKS)}")
    return rank


@dataclass(frozen=True)
class JointTask:
    """One joint's load over the cycle: ``tau`` (N·m, joint side), ``inertia`` (kg·m², M_kk) and ``static`` (N·m,
    the gravity torque τ_g(q), joint side) ``(L, T)`` per load case and sample; the joint's ``qd`` (rad/s),
    ``qdd`` (rad/s²) and the samples' ``weight`` (s) ``(T,)``; the cycle's knots ``knot_sample``, ``knot_time``
    ``(K,)`` (:class:`~armlab.sizing.duty.CycleSamples`)."""

    tau: NDArray[np.float64]
    inertia: NDArray[np.float64]
    qd: NDArray[np.float64]
    qdd: NDArray[np.float64]
    weight: NDArray[np.float64]
    static: NDArray[np.float64]
    knot_sample: NDArray[np.intp]
    knot_time: NDArray[np.float64]

    @classmethod
    def of(cls, samples: CycleSamples, loads: Loads, k: int) -> JointTask:
        """Joint ``k``'s (0-based) task from a cycle's samples and the loads along it."""
        return cls(loads.tau[..., k], loads.inertia[..., k], samples.qd[:, k], samples.qdd[:, k], samples.weight,
                   loads.static[..., k], samples.knot_sample, samples.knot_time)

    def mean(self, values: NDArray[np.float64]) -> NDArray[np.float64]:
        """The cycle's time average of ``values`` ``(..., T)`` over its last axis: Σ w·v / Σ w."""
        return values @ self.weight / self.weight.sum()


def candidate_train(motors: Motors, gearboxes: Gearboxes, motor: NDArray[np.intp],
                    gearbox: NDArray[np.intp]) -> DriveTrain:
    """The drive train of the candidates (``motor[c]``, ``gearbox[c]``) ``(C,)``: G, J = J_m + J_g, η and no
    friction of its own (the joints' friction is in the load τ_L already: :func:`armlab.sizing.loads.joint_loads`)."""
    zeros = np.zeros(np.shape(motor))
    return DriveTrain(gearboxes.ratio[gearbox], motors.rotor_inertia[motor] + gearboxes.input_inertia[gearbox],
                      gearboxes.efficiency[gearbox], zeros, zeros)


def motor_side(train: DriveTrain, tau: NDArray[np.float64], qd: NDArray[np.float64],
               qdd: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Motor torque (N·m) and signed motor speed (rad/s) of load torques ``tau`` at rates ``qd``, ``qdd``, all
    broadcast against the drive train's last axis: τ_m = :func:`motor_torque` of τ_L + G²·J·q̈ (+ its friction)."""
    return motor_torque(train, tau + train.torque(qd, qdd), qd), motor_speed(train, qd)


def _ratio(limit: NDArray, value: NDArray) -> NDArray:
    """limit / value, +inf where the value is 0, NaN where either is (a check not made)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.isnan(limit) | np.isnan(value), np.nan, np.where(value > 0, limit / value, np.inf))


#: The per-load-case figures of a candidate (motor side; SI): peak and RMS |τ_m| (N·m), peak and mean |ω_m|
#: (rad/s), peak power (W), mechanical energy delivered and regenerated per cycle (J), the inertia ratio
#: (J_load/G² + J_g)/J_m min/max (:mod:`armlab.sizing.checks`); the checks' own figures follow these.
STATS = ("peak_torque", "rms_torque", "peak_speed", "mean_speed", "peak_power", "energy", "regenerated",
         "inertia_ratio_min", "inertia_ratio_max")


@dataclass(frozen=True)
class Evaluation:
    """Full checks of candidates ``C`` (pair indices ``motor``, ``gearbox`` ``(C,)``): ``ratios``
    ``(len(CHECKS), C)``, each check's worst limit/value over the load cases. With ``describe``: ``stats`` name →
    ``(L, C)`` per load case (:data:`STATS`), and ``values``, ``limits`` ``(len(CHECKS), C)`` each check's value
    (with the safety factor) and limit in its worst case, ``speeds`` ``(C,)`` the speed of the envelope's worst
    operating point, ``cases`` ``(len(CHECKS), C)`` each check's worst load case; else they are empty."""

    motor: NDArray[np.intp]
    gearbox: NDArray[np.intp]
    ratios: NDArray[np.float64]
    stats: dict[str, NDArray[np.float64]]
    values: NDArray[np.float64]
    limits: NDArray[np.float64]
    speeds: NDArray[np.float64]
    cases: NDArray[np.intp]

    @property
    def margin(self) -> NDArray[np.float64]:
        """Smallest ratio of the checks made − 1 per candidate ``(C,)``."""
        return np.nanmin(self.ratios, axis=0) - 1

    @property
    def passed(self) -> NDArray[np.bool_]:
        """Whether each check of each candidate passes, ``(len(CHECKS), C)``: its ratio is not below 1
        (:func:`armlab.bounds.below`), or it was not made (NaN: no data; reported as such, never ranked on)."""
        return np.isnan(self.ratios) | ~below(self.ratios, 1.0)

    @property
    def feasible(self) -> NDArray[np.bool_]:
        """Whether every check made of each candidate passes, ``(C,)``."""
        return self.passed.all(axis=0)


def evaluate(task: JointTask, motors: Motors, gearboxes: Gearboxes, motor: NDArray[np.intp],
             gearbox: NDArray[np.intp], safety: float, describe: bool = False,
             conditions: Conditions | None = None) -> Evaluation:
    """Every check (and with ``describe`` every figure) of the candidates (``motor[c]``, ``gearbox[c]``) over every
    sample and load case, :data:`CHUNK` candidates at a time; ``conditions`` default :class:`Conditions()`."""
    conditions = conditions or Conditions()
    parts = [_evaluate(task, motors, gearboxes, motor[s:s + CHUNK], gearbox[s:s + CHUNK], safety, describe,
                       conditions) for s in range(0, max(motor.size, 1), CHUNK)]
    return Evaluation(motor, gearbox, np.concatenate([p.ratios for p in parts], axis=1),
                      {k: np.concatenate([p.stats[k] for p in parts], axis=1) for k in parts[0].stats},
                      *(np.concatenate([getattr(p, f) for p in parts], axis=-1)
                        for f in ("values", "limits", "speeds", "cases")))


def _evaluate(task: JointTask, motors: Motors, gearboxes: Gearboxes, im: NDArray[np.intp], ig: NDArray[np.intp],
              safety: float, describe: bool, conditions: Conditions) -> Evaluation:
    L, C = task.tau.shape[0], im.size
    train = candidate_train(motors, gearboxes, im, ig)
    # (L, T, 1) and (T, 1) against the candidates (C,): τ_m (L, T, C), ω_m (T, C)
    tau_m, speed = motor_side(train, task.tau[:, :, None], task.qd[:, None], task.qdd[:, None])
    omega = np.abs(speed)
    abs_m = np.abs(tau_m)
    w = task.weight
    peak_speed, mean_speed = omega.max(axis=0), w @ omega / w.sum()  # (C,)
    stats = {"peak_torque": abs_m.max(axis=1),
             "rms_torque": np.sqrt(np.einsum("ltc,ltc,t->lc", tau_m, tau_m, w) / w.sum())}
    envelope = motors.envelope(im, omega)  # (T, C)
    with np.errstate(divide="ignore", invalid="ignore"):
        use = abs_m / envelope  # (L, T, C): the share of the envelope used (inf where it gives nothing)
    use[np.isnan(use)] = np.inf  # 0 N·m where the envelope is 0 (beyond the no-load speed)
    env_use = use.max(axis=1)  # (L, C)
    load_rms = np.sqrt(task.mean(task.tau**2))[:, None] * np.ones(C)  # (L, C)
    load_peak = np.abs(task.tau).max(axis=1)[:, None] * np.ones(C)
    gb, one = gearboxes, np.ones((L, 1))
    rows = [  # (value, limit) per check, each (L, C)
        (safety * stats["rms_torque"], one * motors.rated_torque[im]),
        (one * mean_speed, one * motors.rated_speed[im]),
        (safety * stats["peak_torque"], one * motors.peak_torque[im]),
        (safety * env_use, one),
        (one * peak_speed, one * motors.max_speed[im]),
        (safety * load_rms, one * gb.rated_torque[ig]),
        (safety * load_peak, one * gb.peak_torque[ig]),
        (one * peak_speed, one * gb.max_input_speed[ig]),
    ]
    torque_rows = np.stack([_ratio(limit, value) for value, limit in rows])  # (checks, L, C)
    floor = torque_rows.min(axis=(0, 1))  # (C,) the smallest ratio so far
    active = np.ones(C, dtype=bool) if describe else ~below(floor, 1.0)
    drive = drive_checks(task, motors, gearboxes, im, ig, tau_m, speed, safety, conditions, active, describe,
                         stats["peak_torque"], stats["rms_torque"], None if describe else floor)
    rows += [drive.rows[check] for check in DRIVE_CHECKS]
    ratio_rows = np.concatenate([torque_rows, np.stack([_ratio(limit, value) for value, limit in rows[len(
        TORQUE_CHECKS):]])])
    ratios = ratio_rows.min(axis=1)
    if not describe:
        empty = np.empty((len(CHECKS), 0))
        return Evaluation(im, ig, ratios, {}, empty, empty, np.empty(0), np.empty((len(CHECKS), 0), dtype=np.intp))
    power = tau_m * speed[None]
    stats.update(
        peak_speed=one * peak_speed, mean_speed=one * mean_speed, peak_power=power.max(axis=1),
        energy=np.einsum("ltc,t->lc", np.maximum(power, 0.0), w),
        regenerated=np.einsum("ltc,t->lc", np.maximum(-power, 0.0), w), **drive.stats)
    # the envelope check as torque against the envelope at its worst operating point
    at = np.take_along_axis
    worst_t = use.argmax(axis=1)  # (L, C)
    worst_omega = at(np.broadcast_to(omega[None], use.shape), worst_t[:, None], axis=1)[:, 0]  # (L, C)
    worst_limit = motors.envelope(im, worst_omega)
    rows[3] = (safety * at(abs_m, worst_t[:, None], axis=1)[:, 0], worst_limit)
    case = np.nan_to_num(ratio_rows, nan=np.inf).argmin(axis=1)  # the worst case of each check (checks, C)
    values = at(np.stack([np.broadcast_to(v, (L, C)) for v, _ in rows]), case[:, None], axis=1)[:, 0]
    limits = at(np.stack([np.broadcast_to(lim, (L, C)) for _, lim in rows]), case[:, None], axis=1)[:, 0]
    return Evaluation(im, ig, ratios, stats, values, limits, at(worst_omega, case[3][None], axis=0)[0], case)


def screen(task: JointTask, motors: Motors, gearboxes: Gearboxes, safety: float,
           conditions: Conditions | None = None) -> tuple[NDArray, NDArray, NDArray]:
    """The screen of every pair (see the module docstring): ``(ratio (M, B), alpha_max (M,), beta (L,))``, ratio the
    smallest of the bounds' limit/value (not below 1 by :func:`armlab.bounds.below`: go on to the full check; −inf:
    dropped in stage 1),
    alpha_max each motor's best accelerating factor (1/s²·N·m… = N²·m²/(kg·m²)), beta the load factors; with the
    bounds of :func:`armlab.sizing.checks.screen_bounds` for the checks of :mod:`armlab.sizing.checks`."""
    a = task.mean(task.qdd**2)
    b = task.mean(task.tau**2)  # (L,)
    c = task.mean(task.tau * task.qdd)
    beta = 2 * (c + np.sqrt(a * b))
    gb = gearboxes
    alpha_max = (motors.rated_torque / (safety * gb.efficiency.min())) ** 2 / (motors.rotor_inertia
                                                                                + gb.input_inertia.min())
    stage1 = ~below(alpha_max, beta.max())
    G = gb.ratio[None, :]
    J = motors.rotor_inertia[:, None] + gb.input_inertia[None, :]
    G2J = G**2 * J
    rms_sq = b[:, None, None] + 2 * G2J * c[:, None, None] + G2J**2 * a  # (L, M, B) ≥ RMS(τ_joint)²
    rms_low = (gb.efficiency / G) * np.sqrt(np.maximum(rms_sq.max(axis=0), 0.0))
    top, mean = np.abs(task.qd).max(), task.mean(np.abs(task.qd))
    load_rms, load_peak = np.sqrt(b.max()), np.abs(task.tau).max()
    ratios = [
        _ratio(motors.rated_torque[:, None], safety * rms_low),
        _ratio(motors.peak_torque[:, None], safety * rms_low),
        _ratio(motors.rated_speed[:, None], G * mean),
        _ratio(motors.max_speed[:, None], G * top),
        _ratio(gb.max_input_speed[None, :], G * top) * np.ones_like(J),
        _ratio(gb.rated_torque[None, :], safety * load_rms * np.ones_like(J)),
        _ratio(gb.peak_torque[None, :], safety * load_peak * np.ones_like(J)),
        *screen_bounds(task, motors, gearboxes, safety, conditions or Conditions(), rms_low),
    ]
    ratio = np.minimum.reduce(ratios)
    return np.where(stage1[:, None], ratio, -np.inf), alpha_max, beta


@dataclass(frozen=True)
class CheckResult:
    """One check of a pair in its worst load case ``case`` (index): ``ratio`` limit/value (NaN: not checked, for
    the reason in ``note``), ``value`` and ``limit`` as text ("RMS 3.1 N·m", "rated 2.6 N·m"), ``failure`` the
    text when it fails ("RMS 3.1 N·m > rated 2.6 N·m")."""

    name: str
    ratio: float
    value: str
    limit: str
    failure: str
    case: int
    note: str = ""

    @property
    def checked(self) -> bool:
        """Whether the check was made (the catalogues had its data)."""
        return not np.isnan(self.ratio)

    @property
    def margin(self) -> float:
        """ratio − 1 (NaN: not checked)."""
        return self.ratio - 1


@dataclass(frozen=True)
class Candidate:
    """A checked pair: catalogue indices, names, mass (kg, motor + gearbox), margin, per-load-case ``stats``
    (:data:`STATS` and the checks' figures → ``(L,)``), ``checks`` one :class:`CheckResult` per check of
    :data:`CHECKS` and ``failed``: one text per failing check, e.g. "RMS 3.1 N·m > rated 2.6 N·m"."""

    motor: int
    gearbox: int
    motor_name: str
    gearbox_name: str
    ratio: float
    mass: float
    margin: float
    stats: dict[str, NDArray[np.float64]]
    failed: tuple[str, ...]
    checks: tuple[CheckResult, ...] = field(default=())

    @property
    def feasible(self) -> bool:
        """Whether every check passes."""
        return not self.failed

    @property
    def binding(self) -> CheckResult | None:
        """The check with the smallest ratio: the one that decides the margin."""
        made = [c for c in self.checks if c.checked]
        return min(made, key=lambda c: c.ratio) if made else None

    @property
    def unchecked(self) -> tuple[CheckResult, ...]:
        """The checks not made, each with its reason."""
        return tuple(c for c in self.checks if not c.checked)


@dataclass(frozen=True)
class JointSelection:
    """One joint's selection: the best ``feasible`` pairs ranked (best first; ``feasible_count`` found feasible
    among the ``checked``), the ``nearest`` infeasible ones (closest first) and the screen's counts: ``pairs`` in
    all, ``motors_screened`` (passing stage 1), ``screened`` (stage 2), the load factors ``beta`` (L,)."""

    joint: str
    feasible: tuple[Candidate, ...]
    feasible_count: int
    nearest: tuple[Candidate, ...]
    pairs: int
    motors_screened: int
    screened: int
    checked: int
    beta: NDArray[np.float64]

    @property
    def chosen(self) -> Candidate | None:
        """The best feasible pair, ``None`` if there is none."""
        return self.feasible[0] if self.feasible else None


_UNITS = {"RMS": ("RMS", "rated", "N·m"), "RMS speed": ("mean speed", "rated speed", "rpm"),
          "peak": ("peak", "peak", "N·m"), "envelope": ("torque", "envelope", "N·m"),
          "speed": ("speed", "max", "rpm"), "gearbox RMS": ("output RMS", "gearbox rated", "N·m"),
          "gearbox peak": ("output peak", "gearbox peak", "N·m"),
          "gearbox speed": ("input speed", "gearbox max", "rpm"),
          "inertia ratio": ("inertia ratio", "max", ""), "current peak": ("peak current", "drive peak", "A"),
          "current RMS": ("RMS current", "drive continuous", "A"),
          "I²t": ("I²t current", "drive continuous", "A"), "brake": ("K·T_static/G", "holding brake", "N·m")}
RPM_PER = 60 / (2 * np.pi)


def _texts(check: str, value: float, limit: float, safety: float, speed: float, stat: dict[str, float],
           conditions: Conditions) -> tuple[str, str, str]:
    """(value, limit, failure) texts of one check (module docstring); ``stat`` the pair's figures in the check's
    worst load case, ``speed`` the envelope's worst operating point (rad/s)."""
    n = number
    if check in ("voltage", "winding temperature", "regeneration", "gearbox life"):
        if check == "voltage":
            v = f"voltage {n(value)} V at {n(stat['voltage_speed'] * RPM_PER)} rpm"
            lim = f"available {n(limit)} V (bus {n(limit * np.sqrt(2))} V DC)"
        elif check == "winding temperature":
            v = f"winding {n(conditions.ambient + value)} °C (periodic peak)"
            lim = f"limit {n(conditions.ambient + limit)} °C"
        elif check == "regeneration":
            basis = stat["regeneration_basis"]
            if basis == 0:
                v = (f"bus energy {n(value)} J" if np.isfinite(value) else
                     f"bus energy growing by {n(stat['bus_net_J'])} J a cycle")
                lim = f"capacitors {n(limit)} J"
                if stat["resistor_fitted"] == 0 and not within(value, limit):
                    lim += (f" (no braking resistor, column braking_resistor_W: one of ≥ {n(stat['resistor_power_W'])}"
                            f" W mean, ≥ {n(stat['regen_power_peak_W'])} W peak is needed)")
            else:
                kind = "mean" if basis == 1 else "peak"
                v, lim = f"braking resistor {kind} {n(value)} W", f"its {kind} rating {n(limit)} W"
        else:
            binding = stat["life_binding"]
            if binding < 0:
                v, lim = f"required life {n(value)} h", f"L10 {n(limit)} h"
                return v, lim, f"{v} > {lim}"
            v, lim = [(f"mean output torque {n(value)} N·m", f"rated {n(limit)} N·m"),
                      (f"mean input speed {n(value * RPM_PER)} rpm", f"rated {n(limit * RPM_PER)} rpm"),
                      (f"required life {n(value)} h", f"rated life {n(limit)} h")][int(binding)]
        return v, lim, f"{v} > {lim}"
    what, limit_name, unit = _UNITS[check]
    scale = RPM_PER if unit == "rpm" else 1.0
    factor = f"{safety:g}×" if unit in ("N·m", "A") and safety != 1 and check != "brake" else ""
    where = f" at {n(speed * RPM_PER)} rpm" if check == "envelope" else ""
    unit_text = f" {unit}" if unit else ""
    v = f"{factor}{what} {n(value * scale)}{unit_text}{where}"
    lim = f"{limit_name} {n(limit * scale)}{unit_text}"
    return v, lim, f"{v} > {lim}"


def _results(ev: Evaluation, c: int, safety: float, motors: Motors, gearboxes: Gearboxes,
             conditions: Conditions) -> tuple[CheckResult, ...]:
    out = []
    for k, check in enumerate(CHECKS):
        case = int(ev.cases[k, c])
        ratio = float(ev.ratios[k, c])
        if np.isnan(ratio):
            column = missing_column(check, motors, gearboxes, int(ev.motor[c]), int(ev.gearbox[c]), conditions)
            out.append(CheckResult(check, ratio, "", "", "", case, f"not checked (no column {column})"))
            continue
        stat = {name: float(v[case, c]) for name, v in ev.stats.items()}
        value, limit, failure = _texts(check, float(ev.values[k, c]), float(ev.limits[k, c]), safety,
                                       float(ev.speeds[c]), stat, conditions)
        out.append(CheckResult(check, ratio, value, limit, failure, case))
    return tuple(out)


def _candidates(ev: Evaluation, order: NDArray[np.intp], motors: Motors, gearboxes: Gearboxes,
                safety: float, conditions: Conditions) -> tuple[Candidate, ...]:
    margin = ev.margin
    out = []
    for c in order:
        checks = _results(ev, int(c), safety, motors, gearboxes, conditions)
        failed = tuple(r.failure for r in checks if r.checked and below(r.ratio, 1.0))
        out.append(Candidate(int(ev.motor[c]), int(ev.gearbox[c]), motors.name[ev.motor[c]],
                             gearboxes.name[ev.gearbox[c]], float(gearboxes.ratio[ev.gearbox[c]]),
                             float(f"{motors.mass[ev.motor[c]] + gearboxes.mass[ev.gearbox[c]]:.12g}"),
                             float(margin[c]), {k: v[:, c].copy() for k, v in ev.stats.items()}, failed, checks))
    return tuple(out)


def _order(rank: str, survivors: NDArray[np.intp], flat: NDArray, mass: NDArray, inertia: NDArray
           ) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """The survivors in the order they are fully checked, and each pair's rank key's lower bound (smaller is
    better): the exact mass or inertia ratio, and for ``margin`` −(screen ratio − 1) ≤ −margin."""
    if rank == "mass":
        return survivors[np.lexsort((-flat[survivors], mass[survivors]))], mass
    if rank == "inertia":
        return survivors[np.lexsort((mass[survivors], inertia[survivors]))], inertia
    return survivors[np.argsort(-flat[survivors], kind="stable")], 1 - flat


def select_joint(joint: str, task: JointTask, motors: Motors, gearboxes: Gearboxes, safety: float = 1.0,
                 rank: str = "mass", keep: int = 10, conditions: Conditions | None = None) -> JointSelection:
    """The best ``keep`` feasible pairs of one joint by ``rank`` (:data:`RANKS`) and the :data:`NEAREST` infeasible
    ones with the checks they fail (see the module docstring).

    The pairs past the screen are fully checked in the order of their rank key (mass and inertia ratio are known
    before the check; the margin is bounded above by the screen), :data:`FIRST` first, then twice as many each time
    up to :data:`CHUNK`, until ``keep`` feasible ones are found and no pair left could rank before them (branch and
    bound): the best pairs are the ones a check of every pair would give, without checking the many heavier ones."""
    safety, rank = check_safety_factor(safety), check_rank(rank)
    conditions = conditions or Conditions()
    ratio, alpha_max, beta = screen(task, motors, gearboxes, safety, conditions)
    B = len(gearboxes)
    flat = ratio.ravel()
    mass = (motors.mass[:, None] + gearboxes.mass[None, :]).ravel()
    at_motor = task.inertia.max() / gearboxes.ratio[None, :] ** 2 + gearboxes.input_inertia[None, :]
    inertia = (at_motor / motors.rotor_inertia[:, None]).ravel()  # the largest inertia ratio of each pair
    survivors = np.flatnonzero(~below(flat, 1.0))
    order, bound = _order(rank, survivors, flat, mass, inertia)
    checked, margins = [], []
    start, size = 0, FIRST
    while start < order.size:
        part = order[start:start + size]
        size = min(2 * size, CHUNK)
        checked.append(part)
        margins.append(evaluate(task, motors, gearboxes, part // B, part % B, safety, conditions=conditions).margin)
        start += part.size
        so_far = np.concatenate(margins)
        ok = np.concatenate(checked)[so_far >= 0]
        if ok.size >= keep and start < order.size:
            true = -so_far[so_far >= 0] if rank == "margin" else bound[ok]  # the rank keys found
            if above(bound[order[start]], np.sort(true)[keep - 1]):  # no pair left can rank among the best keep
                break
    done = np.concatenate(checked) if checked else np.empty(0, dtype=np.intp)
    margin = np.concatenate(margins) if margins else np.empty(0)
    good = ~below(margin, 0.0)
    ok, bad = done[good], done[~good]
    dropped = np.flatnonzero(below(flat, 1.0))
    near = dropped[np.argsort(-flat[dropped], kind="stable")[:NEAREST]]
    bad_margin = margin[~good]
    nearest_checked = bad[np.argsort(-bad_margin, kind="stable")[:NEAREST]]
    ok_margin = margin[good]
    keys = {"mass": (-ok_margin, mass[ok]), "margin": (mass[ok], -ok_margin), "inertia": (mass[ok], inertia[ok])}
    best = ok[np.lexsort(keys[rank])[:keep]]  # the last key first
    shown = np.concatenate([best, nearest_checked, near])
    ev = evaluate(task, motors, gearboxes, shown // B, shown % B, safety, describe=True, conditions=conditions)
    candidates = _candidates(ev, np.arange(shown.size), motors, gearboxes, safety, conditions)
    feasible = candidates[:best.size]
    others = sorted(candidates[best.size:], key=lambda c: -c.margin)[:NEAREST]
    return JointSelection(joint, feasible, int(ok.size), tuple(others), int(flat.size),
                          int((~below(alpha_max, beta.max())).sum()), int(survivors.size), int(done.size),
                          beta)
