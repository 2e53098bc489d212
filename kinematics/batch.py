"""Shape handling shared by the kinematics modules: one configuration or a batch."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["as_batch"]


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
