"""The iterative algorithm of paper 003 (Schonstein & Panc, 2017), eqs. (24)–(33).

For a chain given by its matrix of nominal geometry (:class:`LocatingTable`), starting
from a base at rest (``⁰ω₀ = ⁰ω̇₀ = ⁰v₀ = ⁰v̇₀ = 0``), for i = 1 … n (and the tool,
i = n+1, a joint with q̇ = q̈ = 0)::

    ω_i = ω_{i−1} + Δ_i q̇_i k_i                                          (24)
    v_i = v_{i−1} + ω_{i−1} × p_{i,i−1} + (1 − Δ_i) q̇_i k_i              (25)
    ω̇_i = ω̇_{i−1} + Δ_i (ω_{i−1} × q̇_i k_i + q̈_i k_i)                    (26)
    v̇_i = v̇_{i−1} + ω̇_{i−1} × p_{i,i−1} + ω_{i−1} × (ω_{i−1} × p_{i,i−1})
          + (1 − Δ_i)(2 ω_i × q̇_i k_i + q̈_i k_i)                          (27)

all projected on the base frame {0}, where ``k_i = ⁰_i[R]·ⁱk_i`` and ``p_{i,i−1}`` is the
vector from the origin of {i−1} to the origin of {i}. The same quantities projected on
the link's own frame {i} are ``ⁱx_i = ⁰_i[R]ᵀ·⁰x_i`` (eqs. 28–31). ``v_i`` and ``v̇_i`` are
the velocity and acceleration of the origin of frame {i}. The end effector's
``Ẋ = [v; ω]`` and ``Ẍ = [v̇; ω̇]`` are eqs. (32)–(33).

Every array has a leading batch shape: pass ``q, qd, qdd`` of shape ``(..., n)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import as_batch
from armlab.kinematics.locating import LocatingTable

__all__ = ["LinkMotion", "iterative_kinematics"]


@dataclass(frozen=True)
class LinkMotion:
    """ω, v, ω̇, v̇ of links 1 … n and the tool (index n), each of shape ``(..., n+1, 3)``.

    ``*_0`` are projected on the base frame {0} (eqs. 24–27), ``*_i`` on the link's own
    frame {i} (eqs. 28–31).
    """

    w_0: NDArray[np.float64]
    v_0: NDArray[np.float64]
    wd_0: NDArray[np.float64]
    vd_0: NDArray[np.float64]
    w_i: NDArray[np.float64]
    v_i: NDArray[np.float64]
    wd_i: NDArray[np.float64]
    vd_i: NDArray[np.float64]

    @property
    def Xd(self) -> NDArray[np.float64]:
        """End-effector velocity ``[v; ω]``, eq. (32), shape ``(..., 6)``."""
        return np.concatenate([self.v_0[..., -1, :], self.w_0[..., -1, :]], axis=-1)

    @property
    def Xdd(self) -> NDArray[np.float64]:
        """End-effector acceleration ``[v̇; ω̇]``, eq. (33), shape ``(..., 6)``."""
        return np.concatenate([self.vd_0[..., -1, :], self.wd_0[..., -1, :]], axis=-1)


def iterative_kinematics(
    table: LocatingTable, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike
) -> LinkMotion:
    """Run eqs. (24)–(31) over a batch of configurations, rates and accelerations."""
    n = table.n
    q = as_batch(q, n, "q")
    qd = as_batch(qd, n, "qd")
    qdd = as_batch(qdd, n, "qdd")
    shape = np.broadcast_shapes(q.shape, qd.shape, qdd.shape)[:-1]
    frames = np.broadcast_to(table.frames(q), shape + (n + 2, 4, 4))
    R0 = frames[..., 1:, :3, :3]  # ⁰_i[R], i = 1 … n+1
    origins = frames[..., :, :3, 3]
    zero = np.zeros(shape + (3,))
    w, v, wd, vd = zero, zero, zero, zero
    out = {key: np.empty(shape + (n + 1, 3)) for key in ("w", "v", "wd", "vd")}
    for i in range(n + 1):
        p = origins[..., i + 1, :] - origins[..., i, :]  # p_{i,i−1} in {0}, eq. (7)
        if i < n:
            row = table.rows[i]
            delta = row.delta
            k = R0[..., i, :, :] @ np.asarray(row.k)  # ⁰k_i = ⁰_i[R]·ⁱk_i
            k_rate = qd[..., i, None] * k
            k_acc = qdd[..., i, None] * k
        else:  # the tool row T_{n+1,n}: rigidly attached
            delta, k_rate, k_acc = 1.0, zero, zero
        w_new = w + delta * k_rate  # (24)
        v_new = v + np.cross(w, p) + (1 - delta) * k_rate  # (25)
        wd_new = wd + delta * (np.cross(w, k_rate) + k_acc)  # (26)
        vd_new = (
            vd
            + np.cross(wd, p)
            + np.cross(w, np.cross(w, p))
            + (1 - delta) * (2 * np.cross(w_new, k_rate) + k_acc)
        )  # (27)
        w, v, wd, vd = w_new, v_new, wd_new, vd_new
        for key, value in (("w", w), ("v", v), ("wd", wd), ("vd", vd)):
            out[key][..., i, :] = value
    # (28)–(31): ⁱx_i = ⁰_i[R]ᵀ·⁰x_i, the four vectors of every link projected in one batched product
    projected = np.swapaxes(R0, -1, -2) @ np.stack(list(out.values()), axis=-1)
    own = {key: projected[..., j] for j, key in enumerate(out)}
    return LinkMotion(
        w_0=out["w"], v_0=out["v"], wd_0=out["wd"], vd_0=out["vd"],
        w_i=own["w"], v_i=own["v"], wd_i=own["wd"], vd_i=own["vd"],
    )
