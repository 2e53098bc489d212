"""Transformation matrices of basic movements (paper 000, Hroncová et al., section 7).

The six elementary 4×4 homogeneous matrices of paper 000, eqs. (10)–(13):

* ``T_Z1(a)`` translation along x, ``T_Z2(b)`` along y, ``T_Z3(c)`` along z,
* ``T_Z4(α)`` rotation about x, ``T_Z5(β)`` about y, ``T_Z6(γ)`` about z.

Every function accepts a scalar or an array of any shape ``S`` and returns an array
of shape ``S + (4, 4)``, so a whole time grid or workspace grid is one call.

The RRRR manipulator of Figs. 11/13 is written twice, as the paper does:

* the DH form, eqs. (21)–(34): ``T01 = T_Z3(L1) T_Z6(q1) T_Z4(π/2)``,
  ``T_{i,i+1} = T_Z6(q) T_Z1(L)``;
* the form of Fig. 20, eqs. (36)–(47): ``T01 = T_Z2(L1) T_Z5(q1)``, the rest the same —
  the same arm described in a base frame whose y axis points up.

Both give ``r_0M = T01 T12 T23 T34 r_4M`` with ``r_4M = [0 0 0 1]ᵀ`` (eqs. 17–20, 35).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "DH_TO_YUP",
    "T_Z1",
    "T_Z2",
    "T_Z3",
    "T_Z4",
    "T_Z5",
    "T_Z6",
    "rrrr_dh_chain",
    "rrrr_point_M",
    "rrrr_yup_chain",
]


def _translation(value: ArrayLike, axis: int) -> NDArray[np.float64]:
    v = np.asarray(value, dtype=float)
    T = np.broadcast_to(np.eye(4), v.shape + (4, 4)).copy()
    T[..., axis, 3] = v
    return T


def _rotation(angle: ArrayLike, axis: int) -> NDArray[np.float64]:
    a = np.asarray(angle, dtype=float)
    c, s = np.cos(a), np.sin(a)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    T = np.broadcast_to(np.eye(4), a.shape + (4, 4)).copy()
    T[..., i, i] = c
    T[..., i, j] = -s
    T[..., j, i] = s
    T[..., j, j] = c
    return T


def T_Z1(a: ArrayLike) -> NDArray[np.float64]:
    """Translation by ``a`` along x (eq. 12)."""
    return _translation(a, 0)


def T_Z2(b: ArrayLike) -> NDArray[np.float64]:
    """Translation by ``b`` along y."""
    return _translation(b, 1)


def T_Z3(c: ArrayLike) -> NDArray[np.float64]:
    """Translation by ``c`` along z (eq. 10)."""
    return _translation(c, 2)


def T_Z4(alpha: ArrayLike) -> NDArray[np.float64]:
    """Rotation by ``alpha`` about x (eq. 13)."""
    return _rotation(alpha, 0)


def T_Z5(beta: ArrayLike) -> NDArray[np.float64]:
    """Rotation by ``beta`` about y."""
    return _rotation(beta, 1)


def T_Z6(gamma: ArrayLike) -> NDArray[np.float64]:
    """Rotation by ``gamma`` about z (eq. 11)."""
    return _rotation(gamma, 2)


def _rrrr_chain(T01: NDArray, q: NDArray, L: tuple[float, float, float, float]) -> list[NDArray]:
    _, L2, L3, L4 = L
    T12 = T_Z6(q[..., 1]) @ T_Z1(L2)  # eq. (26)
    T23 = T_Z6(q[..., 2]) @ T_Z1(L3)  # eq. (29)
    T34 = T_Z6(q[..., 3]) @ T_Z1(L4)  # eq. (32)
    return [T01, T12, T23, T34]


def rrrr_dh_chain(q: ArrayLike, L: tuple[float, float, float, float]) -> list[NDArray]:
    """``[T01, T12, T23, T34]`` of the RRRR arm in its DH form, eqs. (21)–(34).

    ``q`` has shape ``(..., 4)``; ``L = (L1, L2, L3, L4)``.
    """
    q = np.asarray(q, dtype=float)
    T01 = T_Z3(L[0]) @ T_Z6(q[..., 0]) @ T_Z4(np.pi / 2)  # eq. (21)
    return _rrrr_chain(T01, q, L)


def rrrr_yup_chain(q: ArrayLike, L: tuple[float, float, float, float]) -> list[NDArray]:
    """``[T01, T12, T23, T34]`` of the RRRR arm in the y-up form of Fig. 20, eqs. (36)–(47)."""
    q = np.asarray(q, dtype=float)
    T01 = T_Z2(L[0]) @ T_Z5(q[..., 0])  # eq. (36)
    return _rrrr_chain(T01, q, L)


def rrrr_point_M(chain: list[NDArray]) -> NDArray[np.float64]:
    """``r_0M = T01 T12 T23 T34 r_4M`` (eqs. 19, 35) as an array of shape ``(..., 3)``."""
    T04 = chain[0] @ chain[1] @ chain[2] @ chain[3]  # eq. (18)
    return T04[..., :3, 3]


#: The base-frame change between the two RRRR forms: ``T_yup = DH_TO_YUP @ T_dh``
#: (x equal, y_Fig.20 = z_DH, z_Fig.20 = −y_DH), i.e. a rotation by −π/2 about x.
DH_TO_YUP = T_Z4(-np.pi / 2)
