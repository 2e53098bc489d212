"""Differential kinematics (armlab.kinematics.differential) against Drake, finite differences,
paper 003's iterative algorithm and the RR arm's closed form."""

from __future__ import annotations

import functools

import numpy as np
import pytest
from helpers import ARM_NAMES, arm_and_plant, data, random_q

from armlab.kinematics.differential import jacobian, manipulability, sigma_min, tool_motion
from armlab.kinematics.iterative import iterative_kinematics
from armlab.models import get_arm

SAMPLES = 200

#: A user DH table: standard convention, a prismatic joint, twists and offsets.
DH_TABLE = data("dh_prismatic_twists.csv")

#: A user URDF: joint axes along x, y, −z and oblique, a prismatic joint on an oblique axis,
#: fixed joints between the moving ones and a fixed tool link two welds past the last joint.
USER_URDF = data("oblique.urdf")


@functools.cache
def _user_arm(kind: str, folder: str):
    """(arm, plant, context) of a user DH arm (standard or modified) or the user URDF, written to ``folder``."""
    from pathlib import Path

    if kind == "urdf":
        path = Path(folder) / "oblique.urdf"
        path.write_text(USER_URDF)
    else:
        path = Path(folder) / f"dh_{kind}.csv"
        path.write_text(DH_TABLE.replace("# convention: standard", f"# convention: {kind}"))
    arm = get_arm(str(path))
    plant = arm.make_plant()
    return arm, plant, plant.CreateDefaultContext()


@pytest.fixture(params=ARM_NAMES + ["dh standard", "dh modified", "user urdf"])
def any_arm(request, tmp_path_factory):
    """(arm, plant, context) for each paper arm, two user DH arms and a user URDF arm."""
    if request.param in ARM_NAMES:
        return arm_and_plant(request.param)
    kind = request.param.split()[-1]
    return _user_arm(kind, str(tmp_path_factory.getbasetemp()))


def _drake_jacobian(arm, plant, ctx, q):
    """Drake's CalcJacobianSpatialVelocity (w.r.t. v, tool origin, world) with rows [v; ω]."""
    from pydrake.multibody.tree import JacobianWrtVariable

    tool, world = plant.GetFrameByName(arm.tool_name), plant.world_frame()
    out = []
    for qk in q:
        plant.SetPositions(ctx, qk)
        J = plant.CalcJacobianSpatialVelocity(ctx, JacobianWrtVariable.kV, tool, np.zeros(3), world, world)
        out.append(np.vstack([J[3:], J[:3]]))
    return np.array(out)


def _drake_motion(arm, plant, ctx, q, qd, qdd):
    """Drake's spatial velocity and acceleration of the tool frame in the world, as [v; ω], [a; ω̇]."""
    tool = plant.GetFrameByName(arm.tool_name)
    assert np.allclose(tool.GetFixedPoseInBodyFrame().GetAsMatrix4(), np.eye(4))  # the tool is a body's origin
    twists, accels = [], []
    for qk, qdk, qddk in zip(q, qd, qdd, strict=True):
        plant.SetPositionsAndVelocities(ctx, np.concatenate([qk, qdk]))
        V = tool.CalcSpatialVelocityInWorld(ctx)
        A = plant.CalcSpatialAccelerationsFromVdot(ctx, qddk)[tool.body().index()]
        twists.append(np.concatenate([V.translational(), V.rotational()]))
        accels.append(np.concatenate([A.translational(), A.rotational()]))
    return np.array(twists), np.array(accels)


def test_jacobian_matches_drake(any_arm, rng):
    arm, plant, ctx = any_arm
    q = random_q(arm, rng, SAMPLES)
    J = jacobian(arm, q)
    assert J.shape == (SAMPLES, 6, arm.n)
    np.testing.assert_allclose(J, _drake_jacobian(arm, plant, ctx, q), rtol=0, atol=1e-9)
    np.testing.assert_allclose(jacobian(arm, q[0]), J[0], rtol=0, atol=1e-15)  # one configuration → (6, n)


def test_jacobian_matches_finite_differences_of_forward(any_arm, rng):
    arm, _, _ = any_arm
    q = random_q(arm, rng, 50)
    J = jacobian(arm, q)
    h = 1e-6
    for i in range(arm.n):
        step = np.zeros(arm.n)
        step[i] = h
        T_plus, T_minus = arm.forward(q + step).tool, arm.forward(q - step).tool
        v = (T_plus[:, :3, 3] - T_minus[:, :3, 3]) / (2 * h)
        dR = (T_plus[:, :3, :3] - T_minus[:, :3, :3]) / (2 * h)
        W = dR @ np.swapaxes(arm.forward(q).tool[:, :3, :3], -1, -2)  # Ṙ Rᵀ = [ω]×
        w = np.stack([W[:, 2, 1], W[:, 0, 2], W[:, 1, 0]], axis=-1)
        np.testing.assert_allclose(J[:, :3, i], v, rtol=0, atol=1e-8)
        np.testing.assert_allclose(J[:, 3:, i], w, rtol=0, atol=1e-8)


def test_tool_motion_matches_drake(any_arm, rng):
    arm, plant, ctx = any_arm
    q = random_q(arm, rng, SAMPLES)
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape) * 3
    twist, accel = tool_motion(arm, q, qd, qdd)
    drake_twist, drake_accel = _drake_motion(arm, plant, ctx, q, qd, qdd)
    np.testing.assert_allclose(twist, drake_twist, rtol=0, atol=1e-9)
    np.testing.assert_allclose(accel, drake_accel, rtol=0, atol=1e-9)
    np.testing.assert_allclose(twist, np.einsum("kij,kj->ki", jacobian(arm, q), qd), rtol=0, atol=1e-12)
    one = tool_motion(arm, q[0], qd[0], qdd[0])
    np.testing.assert_allclose(one[1], accel[0], rtol=0, atol=1e-15)


def test_tool_acceleration_is_the_derivative_of_the_twist(any_arm, rng):
    """a = d/dt of the twist along q(t) = q + t q̇ + t²/2 q̈ (central differences in t)."""
    arm, _, _ = any_arm
    q = random_q(arm, rng, 50)
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
    h = 1e-5
    ahead = tool_motion(arm, q + h * qd + h**2 / 2 * qdd, qd + h * qdd, qdd)[0]
    behind = tool_motion(arm, q - h * qd + h**2 / 2 * qdd, qd - h * qdd, qdd)[0]
    np.testing.assert_allclose(tool_motion(arm, q, qd, qdd)[1], (ahead - behind) / (2 * h), rtol=0, atol=1e-7)


def test_tool_motion_matches_paper_003_iterative_algorithm(rng):
    arm, _, _ = arm_and_plant("r2t")
    q = random_q(arm, rng, SAMPLES)
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
    twist, accel = tool_motion(arm, q, qd, qdd)
    motion = iterative_kinematics(arm.table, q, qd, qdd)  # eqs. (24)–(33)
    np.testing.assert_allclose(twist, motion.Xd, rtol=0, atol=1e-12)
    np.testing.assert_allclose(accel, motion.Xdd, rtol=0, atol=1e-12)


def test_rr_manipulability_is_l1_l2_sin_theta2(rng):
    arm, _, _ = arm_and_plant("rr")
    q = random_q(arm, rng, SAMPLES)
    J = jacobian(arm, q)
    expected = np.abs(arm.parameters["L1"] * arm.parameters["L2"] * np.sin(q[:, 1]))
    np.testing.assert_allclose(manipulability(J), expected, rtol=0, atol=1e-12)  # n = 2 < 6: "trans"
    np.testing.assert_allclose(manipulability(J, "trans"), expected, rtol=0, atol=1e-12)
    # the two singular values of the planar Jacobian: product |L1 L2 sin θ2|, and σ_min is the smaller
    sigma = sigma_min(J)
    assert np.all(sigma >= 0) and np.all(sigma**2 <= expected + 1e-12)
    stretched = jacobian(arm, [0.7, 0.0])
    assert manipulability(stretched) == pytest.approx(0.0, abs=1e-15)
    assert sigma_min(stretched) == pytest.approx(0.0, abs=1e-15)


def test_manipulability_is_yoshikawas_determinant(any_arm, rng):
    arm, _, _ = any_arm
    J = jacobian(arm, random_q(arm, rng, 50))
    for axes, rows in (("all", slice(0, 6)), ("trans", slice(0, 3)), ("rot", slice(3, 6))):
        Js = J[:, rows, :]
        gram = Js @ np.swapaxes(Js, -1, -2) if Js.shape[-2] <= arm.n else np.swapaxes(Js, -1, -2) @ Js
        # squared: √det of a (structurally) singular Gram matrix would only measure its round-off
        np.testing.assert_allclose(manipulability(J, axes) ** 2, np.linalg.det(gram), rtol=1e-9, atol=1e-12)
        eigen = np.linalg.eigvalsh(gram)[:, 0]  # the smallest eigenvalue of the Gram matrix = σ_min²
        np.testing.assert_allclose(sigma_min(J, axes) ** 2, np.clip(eigen, 0, None), rtol=1e-7, atol=1e-12)
    default = "all" if arm.n >= 6 else "trans"  # the documented rule, written out (not default_axes)
    # exact: the default is the same axes: same code, same input
    np.testing.assert_array_equal(manipulability(J), manipulability(J, default))


def test_bad_input_is_a_value_error():
    arm, _, _ = arm_and_plant("rr")
    with pytest.raises(ValueError, match="expected 2 joint values"):
        jacobian(arm, [0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match="not a finite number"):
        tool_motion(arm, [0.1, np.nan], [0, 0], [0, 0])
    with pytest.raises(ValueError, match="axes = 'xyz' is not allowed"):
        manipulability(jacobian(arm, [0.1, 0.2]), "xyz")
    with pytest.raises(ValueError, match=r"expected a Jacobian of shape \(6, n\)"):
        sigma_min(np.zeros((3, 2)))


@pytest.mark.parametrize("name", ARM_NAMES)
def test_batches_longer_than_a_block(name, rng):
    """Across block boundaries (kinematics.batch.BLOCK) every sample equals its own one-sample evaluation."""
    from armlab.kinematics.batch import BLOCK

    arm, _, _ = arm_and_plant(name)
    q = random_q(arm, rng, BLOCK + 7).reshape(1, BLOCK + 7, arm.n)  # a batch of any shape
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
    forward, frames, J = arm.forward(q), arm.table.frames(q), jacobian(arm, q)
    twist, accel = tool_motion(arm, q, qd, qdd)
    assert J.shape == (1, BLOCK + 7, 6, arm.n) and frames.shape == (1, BLOCK + 7, arm.n + 2, 4, 4)
    for k in (0, BLOCK - 1, BLOCK, BLOCK + 6):
        one = arm.forward(q[0, k])
        np.testing.assert_allclose(forward.tool[0, k], one.tool, rtol=0, atol=1e-14)
        for point, value in one.points.items():
            np.testing.assert_allclose(forward.points[point][0, k], value, rtol=0, atol=1e-14)
        np.testing.assert_allclose(frames[0, k], arm.table.frames(q[0, k]), rtol=0, atol=1e-14)
        np.testing.assert_allclose(J[0, k], jacobian(arm, q[0, k]), rtol=0, atol=1e-14)
        one_twist, one_accel = tool_motion(arm, q[0, k], qd[0, k], qdd[0, k])
        np.testing.assert_allclose(twist[0, k], one_twist, rtol=0, atol=1e-13)
        np.testing.assert_allclose(accel[0, k], one_accel, rtol=0, atol=1e-13)


def test_rrrr_forward_is_paper_000s_basic_movement_product(rng):
    """The rrrr arm's forward (chained link by link) equals eq. (18)'s product of eqs. (21)–(32)'s matrices."""
    from armlab.kinematics.basic_movements import rrrr_dh_chain

    arm, _, _ = arm_and_plant("rrrr")
    q = random_q(arm, rng, SAMPLES)
    T01, T12, T23, T34 = rrrr_dh_chain(q, tuple(arm.parameters[k] for k in ("L1", "L2", "L3", "L4")))
    forward = arm.forward(q)
    np.testing.assert_allclose(forward.tool, T01 @ T12 @ T23 @ T34, rtol=0, atol=1e-14)
    np.testing.assert_allclose(forward.points["O2"], (T01 @ T12)[:, :3, 3], rtol=0, atol=1e-14)


def test_cos_sin_from_the_half_angle_tangent(rng):
    """kinematics.batch.cos_sin (used by every chain) equals numpy's cos and sin to 2 ulp, ±π included."""
    from armlab.kinematics.batch import cos_sin

    angle = np.concatenate([rng.uniform(-50, 50, 20_000), np.pi * np.array([-3, -1, -0.5, 0, 0.5, 1, 2, 3]),
                            [np.nextafter(np.pi, 0), np.nextafter(-np.pi, 0), 1e6]])
    c, s = cos_sin(angle)
    np.testing.assert_allclose(c, np.cos(angle), rtol=0, atol=4.5e-16)
    np.testing.assert_allclose(s, np.sin(angle), rtol=0, atol=4.5e-16)
