"""Shape handling shared by the kinematics modules: one configuration or a batch, and chains of frames.

The batched computations here store a batch *last*: a block of B frames is an array ``(3, 4, B)`` (rows,
columns of the affine part [R | p], then samples), a block of vectors ``(3, B)``, so every elementwise
operation runs over long contiguous rows. A long batch is computed a block of :data:`BLOCK` samples at a
time in working arrays that stay in the processor's cache, and the results are written into arrays whose
batch axis is last in memory (returned as views with the batch axes first, as everywhere in armlab).

Each link of a chain costs one matrix product by a constant (:func:`times_constant`) and the joint's own
motion about or along z, which only mixes two columns (:func:`turn_z`) or shifts one (:func:`slide_z`).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.limits import real_array

__all__ = ["BLOCK", "ZStep", "as_batch", "blocks", "chain_blocks", "chain_frames", "chain_points", "cos_sin", "cross",
           "slide_z", "times_constant", "turn_z"]

#: Samples per block (see the module docstring).
BLOCK = 4096


def as_batch(q: ArrayLike, n: int, name: str = "q") -> NDArray[np.float64]:
    """``q`` as a float array of shape ``(n,)`` or ``(..., n)``, checked to be finite.

    Raises ``ValueError`` naming the bad value when the last axis is not ``n`` long or a
    value is NaN or infinite.
    """
    a = real_array(q, name)
    if a.ndim == 0 or a.shape[-1] != n:
        raise ValueError(f"{name} has shape {a.shape}; expected {n} joint values (shape (..., {n}))")
    if not np.isfinite(a).all():
        bad = ~np.isfinite(a)
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ValueError(f"{name}{list(index)} = {a[index]} is not a finite number")
    return a


def blocks(count: int) -> list[slice]:
    """Slices of at most :data:`BLOCK` samples covering ``range(count)``."""
    return [slice(start, min(start + BLOCK, count)) for start in range(0, count, BLOCK)]


def cos_sin(angle: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(cos θ, sin θ) from one tangent of the half angle, t = tan(θ/2): cos θ = (1 − t²)/(1 + t²), sin θ = 2t/(1 + t²).

    One transcendental call instead of two (numpy's float64 cos and sin are not vectorised); exact to a few
    units in the last place, also near θ = ±π where t grows without bound.
    """
    t = np.tan(0.5 * angle)
    t2 = t * t
    inverse = 1.0 / (1.0 + t2)
    return (1.0 - t2) * inverse, 2.0 * t * inverse


def times_constant(C: NDArray[np.float64], T: NDArray[np.float64], out: NDArray | None = None) -> NDArray[np.float64]:
    """``T·C`` for a block of frames ``T`` ``(r, c, B)`` and a constant ``C`` ``(c, k)``: ``(r, k, B)``.

    Row by row, (T·C)_r = Cᵀ·T_r: one matrix product per row over the whole block.
    """
    return np.matmul(C.T, T, out=out)


def turn_z(T: NDArray[np.float64], c: NDArray[np.float64], s: NDArray[np.float64]) -> None:
    """``T ← T·R_z(θ)`` in place for a block ``(3, 3 or 4, B)``; ``c, s = cos θ, sin θ`` of shape ``(B,)``.

    Only the first two columns change: ``x' = c x + s y``, ``y' = c y − s x``.
    """
    x, y = T[:, 0], T[:, 1]
    new_x = x * c
    new_x += y * s
    y *= c
    x *= s
    y -= x
    x[...] = new_x


def slide_z(T: NDArray[np.float64], d: NDArray[np.float64]) -> None:
    """``T ← T·Trans_z(d)`` in place for a block ``(3, 4, B)``: the origin moves by ``d`` along the frame's z."""
    T[:, 3] += d * T[:, 2]


def cross(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """a × b for vectors stored as ``(..., 3, B)`` (components second to last; either may be ``(3, 1)``)."""
    a0, a1, a2 = a[..., 0, :], a[..., 1, :], a[..., 2, :]
    b0, b1, b2 = b[..., 0, :], b[..., 1, :], b[..., 2, :]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-2)


@dataclass(frozen=True)
class ZStep:
    """One link of a chain: ``T_{i−1,i}(q_i) = pre · J_z(q_i) · post``.

    ``J_z`` is a rotation about z (``revolute``) or a translation along z by ``q_i``; ``pre`` and ``post``
    are constant 4×4 transforms, ``None`` for the identity.
    """

    pre: NDArray[np.float64] | None
    revolute: bool
    post: NDArray[np.float64] | None = None


def chain_blocks(
    q: NDArray[np.float64], steps: Sequence[ZStep], tail: NDArray[np.float64] | None = None
) -> Iterator[tuple[slice, NDArray[np.float64]]]:
    """The frames of :func:`chain_frames` a block of samples at a time: ``(block, frames)``.

    ``block`` slices the batch flattened to ``(N, n)``; ``frames`` ``(k, 3, 4, B)`` holds the affine
    parts [R | p] of the k frames (base first) of those B samples. It is a working array, overwritten
    by the next block.
    """
    flat = q.reshape(-1, q.shape[-1])
    joints = np.ascontiguousarray(flat.T)  # (n, N): one joint's values contiguous
    work = np.empty((len(steps) + 1 + (tail is not None), 3, 4, min(flat.shape[0], BLOCK)))
    work[0] = np.eye(4)[:3, :, None]
    for block in blocks(flat.shape[0]):
        frames = work[..., : block.stop - block.start]
        for i, step in enumerate(steps):
            T = frames[i + 1]
            if step.pre is None:
                T[...] = frames[i]
            else:
                times_constant(step.pre, frames[i], out=T)
            qi = joints[i, block]
            if step.revolute:
                turn_z(T, *cos_sin(qi))
            else:
                slide_z(T, qi)
            if step.post is not None:
                T[...] = times_constant(step.post, T)
        if tail is not None:
            times_constant(tail, frames[-2], out=frames[-1])
        yield block, frames


def chain_frames(
    q: NDArray[np.float64], steps: Sequence[ZStep], tail: NDArray[np.float64] | None = None
) -> NDArray[np.float64]:
    """T_{0,i} = T_{0,1}·T_{1,2} ⋯ T_{i−1,i} for i = 0 … n (the base first), then ``T_{0,n}·tail`` if given.

    ``q`` has shape ``(..., n)``, one value per step; the result has shape ``(..., n + 1 (+ 1), 4, 4)``
    (a view of an array stored batch-last).
    """
    k = len(steps) + 1 + (tail is not None)
    out = np.empty((k, 4, 4, int(np.prod(q.shape[:-1]))))
    out[:, 3] = np.array([0.0, 0.0, 0.0, 1.0])[:, None]
    for block, frames in chain_blocks(q, steps, tail):
        out[:, :3, :, block] = frames
    return np.moveaxis(out, -1, 0).reshape(q.shape[:-1] + (k, 4, 4))


def chain_points(
    q: NDArray[np.float64], steps: Sequence[ZStep], points: dict[str, tuple[int, ArrayLike]],
    tail: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.float64], dict[str, NDArray[np.float64]]]:
    """The last frame of :func:`chain_frames` ``(..., 4, 4)`` and named points ``(..., 3)``, without the others.

    ``points``: name → (frame index i, xyz in frame i); the point is T_{0,i}·xyz. Each block's frames are
    computed once and only these results are written out (stored batch-last, returned as views).
    """
    count = int(np.prod(q.shape[:-1]))
    last = np.empty((4, 4, count))
    last[3] = np.array([0.0, 0.0, 0.0, 1.0])[:, None]
    out = {name: np.empty((3, count)) for name in points}
    where = {name: (index, np.asarray(xyz, dtype=float)) for name, (index, xyz) in points.items()}
    for block, frames in chain_blocks(q, steps, tail):
        last[:3, :, block] = frames[-1]
        for name, (index, xyz) in where.items():
            point = out[name][:, block]
            point[...] = frames[index, :, 3]
            for j in np.flatnonzero(xyz):
                point += xyz[j] * frames[index, :, j]
    shape = q.shape[:-1]
    named = {name: a.T.reshape(shape + (3,)) for name, a in out.items()}
    return np.moveaxis(last, -1, 0).reshape(shape + (4, 4)), named
