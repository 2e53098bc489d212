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
  ``gearbox speed``: max |ω_m| ≤ its maximum input speed.

Each check's ratio limit / value passes when it is not below 1 (:func:`armlab.bounds.below`: a value on its limit
passes); a pair's **margin** is the smallest ratio minus 1 (feasible: every check passes, a margin of 0 up to the
slack).

The screen (Giberti, Cinquemani & Legnani, *Mechatronics* 2010's accelerating factor) bounds the RMS motor
torque from below without the samples: |τ_m| ≥ η·|τ_L + G²J q̈|/G whichever way power flows, so
RMS(τ_m)² ≥ (η/G)²·(b + 2G²J·c + G⁴J²·a) with the cycle's moments a = ⟨q̈²⟩, b = ⟨τ_L²⟩, c = ⟨q̈ τ_L⟩. That
has a ratio G meeting S·RMS ≤ T_rated only if the accelerating factor α = T_e²/J (T_e = T_rated/(S·η)) is at
least the load factor β = 2(c + √(ab)), and then only G² between the roots of J²a x² + (2Jc − T_e²) x + b.
Stage 1 drops the motors whose α with the most favourable gearbox is below β; stage 2 applies the bound, the
speed checks (exact: G·max|q̇|, G·mean|q̇|) and the gearbox's torque checks (exact: they need only τ_L) to each
pair. The screen keeps every pair whose bound is not below :data:`ACCEPTED` (the smallest ratio the full check
accepts) by more than the slack, so it never drops a pair the full check accepts, round-off included
(tests/test_drives_select.py, against brute force).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armlab.bounds import above, allowance, below
from armlab.drives.train import DriveTrain, motor_speed, motor_torque

if TYPE_CHECKING:
    from armlab.sizing.catalogue import Gearboxes, Motors

__all__ = ["ACCEPTED", "CHECKS", "RANKS", "STATS", "Candidate", "Evaluation", "JointSelection", "JointTask",
           "candidate_train", "check_rank", "check_safety_factor", "evaluate", "motor_side", "screen", "select_joint"]

#: The checks, in the order they are reported.
CHECKS = ("RMS", "RMS speed", "peak", "envelope", "speed", "gearbox RMS", "gearbox peak", "gearbox speed")
#: How feasible pairs can be ranked: lightest first, largest margin first, smallest inertia ratio first.
RANKS = ("mass", "margin", "inertia")
#: Candidates fully checked at a time (bounds the working arrays: load cases × samples × CHUNK).
CHUNK = 512
#: Pairs in the first batch of full checks (the next ones double, up to :data:`CHUNK`).
FIRST = 64
#: How many of the nearest infeasible pairs are reported.
NEAREST = 5
#: The smallest ratio limit/value the full check accepts: 1 less the slack (:func:`armlab.bounds.allowance`).
ACCEPTED = 1.0 - float(allowance(1.0))


def check_safety_factor(value: float) -> float:
    """The safety factor as a float; ``ValueError`` unless a finite number ≥ 1."""
    try:
        s = float(value)
    except (TypeError, ValueError):
        s = float("nan")
    if not (np.isfinite(s) and s >= 1):
        raise ValueError(f"safety factor {value!r} is not allowed: a finite number ≥ 1 (1: no oversizing)")
    return s


def check_rank(rank: str) -> str:
    """``rank`` if it is one of :data:`RANKS`; ``ValueError`` otherwise."""
    if rank not in RANKS:
        raise ValueError(f"rank {rank!r} is not allowed: one of {', '.join(RANKS)}")
    return rank


@dataclass(frozen=True)
class JointTask:
    """One joint's load over the cycle: ``tau`` (N·m, joint side) and ``inertia`` (kg·m², M_kk) ``(L, T)`` per
    load case and sample; the joint's ``qd`` (rad/s), ``qdd`` (rad/s²) and the samples' ``weight`` (s) ``(T,)``."""

    tau: NDArray[np.float64]
    inertia: NDArray[np.float64]
    qd: NDArray[np.float64]
    qdd: NDArray[np.float64]
    weight: NDArray[np.float64]

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
    """limit / value, +inf where the value is 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(value > 0, limit / value, np.inf)


#: The per-load-case figures of a candidate (motor side; SI): peak and RMS |τ_m| (N·m), peak and mean |ω_m|
#: (rad/s), peak power (W), energy delivered and regenerated per cycle (J), inertia ratio J_load/(G²·J) min/max.
STATS = ("peak_torque", "rms_torque", "peak_speed", "mean_speed", "peak_power", "energy", "regenerated",
         "inertia_ratio_min", "inertia_ratio_max")


@dataclass(frozen=True)
class Evaluation:
    """Full checks of candidates ``C`` (pair indices ``motor``, ``gearbox`` ``(C,)``): ``ratios``
    ``(len(CHECKS), C)``, each check's worst limit/value over the load cases. With ``describe``: ``stats`` name →
    ``(L, C)`` per load case (:data:`STATS`), and ``values``, ``limits`` ``(len(CHECKS), C)`` each check's value
    (with the safety factor) and limit in its worst case, ``speeds`` ``(C,)`` the speed of the envelope's worst
    operating point; else they are empty."""

    motor: NDArray[np.intp]
    gearbox: NDArray[np.intp]
    ratios: NDArray[np.float64]
    stats: dict[str, NDArray[np.float64]]
    values: NDArray[np.float64]
    limits: NDArray[np.float64]
    speeds: NDArray[np.float64]

    @property
    def margin(self) -> NDArray[np.float64]:
        """Smallest ratio − 1 per candidate ``(C,)``."""
        return self.ratios.min(axis=0) - 1

    @property
    def passed(self) -> NDArray[np.bool_]:
        """Whether each check of each candidate passes, ``(len(CHECKS), C)``: its ratio is not below 1."""
        return ~below(self.ratios, 1.0)

    @property
    def feasible(self) -> NDArray[np.bool_]:
        """Whether every check of each candidate passes, ``(C,)``."""
        return self.passed.all(axis=0)


def evaluate(task: JointTask, motors: Motors, gearboxes: Gearboxes, motor: NDArray[np.intp],
             gearbox: NDArray[np.intp], safety: float, describe: bool = False) -> Evaluation:
    """Every check (and with ``describe`` every figure) of the candidates (``motor[c]``, ``gearbox[c]``) over every
    sample and load case, :data:`CHUNK` candidates at a time."""
    parts = [_evaluate(task, motors, gearboxes, motor[s:s + CHUNK], gearbox[s:s + CHUNK], safety, describe)
             for s in range(0, max(motor.size, 1), CHUNK)]
    return Evaluation(motor, gearbox, np.concatenate([p.ratios for p in parts], axis=1),
                      {k: np.concatenate([p.stats[k] for p in parts], axis=1) for k in parts[0].stats},
                      *(np.concatenate([getattr(p, f) for p in parts], axis=-1)
                        for f in ("values", "limits", "speeds")))


def _evaluate(task: JointTask, motors: Motors, gearboxes: Gearboxes, im: NDArray[np.intp], ig: NDArray[np.intp],
              safety: float, describe: bool) -> Evaluation:
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
    ratio_rows = np.stack([_ratio(limit, value) for value, limit in rows])  # (checks, L, C)
    ratios = ratio_rows.min(axis=1)
    if not describe:
        empty = np.empty((len(CHECKS), 0))
        return Evaluation(im, ig, ratios, {}, empty, empty, np.empty(0))
    power = tau_m * speed[None]
    stats.update(
        peak_speed=one * peak_speed, mean_speed=one * mean_speed, peak_power=power.max(axis=1),
        energy=np.einsum("ltc,t->lc", np.maximum(power, 0.0), w),
        regenerated=np.einsum("ltc,t->lc", np.maximum(-power, 0.0), w),
        inertia_ratio_min=task.inertia.min(axis=1)[:, None] / train.reflected_inertia,
        inertia_ratio_max=task.inertia.max(axis=1)[:, None] / train.reflected_inertia)
    # the envelope check as torque against the envelope at its worst operating point
    at = np.take_along_axis
    worst_t = use.argmax(axis=1)  # (L, C)
    worst_omega = at(np.broadcast_to(omega[None], use.shape), worst_t[:, None], axis=1)[:, 0]  # (L, C)
    worst_limit = motors.envelope(im, worst_omega)
    rows[3] = (safety * at(abs_m, worst_t[:, None], axis=1)[:, 0], worst_limit)
    case = ratio_rows.argmin(axis=1)  # the worst case of each check (checks, C)
    values = at(np.stack([np.broadcast_to(v, (L, C)) for v, _ in rows]), case[:, None], axis=1)[:, 0]
    limits = at(np.stack([np.broadcast_to(lim, (L, C)) for _, lim in rows]), case[:, None], axis=1)[:, 0]
    return Evaluation(im, ig, ratios, stats, values, limits, at(worst_omega, case[3][None], axis=0)[0])


def screen(task: JointTask, motors: Motors, gearboxes: Gearboxes, safety: float) -> tuple[NDArray, NDArray, NDArray]:
    """The screen of every pair (see the module docstring): ``(ratio (M, B), alpha_max (M,), beta (L,))``, ratio the
    smallest of the bounds' limit/value (not below :data:`ACCEPTED`: go on to the full check; −inf: dropped in stage
    1),
    alpha_max each motor's best accelerating factor (1/s²·N·m… = N²·m²/(kg·m²)), beta the load factors."""
    a = task.mean(task.qdd**2)
    b = task.mean(task.tau**2)  # (L,)
    c = task.mean(task.tau * task.qdd)
    beta = 2 * (c + np.sqrt(a * b))
    gb = gearboxes
    alpha_max = (motors.rated_torque / (safety * gb.efficiency.min())) ** 2 / (motors.rotor_inertia
                                                                                + gb.input_inertia.min())
    stage1 = _stage1(alpha_max, beta)
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
    ]
    ratio = np.minimum.reduce(ratios)
    return np.where(stage1[:, None], ratio, -np.inf), alpha_max, beta


def _stage1(alpha_max: NDArray, beta: NDArray) -> NDArray[np.bool_]:
    """The motors ``(M,)`` stage 1 keeps: the RMS check accepts S·RMS up to T_rated/:data:`ACCEPTED`, so α up to
    α_max/ACCEPTED², which must not be below the largest load factor β."""
    return ~below(alpha_max / ACCEPTED**2, beta.max())


def _screened(ratio: NDArray) -> NDArray[np.bool_]:
    """The pairs the screen's ratios (an upper bound of the full check's smallest ratio) keep."""
    return ~below(ratio, ACCEPTED)


@dataclass(frozen=True)
class Candidate:
    """A checked pair: catalogue indices, names, mass (kg, motor + gearbox), margin, per-load-case ``stats``
    (:data:`STATS` → ``(L,)``) and ``failed``: one text per failing check, e.g. "RMS 3.1 N·m > rated 2.6 N·m"."""

    motor: int
    gearbox: int
    motor_name: str
    gearbox_name: str
    ratio: float
    mass: float
    margin: float
    stats: dict[str, NDArray[np.float64]]
    failed: tuple[str, ...]

    @property
    def feasible(self) -> bool:
        """Whether every check passes."""
        return not self.failed


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
          "gearbox speed": ("input speed", "gearbox max", "rpm")}


def _failed(ev: Evaluation, c: int, safety: float) -> tuple[str, ...]:
    out = []
    rpm = 60 / (2 * np.pi)
    passed = ev.passed[:, c]
    for k, check in enumerate(CHECKS):
        if passed[k]:
            continue
        what, limit_name, unit = _UNITS[check]
        scale = rpm if unit == "rpm" else 1.0
        factor = f"{safety:g}×" if unit == "N·m" and safety != 1 else ""
        where = f" at {ev.speeds[c] * rpm:.4g} rpm" if check == "envelope" else ""
        out.append(f"{factor}{what} {ev.values[k, c] * scale:.3g} {unit}{where} > {limit_name} "
                   f"{ev.limits[k, c] * scale:.3g} {unit}")
    return tuple(out)


def _candidates(ev: Evaluation, order: NDArray[np.intp], motors: Motors, gearboxes: Gearboxes,
                safety: float) -> tuple[Candidate, ...]:
    margin = ev.margin
    return tuple(Candidate(int(ev.motor[c]), int(ev.gearbox[c]), motors.name[ev.motor[c]],
                           gearboxes.name[ev.gearbox[c]], float(gearboxes.ratio[ev.gearbox[c]]),
                           float(motors.mass[ev.motor[c]] + gearboxes.mass[ev.gearbox[c]]), float(margin[c]),
                           {k: v[:, c].copy() for k, v in ev.stats.items()}, _failed(ev, c, safety))
                 for c in order)


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
                 rank: str = "mass", keep: int = 10) -> JointSelection:
    """The best ``keep`` feasible pairs of one joint by ``rank`` (:data:`RANKS`) and the :data:`NEAREST` infeasible
    ones with the checks they fail (see the module docstring).

    The pairs past the screen are fully checked in the order of their rank key (mass and inertia ratio are known
    before the check; the margin is bounded above by the screen), :data:`FIRST` first, then twice as many each time
    up to :data:`CHUNK`, until ``keep`` feasible ones are found and no pair left could rank before them (branch and
    bound): the best pairs are the ones a check of every pair would give, without checking the many heavier ones."""
    safety, rank = check_safety_factor(safety), check_rank(rank)
    ratio, alpha_max, beta = screen(task, motors, gearboxes, safety)
    B = len(gearboxes)
    flat = ratio.ravel()
    mass = (motors.mass[:, None] + gearboxes.mass[None, :]).ravel()
    reflected = gearboxes.ratio[None, :] ** 2 * (motors.rotor_inertia[:, None] + gearboxes.input_inertia[None, :])
    inertia = (task.inertia.max() / reflected).ravel()  # the largest inertia ratio of each pair
    survivors = np.flatnonzero(_screened(flat))
    order, bound = _order(rank, survivors, flat, mass, inertia)
    checked, margins, feasible_parts = [], [], []
    start, size = 0, FIRST
    while start < order.size:
        part = order[start:start + size]
        size = min(2 * size, CHUNK)
        checked.append(part)
        ev = evaluate(task, motors, gearboxes, part // B, part % B, safety)
        margins.append(ev.margin)
        feasible_parts.append(ev.feasible)
        start += part.size
        so_far, good = np.concatenate(margins), np.concatenate(feasible_parts)
        ok = np.concatenate(checked)[good]
        if ok.size >= keep and start < order.size:
            true = -so_far[good] if rank == "margin" else bound[ok]  # the rank keys found
            if above(bound[order[start]], np.sort(true)[keep - 1]):  # no pair left can rank among the best keep
                break
    done = np.concatenate(checked) if checked else np.empty(0, dtype=np.intp)
    margin = np.concatenate(margins) if margins else np.empty(0)
    good = np.concatenate(feasible_parts) if feasible_parts else np.empty(0, dtype=bool)
    ok, bad = done[good], done[~good]
    dropped = np.flatnonzero(~_screened(flat))
    near = dropped[np.argsort(-flat[dropped], kind="stable")[:NEAREST]]
    bad_margin = margin[~good]
    nearest_checked = bad[np.argsort(-bad_margin, kind="stable")[:NEAREST]]
    ok_margin = margin[good]
    keys = {"mass": (-ok_margin, mass[ok]), "margin": (mass[ok], -ok_margin), "inertia": (mass[ok], inertia[ok])}
    best = ok[np.lexsort(keys[rank])[:keep]]  # the last key first
    shown = np.concatenate([best, nearest_checked, near])
    ev = evaluate(task, motors, gearboxes, shown // B, shown % B, safety, describe=True)
    candidates = _candidates(ev, np.arange(shown.size), motors, gearboxes, safety)
    feasible = candidates[:best.size]
    others = sorted(candidates[best.size:], key=lambda c: -c.margin)[:NEAREST]
    return JointSelection(joint, feasible, int(ok.size), tuple(others), int(flat.size),
                          int(_stage1(alpha_max, beta).sum()), int(survivors.size), int(done.size),
                          beta)
