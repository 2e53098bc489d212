"""The library arms (issue 22): every one loads by name and everything armlab does works on it, each number checked
two ways (Drake's plant vs armlab's own kinematics and dynamics, finite differences vs the analytic Jacobian); the
closed forms of the UR and Puma layouts against the numerical solver's branches; and each arm against the
Robotics Toolbox's model of it and against Pinocchio reading armlab's URDF (both test-only extras; skipped with
the reason when absent)."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from helpers import armlab_main

from armlab.kinematics.ik import solve
from armlab.models import get_arm
from armlab.models.library import LIBRARY, library_arm

#: Kinematics to round-off (m, rad), as everywhere in armlab's tests.
TOL = 1e-9
#: Torques (N·m, N) of two implementations of the same rigid-body algorithm: round-off on ≤ 400 N·m.
TORQUE_TOL = 1e-9
MODELS_README = Path(__file__).resolve().parents[1] / "models" / "README.md"


def _inside(arm, rng: np.random.Generator, size: int) -> np.ndarray:
    """Random configurations 1 % inside the limits (revolute within ±π, so that FK ∘ IK has no 2π ambiguity)."""
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    lower, upper = np.maximum(lower, -np.pi), np.minimum(upper, np.pi)
    margin = 0.01 * (upper - lower)
    return rng.uniform(lower + margin, upper - margin, size=(size, arm.n))


def _drake(arm, q: np.ndarray, qd: np.ndarray | None = None, qdd: np.ndarray | None = None):
    """(tool pose (4, 4), inverse dynamics τ (n,) or None) of one state by the arm's Drake plant."""
    plant = arm.make_plant()
    context = plant.CreateDefaultContext()
    plant.SetPositions(context, q)
    pose = plant.CalcRelativeTransform(context, plant.world_frame(), plant.GetFrameByName(arm.tool_name))
    if qd is None or qdd is None:
        return pose.GetAsMatrix4(), None
    from pydrake.multibody.tree import MultibodyForces

    plant.SetVelocities(context, qd)
    forces = MultibodyForces(plant)
    plant.CalcForceElementsContribution(context, forces)
    return pose.GetAsMatrix4(), plant.CalcInverseDynamics(context, qdd, forces)


# ------------------------------------------------------------------ every library arm, everything armlab does
@pytest.mark.parametrize("name", LIBRARY)
def test_library_arm_kinematics_and_dynamics_two_ways(name: str, rng: np.random.Generator) -> None:
    """FK: armlab's DH forward kinematics vs Drake's plant; Jacobian: analytic vs central differences of FK;
    inverse dynamics: armlab's RNEA vs Drake's CalcInverseDynamics (or a one-line refusal for a kinematic arm)."""
    arm = get_arm(name)
    assert arm.paper.startswith("library: ") and arm.notes, "every library arm cites its sources"
    for q in _inside(arm, rng, 3):
        pose, _ = _drake(arm, q)
        np.testing.assert_allclose(arm.fk(q), pose, atol=TOL)
        J, h = arm.jacobian(q), 1e-6
        for j in range(arm.n):
            step = np.zeros(arm.n)
            step[j] = h
            dp = (arm.forward(q + step).tool[:3, 3] - arm.forward(q - step).tool[:3, 3]) / (2 * h)
            np.testing.assert_allclose(J[:3, j], dp, atol=1e-8)  # central differences: O(h²) ≈ 1e-12, round-off 1e-10
        qd, qdd = rng.uniform(-1, 1, size=(2, arm.n))
        if arm.has_dynamics:  # the rigid arm here (a drive train's terms: tests/test_drive_model.py)
            rigid = arm.with_drives(None)
            _, tau = _drake(rigid, q, qd, qdd)
            np.testing.assert_allclose(rigid.inverse_dynamics(q, qd, qdd), tau, atol=TORQUE_TOL, rtol=1e-12)
        else:
            with pytest.raises(ValueError, match="kinematic arm"):
                arm.inverse_dynamics(q, qd, qdd)


#: numerical multi-start IK of a 6- or 7-DOF arm takes seconds: slow (the closed-form arms and irb140 stay fast)
@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in ("kr5", "panda", "stanford")
                                  else n for n in LIBRARY])
def test_library_arm_ik_every_solution_reaches_the_pose(name: str, rng: np.random.Generator) -> None:
    """A pose from FK of a random configuration: every solution returned reaches it to 1e-9 (armlab's FK), the
    single solution nearest ``near`` = q is q, and with a closed form the configuration is among the branches."""
    arm = get_arm(name)
    (q,) = _inside(arm, rng, 1)
    target = arm.fk(q)
    every = arm.ik(target, all=True)
    for s in every:
        T = arm.fk(s)
        assert np.abs(T[:3, 3] - target[:3, 3]).max() <= TOL and np.abs(T[:3, :3] - target[:3, :3]).max() <= TOL
    (best,) = arm.ik(target, near=q)
    np.testing.assert_allclose(best, q, atol=1e-7)  # from near = q the solver stays at q
    if arm.closed_form is not None:
        assert np.min(np.abs(every - q).max(axis=1)) < 1e-9


def test_library_arms_run_through_the_cli(tmp_path) -> None:
    """list shows the library apart from the paper arms; show prints each source; fk and ik run; a kinematic arm's
    simulate is refused in one line; an unknown name lists paper and library arms."""
    listing = armlab_main("list")
    assert listing.returncode == 0
    paper, library = listing.stdout.split("library arms")
    assert all(name not in paper.split() for name in LIBRARY) and all(name in library for name in LIBRARY)
    for name in ("puma560", "panda"):
        shown = armlab_main("show", name)
        assert shown.returncode == 0 and "sources:" in shown.stdout and library_arm(name).paper in shown.stdout
    assert "Corke & Armstrong-Hélouvry" in armlab_main("show", "puma560").stdout
    assert "Gaz et al." in armlab_main("show", "panda").stdout
    fk = armlab_main("fk", "ur5", "--q", "0.1,-1,1,0.2,0.3,0.4")
    assert fk.returncode == 0 and "tool O6" in fk.stdout
    ik = armlab_main("ik", "ur5", "--target", "0.4,0.2,0.3", "--all")
    assert ik.returncode == 0 and 1 <= ik.stdout.count("q (SI)") <= 9
    refused = armlab_main("simulate", "kr5", "--out", str(tmp_path / "run"))
    assert refused.returncode == 2 and "kinematic arm" in refused.stderr and len(refused.stderr.splitlines()) == 1
    unknown = armlab_main("fk", "puma", "--q", "0")
    assert unknown.returncode == 2 and "a library arm (" in unknown.stderr and "puma560" in unknown.stderr
    with pytest.raises(ValueError, match="takes no parameters"):
        get_arm("ur5", d1=0.1)


@pytest.mark.slow  # a Drake simulation per arm with dynamics (seconds each); their torques are checked above
@pytest.mark.parametrize("name", [n for n in LIBRARY if library_arm(n).has_dynamics])
def test_library_arm_simulates_and_its_torques_are_the_inverse_dynamics(name: str) -> None:
    import armlab
    from armlab.controllers.inverse_dynamics import DEFAULT_KD, DEFAULT_KP

    arm = armlab.load(name)
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    middle = (np.maximum(lower, -np.pi) + np.minimum(upper, np.pi)) / 2
    run = armlab.simulate(arm, armlab.quintic(arm, middle, middle + 0.1 * (upper > lower), 0.3))
    assert np.abs(run.q - run.q_ref).max() < 1e-6
    # the computed-torque controller's law, τ = ID(q, q̇, q̈_ref + kp·e + kd·ė) at the state the simulation reached
    commanded = run.qdd_ref + DEFAULT_KP * (run.q_ref - run.q) + DEFAULT_KD * (run.qd_ref - run.qd)
    np.testing.assert_allclose(run.tau, arm.inverse_dynamics(run.q, run.qd, commanded), atol=1e-8, rtol=1e-9)


# ------------------------------------------------------------------ closed forms and what ik returns
@pytest.mark.parametrize("name", ["ur5", *(pytest.param(name, marks=pytest.mark.slow)  # multi-start IK: seconds
                                           for name in ("ur10", "puma560", "irb140", "kr5", "stanford"))])
def test_closed_form_branches_are_the_numerical_solvers(name: str, rng: np.random.Generator) -> None:
    """Without its closed form the arm is solved by the multi-start numerical solver: the same set of solutions
    (each numerical one within 1e-6 of a branch, every branch within the limits found), and 8 branches before the
    limits, each reaching the pose to 1e-9 by FK, one of them the configuration the pose came from."""
    arm = get_arm(name)
    numeric = replace(arm, closed_form=None)
    for q in _inside(arm, rng, 2):
        target = arm.fk(q)
        assert arm.closed_form is not None
        branches = arm.closed_form.solve(target[:3, 3], target[:3, :3], np.zeros(6))
        assert branches.shape == (8, 6)
        miss = np.abs(arm.forward(branches).tool - target).max(axis=(-2, -1))
        assert miss.max() <= TOL
        closed = np.array(solve(arm, target, all_solutions=True))
        found = np.array(solve(numeric, target, all_solutions=True))
        assert len(found) == len(closed)
        d = np.abs((found[:, None, :] - closed[None] + np.pi) % (2 * np.pi) - np.pi).max(axis=-1)
        assert d.min(axis=1).max() < 1e-6 and d.min(axis=0).max() < 1e-6


@pytest.mark.parametrize("name", ["ur5", "ur10"])
def test_ur_branches_of_a_batch_are_each_poses_closed_form(name: str, rng: np.random.Generator) -> None:
    """ur_branches solves a batch of poses at once, (N, 8, 6): each pose's existing branches are the one-pose closed
    form's (same order), each reaching its pose to 1e-9 by FK (the arm's own, a second way); a pose out of reach
    (beyond the arm, on the base axis closer than the shoulder offset) has only NaN branches."""
    from armlab.kinematics.dh import DHRow, DHTable
    from armlab.kinematics.ik_wrist import ur_branches

    arm = get_arm(name)
    module = __import__(f"armlab.models.library.{name}", fromlist=["DH"])
    table = DHTable(tuple(DHRow(a, alpha, d, 0.0) for a, alpha, d in module.DH))
    q = rng.uniform(-np.pi, np.pi, (40, 6))
    q[0, 4] = 0.0  # a wrist singularity: θ6 is near's
    targets = arm.forward(q).tool
    far = np.eye(4)
    far[:3, 3] = (10.0, 0.0, 0.0)
    axis = np.eye(4)
    axis[:3, 3] = (0.0, 0.0, 0.3)
    targets = np.concatenate([targets, far[None], axis[None]])
    near = np.concatenate([q, np.zeros((2, 6))])
    batch = ur_branches(table, targets[:, :3, 3], targets[:, :3, :3], near)
    assert batch.shape == (42, 8, 6)
    assert np.isnan(batch[40:]).all()
    assert arm.closed_form is not None
    for k in range(40):
        exists = ~np.isnan(batch[k, :, 0])
        one = arm.closed_form.solve(targets[k, :3, 3], targets[k, :3, :3], near[k])
        np.testing.assert_allclose(batch[k, exists], one, atol=1e-12, rtol=0)
        assert np.abs(arm.forward(batch[k, exists]).tool - targets[k]).max() <= TOL


@pytest.mark.parametrize("name", ["puma560", "irb140", "kr5", "stanford"])
def test_spherical_wrist_closed_form_reaches_every_pose_and_finds_its_configuration(name: str,
                                                                                   rng: np.random.Generator) -> None:
    """The spherical-wrist closed form (Puma 560; the IRB 140's and KR 5's shoulder offsets a1; the Stanford arm's
    sliding boom): every branch of random poses (one at a wrist singularity, θ5 = 0) reaches its pose to 1e-9 by the
    arm's own FK, and the configuration the pose came from is among the branches (modulo 2π)."""
    arm = get_arm(name)
    assert arm.closed_form is not None and arm.closed_form.needs_pose
    q = _inside(arm, rng, 30)
    q[0, 4] = 0.0
    for k, target in enumerate(arm.fk(q)):
        branches = arm.closed_form.solve(target[:3, 3], target[:3, :3], q[k])
        assert 1 <= len(branches) <= 8
        assert np.abs(arm.forward(branches).tool - target).max() <= TOL
        d = np.where(arm.revolute, (branches - q[k] + np.pi) % (2 * np.pi) - np.pi, branches - q[k])
        assert np.abs(d).max(axis=1).min() < 1e-9


def test_the_spherical_wrist_closed_form_refuses_another_layout() -> None:
    """A table whose wrist is not spherical (the UR5's, a5 … offsets along z) or whose axes 2, 3 are not parallel
    has no such closed form: ValueError saying why."""
    from armlab.kinematics.dh import DHRow, DHTable
    from armlab.kinematics.ik_wrist import spherical_wrist_closed_form
    from armlab.models.library import puma560, ur5

    with pytest.raises(ValueError, match="spherical wrist has a4 = a5 = a6 = d5 = 0"):
        spherical_wrist_closed_form(DHTable(tuple(DHRow(a, alpha, d, 0.0) for a, alpha, d in ur5.DH)))
    rows = [DHRow(a, alpha, d, theta) for a, alpha, d, theta in puma560.DH]
    rows[1] = replace(rows[1], alpha=0.3)
    with pytest.raises(ValueError, match="axes 2 and 3 must be parallel"):
        spherical_wrist_closed_form(DHTable(tuple(rows)))


@pytest.mark.parametrize("name", ["ur5", "puma560", "irb140", "kr5", "stanford"])
def test_one_solution_is_the_nearest_of_every_solution(name: str, rng: np.random.Generator) -> None:
    """solve() without all_solutions (the nearest branch, checked alone by FK) returns the first of what it returns
    with all_solutions (every branch fitted, checked and ordered), for near the pose's own q and elsewhere."""
    arm = get_arm(name)
    q = _inside(arm, rng, 12)
    for k, target in enumerate(arm.fk(q)):
        for near in (q[k], q[(k + 1) % len(q)]):
            (one,) = solve(arm, target, near=near)
            every = solve(arm, target, near=near, all_solutions=True)
            np.testing.assert_allclose(one, every[0], rtol=0, atol=1e-12)


def test_position_target_of_a_six_axis_arm_is_its_branches_at_one_orientation(rng: np.random.Generator) -> None:
    """A position alone on a 6-DOF arm is a continuum: all=True gives the solution reached from near and the other
    branches with its tool orientation (the UR5's closed form), not samples of the continuum."""
    arm = get_arm("ur5")
    (q,) = _inside(arm, rng, 1)
    position = arm.fk(q)[:3, 3]
    every = arm.ik(position, all=True)
    (local,) = arm.ik(position)
    R = arm.fk(local)[:3, :3]
    assert 1 <= len(every) <= 8
    np.testing.assert_allclose(arm.fk(every)[:, :3, 3], np.broadcast_to(position, (len(every), 3)), atol=TOL)
    np.testing.assert_allclose(arm.fk(every)[:, :3, :3], np.broadcast_to(R, (len(every), 3, 3)), atol=TOL)


@pytest.mark.slow  # a multi-start search of the Panda (2 s); the rule is also in the dispatcher's docstring
def test_panda_pose_all_is_the_solutions_at_the_local_solutions_joint7(rng: np.random.Generator) -> None:
    """A pose on the 7-DOF Panda is a continuum: all=True gives the local solution and the others with the same
    q7 (the redundant joint held), each reaching the pose."""
    arm = get_arm("panda")
    (q,) = _inside(arm, rng, 1)
    target = arm.fk(q)
    every = arm.ik(target, all=True, near=q)
    np.testing.assert_allclose(every[0], q, atol=1e-7)
    np.testing.assert_allclose(every[:, 6], q[6], atol=1e-12)
    np.testing.assert_allclose(arm.fk(every), np.broadcast_to(target, (len(every), 4, 4)), atol=TOL)


# ------------------------------------------------------------------ the sources' data and armlab's corrections
def test_puma560_corrections_are_physical_and_change_no_gravity_torque(rng: np.random.Generator) -> None:
    """The source's links 1 and 3 are refused by armlab's check (why they are corrected); the drive train is the
    source's, converted to the joint side. (That the corrections change no gravity torque and the mass matrix by
    at most 0.0075 kg·m² is checked against the toolbox's own model below.)"""
    from armlab.models.library import puma560, stanford, ur10
    from armlab.models.write_urdf import check_inertia

    others = [(k, module.MASS[k - 1], m) for module in (stanford, ur10) for k, m in module.SOURCE_VALUES]
    for link, mass, moments in list(puma560.SOURCE_VALUES) + others:
        with pytest.raises(ValueError, match="not physical"):
            check_inertia(mass, np.diag(moments), f"link {link}")
    train = puma560.drive_train()
    np.testing.assert_allclose(train.gear_ratio, puma560.GEAR_RATIO, rtol=1e-15)
    np.testing.assert_allclose(train.viscous, np.square(puma560.GEAR_RATIO) * puma560.VISCOUS_MOTOR, rtol=1e-14)
    np.testing.assert_allclose(train.reflected_inertia[0], 62.6111**2 * 200e-6, rtol=1e-14)
    carried = get_arm("puma560").drives  # the arm carries it: its torques and simulations include it
    assert carried is not None
    np.testing.assert_allclose(carried.reflected_inertia, train.reflected_inertia, rtol=1e-15)


def _rtb(name: str):
    import roboticstoolbox as rtb  # the test extra: the toolbox users come from
    return {"puma560": rtb.models.DH.Puma560, "ur5": rtb.models.DH.UR5, "ur10": rtb.models.DH.UR10,
            "panda": rtb.models.DH.Panda, "stanford": rtb.models.DH.Stanford, "irb140": rtb.models.DH.IRB140,
            "kr5": rtb.models.DH.KR5}[name]()


@pytest.mark.slow  # importing the toolbox takes 10-15 s; make test (CI) runs it, with the test extra installed
@pytest.mark.parametrize("name", LIBRARY)
def test_against_the_robotics_toolbox(name: str, rng: np.random.Generator) -> None:
    """FK and Jacobian equal to the toolbox's DH model of the same arm (its tool offset removed: armlab's tool is
    the last DH frame); gravity torques equal where both have the same mass data (links' inertias do not enter
    them), and the mass matrix within the documented corrections."""
    robot = _rtb(name)
    from spatialmath import SE3

    robot.tool = SE3()
    if name == "ur5":  # armlab's d1 is UR's own table's (issue 33), the toolbox's 0.3 mm more
        from armlab.models.library import ur5

        robot.links[0].d = ur5.DH[0][2]
    arm = get_arm(name)
    for q in _inside(arm, rng, 3):
        np.testing.assert_allclose(arm.fk(q), robot.fkine(q).A, atol=TOL)
        np.testing.assert_allclose(arm.jacobian(q), robot.jacob0(q), atol=TOL)
        if name in ("puma560", "ur5", "ur10", "stanford"):
            zero = np.zeros(arm.n)
            np.testing.assert_allclose(arm.inverse_dynamics(q, zero, zero), robot.gravload(q),
                                       atol=TORQUE_TOL)
            # the toolbox adds G²·Jm to its mass matrix: so does armlab for an arm with a drive train (the Puma's)
            if arm.drives is None:
                for link in robot.links:
                    link.Jm = 0.0
            M = np.array([arm.inverse_dynamics(q, zero, e, gravity="off") for e in np.eye(arm.n)]).T
            bound = {"puma560": 0.0075, "ur5": 1.4e-4, "ur10": 1.1e-4, "stanford": 0.0026}[name]
            assert np.abs(M - robot.inertia(q)).max() <= bound * (1 + 1e-9)


@pytest.mark.parametrize("name", [n for n in LIBRARY if library_arm(n).has_dynamics])
def test_against_pinocchio_reading_armlabs_urdf(name: str, rng: np.random.Generator) -> None:
    """Pinocchio's RNEA, FK and Jacobian of armlab's URDF equal armlab's to round-off. urdfdom (Pinocchio's URDF
    reader) requires an effort limit where armlab writes none (unknown): ROS's 0 ("none") is written, which no
    algorithm here reads. The rigid arm: Pinocchio's RNEA has no drive train (the Puma's is checked in
    tests/test_drive_model.py)."""
    import pinocchio as pin  # the test extra: an independent RNEA
    arm = get_arm(name).with_drives(None)
    model = pin.buildModelFromXML(arm.urdf(ros_limits=True))
    model.gravity.linear = np.array(arm.gravity)
    data = model.createData()
    tool = model.getFrameId(arm.tool_name)
    for q in _inside(arm, rng, 3):
        qd, qdd = rng.uniform(-1, 1, size=(2, arm.n))
        np.testing.assert_allclose(pin.rnea(model, data, q, qd, qdd), arm.inverse_dynamics(q, qd, qdd),
                                   atol=TORQUE_TOL, rtol=1e-12)
        pin.framesForwardKinematics(model, data, q)
        np.testing.assert_allclose(data.oMf[tool].homogeneous, arm.fk(q), atol=TOL)
        J = pin.computeFrameJacobian(model, data, q, tool, pin.LOCAL_WORLD_ALIGNED)
        np.testing.assert_allclose(J, arm.jacobian(q), atol=TOL)


def test_models_readme_puma560_gravity_table_is_computed() -> None:
    """The models/README.md table of the Puma 560's gravity torques at qz, qr, qs, qn is what the script computes
    (to its printed 4 decimals); the toolbox's gravload at the same configurations: the next test."""
    from armlab.papers.library_tables import puma560_gravity

    text = MODELS_README.read_text(encoding="utf-8")
    computed = puma560_gravity()
    for name, tau in computed.items():
        (row,) = re.findall(rf"^\| `{name}` \|(.*)\|$", text, flags=re.MULTILINE)
        printed = [float(v) for v in row.split("|")[1:]]
        np.testing.assert_allclose(printed, tau, atol=0.5e-4 + 1e-12)


@pytest.mark.slow  # importing the toolbox takes 10-15 s
def test_puma560_gravity_at_the_named_configurations_is_the_toolboxs() -> None:
    from armlab.models.library import puma560
    from armlab.papers.library_tables import puma560_gravity

    robot = _rtb("puma560")
    for name, tau in puma560_gravity().items():
        np.testing.assert_allclose(tau, robot.gravload(np.array(puma560.CONFIGURATIONS[name])), atol=TORQUE_TOL)


@pytest.mark.slow  # importing the toolbox takes 10-15 s
def test_puma560_with_its_drive_train_is_the_toolboxs_rne(rng: np.random.Generator) -> None:
    """The Puma 560 with its library drive train (rotor inertia G²·J_m, viscous G²·B_m, Coulomb |G|·T_c± by the sign of
    the joint velocity) equals ``Puma560().rne`` as the toolbox ships it, friction and all, to 1e-9 relative, at
    states where every joint moves, each both ways (|q̇| ≥ 0.3 rad/s: armlab's smooth T_c±·tanh(q̇/v_s) is then
    T_c± to 1e-26). The one change made to the toolbox's model is armlab's documented correction of link 3's Izz
    (puma560.SOURCE_VALUES: 0.0125 → 0.0200 kg·m², which enters the torques; link 1's does not), so both compute the
    same rigid body. The mean of T_c+ and |T_c−| (armlab's model before issue 31) misses by up to 2.96 N·m."""
    from armlab.models.library import puma560

    robot = _rtb("puma560")
    (link, _, source), = [v for v in puma560.SOURCE_VALUES if v[0] == 3]
    np.testing.assert_allclose(np.diag(robot.links[2].I), source, rtol=1e-15)  # the toolbox ships the source's
    robot.links[2].I = np.diag(puma560.INERTIA[link - 1])
    arm = get_arm("puma560")
    q = _inside(arm, rng, 4)
    speed = rng.uniform(0.3, 1.5, (4, arm.n)) * rng.choice([-1.0, 1.0], (4, arm.n))
    qd = np.concatenate([speed, -speed])  # every joint both ways
    qd[0] = np.abs(qd[0])
    qd[1] = -np.abs(qd[1])  # and all forwards, all backwards
    q, qdd = np.concatenate([q, q]), rng.uniform(-2, 2, (8, arm.n))
    ours = arm.inverse_dynamics(q, qd, qdd)
    theirs = np.array([robot.rne(q[k], qd[k], qdd[k]) for k in range(len(q))])
    np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=1e-9 * np.abs(theirs).max())
    mean = replace(arm.drives, coulomb=(arm.drives.coulomb + arm.drives.negative) / 2, coulomb_negative=None)
    missed = np.abs(arm.inverse_dynamics(q, qd, qdd, drives=mean) - theirs).max(axis=0)
    np.testing.assert_allclose(missed[1], 107.815 * (0.126 - 0.071) / 2, rtol=1e-9)  # joint 2: 2.96 N·m


# the limits Universal Robots publishes (UR5/CB3 and UR10/CB3 User Manuals' technical specifications, deg/s; the
# support article "Max. joint torques", N·m), typed here from the sources as the arm files must carry them
UR_LIMITS = {"ur5": ([180.0] * 6, [150.0, 150.0, 150.0, 28.0, 28.0, 28.0]),
             "ur10": ([120.0, 120.0, 180.0, 180.0, 180.0, 180.0], [330.0, 330.0, 150.0, 56.0, 56.0, 56.0])}


@pytest.mark.parametrize("name", sorted(UR_LIMITS))
def test_ur_arms_carry_urs_published_velocity_and_effort_limits(name: str) -> None:
    """Issue 33: the UR5 and UR10 carried no velocity or effort limits; now UR's own, in the arm and in the plant
    Drake builds from its URDF (two readings: armlab's limits and Drake's joint actuator and velocity limits)."""
    from armlab.models.plant import PlantOptions, make_plant

    speed, effort = UR_LIMITS[name]
    arm = get_arm(name)
    np.testing.assert_allclose([lim.velocity for lim in arm.limits], np.radians(speed), rtol=1e-15)
    np.testing.assert_allclose([lim.effort for lim in arm.limits], effort, rtol=1e-15)
    plant = make_plant(arm, PlantOptions())
    np.testing.assert_allclose(plant.GetVelocityUpperLimits(), np.radians(speed), rtol=1e-15)
    np.testing.assert_allclose(plant.GetEffortUpperLimits(), effort, rtol=1e-15)


def test_ur5_d1_is_urs_own() -> None:
    """Issue 33: UR's DH table (UR5, CB3 series 3) has d1 = 0.089159 m; armlab had the toolbox's 0.089459. At q = 0
    the tool flange is at z = d1 − d5 (joints 2-4 parallel and horizontal, joint 5's offset down): Drake's FK."""
    from armlab.models.plant import PlantOptions, make_plant

    arm = get_arm("ur5")
    plant = make_plant(arm, PlantOptions())
    context = plant.CreateDefaultContext()
    z = plant.GetFrameByName(arm.tool_name).CalcPoseInWorld(context).translation()[2]
    np.testing.assert_allclose(z, 0.089159 - 0.09465, rtol=0, atol=1e-12)
