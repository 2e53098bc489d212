"""Inverse kinematics: the one dispatcher, :func:`solve`, between an arm's closed form and the numerical solver.

* A paper arm's module gives its arm its paper's closed form (:attr:`armlab.models.arm.Arm.closed_form`,
  a :class:`armlab.kinematics.ik_closed_form.ClosedForm`: rr, arm4r and r2t, the functions of
  :mod:`armlab.kinematics.ik_closed_form`); :func:`solve` uses it when the arm has one.
* Any other arm (urm6, rrrr, users' arms) is solved numerically: one solution nearest ``near`` by one start on one
  configuration, :func:`armlab.kinematics.ik_local.local_ik` (a few ms), every solution by the batched multi-start
  search, :func:`armlab.kinematics.ik_numeric.numeric_ik`.
* :func:`solve` — what ``armlab ik`` and ``Arm.ik`` call: fits every angle into the joint limits,
  drops, deduplicates (modulo 2π) and orders the solutions (nearest to ``near`` first, ties broken
  by :data:`ORDER_TOL`'s rule); :func:`solve_branch` — one chosen branch of a closed form (rr's);
  :func:`target_pose` — a pose target as :func:`solve` takes it for an arm.

Unreachable targets and targets reachable only outside the joint limits raise
``ValueError`` naming the target (paper 001: "some of the possible solutions … can not be
realized because of the structure limitation … the nearest set of solution will be chosen");
an unreachable position's error gives the closest distance the tool gets to it.
"""

from __future__ import annotations

from dataclasses import replace
from functools import cmp_to_key
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import tolerated
from armlab.kinematics.ik_local import chain_of, local_ik, tool_error
from armlab.kinematics.ik_numeric import DISTINCT_TOL, SEEDS, numeric_ik
from armlab.kinematics.ik_target import (
    ORIENTATION_TOL,
    POSITION_TOL,
    check_pose,
    fit_limits,
    joint_constants,
    on_target,
    outside_limits_message,
    pose,
    pose_error,
    single,
    target_text,
)
from armlab.limits import check_range, real_array
from armlab.values import shown

if TYPE_CHECKING:
    from armlab.kinematics.ik_closed_form import ClosedForm
    from armlab.models.arm import Arm

__all__ = ["ORDER_TOL", "SEEDS", "solve", "solve_branch", "target_pose"]

#: Two solutions of a closed form closer than this in every joint are the same solution.
SAME_SOLUTION_TOL = 1e-9
#: When ordering solutions, distances to ``near`` and joint values that differ by no more than this
#: (rad or m) are equal: a tie, so that round-off (a few ulp, which differ between machines) never decides.
ORDER_TOL = 1e-9


def _coordinates(arm: Arm, position: NDArray) -> NDArray[np.float64]:
    """A position target as ``arm`` takes it, (3,): x, y, z; a closed form may take fewer coordinates (rr: x, y in
    its plane, from x,y or x,y,0) and the rest of the tool position is then 0."""
    form = arm.closed_form
    if form is not None and form.coordinates is not None:
        own = form.coordinates(position)
        return np.append(own, np.zeros(3 - own.size))
    if position.shape != (3,):
        raise ValueError(f"target {shown(np.ravel(position).tolist())} has {position.size} values; {arm.name} takes "
                         "3 coordinates (x,y,z in m) or a 4×4 pose")
    return position


def _target(arm: Arm, target: ArrayLike) -> tuple[NDArray, NDArray | None]:
    """(position (3,), rotation (3, 3) or None) of a position or 4×4 pose target, checked."""
    t = real_array(target, "target")  # not bools, text or complex numbers: as fk and jacobian refuse them
    position, rotation = check_pose(t) if t.shape == (4, 4) else (t, None)
    position = single(_coordinates(arm, position), 3)
    try:
        check_range(position, "target", key="coordinate")  # all three at once; the message names the axis:
    except ValueError:
        for axis, value in zip("xyz", position, strict=True):
            check_range(value, f"target {axis}", key="coordinate")
        raise
    return position, rotation


def target_pose(arm: Arm, position: ArrayLike, rpy: ArrayLike) -> NDArray[np.float64]:
    """The 4×4 pose target of ``position`` as :func:`solve` takes it for ``arm`` (rr: x,y or x,y,0) and ``rpy``
    (rad, R = Rz(y)·Ry(p)·Rx(r), :func:`armlab.kinematics.ik_target.pose`)."""
    return pose(_target(arm, position)[0], rpy)


def _closed_form(arm: Arm, form: ClosedForm, position: NDArray, rotation: NDArray | None, options: dict[str, float],
                 near: NDArray) -> NDArray[np.float64]:
    """Every branch of the arm's closed form reaching ``position`` (and ``rotation``), shape ``(k, n)``.

    The closed form takes the position, the rotation (arm4r reads its θ1 and pitch off it), ``near`` and its
    ``options`` (arm4r: the pitch); for a pose, the branches are kept whose tool orientation (by
    ``arm.forward``) matches the target's to 1e-9 rad.
    """
    candidates = form.solve(position, rotation, near, **options)
    if rotation is None or form.needs_pose:  # a closed form of the pose matches its orientation by construction
        return candidates  # (solve's own FK check of what it returns still has the last word)
    miss = np.linalg.norm(pose_error(arm, position, rotation, candidates)[:, 3:], axis=-1)
    if not np.any(tolerated(miss, ORIENTATION_TOL)):
        raise ValueError(f"{target_text(position, rotation)} is out of reach of {arm.name}: its position is "
                         f"reachable, but not with this orientation (the {len(miss)} branches of the closed form "
                         f"reaching it miss the orientation by {miss.min():.3g} rad at least)")
    return candidates[tolerated(miss, ORIENTATION_TOL)]


def _check_options(arm: Arm, options: dict[str, float]) -> None:
    """``ValueError`` for an option (``pitch``) the arm's closed form does not take, naming those it takes."""
    form = arm.closed_form
    for name, value in options.items():
        if form is None or name not in form.options:
            takes = ", ".join(f"{option} ({what})" for option, what in (form.options if form else {}).items())
            raise ValueError(f"{name} = {value} is not an option of {arm.name}'s inverse kinematics; it takes "
                             f"{takes or 'none'}")


def solve_branch(arm: Arm, point: ArrayLike, branch: int) -> NDArray[np.float64]:
    """Branch ``branch`` of ``arm``'s closed form reaching ``point`` (the closed form's coordinates, rr: x,y or
    x,y,0), fitted into the joint limits nearest itself: ``(n,)``.

    Only a closed form whose branches can be chosen (:attr:`~armlab.kinematics.ik_closed_form.ClosedForm.selectable`:
    rr's two elbows, paper 000's Table 2) takes a branch; ``ValueError`` for any other arm or branch, or a branch
    outside the joint limits.
    """
    form = arm.closed_form
    if form is None or not form.selectable or branch not in range(len(form.branches)):
        choices = (" and ".join(f"{k} ({text})" for k, text in enumerate(form.branches))
                   if form is not None and form.selectable else "")
        raise ValueError(f"IK branch {branch!r} is not allowed for {arm.name}: "
                         + (f"its branches are {choices}" if choices else "it has no branch to choose; give none (the "
                            "solution nearest the previous joints is taken)"))
    own = np.asarray(point, dtype=float)
    own = own if form.coordinates is None else form.coordinates(own)
    q = form.solve(np.append(own, np.zeros(3 - own.size)), None, np.zeros(arm.n))[branch]
    fitted, violations = fit_limits(arm, q, near=q)
    if violations[0] is not None:
        raise ValueError(f"point {own.tolist()} on IK branch {branch} is outside {arm.name}'s joint limits")
    return fitted[0]


def _joint_difference(arm: Arm, q: NDArray, near: NDArray) -> NDArray[np.float64]:
    """``q − near``, for an unlimited revolute joint taken modulo 2π into [−π, π) (its angle is wrapped anyway)."""
    joints = joint_constants(arm)
    unlimited = joints.revolute & ~joints.limited
    d = q - near
    return np.where(unlimited, np.remainder(d + np.pi, 2 * np.pi) - np.pi, d)


def _distinct(arm: Arm, q: NDArray, tol: float) -> NDArray[np.float64]:
    """The rows of ``q`` ``(k, n)`` that differ from every earlier row by more than ``tol`` (revolute: modulo 2π)."""
    d = q[None, :, :] - q[:, None, :]
    d = np.where(arm.revolute, np.remainder(d + np.pi, 2 * np.pi) - np.pi, d)
    same = tolerated(np.abs(d).max(axis=-1), tol).tolist()  # (k, k): row i within tol of row j
    keep: list[int] = []
    for i, row in enumerate(same):
        if not any(row[j] for j in keep):
            keep.append(i)
    return q[keep]


def _ordered(arm: Arm, q: NDArray, near: NDArray) -> list[NDArray[np.float64]]:
    """The rows of ``q`` ``(k, n)`` nearest ``near`` first; ties (distances within :data:`ORDER_TOL`) in
    lexicographic order of the joint values, a joint's values within :data:`ORDER_TOL` counting as equal."""
    distance = np.linalg.norm(_joint_difference(arm, q, near), axis=-1)

    def compare(i: int, j: int) -> int:
        if not tolerated(abs(distance[i] - distance[j]), ORDER_TOL):
            return -1 if distance[i] < distance[j] else 1  # not a bound: the order of two distances, not a tie
        apart = np.flatnonzero(~tolerated(np.abs(q[i] - q[j]), ORDER_TOL))
        return 0 if apart.size == 0 else (-1 if q[i, apart[0]] < q[j, apart[0]] else 1)

    return [q[i] for i in sorted(range(q.shape[0]), key=cmp_to_key(compare))]


def _local(arm: Arm, position: NDArray, rotation: NDArray | None, near: NDArray, seeds: int) -> NDArray[np.float64]:
    """The solution the numerical solver reaches from ``near`` alone, ``(1, n)``: what one solution costs (a few
    ms, :func:`armlab.kinematics.ik_local.local_ik`); if that start fails within the limits, what the one start reaches
    without them fitted into them by 2π shifts, else every solution ``seeds`` starts find (the search's own error if
    none)."""
    found = local_ik(arm, position, rotation, near)
    if found is not None:
        return found[None, :]
    try:
        return numeric_ik(arm, position, rotation, q0=near, seeds=1)[:1]
    except ValueError:
        return numeric_ik(arm, position, rotation, q0=near, seeds=seeds)


def _held(arm: Arm, joints: range, q: NDArray) -> Arm:
    """``arm`` with ``joints`` held at ``q``'s values (their limits closed onto them)."""
    limits = tuple(replace(lim, lower=float(q[i]), upper=float(q[i])) if i in joints else lim
                   for i, lim in enumerate(arm.limits))
    return replace(arm, limits=limits)


def _numeric(arm: Arm, position: NDArray, rotation: NDArray | None, near: NDArray, all_solutions: bool,
             seeds: int) -> NDArray[np.float64]:
    """Numerical candidates ``(k, n)``: the local solution from ``near`` first, then (``all_solutions``) the rest.

    A request with as many constraints as joints (a pose on six, a position on three) has a finite set: every
    solution ``seeds`` starts find. One with fewer (a position on more than three joints, a pose on more than six) has
    a continuum; its rest is the finite set at the continuum's parameter held at the local solution q*'s: for a
    position, the tool orientation of q* (then, for more than six joints, also joints 7 … n at q*'s values), for a
    pose, joints 7 … n at q*'s values. An arm whose closed form needs a pose (``needs_pose``) solves that pose by it.
    """
    local = _local(arm, position, rotation, near, seeds)
    if not all_solutions:
        return local
    fitted = fit_limits(arm, local, near)[0]
    best = fitted[np.argmin(np.linalg.norm(_joint_difference(arm, fitted, near), axis=-1))]
    if rotation is None and arm.n > 3:
        rotation = arm.forward(best).tool[:3, :3]
        form = arm.closed_form
        if form is not None and form.needs_pose:
            rest = _closed_form(arm, form, position, rotation, {}, near)
            return np.vstack([best[None, :], rest])
    held = arm if arm.n <= 6 else _held(arm, range(6, arm.n), best)
    rest = numeric_ik(held, position, rotation, q0=near, seeds=seeds)
    return np.vstack([best[None, :], rest])


def _checked_nearest(arm: Arm, candidates: NDArray, position: NDArray, rotation: NDArray | None,
                     near: NDArray) -> NDArray[np.float64] | None:
    """What :func:`solve` without ``all_solutions`` returns from ``candidates`` ``(k, n)``, checked only where it
    decides: the candidate nearest ``near`` once fitted into the limits, if it is the only one that near (no tie
    within :data:`ORDER_TOL`) and reaches the target by the arm's own FK; ``None`` otherwise (then :func:`solve`'s
    whole path decides, and names what is wrong). The FK of a DH arm is its chain's (:func:`chain_of`: the same
    frames as ``arm.forward``'s, multiplied out for one configuration, as :func:`local_ik` checks its own), of a paper
    arm its own ``arm.forward``."""
    fitted, violations = fit_limits(arm, candidates, near)
    kept = fitted[[v is None for v in violations]]
    if kept.shape[0] == 0:
        return None
    distance = np.linalg.norm(_joint_difference(arm, kept, near), axis=-1)
    order = np.argsort(distance)
    best = kept[order[0]]
    if order.size > 1 and tolerated(distance[order[1]] - distance[order[0]], ORDER_TOL):
        return None  # a tie: _ordered's rule breaks it
    if arm.dh is not None or arm.forward_fn is None:  # a DH arm: its URDF frames' chain (tests/test_ik_local.py)
        error = tool_error(position, rotation, chain_of(arm).pose(best))
    else:
        error = pose_error(arm, position, rotation, best)
    return best if on_target(error) else None


def solve(
    arm: Arm,
    target: ArrayLike,
    pitch: float | None = None,
    near: ArrayLike | None = None,
    all_solutions: bool = False,
    seeds: int = SEEDS,
) -> list[NDArray[np.float64]]:
    """Joint values reaching ``target`` within ``arm``'s joint limits, nearest to ``near`` first.

    ``target`` is a tool position (3,) in m (rr: (x, y) or (x, y, 0)) or a full tool pose,
    a 4×4 homogeneous matrix (its rotation orthonormal with determinant +1, to 1e-9).

    * An arm with a closed form (``arm.closed_form``, from its paper's module) is solved by it, every
      branch: rr :func:`~armlab.kinematics.ik_closed_form.rr_ik`, 2 branches — the arm moves in z = 0;
      arm4r :func:`~armlab.kinematics.ik_closed_form.arm4r_ik`, 4 branches, with ``pitch`` = θ2 + θ3 + θ4
      (rad), **pitch = 0 if not given** (tool x axis horizontal, the "stretched" state of paper 001's
      simulation); r2t :func:`~armlab.kinematics.ik_closed_form.r2t_ik`, 2 branches. For a pose the
      branches are kept whose orientation matches (:func:`_closed_form`).
      A library arm with a closed form for a full pose (UR5, UR10: :func:`~armlab.kinematics.ik_wrist.ur_ik`;
      Puma 560, IRB 140, KR5, Stanford: :func:`~armlab.kinematics.ik_wrist.spherical_wrist_ik`) solves a pose by it,
      8 branches. Without ``all_solutions``, only the branch nearest ``near`` is checked by FK
      (:func:`_checked_nearest`; the whole path below if it does not decide alone).
    * any other arm (urm6, rrrr, users' arms, Panda, …), and a position target of an arm whose closed form
      needs a pose: :func:`~armlab.kinematics.ik_numeric.numeric_ik`. Without ``all_solutions``, the
      solution reached from ``near`` alone (one start, :func:`~armlab.kinematics.ik_local.local_ik`: a few ms; the
      local solution, nearest ``near`` in most cases, not always), or, if that start fails, the nearest of ``seeds``
      starts. With it, the local
      solution and every distinct solution ``seeds`` starts find; a request with fewer constraints than
      joints has a continuum of solutions, so what is returned is the finite set at its parameter held at the
      local solution's (:func:`_numeric`): a **position** target of an arm of more than three joints, the
      solutions with the tool orientation of the local solution (the 8 branches of a UR or spherical-wrist closed form);
      a **pose** target of an arm of more than six joints (Panda), the solutions with joints 7 … n at the
      local solution's values.

    Every solution is fitted into the joint limits by :func:`~armlab.kinematics.ik_target.fit_limits`;
    those that do not fit are dropped, duplicates (revolute joints modulo 2π) removed, and the rest
    sorted by Euclidean joint distance to ``near`` (default zeros; an unlimited revolute joint's
    difference taken modulo 2π). Distances within :data:`ORDER_TOL` (1e-9) are a tie, broken by the
    joint values in lexicographic order (q1 first, smaller first; values within 1e-9 equal), so the
    order is the same on every machine. Each is checked by the arm's own FK to reach the target to
    1e-9 m (and 1e-9 rad). Returns every solution if ``all_solutions``, else ``[best]``. ``ValueError``
    (naming the bad value) for a wrong number of coordinates, NaN/inf, a coordinate beyond ±1e6 m or a
    pitch or ``near`` beyond ±1e6, a matrix that is not a pose, a pitch for an arm whose closed form
    takes none (only arm4r's does; nor with a pose), an unreachable target (with the closest
    distance), or a target reachable only outside the joint limits (naming the joint and its limits).
    """
    position, rotation = _target(arm, target)
    near = np.zeros(arm.n) if near is None else single(near, arm.n, "near")
    check_range(near, "near", key="q")
    options = {} if pitch is None else {"pitch": pitch}
    _check_options(arm, options)
    if pitch is not None and np.isfinite(pitch):  # NaN/inf: the closed form names them as such
        check_range(pitch, "pitch", key="angle")
    form = arm.closed_form
    closed = form is not None and (rotation is not None or not form.needs_pose)
    if not all_solutions:  # one solution: only the nearest candidate is checked, if it decides alone
        if form is not None and closed:
            candidates = _closed_form(arm, form, position, rotation, options, near)
        else:
            local = local_ik(arm, position, rotation, near)
            candidates = np.empty((0, arm.n)) if local is None else local[None, :]
        best = _checked_nearest(arm, candidates, position, rotation, near) if candidates.shape[0] else None
        if best is not None:
            return [best]
    if form is not None and closed:
        candidates, tol = _closed_form(arm, form, position, rotation, options, near), SAME_SOLUTION_TOL
    else:
        candidates, tol = _numeric(arm, position, rotation, near, all_solutions, seeds), DISTINCT_TOL
    fitted, violations = fit_limits(arm, candidates, near)
    kept = fitted[[v is None for v in violations]]
    if kept.shape[0] == 0:
        raise ValueError(outside_limits_message(arm, target_text(position, rotation), violations))
    error = pose_error(arm, position, rotation, kept)  # the last word: the arm's own FK of what is returned
    reached = on_target(error)
    if not np.any(reached):
        miss = np.maximum(np.linalg.norm(error[:, :3], axis=-1) / POSITION_TOL,
                          np.linalg.norm(error[:, 3:], axis=-1) / ORIENTATION_TOL)
        raise ValueError(f"{target_text(position, rotation)}: no solution of {arm.name} reaches it to "
                         f"{POSITION_TOL:g} m and {ORIENTATION_TOL:g} rad (the closest misses by "
                         f"{np.linalg.norm(error[np.argmin(miss)]):.3g})")
    unique = _ordered(arm, _distinct(arm, kept[reached], tol), near)
    return unique if all_solutions else unique[:1]
