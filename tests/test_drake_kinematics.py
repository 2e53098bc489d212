"""Each paper's formulation against Drake's own queries, ≥ 100 random samples per arm, 1e-9."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import arm_and_plant, assert_rounding_close, random_q

from armlab.kinematics.iterative import iterative_kinematics

N = 120
TOL = 1e-9


def test_forward_pose_and_points_match_drake(arm_name, rng):
    arm, plant, ctx = arm_and_plant(arm_name)
    qs = random_q(arm, rng, N)
    fk = arm.forward(qs)  # the paper's method, batched
    table = arm.table_forward(qs)  # paper 003's locating matrices
    world = plant.world_frame()
    tool = plant.GetFrameByName(arm.tool_name)
    for k, q in enumerate(qs):
        plant.SetPositions(ctx, q)
        X = plant.CalcRelativeTransform(ctx, world, tool).GetAsMatrix4()
        np.testing.assert_allclose(fk.tool[k], X, atol=TOL, rtol=0)
        np.testing.assert_allclose(table.tool[k], X, atol=TOL, rtol=0)
        for name, p in fk.points.items():
            expected = plant.CalcRelativeTransform(ctx, world, plant.GetFrameByName(name)).translation()
            np.testing.assert_allclose(p[k], expected, atol=TOL, rtol=0, err_msg=name)
            np.testing.assert_allclose(table.points[name][k], expected, atol=TOL, rtol=0, err_msg=name)


def test_points_are_ordered_base_to_tool(arm_name):
    arm, _, _ = arm_and_plant(arm_name)
    names = list(arm.forward(np.zeros(arm.n)).points)
    assert names == [p.name for p in arm.points]
    assert names[-1] == arm.tool_name


def _drake_motion(plant, ctx, bodies, q, qd, qdd):
    """Per-body ω, v, ω̇, v̇ (world frame, at the body origin) and R_WB from Drake."""
    plant.SetPositions(ctx, q)
    plant.SetVelocities(ctx, qd)
    accelerations = plant.CalcSpatialAccelerationsFromVdot(ctx, qdd)
    rows = []
    for body in bodies:
        V = plant.EvalBodySpatialVelocityInWorld(ctx, body)
        A = accelerations[int(body.index())]
        R = plant.EvalBodyPoseInWorld(ctx, body).rotation().matrix()
        rows.append((V.rotational(), V.translational(), A.rotational(), A.translational(), R))
    return rows


@pytest.mark.slow
def test_iterative_algorithm_matches_drake_per_link(arm_name, rng):
    """Paper 003 eqs. (24)–(31) for every link and the tool, in {0} and in the link's own frame."""
    arm, plant, ctx = arm_and_plant(arm_name)
    qs = random_q(arm, rng, N)
    qds = rng.normal(scale=2.0, size=qs.shape)
    qdds = rng.normal(scale=5.0, size=qs.shape)
    motion = iterative_kinematics(arm.table, qs, qds, qdds)
    bodies = [plant.GetBodyByName(f"link{i}") for i in range(1, arm.n + 1)] + [plant.GetBodyByName(arm.tool_name)]
    for k in range(N):
        for i, (w, v, wd, vd, R) in enumerate(_drake_motion(plant, ctx, bodies, qs[k], qds[k], qdds[k])):
            np.testing.assert_allclose(motion.w_0[k, i], w, atol=TOL, rtol=0)
            np.testing.assert_allclose(motion.v_0[k, i], v, atol=TOL, rtol=0)
            np.testing.assert_allclose(motion.wd_0[k, i], wd, atol=TOL, rtol=0)
            np.testing.assert_allclose(motion.vd_0[k, i], vd, atol=TOL, rtol=0)
            np.testing.assert_allclose(motion.w_i[k, i], R.T @ w, atol=TOL, rtol=0)
            np.testing.assert_allclose(motion.v_i[k, i], R.T @ v, atol=TOL, rtol=0)
            np.testing.assert_allclose(motion.wd_i[k, i], R.T @ wd, atol=TOL, rtol=0)
            np.testing.assert_allclose(motion.vd_i[k, i], R.T @ vd, atol=TOL, rtol=0)


def test_end_point_velocity_and_acceleration_match_jacobian(arm_name, rng):
    """Eqs. (32)–(33) against Drake's Jacobian·q̇ and Jacobian·q̈ + bias acceleration."""
    from pydrake.multibody.tree import JacobianWrtVariable

    arm, plant, ctx = arm_and_plant(arm_name)
    qs = random_q(arm, rng, N)
    qds = rng.normal(size=qs.shape)
    qdds = rng.normal(size=qs.shape)
    motion = iterative_kinematics(arm.table, qs, qds, qdds)
    world, tool = plant.world_frame(), plant.GetFrameByName(arm.tool_name)
    for k in range(N):
        plant.SetPositions(ctx, qs[k])
        plant.SetVelocities(ctx, qds[k])
        J = plant.CalcJacobianSpatialVelocity(ctx, JacobianWrtVariable.kV, tool, np.zeros(3), world, world)
        bias = plant.CalcBiasSpatialAcceleration(ctx, JacobianWrtVariable.kV, tool, np.zeros(3), world, world)
        V = J @ qds[k]
        A = J @ qdds[k] + bias.get_coeffs()
        np.testing.assert_allclose(motion.Xd[k], np.concatenate([V[3:], V[:3]]), atol=TOL, rtol=0)
        np.testing.assert_allclose(motion.Xdd[k], np.concatenate([A[3:], A[:3]]), atol=TOL, rtol=0)


def test_finite_differences_of_position_give_velocity(arm_name, rng):
    """Central differences of the paper's FK along q̇ equal the iterative algorithm's v (O(h²) error)."""
    arm, _, _ = arm_and_plant(arm_name)
    qs = random_q(arm, rng, N)
    qds = rng.normal(size=qs.shape)
    h = 1e-5
    fd = (arm.forward(qs + h * qds).tool[:, :3, 3] - arm.forward(qs - h * qds).tool[:, :3, 3]) / (2 * h)
    v = iterative_kinematics(arm.table, qs, qds, np.zeros_like(qs)).v_0[:, -1]
    np.testing.assert_allclose(fd, v, atol=1e-8, rtol=0)  # truncation ~h²·|x'''| ≈ 1e-10, rounding ~1e-11


@pytest.mark.parametrize("shape", [(), (7,), (3, 5)])
def test_batches_of_any_shape(arm_name, shape, rng):
    arm, _, _ = arm_and_plant(arm_name)
    qs = random_q(arm, rng, int(np.prod(shape, dtype=int))).reshape(shape + (arm.n,))
    fk = arm.forward(qs)
    assert fk.tool.shape == shape + (4, 4)
    flat = arm.forward(qs.reshape(-1, arm.n))
    # another batch shape can take another vectorised numpy loop (a single q: no batch at all); 32 ulps as test_api
    assert_rounding_close(fk.tool.reshape(-1, 4, 4), flat.tool, ulps=32)
