"""The numerical inverse kinematics of any arm: multi-start damped least squares, polished by Newton steps.

:func:`numeric_ik` solves a position or a full pose target for any arm (urm6, rrrr, users'
arms): Levenberg–Marquardt on the tool pose error from many starts at once, each converged start
polished by Newton steps and checked by the arm's own forward kinematics. Unreachable targets and
targets reachable only outside the joint limits raise ``ValueError`` naming the target; an
unreachable position's error gives the closest distance the tool gets to it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import above, below
from armlab.kinematics.differential import jacobian
from armlab.kinematics.ik_local import LM_ITERATIONS, NEWTON_STEPS, first_start
from armlab.kinematics.ik_target import (
    check_pose,
    fit_limits,
    on_target,
    outside_limits_message,
    pose_error,
    project_into_limits,
    single,
    target_text,
)
from armlab.kinematics.locating import homogeneous

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["DISTINCT_TOL", "SEEDS", "numeric_ik"]

#: Starts of the numerical solver, solved as one batch: the first is ``near``, the rest random within limits.
SEEDS = 256
#: Numerical solutions closer than this (rad or m, revolute joints modulo 2π) are the same solution.
DISTINCT_TOL = 1e-6


def _jacobian_rows(arm: Arm, q: NDArray, rows: int) -> NDArray[np.float64]:
    """The tool Jacobian's first ``rows`` rows (3: linear velocity; 6: [v; ω]), world frame, ``(..., rows, n)``."""
    return jacobian(arm, q)[..., :rows, :]


def _levenberg_marquardt(
    arm: Arm, position: NDArray, rotation: NDArray | None, q: NDArray, lower: NDArray, upper: NDArray
) -> tuple[NDArray, NDArray]:
    """Damped least squares on the tool pose error, every start ``q`` ``(S, n)`` at once; returns (q, error).

    Each start takes the step (JᵀJ + λI) δ = Jᵀe, projected into the limits (:func:`_project`); a
    joint at a limit that the step would push beyond it is held (its column of J dropped). A step
    that lowers |e| is kept and λ divided by 3, else λ is multiplied by 4. A start stops when it
    reaches the target (|e|² < 1e-26), when it is stationary (|Jᵀe| ≤ 1e-6 |J| |e| over the joints
    not held: a local minimum of |e| within the limits, the closest the tool gets from there) or
    when no step lowers |e| (λ ≥ 1e10). Only the starts still running are computed.
    """
    rows = 3 if rotation is None else 6
    q = q.copy()
    error = pose_error(arm, position, rotation, q)
    cost = np.einsum("...i,...i", error, error)
    damping = np.full(q.shape[0], 1e-3)
    running = np.arange(q.shape[0])
    for _ in range(LM_ITERATIONS):
        J = _jacobian_rows(arm, q[running], rows)
        Jt = np.swapaxes(J, -1, -2)
        gradient = (Jt @ error[running, :, None])[..., 0]
        held = (~above(q[running], lower) & (gradient < 0)) | (~below(q[running], upper) & (gradient > 0))  # limit
        gradient = np.where(held, 0.0, gradient)
        stationary = np.linalg.norm(gradient, axis=-1) <= 1e-6 * np.linalg.norm(J, axis=(-2, -1)) * np.sqrt(
            cost[running])
        J = np.where(held[:, None, :], 0.0, J)  # a joint held by its limit takes no part in the step
        Jt = np.swapaxes(J, -1, -2)
        if rows < arm.n:  # the same step as Jᵀ(JJᵀ + λI)⁻¹e: a rows × rows system instead of n × n
            A = J @ Jt + damping[running, None, None] * np.eye(rows)
            step = (Jt @ np.linalg.solve(A, error[running, :, None]))[..., 0]
        else:
            A = Jt @ J + damping[running, None, None] * np.eye(arm.n)
            step = np.linalg.solve(A, gradient[..., None])[..., 0]
        trial = project_into_limits(arm, q[running] + step, lower, upper)
        trial_error = pose_error(arm, position, rotation, trial)
        trial_cost = np.einsum("...i,...i", trial_error, trial_error)
        better = trial_cost < cost[running]
        accepted = running[better]
        q[accepted], error[accepted], cost[accepted] = trial[better], trial_error[better], trial_cost[better]
        damping[running] = np.clip(np.where(better, damping[running] / 3, damping[running] * 4), 1e-12, 1e10)
        done = (cost[running] < 1e-26) | stationary | (damping[running] >= 1e10)
        running = running[~done]
        if running.size == 0:
            break
    return q, error


def _newton(
    arm: Arm, position: NDArray, rotation: NDArray | None, q: NDArray, lower: NDArray, upper: NDArray
) -> tuple[NDArray, NDArray]:
    """Newton steps q ← q + J⁺e (least-norm for a redundant request), kept within limits; returns (q, error)."""
    rows = 3 if rotation is None else 6
    error = pose_error(arm, position, rotation, q)
    for _ in range(NEWTON_STEPS):
        if np.abs(error).max(initial=0.0) < 1e-15:
            break
        step = np.linalg.pinv(_jacobian_rows(arm, q, rows), rcond=1e-10) @ error[..., None]
        trial = project_into_limits(arm, q + step[..., 0], lower, upper)
        trial_error = pose_error(arm, position, rotation, trial)
        better = np.linalg.norm(trial_error, axis=-1) < np.linalg.norm(error, axis=-1)
        q, error = np.where(better[:, None], trial, q), np.where(better[:, None], trial_error, error)
    return q, error


def _starts(arm: Arm, q0: NDArray, seeds: int) -> NDArray[np.float64]:
    """``q0`` and ``seeds − 1`` deterministic random starts within the limits (unlimited joints: (−π, π])."""
    lower, upper = arm.limit_arrays(unlimited=np.pi)
    random = np.random.default_rng(0).uniform(lower, upper, size=(seeds - 1, arm.n))
    first = first_start(arm, q0)
    return np.vstack([first[None, :], random])


def _search(
    arm: Arm, position: NDArray, rotation: NDArray | None, starts: NDArray, limited: bool
) -> tuple[NDArray, NDArray]:
    """(solutions reaching the target to 1e-9 m and 1e-9 rad, error of every start) from ``starts``."""
    lower, upper = arm.limit_arrays() if limited else (np.full(arm.n, -np.inf), np.full(arm.n, np.inf))
    q, error = _levenberg_marquardt(arm, position, rotation, starts, lower, upper)
    close = np.linalg.norm(error, axis=-1) < 1e-5
    q, polished = _newton(arm, position, rotation, q[close], lower, upper)
    error[close] = polished
    reached = on_target(polished)
    return q[reached], error


def numeric_ik(
    arm: Arm, position: ArrayLike, rotation: ArrayLike | None = None, q0: ArrayLike | None = None,
    seeds: int = SEEDS,
) -> NDArray[np.float64]:
    """Joint values ``(k, n)`` putting ``arm``'s tool at ``position`` (and orientation ``rotation``), any arm.

    A multi-start damped least squares (Levenberg–Marquardt) on the tool pose error
    [target − p(q); log(R* R(q)ᵀ)] (m, rad; :func:`armlab.kinematics.ik_target.rotation_log`) with the arm's geometric
    Jacobian (:func:`armlab.kinematics.differential.jacobian`), from ``q0`` (default zeros)
    and ``seeds − 1`` deterministic random starts within the joint limits, all solved as one
    batch and kept within the limits (revolute angles shifted by 2π, else clipped). Each
    converged start is polished by Newton steps and kept only if the arm's own forward
    kinematics (``arm.forward``) reaches the target to 1e-9 m and 1e-9 rad. One row per
    start that succeeded, duplicates included (:func:`armlab.kinematics.ik.solve` removes them): every solution
    *found* — a redundant request (fewer constraints than joints) has infinitely many.

    ``ValueError`` naming the target if no start succeeds: "reachable only outside the joint
    limits" if the search without limits succeeds; else the closest distance the tool gets to
    the position (the minimum of |p(q) − target| over the limits, from the same starts), or,
    for a pose whose position is reachable, the closest pose found.
    """
    position = single(position, 3)
    if rotation is not None:
        _, rotation = check_pose(homogeneous(rotation, position))
    q0 = np.zeros(arm.n) if q0 is None else single(q0, arm.n, "q0")
    if not (isinstance(seeds, int) and seeds >= 1):
        raise ValueError(f"seeds = {seeds!r} must be a positive whole number")
    starts = _starts(arm, q0, seeds)
    found, error = _search(arm, position, rotation, starts, limited=True)
    if found.shape[0]:
        return found
    what = target_text(position, rotation)
    lower, upper = arm.limit_arrays()
    if np.isfinite(lower).any() or np.isfinite(upper).any():
        free, _ = _search(arm, position, rotation, starts, limited=False)
        if free.shape[0]:
            fitted, violations = fit_limits(arm, free, q0)
            inside = [v is None for v in violations]
            if any(inside):
                return fitted[inside]
            raise ValueError(outside_limits_message(arm, what, violations))
    if rotation is not None:
        _, position_error = _search(arm, position, None, starts, limited=True)
        if on_target(position_error).any():
            best = error[np.argmin(np.linalg.norm(error, axis=-1))]
            raise ValueError(
                f"{what} is out of reach of {arm.name}: its position is reachable, but not with this "
                f"orientation (the closest pose found from {seeds} starts is {np.linalg.norm(best[:3]):.3g} m and "
                f"{np.linalg.norm(best[3:]):.3g} rad away)")
        error = position_error
    closest = float(np.linalg.norm(error[:, :3], axis=-1).min())
    raise ValueError(f"{what} is out of reach of {arm.name}: the tool gets no closer than {closest:.6g} m to it "
                     f"(the minimum of |p(q) − target| within the joint limits, from {seeds} starts)")
