"""What a sizing writes: ``sizing.csv`` (per joint and load case, the chosen drive's figures), ``sizing.md`` (the
choice, every check with its value, limit and margin or why it was not made, the winding's duty type and
temperature, the DC link's energy, the runners-up, the nearest infeasible pairs with the checks they fail, the mass
iteration) and one torque–speed figure per joint (``torque_speed_JOINT.png``: the chosen motor's envelope from its
catalogue line and at the bus voltage, every load case's operating points and its RMS point).
:func:`summary_lines` is what ``armlab size`` prints. Values are shown to 3 significant digits (4 for masses),
margins as percentages, "≫ 100 %" from :data:`~armlab.sizing.checks.MARGIN_SHOWN` on.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armlab.files import OutputFolder, csv_text
from armlab.sizing.checks import ALPHA_CU, RESISTANCE_AT, duty_type, number, percent
from armlab.sizing.select import STATS, Candidate, JointSelection, candidate_train, motor_side

if TYPE_CHECKING:
    from armlab.sizing.sizing import Sizing

__all__ = ["CSV_HEADERS", "figure_names", "sizing_folder", "sizing_markdown", "summary_lines", "torque_speed_figure",
           "voltage_envelope", "write_sizing"]

RPM = 60 / (2 * np.pi)
#: The figures of sizing.csv after its first columns, as (column, stat): SI, each named with its side (motor:
#: at the motor shaft; joint: at the gearbox output) and unit; speeds in rad/s.
CSV_FIGURES = (
    ("motor_peak_torque_Nm", "peak_torque"), ("motor_rms_torque_Nm", "rms_torque"),
    ("motor_peak_speed_rad_s", "peak_speed"), ("motor_mean_speed_rad_s", "mean_speed"),
    ("motor_peak_power_W", "peak_power"), ("motor_energy_J", "energy"), ("motor_regenerated_J", "regenerated"),
    ("inertia_ratio_min", "inertia_ratio_min"), ("inertia_ratio_max", "inertia_ratio_max"),
    ("winding_peak_C", "winding_peak_C"), ("copper_loss_W", "copper_loss_W"),
    ("bus_energy_peak_J", "bus_energy_peak_J"), ("capacitor_J", "capacitor_J"),
    ("bus_regenerated_J", "bus_regenerated_J"), ("braking_resistor_W", "resistor_power_W"),
    ("joint_static_torque_Nm", "static_torque"), ("gearbox_life_h", "life_h"),
)
#: The columns of sizing.csv (SI; speeds in rad/s; NaN cells empty where a check was not made).
CSV_HEADERS = ("joint", "load_case", "motor", "gearbox", "ratio", "drive_mass_kg", "margin", "binding_check",
               *(column for column, _ in CSV_FIGURES))


def _tag(joint: str) -> str:
    return "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in joint)


def figure_names(sizing: Sizing) -> list[str]:
    """The torque–speed figures' file names, one per joint."""
    return [f"torque_speed_{_tag(j.joint)}.png" for j in sizing.joints]


def sizing_folder(out: str | Path) -> OutputFolder:
    """The output folder of a sizing (:class:`~armlab.files.OutputFolder`): an earlier one is replaced."""

    def is_previous(folder: Path) -> bool:
        names = {p.name for p in folder.iterdir()}
        return "sizing.csv" in names and all(n.startswith("torque_speed_") or n in ("sizing.csv", "sizing.md")
                                             for n in names)

    return OutputFolder(Path(out).expanduser(), is_previous, "an armlab sizing folder (sizing.csv, sizing.md and "
                                                            "torque–speed figures only)")


def _cell(value: float) -> float | None:
    return None if np.isnan(value) else float(value)


def _csv_rows(sizing: Sizing) -> list[list[object]]:
    rows: list[list[object]] = []
    for j in sizing.joints:
        c = j.chosen
        for k, case in enumerate(sizing.cases):
            if c is None:
                rows.append([j.joint, case.label, *[None] * (len(CSV_HEADERS) - 2)])
                continue
            binding = c.binding
            rows.append([j.joint, case.label, c.motor_name, c.gearbox_name, c.ratio, c.mass, c.margin,
                         binding.name if binding else None, *(_cell(c.stats[stat][k]) for _, stat in CSV_FIGURES)])
    return rows


def _pair(c: Candidate) -> str:
    return f"{c.motor_name} + {c.gearbox_name} (G = {c.ratio:g})"


def _binds(c: Candidate) -> str:
    b = c.binding
    return f"binds: {b.value} ≤ {b.limit}" if b is not None and b.ratio >= 1 else ""


def summary_lines(sizing: Sizing) -> list[str]:
    """The printed summary: one line per joint (its choice with its margin and the check that binds, or the nearest
    pairs and what each fails), the checks not made, the iteration and the total."""
    s = sizing
    lines = [f"{s.arm.name}: {s.cycle.description or 'duty cycle'} ({number(s.cycle.duration, 4)} s), load cases "
             f"{', '.join(c.label for c in s.cases)}, safety factor {s.safety_factor:g}, ranked by {s.rank}"]
    unchecked: dict[str, str] = {}
    for j in s.joints:
        c = j.chosen
        if c is None:
            lines.append(f"{j.joint}: no feasible motor and gearbox among {j.pairs} pairs; nearest:")
            lines += [f"  {_pair(n)}: {'; '.join(n.failed)}" for n in j.nearest]
            continue
        k = int(np.argmax(c.stats["rms_torque"]))
        winding = c.stats["winding_peak_C"].max()
        joint_peak = np.abs(s.loads.tau[:, :, s.joints.index(j)]).max()  # the load at the gearbox output
        lines.append(f"{j.joint}: {_pair(c)}, {number(c.mass, 4)} kg, margin {percent(c.margin)} ({_binds(c)}); "
                     f"joint peak {number(joint_peak)} N·m; worst case {s.cases[k].label}: motor RMS "
                     f"{number(c.stats['rms_torque'][k])} N·m, peak "
                     f"{number(c.stats['peak_torque'].max())} N·m, {number(c.stats['peak_speed'].max() * RPM)} rpm"
                     + (f"; winding {number(winding)} °C" if np.isfinite(winding) else "")
                     + f"; {j.pairs} pairs, {j.screened} past the screen, {j.checked} checked in order of {s.rank}, "
                       f"{j.feasible_count} feasible")
        for r in c.unchecked:
            unchecked.setdefault(r.name, r.note.removeprefix("not checked "))
    if unchecked:
        lines.append("not checked (the catalogues lack the data): "
                     + "; ".join(f"{name} {why}" for name, why in unchecked.items()))
    mass = "mass iteration: " + (f"converged after {s.iterations} selections" if s.converged
                                 else f"stopped after {s.iterations} selection(s), not converged")
    lines.append(mass + (f"; total drive mass {number(s.drive_mass, 4)} kg" if s.feasible
                         else "; no feasible drive set"))
    return lines


def _table(rows: list[list[str]]) -> list[str]:
    return ["| " + " | ".join(rows[0]) + " |", "|" + "---|" * len(rows[0])] + ["| " + " | ".join(r) + " |"
                                                                             for r in rows[1:]]


def _motor_side(sizing: Sizing, k: int, c: Candidate) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The chosen pair's motor torque ``(L, T)`` (N·m) and speed ``(T,)`` (rad/s) along the cycle, as selected."""
    train = candidate_train(sizing.motors, sizing.gearboxes, np.array([c.motor]), np.array([c.gearbox]))
    s = sizing.samples
    tau_m, omega = motor_side(train, sizing.loads.tau[:, :, k:k + 1], s.qd[:, k:k + 1], s.qdd[:, k:k + 1])
    return tau_m[..., 0], omega[:, 0]


def _details(sizing: Sizing, k: int, c: Candidate) -> list[str]:
    """The winding's duty type and temperature and the DC link's energy of the chosen pair, per load case."""
    s, m = sizing, sizing.motors
    out = []
    if np.isfinite(c.stats["winding_peak_C"]).all():
        tau_m, omega = _motor_side(s, k, c)
        period = s.samples.duration
        for case, label in enumerate(cl.label for cl in s.cases):
            current = s.safety_factor * tau_m[case] / m.torque_constant[c.motor]
            kind, factor = duty_type(current, omega, s.samples.weight)
            cycles = c.stats["cycles_to_periodic"][case]
            out.append(f"- winding, {label}: duty {kind} (duty factor {number(100 * factor)} %; IEC 60034-1), "
                       f"periodic peak {number(c.stats['winding_peak_C'][case])} °C (limit "
                       f"{number(m.max_winding_temperature[c.motor])} °C, ambient {number(s.conditions.ambient)} °C), "
                       f"the mean copper losses {number(c.stats['copper_loss_W'][case])} W would give "
                       f"{number(c.stats['winding_mean_loss_C'][case])} °C; within 0.1 K of periodic after ≈ "
                       f"{number(cycles)} cycles ({number(cycles * period / 60)} min) from cold")
    if np.isfinite(c.stats["bus_energy_peak_J"]).all():
        for case, label in enumerate(cl.label for cl in s.cases):
            st = {name: c.stats[name][case] for name in c.stats}
            resistor = (f"; the braking resistor takes {number(st['resistor_energy_J'])} J per cycle "
                        f"({number(st['resistor_power_W'])} W mean, {number(st['regen_power_peak_W'])} W peak)"
                        if st["resistor_energy_J"] > 0 else "; no braking resistor needed")
            out.append(f"- DC link, {label} (torques × the safety factor): {number(st['bus_regenerated_J'])} J "
                       f"returned per cycle, at most "
                       f"{number(st['bus_energy_peak_J'])} J stored at once (capacitors hold "
                       f"{number(st['capacitor_J'])} J = ½C(V_max² − V_bus²)){resistor}")
    return out


def _check_table(sizing: Sizing, c: Candidate) -> list[str]:
    rows = [["check", "worst load case", "value", "limit", "margin"]]
    for r in c.checks:
        if not r.checked:
            rows.append([r.name, "—", "—", "—", r.note])
            continue
        rows.append([r.name, sizing.cases[r.case].label, r.value, r.limit, percent(r.margin)])
    return _table(rows)


def _joint_section(sizing: Sizing, k: int, j: JointSelection) -> list[str]:
    s = sizing
    out = [f"## {j.joint}", "",
           f"{j.pairs} pairs; the screen (accelerating factor α = T²/J against the load factor β = "
           f"{', '.join(number(b, 4) for b in j.beta)} N²·m²/(kg·m²) per load case) kept {j.motors_screened} "
           f"motors and {j.screened} pairs for the full check; {j.checked} were checked, in order of {s.rank} "
           f"until no pair left could rank among the best, {j.feasible_count} of them feasible.", ""]
    c = j.chosen
    if c is not None:
        out += [f"Chosen: **{_pair(c)}**, {number(c.mass, 4)} kg, margin {percent(c.margin)}"
                + (f" ({_binds(c)})" if _binds(c) else "") + ".", ""]
        out += _check_table(s, c) + [""]
        details = _details(s, k, c)
        if details:
            out += details + [""]
        out += ["Per load case (motor side unless marked):", ""]
        out += _table([["load case", "peak N·m", "RMS N·m", "peak rpm", "mean rpm", "peak W", "energy J",
                        "regen J", "J ratio min", "J ratio max"]]
                      + [[case.label, *(number(c.stats[st][n] * (RPM if "speed" in st else 1)) for st in STATS)]
                         for n, case in enumerate(s.cases)])
        out.append("")
        if len(j.feasible) > 1:
            out += ["Runners-up:", ""]
            out += _table([["motor + gearbox", "mass kg", "margin", "binds"]]
                          + [[_pair(f), number(f.mass, 4), percent(f.margin), f.binding.name if f.binding else ""]
                             for f in j.feasible[1:]])
            out.append("")
    if j.nearest:
        out += ["Nearest infeasible:", ""]
        out += _table([["motor + gearbox", "mass kg", "fails"]]
                      + [[_pair(f), number(f.mass, 4), "; ".join(f.failed)] for f in j.nearest])
        out.append("")
    return out


def sizing_markdown(sizing: Sizing) -> str:
    """``sizing.md``: the summary, then per joint the chosen pair's checks (value, limit, margin, or why not made),
    its winding and DC link, its figures per load case, the feasible runners-up and the nearest infeasible pairs
    with the checks they fail."""
    s = sizing
    cond = s.conditions
    bus = f"{number(cond.bus_voltage)} V DC" if cond.bus_voltage is not None else "each drive's catalogue value"
    out = ["# Drive sizing", "", *[f"{line}  " for line in summary_lines(s)], ""]
    out += ["Feasible: every check made passes, for every load case: RMS, peak and every operating point inside the "
            "torque–speed envelope (torques × the safety factor), speeds within the motor's and the gearbox's, the "
            "gearbox's output torques within its ratings, and where the catalogues give their data the inertia "
            "ratio, the voltage at the bus voltage, the drive's current and I²t, the winding temperature over the "
            "cycle repeated until periodic, the regenerated energy (DC-link capacitors or braking resistor), the "
            "holding brake and the gearbox life (sizing/checks.py). A check without its data is not checked and "
            "says which column it lacks. The payload is carried where the cycle says.", "",
            f"Conditions: ambient {number(cond.ambient)} °C, bus voltage {bus}, brake factor K = "
            f"{number(cond.brake_factor)}, required gearbox life L10 ≥ {number(cond.required_life)} h.", ""]
    for k, j in enumerate(s.joints):
        out += _joint_section(s, k, j)
    return "\n".join(out)


def voltage_envelope(sizing: Sizing, motor: int, speed: NDArray[np.float64]) -> tuple[NDArray, NDArray] | None:
    """The largest motor torque (N·m) the voltage allows at motor speeds ``speed`` ≥ 0 (rad/s) at the sizing's bus
    voltage, motoring (τ·ω > 0) and braking (τ·ω < 0), each ``speed``'s shape (the quadratic in I of
    :mod:`armlab.sizing.checks`' voltage, divided by the safety factor as the check applies it; 0 where no current
    is possible); ``None`` without the motor's electrical data."""
    m = sizing.motors
    bus = sizing.conditions.bus_voltage if sizing.conditions.bus_voltage is not None else m.bus_voltage[motor]
    values = (m.torque_constant[motor], m.back_emf[motor], m.resistance[motor], m.inductance[motor],
              m.pole_pairs[motor], m.max_winding_temperature[motor], bus)
    if np.isnan(values).any():
        return None
    kt, ke, r, ind, poles, t_max, bus = values
    a = np.sqrt(3) / 2 * r * (1 + ALPHA_CU * (t_max - RESISTANCE_AT))
    b = np.sqrt(3) / 2 * poles * ind * speed
    A, B, C = a**2 + b**2, 2 * a * ke * speed, (ke * speed) ** 2 - bus**2 / 2
    disc = np.maximum(B**2 - 4 * A * C, 0.0)
    motoring = np.maximum((-B + np.sqrt(disc)) / (2 * A), 0.0)
    braking = np.where(B**2 - 4 * A * C >= 0, (B + np.sqrt(disc)) / (2 * A), 0.0)
    return kt * motoring / sizing.safety_factor, kt * braking / sizing.safety_factor


def _rms_quadrant(tau_m: NDArray[np.float64], omega: NDArray[np.float64], weight: NDArray[np.float64]
                  ) -> tuple[float, float]:
    """The signs (speed, torque) of the quadrant holding most of Σ w·τ² (where the RMS point is drawn)."""
    best, signs = -1.0, (1.0, 1.0)
    for s_w in (1.0, -1.0):
        for s_t in (1.0, -1.0):
            inside = (s_w * omega >= 0) & (s_t * tau_m >= 0)
            heat = float(np.sum(weight * tau_m**2 * inside))
            if heat > best:
                best, signs = heat, (s_w, s_t)
    return signs


def torque_speed_figure(sizing: Sizing, k: int) -> Any:
    """Joint k's torque–speed figure (a matplotlib figure; motor side): the chosen motor's envelope from its catalogue
    and at the bus voltage, its continuous region, each load case's operating points and RMS point (drawn in the
    quadrant where most of its heating is). ``ValueError`` for a joint without one."""
    # lazy: matplotlib only when figures are drawn
    from armlab.presentation.figures import new_figure

    s, j = sizing, sizing.joints[k]
    c = j.chosen
    if c is None:
        raise ValueError(f"{j.joint} has no feasible motor and gearbox: no torque–speed figure")
    tau_all, omega_all = _motor_side(s, k, c)  # as the selection
    fig, ax = new_figure(f"{s.arm.name} {j.joint}: {_pair(c)} — motor torque against speed, safety factor "
                         f"{s.safety_factor:g}", size=(9.0, 4.8))
    m = s.motors
    top = m.max_speed[c.motor] * RPM
    speeds = np.linspace(0, m.max_speed[c.motor], 200)
    envelope = m.envelope(np.full(speeds.size, c.motor), speeds)
    for sign in (1, -1):
        ax.plot(sign * speeds * RPM, sign * envelope, color="k", lw=1.6,
                label="peak envelope (catalogue)" if sign == 1 else None)
        ax.plot(sign * speeds * RPM, -sign * envelope, color="k", lw=1.6)
    volts = voltage_envelope(s, c.motor, speeds)
    if volts is not None:
        bus = s.conditions.bus_voltage if s.conditions.bus_voltage is not None else m.bus_voltage[c.motor]
        motoring, braking = volts
        for sign in (1, -1):
            ax.plot(sign * speeds * RPM, sign * motoring, color="#b22222", lw=1.2, ls="--",
                    label=f"voltage limit at {number(bus)} V DC ÷ safety factor" if sign == 1 else None)
            ax.plot(sign * speeds * RPM, -sign * braking, color="#b22222", lw=1.2, ls="--")
    rated, rated_speed = m.rated_torque[c.motor], m.rated_speed[c.motor] * RPM
    ax.fill([-rated_speed, rated_speed, rated_speed, -rated_speed], [-rated, -rated, rated, rated], color="#2e8b57",
            alpha=0.12, label="continuous (rated torque, rated speed)")
    ax.axvline(top, color="k", ls=":", lw=1, label="maximum speed")
    ax.axvline(-top, color="k", ls=":", lw=1)
    for case_index, case in enumerate(s.cases):
        tau_m, omega = tau_all[case_index], omega_all
        (points,) = ax.plot(omega * RPM, tau_m, ".", ms=2.5, alpha=0.6, label=f"{case.label}: operating points")
        s_w, s_t = _rms_quadrant(tau_m, omega, s.samples.weight)
        ax.plot([s_w * c.stats["mean_speed"][case_index] * RPM], [s_t * c.stats["rms_torque"][case_index]],
                marker="*", ms=13, color=points.get_color(), mec="k", ls="none",
                label=f"{case.label}: RMS point (mean |ω|, RMS τ)")
    ax.set_xlabel("motor speed ω_m (rpm)")
    ax.set_ylabel("motor torque τ_m (N·m)")
    peak = m.peak_torque[c.motor]
    ax.set_xlim(-1.08 * top, 1.08 * top)
    ax.set_ylim(-1.15 * peak, 1.15 * peak)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7)  # beside the axes: it covers no data
    return fig


def write_sizing(sizing: Sizing, folder: Path) -> list[str]:
    """``sizing.csv``, ``sizing.md`` and (for a feasible sizing) the torque–speed figures into ``folder``; the
    names written."""
    (folder / "sizing.csv").write_text(csv_text(CSV_HEADERS, _csv_rows(sizing)))
    (folder / "sizing.md").write_text(sizing_markdown(sizing) + "\n")
    written = ["sizing.csv", "sizing.md"]
    if sizing.feasible:
        # lazy: matplotlib only when figures are written
        from armlab.presentation.figures import save_png

        written += [save_png(torque_speed_figure(sizing, k), folder / name)
                    for k, name in enumerate(figure_names(sizing))]
    return written
