"""The vendors' checks (sizing/checks.py) against hand-worked cases: the winding's temperature under a constant torque
(the two-node network's step response, solved by hand), a braking inertia's regenerated energy (½Jω² less the
copper losses), the drive's I²t, the voltage at a known operating point, the brake, the gearbox's life; a check
without its data is "not checked", and the selection ranks only pairs passing every check it has data for.

A hand-made task (:func:`_task`) is a sequence of phases of constant acceleration, each sampled with Simpson's
weights (exact for the polynomials here) and joined at knots (sizing/duty.py); with G = 1, η = 1 and no load
the motor torque is J·q̈ (the rotor's and the gearbox's inertia) plus the load's τ_L.
"""

from __future__ import annotations

import math
from dataclasses import fields
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from armlab.sizing.catalogue import RPM, Gearboxes, Motors, read_gearboxes, read_motors
from armlab.sizing.checks import ALPHA_CU, Conditions, duty_type, thermal_modes, winding_temperature
from armlab.sizing.select import CHECKS, JointTask, evaluate, select_joint

R1, R2, TAU_W, TAU_M, T_MAX = 0.5, 1.5, 30.0, 600.0, 155.0  # K/W, K/W, s, s, °C
KT, KE_V_KRPM, R25, L_H, POLES = 0.8, 48.0, 2.0, 4e-3, 4  # N·m/A, V/krpm, Ω, H, pole pairs
R_HOT = R25 * (1 + ALPHA_CU * (T_MAX - 25.0))


def _task(phases: list[tuple[float, float, float, float]], intervals: int = 400) -> JointTask:
    """A one-load-case task of phases (duration s, q̇ at its start and end rad/s, load torque τ_L N·m), each a
    constant acceleration; the static torque is τ_L."""
    qd, qdd, tau, weight, knot_time = [], [], [], [], []
    now = 0.0
    for duration, start, end, load in phases:
        t = np.linspace(0.0, duration, intervals + 1)
        w = np.full(t.size, 2.0)
        w[1::2] = 4.0
        w[0] = w[-1] = 1.0
        qd.append(start + (end - start) * t / duration)
        qdd.append(np.full(t.size, (end - start) / duration))
        tau.append(np.full(t.size, load))
        weight.append(w * duration / intervals / 3)
        knot_time.append(now + t)
        now += duration
    loads = np.concatenate(tau)[None]
    return JointTask(loads, np.zeros_like(loads), np.concatenate(qd), np.concatenate(qdd), np.concatenate(weight),
                     loads.copy(), np.arange(loads.shape[1]), np.concatenate(knot_time))


def _motor(**changes: float) -> Motors:
    """One motor with every column (the constants above); ``changes`` replace fields."""
    values = dict(rated_torque=10.0, peak_torque=30.0, rated_speed=3000 * RPM, max_speed=6000 * RPM,
                  rotor_inertia=1e-3, mass=2.0, torque_constant=KT, back_emf=KE_V_KRPM / (1000 * RPM),
                  resistance=R25, inductance=L_H, pole_pairs=float(POLES), thermal_resistance_winding=R1,
                  thermal_resistance_housing=R2, time_constant_winding=TAU_W, time_constant_motor=TAU_M,
                  max_winding_temperature=T_MAX, brake_torque=5.0, drive_continuous_current=20.0,
                  drive_peak_current=60.0, drive_peak_time=2.0, bus_voltage=325.0, bus_max_voltage=390.0,
                  bus_capacitance=1e-3, braking_resistor_power=100.0, braking_resistance=50.0)
    values.update(changes)
    return Motors(("m",), **{k: np.array([v]) for k, v in values.items()})


def _gearbox(**changes: float) -> Gearboxes:
    values = dict(ratio=1.0, efficiency=1.0, rated_torque=100.0, peak_torque=300.0, max_input_speed=1e4 * RPM,
                  input_inertia=0.0, mass=1.0, life_basis=1.0, rated_life=35000.0, rated_input_speed=2000 * RPM)
    values.update(changes)
    return Gearboxes(("g",), **{k: np.array([v]) for k, v in values.items()})


def _check(task: JointTask, motors: Motors, gearboxes: Gearboxes, conditions: Conditions | None = None,
           safety: float = 1.0):
    ev = evaluate(task, motors, gearboxes, np.array([0]), np.array([0]), safety, describe=True, conditions=conditions)
    ratio = {name: float(ev.ratios[k, 0]) for k, name in enumerate(CHECKS)}
    values = {name: (float(ev.values[k, 0]), float(ev.limits[k, 0])) for k, name in enumerate(CHECKS)}
    return ratio, values, {k: float(v[0, 0]) for k, v in ev.stats.items()}


def _step_response(P: float, t: np.ndarray) -> np.ndarray:
    """The winding's rise over ambient (K) from cold under constant losses P (W), by hand: with
    a = 1/(R1·C_w), b = 1/(R1·C_h), g = 1/(R2·C_h), θ_w'' + (a + b + g)·θ_w' + a·g·θ_w = (b + g)·a·R1·P... whose
    solution is θ_w = P·(R1 + R2) + c1·e^{s1 t} + c2·e^{s2 t}, s1, s2 the roots of s² + (a + b + g)s + a·g, and
    θ_w(0) = 0, θ_w'(0) = P/C_w fix c1 + c2 = −P(R1 + R2), s1·c1 + s2·c2 = P/C_w."""
    cw, ch = TAU_W / R1, TAU_M / R2
    a, b, g = 1 / (R1 * cw), 1 / (R1 * ch), 1 / (R2 * ch)
    disc = math.sqrt((a + b + g) ** 2 - 4 * a * g)
    s1, s2 = (-(a + b + g) - disc) / 2, (-(a + b + g) + disc) / 2
    final = P * (R1 + R2)
    c2 = (P / cw + s1 * final) / (s2 - s1)
    c1 = -final - c2
    return final + c1 * np.exp(s1 * t) + c2 * np.exp(s2 * t)


def test_a_constant_torque_heats_the_winding_as_the_hand_worked_step_response():
    """Constant torque: P = (3/2)·R_hot·(τ/K_t)², the curve from cold over 5 cycles of 60 s to 1e-6 K, the periodic
    peak the steady state T_a + P·(R1 + R2) (S1 duty), the modes' static gain R1 + R2."""
    torque = 6.0
    task = _task([(60.0, 0.0, 0.0, torque)])
    P = 1.5 * R_HOT * (torque / KT) ** 2
    motors = _motor()
    lam1, lam2, w1, w2 = thermal_modes(motors, np.array([0]))
    np.testing.assert_allclose(-(w1 / lam1 + w2 / lam2), R1 + R2, rtol=1e-12)
    loss = np.full((1, task.knot_time.size), P)
    curve = winding_temperature(motors, np.array([0]), loss, task.knot_time, 40.0, cycles=5)[0]  # (5, K)
    times = task.knot_time[None, :] + 60.0 * np.arange(5)[:, None]
    np.testing.assert_allclose(curve, 40.0 + _step_response(P, times), rtol=0, atol=1e-6)
    ratio, values, stats = _check(task, motors, _gearbox())
    np.testing.assert_allclose(stats["winding_peak_C"], 40.0 + P * (R1 + R2), rtol=0, atol=1e-6)
    np.testing.assert_allclose(values["winding temperature"], (P * (R1 + R2), T_MAX - 40.0), rtol=1e-12)
    np.testing.assert_allclose(ratio["winding temperature"], (T_MAX - 40.0) / (P * (R1 + R2)), rtol=1e-12)
    assert duty_type(np.full(5, 2.0), np.zeros(5), np.ones(5)) == ("S1", 1.0)  # exact: a copy or a constant


@pytest.mark.slow  # 300 short scipy integrations, ~2 s
def test_the_periodic_winding_temperature_is_the_one_repeated_cycles_reach():
    """A varying cycle (accelerate, brake, rest) with short time constants, integrated by scipy over 100 cycles from
    cold (the two-node ODE, its losses linear between the knots as the model has them, phase by phase): the last
    cycle's peak winding temperature equals the periodic solution's to 1e-6 K; it lies above the steady temperature
    of the mean losses (the RMS rule), which a slow winding would not show."""
    r1, r2, tw, tm = 0.4, 1.2, 0.5, 2.0
    motors = _motor(thermal_resistance_winding=r1, thermal_resistance_housing=r2, time_constant_winding=tw,
                    time_constant_motor=tm, rotor_inertia=0.02)
    task = _task([(0.3, 0.0, 300.0, 1.0), (0.4, 300.0, 0.0, -0.5), (0.5, 0.0, 0.0, 2.0)], intervals=40)
    _, _, stats = _check(task, motors, _gearbox())
    tau_m = 0.02 * task.qdd + task.tau[0]
    loss = 1.5 * R_HOT * (tau_m[task.knot_sample] / KT) ** 2
    t, period = task.knot_time, task.knot_time[-1]
    cw, ch = tw / r1, tm / r2

    jumps = np.flatnonzero(np.diff(t) == 0)  # the phases meet at zero-length steps: integrate phase by phase
    phases = np.split(np.arange(t.size), jumps + 1)
    state, cycles = np.zeros(2), 100
    for _ in range(cycles):
        last = []
        for knots in phases:
            def rhs(time, x, knots=knots):
                p = np.interp(time, t[knots], loss[knots])  # the losses as the model has them: linear between knots
                return [(p - (x[0] - x[1]) / r1) / cw, ((x[0] - x[1]) / r1 - x[1] / r2) / ch]

            run = solve_ivp(rhs, (t[knots[0]], t[knots[-1]]), state, t_eval=t[knots], rtol=1e-12, atol=1e-12)
            state = run.y[:, -1]
            last.append(run.y[0])
    slow = thermal_modes(motors, np.array([0]))[1][0]
    assert np.exp(slow * cycles * period) * 100 < 1e-9  # after 100 cycles the start's 100 K would be gone
    np.testing.assert_allclose(40.0 + np.concatenate(last).max(), stats["winding_peak_C"], rtol=0, atol=1e-6)
    assert stats["winding_peak_C"] > stats["winding_mean_loss_C"] + 0.1  # the ripple the RMS rule misses


def test_a_braking_inertia_returns_half_j_omega_squared_less_its_copper_losses():
    """Accelerate J from 0 to ω0 in t_a, brake to 0 in t_b (deceleration α = ω0/t_b), rest. Braking, the motor
    returns J·α·ω and its copper burns P_c = (3/2)·R_25·I² (I = J·α/K_t): power comes back while ω > ω* = P_c/(J·α),
    E = ∫(J·α·ω − P_c)dt = ½J(ω0² − ω*²) − P_c·(ω0 − ω*)/α, all of it stored at once (the DC link's peak). With
    capacitors holding half of it the braking resistor takes the other half per cycle."""
    J, omega0, t_a, t_b, rest = 0.02, 300.0, 0.3, 0.4, 0.5
    task = _task([(t_a, 0.0, omega0, 0.0), (t_b, omega0, 0.0, 0.0), (rest, 0.0, 0.0, 0.0)])
    alpha = omega0 / t_b
    current = J * alpha / KT
    copper = 1.5 * R25 * current**2
    low = copper / (J * alpha)
    energy = 0.5 * J * (omega0**2 - low**2) - copper * (omega0 - low) / alpha
    assert 0 < low < omega0
    motors = _motor(rotor_inertia=J, bus_capacitance=1.0, drive_peak_current=100.0)
    ratio, values, stats = _check(task, motors, _gearbox())
    np.testing.assert_allclose(values["regeneration"], (energy, 0.5 * 1.0 * (390.0**2 - 325.0**2)), rtol=1e-12)
    np.testing.assert_allclose(stats["bus_energy_peak_J"], energy, rtol=1e-12)
    np.testing.assert_allclose(stats["bus_regenerated_J"], energy, rtol=1e-12)
    np.testing.assert_allclose(stats["regenerated"], 0.5 * J * omega0**2, rtol=1e-12)  # mechanical, no losses
    np.testing.assert_allclose(stats["regen_power_peak_W"], J * alpha * omega0 - copper, rtol=1e-12)
    assert stats["regeneration_basis"] == 0 and ratio["regeneration"] > 1
    half = 2 * (energy / 2) / (390.0**2 - 325.0**2)  # C with ½C(V_max² − V²) = half the energy
    _, _, stats = _check(task, _motor(rotor_inertia=J, bus_capacitance=half, drive_peak_current=100.0), _gearbox())
    np.testing.assert_allclose(stats["capacitor_J"], energy / 2, rtol=1e-12)
    np.testing.assert_allclose(stats["resistor_energy_J"], energy / 2, rtol=1e-12)
    np.testing.assert_allclose(stats["resistor_power_W"], energy / 2 / (t_a + t_b + rest), rtol=1e-12)
    assert stats["regeneration_basis"] in (1, 2)
    # without a braking resistor the drive cannot take it: the check fails and says what resistor is needed
    bare = _motor(rotor_inertia=J, bus_capacitance=half, drive_peak_current=100.0, braking_resistor_power=np.nan,
                  braking_resistance=np.nan)
    chosen = select_joint("j", task, bare, _gearbox())
    assert chosen.chosen is None
    (text,) = [t for t in chosen.nearest[0].failed if t.startswith("bus energy")]
    assert "no braking resistor" in text and "W mean" in text


def test_the_drives_i2t_lets_the_peak_current_last_its_peak_time():
    """The peak current for exactly the drive's t_p from cold (then a long rest) brings the I²t filter to I_c."""
    i_c, i_p, t_p = 10.0, 30.0, 2.0
    tau_d = -t_p / math.log(1 - (i_c / i_p) ** 2)
    task = _task([(t_p, 0.0, 0.0, i_p * KT), (60 * tau_d, 0.0, 0.0, 0.0)])
    motors = _motor(drive_continuous_current=i_c, drive_peak_current=i_p, drive_peak_time=t_p)
    ratio, values, _ = _check(task, motors, _gearbox())
    np.testing.assert_allclose(values["I²t"], (i_c, i_c), rtol=1e-9)
    np.testing.assert_allclose(values["current peak"], (i_p, i_p), rtol=1e-12)
    np.testing.assert_allclose(ratio["I²t"], 1.0, rtol=1e-9)


def test_the_voltage_at_an_operating_point_and_the_bus_voltage_decides():
    """Constant speed and torque: V = √((K_e·ω + (√3/2)·R_hot·I)² + ((√3/2)·p·ω·L·I)²) by hand; at the catalogue's
    325 V bus it passes, at a 150 V bus (--bus-voltage) it does not."""
    omega, torque = 2500 * RPM, 4.0
    task = _task([(1.0, omega, omega, torque)])
    current = torque / KT
    ke = KE_V_KRPM / (1000 * RPM)
    half3 = math.sqrt(3) / 2
    volts = math.hypot(ke * omega + half3 * R_HOT * current, half3 * POLES * omega * L_H * current)
    ratio, values, stats = _check(task, _motor(), _gearbox())
    np.testing.assert_allclose(values["voltage"], (volts, 325 / math.sqrt(2)), rtol=1e-12)
    np.testing.assert_allclose(stats["voltage_speed"], omega, rtol=1e-12)
    assert ratio["voltage"] > 1
    ratio, values, _ = _check(task, _motor(), _gearbox(), Conditions(bus_voltage=150.0))
    np.testing.assert_allclose(values["voltage"], (volts, 150 / math.sqrt(2)), rtol=1e-12)
    assert ratio["voltage"] < 1


def test_the_brake_and_the_gearbox_life_by_hand():
    """Brake: T_H against K·max|τ_g|/G. Strain-wave life: two phases at input speeds n1, n2 (times t1, t2) and output
    torques T1, T2: n_av = (n1 t1 + n2 t2)/(t1 + t2), T_av = ((n1 t1 T1³ + n2 t2 T2³)/(n1 t1 + n2 t2))^⅓,
    L10 = L_n·(n_N/n_av)·(T_N/T_av)³/5; a rating gearbox: its rated life if T_av ≤ T_N and n_av ≤ n_N."""
    G = 50.0
    n1, n2, t1, t2, T1, T2 = 1000 * RPM, 3000 * RPM, 2.0, 1.0, 40.0, 20.0
    task = _task([(t1, n1 / G, n1 / G, T1), (t2, n2 / G, n2 / G, T2)])
    gearbox = _gearbox(ratio=G, rated_torque=60.0)
    ratio, values, stats = _check(task, _motor(), gearbox, Conditions(brake_factor=2.5, required_life=10000.0))
    np.testing.assert_allclose(values["brake"], (2.5 * T1 / G, 5.0), rtol=1e-12)
    n_av = (n1 * t1 + n2 * t2) / (t1 + t2)
    t_av = ((n1 * t1 * T1**3 + n2 * t2 * T2**3) / (n1 * t1 + n2 * t2)) ** (1 / 3)
    l10 = 35000 * (2000 * RPM / n_av) * (60 / t_av) ** 3 / 5
    np.testing.assert_allclose(values["gearbox life"], (10000.0, l10), rtol=1e-12)
    np.testing.assert_allclose([stats["life_T_av_Nm"], stats["life_n_av"]], [t_av, n_av], rtol=1e-12)
    rating = _gearbox(ratio=G, rated_torque=30.0, life_basis=2.0, rated_life=30000.0, rated_input_speed=3000 * RPM)
    ratio, values, _ = _check(task, _motor(), rating, Conditions(required_life=10000.0))
    np.testing.assert_allclose(values["gearbox life"], (t_av, 30.0), rtol=1e-12)  # T_av binds: 30/T_av < 3
    np.testing.assert_allclose(ratio["gearbox life"], 30.0 / t_av, rtol=1e-12)


def test_a_check_without_its_data_is_not_checked_and_the_selection_skips_failing_pairs():
    """The example catalogues without the electrical columns: every such check "not checked (no column X)", NaN, not
    passed; with two motors, the lighter one's winding too hot: the heavier is chosen and the binding check named."""
    task = _task([(1.0, 0.0, 0.0, 2.0)])
    bare = Motors(("m",), *(np.array([v]) for v in (10.0, 30.0, 3000 * RPM, 6000 * RPM, 1e-3, 2.0)))
    chosen = select_joint("j", task, bare, _gearbox()).chosen
    assert chosen is not None
    notes = {c.name: c.note for c in chosen.unchecked}
    assert notes["winding temperature"] == "not checked (no column torque_constant_Nm_A)"
    assert notes["brake"] == "not checked (no column brake_holding_torque_Nm)"
    assert set(notes) == {"voltage", "current peak", "current RMS", "I²t", "winding temperature", "regeneration",
                          "brake"}
    assert chosen.binding is not None and chosen.binding.checked
    hot, cool = _motor(mass=1.0, thermal_resistance_housing=50.0), _motor(mass=3.0)
    both = Motors(("hot", "cool"), **{f.name: np.concatenate([getattr(hot, f.name), getattr(cool, f.name)])
                                      for f in fields(hot) if f.name != "name"})
    selection = select_joint("j", task, both, _gearbox())
    assert selection.chosen.motor_name == "cool"
    assert selection.nearest[0].motor_name == "hot"
    assert any(text.startswith("winding") and "°C" in text for text in selection.nearest[0].failed)


CATALOGUE_ERRORS = [
    ("gearbox", "life_basis,rated_life_h\ng,10,0.9,5,10,6000,0.01,1,helical,20000\n",
     "life_basis = 'helical' is not allowed: one of strain-wave, rating"),
    ("motor", "drive_continuous_current_A,drive_peak_current_A\na,1,3,3000,5000,0.1,1,5,4\n",
     "drive_peak_current_A = 4 A is below the rated current 5 A"),
    ("motor", "bus_voltage_V,bus_max_voltage_V\na,1,3,3000,5000,0.1,1,560,400\n",
     "bus_max_voltage_V = 400 V is below the rated bus voltage 560 V"),
    ("motor", "resistance_ohm\na,1,3,3000,5000,0.1,1,0\n", "resistance_ohm = '0' is not allowed: a finite number > 0"),
]


@pytest.mark.parametrize(("kind", "extra", "message"), CATALOGUE_ERRORS)
def test_bad_new_columns_are_one_line_errors(tmp_path: Path, kind, extra, message):
    base = {"motor": "name,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgcm2,mass_kg",
            "gearbox": "name,ratio,efficiency,rated_torque_Nm,peak_torque_Nm,max_input_speed_rpm,"
                       "input_inertia_kgcm2,mass_kg"}[kind]
    path = tmp_path / f"{kind}s.csv"
    path.write_text(base + "," + extra)
    with pytest.raises(ValueError, match=message) as error:
        (read_motors if kind == "motor" else read_gearboxes)(path)
    assert "\n" not in str(error.value)


def test_the_example_catalogues_have_every_column_labelled_illustrative():
    motors, gearboxes = read_motors(), read_gearboxes()
    for name in ("torque_constant", "resistance", "thermal_resistance_winding", "drive_peak_current",
                 "bus_capacitance"):
        assert np.all(np.isfinite(getattr(motors, name)))
    assert np.isnan(motors.brake_torque).any() and np.isfinite(motors.brake_torque).any()  # some motors have none
    assert set(np.unique(gearboxes.life_basis)) == {1.0, 2.0}  # exact: booleans or integer codes
    folder = Path(__file__).resolve().parents[1] / "scripts" / "examples" / "catalogues"
    for path in folder.glob("*.csv"):
        assert "ILLUSTRATIVE" in path.read_text().splitlines()[0]
    assert "datasheet" in (folder / "README.md").read_text()


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"ambient": 200.0}, "ambient 200.0 °C is not allowed"),
    ({"brake_factor": 0.5}, "brake_factor 0.5 is not allowed"),
    ({"required_life": -1.0}, "required_life -1.0 h is not allowed"),
    ({"bus_voltage": 0.0}, "bus voltage 0.0 V is not allowed"),
])
def test_bad_conditions(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Conditions(**kwargs)
