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
one-sided reflected walk E = S − min(0, min S) of S(t) = −∫₀ᵗ p, and over the second cycle (periodic: the
walk from the first cycle's end E₁ is S − min(−E₁, min S)) — unless the cycle returns net energy (a payload
carried down and not up): then the link fills whatever its size, the stored energy is unbounded —, each
interval split where p changes sign (:func:`energy_steps`: S is then monotone between the points, so its extremes
are among them, exactly). With a capacity E_cap (the capacitors' ½C(V_max² − V_nom²)) whatever would lift E above
it goes to the braking resistor (:func:`resistor_energy`: the two-sided walk, part by part).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["BLOCK", "bus_energy", "energy_steps", "lag", "lag_periodic", "lag_weights", "resistor_energy",
           "within_zero"]

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
    out = np.empty(power.shape[:-1] + (2 * h.size,))
    out[..., 0::2] = np.where(turns, -p0 * s / 2, -(p0 + p1) * h / 2)
    out[..., 1::2] = np.where(turns, -p1 * (h - s) / 2, 0.0)
    return out


def bus_energy(power: NDArray[np.float64], t: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The largest energy (J) the DC link stores above its nominal voltage over the periodic cycle, and the net
    energy the cycle returns to it (J, −∫p; > 0: more comes back than is drawn), each ``(...)``, for the power
    drawn from it ``power`` ``(..., K)`` (W) at the knots ``t`` ``(K,)`` (module docstring). A cycle returning
    net energy fills any capacitor in the end: its stored energy is +inf."""
    steps = energy_steps(power, t)
    S = np.cumsum(steps, axis=-1)  # after each part (S = 0 at the start)
    low = np.minimum(np.minimum.accumulate(S, axis=-1), 0.0)
    net = S[..., -1]
    end = net - low[..., -1]  # the stored energy after one cycle from empty: the second cycle starts there
    # the second cycle, from `end`: E = S − min(−end, min S) (the reflected walk from a start ≥ 0); periodic when
    # the cycle returns no net energy (the walk from empty ends where the periodic one starts)
    peak = np.maximum(end, (S - np.minimum(low, -end[..., None])).max(axis=-1))
    gross = np.maximum(steps, 0.0).sum(axis=-1)
    charging = ~within_zero(net, gross)
    return np.where(charging, np.inf, peak), net


def within_zero(value: NDArray[np.float64], scale: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Whether ``value`` ≤ 0 but for round-off: ≤ 10⁻⁹·max(1, ``scale``) (a net energy against the gross)."""
    return np.asarray(value <= 1e-9 * np.maximum(1.0, scale))


def _runs(gain: NDArray[np.float64]) -> NDArray[np.float64]:
    """One row's gains ``(P,)`` summed over its runs of one sign: within a run the walk is monotone, so it meets
    at most one of its bounds, and the run's sum does what its parts do."""
    sign = np.sign(gain)
    keep = np.flatnonzero(sign != 0)
    if keep.size == 0:
        return np.zeros(0)
    starts = keep[np.concatenate([[True], sign[keep][1:] != sign[keep][:-1]])]
    return np.add.reduceat(gain, starts)


def _walk(gain: NDArray[np.float64], start: NDArray[np.float64], cap: NDArray[np.float64]
          ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The two-sided walk E ← clip(E + gain, 0, cap) part by part from ``start``, for each row of ``gain``
    ``(..., P)``: its end and what the cap cut, each ``(...)`` (over the runs of :func:`_runs`)."""
    rows = gain.reshape(-1, gain.shape[-1])
    ends, cut = np.empty(rows.shape[0]), np.zeros(rows.shape[0])
    starts = np.broadcast_to(start, gain.shape[:-1]).ravel().tolist()
    tops = np.broadcast_to(cap, gain.shape[:-1]).ravel().tolist()
    for r, row in enumerate(rows):
        level, top, burnt = float(starts[r]), float(tops[r]), 0.0
        for g in _runs(row).tolist():
            level += g
            if level > top:
                burnt += level - top
                level = top
            elif level < 0.0:
                level = 0.0
        ends[r], cut[r] = level, burnt
    return ends.reshape(gain.shape[:-1]), cut.reshape(gain.shape[:-1])


def resistor_energy(power: NDArray[np.float64], t: NDArray[np.float64], capacity: NDArray[np.float64]
                    ) -> NDArray[np.float64]:
    """The energy (J per cycle, ``(...)``) a braking resistor takes in the periodic cycle: what would lift the
    DC link's stored energy above ``capacity`` ``(...)`` (J), part by part of :func:`energy_steps`. One cycle maps
    its start e to clip(e + A, lo, hi) (a composition of clips is one), A the net energy returned; its fixed
    point, where the periodic cycle starts, is hi = the end from a full link if A > 0, else lo = the end from an
    empty one; the resistor's share is what that cycle cuts."""
    gain = energy_steps(power, t)
    cap = np.maximum(np.broadcast_to(np.asarray(capacity, dtype=float), gain.shape[:-1]), 0.0)
    net = gain.sum(axis=-1)
    charging = ~within_zero(net, np.maximum(gain, 0.0).sum(axis=-1))
    start = np.where(charging, cap, 0.0)
    periodic, _ = _walk(gain, start, cap)
    return _walk(gain, periodic, cap)[1]
