"""One start of the numerical inverse kinematics on one configuration: what one solution nearest ``near`` costs.

:func:`local_ik` runs the damped least squares of :func:`armlab.kinematics.ik_numeric.numeric_ik` from a single
start, with the numpy calls sized for one configuration: :class:`ToolChain` gives the tool pose **and** the
geometric Jacobian of a configuration in one pass through the chain (the n link transforms from one ``einsum``,
n small products for the frames, the columns from the frames' axes and origins), so an iteration costs a few
dozen small numpy calls instead of the batched path's hundreds (sized for thousands of configurations at once).
The converged start is polished by Newton steps on the arm's own forward kinematics (``arm.forward``), which has
the last word: a solution is returned only if it reaches the target to 1e-9 m and 1e-9 rad by it.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armlab.kinematics.ik_target import (
    fit_limits,
    joint_constants,
    made_once,
    on_target,
    project_into_limits,
    rotation_log,
)

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["LM_ITERATIONS", "NEWTON_STEPS", "ToolChain", "chain_of", "first_start", "local_ik", "tool_error"]

#: Levenberg–Marquardt iterations at most, then Newton polishing steps at most (here and in the batched search).
LM_ITERATIONS, NEWTON_STEPS = 200, 8

#: J_z(θ) = cos θ·_COS + sin θ·_SIN + _FIXED (a turn about z); J_z(d) = d·_SLIDE + I (a slide along z).
_COS, _SIN, _FIXED, _SLIDE = (np.zeros((4, 4)) for _ in range(4))
_COS[0, 0] = _COS[1, 1] = 1.0
_SIN[0, 1], _SIN[1, 0] = -1.0, 1.0
_FIXED[2, 2] = _FIXED[3, 3] = 1.0
_SLIDE[2, 3] = 1.0
#: The Levi-Civita symbol ε_ijk: (a × b)_i = ε_ijk a_j b_k, every column's cross product in one ``einsum``.
_EPSILON = np.zeros((3, 3, 3))
_EPSILON[0, 1, 2] = _EPSILON[1, 2, 0] = _EPSILON[2, 0, 1] = 1.0
_EPSILON[0, 2, 1] = _EPSILON[2, 1, 0] = _EPSILON[1, 0, 2] = -1.0
_IDENTITY = np.eye(4)


class ToolChain:
    """The constants of ``arm.table``'s chain, for the tool pose and Jacobian of one configuration at a time.

    Link i's transform pre_i · J_z(q_i) · post_i (:class:`armlab.kinematics.batch.ZStep`) is
    cos q_i·K_cos + sin q_i·K_sin + q_i·K_slide + K_0 with constant 4×4 matrices K (a revolute joint's K_slide and a
    prismatic joint's K_cos, K_sin are 0), so the n transforms are one ``einsum`` of a ``(4, n)`` weight array.
    """

    def __init__(self, arm: Arm) -> None:
        steps = arm.table.steps
        pre = np.array([_IDENTITY if step.pre is None else step.pre for step in steps])  # (n, 4, 4)
        post = np.array([_IDENTITY if step.post is None else step.post for step in steps])
        self.revolute = np.array([step.revolute for step in steps])
        self._all_revolute = bool(self.revolute.all())
        turn = self.revolute[:, None, None]
        self._K = np.stack([np.where(turn, pre @ _COS @ post, 0.0), np.where(turn, pre @ _SIN @ post, 0.0),
                            np.where(turn, 0.0, pre @ _SLIDE @ post),
                            np.where(turn, pre @ _FIXED @ post, pre @ post)])  # (4, n, 4, 4)
        self._k = np.array([row.k for row in arm.table.rows])  # joint axes in their frames {i}, (n, 3)
        self._tool = arm.table.tool
        self._frames = np.empty((arm.n, 4, 4))

    def pose(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """The tool pose ``(4, 4)`` at ``q`` ``(n,)`` (rad or m): :meth:`pose_jacobian`'s pose, without the Jacobian."""
        weights = np.array([np.cos(q), np.sin(q), q, np.ones_like(q)])
        links = np.einsum("kn,knij->nij", weights, self._K)
        T = links[0]
        for i in range(1, q.shape[0]):
            T = T @ links[i]
        return T @ self._tool

    def pose_jacobian(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The tool pose ``(4, 4)`` and the geometric Jacobian ``(6, n)`` (rows [v; ω], world frame) at ``q`` ``(n,)``
        (rad or m): the values of ``arm.table``'s chain that :func:`armlab.kinematics.differential.jacobian` gives."""
        weights = np.array([np.cos(q), np.sin(q), q, np.ones_like(q)])
        links = np.einsum("kn,knij->nij", weights, self._K)
        F = self._frames
        F[0] = links[0]
        for i in range(1, q.shape[0]):
            np.matmul(F[i - 1], links[i], out=F[i])
        tool = F[-1] @ self._tool
        z = np.einsum("nij,nj->ni", F[:, :3, :3], self._k)  # world axes z_i, (n, 3)
        lever = tool[:3, 3] - F[:, :3, 3]  # p_t − p_i
        moment = np.einsum("ijk,nj,nk->in", _EPSILON, z, lever)  # z_i × (p_t − p_i), (3, n)
        if self._all_revolute:
            return tool, np.concatenate([moment, z.T])
        turn = self.revolute
        return tool, np.concatenate([np.where(turn, moment, z.T), np.where(turn, z.T, 0.0)])


def chain_of(arm: Arm) -> ToolChain:
    """``arm``'s :class:`ToolChain`, made once per arm (:func:`armlab.kinematics.ik_target.made_once`: its constants
    cost more than an iteration of the solver)."""
    return made_once(arm, "chain", ToolChain)


def tool_error(position: NDArray, rotation: NDArray | None, tool: NDArray) -> NDArray[np.float64]:
    """[target − p; log(R* Rᵀ)] of one tool pose ``(4, 4)``: ``(3,)`` or ``(6,)`` (m, rad), as
    :func:`armlab.kinematics.ik_target.pose_error` has it."""
    error = position - tool[:3, 3]
    if rotation is None:
        return error
    return np.concatenate([error, rotation_log(rotation @ tool[:3, :3].T)])


def first_start(arm: Arm, q0: NDArray) -> NDArray[np.float64]:
    """The numerical solver's start from ``q0`` ``(n,)``: fitted into the joint limits by 2π shifts, else clipped."""
    joints = joint_constants(arm)
    return project_into_limits(arm, fit_limits(arm, q0[None, :], q0)[0][0], joints.lower, joints.upper, joints.interval)


def local_ik(arm: Arm, position: NDArray, rotation: NDArray | None, near: NDArray) -> NDArray[np.float64] | None:
    """The solution ``(n,)`` the numerical solver reaches within the joint limits from the one start ``near`` ``(n,)``
    (:func:`first_start`), or ``None`` if it does not reach ``position`` (m, ``(3,)``) and ``rotation`` (``(3, 3)`` or
    ``None``) to 1e-9 m and 1e-9 rad by ``arm.forward``.

    The rules of :func:`armlab.kinematics.ik_numeric.numeric_ik`'s Levenberg–Marquardt for one start: the step
    (JᵀJ + λI) δ = Jᵀe (as Jᵀ(JJᵀ + λI)⁻¹e when there are fewer rows than joints), projected into the limits; a joint
    at a limit the gradient pushes beyond is held; a step lowering |e| is kept and λ divided by 3, else λ multiplied
    by 4 (within [1e-12, 1e10]); it stops at |e|² < 1e-26, at a stationary point (|Jᵀe| ≤ 1e-6 |J| |e|) or at
    λ = 1e10, after :data:`LM_ITERATIONS` at most. Within |e| < 1e-5, up to :data:`NEWTON_STEPS` steps
    q ← q + J⁺e polish it.
    """
    joints = joint_constants(arm)
    lower, upper, limits = joints.lower, joints.upper, joints.interval
    chain = chain_of(arm)
    rows = 3 if rotation is None else 6
    identity = np.eye(rows if rows < arm.n else arm.n)
    q = first_start(arm, near)
    tool, J = chain.pose_jacobian(q)
    J = J[:rows]
    error = tool_error(position, rotation, tool)
    cost = float(error @ error)
    damping = 1e-3
    for _ in range(LM_ITERATIONS):
        gradient = J.T @ error
        held = (~limits.above_lower(q) & (gradient < 0)) | (~limits.below_upper(q) & (gradient > 0))  # by a limit
        Jf = J
        if held.any():
            gradient[held] = 0.0
            Jf = np.where(held, 0.0, J)  # a joint held by its limit takes no part in the step
        stationary = math.sqrt(gradient @ gradient) <= 1e-6 * math.sqrt(float(np.vdot(J, J)) * cost)
        if rows < arm.n:
            step = Jf.T @ np.linalg.solve(Jf @ Jf.T + damping * identity, error)
        else:
            step = np.linalg.solve(Jf.T @ Jf + damping * identity, gradient)
        trial = project_into_limits(arm, q + step, lower, upper, limits)
        trial_tool, trial_J = chain.pose_jacobian(trial)
        trial_error = tool_error(position, rotation, trial_tool)
        trial_cost = float(trial_error @ trial_error)
        if trial_cost < cost:
            q, J, error, cost, damping = trial, trial_J[:rows], trial_error, trial_cost, max(damping / 3, 1e-12)
        else:
            damping = min(damping * 4, 1e10)
        if cost < 1e-26 or stationary or damping >= 1e10:
            break
    if math.sqrt(cost) >= 1e-5:
        return None
    for _ in range(NEWTON_STEPS):
        if np.abs(error).max() < 1e-15:
            break
        trial = project_into_limits(arm, q + np.linalg.pinv(J, rcond=1e-10) @ error, lower, upper, limits)
        trial_tool, trial_J = chain.pose_jacobian(trial)
        trial_error = tool_error(position, rotation, trial_tool)
        if trial_error @ trial_error >= error @ error:
            break
        q, J, error = trial, trial_J[:rows], trial_error
    if on_target(error):
        return q
    return None
