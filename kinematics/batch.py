"""Shape handling shared by the kinematics modules: one configuration or a batch, and chains of frames.

A batch of frames is an array ``(..., 4, 4)`` (or rotations ``(..., 3, 3)``). The chain of a serial arm is
computed without any Python loop over samples and without batched 4×4 products: each link costs one
matrix product by a constant (one BLAS call over the whole batch, :func:`times_constant`) and the joint's
own motion about or along z, which only mixes two columns (:func:`turn_z`) or shifts one (:func:`slide_z`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["ZStep", "as_batch", "chain_frames", "slide_z", "times_constant", "turn_z"]


def as_batch(q: ArrayLike, n: int, name: str = "q") -> NDArray[np.float64]:
    """``q`` as a float array of shape ``(n,)`` or ``(..., n)``, checked to be finite.

    Raises ``ValueError`` naming the bad value when the last axis is not ``n`` long or a
    value is NaN or infinite.
    """
    a = np.asarray(q, dtype=float)
    if a.ndim == 0 or a.shape[-1] != n:
        raise ValueError(f"{name} has shape {a.shape}; expected {n} joint values (shape (..., {n}))")
    if not np.isfinite(a).all():
        bad = ~np.isfinite(a)
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ValueError(f"{name}{list(index)} = {a[index]} is not a finite number")
    return a


def times_constant(A: NDArray[np.float64], C: NDArray[np.float64]) -> NDArray[np.float64]:
    """``A @ C`` for a batch ``A`` of shape ``(..., r, c)`` and one constant ``C`` ``(c, k)``: one matrix product."""
    A = np.ascontiguousarray(A)
    return (A.reshape(-1, A.shape[-1]) @ C).reshape(A.shape[:-1] + (C.shape[-1],))


def turn_z(T: NDArray[np.float64], c: NDArray[np.float64], s: NDArray[np.float64]) -> None:
    """``T ← T·R_z(θ)`` in place for frames ``(..., 4, 4)`` or rotations ``(..., 3, 3)``; ``c, s = cos θ, sin θ``.

    Only the first two columns change: ``x' = c x + s y``, ``y' = c y − s x``.
    """
    x, y = T[..., :3, 0], T[..., :3, 1]
    c, s = c[..., None], s[..., None]
    new_x = x * c
    new_x += y * s
    y *= c
    x *= s
    y -= x
    x[...] = new_x


def slide_z(T: NDArray[np.float64], d: NDArray[np.float64]) -> None:
    """``T ← T·Trans_z(d)`` in place for frames ``(..., 4, 4)``: the origin moves by ``d`` along the frame's z."""
    T[..., :3, 3] += d[..., None] * T[..., :3, 2]


@dataclass(frozen=True)
class ZStep:
    """One link of a chain: ``T_{i−1,i}(q_i) = pre · J_z(q_i) · post``.

    ``J_z`` is a rotation about z (``revolute``) or a translation along z by ``q_i``; ``pre`` and ``post``
    are constant 4×4 transforms, ``None`` for the identity.
    """

    pre: NDArray[np.float64] | None
    revolute: bool
    post: NDArray[np.float64] | None = None


def chain_frames(
    q: NDArray[np.float64], steps: Sequence[ZStep], tail: NDArray[np.float64] | None = None
) -> NDArray[np.float64]:
    """T_{0,i} = T_{0,1}·T_{1,2} ⋯ T_{i−1,i} for i = 0 … n (the base first), then ``T_{0,n}·tail`` if given.

    ``q`` has shape ``(..., n)``, one value per step; the result has shape ``(..., n + 1 (+ 1), 4, 4)``.
    Each frame is computed into its own contiguous block over the whole batch (a product by a constant,
    the joint's motion in place) and the result is a view with the frame axis third from last.
    """
    shape = q.shape[:-1]
    flat = q.reshape(-1, q.shape[-1])
    out = np.empty((len(steps) + 1 + (tail is not None), flat.shape[0], 4, 4))
    out[0] = np.eye(4)
    for i, step in enumerate(steps):
        T = out[i + 1]
        if step.pre is None:
            T[...] = out[i]
        else:
            np.matmul(out[i].reshape(-1, 4), step.pre, out=T.reshape(-1, 4))
        if step.revolute:
            turn_z(T, np.cos(flat[:, i]), np.sin(flat[:, i]))
        else:
            slide_z(T, flat[:, i])
        if step.post is not None:
            T[...] = times_constant(T, step.post)
    if tail is not None:
        np.matmul(out[-2].reshape(-1, 4), tail, out=out[-1].reshape(-1, 4))
    return np.moveaxis(out, 0, -3).reshape(shape + out.shape[:1] + (4, 4))
