"""``armlab export`` / ``armlab.export``: an arm leaves as a URDF or a DH table and comes back the same.

Round trips: the exported file read back by armlab (its own formulation of the re-read model), by Drake (the
plant of the re-read arm, parsed from the file's text) and by Pinocchio (its own URDF parser, on the file) gives
the original arm's forward kinematics, Jacobian and inverse dynamics to 1e-9. A drive train leaves as Drake's
tags, which Drake's parser reads into the actuators (and their reflected inertia into the mass matrix). Paths
are refused before any work, and nothing is written unless everything can be.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from bench_kinematics import Drake, Pinocchio  # scripts/bench/ (pytest's pythonpath): the benchmark's references
from helpers import DATA, armlab_main, random_q

import armlab
from armlab.drives.train import DRIVE_FIELDS, DriveTrain
from armlab.models.meshes import MeshWarning, parse_xml
from armlab.models.read_dh import dh_inertials, read_dh_csv

#: The arms sent out and read back: paper arms (revolute, prismatic), DH tables (with base and tool header lines,
#: a prismatic joint, products of inertia) and a ROS-style URDF (world root, tool0 chosen).
ARMS = {
    "rr": ("rr", {}),
    "r2t": ("r2t", {}),
    "urm6": ("urm6", {}),
    "dh_base_tool": (str(DATA / "dh_base_tool.csv"), {}),
    "two_link_masses_dh": (str(DATA / "two_link_masses_dh.csv"), {}),
    "ur_like": (str(DATA / "ros" / "robots" / "ur_like.urdf"),
                {"tool": "tool0", "package_paths": [DATA / "ros" / "pkgs"]}),
}
TOL = 1e-9


def _load(key: str) -> armlab.Arm:
    name, options = ARMS[key]
    if key != "ur_like":
        return armlab.load(name, **options)
    with pytest.warns(MeshWarning):  # its missing mesh, its .stl collision meshes
        return armlab.load(name, **options)


def _states(arm: armlab.Arm, count: int = 5) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(22)
    return random_q(arm, rng, count), rng.uniform(-1, 1, (count, arm.n)), rng.uniform(-2, 2, (count, arm.n))


def _turned(original: armlab.Arm, copy: armlab.Arm) -> np.ndarray:
    """The pose (4×4) of ``original``'s base in ``copy``'s: a turn taking the original's gravity to the copy's −z (a
    URDF's readers all take gravity −z: rr's −y leaves turned), checked; the identity for an arm whose gravity is
    −z already."""
    q0 = random_q(original, np.random.default_rng(5), 1)[0]
    X = copy.fk(q0) @ np.linalg.inv(original.fk(q0))
    np.testing.assert_allclose(X[:3, :3] @ X[:3, :3].T, np.eye(3), atol=TOL, rtol=0)
    np.testing.assert_allclose(X[:3, 3], 0, atol=TOL, rtol=0)
    np.testing.assert_allclose(X[:3, :3] @ original.gravity, copy.gravity, atol=TOL, rtol=0)
    np.testing.assert_allclose(copy.gravity, [0, 0, -9.81], atol=0, rtol=0)  # exact: what a URDF reader sets
    return X


def _assert_same_arm(original: armlab.Arm, copy: armlab.Arm) -> None:
    """FK and Jacobian of ``copy`` equal ``original``'s, in the copy's turned base (:func:`_turned`), and the
    inverse dynamics (each arm's own gravity) to 1e-9."""
    q, qd, qdd = _states(original)
    X = _turned(original, copy)
    R6 = np.kron(np.eye(2), X[:3, :3])
    np.testing.assert_allclose(copy.fk(q), X @ original.fk(q), atol=TOL, rtol=0)
    np.testing.assert_allclose(copy.jacobian(q), R6 @ original.jacobian(q), atol=TOL, rtol=0)
    if original.has_dynamics:
        np.testing.assert_allclose(copy.inverse_dynamics(q, qd, qdd), original.inverse_dynamics(q, qd, qdd),
                                   atol=TOL, rtol=TOL)


@pytest.mark.parametrize("key", list(ARMS))
def test_urdf_round_trip_armlab_drake_pinocchio(key, tmp_path):
    original = _load(key)
    (path,) = armlab.export(original, urdf=tmp_path / f"{key}.urdf")
    copy = armlab.load(path)
    assert copy.joint_names == original.joint_names
    _assert_same_arm(original, copy)
    q, qd, qdd = _states(original)
    X = _turned(original, copy)
    R6 = np.kron(np.eye(2), X[:3, :3])
    gravity_z = np.array([0.0, 0.0, -9.81])
    pino = Pinocchio(copy, path.read_text())  # Pinocchio's parser on the file armlab wrote
    pino.model.gravity.linear = gravity_z
    qp = pino.configurations(q)
    np.testing.assert_allclose(pino.forward(qp), X @ original.fk(q), atol=TOL, rtol=0)
    np.testing.assert_allclose([J[:, pino.v_index] for J in pino.jacobian(qp)], R6 @ original.jacobian(q),
                               atol=TOL, rtol=0)
    drake = Drake(copy)  # Drake's parser on the same text (the re-read arm's model text)
    np.testing.assert_allclose(drake.forward(q), X @ original.fk(q), atol=TOL, rtol=0)
    np.testing.assert_allclose(drake.jacobian(q), R6 @ original.jacobian(q), atol=TOL, rtol=0)
    if original.has_dynamics:
        tau = original.inverse_dynamics(q, qd, qdd)  # the original's own gravity (rr's −y), the file's −z
        tau_pin = [t[pino.v_index] for t in pino.rnea(qp, pino.velocities(qd), pino.velocities(qdd))]
        np.testing.assert_allclose(tau_pin, tau, atol=TOL, rtol=TOL)
        np.testing.assert_allclose(drake.inverse_dynamics(q, qd, qdd), tau, atol=TOL, rtol=TOL)


@pytest.mark.parametrize("key", ["dh_base_tool", "two_link_masses_dh"])
def test_dh_round_trip(key, tmp_path):
    original = _load(key)
    (path,) = armlab.export(original, dh=tmp_path / f"{key}.csv")
    copy = armlab.load(path)
    _assert_same_arm(original, copy)
    table, limits, inertials = read_dh_csv(path)
    typed_table, typed_limits, typed_inertials = read_dh_csv(ARMS[key][0])
    assert table.convention == typed_table.convention  # exact: a word of the file
    for row, typed in zip(table.rows, typed_table.rows, strict=True):
        np.testing.assert_allclose([row.a, row.alpha, row.d, row.theta],
                                   [typed.a, typed.alpha, typed.d, typed.theta], atol=1e-12, rtol=0)
    assert limits == typed_limits  # exact: the shortest decimal of a float reads back to that float
    assert inertials is not None and typed_inertials is not None
    for body, typed in zip(inertials, typed_inertials, strict=True):  # back in the DH frames the user typed
        np.testing.assert_allclose(body.com, typed.com, atol=1e-12, rtol=0)
        np.testing.assert_allclose(body.inertia, typed.inertia, atol=1e-12, rtol=0)


def test_dh_round_trip_carries_drives_and_radii(tmp_path):
    puma = armlab.load("puma560")  # a library arm with its drive train
    assert puma.drives is not None
    radii = np.array([0.09, 0.07, 0.0, 0.05, 0.04, 0.03])  # link 3 without a shape (radius 0)
    original = replace(puma, bodies=tuple(replace(body, radius=float(r), collides=True) if r > 0 else
                                          replace(body, collides=False) for body, r in
                                          zip(puma.bodies, radii, strict=True)))
    (path,) = armlab.export(original, dh=tmp_path / "puma560.csv")
    copy = armlab.load(path)
    _assert_same_arm(original, copy)  # inverse dynamics through each arm's own drive train
    assert copy.drives is not None
    for name in DRIVE_FIELDS:
        np.testing.assert_allclose(getattr(copy.drives, name), getattr(original.drives, name), atol=TOL, rtol=TOL)
    assert [body.collides for body in copy.bodies] == [True, True, False, True, True, True]
    # exact: the shortest decimal reads back
    assert [body.radius for body in copy.bodies if body.collides] == [r for r in radii if r > 0]


def test_dh_export_refuses_what_a_table_cannot_hold(tmp_path):
    puma = armlab.load("puma560")
    slow = puma.with_drives(replace(puma.drives, coulomb_speed=0.1))
    with pytest.raises(ValueError, match=r"coulomb_speed = 0\.1 rad/s cannot be written in a DH table"):
        armlab.export(slow, dh=tmp_path / "slow.csv")
    assert list(tmp_path.iterdir()) == []


def test_dh_inertials_are_the_typed_ones():
    arm = _load("dh_base_tool")
    _, _, typed = read_dh_csv(ARMS["dh_base_tool"][0])
    for body, given in zip(dh_inertials(arm), typed, strict=True):
        assert body.mass == given.mass  # exact: the mass is carried, never transformed
        np.testing.assert_allclose(body.com, given.com, atol=1e-12, rtol=0)
        np.testing.assert_allclose(body.inertia, given.inertia, atol=1e-12, rtol=0)


def test_drive_train_leaves_as_drakes_tags(tmp_path):
    original = _load("urm6")
    n = original.n
    train = DriveTrain(gear_ratio=np.arange(1.0, n + 1) * 10, rotor_inertia=np.full(n, 2e-4),
                       efficiency=np.full(n, 0.9), viscous=np.arange(n) * 0.1, coulomb=np.full(n, 0.5))
    (path,) = armlab.export(original, urdf=tmp_path / "urm6.urdf", drives=train)
    text = path.read_text()
    assert 'xmlns:drake="http://drake.mit.edu"' in text and "<drake:rotor_inertia" in text
    copy = armlab.load(path)
    plant = copy.make_plant()
    actuators = [plant.GetJointActuatorByName(f"{name}_motor") for name in copy.joint_names]
    np.testing.assert_allclose([a.default_gear_ratio() for a in actuators], train.gear_ratio, rtol=1e-15)
    np.testing.assert_allclose([a.default_rotor_inertia() for a in actuators], train.rotor_inertia, rtol=1e-15)
    np.testing.assert_allclose([plant.GetJointByName(name).default_damping() for name in copy.joint_names],
                               train.viscous, rtol=1e-15)
    # Drake puts the reflected inertia G²·J_m on the mass matrix's diagonal: against the arm without drives
    q = _states(original)[0][0]
    bare = original.make_plant()
    masses = []
    for model in (plant, bare):
        context = model.CreateDefaultContext()
        model.SetPositions(context, q)
        masses.append(model.CalcMassMatrix(context))
    np.testing.assert_allclose(masses[0] - masses[1], np.diag(train.reflected_inertia), atol=1e-12, rtol=0)


def test_cli_export_writes_both(tmp_path):
    result = armlab_main("export", ARMS["dh_base_tool"][0], "--urdf", str(tmp_path / "a.urdf"),
                         "--dh", str(tmp_path / "a.csv"))
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == [f"wrote {tmp_path / 'a.urdf'}", f"wrote {tmp_path / 'a.csv'}"]
    _assert_same_arm(_load("dh_base_tool"), armlab.load(tmp_path / "a.csv"))


@pytest.mark.parametrize("args, message", [
    ((), "nothing to export"),
    (("--urdf", "{tmp}/"), "is a folder"),
    (("--urdf", "{tmp}"), "is a folder"),
    (("--urdf", "{tmp}/a.txt"), "must end in .urdf"),
    (("--dh", "{tmp}/a.urdf"), "must end in .csv"),
    (("--urdf", "{tmp}/file.txt/a.urdf"), "cannot write in"),
])
def test_cli_export_refuses_paths_before_work(args, message, tmp_path):
    (tmp_path / "file.txt").write_text("a file, not a folder")
    argv = [arg.format(tmp=tmp_path) for arg in args]
    # the arm does not exist: a path refused before any work never gets to read it
    result = armlab_main("export", str(tmp_path / "missing.csv"), *argv)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and message in result.stderr, result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file.txt"]


def test_export_writes_nothing_unless_everything_can_be(tmp_path):
    with pytest.raises(ValueError, match="rr has no DH description"):
        armlab.export(armlab.load("rr"), urdf=tmp_path / "rr.urdf", dh=tmp_path / "rr.csv")
    assert list(tmp_path.iterdir()) == []


#: every arm armlab names: the paper arms and the library's
NAMED = ("rr", "rrrr", "arm4r", "r2t", "urm6", "irb140", "kr5", "panda", "puma560", "stanford", "ur10", "ur5")


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMED)
def test_every_export_loads_in_mujoco_or_says_in_one_line_why_not(name, tmp_path, capsys):
    """Issue 33: 4 of 7 library exports did not load in MuJoCo (ur5, irb140, kr5: no mass or no inertia; ur10:
    its corrected link-6 inertia on the triangle inequality, below it in binary) though ``export --help`` says
    MuJoCo reads them. Now each loads in MuJoCo's own URDF reader, or ``armlab export`` says, in one warning line,
    that it will not and why — and MuJoCo then refuses it indeed."""
    import mujoco  # the test extra: an independent reader

    from armlab.cli import main

    path = tmp_path / f"{name}.urdf"
    assert main(["export", name, "--urdf", str(path)]) == 0
    err = capsys.readouterr().err
    try:
        mujoco.MjModel.from_xml_path(str(path))
        loads = True
    except ValueError as error:
        loads = False
        reason = str(error).splitlines()[0]
    kinematic = name in ("irb140", "kr5")  # no mass data: MuJoCo infers masses from their collision capsules
    if loads and not kinematic:
        assert err == ""
    else:
        assert len(err.splitlines()) == 1 and "MuJoCo will not load" in err, err
        assert "without mass" in err if kinematic else ("point masses" in err) == ("mjMINVAL" in reason)
    assert loads == (name != "ur5")  # ur10 loads now: its corrected inertia keeps a margin


# issue 36, item 3: names are escaped in the URDF's attributes, kept out of its comments, and read back
@pytest.mark.parametrize("name, joint", [
    ("a--b", "j&1"),
    ('x--><!DOCTYPE robot [<!ENTITY e SYSTEM "file:///etc/hostname">]><!--', "j'\"<>1"),
    ("tab\tand\nline", "j\r2"),
])
def test_names_leave_as_they_are(tmp_path, name, joint):
    rr = armlab.load("rr")
    arm = replace(rr, name=name, table=replace(rr.table, rows=(replace(rr.table.rows[0], name=joint),
                                                               *rr.table.rows[1:])))
    (path,) = armlab.export(arm, urdf=tmp_path / "out.urdf")
    assert parse_xml(path.read_text(), "out.urdf").get("name") == name  # exact: text; no DOCTYPE (refused)
    copy = armlab.load(path)
    assert copy.name == name and copy.joint_names == [joint, *rr.joint_names[1:]]


def test_a_name_xml_cannot_hold_is_refused_before_writing(tmp_path):
    arm = replace(armlab.load("rr"), name="a\x01b")
    result = armlab_main("export", "rr", "--urdf", str(tmp_path / "ok.urdf"))
    assert result.returncode == 0 and result.stdout.startswith("wrote ")
    with pytest.raises(ValueError, match=r"out\.urdf: a name of the arm 'a\\x01b' or of its joints cannot be "
                                         "written as XML"):
        armlab.export(arm, urdf=tmp_path / "out.urdf")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ok.urdf"]


def test_rr_leaves_with_its_gravity(tmp_path):
    """Issue 36, item 10: rr's gravity is −y in its base; its URDF turns the base so that the readers' −z is it."""
    (path,) = armlab.export(armlab.load("rr"), urdf=tmp_path / "rr.urdf")
    copy = armlab.load(path)
    np.testing.assert_allclose(copy.inverse_dynamics([0.3, 0.4], [0, 0], [0, 0]), [6.1486, 0.9004], atol=5e-5,
                               rtol=0)
