"""Manipulability over a workspace and the singular configurations, where σ_min(J) → 0.

The Jacobian is :func:`armlab.kinematics.differential.jacobian`'s, its rows chosen as that module's
default (all six for n ≥ 6 joints, the translational ones otherwise): Yoshikawa's measure
w = √det(J Jᵀ) and the smallest singular value σ_min are evaluated on the workspace's kept
configurations (:func:`add_manipulability`).

Singular configurations (:func:`singular_configurations`):

* the joints σ_min depends on are found by redrawing one joint at a time (the base joint of every
  arm here never matters: turning the whole arm does not change J's singular values);
* when σ_min depends on one joint only (rr: θ2), that joint is scanned over its range and every zero
  of σ_min found by golden-section search: the singular **loci** are those joint values, whatever the
  other joints (checked at several random values of them);
* otherwise the sampled configurations with the smallest σ_min are each refined by a golden-section
  search along the joint that changes σ_min most, which crosses the singular hypersurface when J is
  square; a configuration is listed as singular when σ_min ≤ :data:`SINGULAR_TOL` there
  (:func:`armlab.bounds.tolerated`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armlab.analysis.workspace import joint_box, tool_positions
from armlab.bounds import above, tolerated
from armlab.kinematics.differential import default_axes, jacobian, manipulability, sigma_min

if TYPE_CHECKING:
    from armlab.analysis.workspace import Workspace
    from armlab.models.arm import Arm

__all__ = ["SINGULAR_TOL", "add_manipulability", "singular_configurations", "task_sigma"]

#: σ_min up to this (m per rad, or mixed units for six rows) counts as singular.
SINGULAR_TOL = 1e-9
#: Kept configurations whose Jacobian is evaluated.
JACOBIAN_SAMPLES = 20_000
#: Sampled configurations refined into singular ones (arms whose σ_min depends on several joints).
REFINED = 12
_GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


def task_sigma(arm: Arm, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Yoshikawa's manipulability and σ_min of the batch ``q`` (..., n), each ``(...)``."""
    J = jacobian(arm, q)
    return manipulability(J), sigma_min(J)


def _axes(arm: Arm) -> str:
    return {"all": "all (v and ω)", "trans": "translational (v)"}[default_axes(arm.n)]


def add_manipulability(arm: Arm, result: Workspace) -> None:
    """Fill ``result``'s manipulability, σ_min (on its first :data:`JACOBIAN_SAMPLES` kept configurations)
    and singular configurations."""
    q = result.q[:JACOBIAN_SAMPLES]
    result.manipulability, result.sigma_min = task_sigma(arm, q)
    result.singular = singular_configurations(arm, q, result.sigma_min)


def _golden(f: Any, lo: NDArray, hi: NDArray, iterations: int = 80) -> NDArray:
    """Minimisers of the unimodal functions ``f(x)`` (vectorised over a batch) within [lo, hi]."""
    a, b = lo.copy(), hi.copy()
    c, d = b - _GOLDEN * (b - a), a + _GOLDEN * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(iterations):
        left = fc < fd
        b = np.where(left, d, b)
        a = np.where(left, a, c)
        d_new = np.where(left, c, a + _GOLDEN * (b - a))
        c_new = np.where(left, b - _GOLDEN * (b - a), d)
        fd_new = np.where(left, fc, np.nan)
        fc_new = np.where(left, np.nan, fd)
        c, d = c_new, d_new
        need_c, need_d = np.isnan(fc_new), np.isnan(fd_new)
        fc_new[need_c] = f(c)[need_c] if need_c.any() else fc_new[need_c]
        fd_new[need_d] = f(d)[need_d] if need_d.any() else fd_new[need_d]
        fc, fd = fc_new, fd_new
    return (a + b) / 2


def _depends_on(arm: Arm, q: NDArray, sigma: NDArray, rng: np.random.Generator) -> list[int]:
    """The joints σ_min changes with (redrawn one at a time over 200 configurations)."""
    lower, upper = joint_box(arm)
    q, sigma = q[:200], sigma[:200]
    scale = max(float(np.max(sigma)), 1e-300)
    joints = []
    for j in range(arm.n):
        moved = q.copy()
        moved[:, j] = lower[j] + (upper[j] - lower[j]) * rng.random(len(q))
        if above(np.max(np.abs(task_sigma(arm, moved)[1] - sigma)) / scale, 0.0):  # more than round-off
            joints.append(j)
    return joints


def singular_configurations(arm: Arm, q: NDArray[np.float64], sigma: NDArray[np.float64],
                            seed: int = 1) -> dict[str, Any]:
    """The singular configurations of ``arm`` (see the module docstring) from sampled ``q`` and their σ_min.

    Returns ``{"rows", "depends_on", "loci" | "configurations", "tolerance", "min_sigma_sampled"}``;
    ``loci`` lists, for a single joint, its singular values (rad); ``configurations`` lists refined
    singular configurations (rad or m) with their σ_min.
    """
    rng = np.random.default_rng(seed)
    depends = _depends_on(arm, q, sigma, rng)
    out: dict[str, Any] = {"rows": _axes(arm), "depends_on": [arm.joint_names[j] for j in depends],
                           "tolerance": SINGULAR_TOL, "min_sigma_sampled": float(sigma.min())}
    lower, upper = joint_box(arm)
    if len(depends) == 1:
        j = depends[0]
        out["loci"] = _loci(arm, j, q[:4], lower, upper)
        grid = np.linspace(lower[j], upper[j], 721)
        out["_scan"] = np.stack([grid, task_sigma(arm, _moved(np.broadcast_to(q[0], (grid.size, arm.n)), j, grid))[1]],
                                axis=-1)
        on_loci = [_moved(q[:100], j, value) for value in out["loci"]["values"]]
        out["_tool_points"] = tool_positions(arm, np.concatenate(on_loci)) if on_loci else np.zeros((0, 3))
        return out
    if not depends:
        return out | {"configurations": []}
    worst = q[np.argsort(sigma)[:REFINED]]
    step = (upper - lower) / 50
    found = []
    for row in worst:  # the joint that changes σ_min most, searched ±step around the sample
        gradient = [abs(task_sigma(arm, _moved(row[None], j, row[j] + 1e-6))[1][0] - task_sigma(arm, row[None])[1][0])
                    for j in depends]
        j = depends[int(np.argmax(gradient))]
        lo, hi = max(row[j] - step[j], lower[j]), min(row[j] + step[j], upper[j])
        x = _golden(lambda t, r=row, j=j: task_sigma(arm, _moved(np.broadcast_to(r, (t.size, arm.n)), j, t))[1],
                    np.array([lo]), np.array([hi]))[0]
        refined = _moved(row[None], j, x)[0]
        s = float(task_sigma(arm, refined[None])[1][0])
        if tolerated(s, SINGULAR_TOL):
            found.append({"q": refined.tolist(), "sigma_min": s})
    points = tool_positions(arm, np.array([f["q"] for f in found])) if found else np.zeros((0, 3))
    return out | {"configurations": found, "_tool_points": points}


def _moved(q: NDArray, j: int, value: Any) -> NDArray:
    """``q`` with joint ``j`` set to ``value`` (broadcast)."""
    out = np.array(q, dtype=float)
    out[..., j] = value
    return out


def _loci(arm: Arm, j: int, others: NDArray, lower: NDArray, upper: NDArray) -> dict[str, Any]:
    """Every zero of σ_min as joint ``j`` runs over its range, at each configuration of ``others``."""
    grid = np.linspace(lower[j], upper[j], 721)
    found = []
    for row in others:
        sigma = task_sigma(arm, _moved(np.broadcast_to(row, (grid.size, arm.n)), j, grid))[1]
        minima = [k for k in range(grid.size) if sigma[k] <= sigma[max(k - 1, 0)]  # not a bound: local minima
                  and sigma[k] <= sigma[min(k + 1, grid.size - 1)]]  # not a bound: against its neighbours
        lo = grid[[max(k - 1, 0) for k in minima]]
        hi = grid[[min(k + 1, grid.size - 1) for k in minima]]
        x = _golden(lambda t, r=row: task_sigma(arm, _moved(np.broadcast_to(r, (t.size, arm.n)), j, t))[1], lo, hi)
        s = task_sigma(arm, _moved(np.broadcast_to(row, (x.size, arm.n)), j, x))[1]
        found.append(np.sort(x[tolerated(s, SINGULAR_TOL)]))
    values = found[0]
    same = all(f.shape == values.shape and np.allclose(f, values, atol=1e-7) for f in found[1:])
    return {"joint": arm.joint_names[j], "index": j, "values": values.tolist(),
            "unit": "rad" if arm.revolute[j] else "m", "independent_of_other_joints": bool(same)}
