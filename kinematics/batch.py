"""Shape handling shared by the kinematics modules: one configuration or a batch, and chains of frames."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["as_batch", "chain_frames"]


def as_batch(q: ArrayLike, n: int, name: str = "q") -> NDArray[np.float64]:
    """``q`` as a float array of shape ``(n,)`` or ``(..., n)``, checked to be finite.

    Raises ``ValueError`` naming the bad value when the last axis is not ``n`` long or a
    value is NaN or infinite.
    """
    a = np.asarray(q, dtype=float)
    if a.ndim == 0 or a.shape[-1] != n:
        raise ValueError(f"{name} has shape {a.shape}; expected {n} joint values (shape (..., {n}))")
    bad = ~np.isfinite(a)
    if bad.any():
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ValueError(f"{name}{list(index)} = {a[index]} is not a finite number")
    return a


def chain_frames(links: Sequence[NDArray[np.float64]], shape: tuple[int, ...]) -> NDArray[np.float64]:
    """T_{0,i} = T_{0,1}·T_{1,2} ⋯ T_{i−1,i} for i = 0 … k (the base first), shape ``shape + (k + 1, 4, 4)``.

    ``links`` are the k transforms T_{i−1,i}, each ``(4, 4)`` or ``shape + (4, 4)``. Each frame is
    computed into its own contiguous block (one batched matrix product per link, no copies) and the
    result is a view with the frame axis third from last.
    """
    out = np.empty((len(links) + 1, *shape, 4, 4))
    out[0] = np.eye(4)
    for i, T in enumerate(links):
        np.matmul(out[i], T, out=out[i + 1])
    return np.moveaxis(out, 0, -3)
