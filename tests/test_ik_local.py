"""One start of the numerical IK on one configuration (armlab.kinematics.ik_local): its tool pose and Jacobian against
the arm's own FK, the batched Jacobian and finite differences; its solution against the batched solver's from the same
start, each put back through ``arm.forward`` to 1e-9 m and 1e-9 rad."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import ARM_NAMES, random_q

from armlab.kinematics.differential import jacobian
from armlab.kinematics.ik import solve
from armlab.kinematics.ik_local import ToolChain, local_ik
from armlab.kinematics.ik_numeric import numeric_ik
from armlab.kinematics.ik_target import fit_limits
from armlab.models import get_arm
from armlab.models.library import LIBRARY

TOL = 1e-9
#: Two evaluations of the same chain of products in another order: round-off on arms of about a metre.
CHAIN_TOL = 1e-12
#: Central differences with h = 1e-6: truncation ~h² and round-off ~1e-16/h, both far below this (m/rad per rad or m).
DIFFERENCE_TOL = 1e-8


@pytest.mark.parametrize("name", ARM_NAMES + list(LIBRARY))
def test_pose_and_jacobian_of_one_configuration(name: str, rng: np.random.Generator) -> None:
    """ToolChain.pose_jacobian(q) is arm.forward(q).tool and differential.jacobian(arm, q) (the batched path), and
    its [v] rows are the central differences of its own tool position, on every paper and library arm (the Stanford
    arm's prismatic joint and r2t's included)."""
    arm = get_arm(name)
    chain = ToolChain(arm)
    h = 1e-6
    for q in random_q(arm, rng, 5):
        tool, J = chain.pose_jacobian(q)
        np.testing.assert_allclose(tool, arm.forward(q).tool, rtol=0, atol=CHAIN_TOL)
        np.testing.assert_allclose(J, jacobian(arm, q), rtol=0, atol=CHAIN_TOL)
        steps = h * np.eye(arm.n)
        differences = np.array([chain.pose_jacobian(q + s)[0][:3, 3] - chain.pose_jacobian(q - s)[0][:3, 3]
                                for s in steps]).T / (2 * h)
        np.testing.assert_allclose(J[:3], differences, rtol=0, atol=DIFFERENCE_TOL)


@pytest.mark.parametrize(("name", "pose"), [("kr5", True), ("panda", True), ("urm6", True), ("panda", False),
                                            ("rrrr", False), ("kr5", False)])
def test_local_solution_is_the_batched_solvers_from_the_same_start(name: str, pose: bool,
                                                                   rng: np.random.Generator) -> None:
    """local_ik from near is the solution numeric_ik reaches from the one start near (same rules, batched numpy), to
    1e-9, and reaches the target by arm.forward to 1e-9 m and 1e-9 rad; solve() without all returns it (its angles
    shifted by 2π nearest near)."""
    arm = get_arm(name)
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    solved = 0
    for q in rng.uniform(np.maximum(lower, -np.pi) + 0.05, np.minimum(upper, np.pi) - 0.05, size=(8, arm.n)):
        T = arm.forward(q).tool
        position, rotation = T[:3, 3], (T[:3, :3] if pose else None)
        near = np.clip(q + rng.normal(0, 0.2, arm.n), *arm.limit_arrays())
        ours = local_ik(arm, position, rotation, near)
        try:
            batched = numeric_ik(arm, position, rotation, q0=near, seeds=1)[0]
        except ValueError:
            assert ours is None
            continue
        assert ours is not None
        solved += 1
        np.testing.assert_allclose(ours, batched, rtol=0, atol=TOL)
        reached = arm.forward(ours).tool
        np.testing.assert_allclose(reached[:3, 3], position, rtol=0, atol=TOL)
        if pose:
            np.testing.assert_allclose(reached[:3, :3], rotation, rtol=0, atol=TOL)
        (answer,) = solve(arm, T if pose else position, near=near)
        np.testing.assert_allclose(answer, fit_limits(arm, ours, near)[0][0], rtol=0, atol=TOL)  # 2π shifts near near
    assert solved >= 6  # a tracking step from 0.2 rad away: the one start reaches the target nearly always


def test_an_unreachable_target_is_none_and_solve_names_it() -> None:
    """A position 10 m from the KR5's base: local_ik returns None; solve falls back to the multi-start search,
    whose error gives the closest distance."""
    arm = get_arm("kr5")
    far = np.array([10.0, 0.0, 0.5])
    assert local_ik(arm, far, None, np.zeros(arm.n)) is None
    with pytest.raises(ValueError, match=r"out of reach of kr5: the tool gets no closer than"):
        solve(arm, far)
