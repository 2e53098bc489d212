"""Batch inverse dynamics (armlab.kinematics.rnea) against Drake's CalcInverseDynamics and the RR arm's
Lagrange equations."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import arm_and_plant, random_q

from armlab.kinematics.rnea import inverse_dynamics
from armlab.models import get_arm
from armlab.models.plant import PlantOptions, make_plant

SAMPLES = 100


def _drake_inverse_dynamics(arm, gravity, payload, q, qd, qdd):
    """Drake's CalcInverseDynamics, gravity as the plant's force elements, one sample at a time."""
    from pydrake.multibody.tree import MultibodyForces

    plant = make_plant(arm, PlantOptions(tuple(gravity), payload, ideal_drives=True))
    context = plant.CreateDefaultContext()
    forces = MultibodyForces(plant)
    tau = []
    for qk, qdk, qddk in zip(q, qd, qdd, strict=True):
        plant.SetPositions(context, qk)
        plant.SetVelocities(context, qdk)
        plant.CalcForceElementsContribution(context, forces)
        tau.append(plant.CalcInverseDynamics(context, qddk, forces))
    return np.array(tau)


@pytest.mark.parametrize(("gravity", "payload"), [(None, 0.0), ("off", 0.0), ((1.0, -4.0, -9.0), 2.5)])
def test_inverse_dynamics_matches_drake(dynamic_arm, rng, gravity, payload):
    from armlab.values import resolve_gravity

    arm = dynamic_arm
    q = random_q(arm, rng, SAMPLES)
    qd, qdd = rng.normal(size=q.shape) * 2, rng.normal(size=q.shape) * 5
    tau = inverse_dynamics(arm, q, qd, qdd, gravity=gravity, payload=payload)
    expected = _drake_inverse_dynamics(arm, resolve_gravity(arm, gravity), payload, q, qd, qdd)
    assert tau.shape == (SAMPLES, arm.n)
    np.testing.assert_allclose(tau, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
    np.testing.assert_allclose(inverse_dynamics(arm, q[0], qd[0], qdd[0], gravity, payload), tau[0],
                               rtol=1e-13, atol=1e-12)


def test_rr_matches_lagrange_closed_form(rng):
    """The 2R planar arm's Lagrange equations, from the URDF's uniform cylinders and a tool point mass."""
    arm, _, _ = arm_and_plant("rr")
    p = arm.parameters
    G = 9.81  # gravity −y, in the arm's plane
    payload = 1.5
    q = random_q(arm, rng, SAMPLES)
    qd, qdd = rng.normal(size=q.shape) * 2, rng.normal(size=q.shape) * 5
    L1, L2, m1, m2 = p["L1"], p["L2"], p["m1"], p["m2"]
    I1 = m1 * (3 * p["r1"] ** 2 + L1**2) / 12  # uniform cylinders about their centres, across their axis
    I2 = m2 * (3 * p["r2"] ** 2 + L2**2) / 12
    lc1 = L1 / 2
    # link 2 with the payload at its end: mass, centre and inertia of the two together
    M2 = m2 + payload
    lc2 = (m2 * L2 / 2 + payload * L2) / M2
    I2 = I2 + m2 * (L2 / 2 - lc2) ** 2 + payload * (L2 - lc2) ** 2
    c2, s2 = np.cos(q[:, 1]), np.sin(q[:, 1])
    M11 = I1 + I2 + m1 * lc1**2 + M2 * (L1**2 + lc2**2 + 2 * L1 * lc2 * c2)
    M12 = I2 + M2 * (lc2**2 + L1 * lc2 * c2)
    M22 = I2 + M2 * lc2**2
    h = M2 * L1 * lc2 * s2
    g1 = (m1 * lc1 + M2 * L1) * G * np.cos(q[:, 0]) + M2 * lc2 * G * np.cos(q[:, 0] + q[:, 1])
    g2 = M2 * lc2 * G * np.cos(q[:, 0] + q[:, 1])
    tau1 = M11 * qdd[:, 0] + M12 * qdd[:, 1] - h * (2 * qd[:, 0] * qd[:, 1] + qd[:, 1] ** 2) + g1
    tau2 = M12 * qdd[:, 0] + M22 * qdd[:, 1] + h * qd[:, 0] ** 2 + g2
    np.testing.assert_allclose(inverse_dynamics(arm, q, qd, qdd, payload=payload), np.stack([tau1, tau2], -1),
                               rtol=1e-10, atol=1e-10)


def test_the_arms_inverse_dynamics_is_the_batch_rnea(rng):
    arm, _, _ = arm_and_plant("rrrr")
    q = random_q(arm, rng, 20)
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
    # exact: the method calls this function
    np.testing.assert_array_equal(arm.inverse_dynamics(q, qd, qdd, payload=0.5),
                                  inverse_dynamics(arm, q, qd, qdd, payload=0.5))


def test_a_batch_of_any_shape_and_broadcasting(rng):
    arm, _, _ = arm_and_plant("urm6")
    q = random_q(arm, rng, 12).reshape(3, 4, 6)
    qd = rng.normal(size=6)
    tau = inverse_dynamics(arm, q, qd, np.zeros(6))
    assert tau.shape == (3, 4, 6)
    np.testing.assert_allclose(tau[1, 2], inverse_dynamics(arm, q[1, 2], qd, np.zeros(6)), rtol=1e-13, atol=1e-13)


def test_kinematic_arm_and_bad_input_are_value_errors(tmp_path):
    path = tmp_path / "no_masses.csv"
    path.write_text("type,a,alpha,d,theta,lower,upper\nR,0.3,0,0,0,-3,3\nR,0.2,0,0,0,-3,3\n")
    arm = get_arm(str(path))
    with pytest.raises(ValueError, match="inverse dynamics needs mass data"):
        inverse_dynamics(arm, [0, 0], [0, 0], [0, 0])
    rr, _, _ = arm_and_plant("rr")
    with pytest.raises(ValueError, match="expected 2 joint values"):
        inverse_dynamics(rr, [0, 0, 0], [0, 0], [0, 0])
    with pytest.raises(ValueError, match="payload"):
        inverse_dynamics(rr, [0, 0], [0, 0], [0, 0], payload=-1.0)
    with pytest.raises(ValueError, match="gravity"):
        inverse_dynamics(rr, [0, 0], [0, 0], [0, 0], gravity="sideways")


def test_batches_longer_than_a_block(rng):
    from armlab.kinematics.batch import BLOCK

    arm, _, _ = arm_and_plant("r2t")
    q = random_q(arm, rng, BLOCK + 5)
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
    tau = inverse_dynamics(arm, q, qd, qdd, payload=3.0)
    for k in (0, BLOCK - 1, BLOCK, BLOCK + 4):
        np.testing.assert_allclose(tau[k], inverse_dynamics(arm, q[k], qd[k], qdd[k], payload=3.0), rtol=1e-13,
                                   atol=1e-10)
