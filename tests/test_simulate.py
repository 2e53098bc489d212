"""Paper 000's Fig. 6 diagram: tracking, torques vs inverse dynamics and Lagrange, energy, open loop, CLI output."""

from __future__ import annotations

import functools
import json
import os
import re
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from helpers import assert_rounding_close

import armlab
from armlab.cli import main
from armlab.diagrams.build import build_diagram
from armlab.diagrams.simulate import (
    DEFAULT_ACCURACY,
    DEFAULT_INTEGRATOR,
    MAX_STEP,
    SimulationLog,
    SimulationOptions,
    log_samples,
    run_simulator,
    sample_times,
    simulate,
    state_rows,
    summarize,
)
from armlab.kinematics.quintic import Motion, QuinticSegment
from armlab.models import get_arm
from armlab.models.plant import PlantOptions, make_plant
from armlab.planning.motions import paper_motion
from armlab.presentation.output import RUN_OUTPUTS, csv_header
from armlab.presentation.servo_plots import SERVO_PLOTS
from armlab.values import resolve_gravity

#: Every paper motion armlab simulate runs by default (arm, --path).
PAPER_MOTIONS = [("rr", None), ("rr", "abcd"), ("rrrr", None), ("arm4r", None), ("r2t", None), ("urm6", None)]
IDS = [f"{a}-{p}" if p else a for a, p in PAPER_MOTIONS]


@functools.cache
def run(name: str, path: str | None = None, log_period: float = 0.01, mode: str = "controller",
        gravity: str | None = None, payload: float = 0.0) -> SimulationLog:
    """A paper motion simulated once per session (coarse log by default: the tests stay fast)."""
    arm = get_arm(name)
    plant = PlantOptions(gravity=gravity, payload=payload, ideal_drives=True)
    return simulate(arm, paper_motion(arm, path), SimulationOptions(plant, log_period=log_period, mode=mode))


def sim_plant(log: SimulationLog):
    """The plant ``log`` was simulated with: its arm, gravity and payload, outside a diagram."""
    return make_plant(log.arm, PlantOptions(tuple(log.gravity), log.payload, ideal_drives=True))


def inverse_dynamics(log: SimulationLog, q, qd, qdd) -> np.ndarray:
    """Drake's CalcInverseDynamics (gravity included through the force elements), row by row."""
    from pydrake.multibody.tree import MultibodyForces

    plant = sim_plant(log)
    context = plant.CreateDefaultContext()
    forces = MultibodyForces(plant)
    out = []
    for row in zip(q, qd, qdd, strict=True):
        plant.SetPositions(context, row[0])
        plant.SetVelocities(context, row[1])
        plant.CalcForceElementsContribution(context, forces)
        out.append(plant.CalcInverseDynamics(context, row[2], forces))
    return np.array(out)


# ----------------------------------------------------------------------------------------- the closed loop
@pytest.mark.slow
@pytest.mark.parametrize(("name", "path"), PAPER_MOTIONS, ids=IDS)
def test_tracking_error_with_the_exact_model(name, path):
    log = run(name, path)
    assert log.t[0] == 0.0 and abs(log.t[-1] - log.motion.duration) < 1e-12  # exact: the start time
    q_ref, qd_ref, qdd_ref = log.motion.evaluate(log.t)
    # the logged reference is the trajectory (except at run joins, where the log holds both runs' ends)
    inside = np.ones(log.t.shape, dtype=bool)
    for start in log.run_starts[1:]:
        inside &= ~((log.t == start) & (log.run < log.run.max()))
    np.testing.assert_allclose(log.q_ref[inside], q_ref[inside], rtol=0, atol=1e-12)
    np.testing.assert_allclose(log.qd_ref[inside], qd_ref[inside], rtol=0, atol=1e-12)
    np.testing.assert_allclose(log.qdd_ref[inside], qdd_ref[inside], rtol=0, atol=1e-10)
    assert np.max(np.abs(log.q - log.q_ref)) <= 1e-6


@pytest.mark.parametrize(("name", "path"), PAPER_MOTIONS, ids=IDS)
def test_torques_equal_drake_inverse_dynamics_along_the_reference(name, path):
    log = run(name, path)
    expected = inverse_dynamics(log, log.q_ref, log.qd_ref, log.qdd_ref)
    np.testing.assert_allclose(log.tau, expected, rtol=0, atol=1e-6)


def lagrange_rr(arm, q, qd, qdd, g):
    """The two-link arm's Lagrange equations, written out (uniform cylinders along each link, gravity g ∈ x–y)."""
    p = arm.parameters
    L1, L2, m1, m2 = p["L1"], p["L2"], p["m1"], p["m2"]
    I1 = m1 * (3 * p["r1"] ** 2 + L1**2) / 12  # about the centre, perpendicular to the link
    I2 = m2 * (3 * p["r2"] ** 2 + L2**2) / 12
    c1, c2 = L1 / 2, L2 / 2
    t1, t2 = q[:, 0], q[:, 1]
    cos2, sin2 = np.cos(t2), np.sin(t2)
    M11 = I1 + I2 + m1 * c1**2 + m2 * (L1**2 + c2**2 + 2 * L1 * c2 * cos2)
    M12 = I2 + m2 * (c2**2 + L1 * c2 * cos2)
    M22 = I2 + m2 * c2**2
    h = m2 * L1 * c2 * sin2
    # potential V = −g·(m1 r_c1 + m2 r_c2); τ_g = ∂V/∂θ
    gx, gy = g[0], g[1]

    def dV(theta, lever):  # ∂/∂θ of −lever·g·(cos θ, sin θ)
        return -lever * (-gx * np.sin(theta) + gy * np.cos(theta))

    G1 = dV(t1, m1 * c1 + m2 * L1) + dV(t1 + t2, m2 * c2)
    G2 = dV(t1 + t2, m2 * c2)
    tau1 = M11 * qdd[:, 0] + M12 * qdd[:, 1] - h * (2 * qd[:, 0] * qd[:, 1] + qd[:, 1] ** 2) + G1
    tau2 = M12 * qdd[:, 0] + M22 * qdd[:, 1] + h * qd[:, 0] ** 2 + G2
    return np.stack([tau1, tau2], axis=-1)


def test_inverse_dynamics_along_samples_equals_the_lagrange_equations(rng):
    """arm.inverse_dynamics (no diagram) at random states, gravity in the arm's plane, against Lagrange."""
    arm = get_arm("rr")
    q, qd, qdd = rng.uniform(-3, 3, (3, 200, 2))
    for gravity in (None, "off", (3.0, -4.0, 0.0)):
        g = resolve_gravity(arm, gravity)
        np.testing.assert_allclose(arm.inverse_dynamics(q, qd, qdd, gravity), lagrange_rr(arm, q, qd, qdd, g),
                                   rtol=0, atol=1e-9)
    with pytest.raises(ValueError, match="qd"):
        arm.inverse_dynamics(q, qd[:, :1], qdd)
    with pytest.raises(ValueError, match="not a finite number"):
        arm.inverse_dynamics(q, qd, np.full_like(qdd, np.nan))


@pytest.mark.parametrize("path", [None, "abcd"])
def test_rr_torques_equal_the_lagrange_equations(path):
    log = run("rr", path)
    np.testing.assert_allclose(log.tau, lagrange_rr(log.arm, log.q_ref, log.qd_ref, log.qdd_ref, log.gravity),
                               rtol=0, atol=1e-6)


@pytest.mark.slow
def test_rr_gravity_along_the_joint_axes_leaves_pure_inertial_torques():
    """Gravity ±z (along rr's joint axes) does no work: torques equal gravity off, as Table 3's pairs suggest."""
    off = run("rr", "abcd", gravity="off")
    np.testing.assert_array_equal(off.gravity, [0, 0, 0])  # exact: gravity off
    for g in ("+z", "-z"):
        np.testing.assert_allclose(run("rr", "abcd", gravity=g).tau, off.tau, rtol=0, atol=1e-6)
    np.testing.assert_allclose(off.tau, lagrange_rr(off.arm, off.q_ref, off.qd_ref, off.qdd_ref, off.gravity),
                               rtol=0, atol=1e-6)
    assert np.max(np.abs(off.tau - run("rr", "abcd").tau)) > 1.0  # −y gravity (the default) matters


def test_gravity_settings():
    rr = get_arm("rr")
    np.testing.assert_array_equal(resolve_gravity(rr), [0, -9.81, 0])  # exact: the arm's gravity constant
    np.testing.assert_array_equal(resolve_gravity(rr, "default"), [0, -9.81, 0])  # exact: the arm's gravity constant
    # exact: the arm's gravity constant
    np.testing.assert_array_equal(resolve_gravity(get_arm("r2t"), None), [0, 0, -9.81])
    np.testing.assert_array_equal(resolve_gravity(rr, "+x"), [9.81, 0, 0])  # exact: 9.81 along +x
    np.testing.assert_array_equal(resolve_gravity(rr, "1,2,-3.5"), [1, 2, -3.5])  # exact: parsed from the text
    for bad in ("up", "1,2", "1,nan,2", [1, 2]):
        with pytest.raises(ValueError, match="gravity"):
            resolve_gravity(rr, bad)


def test_r2t_payload_adds_its_point_mass_dynamics():
    """The 20 kg payload's extra torques are Jᵀ m (a − g) at the tool point, from the logged tool acceleration."""
    base, loaded = run("r2t"), run("r2t", payload=20.0)
    np.testing.assert_allclose(loaded.tool, base.tool, rtol=0, atol=1e-8)  # exact tracking: the same motion
    from pydrake.multibody.tree import JacobianWrtVariable

    plant = sim_plant(base)
    context = plant.CreateDefaultContext()
    frame, world = plant.GetFrameByName(base.arm.tool_name), plant.world_frame()
    extra = []
    for q, tool in zip(base.q_ref, base.tool, strict=True):
        plant.SetPositions(context, q)
        J = plant.CalcJacobianTranslationalVelocity(context, JacobianWrtVariable.kV, frame, np.zeros(3), world, world)
        extra.append(J.T @ (20.0 * (tool[6:] - base.gravity)))
    np.testing.assert_allclose(loaded.tau - base.tau, np.array(extra), rtol=0, atol=1e-6)
    assert np.max(np.abs(loaded.tau[:, 1] - base.tau[:, 1])) > 150  # lifting 20 kg: ≈ 196 N more on the carriage


# ------------------------------------------------------------------------------------- open loop, energy
OPEN_LOOP = [("rr", None), ("rr", "abcd"), ("arm4r", None), ("r2t", None)]


@pytest.mark.slow
@pytest.mark.parametrize(("name", "path"), OPEN_LOOP, ids=[f"{a}-{p}" if p else a for a, p in OPEN_LOOP])
def test_pure_inverse_dynamics_mode_agrees_with_the_controller(name, path):
    """SimMechanics' inverse-dynamics mode (torques from the reference alone, open loop) gives the controller's
    torques when tracking is exact, and drives the plant along the reference to the integrator's accuracy.

    Not for rrrr's 15 s spin and urm6: their open-loop error dynamics are exponentially unstable (a 7 rad/s
    whirl, a gravity-loaded stack), so round-off grows without feedback; that is what feedback is for.
    """
    closed, open_loop = run(name, path, log_period=1e-3), run(name, path, log_period=1e-3, mode="inverse_dynamics")
    np.testing.assert_allclose(open_loop.tau, closed.tau, rtol=0, atol=1e-6)
    np.testing.assert_allclose(open_loop.tau, inverse_dynamics(open_loop, open_loop.q_ref, open_loop.qd_ref,
                                                               open_loop.qdd_ref), rtol=0, atol=1e-9)
    assert np.max(np.abs(open_loop.q - open_loop.q_ref)) <= 1e-6


def test_logged_torques_replayed_open_loop_reproduce_the_trajectory():
    """Feed the logged feed-forward torques (1 ms samples, cubic spline) to the bare plant: q follows the reference."""
    from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator
    from pydrake.systems.framework import DiagramBuilder
    from pydrake.systems.primitives import LogVectorOutput, TrajectorySource
    from pydrake.trajectories import PiecewisePolynomial

    log = run("rr", log_period=1e-3, mode="inverse_dynamics")
    builder = DiagramBuilder()
    plant = builder.AddSystem(sim_plant(log))
    torque = PiecewisePolynomial.CubicWithContinuousSecondDerivatives(log.t, log.tau.T, periodic_end_condition=False)
    source = builder.AddSystem(TrajectorySource(torque))
    builder.Connect(source.get_output_port(), plant.get_actuation_input_port())
    logger = LogVectorOutput(plant.get_state_output_port(), builder, 1e-3)
    diagram = builder.Build()
    simulator = Simulator(diagram)
    plant.SetPositions(plant.GetMyMutableContextFromRoot(simulator.get_mutable_context()), log.q_ref[0])
    ResetIntegratorFromFlags(simulator, DEFAULT_INTEGRATOR, MAX_STEP)  # the integrator armlab simulate uses
    simulator.get_mutable_integrator().set_target_accuracy(DEFAULT_ACCURACY)
    simulator.AdvanceTo(log.t[-1])
    data = logger.FindLog(simulator.get_context())
    q_ref = log.motion.evaluate(data.sample_times())[0]
    assert np.max(np.abs(data.data()[:2].T - q_ref)) <= 1e-6


@pytest.mark.parametrize(("name", "path", "payload"), [("rr", None, 0.0), ("rr", "abcd", 0.0), ("r2t", None, 20.0),
                                                        ("arm4r", None, 0.0)])
def test_energy_work_of_the_torques_equals_the_change_in_energy(name, path, payload):
    """∫ τ·q̇ dt (composite Simpson over the 1 ms log) = Δ(kinetic + potential energy), Drake's energies."""
    log = run(name, path, log_period=1e-3, payload=payload)
    plant = sim_plant(log)
    context = plant.CreateDefaultContext()
    for k in range(len(log.run_starts)):
        rows = np.flatnonzero(log.run == k)
        rows = rows[: len(rows) - (len(rows) - 1) % 2]  # an odd number of samples for Simpson's rule
        t, power = log.t[rows], np.sum(log.tau[rows] * log.qd[rows], axis=1)
        h = np.diff(t)
        assert np.allclose(h, h[0], rtol=1e-9)
        work = np.concatenate([[0.0], np.cumsum(h[0] / 3 * (power[:-2:2] + 4 * power[1:-1:2] + power[2::2]))])
        energy = []
        for i in rows[::2]:
            plant.SetPositions(context, log.q[i])
            plant.SetVelocities(context, log.qd[i])
            energy.append(plant.CalcKineticEnergy(context) + plant.CalcPotentialEnergy(context))
        energy = np.array(energy)
        scale = max(1.0, np.max(np.abs(energy - energy[0])))
        np.testing.assert_allclose(work, energy - energy[0], rtol=0, atol=1e-7 * scale)


# --------------------------------------------------------------------------------------------- tool point
def test_rr_tool_point_matches_the_papers_equations():
    """x = L1 c1 + L2 c12, y = L1 s1 + L2 s12 (eqs. 1–2) and their time derivatives, written out."""
    log = run("rr", "abcd")
    L1, L2 = log.arm.parameters["L1"], log.arm.parameters["L2"]
    (t1, t2), (w1, w2), (a1, a2) = log.q.T, log.qd.T, log.qdd_ref.T
    t12, w12, a12 = t1 + t2, w1 + w2, a1 + a2
    p = np.stack([L1 * np.cos(t1) + L2 * np.cos(t12), L1 * np.sin(t1) + L2 * np.sin(t12)], axis=-1)
    v = np.stack([-L1 * np.sin(t1) * w1 - L2 * np.sin(t12) * w12, L1 * np.cos(t1) * w1 + L2 * np.cos(t12) * w12], -1)
    a = np.stack([-L1 * (np.cos(t1) * w1**2 + np.sin(t1) * a1) - L2 * (np.cos(t12) * w12**2 + np.sin(t12) * a12),
                  -L1 * (np.sin(t1) * w1**2 - np.cos(t1) * a1) - L2 * (np.sin(t12) * w12**2 - np.cos(t12) * a12)], -1)
    np.testing.assert_allclose(log.tool[:, :2], p, rtol=0, atol=1e-12)
    np.testing.assert_allclose(log.tool[:, 3:5], v, rtol=0, atol=1e-12)
    np.testing.assert_allclose(log.tool[:, 6:8], a, rtol=0, atol=1e-6)  # v̇ of the plant = q̈_ref to tracking accuracy
    np.testing.assert_array_equal(log.tool[:, [2, 5, 8]], 0.0)  # exact: rr's z


@pytest.mark.slow
@pytest.mark.parametrize("name", ["rrrr", "arm4r", "r2t", "urm6"])
def test_tool_point_matches_forward_kinematics_and_finite_differences(name):
    log = run(name, log_period=1e-3) if name != "rrrr" else run(name)
    np.testing.assert_allclose(log.tool[:, :3], log.arm.forward(log.q).tool[:, :3, 3], rtol=0, atol=1e-9)
    h = log.t[1] - log.t[0]
    for k in (0, 1):  # velocity from position, acceleration from velocity: central differences, O(h²)
        x = log.tool[:, 3 * k: 3 * k + 3]
        fd = (x[2:] - x[:-2]) / (2 * h)
        d3 = np.max(np.abs(np.diff(log.tool[:, 3 * k + 3: 3 * k + 6], 2, axis=0))) / h**2  # ≈ max |third derivative|
        np.testing.assert_allclose(log.tool[1:-1, 3 * k + 3: 3 * k + 6], fd, rtol=0, atol=h**2 * d3 / 6 * 1.5 + 1e-9)


# ------------------------------------------------------------------------- samples from the dense output
@pytest.mark.parametrize(("name", "mode"), [("rr", "controller"), ("r2t", "controller"), ("urm6", "controller"),
                                            ("rr", "inverse_dynamics"), ("r2t", "inverse_dynamics")])
def test_log_samples_equal_the_diagram_evaluated_at_each_state(rng, name, mode):
    """log_samples (batched, after the run) = what the diagram's loggers record at the same time and state.

    At random times and states off the reference (so the PD and integral terms, gravity and the payload all
    matter), the diagram is evaluated one sample at a time by a forced publish of its loggers.
    """
    arm = get_arm(name)
    run = build_diagram(arm, paper_motion(arm), SimulationOptions(PlantOptions(payload=2.0, ideal_drives=True),
                                                                  mode=mode, ki=5.0))
    context = run.diagram.CreateDefaultContext()
    plant_rows, other_rows = state_rows(run, context)
    assert len(plant_rows) == 2 * arm.n and len(other_rows) == (arm.n if mode == "controller" else 0)
    t = np.sort(rng.uniform(0, run.motion.duration, 40))
    q, v = run.motion.evaluate(t)[:2]
    x = np.empty((t.size, context.num_continuous_states()))
    x[:, plant_rows] = np.hstack([q + rng.normal(0, 0.05, q.shape), v + rng.normal(0, 0.2, v.shape)])
    x[:, other_rows] = rng.normal(0, 0.02, (t.size, other_rows.size))
    for ti, xi in zip(t, x, strict=True):
        context.SetTime(ti)
        context.SetContinuousState(xi)
        run.diagram.ForcedPublish(context)
    made = log_samples(run, t, x, plant_rows, other_rows)
    for role, logger in run.loggers.items():
        log = logger.FindLog(context)
        np.testing.assert_array_equal(log.sample_times(), t)  # exact: the times this test set
        own = log.data().T
        np.testing.assert_allclose(made[role], own, rtol=0, atol=1e-9 * max(1.0, np.max(np.abs(own))), err_msg=role)


def test_sample_times_are_the_periodic_publish_times():
    """k·Δt up to the end, and the end itself when Δt does not divide it (as Drake's periodic events and the end)."""
    np.testing.assert_array_equal(sample_times(2.0, 1e-3), np.arange(2001) * 1e-3)  # exact: k·Δt, one product each
    t = sample_times(1.5, 0.007)
    assert t.size == 216 and t[-2] == 214 * 0.007 and t[-1] == 1.5  # exact: k·Δt, and the end as given
    # exact: 0·0.1, 1·0.1, 2·0.1 and the end
    np.testing.assert_array_equal(sample_times(0.3, 0.1), [0.0, 0.1, 0.2, 0.3])  # 3·0.1 > 0.3: the end instead
    arm = get_arm("rr")
    for tf, dt in ((0.3, 0.1), (0.7, 0.1), (1.5, 0.007)):
        motion = Motion((QuinticSegment(np.zeros(2), np.ones(2), tf),))
        # Drake's periodic event times (k·period, in C++) against numpy's: one correctly rounded product each, so
        # equal in practice; 4 ulps of the end time for another evaluation order in another Drake or CPU
        options = SimulationOptions(log_period=dt, sampling="periodic")
        assert_rounding_close(simulate(arm, motion, options).t, sample_times(tf, dt), 4)


#: Dense-output runs against the periodic loggers (the integrator stopping at every sample): (arm, path, Δt, mode).
PERIODIC = [("rr", None, 1e-3, "controller"), ("rr", "abcd", 3e-3, "controller"), ("rrrr", None, 7e-3, "controller"),
            ("arm4r", None, 3e-3, "controller"), ("r2t", None, 3e-3, "controller"), ("urm6", None, 3e-3, "controller"),
            ("rr", None, 3e-3, "inverse_dynamics"), ("r2t", None, 7e-3, "inverse_dynamics")]


@pytest.mark.slow
@pytest.mark.parametrize(("name", "path", "dt", "mode"), PERIODIC,
                         ids=[f"{a}-{p or ''}-{dt:g}-{m}" for a, p, dt, m in PERIODIC])
def test_dense_samples_equal_the_periodic_loggers(name, path, dt, mode):
    """The samples made from the dense output after the run equal what loggers publishing every Δt record.

    Same times (to 4 ulps: Drake's and numpy's k·Δt), the reference to round-off; the state within 1e-8 (both runs
    are error-controlled to 1e-6 and track to ~1e-9), torques and the tool point within 1e-6 of their size.
    """
    arm = get_arm(name)
    motion = paper_motion(arm, path)
    dense = simulate(arm, motion, SimulationOptions(log_period=dt, mode=mode))
    periodic = simulate(arm, motion, SimulationOptions(log_period=dt, mode=mode, sampling="periodic"))
    assert_rounding_close(dense.t, periodic.t, ulps=4)  # numpy's sample times against Drake's: as above
    # exact: run indices are integers
    np.testing.assert_array_equal(dense.run, periodic.run)
    for key, atol in (("q_ref", 1e-12), ("qd_ref", 1e-12), ("qdd_ref", 1e-10), ("q", 1e-8), ("qd", 1e-8),
                      ("tau", 1e-6), ("tool", 1e-6)):
        expected = getattr(periodic, key)
        scale = max(1.0, np.max(np.abs(expected))) if key in ("tau", "tool") else 1.0
        np.testing.assert_allclose(getattr(dense, key), expected, rtol=0, atol=atol * scale, err_msg=key)
    assert np.max(np.abs(dense.q - dense.q_ref)) <= 1e-6


def test_no_integrator_step_straddles_a_jump_of_the_time_optimal_timing():
    """A time-optimal timing's s̈ switches at its knots (q̈_d jumps there): the simulation ends a step at each of
    them, as at a join of segments, so no step meets a jump inside it. Issue 29's UR5 line (5 kg): straddled, the
    error control left 8e-5 rad of tracking error there, and the controller's feedback on it took joint 2 to
    150.0075 N·m, past the limit its timing kept 0.05 % free of, on one OpenBLAS kernel of four."""
    from armlab.planning.timing import fastest

    arm = get_arm("ur5")
    upright = np.array([0.0, -np.pi / 2, 0.0, -np.pi / 2, 0.0, 0.0])
    line = armlab.line(arm, None, [0.3, 0.3, 0.2], tf=2.0, q0=upright)
    motion = fastest(arm, line, velocity=np.pi, effort=[150, 150, 150, 28, 28, 28], payload=5.0).motion
    (segment,) = motion.segments
    jumps = motion.jumps()
    knots = segment.knots()
    assert jumps[0] == 0.0 and jumps[-1] == motion.duration  # exact: the ends themselves
    assert knots.size > 500 and np.abs(jumps[:, None] - knots[None, :]).min(axis=0).max() <= 1e-12
    ends: list[float] = []
    options = SimulationOptions(PlantOptions(payload=5.0, ideal_drives=True))
    run_simulator(build_diagram(arm, motion, options), DEFAULT_ACCURACY,
                  lambda context: ends.append(context.get_time()))
    ends_array = np.array(ends)
    assert np.abs(ends_array[None, :] - jumps[1:, None]).min(axis=1).max() <= 1e-12  # a step ends on every jump
    run = armlab.simulate(arm, motion, payload=5.0)
    assert np.max(np.abs(run.q - run.q_ref)) <= 2e-5  # 8e-5 rad with the jumps straddled
    assert run.violations == []


def test_a_sample_the_loggers_disagree_with_is_an_error(monkeypatch):
    """run_simulator checks the samples it makes against the loggers' own end sample."""
    import armlab.diagrams.simulate as simulate_module

    real = simulate_module.log_samples

    def off_by_a_little(*args):
        made = real(*args)
        made["torque"] = made["torque"] * (1 + 1e-6)
        return made

    monkeypatch.setattr(simulate_module, "log_samples", off_by_a_little)
    arm = get_arm("rr")
    with pytest.raises(RuntimeError, match="torque samples made from the integrator's dense output differ"):
        simulate(arm, paper_motion(arm), SimulationOptions(log_period=0.01))


# ---------------------------------------------------------------------------------------------- diagram
def test_dot_names_the_fig6_blocks():
    arm = get_arm("rr")
    for mode, controller in (("controller", "InverseDynamicsController"), ("inverse_dynamics", "InverseDynamics")):
        dot = build_diagram(arm, paper_motion(arm), SimulationOptions(mode=mode)).diagram.GetGraphvizString(
            max_depth=1)
        for name in ("TrajectorySource", controller, "MultibodyPlant", "ToolPoint", "log_reference", "log_state",
                     "log_torque", "log_tool"):
            assert f"name={name}" in dot, name
    with pytest.raises(ValueError, match="one continuous run"):
        build_diagram(arm, paper_motion(arm, "abcd"))
    with pytest.raises(ValueError, match="mode 'open' is not allowed"):
        SimulationOptions(mode="open")
    with pytest.raises(ValueError, match="log period = 0 s"):
        SimulationOptions(log_period=0)
    with pytest.raises(ValueError, match=r"log period = 3 s is longer than the motion \(2 s\)"):
        build_diagram(arm, paper_motion(arm), SimulationOptions(log_period=3))


def test_the_motion_is_checked_against_the_limits_once(monkeypatch):
    """simulate checks the whole motion once (not again in each run's build_diagram); build_diagram alone checks."""
    arm = get_arm("rr")
    motion = paper_motion(arm, "abcd")
    calls = []
    check = Motion.check_limits
    monkeypatch.setattr(Motion, "check_limits", lambda self, a: calls.append(self) or check(self, a))
    simulate(arm, motion, SimulationOptions(log_period=0.01))
    assert calls == [motion] and len(motion.runs()) > 1
    run = motion.runs()[0][1]
    build_diagram(arm, run)
    assert calls == [motion, run]
    beyond = Motion((QuinticSegment(np.zeros(2), np.array([0.0, 9.0]), 1.0, "far"),), "past q2's limit")
    with pytest.raises(ValueError, match="segment far end"):
        build_diagram(arm, beyond)


# --------------------------------------------------------------------------------------------- the CLI
def cli(*argv: str) -> int:
    """``armlab ARGV`` in this process: its exit code (argparse's own errors exit 2 too)."""
    try:
        return main(list(argv))
    except SystemExit as error:
        return int(error.code)


@pytest.mark.slow  # a whole simulate run's files; the numbers in them are checked by the tests above
def test_simulate_writes_the_whole_run(tmp_path, capsys):
    out = tmp_path / "runs" / "rr"
    assert cli("simulate", "rr", "--path", "abcd", "--dt", "0.01", "--out", str(out)) == 0
    files = {p.name for p in out.iterdir()}
    # log, summary, diagrams, plots, drives and the replay; no clearance.png: rr's two links are adjacent
    assert files == set(RUN_OUTPUTS) - {"clearance.png", *SERVO_PLOTS}  # not a servo run: no servo.png, bode.png
    assert [p.name for p in (tmp_path / "runs").iterdir()] == ["rr"]  # no temporary folder left
    umask = os.umask(0o022)
    os.umask(umask)
    assert stat.S_IMODE(out.stat().st_mode) == 0o777 & ~umask  # an ordinary folder and files, not mkdtemp's 0700 …
    for path in out.iterdir():  # … or mkstemp's 0600
        assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask, path.name
    header = (out / "log.csv").read_text().splitlines()[0].split(",")
    assert header == csv_header(2)
    assert header[:4] == ["t", "q1_ref", "q2_ref", "qd1_ref"] and header[-9:] == "x y z vx vy vz ax ay az".split()
    table = np.loadtxt(out / "log.csv", delimiter=",", skiprows=1)
    assert table.shape == (803, 1 + 6 * 2 + 9)  # 3 runs: 401 + 201 + 201 samples
    summary = json.loads((out / "summary.json").read_text())
    for key in ("max_abs_torque", "rms_torque", "peak_power", "max_tracking_error", "quintic_coefficients", "segments"):
        assert key in summary, key
    assert [s["label"] for s in summary["segments"]] == ["A-B", "B-C", "C-D", "D-A"]
    assert np.array(summary["quintic_coefficients"]).shape == (4, 2, 6)
    assert summary["runs"]["count"] == 3 and "reconfigure" in summary["runs"]["note"]
    per_segment = np.array([s["max_abs_torque"] for s in summary["segments"]])
    np.testing.assert_allclose(per_segment.max(axis=0), summary["max_abs_torque"])
    np.testing.assert_allclose(summary["max_abs_torque"], np.max(np.abs(table[:, 11:13]), axis=0), rtol=1e-10)
    assert (out / "diagram.svg").read_text().lstrip().startswith(("<?xml", "<svg"))
    captured = capsys.readouterr()
    assert "wrote" in captured.out and captured.err == ""  # stderr not a terminal: no progress bar
    # running again replaces the previous run
    assert cli("simulate", "rr", "--dt", "0.01", "--out", str(out)) == 0
    assert json.loads((out / "summary.json").read_text())["duration"] == 2.0  # exact: --tf 2


@pytest.mark.slow
@pytest.mark.parametrize("name", ["rrrr", "arm4r", "r2t", "urm6"])
def test_simulate_every_arm(simulated, name):
    extra = ("--tf", "2") if name == "rrrr" else ()  # the paper's 15 s run, shortened
    out = simulated(name, "--dt", "0.01", *extra)  # exit 0; the same run test_replay.py's Chromium test opens
    summary = json.loads((out / "summary.json").read_text())
    assert summary["arm"] == name and max(summary["max_tracking_error"]) <= 1e-6
    assert summary["min_clearance"]  # each of these arms has pairs of non-adjacent links: clearance.png is written
    assert {p.name for p in out.iterdir()} == set(RUN_OUTPUTS) - set(SERVO_PLOTS)


@pytest.mark.slow
def test_simulate_motion_options(tmp_path):
    out = tmp_path / "run"
    cli("simulate", "r2t", "--from", "0,0.1,0.1", "--to", "90,0.2,0.0", "--deg", "--tf", "1.5", "--payload", "20",
        "--gravity", "off", "--mode", "inverse_dynamics", "--dt", "0.007", "--out", str(out))
    summary = json.loads((out / "summary.json").read_text())
    # exact: the options given
    assert summary["duration"] == 1.5 and summary["payload_kg"] == 20 and summary["gravity"] == [0, 0, 0]
    # exact: the open loop's constant
    assert summary["mode"] == "inverse_dynamics" and summary["integrator"]["max_step"] == 0.002  # open loop: 2 ms
    np.testing.assert_allclose(summary["segments"][0]["q_end"], [np.pi / 2, 0.2, 0.0])
    table = np.loadtxt(out / "log.csv", delimiter=",", skiprows=1)
    # exact: the end time given
    assert table.shape[0] == 216 and table[-2, 0] == pytest.approx(1.498) and table[-1, 0] == 1.5  # 7 ms, and the end
    cli("simulate", "r2t", "--gravity", "-x", "--tf", "1", "--dt", "0.01", "--out", str(out))  # -x: not an option
    assert json.loads((out / "summary.json").read_text())["gravity"] == [-9.81, 0, 0]  # exact: -x gravity


@pytest.mark.parametrize(("argv", "message"), [
    (("rr", "--tf", "0"), "tf = 0.0 s is not allowed"),
    (("rr", "--tf", "nan"), "not a finite number"),
    (("rr", "--tf", "1,2"), "give one duration"),
    (("rr", "--from", "0,0", "--to", "0,nan"), "not a finite number"),
    (("rr", "--from", "0,0", "--to", "0,300", "--deg"), "outside its limits"),
    (("rr", "--from", "0,0"), "--from needs --to"),
    (("rr", "--from", "0,0,0", "--to", "0,0"), "rr has 2 joints"),
    (("arm4r", "--path", "abcd"), "invalid choice|not available"),
    (("rr", "--dt", "0"), "log period = 0.0 s"),
    (("rr", "--dt", "5"), "longer than the motion"),
    (("rr", "--payload", "-1"), "payload"),
    (("rr", "--gravity", "sideways"), "gravity"),
    (("rr", "--kp", "1,2,3"), "kp has 3 values"),
    (("rr", "--segments", "x.json", "--tf", "1"), "do not combine"),
])
def test_simulate_bad_input_is_one_clear_error_and_writes_nothing(tmp_path, capsys, argv, message):
    assert cli("simulate", *argv, "--out", str(tmp_path / "run")) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and err.startswith("armlab: error:"), err
    assert re.search(message, err), err
    assert list(tmp_path.iterdir()) == []


def test_unwritable_out_is_an_error_before_simulating(tmp_path, monkeypatch, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setattr("armlab.api.run_diagram", lambda *a, **k: pytest.fail("simulated anyway"))
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("keep me")
    for out, message in ((blocker / "run", "cannot write in"), (blocker, "exists and is not a folder"),
                         (tmp_path / "mine", "not an armlab run folder")):
        assert cli("simulate", "rr", "--out", str(out)) == 2
        assert message in capsys.readouterr().err
    assert (tmp_path / "mine" / "notes.txt").read_text() == "keep me"
    for name in ("log.csv", "summary.json"):  # a run's files beside a file of the user's: still not a run folder
        (tmp_path / "mine" / name).write_text("")
    assert cli("simulate", "rr", "--out", str(tmp_path / "mine")) == 2
    assert "not an armlab run folder" in capsys.readouterr().err
    assert (tmp_path / "mine" / "notes.txt").read_text() == "keep me"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file", "mine"]


def test_failed_run_leaves_no_folder(tmp_path, monkeypatch, capsys):
    def broken(*args, **kwargs):
        raise ValueError("boom")

    monkeypatch.setattr("armlab.diagrams.run.replay_log", broken)  # the last file a run writes
    assert cli("simulate", "rr", "--dt", "0.01", "--out", str(tmp_path / "run")) == 2
    assert "boom" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("suffix", ["dot", "svg", "png", "pdf"])
def test_diagram_command(tmp_path, suffix):
    out = tmp_path / f"fig6.{suffix}"
    assert cli("diagram", "arm4r", "--out", str(out)) == 0
    data = out.read_bytes()
    if suffix == "dot":
        text = data.decode()
        assert text.startswith("digraph") and all(name in text for name in (
            "TrajectorySource", "InverseDynamicsController", "MultibodyPlant", "ToolPoint", "log_tool"))
        assert cli("diagram", "arm4r", "--full", "--out", str(out)) == 0  # Drake's own graph
        text = out.read_text()
        assert "name=InverseDynamicsController" in text and "name=log_tool" in text
    elif suffix == "svg":
        assert b"<svg" in data and b"TrajectorySource" in data
    elif suffix == "png":
        assert data.startswith(b"\x89PNG")
    else:
        assert data.startswith(b"%PDF")
    assert cli("diagram", "rr", "--out", str(tmp_path / "fig6.jpg")) == 2


def test_summarize_single_segment_keys():
    log = run("rr")
    summary = summarize(log)
    assert summary["segments"][0]["label"] == "Fig3" and summary["runs"]["count"] == 1
    np.testing.assert_allclose(summary["quintic_coefficients"][0], log.motion.coefficients()[0])
    assert summary["peak_power"] == pytest.approx(np.max(np.abs(np.sum(log.tau * log.qd, axis=1))))


def test_hold_motion_for_the_diagram_of_a_still_arm():
    arm = get_arm("rr")
    motion = Motion((QuinticSegment(np.zeros(2), np.zeros(2), 1.0),))
    log = simulate(arm, motion, SimulationOptions(log_period=0.05))
    np.testing.assert_allclose(log.q, 0.0, atol=1e-12)
    # holding still against gravity: τ = gravity torques, the Lagrange equations with q̇ = q̈ = 0
    np.testing.assert_allclose(log.tau, lagrange_rr(arm, log.q, 0 * log.q, 0 * log.q, log.gravity), atol=1e-9)


# ------------------------------------------------------------------------------- work limits, progress, Ctrl-C
@pytest.mark.parametrize(("argv", "message"), [
    (("rr", "--tf", "1e6"), r"makes 1,000,000,00\d log samples, more than the 1,000,000 allowed: give a longer log "
                            r"period \(--dt\)"),
    (("rr", "--dt", "1e-9"), "makes 2,000,000,00\\d log samples"),
    (("rr", "--tf", "1e4", "--dt", "1"), "needs at least 1,000,000 integrator steps .* more than the 500,000 allowed"),
    (("urm6", "--from", "0,0,0,0,0,0", "--to", "1e6,0,0,0,0,0"), "1e\\+06 rad \\(or m\\) of joint travel needs at "
                                                                 "least 2,000,000 integrator steps"),
    (("rrrr", "--segments", "SEGMENTS"), "makes 10,000,00\\d log samples"),
])
def test_work_that_cannot_finish_is_refused_before_it_starts(tmp_path, capsys, argv, message):
    segments = tmp_path / "huge.json"
    segments.write_text(json.dumps({"segments": [{"from": [0, 0, 0, 0], "to": [1, 1, 1, 1], "tf": 1e4}]}))
    argv = tuple(str(segments) if a == "SEGMENTS" else a for a in argv)
    assert cli("simulate", *argv, "--out", str(tmp_path / "run")) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and err.startswith("armlab: error:"), err
    assert re.search(message, err), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["huge.json"]


def test_a_run_past_the_step_budget_stops_with_a_clear_error(monkeypatch):
    """The integrator's steps are counted as it goes: past MAX_STEPS the run stops (ValueError), where it is."""
    import armlab.diagrams.simulate as simulate_module

    arm = get_arm("rr")
    motion = paper_motion(arm)
    assert simulate_module.check_work(motion, 1e-3) == (2001, 200)  # within the limits before it starts
    monkeypatch.setattr(simulate_module, "MAX_STEPS", 500)  # the estimate, 200, passes; at 1e-12 it takes ~1000
    with pytest.raises(ValueError, match=r"took more than 500 steps and reached only t = [01]\.\d* s of 2 s"):
        simulate(arm, motion, SimulationOptions(accuracy=1e-12))


def _armlab(*argv: str, **kwargs) -> subprocess.Popen:
    """``armlab ARGV`` in a new process (the venv's console script)."""
    return subprocess.Popen([str(Path(sys.executable).with_name("armlab")), *argv], **kwargs)


def test_ctrl_c_stops_a_long_simulation_promptly(tmp_path):
    """SIGINT while the integrator runs: exit 130 within a second or two, no output folder."""
    out = tmp_path / "run"
    process = _armlab("simulate", "rr", "--tf", "3000", "--dt", "0.01", "--out", str(out), stdout=subprocess.PIPE,
                      stderr=subprocess.PIPE, text=True)
    assert process.stdout.readline().startswith("rr:")  # printed just before the simulation starts
    time.sleep(1.0)
    assert process.poll() is None  # 300,000 integrator steps take longer than that
    process.send_signal(signal.SIGINT)
    sent = time.monotonic()
    assert process.wait(timeout=30) == 130
    assert time.monotonic() - sent < 5.0
    assert list(tmp_path.iterdir()) == []


def test_progress_shows_on_a_terminal(tmp_path):
    """On a terminal, stderr shows the simulated time out of the total and the rate (test_simulate_writes_the_whole_run:
    not elsewhere)."""
    import fcntl
    import pty
    import struct
    import termios

    argv = ("simulate", "rr", "--tf", "40", "--dt", "0.1")  # 4,000 integrator steps: longer than the bar's delay
    leader, follower = pty.openpty()
    fcntl.ioctl(follower, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 120, 0, 0))  # a terminal 120 columns wide
    process = _armlab(*argv, "--out", str(tmp_path / "tty"), stdout=subprocess.DEVNULL, stderr=follower)
    os.close(follower)
    shown = b""
    while True:
        try:
            chunk = os.read(leader, 4096)
        except OSError:  # the process closed the terminal
            break
        if not chunk:
            break
        shown += chunk
    os.close(leader)
    assert process.wait(timeout=120) == 0
    text = shown.decode(errors="replace")
    assert re.search(r"simulating rr: \d+\.\d\d/40 s \|.*\| .*s/s", text), text  # elsewhere: quiet (see above)
