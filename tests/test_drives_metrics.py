"""A candidate drive's figures over a duty cycle against closed forms on the one-joint arm, and the loads two ways.

arm1r (tests/arm1r.py) turns a uniform cylinder (mass m, length L, radius r) about z with gravity along −z, so its
joint torque is J·q̈ with J = m(3r² + L²)/12 + m(L/2)² and no gravity term; a payload at the tool point (L, 0, 0)
adds m_p·L². Its quarter turn is the rest-to-rest quintic q = q0 + Δ(10s³ − 15s⁴ + 6s⁵), s = t/tf, whose
acceleration Δ/tf²·(60s − 180s² + 120s³) has ∫₀¹ (…)² ds = 120/7 and peak 10√3/3·Δ/tf² at s = (3 − √3)/6, and
whose rate peaks at 15/8·Δ/tf. Through a gearbox (G, η) with J_m + J_g = J_d the joint-side torque is
(J + G²J_d)·q̈ = J_e·q̈; the motor delivers in the first half (τ·q̇ > 0: τ_m = τ/(Gη)) and is driven back in the
second (τ_m = τη/G), so RMS² = J_e²(Δ/tf²)²·(120/7)·½(1/(Gη)² + (η/G)²)·tf/T over a cycle of T s, the energy
delivered is J_e·q̇_max²/(2η) and the energy regenerated η·J_e·q̇_max²/2.
"""

from __future__ import annotations

import importlib
import sys
from dataclasses import replace

import numpy as np
import pytest
from helpers import arm_and_plant

from armlab.models import get_arm, unregister
from armlab.sizing.catalogue import Gearboxes, Motors
from armlab.sizing.duty import DutyCycle, Dwell, LoadCase, Move, sample
from armlab.sizing.loads import joint_loads, with_link_masses, with_payload
from armlab.sizing.select import JointTask, evaluate

#: Samples per second: Simpson's rule on the quintic's polynomials is then exact to ~1e-12 relative.
RATE = 2000.0
G_RATIO, ETA, J_MOTOR, J_GEAR = 20.0, 0.8, 3e-5, 1e-5


@pytest.fixture
def arm1r():
    """The one-joint test arm (its module registers it; the registry is restored afterwards)."""
    sys.modules.pop("arm1r", None)
    module = importlib.import_module("arm1r")
    yield module.build()
    unregister("arm1r")
    sys.modules.pop("arm1r", None)


def _catalogues() -> tuple[Motors, Gearboxes]:
    """One motor (no voltage line) and one gearbox with the constants above, big enough for every check."""
    one = np.ones(1)
    motors = Motors(("m",), 10 * one, 30 * one, 1e4 * one, 2e4 * one, J_MOTOR * one, 1.0 * one,
                    np.full(1, np.nan), np.full(1, np.nan))
    gearboxes = Gearboxes(("g",), G_RATIO * one, ETA * one, 100 * one, 200 * one, 2e4 * one, J_GEAR * one, 0.5 * one)
    return motors, gearboxes


def _figures(arm, cycle, case):
    samples = sample(cycle, RATE)
    loads = joint_loads(arm, samples, (case,))
    task = JointTask.of(samples, loads, 0)
    motors, gearboxes = _catalogues()
    ev = evaluate(task, motors, gearboxes, np.array([0]), np.array([0]), 1.0, describe=True)
    return {k: float(v[0, 0]) for k, v in ev.stats.items()}, samples


@pytest.mark.parametrize("dwell", [0.0, 0.5])
def test_a_quarter_turns_figures_are_the_closed_forms(arm1r, dwell):
    p = arm1r.parameters
    m, L, r, m_p = p["m"], p["L"], 0.02, 0.3
    motion = arm1r.motion(arm1r, 1.0)
    tf, delta = 1.0, np.pi / 2
    cycle = DutyCycle((Move(motion, payload=True), Dwell(dwell, payload=True)))
    stats, samples = _figures(arm1r, cycle, LoadCase(m_p))
    J_load = m * (3 * r**2 + L**2) / 12 + m * (L / 2) ** 2 + m_p * L**2
    J_e = J_load + G_RATIO**2 * (J_MOTOR + J_GEAR)
    period = tf + dwell
    rms = J_e * delta / tf**2 * np.sqrt(120 / 7 * 0.5 * (1 / (G_RATIO * ETA) ** 2 + (ETA / G_RATIO) ** 2) * tf / period)
    np.testing.assert_allclose(samples.duration, period, rtol=1e-15)
    np.testing.assert_allclose(stats["rms_torque"], rms, rtol=1e-9)
    qdd_top, qd_top = 10 * np.sqrt(3) / 3 * delta / tf**2, 15 / 8 * delta / tf
    h = tf / (samples.weight.size - (dwell > 0) - 1)
    # the grid's largest value is within ½h²·max|f''| of the true peak (f'' of q̈ is 360 s⁻⁴·Δ/tf⁴ at most)
    np.testing.assert_allclose(stats["peak_torque"], J_e * qdd_top / (G_RATIO * ETA),
                               rtol=0.5 * h**2 * 360 * delta / tf**4 / qdd_top)
    np.testing.assert_allclose(stats["peak_speed"], G_RATIO * qd_top, rtol=0.5 * h**2 * 7.5 * delta / qd_top)
    np.testing.assert_allclose(stats["mean_speed"], G_RATIO * delta / period, rtol=1e-12)
    np.testing.assert_allclose(stats["energy"], J_e * qd_top**2 / (2 * ETA), rtol=1e-9)
    np.testing.assert_allclose(stats["regenerated"], ETA * J_e * qd_top**2 / 2, rtol=1e-9)
    for key in ("inertia_ratio_min", "inertia_ratio_max"):  # the load at the motor, gearbox included, over J_m
        np.testing.assert_allclose(stats[key], (J_load / G_RATIO**2 + J_GEAR) / J_MOTOR, rtol=1e-12)


def test_holding_against_gravity_in_a_dwell_adds_the_static_torque(arm1r):
    """With gravity along −y the link is a pendulum: held at q for d s it needs (m L/2 + m_p L)·g·cos q, so the
    cycle's Σ w τ_m² grows by d·(τ/(Gη))² and its energy not at all; the payload counts only where it is held."""
    arm = replace(arm1r, gravity=(0.0, -9.81, 0.0))
    m, L, m_p, d = arm.parameters["m"], arm.parameters["L"], 2.0, 0.7
    motion = arm.motion(arm, 1.0)
    stats = {}
    for held, dwell in ((True, 0.0), (True, d), (False, d)):
        cycle = DutyCycle((Move(motion, payload=True), Dwell(dwell, payload=held)))
        stats[held, dwell], _ = _figures(arm, cycle, LoadCase(m_p))
    moving = stats[True, 0.0]["rms_torque"] ** 2 * 1.0
    for held in (True, False):
        hold = (m * L / 2 + (m_p * L if held else 0.0)) * 9.81 * np.cos(np.pi / 4) / (G_RATIO * ETA)
        np.testing.assert_allclose(stats[held, d]["rms_torque"] ** 2 * (1.0 + d), moving + d * hold**2, rtol=1e-12)
        np.testing.assert_allclose(stats[held, d]["energy"], stats[True, 0.0]["energy"], rtol=1e-12)


def test_a_payloads_offset_and_inertia_enter_as_a_rigid_body(arm1r):
    """Offset d along the tool's x and inertia I_zz: J grows by m_p(L + d)² + I_zz (parallel axes), and the arm
    carrying it has the same torques by its Drake plant as by the Newton–Euler pass."""
    L, m_p, d, I = arm1r.parameters["L"], 1.5, 0.1, 0.02
    inertia = ((0.01, 0.0, 0.0), (0.0, 0.01, 0.0), (0.0, 0.0, I))
    carrying = with_payload(arm1r, LoadCase(m_p, (d, 0.0, 0.0), inertia))
    q, qd, qdd = np.array([[0.3]]), np.array([[0.0]]), np.array([[2.0]])
    gained = carrying.inverse_dynamics(q, qd, qdd) - arm1r.inverse_dynamics(q, qd, qdd)
    np.testing.assert_allclose(gained, (m_p * (L + d) ** 2 + I) * 2.0, rtol=1e-12)
    _assert_plant_agrees(carrying, np.random.default_rng(1))


def test_a_point_payload_is_the_plants_payload():
    """No offset, no inertia: the arm carrying it and ``inverse_dynamics(payload=m)`` (the plant's payload) agree."""
    arm = get_arm("urm6")
    rng = np.random.default_rng(2)
    q, qd, qdd = rng.uniform(-1, 1, (3, 50, arm.n))
    np.testing.assert_allclose(with_payload(arm, LoadCase(2.5)).inverse_dynamics(q, qd, qdd),
                               arm.inverse_dynamics(q, qd, qdd, payload=2.5), rtol=1e-9, atol=1e-9)


def test_drive_masses_sit_on_the_link_before_their_joint():
    """rr with 3 kg at joint 2 (on link 1, at L1 from joint 1): joint 1's holding torque grows by 3·g·L1·cos q1
    (gravity −y), joint 2's not at all; its Drake plant agrees."""
    arm = get_arm("rr")
    heavier = with_link_masses(arm, [5.0, 3.0])  # joint 1's drive sits on the base: it moves nothing
    q = np.array([[0.4, -0.9], [-1.1, 0.5]])
    zero = np.zeros_like(q)
    gained = heavier.inverse_dynamics(q, zero, zero) - arm.inverse_dynamics(q, zero, zero)
    np.testing.assert_allclose(gained[:, 0], 3.0 * 9.81 * arm.parameters["L1"] * np.cos(q[:, 0]), rtol=1e-12)
    np.testing.assert_allclose(gained[:, 1], 0.0, atol=1e-12)
    _assert_plant_agrees(heavier, np.random.default_rng(3))


def test_the_load_inertia_is_the_mass_matrix_diagonal():
    """J_load of joint_loads (unit accelerations through the Newton–Euler pass) against Drake's CalcMassMatrix."""
    arm, plant, context = arm_and_plant("urm6")
    motion = arm.motion(arm, None)
    samples = sample(DutyCycle.of(motion), 20.0)
    loads = joint_loads(arm, samples, (LoadCase(0.0),))
    for k in range(0, samples.q.shape[0], 7):
        plant.SetPositions(context, samples.q[k])
        np.testing.assert_allclose(loads.inertia[0, k], np.diag(plant.CalcMassMatrix(context)), rtol=1e-9,
                                   atol=1e-12)


def _assert_plant_agrees(arm, rng) -> None:
    """``arm``'s Newton–Euler torques equal its Drake plant's CalcInverseDynamics (gravity included), 1e-9."""
    from pydrake.multibody.tree import MultibodyForces

    plant = arm.make_plant()
    context = plant.CreateDefaultContext()
    forces = MultibodyForces(plant)
    for _ in range(3):
        q, qd, qdd = rng.uniform(-1, 1, (3, arm.n))
        plant.SetPositions(context, q)
        plant.SetVelocities(context, qd)
        plant.CalcForceElementsContribution(context, forces)
        drake = plant.CalcInverseDynamics(context, qdd, forces)
        np.testing.assert_allclose(arm.inverse_dynamics(q, qd, qdd), drake, rtol=1e-9, atol=1e-9)
