"""Batched signed distances of capsules (spheres are capsules of no length) to capsules and floors, with numpy.

The same numbers as Drake's ``SceneGraph`` queries (:mod:`armlab.collision.model` checks them against each
other), for whole batches at once: what the clearance along a motion and the collision-free workspace need.
A capsule is a segment P0–P1 (m, world) and a radius r (m); its signed distance to another is the distance
between the two segments minus both radii, negative when they overlap (then −distance is the penetration
depth). The closest points lie on the two surfaces, along the line joining the segments' closest points.
A capsule and a box: the segment's distance to the box less the radius, exact while the segment stays outside
the box (a convex set grown by r: every distance shrinks by r); where the segment enters the box the depth is
not this, and the caller asks Drake (:func:`capsule_box` says where).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["capsule_box", "capsule_capsule", "capsule_floor", "segment_box", "segment_segment"]

#: Squared lengths below this (m²) make a segment a point.
_EPS = 1e-24


def _dot(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.einsum("...k,...k->...", a, b)


def segment_segment(
    P0: NDArray[np.float64], P1: NDArray[np.float64], Q0: NDArray[np.float64], Q1: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The closest points of segments P0–P1 and Q0–Q1, each ``(..., 3)`` (m): ``(C_P, C_Q)``, each ``(..., 3)``.

    Ericson, Real-Time Collision Detection, §5.1.9: the parameters s, t ∈ [0, 1] of the unconstrained
    closest points, clamped to the segments one after the other; a segment of no length is its point.
    """
    d1, d2, r = P1 - P0, Q1 - Q0, P0 - Q0
    a, e, f = _dot(d1, d1), _dot(d2, d2), _dot(d2, r)
    c, b = _dot(d1, r), _dot(d1, d2)
    point_p, point_q = a <= _EPS, e <= _EPS
    safe_a, safe_e = np.where(point_p, 1.0, a), np.where(point_q, 1.0, e)
    denom = a * e - b * b
    parallel = denom <= 1e-12 * np.maximum(a * e, _EPS)
    s = np.where(parallel, 0.0, np.clip((b * f - c * e) / np.where(parallel, 1.0, denom), 0.0, 1.0))
    t = (b * s + f) / safe_e
    s = np.where(t < 0, np.clip(-c / safe_a, 0.0, 1.0), np.where(t > 1, np.clip((b - c) / safe_a, 0.0, 1.0), s))
    t = np.clip(t, 0.0, 1.0)
    # one or both segments are points
    s = np.where(point_p, 0.0, np.where(point_q, np.clip(-c / safe_a, 0.0, 1.0), s))
    t = np.where(point_q, 0.0, np.where(point_p, np.clip(f / safe_e, 0.0, 1.0), t))
    return P0 + s[..., None] * d1, Q0 + t[..., None] * d2


def capsule_capsule(
    P0: NDArray[np.float64], P1: NDArray[np.float64], rP: NDArray[np.float64] | float,
    Q0: NDArray[np.float64], Q1: NDArray[np.float64], rQ: NDArray[np.float64] | float,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Signed distance (m, ``(...)``) of capsules (P0–P1, rP) and (Q0–Q1, rQ) and the closest points on their
    surfaces (m, ``(..., 3)`` each, world); where the segments meet, the points are the segments' common point."""
    CP, CQ = segment_segment(P0, P1, Q0, Q1)
    gap = CQ - CP
    length = np.sqrt(_dot(gap, gap))
    unit = gap / np.where(length > 0, length, 1.0)[..., None]
    rP, rQ = np.asarray(rP, dtype=float), np.asarray(rQ, dtype=float)
    return length - rP - rQ, CP + rP[..., None] * unit, CQ - rQ[..., None] * unit


def capsule_floor(
    P0: NDArray[np.float64], P1: NDArray[np.float64], r: NDArray[np.float64] | float,
    point: NDArray[np.float64], normal: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Signed distance (m) of capsule (P0–P1, r) to the floor through ``point`` with outward unit ``normal``
    (everything on the other side solid), and the closest points on the capsule and on the floor (m, world)."""
    h0, h1 = _dot(P0 - point, normal), _dot(P1 - point, normal)
    low = np.where((h1 < h0)[..., None], P1, P0)
    height = np.minimum(h0, h1)
    r = np.asarray(r, dtype=float)
    return height - r, low - r[..., None] * normal, low - height[..., None] * normal


def segment_box(
    P0: NDArray[np.float64], P1: NDArray[np.float64], half: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The closest points of segment P0–P1 (``(..., 3)``, m, in the box's frame) and the box of half edges
    ``half`` (``(..., 3)``, m, centred at the origin): ``(C_S, C_B)``; equal where the segment meets the box.

    The squared distance of the segment's point P(s) to the box, f(s) = Σ_k (x_k − clamp(x_k, ±h_k))², is convex
    and quadratic between the s where P(s) crosses a face plane, so its slope f'(s)/2 = Σ_k (x_k − clamp(x_k)) d_k
    is nondecreasing and linear between those knots: the least s is where the slope crosses zero, interpolated
    between the last knot where it is ≤ 0 and the first where it is > 0 (s = 0 or 1 where it does not cross).
    """
    d = P1 - P0
    with np.errstate(divide="ignore", invalid="ignore"):
        cross = np.concatenate([(-half - P0) / d, (half - P0) / d], axis=-1)  # (..., 6): where P(s) crosses a plane
    ends = P0.shape[:-1] + (1,)
    knots = np.concatenate([np.where(np.isfinite(cross), np.clip(cross, 0.0, 1.0), 0.0), np.zeros(ends),
                            np.ones(ends)], axis=-1)  # (..., 8), unsorted
    x = P0[..., None, :] + knots[..., None] * d[..., None, :]  # (..., 8, 3)
    slope = np.einsum("...jk,...k->...j", x - np.clip(x, -half[..., None, :], half[..., None, :]), d)
    rising = slope > 0
    s_a, g_a = (np.where(rising, -np.inf, v).max(axis=-1) for v in (knots, slope))  # the last knot with slope ≤ 0
    s_b, g_b = (np.where(rising, v, np.inf).min(axis=-1) for v in (knots, slope))  # the first with slope > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(np.isinf(s_a), 0.0, np.where(np.isinf(s_b), 1.0, s_a - g_a * (s_b - s_a) / (g_b - g_a)))
    point = P0 + s[..., None] * d
    return point, np.clip(point, -half, half)


def capsule_box(
    P0: NDArray[np.float64], P1: NDArray[np.float64], r: NDArray[np.float64] | float,
    X: NDArray[np.float64], half: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """Signed distance (m) of capsule (P0–P1, r; world) to the box of pose ``X`` (``(..., 4, 4)``, world) and half
    edges ``half`` (m), the closest points on the capsule and the box (m, world), and where the capsule's axis
    enters the box (``(...)`` bool: there the distance is not exact and is to be asked of Drake)."""
    R, c = X[..., :3, :3], X[..., :3, 3]
    to_box = np.swapaxes(R, -1, -2)
    CS, CB = segment_box(np.einsum("...ij,...j->...i", to_box, P0 - c),
                         np.einsum("...ij,...j->...i", to_box, P1 - c), half)
    CS, CB = np.einsum("...ij,...j->...i", R, CS) + c, np.einsum("...ij,...j->...i", R, CB) + c
    gap = CB - CS
    length = np.sqrt(_dot(gap, gap))
    unit = gap / np.where(length > 0, length, 1.0)[..., None]
    r = np.asarray(r, dtype=float)
    return length - r, CS + r[..., None] * unit, CB, length <= 1e-12
