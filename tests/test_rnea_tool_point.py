"""The tool point from the recursive Newton–Euler pass (armlab.kinematics.rnea.inverse_dynamics_and_tool_point)
against the Jacobian-column formulas of armlab.kinematics.differential and the forward kinematics."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import assert_rounding_close, random_q

from armlab.kinematics.batch import BLOCK
from armlab.kinematics.differential import tool_motion
from armlab.kinematics.rnea import inverse_dynamics, inverse_dynamics_and_tool_point


@pytest.mark.parametrize(("gravity", "payload"), [(None, 0.0), ("off", 0.0), ((1.0, -4.0, -9.0), 2.5)])
def test_tool_point_equals_tool_motion_and_the_torques_inverse_dynamics(dynamic_arm, rng, gravity, payload):
    """[p v a] from the outward recursion = forward kinematics and tool_motion's [v], [a]; τ = inverse_dynamics.

    More samples than one block, so that the blocks are stitched together too.
    """
    arm = dynamic_arm
    q = random_q(arm, rng, BLOCK + 37)
    qd, qdd = rng.normal(size=q.shape) * 2, rng.normal(size=q.shape) * 5
    tau, pva = inverse_dynamics_and_tool_point(arm, q, qd, qdd, gravity, payload)
    twist, accel = tool_motion(arm, q, qd, qdd)
    expected = np.hstack([arm.forward(q).tool[:, :3, 3], twist[:, :3], accel[:, :3]])
    assert pva.shape == (q.shape[0], 9)
    np.testing.assert_allclose(pva, expected, rtol=0, atol=1e-12 * np.abs(expected).max())
    # the recursion with the velocity row stacked in is another numpy path (other array shapes) for the same
    # sums: a few ulps of the largest torque apart; 64 ulps of it (the n links' sums, terms up to its size)
    assert_rounding_close(tau, inverse_dynamics(arm, q, qd, qdd, gravity, payload), ulps=64)
    one_tau, one_pva = inverse_dynamics_and_tool_point(arm, q[5], qd[5], qdd[5], gravity, payload)
    assert one_tau.shape == (arm.n,) and one_pva.shape == (9,)
    np.testing.assert_allclose(one_pva, pva[5], rtol=0, atol=1e-13 * np.abs(expected).max())
