"""What a repeated cycle does over time: first-order lags (a winding's temperature, a drive's I²t) in their
periodic steady state, and the energy a drive's DC link takes back.

Inputs are time functions on a cycle's knots (:class:`~armlab.sizing.duty.CycleSamples`: piecewise linear
between knot times ``t`` ``(K,)``, from 0 to the cycle's duration T; a zero-length step where a value jumps).

**A lag** y' = λ·y + u(t) (λ < 0, 1/s) is integrated exactly for such a u: over an interval of h s from y_k,

    y_{k+1} = e^{λh}·y_k + φ₀·u_k + φ₁·u_{k+1},  φ₁ = h·(e^x − 1 − x)/x²,  φ₀ = h·(x·e^x − e^x + 1)/x²,  x = λh

(the integrals of e^{λ(h−s)} against the two hat functions; their series for |x| < 10⁻³). The recursion is
solved without a loop over the knots: y_k = e^{λ(t_k − t_s)}·(y_s + Σ_{s≤j<k} b_j·e^{−λ(t_{j+1} − t_s)}) in
blocks of at most :data:`BLOCK` time constants (so no exponential overflows). The cycle repeated forever has
the **periodic** solution whose start is y_0* = y_T(0)/(1 − e^{λT}) (y_T(0): the end of one cycle from 0); from
0 ("cold") the start of cycle m is (1 − e^{mλT})·y_0*.

**The DC link's energy** (:func:`bus_energy`): with p(t) the power a drive draws from its bus (W, negative
when the motor brakes and returns energy), the energy stored above the nominal voltage rises by −∫p while p < 0
and is drawn first when p > 0 (a rectifier supply returns nothing and takes over at the nominal voltage): the
one-sided reflected walk E = S − min(0, min S) of S(t) = −∫₀ᵗ p, over two cycles (the second periodic), each
interval split where p changes sign (:func:`energy_steps`: S is then monotone between the points, so its extremes
are among them, exactly). With a capacity E_cap (the capacitors' ½C(V_max² − V_nom²)) whatever would lift E above
it goes to the braking resistor (:func:`resistor_energy`: the two-sided walk, part by part).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["BLOCK", "bus_energy", "energy_steps", "lag", "lag_periodic", "lag_weights", "resistor_energy"]

#: A block of the lag's solution spans at most this many of its fastest time constants (e^BLOCK < 1e217).
BLOCK = 500.0


def lag_weights(x: NDArray[np.float64], h: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """φ₀, φ₁ of the module docstring for x = λh and h (broadcast together)."""
    small = np.abs(x) < 1e-3
    xs = np.where(small, 1.0, x)  # no division by 0 where the series is used
    e = np.exp(xs)
    with np.errstate(over="ignore", invalid="ignore"):
        f1 = np.where(small, 0.5 + x / 6 + x**2 / 24 + x**3 / 120, (np.expm1(xs) - xs) / xs**2)
        f0 = np.where(small, 0.5 + x / 3 + x**2 / 8 + x**3 / 30, (xs * e - np.expm1(xs)) / xs**2)
    return h * f0, h * f1


def lag(rate: NDArray[np.float64], u: NDArray[np.float64], t: NDArray[np.float64],
        start: NDArray[np.float64] | float = 0.0) -> NDArray[np.float64]:
    """y at the knots ``(..., K)`` of y' = λ·y + u from y(t_0) = ``start`` ``(...)``: ``rate`` λ (< 0, 1/s) and
    ``u`` ``(..., K)`` the input at the knots ``t`` ``(K,)`` (s, non-decreasing), broadcast together (a rate per
    candidate ``(C,)`` against inputs ``(L, C, K)``: the interval weights are computed once per rate)."""
    lam = np.asarray(rate, dtype=float)[..., None]
    if not np.all(lam < 0):
        raise ValueError(f"a lag's rate must be negative (a decay, 1/s); got {np.max(lam):g}")
    steps, which = np.unique(np.diff(t), return_inverse=True)  # a cycle has few interval lengths
    phi0, phi1 = (phi[..., which] for phi in lag_weights(lam * steps, steps))
    b = u[..., :-1] * phi0 + u[..., 1:] * phi1  # (..., K − 1): what each interval adds
    y = np.empty(np.broadcast_shapes(lam.shape[:-1] + (t.size,), u.shape))
    y[..., 0] = start
    fastest = float(-lam.min())
    s = 0
    while s < t.size - 1:
        e = int(np.searchsorted(t, t[s] + BLOCK / fastest, side="right"))  # knots s … e − 1 in this block
        e = min(max(e, s + 2), t.size)
        dt = t[s:e] - t[s]  # (n,)
        grow = np.exp(-lam * dt[1:])  # e^{−λ(t_{j+1} − t_s)}, j = s … e − 2
        total = np.cumsum(b[..., s:e - 1] * grow, axis=-1)
        y[..., s + 1:e] = np.exp(lam * dt[1:]) * (y[..., s:s + 1] + total)
        s = e - 1
    return y


def lag_periodic(rate: NDArray[np.float64], u: NDArray[np.float64], t: NDArray[np.float64]
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The periodic solution at the knots ``(..., K)`` of :func:`lag` (the cycle repeated forever, y(T) = y(0))
    and its start y_0* ``(...)``."""
    lam = np.asarray(rate, dtype=float)
    cold = lag(lam, u, t)
    start = cold[..., -1] / -np.expm1(lam * (t[-1] - t[0]))
    return cold + np.exp(lam[..., None] * (t - t[0])) * start[..., None], start


def energy_steps(power: NDArray[np.float64], t: NDArray[np.float64]) -> NDArray[np.float64]:
    """What the DC link gains, −∫p (J), over each interval's two parts ``(..., 2(K − 1))``, in time order: an interval
    where the piecewise-linear ``power`` ``(..., K)`` (W) changes sign is split at its zero (s = h·p_k/(p_k − p_k+1)),
    so the stored energy is monotone within each part (its extremes are at the parts' ends); else all of it in the
    first part."""
    h = np.diff(t)
    p0, p1 = power[..., :-1], power[..., 1:]
    turns = p0 * p1 < 0
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(turns, h * p0 / np.where(turns, p0 - p1, 1.0), h)
    first = np.where(turns, -p0 * s / 2, -(p0 + p1) * h / 2)
    second = np.where(turns, -p1 * (h - s) / 2, 0.0)
    return np.stack([first, second], axis=-1).reshape(power.shape[:-1] + (2 * h.size,))


def bus_energy(power: NDArray[np.float64], t: NDArray[np.float64]) -> NDArray[np.float64]:
    """The largest energy (J) the DC link stores above its nominal voltage over the periodic cycle ``(...)``, for
    the power drawn from it ``power`` ``(..., K)`` (W) at the knots ``t`` ``(K,)`` (module docstring)."""
    gain = energy_steps(power, t)
    twice = np.concatenate([gain, gain], axis=-1)
    S = np.concatenate([np.zeros(power.shape[:-1] + (1,)), np.cumsum(twice, axis=-1)], axis=-1)
    return (S - np.minimum(np.minimum.accumulate(S, axis=-1), 0.0)).max(axis=-1)


def resistor_energy(power: NDArray[np.float64], t: NDArray[np.float64], capacity: NDArray[np.float64]
                    ) -> NDArray[np.float64]:
    """The energy (J per cycle, ``(...)``) a braking resistor takes in the periodic cycle: what would lift the
    DC link's stored energy above ``capacity`` ``(...)`` (J), part by part of :func:`energy_steps` (the module
    docstring's two-sided walk, from 0 over two cycles; the second is periodic once the walk has reached the
    capacity, and if it never does the resistor takes nothing)."""
    gain = energy_steps(power, t)
    cap = np.maximum(np.asarray(capacity, dtype=float), 0.0)
    stored = np.zeros(gain.shape[:-1])
    burnt = np.zeros(gain.shape[:-1])
    for cycle in range(2):
        if cycle == 1:
            burnt[...] = 0.0
        for k in range(gain.shape[-1]):
            level = stored + gain[..., k]
            burnt += np.maximum(level - cap, 0.0)
            stored = np.clip(level, 0.0, cap)
    return burnt
