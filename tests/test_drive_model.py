"""The drive train in the model (issue 19 §1; issue 24 item 4): where it comes from, the plant, the controller,
the inverse dynamics, the motor side, and the Puma 560's drive data checked against an independent Newton–Euler."""

from __future__ import annotations

import csv
import json
from dataclasses import replace

import numpy as np
import pytest
from helpers import DATA, armlab_main, random_q, rnea_in_dh_frames

import armlab
from armlab.diagrams.simulate import SimulationOptions, simulate
from armlab.drives.train import COULOMB_SPEED, DRIVE_FIELDS, DriveTrain
from armlab.models.export import dh_text
from armlab.models.plant import PlantOptions

DAMPED = DATA / "damped_two_link.urdf"
PUMA = DATA / "puma560_drives_dh.csv"
RR_DRIVES = DATA / "rr_drives.csv"


def _drake_plant(path):
    """Drake's own reading of a URDF (its parser, not armlab's), base welded, finalized."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(path))
    plant.WeldFrames(plant.world_frame(), plant.GetFrameByName("base"))
    plant.Finalize()
    return plant


def _states(arm, rng, size):
    """``size`` random states (q within the limits, q̇ rad/s, q̈ rad/s²), each ``(size, n)``."""
    return random_q(arm, rng, size), rng.normal(size=(size, arm.n)) * 1.5, rng.normal(size=(size, arm.n)) * 4


# ------------------------------------------------------------------------------------- where it comes from
def test_urdf_drive_train_is_what_drake_reads():
    """armlab reads a URDF's <dynamics damping friction> and <transmission> rotor inertia and gear ratio as Drake's
    parser does (Drake's own plant of the file, not armlab's builder); Drake ignores friction, armlab keeps it."""
    from pydrake.multibody.tree import JointActuatorIndex

    arm = armlab.load(DAMPED)
    plant = _drake_plant(DAMPED)
    actuators = {a.joint().name(): a for a in (plant.get_joint_actuator(JointActuatorIndex(i))
                                               for i in range(plant.num_actuators()))}
    drives = arm.drives
    assert drives is not None
    for k, name in enumerate(arm.joint_names):
        np.testing.assert_allclose(drives.rotor_inertia[k], actuators[name].default_rotor_inertia(), rtol=1e-15)
        np.testing.assert_allclose(drives.gear_ratio[k], actuators[name].default_gear_ratio(), rtol=1e-15)
        np.testing.assert_allclose(drives.viscous[k], plant.GetJointByName(name).default_damping(), rtol=1e-15)
    np.testing.assert_allclose(drives.coulomb, [0.4, 0.0], rtol=1e-15)  # the file's friction=
    shown = armlab_main("show", str(DAMPED))
    assert shown.returncode == 0 and "drive train" in shown.stdout
    assert shown.stdout.splitlines()[-2].split() == ["shoulder", "100", "2e-05", "1", "5", "0.4"]


def test_urdf_drake_namespace_may_be_undeclared(tmp_path):
    """Drake reads <drake:…> tags without the xmlns:drake declaration; so does armlab."""
    path = tmp_path / "undeclared.urdf"
    path.write_text(DAMPED.read_text().replace(' xmlns:drake="http://drake.mit.edu"', ""))
    assert "xmlns:drake" not in path.read_text()
    drives, declared = armlab.load(path).drives, armlab.load(DAMPED).drives
    np.testing.assert_allclose(drives.rotor_inertia, declared.rotor_inertia, rtol=1e-15)
    np.testing.assert_allclose(drives.gear_ratio, declared.gear_ratio, rtol=1e-15)


def test_dh_and_drive_file_columns(tmp_path):
    """A DH table's drive columns and a drive file give the same train; motor-side friction is converted once
    (B = G²·B_m, T_c = |G|·T_c,m); a drive file replaces an arm's own train."""
    puma = armlab.load(PUMA)
    with PUMA.open() as handle:
        rows = list(csv.DictReader(line for line in handle if not line.startswith("#")))
    g = np.array([float(r["gear_ratio"]) for r in rows])
    np.testing.assert_allclose(puma.drives.viscous, g**2 * np.array([float(r["viscous_motor"]) for r in rows]),
                               rtol=1e-15)
    np.testing.assert_allclose(puma.drives.coulomb, np.abs(g) * np.array([float(r["coulomb_motor"]) for r in rows]),
                               rtol=1e-15)
    np.testing.assert_allclose(puma.drives.negative,
                               np.abs(g) * np.array([float(r["coulomb_negative_motor"]) for r in rows]), rtol=1e-15)
    assert puma.drives.asymmetric
    drive_file = tmp_path / "puma_drives.csv"
    columns = ["gear_ratio", "rotor_inertia", "viscous_motor", "coulomb_motor", "coulomb_negative_motor"]
    drive_file.write_text("# the same drives as a drive file\n" + ",".join(columns) + "\n"
                          + "\n".join(",".join(r[c] for c in columns) for r in rows) + "\n")
    again = armlab.load(PUMA, drives=drive_file)
    for name in DRIVE_FIELDS:
        np.testing.assert_allclose(again.drives.per_joint(name), puma.drives.per_joint(name), rtol=1e-15)
    rr = armlab.load("rr", drives=RR_DRIVES)
    assert armlab.load("rr").drives is None and rr.drives is not None and rr.drives.n == 2
    np.testing.assert_allclose(rr.drives.efficiency, [0.8, 0.75], rtol=1e-15)


@pytest.mark.parametrize(("header", "joint_side", "motor_side"), [
    ("gear_ratio,viscous_motor,coulomb", "coulomb", "viscous"),
    ("gear_ratio,coulomb_motor,viscous", "viscous", "coulomb"),
])
def test_each_friction_from_its_own_side(tmp_path, header, joint_side, motor_side):
    """One friction given motor side, the other joint side: each kept, the motor-side one converted
    (B = G²·B_m, T_c = |G|·T_c,m); none dropped."""
    path = tmp_path / "mixed.csv"
    path.write_text(f"{header}\n-10,0.5,3\n20,0.25,4\n")
    drives = armlab.load("rr", drives=path).drives
    g, given = np.array([-10.0, 20.0]), np.array([0.5, 0.25])
    converted = g**2 * given if motor_side == "viscous" else np.abs(g) * given
    np.testing.assert_allclose(getattr(drives, motor_side), converted, rtol=1e-15)
    np.testing.assert_allclose(getattr(drives, joint_side), [3.0, 4.0], rtol=1e-15)
    np.testing.assert_allclose(drives.gear_ratio, g, rtol=1e-15)


def test_asymmetric_coulomb_friction_from_both_sides_and_by_the_joints_direction(tmp_path):
    """T_c+ and T_c− (issue 31): joint side ``coulomb``/``coulomb_negative`` or motor side ``coulomb_motor``/
    ``coulomb_negative_motor`` (× |G|); T_c+ while q̇ ≥ 0, T_c− below, by the joint's direction whatever G's sign;
    without ``coulomb_negative`` the friction is symmetric; a DH export writes both and reads back the same."""
    path = tmp_path / "asymmetric.csv"
    path.write_text("gear_ratio,coulomb_motor,coulomb_negative_motor\n-10,0.5,0.75\n20,0.25,0.1\n")
    drives = armlab.load("rr", drives=path).drives
    np.testing.assert_allclose(drives.coulomb, [5.0, 5.0], rtol=1e-15)
    np.testing.assert_allclose(drives.negative, [7.5, 2.0], rtol=1e-15)
    qd = np.array([[0.5, -0.5], [-0.5, 0.5]])
    np.testing.assert_allclose(drives.coulomb_friction(qd), np.tanh(qd / COULOMB_SPEED) * [[5.0, 2.0], [7.5, 5.0]],
                               rtol=1e-15)
    joint = tmp_path / "joint_side.csv"
    joint.write_text("coulomb,coulomb_negative\n5,7.5\n5,2\n")
    np.testing.assert_allclose(armlab.load("rr", drives=joint).drives.negative, [7.5, 2.0], rtol=1e-15)
    symmetric = tmp_path / "symmetric.csv"
    symmetric.write_text("gear_ratio,coulomb_motor\n-10,0.5\n20,0.25\n")
    plain = armlab.load("rr", drives=symmetric).drives
    assert not plain.asymmetric and "coulomb_negative" not in plain.fields()
    np.testing.assert_allclose(plain.coulomb_friction(-qd), -plain.coulomb_friction(qd), rtol=1e-15)
    puma = armlab.load("puma560")
    table = tmp_path / "puma.csv"
    table.write_text(dh_text(puma))
    again = armlab.load(table)
    for name in DRIVE_FIELDS:
        np.testing.assert_allclose(again.drives.per_joint(name), puma.drives.per_joint(name), rtol=1e-15)


def test_the_plants_coulomb_friction_is_the_drive_trains_both_ways():
    """Drake's side: the diagram's ``joint_friction`` system (drives/friction.py) gives −T_c±·tanh(v/v_s) at the
    plant's state, T_c+ forwards and T_c− backwards, as the inverse dynamics adds it."""
    from armlab.drives.friction import CoulombFriction

    train = DriveTrain(np.ones(2), np.zeros(2), np.ones(2), np.zeros(2), np.array([0.3, 0.2]),
                       coulomb_negative=np.array([0.6, 0.05]))
    system = CoulombFriction(train, -1.0, "joint_friction")
    context = system.CreateDefaultContext()
    for v in ([0.2, -0.004], [-0.05, 0.3]):
        system.get_input_port(0).FixValue(context, np.concatenate([np.zeros(2), v]))
        out = system.get_output_port(0).Eval(context)
        level = np.where(np.array(v) >= 0, [0.3, 0.2], [0.6, 0.05])
        np.testing.assert_allclose(out, -level * np.tanh(np.array(v) / COULOMB_SPEED), rtol=1e-15)


def test_drive_file_trailing_commas_and_a_huge_cell(tmp_path):
    """A spreadsheet's trailing commas are no columns; a cell beyond csv's field limit is a one-line error."""
    path = tmp_path / "excel.csv"
    path.write_text("# from a spreadsheet\r\ngear_ratio,viscous,,\r\n10,1,,\r\n20,2,,\r\n,,,\r\n")
    drives = armlab.load("rr", drives=path).drives
    np.testing.assert_allclose(drives.gear_ratio, [10.0, 20.0], rtol=1e-15)
    np.testing.assert_allclose(drives.viscous, [1.0, 2.0], rtol=1e-15)
    path.write_text(f"gear_ratio\n{'1' * 131073}\n2\n")
    with pytest.raises(ValueError, match=r"drive file cannot be read as CSV: field larger than field limit") as error:
        armlab.load("rr", drives=path)
    assert str(path) in str(error.value) and "\n" not in str(error.value)


# -------------------------------------------------------------------------------------------- the plant
def test_reflected_inertia_enters_the_mass_matrix():
    """Drake's JointActuator rotor inertia and gear ratio: M(q) with the drive train is M(q) without it plus
    diag(G²·J_m), and armlab's inverse dynamics gives that same M column by column."""
    arm = armlab.load(PUMA)
    with_drives, ideal = arm.make_plant(), arm.with_drives(None).make_plant()
    rng = np.random.default_rng(3)
    for q in random_q(arm, rng, 5):
        ctx, ctx0 = with_drives.CreateDefaultContext(), ideal.CreateDefaultContext()
        with_drives.SetPositions(ctx, q)
        ideal.SetPositions(ctx0, q)
        M, M0 = with_drives.CalcMassMatrix(ctx), ideal.CalcMassMatrix(ctx0)
        scale = np.abs(M).max()
        np.testing.assert_allclose(M - M0, np.diag(arm.drives.gear_ratio**2 * arm.drives.rotor_inertia),
                                   rtol=0, atol=1e-12 * scale)
        columns = arm.inverse_dynamics(np.tile(q, (arm.n, 1)), np.zeros((arm.n, arm.n)), np.eye(arm.n),
                                       gravity="off")
        np.testing.assert_allclose(columns.T, M, rtol=0, atol=1e-12 * scale)
    assert np.max(arm.drives.reflected_inertia) > 0.5  # the Puma's joint 2: 107.8² · 200e-6 = 2.3 kg·m²


def test_inverse_dynamics_includes_the_damping_the_plant_applies():
    """Issue 24 item 4: arm.inverse_dynamics is Drake's inverse dynamics of the plant with its force elements
    (gravity and the joints' damping) and reflected inertia, plus the Coulomb friction T_c·tanh(q̇/v_s)."""
    from pydrake.multibody.tree import MultibodyForces

    arm = armlab.load(DAMPED)
    plant = arm.make_plant()
    ctx = plant.CreateDefaultContext()
    q, qd, qdd = _states(arm, np.random.default_rng(5), 20)
    tau = arm.inverse_dynamics(q, qd, qdd)
    for k in range(len(q)):
        plant.SetPositions(ctx, q[k])
        plant.SetVelocities(ctx, qd[k])
        forces = MultibodyForces(plant)
        plant.CalcForceElementsContribution(ctx, forces)
        drake = plant.CalcInverseDynamics(ctx, qdd[k], forces) + arm.drives.coulomb * np.tanh(qd[k] / COULOMB_SPEED)
        np.testing.assert_allclose(tau[k], drake, rtol=1e-9, atol=1e-9 * np.abs(drake).max())
    rigid = arm.inverse_dynamics(q, qd, qdd, drives=DriveTrain.ideal(arm.n))
    np.testing.assert_allclose(tau - rigid, arm.drives.reflected_inertia * qdd + arm.drives.viscous * qd
                               + arm.drives.coulomb * np.tanh(qd / COULOMB_SPEED), rtol=1e-9, atol=1e-9)


# ------------------------------------------------------------------------------------------ the simulation
@pytest.mark.parametrize("mode", ["controller", pytest.param("inverse_dynamics", marks=pytest.mark.slow)])
def test_simulation_with_drives_tracks_and_logs_the_inverse_dynamics(mode):
    """With rotor inertia, damping and Coulomb friction in the plant, the controller's model has the same drive
    train: tracking ≤ 1e-6 rad, and the logged torque is arm.inverse_dynamics along the reference (the dense
    samples: 1e-6 of the peak, what 1e-9 rad of tracking leaves through the steep tanh; open loop: 1e-9)."""
    arm = armlab.load(DAMPED)
    motion = armlab.quintic(arm, [0.0, 0.0], [1.0, -1.2], tf=1.5)
    log = simulate(arm, motion, SimulationOptions(PlantOptions(ideal_drives=True), mode=mode))
    assert np.abs(log.q - log.q_ref).max() <= 1e-6
    expected = arm.inverse_dynamics(log.q_ref, log.qd_ref, log.qdd_ref)
    peak = np.abs(expected).max()
    np.testing.assert_allclose(log.tau, expected, rtol=0, atol=(1e-6 if mode == "controller" else 1e-9) * peak)
    ideal = arm.with_drives(None).inverse_dynamics(log.q_ref, log.qd_ref, log.qdd_ref)
    assert np.abs(log.tau - ideal).max() > 0.2 * peak  # the drive train is a large part of the torque


def test_a_simulation_with_asymmetric_coulomb_friction_logs_its_inverse_dynamics():
    """The plant feels T_c+ on the way out and T_c− on the way back (the motion reverses): the controller's model has
    the same, the run tracks and logs arm.inverse_dynamics to 1e-6 of its peak, far from the mean friction's."""
    arm = armlab.load(DAMPED)
    asymmetric = arm.with_drives(DriveTrain(arm.drives.gear_ratio, arm.drives.rotor_inertia, np.ones(2),
                                            arm.drives.viscous, np.array([0.4, 0.3]), coulomb_negative=[1.6, 0.05]))
    motion = armlab.through(asymmetric, [[0.0, 0.0], [1.0, -1.2], [0.0, 0.0]], tf=1.0)
    log = simulate(asymmetric, motion, SimulationOptions(PlantOptions(ideal_drives=True)))
    assert np.abs(log.q - log.q_ref).max() <= 1e-6
    assert (log.qd_ref[:, 0] > 0.1).any() and (log.qd_ref[:, 0] < -0.1).any()  # both ways
    expected = asymmetric.inverse_dynamics(log.q_ref, log.qd_ref, log.qdd_ref)
    peak = np.abs(expected).max()
    np.testing.assert_allclose(log.tau, expected, rtol=0, atol=1e-6 * peak)
    mean = asymmetric.inverse_dynamics(log.q_ref, log.qd_ref, log.qdd_ref, drives=replace(
        asymmetric.drives, coulomb=np.array([1.0, 0.175]), coulomb_negative=None))
    assert np.abs(log.tau - mean).max() > 0.5  # 0.6 N·m on joint 1 either way


@pytest.mark.parametrize("mode", ["controller", "inverse_dynamics"])
def test_large_damping_from_a_drive_train_reaches_the_joints(mode):
    """Issue 24 item 4: damping large enough that leaving it out of the logged torques crashed ``simulate`` ("the
    torque samples … differ"; open loop "the tool samples …"), on a motion that ends moving (constant rates): the
    drive train's B is the plant's joint damping (Drake's own), and the run tracks and logs B·q̇ with the rest."""
    arm = armlab.load(DAMPED)
    heavy = arm.with_drives(DriveTrain(arm.drives.gear_ratio, arm.drives.rotor_inertia, np.ones(2), [60.0, 25.0],
                                       [1.5, 0.5]))
    plant = heavy.make_plant()
    damping = [plant.GetJointByName(name).default_damping() for name in heavy.joint_names]
    np.testing.assert_allclose(damping, [60.0, 25.0], rtol=1e-15)
    motion = armlab.constant_rate(heavy, [0.0, 0.0], [0.8, -0.6], tf=1.0)
    log = simulate(heavy, motion, SimulationOptions(PlantOptions(ideal_drives=True), mode=mode))
    assert np.abs(log.q - log.q_ref).max() <= 1e-6
    expected = heavy.inverse_dynamics(log.q_ref, log.qd_ref, log.qdd_ref)
    np.testing.assert_allclose(log.tau, expected, rtol=0, atol=1e-6 * np.abs(expected).max())
    friction = [60.0 * 0.8 + 1.5 * np.tanh(0.8 / COULOMB_SPEED), -25.0 * 0.6 - 0.5 * np.tanh(0.6 / COULOMB_SPEED)]
    rigid = arm.with_drives(None).inverse_dynamics(log.q_ref, log.qd_ref, log.qdd_ref)
    np.testing.assert_allclose(log.tau - rigid, friction + heavy.drives.reflected_inertia * log.qdd_ref, rtol=0,
                               atol=1e-5)


@pytest.mark.slow
def test_periodic_loggers_record_the_inverse_dynamics_with_drives():
    """Drake's own loggers (periodic sampling: the diagram's outputs, no armlab recomputation) record the torque
    of arm.inverse_dynamics with the drive train along the motion, to 1e-9 of the peak."""
    arm = armlab.load(DAMPED)
    motion = armlab.quintic(arm, [0.0, 0.0], [1.0, -1.2], tf=1.5)
    log = simulate(arm, motion, SimulationOptions(PlantOptions(ideal_drives=True), sampling="periodic"))
    expected = arm.inverse_dynamics(log.q_ref, log.qd_ref, log.qdd_ref)
    assert np.abs(log.q - log.q_ref).max() <= 1e-6
    np.testing.assert_allclose(log.tau, expected, rtol=0, atol=1e-9 * np.abs(expected).max())


def _motor_side(tau, qd):
    """τ_m = τ/(G·η) where the drive delivers power, τ·η/G where it is driven back, and ω_m = G·q̇, for
    tests/data/rr_drives.csv (G = 100, 80; η = 0.8, 0.75), written out here."""
    g, eta = np.array([100.0, 80.0]), np.array([0.8, 0.75])
    return np.where(tau * qd >= 0, tau / (g * eta), tau * eta / g), g * qd


def test_motor_side_of_a_run(tmp_path):
    """A run with a drive train gives its motor side: the log's τ_m and ω_m, log.csv's tau_m/w_m columns and
    drives.csv's motor columns (Run's own writers), against the rule written out in the test."""
    from armlab.diagrams.drives import drive_table
    from armlab.presentation.output import write_log_csv

    rr = armlab.load("rr", drives=RR_DRIVES)
    log = simulate(rr, armlab.paper_motion(rr))
    tau_m, w_m = _motor_side(log.tau, log.qd)
    np.testing.assert_allclose(log.tau_motor, tau_m, rtol=1e-15, atol=0)
    np.testing.assert_allclose(log.motor_speed, w_m, rtol=1e-15, atol=0)
    assert (log.tau * log.qd < 0).any() and (log.tau * log.qd > 0).any()  # both branches of the rule are used
    table = np.genfromtxt(write_log_csv(log, tmp_path / "log.csv"), delimiter=",", names=True)
    np.testing.assert_allclose(np.column_stack([table["tau_m1"], table["tau_m2"]]), tau_m, rtol=1e-11, atol=1e-15)
    np.testing.assert_allclose(np.column_stack([table["w_m1"], table["w_m2"]]), w_m, rtol=1e-11, atol=1e-15)
    rows = drive_table(log)
    np.testing.assert_allclose([r["rms_motor_torque"] for r in rows], np.sqrt(np.mean(tau_m**2, axis=0)), rtol=1e-12)
    np.testing.assert_allclose([r["peak_motor_speed"] for r in rows], np.abs(w_m).max(axis=0), rtol=1e-12)


@pytest.mark.slow
def test_simulate_cli_writes_the_motor_side(tmp_path):
    """``armlab simulate rr --drives FILE`` as a user runs it: log.csv, drives.csv and summary.json carry the motor
    side and the drive train (the rule checked from the logged τ, q̇ as written)."""
    out = tmp_path / "run"
    result = armlab_main("simulate", "rr", "--drives", str(RR_DRIVES), "--out", str(out))
    assert result.returncode == 0, result.stderr
    with (out / "log.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    tau = np.array([[float(r[f"tau{i}"]) for i in (1, 2)] for r in rows])
    qd = np.array([[float(r[f"qd{i}"]) for i in (1, 2)] for r in rows])
    tau_m = np.array([[float(r[f"tau_m{i}"]) for i in (1, 2)] for r in rows])
    w_m = np.array([[float(r[f"w_m{i}"]) for i in (1, 2)] for r in rows])
    expected, speed = _motor_side(tau, qd)
    np.testing.assert_allclose(tau_m, expected, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(w_m, speed, rtol=1e-9, atol=1e-12)
    g, eta = np.array([100.0, 80.0]), np.array([0.8, 0.75])  # tests/data/rr_drives.csv
    with (out / "drives.csv").open() as handle:
        drives = list(csv.DictReader(handle))
    np.testing.assert_allclose([float(r["peak_motor_torque"]) for r in drives], np.abs(tau_m).max(axis=0), rtol=1e-9)
    np.testing.assert_allclose([float(r["gear_ratio"]) for r in drives], g, rtol=1e-15)
    summary = json.loads((out / "summary.json").read_text())
    np.testing.assert_allclose(summary["drive_train"]["efficiency"], eta, rtol=1e-15)
    assert max(summary["max_tracking_error"]) <= 1e-6


# ------------------------------------------------------------------------------------------ the Puma 560
def test_puma560_joint_torques_equal_an_independent_newton_euler():
    """The Robotics Toolbox's Puma 560 with its drive data (tests/data/puma560_drives_dh.csv): armlab's joint
    torques with the drive train equal a Newton–Euler pass written in the DH frames (tests/helpers.py) plus
    G²·J_m·q̈ plus the friction G²·B_m·q̇ + |G|·T_c±,m·tanh(q̇/v_s) (T_c+ for q̇ ≥ 0, |T_c−| below), all from the
    file's motor-side numbers read here, to 1e-9 relative; and the drive terms are a large part of the torques
    (issue 19: up to 32 of 44 N·m)."""
    arm = armlab.load(PUMA)
    with PUMA.open() as handle:
        rows = list(csv.DictReader(line for line in handle if not line.startswith("#")))
    value = {key: np.array([float(r[key]) for r in rows]) for key in rows[0] if key != "type"}
    dh = [("R", a, np.radians(alpha), d, np.radians(theta))
          for a, alpha, d, theta in zip(value["a"], value["alpha"], value["d"], value["theta"], strict=True)]
    links = [(m, np.array([cx, cy, cz]), np.diag([ixx, iyy, izz])) for m, cx, cy, cz, ixx, iyy, izz in zip(
        *(value[k] for k in ("mass", "cx", "cy", "cz", "Ixx", "Iyy", "Izz")), strict=True)]
    g, jm, bm = value["gear_ratio"], value["rotor_inertia"], value["viscous_motor"]
    tc_plus, tc_minus = value["coulomb_motor"], value["coulomb_negative_motor"]
    rng = np.random.default_rng(560)
    q, qd, qdd = _states(arm, rng, 30)
    tau = arm.inverse_dynamics(q, qd, qdd)
    worst = 0.0
    for k in range(len(q)):
        rigid = rnea_in_dh_frames(dh, "standard", links, q[k], qd[k], qdd[k], arm.gravity)
        tcm = np.where(qd[k] >= 0, tc_plus, tc_minus)
        drive = g**2 * jm * qdd[k] + g**2 * bm * qd[k] + np.abs(g) * tcm * np.tanh(qd[k] / COULOMB_SPEED)
        expected = rigid + drive
        np.testing.assert_allclose(tau[k], expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
        worst = max(worst, float(np.max(np.abs(drive)) / np.max(np.abs(expected))))
    assert worst > 0.5


# -------------------------------------------------------------------------------------------- bad input
@pytest.mark.parametrize(("header", "row", "message"), [
    ("gear_ratio", "0", r"gear_ratio of joint 1 = 0 is not allowed: a finite number other than 0"),
    ("efficiency", "1.5", r"efficiency of joint 1 = 1.5 is not allowed: a number in \(0, 1\]"),
    ("viscous", "-1", r"viscous of joint 1 = -1 N·m·s/rad is not allowed"),
    ("gear_ratio,coulomb", "10,", r"row 1: coulomb is empty"),
    ("rotor_inertia", "nan", r"row 1: rotor_inertia = 'nan' is not a finite number"),
    ("torque", "1", r"unknown drive column\(s\) torque"),
    ("viscous,viscous_motor", "1,1", r"give viscous \(joint side\) or viscous_motor \(motor side\), not both"),
    ("coulomb,coulomb_negative", "1,-0.5", r"coulomb_negative of joint 1 = -0.5 N·m is not allowed: .*magnitude"),
    ("coulomb_negative,coulomb_negative_motor", "1,1", r"give coulomb_negative \(joint side\) or "
                                                         r"coulomb_negative_motor \(motor side\), not both"),
])
def test_bad_drive_file_is_one_line_naming_file_and_value(tmp_path, header, row, message):
    """Every bad value of a drive file is a one-line ValueError naming the file, the row (joint), the column."""
    path = tmp_path / "bad.csv"
    path.write_text(f"{header}\n{row}\n{','.join(['1'] * len(header.split(',')))}\n")  # joint 1 bad, joint 2 not
    with pytest.raises(ValueError, match=message) as error:
        armlab.load("rr", drives=path)
    assert str(path) in str(error.value) and "\n" not in str(error.value)


def test_bad_dh_drive_column_is_one_line(tmp_path):
    """A DH table's drive column with a bad value: one line naming the table and what is allowed; CLI exit 2."""
    path = tmp_path / "puma_bad.csv"
    path.write_text(PUMA.read_text().replace(",71.923,", ",0,"))
    with pytest.raises(ValueError, match=r"puma_bad.csv: drive train gear_ratio of joint 5 = 0 is not allowed"):
        armlab.load(path)
    result = armlab_main("show", str(path))
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1 and "joint 5" in result.stderr


def test_bad_drive_file_shapes_and_cli_exit_2(tmp_path):
    """A drive file with a row count or joint names other than the arm's: one line; the CLI exits 2."""
    path = tmp_path / "three.csv"
    path.write_text("gear_ratio\n10\n20\n30\n")
    with pytest.raises(ValueError, match=r"3 drive row\(s\); the arm has 2 joints"):
        armlab.load("rr", drives=path)
    named = tmp_path / "named.csv"
    named.write_text("joint,gear_ratio\nelbow,10\nshoulder,20\n")
    with pytest.raises(ValueError, match="differs from the arm's joints joint1,joint2"):
        armlab.load("rr", drives=named)
    with pytest.raises(ValueError, match="the drive train has 3 joint"):
        armlab.load("rr").with_drives(DriveTrain.ideal(3))
    result = armlab_main("simulate", "rr", "--drives", str(path), "--out", str(tmp_path / "out"))
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()
