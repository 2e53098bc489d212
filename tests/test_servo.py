"""The servo loop (issue 32): controllers chosen per run, sampled or continuous, saturated with anti-windup; sensors;
motor electrics with a current loop; the linearised loop against the tuning rule; the CLI and the files."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import armlab_main, assert_same_objectives, objectives, write_study

import armlab
from armlab.analysis.study import evaluate, load_study, parse_study
from armlab.analysis.sweep import run_sweep
from armlab.controllers.sensors import SensorDesign, add_sensors, encoder_scale
from armlab.controllers.servo import CONTROLLERS, loop_bandwidth, tuned_gains
from armlab.diagrams.build import build_diagram
from armlab.diagrams.servo import frequency_response, linearize_loop
from armlab.diagrams.simulate import SimulationOptions, simulate
from armlab.drives.read import read_drive_file
from armlab.models import unregister
from armlab.planning.motions import paper_motion
from armlab.presentation.output import csv_header
from armlab.presentation.replay_graphs import log_graphs

DATA = Path(__file__).parent / "data"
RR_MOTORS = Path(__file__).parents[1] / "scripts" / "examples" / "drives" / "rr_motors.csv"  # illustrative motors


@pytest.fixture(scope="module")
def arm1r():
    """The one-joint test arm of tests/arm1r.py (gravity along its axis: a double integrator J s² to its servo)."""
    sys.modules.pop("arm1r", None)
    import arm1r as module

    yield module, module.build()
    unregister("arm1r")
    sys.modules.pop("arm1r", None)


def rr_motors():
    return armlab.load("rr", drives=RR_MOTORS)


def short(arm, tf: float = 0.5):
    """rr's paper motion in ``tf`` s (the same path, faster)."""
    return paper_motion(arm, tf=tf)


# ------------------------------------------------------------------------------------- the default: unchanged
def test_the_default_run_is_paper_000s_ideal_loop():
    options = SimulationOptions()
    assert not options.servo and options.sampling == "dense" and options.controller == "computed-torque"
    arm = armlab.load("rr")
    run = build_diagram(arm, paper_motion(arm))
    assert run.servo is None
    dot = run.diagram.GetGraphvizString(max_depth=1)
    assert "name=InverseDynamicsController" in dot
    for servo_block in ("servo_pid", "reference_sampling", "torque_saturation", "sensor_sampling", "motors"):
        assert servo_block not in dot
    # any servo option makes a servo run, and its loggers sample periodically
    for servo in ({"controller": "pid"}, {"rate": 1000.0}, {"saturate": True}, {"electrics": True}):
        assert SimulationOptions(**servo).servo and SimulationOptions(**servo).sampling == "periodic"


def test_continuous_computed_torque_servo_equals_drakes_inverse_dynamics_controller():
    """Two builds of one law: Drake's InverseDynamicsController (the ideal loop) and the servo's PID core feeding
    Drake's InverseDynamics, saturated at rr's 100 N·m (never reached): the same run to round-off."""
    arm = armlab.load("rr")
    motion = paper_motion(arm)
    ideal = simulate(arm, motion, SimulationOptions(log_period=0.01, sampling="periodic"))
    servo = simulate(arm, motion, SimulationOptions(log_period=0.01, saturate=True))
    assert servo.servo is not None and servo.servo["torque_limit"] == [100.0, 100.0]  # exact: a copy or a constant
    for a, b in ((ideal.q, servo.q), (ideal.qd, servo.qd), (ideal.tau, servo.tau), (servo.tau_command, servo.tau)):
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * max(1.0, float(np.max(np.abs(a)))))


@pytest.mark.slow
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_a_sampled_controller_converges_to_the_continuous_one_at_first_order(controller):
    """Each 4× the rate takes 4× off the distance from the continuous run: the hold's O(h) (3.5 to 4.5: the ratio's
    second-order remainder at these rates is below a tenth)."""
    arm = armlab.load("rr")
    motion = paper_motion(arm)
    common = {"log_period": 0.01, "controller": controller, "bandwidth": None if controller == "computed-torque"
              else 5.0}
    continuous = simulate(arm, motion, SimulationOptions(saturate=True, **common))
    distance = [float(np.max(np.abs(simulate(arm, motion, SimulationOptions(rate=rate, **common)).q - continuous.q)))
                for rate in (250.0, 1000.0, 4000.0)]
    ratios = np.array(distance[:-1]) / np.array(distance[1:])
    assert np.all((ratios > 3.5) & (ratios < 4.5)), (distance, ratios)


# --------------------------------------------------------------------------------------- the tuning rule
def test_the_tuning_rule_by_hand():
    omega = 7.0
    # PD with a double pole at −ω: |ω²/(jw + ω)²|² = ½ at w = ω √(√2 − 1)
    assert loop_bandwidth(omega**2, 2 * omega, 0.0)[0] == pytest.approx(omega * np.sqrt(np.sqrt(2) - 1) / (2 * np.pi),
                                                                       rel=1e-12)
    # PID with a triple pole: the transfer evaluated directly at the bandwidth found has |T| = 1/√2
    kp, kd, ki = 3 * omega**2, 3 * omega, omega**3
    s = 2j * np.pi * loop_bandwidth(kp, kd, ki)[0]
    assert abs((kp * s + ki) / (s**3 + kd * s**2 + kp * s + ki)) == pytest.approx(1 / np.sqrt(2), rel=1e-12)
    for controller in CONTROLLERS:  # the rule inverts: the gains of a bandwidth have that bandwidth
        assert loop_bandwidth(*tuned_gains(controller, 3.3))[0] == pytest.approx(3.3, rel=1e-12)
    assert tuned_gains("computed-torque", loop_bandwidth(100.0, 20.0, 0.0)[0]) == pytest.approx((100.0, 20.0, 0.0))
    options = SimulationOptions(controller="pid", bandwidth=2.0)
    assert (options.kp, options.kd, options.ki) == pytest.approx(tuned_gains("pid", 2.0))
    with pytest.raises(ValueError, match=r"gains .* or a bandwidth, not both"):
        SimulationOptions(kp=50.0, bandwidth=2.0)


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_the_linearised_loop_has_the_design_bandwidth(arm1r, controller):
    """Drake's Linearize of the closed loop (one joint: the rule's double integrator exactly) against the rule: its
    −3 dB bandwidth and its characteristic polynomial (s + ω)^k."""
    _, arm = arm1r
    options = SimulationOptions(controller=controller, bandwidth=5.0)
    response = frequency_response(arm, options, [0.3])
    np.testing.assert_allclose(response.bandwidth, 5.0, rtol=1e-9)
    np.testing.assert_allclose(response.design, 5.0, rtol=1e-12)
    system, _ = linearize_loop(arm, options, [0.3])
    k = system.A().shape[0]
    assert k == (3 if controller == "pid" else 2)  # the plant's (q, q̇), and the PID's integral
    omega = options.kd / (3 if controller == "pid" else 2)  # the rule: kd = 3ω (PID) or 2ω (PD)
    np.testing.assert_allclose(np.poly(system.A()), np.poly(np.full(k, -omega)), rtol=1e-9)


def test_computed_torque_linearises_to_the_design_on_every_joint_and_pose():
    """Computed torque cancels rr's coupling and gravity: each joint's loop is the rule's at any pose."""
    arm = armlab.load("rr")
    for q in ([0.3, -1.2], [-0.66, 1.71]):
        response = frequency_response(arm, SimulationOptions(bandwidth=4.0), q)
        np.testing.assert_allclose(response.bandwidth, 4.0, rtol=1e-9)


# -------------------------------------------------------------------------------- saturation, anti-windup
def test_saturation_at_the_effort_limit_and_anti_windup(arm1r):
    """A quarter turn in 0.1 s needs ~8× arm1r's 10 N·m: the torque stays on the limit, the command passes it, and
    the integral wound back by back-calculation leaves no overshoot where one that winds up overshoots by 0.37 rad."""
    module, arm = arm1r
    q0, qf = np.array([module.TURN[0]]), np.array([module.TURN[1]])
    motion = armlab.through(arm, [q0, qf, qf], [0.1, 1.0])  # the turn, then a hold
    runs = {}
    for anti_windup in (True, False):
        log = simulate(arm, motion, SimulationOptions(log_period=0.001, controller="pid", bandwidth=3.0,
                                                      saturate=True, anti_windup=anti_windup))
        assert np.max(np.abs(log.tau)) <= 10.0 * (1 + 1e-9)
        assert np.max(np.abs(log.tau_command)) > 40.0
        runs[anti_windup] = log
    overshoot = {k: float(np.max(log.q[:, 0]) - qf[0]) for k, log in runs.items()}
    assert overshoot[True] < 1e-3 and overshoot[False] > 0.3, overshoot
    run = armlab.simulate(arm, motion, log_period=0.001, controller="pid", bandwidth=3.0, saturate=True)
    saturated = run.summary["servo"]["saturation_time"][0]
    assert 0.05 < saturated < 0.2  # about the turn's 0.1 s, counted in 1 ms samples


# --------------------------------------------------------------------------------------------- sensors
def test_a_delay_of_k_samples_lags_by_its_analytic_phase():
    """q = sin ωt sampled every h and delayed d samples: the fundamental of what the controller holds lags by
    ω h (d + ½), the hold's half sample included (exactly: the held steps' Fourier integral in closed form)."""
    from pydrake.systems.analysis import Simulator
    from pydrake.systems.framework import DiagramBuilder
    from pydrake.systems.primitives import LogVectorOutput, Sine

    h, f, periods = 1e-3, 5.0, 3  # 200 samples a period
    w = 2 * np.pi * f
    for d in (0, 1, 3, 7):
        builder = DiagramBuilder()
        source = builder.AddSystem(Sine(np.array([1.0, w]), np.full(2, w), np.array([0.0, np.pi / 2])))
        sensors = add_sensors(builder, source.get_output_port(0), SensorDesign(h, None, np.ones(1), delay=d))
        logger = LogVectorOutput(sensors.get_output_port(), builder, h)
        diagram = builder.Build()
        simulator = Simulator(diagram)
        simulator.AdvanceTo(periods / f)
        log = logger.FindLog(simulator.get_context())
        held = log.data()[0, 1:]  # the sample logged at t_{k+1} is the value held over [t_k, t_{k+1})
        t = log.sample_times()[:-1]
        window = (t >= 1 / f - 1e-12) & (t < periods / f - 1e-12)  # whole periods, past the start-up registers
        tk = t[window]
        integral = (np.exp(-1j * w * (tk + h)) - np.exp(-1j * w * tk)) / (-1j * w)
        amplitude = np.sum(held[window] * integral) * 2 * f / (periods - 1)
        lag = -np.angle(1j * amplitude)  # sin(ωt − φ) has the amplitude −j e^{−jφ}
        assert lag == pytest.approx(w * h * (d + 0.5), abs=1e-9), d


def test_the_encoder_reads_its_counts_on_the_motor_or_the_joint():
    arm = armlab.load("rr", drives=DATA / "rr_drives.csv")  # G = 100, 80
    motion = short(arm)
    for side, scale in (("motor", np.array([100.0, 80.0])), ("joint", np.ones(2))):
        log = simulate(arm, motion, SimulationOptions(log_period=1e-3, rate=1000.0, encoder=4096, encoder_side=side))
        step = 2 * np.pi / (4096 * scale)
        np.testing.assert_allclose(log.servo["sensors"]["resolution"], step, rtol=1e-15)
        q_m = log.measured[1:, :2]  # held over the period before each sample: the reading at the sample before
        design = SensorDesign(1e-3, 4096, encoder_scale(side, [100.0, 80.0], [True, True]))
        np.testing.assert_allclose(q_m, design.quantize(log.q[:-1]), rtol=0, atol=1e-12)
        counts = q_m / step
        np.testing.assert_allclose(counts, np.round(counts), rtol=0, atol=1e-6)  # whole counts …
        assert np.all((log.q[:-1] - q_m >= -1e-12) & (log.q[:-1] - q_m < step + 1e-12))  # … below the angle


def test_velocity_by_difference_and_low_pass():
    """v_k = a v_{k−1} + (1 − a)(q_k − q_{k−1})/h, a = exp(−2π f_c h), recomputed from the logged angles."""
    arm = armlab.load("rr")
    motion = short(arm)
    h, cutoff = 1e-3, 40.0
    log = simulate(arm, motion, SimulationOptions(log_period=h, rate=1 / h, velocity="difference",
                                                  velocity_cutoff=cutoff))
    a = np.exp(-2 * np.pi * cutoff * h)
    q = log.q[:-1]  # the angle at each sample t_k
    v = np.zeros_like(q)
    previous, held = q[0], np.zeros(2)  # at rest since ever
    for k in range(q.shape[0]):
        held = a * held + (1 - a) * (q[k] - previous) / h
        previous = q[k]
        v[k] = held
    np.testing.assert_allclose(log.measured[1:, 2:], v, rtol=0, atol=1e-9 * np.max(np.abs(v)))


def test_noise_has_its_seed_and_its_standard_deviation():
    arm = armlab.load("rr")
    motion = short(arm, 1.0)
    sigma = 1e-3

    def measured(seed: int):
        log = simulate(arm, motion, SimulationOptions(log_period=1e-3, rate=1000.0, noise=sigma, seed=seed))
        return log.measured[1:, :2] - log.q[:-1]

    first, again, other = measured(7), measured(7), measured(8)
    np.testing.assert_array_equal(first, again)  # exact: one seed, one run, the same code on the same input
    assert not np.allclose(first, other)
    noise = first[1:]  # the first held value is the start's, noise-free
    assert abs(np.std(noise) / sigma - 1) < 5 / np.sqrt(2 * noise.size)  # five standard errors of the estimate
    assert abs(np.mean(noise)) < 5 * sigma / np.sqrt(noise.size)


# --------------------------------------------------------------------------------------- motor electrics
def test_the_drive_file_reads_the_motor_electrics(tmp_path):
    train = read_drive_file(RR_MOTORS, ["joint1", "joint2"])
    e = train.electrics
    assert e is not None
    np.testing.assert_array_equal(e.resistance, [1.2, 2.0])  # exact: parsed from the same decimal text
    np.testing.assert_array_equal(e.back_emf, e.torque_constant)  # exact: the default k_e = k_t (SI) is a copy
    np.testing.assert_array_equal(e.peak_current, [6.0, 4.0])  # exact: parsed from the same decimal text
    assert read_drive_file(DATA / "rr_drives.csv", ["joint1", "joint2"]).electrics is None
    bad = tmp_path / "bad.csv"
    bad.write_text("gear_ratio,resistance,inductance\n100,1,1e-3\n80,1,1e-3\n")
    with pytest.raises(ValueError, match="motor electrics need torque_constant, bus_voltage too"):
        read_drive_file(bad, ["joint1", "joint2"])
    bad.write_text("resistance,inductance,torque_constant,bus_voltage\n1,1e-3,0.1,48\n-1,1e-3,0.1,48\n")
    with pytest.raises(ValueError, match="motor resistance of joint 2 = -1 Ω is not allowed"):
        read_drive_file(bad, ["joint1", "joint2"])
    with pytest.raises(ValueError, match="electrics need the motors' resistance"):
        simulate(armlab.load("rr"), short(armlab.load("rr")), SimulationOptions(electrics=True))


@pytest.mark.slow
@pytest.mark.parametrize("current_rate", [None, 10000.0])
def test_energy_balance_of_the_motors(current_rate):
    """∫V i dt = ∫τ q̇ dt + ∫R i² dt + Δ(½ L i²) per joint, to 1e-6 relative: the electrical energy from the voltage
    and current, the mechanical from the torque the plant gets and its rates (energy_meter's integrals)."""
    arm = rr_motors()
    run = armlab.simulate(arm, short(arm), controller="pd+feedforward", bandwidth=5.0, rate=1000.0, encoder=4096,
                          electrics=True, current_rate=current_rate, saturate=True, log_period=1e-3)
    energy = run.summary["servo"]["energy"]
    assert max(energy["relative_residual"]) < 1e-6, energy
    assert min(energy["copper"]) > 0  # (joint 2 regenerates: gravity lowers it, its electrical energy is < 0)
    log = run.log
    torque_per_amp = np.array([100 * 0.06, 80 * 0.045])  # G k_t of rr_motors.csv
    np.testing.assert_allclose(log.tau, log.current * torque_per_amp, rtol=1e-12)  # the motors drive the plant


@pytest.mark.slow
def test_the_balance_has_teeth_a_back_emf_unlike_the_torque_constant_breaks_it():
    """A motor whose k_e is 1.2 k_t converts 20 % more electrical power than it delivers: the residual shows it."""
    from dataclasses import replace

    arm = rr_motors()
    e = arm.drives.electrics
    wrong = arm.with_drives(replace(arm.drives, electrics=replace(e, back_emf=1.2 * e.torque_constant)))
    run = armlab.simulate(wrong, short(wrong), electrics=True, log_period=1e-3)
    assert max(run.summary["servo"]["energy"]["relative_residual"]) > 1e-2


def test_the_voltage_saturates_at_the_bus():
    from dataclasses import replace

    arm = rr_motors()
    low = arm.with_drives(replace(arm.drives, electrics=replace(arm.drives.electrics, bus_voltage=np.full(2, 6.0))))
    run = armlab.simulate(low, short(low, 0.4), electrics=True, log_period=1e-3)
    assert np.max(np.abs(run.log.voltage)) <= 6.0 * (1 + 1e-9)
    assert run.summary["servo"]["voltage_saturation_time"][0] > 0.01
    assert run.summary["servo"]["peak_voltage"][0] == pytest.approx(6.0, rel=1e-12)
    graphs = {g.title: g for g in log_graphs(run.log)}  # the replay's graphs: tracking, current, voltage
    assert graphs["tracking error q−q_d"].labels == ("q−q_d1 [rad]", "q−q_d2 [rad]")
    np.testing.assert_array_equal(graphs["motor currents i"].values, run.log.current)  # exact: a copy or a constant
    assert graphs["winding voltages V"].labels == ("V1 [V]", "V2 [V]")


# ------------------------------------------------------------------------------------- bad input, CLI, files
@pytest.mark.parametrize(("options", "message"), [
    ({"controller": "lqr"}, "controller 'lqr' is not allowed; allowed: computed-torque, pid, pd+feedforward"),
    ({"encoder": 4096}, "an encoder needs a sampled controller: give a rate"),
    ({"rate": 0.5}, "rate 0.5 is out of range"),
    ({"rate": 100.0, "encoder": 1}, "encoder 1 is out of range"),
    ({"rate": 100.0, "encoder": 4096.5}, "encoder = 4096.5 is not allowed: give a whole number"),
    ({"rate": 100.0, "velocity_cutoff": 10.0}, "a velocity cutoff filters the velocity by difference"),
    ({"current_rate": 10000.0}, "a current-loop rate needs the motors' electrics"),
    ({"controller": "pid", "mode": "inverse_dynamics"}, "use mode 'controller'"),
    ({"rate": 100.0, "sampling": "dense"}, "a servo run's loggers sample periodically"),
    ({"rate": 100.0, "delay": -1}, "delay -1 is out of range"),
])
def test_bad_servo_options_are_one_clear_error(options, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        SimulationOptions(**options)


@pytest.mark.slow  # a whole servo run with its files
def test_simulate_a_servo_run_prints_and_writes_it(tmp_path):
    out = tmp_path / "servo"
    result = armlab_main("simulate", "rr", "--drives", str(RR_MOTORS), "--controller", "pid", "--bandwidth", "4",
                         "--rate", "1000", "--encoder", "4096", "--saturate", "--electrics", "--tf", "1",
                         "--divergence-tolerance", "0.1", "--out", str(out))
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert any(line.startswith("servo: pid at 1000 Hz; RMS tracking error 1: ") for line in lines)
    assert any(line.startswith("torque saturated for (s) 1: 0 s, 2: 0 s") for line in lines)
    assert any(line.startswith("peak current 1: ") for line in lines)
    assert any(line.startswith("energy: electrical 1: ") for line in lines)
    assert {"servo.png", "bode.png"} <= {p.name for p in out.iterdir()}
    header = (out / "log.csv").read_text().splitlines()[0].split(",")
    assert header == csv_header(2, True, ("tau_command", "measured", "current", "voltage", "energy"))
    assert header[-6:] == ["E_el1", "E_el2", "E_mech1", "E_mech2", "E_cu1", "E_cu2"]
    summary = json.loads((out / "summary.json").read_text())
    servo = summary["servo"]
    assert servo["controller"] == "pid" and servo["rate_hz"] == 1000.0  # exact: parsed from the same decimal text
    assert servo["gains"]["Kp"] == pytest.approx(np.array(servo["gains"]["kp"]) * servo["joint_inertia"])
    assert servo["current_loop"]["bus_voltage"] == [48.0, 48.0]  # exact: parsed from the same decimal text
    table = np.loadtxt(out / "log.csv", delimiter=",", skiprows=1)
    current = table[:, header.index("i1")]
    assert servo["peak_current"][0] == pytest.approx(np.max(np.abs(current)), rel=1e-9)


@pytest.mark.parametrize(("argv", "message"), [
    (["--encoder", "4096"], "an encoder needs a sampled controller: give a rate (--rate HZ)"),
    (["--electrics"], "electrics need the motors' resistance, inductance, torque_constant and bus_voltage"),
    (["--rate", "1e9"], "rate 1e9 is out of range"),
])
def test_bad_servo_options_on_the_cli(tmp_path, argv, message):
    result = armlab_main("simulate", "rr", *argv, "--out", str(tmp_path / "x"))
    assert result.returncode == 2 and message in result.stderr and "Traceback" not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "x").exists()


# ------------------------------------------------------------------------------------- the study (Dask sweep)
SERVO_STUDY = {"arm": "rr", "tf": 0.5, "vary": {"rate": {"values": [0.5, 2.0], "unit": "kHz"},
                                                "encoder": {"values": [1024, 16384]}},
               "evaluate": ["max_tracking_error", "rms_tracking_error"],
               "servo": {"controller": "pd+feedforward", "bandwidth": 5.0, "encoder_side": "joint"}}


@pytest.mark.slow
def test_a_study_evaluates_the_tracking_error_against_rate_and_encoder():
    study = parse_study(SERVO_STUDY)
    assert study.objective_columns == ["max_tracking_error_1", "max_tracking_error_2", "rms_tracking_error_1",
                                       "rms_tracking_error_2"]
    # exact: a copy or a constant
    assert study.servo_settings((2.0, 16384.0)) == {"controller": "pd+feedforward", "bandwidth": 5.0,
                                                    "encoder_side": "joint", "rate": 2000.0, "encoder": 16384}
    got = evaluate(study, (2.0, 16384.0))
    arm = armlab.load("rr")  # the same run by hand
    log = simulate(arm, paper_motion(arm, tf=0.5), SimulationOptions(controller="pd+feedforward", bandwidth=5.0,
                                                                      rate=2000.0, encoder=16384,
                                                                      encoder_side="joint"))
    assert got["max_tracking_error_1"] == float(np.max(np.abs(log.q[:, 0] - log.q_ref[:, 0])))  # exact: same run
    coarse = evaluate(study, (0.5, 1024.0))
    assert coarse["rms_tracking_error_1"] > got["rms_tracking_error_1"]  # slower and coarser: worse tracking
    for change, message in (({"servo": {"gain": 1}}, "servo: unknown setting 'gain'"),
                            ({"evaluate": ["peak_torque"]}, "servo changes only the servo objectives"),
                            ({"servo": {"controller": "lqr"}}, "controller 'lqr' is not allowed")):
        with pytest.raises(ValueError, match=re.escape(message)):
            parse_study(SERVO_STUDY | change)


@pytest.mark.slow
def test_the_servo_study_sweeps_on_a_local_cluster(tmp_path):
    """The study run by Dask workers (a LocalCluster of two processes) gives what this process computes."""
    study_file = write_study(tmp_path, SERVO_STUDY)
    out = tmp_path / "out"
    result = run_sweep(study_file, out, workers=2)
    assert (result.total, result.computed, result.failed) == (4, 4, [])
    study = load_study(study_file)
    columns = study.objective_columns
    assert_same_objectives(objectives(out, columns), {i: [evaluate(study, values)[c] for c in columns]
                                                       for i, values in enumerate(study.candidates)})
    assert (out / "max_tracking_error.png").is_file() and (out / "max_tracking_error_map.png").is_file()


# ------------------------------------------------------------------------------------ beyond paper 000 (reproduce)
@pytest.mark.slow
def test_paper_000s_beyond_the_paper_servo_loop(tmp_path):
    """The reproduction's servo study: the ideal loop tracks to its integrator's 1e-6 rad, the 1 kHz PID on
    4096-count motor encoders with the chosen drives to a few mrad, each row what ``armlab.simulate`` gives."""
    import csv

    from armlab.papers.beyond import OVERSIZE, RR_PAYLOADS, SERVO, rr_servo
    from armlab.papers.paper_output import PaperOutput

    out = PaperOutput("000", tmp_path, lambda *_: None)
    out.group("beyond")
    rr_servo(out, fast=True)
    ideal, pid = list(csv.DictReader((tmp_path / "beyond_servo.csv").open()))
    assert max(float(ideal["max |e1| [rad]"]), float(ideal["max |e2| [rad]"])) < 1e-6
    sizing = armlab.size_drives(armlab.load("rr"), None, RR_PAYLOADS[True], safety_factor=OVERSIZE)
    arm = sizing.arm.with_drives(sizing.drive_train())
    run = armlab.simulate(arm, paper_motion(arm), log_period=1e-3, divergence_tolerance=1.0, **SERVO)
    np.testing.assert_allclose([float(pid["RMS e1 [rad]"]), float(pid["RMS e2 [rad]"])],
                               run.summary["servo"]["rms_tracking_error"], rtol=1e-12)
    assert 1e-4 < float(pid["RMS e1 [rad]"]) < 1e-2
    assert {"beyond_servo_tracking.png", "beyond_servo_bode.png"} <= {p.name for p in tmp_path.iterdir()}


# ------------------------------------------------------------------------------------------- elastic joints
def elastic(arm, stiffness: float, damping: float = 0.0):
    """``arm`` with its drive train's gearboxes of ``stiffness`` (N·m/rad) and ``damping`` at every joint."""
    from dataclasses import replace

    from armlab.drives.elastic import Elasticity

    n = arm.n
    return arm.with_drives(replace(arm.drives, elasticity=Elasticity(np.full(n, stiffness), np.full(n, damping))))


def test_a_two_mass_joint_rings_at_its_analytic_frequency(arm1r):
    """The rotor J_r = G² J_m and the link J_l on a spring K, no control: Drake's Linearize of the rotors and the
    plant has the eigenvalues ±j √(K (1/J_r + 1/J_l)) (and two at 0: the pair turning together)."""
    from pydrake.systems.framework import DiagramBuilder
    from pydrake.systems.primitives import ConstantVectorSource, Linearize

    from armlab.controllers.elastic import ElasticDesign, add_elastic_rotors, link_side
    from armlab.controllers.servo import joint_inertia
    from armlab.drives.elastic import Elasticity
    from armlab.drives.train import DriveTrain
    from armlab.models.plant import PlantOptions, add_arm_plant

    _, arm = arm1r
    arm = arm.with_drives(DriveTrain([10.0], [1e-3], [1.0], [0.0], [0.0]))
    stiffness = 40.0
    builder = DiagramBuilder()
    plant, _ = add_arm_plant(builder, link_side(arm), PlantOptions(ideal_drives=True))
    zero = builder.AddSystem(ConstantVectorSource(np.zeros(1)))
    design = ElasticDesign(Elasticity(np.array([stiffness])), arm.drives.reflected_inertia)
    _, spring = add_elastic_rotors(builder, plant.get_state_output_port(), zero.get_output_port(), design)
    builder.Connect(spring, plant.get_actuation_input_port())
    diagram = builder.Build()
    system = Linearize(diagram, diagram.CreateDefaultContext())
    j_link = joint_inertia(plant, [0.0])[0]
    omega = np.sqrt(stiffness * (1 / 0.1 + 1 / j_link))
    eigenvalues = np.linalg.eigvals(system.A())
    ringing = np.argsort(np.abs(eigenvalues.imag))[-2:]
    np.testing.assert_allclose(np.abs(eigenvalues[ringing].imag), omega, rtol=1e-12)
    np.testing.assert_allclose(eigenvalues[ringing].real, 0.0, atol=1e-12 * omega)
    # the pair turning together: a double zero with one eigenvector (a Jordan block), which an eigenvalue solver
    # returns perturbed by about √(ε·‖A‖) (1e-7 here, its sign and size the BLAS kernel's), not to round-off
    rest = np.delete(eigenvalues, ringing)
    assert np.all(np.abs(rest) <= np.sqrt(np.finfo(float).eps * np.abs(system.A()).max()) * 10)


@pytest.mark.slow
def test_stiff_elastic_joints_approach_the_rigid_arm():
    """The links lag the motor-side measurement by the static twist τ/K: each 4× the stiffness takes 4× off the
    distance from the rigid arm's run (3.6 to 4.4), and the rotors lead the links by that twist."""
    arm = rr_motors()
    motion = paper_motion(arm)
    common = {"log_period": 0.01, "controller": "pd+feedforward", "bandwidth": 5.0}
    rigid = simulate(arm, motion, SimulationOptions(**common))
    distance = []
    for k in (1e3, 4e3, 1.6e4):
        log = simulate(elastic(arm, k), motion, SimulationOptions(elastic=True, **common))
        distance.append(float(np.max(np.abs(log.q - rigid.q))))
        twist = log.rotor[:, :2] - log.q
        np.testing.assert_allclose(np.max(np.abs(twist)), distance[-1], rtol=0.05)
    ratios = np.array(distance[:-1]) / np.array(distance[1:])
    assert np.all((ratios > 3.6) & (ratios < 4.4)), (distance, ratios)


def test_elastic_joints_need_their_stiffness_and_the_linearised_loop_stiffens_to_the_rigid_one(tmp_path):
    arm = rr_motors()
    with pytest.raises(ValueError, match="elastic joints need a drive train with a stiffness column"):
        simulate(arm, short(arm), SimulationOptions(elastic=True))
    bad = tmp_path / "bad.csv"
    bad.write_text("gear_ratio,rotor_inertia,twist_damping\n100,1e-5,1\n80,1e-5,1\n")
    with pytest.raises(ValueError, match="twist_damping needs the stiffness column too"):
        read_drive_file(bad, ["joint1", "joint2"])
    bad.write_text("gear_ratio,rotor_inertia,stiffness\n100,1e-5,0\n80,1e-5,1e4\n")
    with pytest.raises(ValueError, match="joint stiffness of joint 1 = 0 N·m/rad is not allowed"):
        read_drive_file(bad, ["joint1", "joint2"])
    good = tmp_path / "good.csv"
    good.write_text("gear_ratio,rotor_inertia,stiffness,twist_damping\n100,1.2e-5,2e4,1\n80,0.8e-5,1e4,0.5\n")
    # exact: parsed from the same decimal text
    assert read_drive_file(good, ["joint1", "joint2"]).elasticity.stiffness.tolist() == [2e4, 1e4]
    options = SimulationOptions(controller="computed-torque", bandwidth=5.0, elastic=True)
    stiff = frequency_response(elastic(arm, 1e7), options, [-0.66, 1.71])
    np.testing.assert_allclose(stiff.bandwidth, 5.0, rtol=1e-3)  # the rigid rule's, to the spring's 1/K
