"""Inverse kinematics along a tool path on one continuous branch: q(s), q'(s), q''(s) at the path's samples.

The joints at the first sample come from the caller (the start configuration, or the IK solution
:func:`armlab.kinematics.ik.solve` or :func:`~armlab.kinematics.ik.solve_branch` picked). Each following block
of :data:`BLOCK` samples is seeded by the first-order prediction q_i + J⁺(q_i)·Δx from the last solved sample
and solved by Levenberg–Marquardt steps on the whole block at once (numpy, batched FK and Jacobian) until the tool is
on the path to :data:`PATH_TOL` m (and rad); a block that does not converge is redone sample by sample from
its predecessor. The tasks are the tool position (3 rows; a planar arm's out-of-plane row is zero) and, when an
orientation is given, the tool rotation (3 more rows, world frame).

Then q' = J⁺ x' and q'' = J⁺ (x'' − J̇ q') (J̇ q' is the tool's acceleration at q̈ = 0, :func:`tool_motion`);
beside a singularity (σ_min/σ_max < :data:`NEAR_SINGULAR`), where J⁺ amplifies round-off, from the polynomial
through the :data:`STENCIL` samples around each instead.

Failures name the path parameter s and the point: the target leaves the reach (the iteration does not
converge, or it converges only off the branch), the path passes a singularity (σ_min of the task Jacobian below
:data:`SINGULAR_TOL` inside the path, moving the tool the way it cannot move there; a path along a singular
configuration's free directions is followed: paper 000's circle touches the reach at B, stretched, and at D,
folded), a joint
leaves its limits, or a joint steps further between two samples than the path step allows (a jump between
branches: more than :data:`STEP_FACTOR` times the first-order step J⁺Δx). Each of these bounds is applied by
:mod:`armlab.bounds` (one slack): a sample round-off beyond a joint limit is on it (paper 000's circle ends on
joint 2's), and is moved exactly onto it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armlab.bounds import above, below, clamp, outside, tolerated
from armlab.kinematics.differential import jacobian, tool_motion
from armlab.kinematics.ik import solve
from armlab.kinematics.ik_target import pose_error, rotation_log
from armlab.kinematics.locating import homogeneous

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["BLOCK", "PATH_TOL", "SINGULAR_TOL", "STEP_FACTOR", "PathJoints", "solve_path"]

#: Samples solved together (seeded from the last solved sample).
BLOCK = 64
#: The tool is on the path when its position error is ≤ this (m) and its orientation error ≤ this (rad).
PATH_TOL = 1e-12
#: The path passes a singularity where the task Jacobian's smallest singular value is at most this (m/rad).
SINGULAR_TOL = 1e-6
#: A joint step between samples larger than this many times the first-order step (beyond the slack) is a branch jump.
STEP_FACTOR = 3.0
#: Where σ_min/σ_max of the task Jacobian is at most this, q' and q'' come from the samples (finite differences).
NEAR_SINGULAR = 1e-2
#: Samples each local slope is fitted through there.
STENCIL = 7
#: The largest joint step (rad or m) a seed is predicted by.
MAX_SEED_STEP = 0.1
#: Levenberg–Marquardt steps at most per block.
ITERATIONS = 50


class PathJoints:
    """The joints along a path: ``s`` ``(m,)``, ``q``, ``dq`` (dq/ds), ``ddq`` (d²q/ds²), each ``(m, n)``."""

    def __init__(self, s: NDArray, q: NDArray, dq: NDArray, ddq: NDArray) -> None:
        self.s, self.q, self.dq, self.ddq = s, q, dq, ddq


def _task_error(arm: Arm, p: NDArray, R: NDArray | None, q: NDArray, rows: NDArray) -> NDArray[np.float64]:
    """The task rows ``rows`` of the tool's pose error [p* − p(q); log(R* R(q)ᵀ)], ``(m, len(rows))``."""
    return pose_error(arm, p, R, q)[..., rows]


def _task_jacobian(arm: Arm, q: NDArray, rows: NDArray) -> NDArray[np.float64]:
    """The task rows ``rows`` of the tool Jacobian [v; ω], ``(..., len(rows), n)``."""
    return jacobian(arm, q)[..., rows, :]


def _pinv_solve(J: NDArray, b: NDArray) -> NDArray[np.float64]:
    """J⁺ b per sample: J ``(m, r, n)``, b ``(m, r)`` → ``(m, n)`` (least squares, minimum norm): by the normal
    equations of a full-rank J (Jᵀ (J Jᵀ)⁻¹ b for r ≤ n, (JᵀJ)⁻¹ Jᵀ b for r > n), by the SVD where it is not."""
    Jt = np.swapaxes(J, -1, -2)
    try:
        if J.shape[-2] <= J.shape[-1]:
            return np.einsum("mnr,mr->mn", Jt, np.linalg.solve(J @ Jt, b[..., None])[..., 0])
        return np.linalg.solve(Jt @ J, np.einsum("mnr,mr->mn", Jt, b)[..., None])[..., 0]
    except np.linalg.LinAlgError:
        return np.einsum("mnr,mr->mn", np.linalg.pinv(J, rcond=1e-12), b)


def _newton(arm: Arm, p: NDArray, R: NDArray | None, q: NDArray, rows: NDArray) -> tuple[NDArray, NDArray]:
    """Levenberg–Marquardt from ``q`` ``(m, n)`` onto the targets with Sugihara's damping λ = |e|² + 1e-12
    (quadratic convergence where J is regular, and it still converges beside a singularity); (q, converged)."""
    q = q.copy()
    eye = np.eye(arm.n)
    for _ in range(ITERATIONS):
        error = _task_error(arm, p, R, q, rows)
        done = tolerated(np.max(np.abs(error), axis=-1), PATH_TOL)
        if done.all():
            return q, done
        active = ~done
        J, e = _task_jacobian(arm, q[active], rows), error[active]
        Jt = np.swapaxes(J, -1, -2)
        damping = (np.sum(e * e, axis=-1) + 1e-12)[:, None, None] * eye
        q[active] += np.linalg.solve(Jt @ J + damping, np.einsum("mnr,mr->mn", Jt, e)[..., None])[..., 0]
    return q, tolerated(np.max(np.abs(_task_error(arm, p, R, q, rows)), axis=-1), PATH_TOL)


def _unwrapped(arm: Arm, previous: NDArray, q: NDArray) -> NDArray[np.float64]:
    """Samples ``q`` ``(k, n)`` following ``previous`` ``(n,)``, each revolute joint moved by whole turns to within
    π of the sample before it (the same configurations, one continuous branch)."""
    joined = np.unwrap(np.vstack([previous, q]), axis=0)[1:]
    return np.where(arm.revolute, joined, q)


def _extrapolated(s: NDArray, q: NDArray, i: int, js: NDArray) -> NDArray[np.float64]:
    """Seeds at samples ``js`` by the quadratic through the solved samples i − 2, i − 1, i (Lagrange's form): it
    follows a branch through a fold of the IK, where J⁺Δx does not."""
    x = s[i - 2:i + 1]
    t = s[js][:, None]
    weights = [np.prod([(t - x[m]) / (x[k] - x[m]) for m in range(3) if m != k], axis=0) for k in range(3)]
    return sum(w * q[i - 2 + k] for k, w in enumerate(weights))


def _predicted(arm: Arm, q: NDArray, J: NDArray, dx: NDArray) -> NDArray[np.float64]:
    """The seeds q + J⁺Δx ``(k, n)`` for task steps ``dx`` ``(k, rows)`` from ``q`` ``(n,)`` with its Jacobian
    ``J``, each step cut to :data:`MAX_SEED_STEP` (beside a singularity J⁺ is huge; the seed is only a start)."""
    step = _pinv_solve(np.broadcast_to(J, (dx.shape[0], *J.shape)), dx)
    size = np.abs(step).max(axis=-1, keepdims=True)
    return q + step * np.minimum(1.0, MAX_SEED_STEP / np.maximum(size, 1e-300))


def _point(p: NDArray) -> str:
    return "(" + ", ".join(f"{v:.4g}" for v in p) + ") m"


def _delta(p: NDArray, R: NDArray | None, i: int, js: NDArray, rows: NDArray) -> NDArray[np.float64]:
    """Task differences x_j − x_i ``(len(js), len(rows))``: position, and the rotation vector log(R_j R_iᵀ)."""
    d = p[js] - p[i]
    if R is None:
        return d[:, rows]
    return np.concatenate([d, rotation_log(R[js] @ R[i].T)], axis=-1)[:, rows]


def solve_path(arm: Arm, what: str, s: NDArray, p: NDArray, dp: NDArray, ddp: NDArray, q_start: NDArray,
               R: NDArray | None = None, w: NDArray | None = None, dw: NDArray | None = None) -> PathJoints:
    """The joints along a sampled tool path on the branch of ``q_start`` ``(n,)`` (the joints at ``s[0]``).

    ``s`` ``(m,)`` the path parameter; ``p``, ``dp``, ``ddp`` ``(m, 3)``: the tool point (m) and its first and
    second derivatives in s; ``R`` ``(m, 3, 3)`` the tool rotation with its angular rate ``w`` and its derivative
    ``dw`` ``(m, 3)`` per unit s (world frame), or ``None`` (position only). ``what`` names the path in messages
    ("the line"). ``ValueError`` (with s and the point) where the path leaves the reach, passes a singularity,
    leaves a joint's limits or would jump between IK branches (module docstring).
    """
    m, n = s.size, arm.n
    rows = np.arange(3 if R is None else 6)
    q = np.empty((m, n))
    first, ok = _newton(arm, p[:1], None if R is None else R[:1], q_start[None, :], rows)
    if not ok[0]:
        raise ValueError(f"{what} does not start at the start configuration's tool point: {_point(p[0])}")
    q[0] = first[0]
    rows = rows[np.abs(_task_jacobian(arm, q[0], rows)).max(axis=1) > 1e-12]  # a planar arm: not the normal's
    rank = min(rows.size, n)  # the task's dimension the arm moves in
    i = 0
    while i < m - 1:
        js = np.arange(i + 1, min(i + 1 + (BLOCK if i >= 2 else 2 - i), m))  # 3 samples first, to extrapolate
        seed = (_extrapolated(s, q, i, js) if i >= 2 else
                _predicted(arm, q[i], _task_jacobian(arm, q[i], rows), _delta(p, R, i, js, rows)))
        solved, ok = _newton(arm, p[js], None if R is None else R[js], seed, rows)
        if not ok.all():  # sample by sample from the last good one
            for j in map(int, js):
                seed = (_extrapolated(s, q, j - 1, np.array([j])) if j >= 3 else
                        _predicted(arm, q[j - 1], _task_jacobian(arm, q[j - 1], rows),
                                   _delta(p, R, j - 1, np.array([j]), rows)))
                one, good = _newton(arm, p[j:j + 1], None if R is None else R[j:j + 1], seed, rows)
                if not good[0]:
                    _fail(arm, what, s[j], p[j], None if R is None else R[j])
                q[j] = _unwrapped(arm, q[j - 1], one)[0]
        else:
            q[js] = _unwrapped(arm, q[i], solved)
        i = int(js[-1])
    q = clamp(q, *arm.limit_arrays())  # a sample on a limit, round-off beyond it: onto it (_check: the others)
    xd = (dp if w is None else np.concatenate([dp, w], axis=-1))[:, rows]
    J = _task_jacobian(arm, q, rows)
    sigma = np.linalg.svd(J, compute_uv=False)
    _check(arm, what, s, p, R, q, rows, rank, xd, J, sigma)
    xdd = (ddp if dw is None else np.concatenate([ddp, dw], axis=-1))[:, rows]
    dq = _pinv_solve(J, xd)
    _, bias = tool_motion(arm, q, dq, np.zeros_like(dq))
    ddq = _pinv_solve(J, xdd - bias[:, rows])
    near = tolerated(sigma[:, rank - 1], NEAR_SINGULAR * sigma[:, 0])  # J⁺ loses its digits: the samples' slopes
    if near.any():
        dq[near], ddq[near] = _local_slopes(s, q, np.flatnonzero(near))
    return PathJoints(s, q, dq, ddq)


def _local_slopes(s: NDArray, q: NDArray, index: NDArray) -> tuple[NDArray, NDArray]:
    """q' and q'' ``(k, n)`` at the samples ``index`` from the degree-6 polynomial through the 7 samples nearest
    each (a window kept inside the path): sixth-order accurate in the sample step."""
    width = min(STENCIL, s.size)
    start = np.clip(index - width // 2, 0, s.size - width)
    window = start[:, None] + np.arange(width)  # (k, width)
    h = np.maximum(np.abs(np.diff(s)).max(), 1e-300)
    x = (s[window] - s[index][:, None]) / h  # offsets in steps
    V = x[..., None] ** np.arange(width)  # (k, width, width) Vandermonde
    c = np.linalg.solve(V, q[window])  # (k, width, n): q ≈ Σ c_p (Δs/h)^p
    return c[:, 1] / h, 2 * c[:, 2] / h**2


def _fail(arm: Arm, what: str, s: float, p: NDArray, R: NDArray | None) -> None:
    """``ValueError`` for a sample the IK could not follow the branch to: where the point (and rotation) is
    reachable at all (:func:`armlab.kinematics.ik.solve`'s multi-start search or closed form), the branch ends
    at a singularity there; else the path leaves the reach."""
    target = p if R is None else homogeneous(R, p)
    try:
        solve(arm, target)
    except ValueError:
        raise ValueError(f"{what} leaves {arm.name}'s reach at s = {s:.4g}, {_point(p)}") from None
    raise ValueError(f"{what} passes a singularity of {arm.name} at s = {s:.4g}, {_point(p)}: the IK branch ends "
                     "there (the point is reachable on another branch only)")


def _check(arm: Arm, what: str, s: NDArray, p: NDArray, R: NDArray | None, q: NDArray, rows: NDArray,
           rank: int, xd: NDArray, J: NDArray, sigma: NDArray) -> None:
    """Joint limits, singularities and branch jumps over the solved samples ``q`` ``(m, n)``; ``ValueError`` at the
    first. ``J`` ``(m, len(rows), n)``: the task Jacobian at each sample, ``sigma`` its singular values
    ``(m, min(len(rows), n))``, largest first."""
    lower, upper = arm.limit_arrays()
    beyond = np.argwhere(outside(q, lower, upper))
    if beyond.size:
        j, k = beyond[0]
        unit = "rad" if arm.revolute[k] else "m"
        low = bool(below(q[j, k], lower[k]))
        past = lower[k] - q[j, k] if low else q[j, k] - upper[k]  # beyond the limit's slack: no round-off
        raise ValueError(f"{what} takes joint {arm.joint_names[k]} of {arm.name} out of its limits "
                         f"[{lower[k]:.4g}, {upper[k]:.4g}] {unit} at s = {s[j]:.4g}, {_point(p[j])} "
                         f"({arm.joint_names[k]} = {q[j, k]:.6g} {unit}, {past:.3g} {unit} "
                         f"{'below its lower' if low else 'above its upper'} limit)")
    for j in np.flatnonzero(tolerated(sigma[1:-1, rank - 1], SINGULAR_TOL)) + 1:  # a path may start or end at one
        u = np.linalg.svd(J[j])[0][:, rank - 1]  # the direction the tool cannot move in there
        if not tolerated(abs(u @ xd[j]), 1e-3 * np.linalg.norm(xd[j])):  # the path goes that way: unbounded rates
            raise ValueError(f"{what} passes a singularity of {arm.name} at s = {s[j]:.4g}, {_point(p[j])}")
    predicted = np.abs(_pinv_solve(J[:-1], np.concatenate([np.diff(p, axis=0)] + (
        [] if R is None else [rotation_log(R[1:] @ np.swapaxes(R[:-1], -1, -2))]), axis=-1)[:, rows]))
    step = np.abs(np.diff(q, axis=0))
    jump = np.argwhere(above(step, STEP_FACTOR * predicted.max(axis=-1, keepdims=True)))
    if jump.size:
        j, k = jump[0]
        raise ValueError(f"{what}: the IK of {arm.name} jumps between branches at s = {s[j + 1]:.4g}, "
                         f"{_point(p[j + 1])} (joint {arm.joint_names[k]} steps {step[j, k]:.3g}); sample the path "
                         "more densely or start on another branch")
