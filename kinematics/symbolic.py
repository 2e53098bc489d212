"""Symbolic kinematics with sympy: the papers' Matlab symbolic derivations, redone and checked.

Paper 000 (Hroncová et al.) multiplies the matrices of basic movements in Matlab's
symbolic toolbox to get the RRRR arm's T04, the components x0M, y0M, z0M of r_0M and
|r_0M| (Figs. 14–17 for the DH form, eqs. 21–35; Figs. 21–23 for the y-up form of
Fig. 20, eqs. 36–47), then differentiates r_0M with respect to time for v_0M and a_0M.
Paper 003 (Schonstein & Panc) multiplies its locating matrices by hand (eqs. 13–21) and
runs the iterative algorithm for ω4, v4, ω̇4, v̇4 (eqs. 34–49, 50–65).

This module does the same in sympy, from each paper's own formulation:

* :func:`T_Z1` … :func:`T_Z6` — symbolic versions of :mod:`armlab.kinematics.basic_movements`;
* :func:`rrrr_dh`, :func:`rrrr_yup` — paper 000's RRRR arm in both forms (:class:`RRRRForm`);
* :func:`end_point_kinematics` — v = dr/dt and a = d²r/dt² with q_i(t) functions, written
  in q, q̇, q̈ symbols (:class:`EndPointMotion`); :func:`constant_rate` substitutes
  q_i = ω_i t (paper 000's run of Figs. 18–19, 24–25);
* :func:`arm_kinematics` — any paper arm's end-point position, rotation, velocity and
  acceleration (:class:`ArmKinematics`), with batched numpy functions from
  :meth:`ArmKinematics.numeric` (``lambdify``, cached);
* :func:`r2t` — paper 003's T04, R04, p4 (as corrected, see :mod:`armlab.papers.errata`)
  and the end effector's ω4, v4, ω̇4, v̇4 in {0} and in its own frame {4};
* :func:`latex_table` — the expressions the papers print, as labelled LaTeX strings.

This module imports sympy at import time; the CLI (``armlab/cli/``) must import it lazily (``armlab._lazy``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING, Literal

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import as_batch

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = [
    "T_Z1",
    "T_Z2",
    "T_Z3",
    "T_Z4",
    "T_Z5",
    "T_Z6",
    "ArmKinematics",
    "EndPointMotion",
    "LatexItem",
    "NumericKinematics",
    "R2TSymbolic",
    "RRRRForm",
    "angular_velocity",
    "arm_kinematics",
    "batch_function",
    "constant_rate",
    "end_point_kinematics",
    "joint_symbols",
    "latex_table",
    "locating_matrix",
    "r2t",
    "r2t_chain",
    "rate_symbols",
    "rrrr_dh",
    "rrrr_yup",
    "t",
    "time_derivative",
]

#: Time, the variable of q_i(t) in :func:`end_point_kinematics`.
t = sp.Symbol("t", real=True)


# --------------------------------------------------------------------------- basic movements
def _translation(value: sp.Expr, axis: int) -> sp.Matrix:
    T = sp.eye(4)
    T[axis, 3] = value
    return T


def _rotation(angle: sp.Expr, axis: int) -> sp.Matrix:
    c, s = sp.cos(angle), sp.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    T = sp.eye(4)
    T[i, i], T[i, j], T[j, i], T[j, j] = c, -s, s, c
    return T


def T_Z1(a: sp.Expr) -> sp.Matrix:
    """Translation by ``a`` along x (paper 000, eq. 12)."""
    return _translation(a, 0)


def T_Z2(b: sp.Expr) -> sp.Matrix:
    """Translation by ``b`` along y (paper 000, eq. 38)."""
    return _translation(b, 1)


def T_Z3(c: sp.Expr) -> sp.Matrix:
    """Translation by ``c`` along z (paper 000, eq. 10)."""
    return _translation(c, 2)


def T_Z4(alpha: sp.Expr) -> sp.Matrix:
    """Rotation by ``alpha`` about x (paper 000, eq. 13)."""
    return _rotation(alpha, 0)


def T_Z5(beta: sp.Expr) -> sp.Matrix:
    """Rotation by ``beta`` about y (paper 000, eq. 37)."""
    return _rotation(beta, 1)


def T_Z6(gamma: sp.Expr) -> sp.Matrix:
    """Rotation by ``gamma`` about z (paper 000, eq. 11)."""
    return _rotation(gamma, 2)


def _product(matrices: Sequence[sp.Matrix]) -> sp.Matrix:
    out = sp.eye(matrices[0].rows)
    for M in matrices:
        out = out * M
    return out


# --------------------------------------------------------------------------- symbols, time derivatives
def joint_symbols(n: int, stem: str = "q") -> tuple[sp.Symbol, ...]:
    """Real joint symbols ``q1 … qn`` (or another stem, e.g. ``phi``)."""
    return tuple(sp.Symbol(f"{stem}{i}", real=True) for i in range(1, n + 1))


def rate_symbols(q: Sequence[sp.Symbol]) -> tuple[tuple[sp.Symbol, ...], tuple[sp.Symbol, ...]]:
    """``(q̇, q̈)`` symbols for joint symbols ``q`` (``q1`` → ``qdot1``, ``qddot1``; LaTeX \\dot{q}_{1})."""
    qd, qdd = [], []
    for s in q:
        stem = s.name.rstrip("0123456789")
        index = s.name[len(stem):]
        qd.append(sp.Symbol(f"{stem}dot{index}", real=True))
        qdd.append(sp.Symbol(f"{stem}ddot{index}", real=True))
    return tuple(qd), tuple(qdd)


def time_derivative(
    expr: sp.Expr | sp.Matrix, q: Sequence[sp.Symbol], time: sp.Symbol = t
) -> sp.Expr | sp.Matrix:
    """d/dt of an expression in q, q̇ (symbols), with q_i = q_i(t): the result is in q, q̇, q̈.

    The joint symbols are replaced by functions q_i(t), the expression is differentiated
    with respect to ``time``, and the derivatives are written back as the symbols of
    :func:`rate_symbols` (paper 000 differentiates r_0M this way in Matlab).
    """
    qd, qdd = rate_symbols(q)
    functions = [sp.Function(s.name, real=True)(time) for s in q]
    to_time = {s: f for s, f in zip(q, functions, strict=True)}
    to_time |= {sd: f.diff(time) for sd, f in zip(qd, functions, strict=True)}
    derivative = sp.sympify(expr).xreplace(to_time).diff(time)
    back: dict[sp.Basic, sp.Basic] = {f.diff(time, 2): s for f, s in zip(functions, qdd, strict=True)}
    derivative = derivative.xreplace(back)
    back = {f.diff(time): s for f, s in zip(functions, qd, strict=True)}
    derivative = derivative.xreplace(back)
    return derivative.xreplace({f: s for f, s in zip(functions, q, strict=True)})


@dataclass(frozen=True)
class EndPointMotion:
    """Position, velocity and acceleration of a point, in the symbols ``q``, ``qd``, ``qdd``."""

    position: sp.Matrix
    velocity: sp.Matrix
    acceleration: sp.Matrix
    q: tuple[sp.Symbol, ...]
    qd: tuple[sp.Symbol, ...]
    qdd: tuple[sp.Symbol, ...]


def end_point_kinematics(
    position_expr: sp.Matrix, q_symbols: Sequence[sp.Symbol], time: sp.Symbol = t
) -> EndPointMotion:
    """v = dr/dt and a = d²r/dt² of ``position_expr`` (paper 000: v_0M, a_0M from r_0M).

    Each q_i becomes a function q_i(t); the derivatives are returned in the symbols
    q, q̇, q̈ of :func:`rate_symbols`.
    """
    q = tuple(q_symbols)
    r = sp.Matrix(position_expr)
    v = time_derivative(r, q, time)
    a = time_derivative(v, q, time)
    qd, qdd = rate_symbols(q)
    return EndPointMotion(r, v, a, q, qd, qdd)


def constant_rate(
    expr: sp.Expr | sp.Matrix, motion: EndPointMotion, omegas: Sequence[sp.Expr], time: sp.Symbol = t
) -> sp.Expr | sp.Matrix:
    """``expr`` along the constant-rate motion q_i = ω_i t (q̇_i = ω_i, q̈_i = 0), paper 000 Figs. 18–19."""
    subs: dict[sp.Basic, sp.Expr] = {}
    for qi, qdi, qddi, w in zip(motion.q, motion.qd, motion.qdd, omegas, strict=True):
        subs |= {qi: w * time, qdi: w, qddi: sp.Integer(0)}
    return sp.sympify(expr).xreplace(subs)


def angular_velocity(R: sp.Matrix, q: Sequence[sp.Symbol], time: sp.Symbol = t) -> sp.Matrix:
    """ω of a rotation R(q) in the base frame: the axial vector of Ṙ Rᵀ, each entry simplified."""
    W = (time_derivative(R, q, time) * R.T).applyfunc(sp.trigsimp)
    return sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])


# --------------------------------------------------------------------------- paper 000: RRRR
@dataclass(frozen=True)
class RRRRForm:
    """Paper 000's RRRR arm in one of its two forms: the chain, T04, r_0M and |r_0M|."""

    form: Literal["dh", "yup"]
    q: tuple[sp.Symbol, ...]
    L: tuple[sp.Symbol, ...]
    chain: tuple[sp.Matrix, ...]  # T01, T12, T23, T34
    T04: sp.Matrix  # eq. (18), Figs. 16 / 23
    r0M: sp.Matrix  # (x0M, y0M, z0M), eqs. (19) / (49), Figs. 15 / 22

    @property
    def x0M(self) -> sp.Expr:
        """x component of r_0M."""
        return self.r0M[0]

    @property
    def y0M(self) -> sp.Expr:
        """y component of r_0M."""
        return self.r0M[1]

    @property
    def z0M(self) -> sp.Expr:
        """z component of r_0M."""
        return self.r0M[2]

    @property
    def norm(self) -> sp.Expr:
        """|r_0M| = sqrt(x0M² + y0M² + z0M²) (Fig. 17; the m-files' ``r_0M``)."""
        return sp.sqrt(self.x0M**2 + self.y0M**2 + self.z0M**2)

    def motion(self) -> EndPointMotion:
        """v_0M and a_0M by time differentiation of r_0M (paper 000, §7)."""
        return end_point_kinematics(self.r0M, self.q)


def _rrrr_symbols() -> tuple[tuple[sp.Symbol, ...], tuple[sp.Symbol, ...]]:
    return joint_symbols(4), tuple(sp.Symbol(f"L{i}", positive=True) for i in range(1, 5))


def _rrrr(form: Literal["dh", "yup"], T01: sp.Matrix, q: tuple, L: tuple) -> RRRRForm:
    T12 = T_Z6(q[1]) * T_Z1(L[1])  # eq. (26) / (39)
    T23 = T_Z6(q[2]) * T_Z1(L[2])  # eq. (29) / (42)
    T34 = T_Z6(q[3]) * T_Z1(L[3])  # eq. (32) / (45)
    T04 = _product([T01, T12, T23, T34])  # eq. (18)
    r4M = sp.Matrix([0, 0, 0, 1])  # eq. (20)
    r0M = (T04 * r4M)[:3, 0]  # eqs. (19), (35)
    return RRRRForm(form, q, L, (T01, T12, T23, T34), T04, r0M)


@cache
def rrrr_dh() -> RRRRForm:
    """The DH form of paper 000, eqs. (21)–(35): T01 = T_Z3(L1) T_Z6(q1) T_Z4(π/2)."""
    q, L = _rrrr_symbols()
    return _rrrr("dh", T_Z3(L[0]) * T_Z6(q[0]) * T_Z4(sp.pi / 2), q, L)  # eq. (21)


@cache
def rrrr_yup() -> RRRRForm:
    """The form of Fig. 20, eqs. (36)–(47): T01 = T_Z2(L1) T_Z5(q1) (as in the m-file of Fig. 21).

    Eq. (36) prints the product in the other order, T_Z5(q1) T_Z2(L1); the two commute
    (a translation along y and a rotation about y), so both give the same T01.
    """
    q, L = _rrrr_symbols()
    return _rrrr("yup", T_Z2(L[0]) * T_Z5(q[0]), q, L)


# --------------------------------------------------------------------------- paper 003: locating matrices
def _rodrigues(k: Sequence[sp.Expr], angle: sp.Expr) -> sp.Matrix:
    K = sp.Matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return sp.eye(3) + sp.sin(angle) * K + (1 - sp.cos(angle)) * K * K


def locating_matrix(
    kind: Literal["R", "T"], P: Sequence[sp.Expr], k: Sequence[sp.Expr], q: sp.Expr,
    R: sp.Matrix | None = None,
) -> sp.Matrix:
    """ⁱ⁻¹ᵢ[T] = T_{i,i−1} · T_Δ(k_i; q_i), paper 003 eqs. (1), (3)–(4).

    T_Δ = [R(k; q Δ) | (1 − Δ) q k] with Δ = 1 for a rotation and 0 for a translation.
    ``k`` is taken as printed (no unit-length check), so that a misprinted axis can be
    evaluated too (see :mod:`armlab.papers.errata`).
    """
    delta = 1 if kind == "R" else 0
    fixed = sp.eye(4)
    fixed[:3, :3] = sp.eye(3) if R is None else R
    fixed[:3, 3] = sp.Matrix(P)
    T_delta = sp.eye(4)
    T_delta[:3, :3] = _rodrigues(k, q * delta)
    T_delta[:3, 3] = (1 - delta) * q * sp.Matrix(k)
    return fixed * T_delta


def r2t_chain(k2: Sequence[sp.Expr] = (0, 0, 1)) -> tuple[tuple, tuple, tuple[sp.Matrix, ...]]:
    """(q, l, [T01, T12, T23, T34]) of paper 003, Table 1 and eqs. (13)–(18).

    ``k2`` is joint 2's axis (eq. 12: z2); Table 1 misprints it, see :mod:`armlab.papers.errata`.
    """
    q = joint_symbols(3)
    l = tuple(sp.Symbol(f"l{i}", real=True) for i in range(1, 6))
    T01 = locating_matrix("R", (0, 0, l[0]), (0, 0, 1), q[0])  # eq. (13)
    T12 = locating_matrix("T", (0, 0, l[1]), k2, q[1])  # eq. (14)
    T23 = locating_matrix("T", (l[2], 0, 0), (0, 1, 0), q[2])  # eq. (16)
    T34 = sp.Matrix([[0, 1, 0, 0], [1, 0, 0, l[3]], [0, 0, -1, -l[4]], [0, 0, 0, 1]])  # eq. (18)
    return q, l, (T01, T12, T23, T34)


@dataclass(frozen=True)
class R2TSymbolic:
    """Paper 003's R2T robot: locating matrices and end-effector kinematics (all simplified).

    ``*_own`` quantities are projected on the link's own frame (eqs. 50–65).
    """

    q: tuple[sp.Symbol, ...]
    qd: tuple[sp.Symbol, ...]
    qdd: tuple[sp.Symbol, ...]
    l: tuple[sp.Symbol, ...]
    T03: sp.Matrix  # eq. (17)
    T04: sp.Matrix  # eq. (19)
    R04: sp.Matrix  # eq. (20)
    p4: sp.Matrix  # eq. (21), corrected
    v3: sp.Matrix  # eq. (43)
    omega3_dot: sp.Matrix  # eq. (44)
    v3_dot: sp.Matrix  # eq. (45)
    omega4: sp.Matrix  # eq. (46)
    v4: sp.Matrix  # eq. (47)
    omega4_dot: sp.Matrix  # eq. (48)
    v4_dot: sp.Matrix  # eq. (49)
    v3_dot_own: sp.Matrix  # eq. (61)
    v4_own: sp.Matrix  # eqs. (63), (68)
    v4_dot_own: sp.Matrix  # eqs. (65), (69)


def _simplify(M: sp.Matrix) -> sp.Matrix:
    return M.applyfunc(lambda e: sp.collect(sp.trigsimp(sp.expand(e)), sp.symbols("qdot1 qddot1", real=True)))


@cache
def r2t() -> R2TSymbolic:
    """Paper 003, eqs. (13)–(21) by the locating matrices, and eqs. (43)–(49), (61)–(65) by d/dt.

    The velocities are time derivatives of the positions (ω from Ṙ Rᵀ), independent of the
    paper's iterative algorithm (eqs. 24–31, :mod:`armlab.kinematics.iterative`).
    """
    q, l, (T01, T12, T23, T34) = r2t_chain()
    qd, qdd = rate_symbols(q)
    T03 = (T01 * T12 * T23).applyfunc(sp.expand)  # eq. (17)
    T04 = (T03 * T34).applyfunc(sp.expand)  # eq. (19)
    R03, R04 = T03[:3, :3], T04[:3, :3]
    p3, p4 = T03[:3, 3], T04[:3, 3]
    v3 = _simplify(time_derivative(p3, q))
    v3_dot = _simplify(time_derivative(v3, q))
    v4 = _simplify(time_derivative(p4, q))
    v4_dot = _simplify(time_derivative(v4, q))
    omega3 = angular_velocity(R03, q)
    omega4 = angular_velocity(R04, q)
    return R2TSymbolic(
        q=q, qd=qd, qdd=qdd, l=l, T03=T03, T04=T04, R04=R04, p4=p4,
        v3=v3, omega3_dot=_simplify(time_derivative(omega3, q)), v3_dot=v3_dot,
        omega4=omega4, v4=v4, omega4_dot=_simplify(time_derivative(omega4, q)), v4_dot=v4_dot,
        v3_dot_own=_simplify(R03.T * v3_dot), v4_own=_simplify(R04.T * v4), v4_dot_own=_simplify(R04.T * v4_dot),
    )


# --------------------------------------------------------------------------- every arm
def _build_rr(params: dict[str, sp.Symbol]) -> tuple[tuple, sp.Matrix, sp.Matrix]:
    """Paper 000 eqs. (1)–(2); the tool frame turns by θ1 + θ2 about z."""
    q = joint_symbols(2)
    L1, L2 = params["L1"], params["L2"]
    x = L1 * sp.cos(q[0]) + L2 * sp.cos(q[0] + q[1])  # eq. (1)
    y = L1 * sp.sin(q[0]) + L2 * sp.sin(q[0] + q[1])  # eq. (2)
    return q, sp.Matrix([x, y, 0]), T_Z6(q[0] + q[1])[:3, :3]


def _build_rrrr(params: dict[str, sp.Symbol]) -> tuple[tuple, sp.Matrix, sp.Matrix]:
    form = rrrr_dh()
    subs = dict(zip(form.L, (params[f"L{i}"] for i in range(1, 5)), strict=True))
    return form.q, form.r0M.xreplace(subs), form.T04[:3, :3].xreplace(subs)


def _build_arm4r(params: dict[str, sp.Symbol]) -> tuple[tuple, sp.Matrix, sp.Matrix]:
    """Paper 001 eq. (1)–(2), Table 1: T_{i−1,i} = T_Z4(α_{i−1}) T_Z1(a_{i−1}) T_Z6(θ_i) T_Z3(d_i)."""
    q = joint_symbols(4)
    rows = ((0, 0, 0), (-sp.pi / 2, 0, params["d2"]), (0, params["a2"], 0), (0, params["a3"], 0))
    T04 = _product([T_Z4(alpha) * T_Z1(a) * T_Z6(qi) * T_Z3(d) for (alpha, a, d), qi in zip(rows, q, strict=True)])
    return q, T04[:3, 3], T04[:3, :3]


def _build_r2t(params: dict[str, sp.Symbol]) -> tuple[tuple, sp.Matrix, sp.Matrix]:
    """Paper 003 eqs. (13)–(19)."""
    q, l, chain = r2t_chain()
    T04 = _product(chain).xreplace({s: params[s.name] for s in l})
    return q, T04[:3, 3], T04[:3, :3]


def _build_urm6(params: dict[str, sp.Symbol]) -> tuple[tuple, sp.Matrix, sp.Matrix]:
    """Paper 004 eqs. (1)–(7): p1 = R_z1(φ1) r1, p_k = p_{k−1} + R_z1 Π[R_yj(θj) R_zj(φj)] r_k (φ7 = 0)."""
    phi = joint_symbols(6, "phi")
    r = [params[f"r{i}"] for i in range(1, 8)]
    theta = [params[f"theta{i}"] for i in range(2, 8)]
    R = T_Z6(phi[0])[:3, :3]  # eq. (1)
    p = R * sp.Matrix([0, 0, r[0]])  # eq. (3)
    for k in range(1, 7):  # eqs. (4)–(7)
        R = R * T_Z5(theta[k - 1])[:3, :3] * (T_Z6(phi[k])[:3, :3] if k < 6 else sp.eye(3))
        p = p + R * sp.Matrix([0, 0, r[k]])
    return phi, p, R


_BUILDERS: dict[str, Callable[[dict[str, sp.Symbol]], tuple[tuple, sp.Matrix, sp.Matrix]]] = {
    "rr": _build_rr, "rrrr": _build_rrrr, "arm4r": _build_arm4r, "r2t": _build_r2t, "urm6": _build_urm6,
}
_SOURCES = {
    "rr": "000 eqs. (1)-(2)",
    "rrrr": "000 eqs. (21)-(35)",
    "arm4r": "001 eqs. (1)-(5), Table 1 (modified DH)",
    "r2t": "003 eqs. (13)-(21)",
    "urm6": "004 eqs. (1)-(7)",
}


@dataclass(frozen=True)
class NumericKinematics:
    """Batched numpy functions of one arm: inputs of shape ``(..., n)``, outputs ``(..., 3)`` / ``(..., 3, 3)``."""

    n: int
    _position: Callable[..., NDArray]
    _rotation: Callable[..., NDArray]
    _velocity: Callable[..., NDArray]
    _acceleration: Callable[..., NDArray]

    def position(self, q: ArrayLike) -> NDArray[np.float64]:
        """End-point position, shape ``(..., 3)``."""
        return self._position(as_batch(q, self.n, "q"))

    def rotation(self, q: ArrayLike) -> NDArray[np.float64]:
        """Tool-frame rotation in the base frame, shape ``(..., 3, 3)``."""
        out = self._rotation(as_batch(q, self.n, "q"))
        return out.reshape(out.shape[:-1] + (3, 3))

    def velocity(self, q: ArrayLike, qd: ArrayLike) -> NDArray[np.float64]:
        """End-point velocity, shape ``(..., 3)``."""
        return self._velocity(as_batch(q, self.n, "q"), as_batch(qd, self.n, "qd"))

    def acceleration(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> NDArray[np.float64]:
        """End-point acceleration, shape ``(..., 3)``."""
        return self._acceleration(as_batch(q, self.n, "q"), as_batch(qd, self.n, "qd"), as_batch(qdd, self.n, "qdd"))


def batch_function(
    exprs: Sequence[sp.Expr], groups: Sequence[Sequence[sp.Symbol]], subs: dict | None = None
) -> Callable[..., NDArray[np.float64]]:
    """``lambdify`` scalar expressions into ``f(*arrays)`` over batches.

    Each argument is an array ``(..., len(group))`` holding the symbols of one group; the
    result stacks the expressions on the last axis, shape ``(..., len(exprs))`` (constant
    entries are broadcast to the batch shape).
    """
    symbols = [s for group in groups for s in group]
    exprs = [sp.sympify(e).xreplace(subs or {}) for e in exprs]
    f = sp.lambdify(symbols, exprs, modules="numpy", cse=True)
    sizes = [len(group) for group in groups]

    def call(*arrays: NDArray) -> NDArray[np.float64]:
        shape = np.broadcast_shapes(*(a.shape[:-1] for a in arrays))
        columns = [a[..., i] for a, size in zip(arrays, sizes, strict=True) for i in range(size)]
        values = f(*columns)
        return np.stack([np.broadcast_to(np.asarray(v, dtype=float), shape) for v in values], axis=-1)

    return call


@dataclass(frozen=True)
class ArmKinematics:
    """One paper arm's end point, symbolically, from its paper's formulation.

    ``parameters`` maps each parameter symbol (paper names: L1, l3, a2, r1, theta2, …) to
    the arm's value in SI. ``velocity`` and ``acceleration`` are in q, q̇, q̈.
    """

    name: str
    source: str
    #: The arm's parameter values (SI) the numbers are built from, by name, sorted.
    values: tuple[tuple[str, float], ...]
    q: tuple[sp.Symbol, ...]
    qd: tuple[sp.Symbol, ...]
    qdd: tuple[sp.Symbol, ...]
    parameters: dict[sp.Symbol, float]
    position: sp.Matrix
    rotation: sp.Matrix
    velocity: sp.Matrix
    acceleration: sp.Matrix

    def numeric(self) -> NumericKinematics:
        """Batched numpy functions with the parameter values substituted (built once per arm)."""
        return _numeric(self.name, self.values)


@cache
def _arm_kinematics(name: str, parameters: tuple[tuple[str, float], ...]) -> ArmKinematics:
    params = {key: sp.Symbol(key, real=True) for key, _ in parameters}
    q, position, rotation = _BUILDERS[name](params)
    motion = end_point_kinematics(position, q)
    used = position.free_symbols | rotation.free_symbols
    values = {s: float(dict(parameters)[key]) for key, s in params.items() if s in used}
    return ArmKinematics(name, _SOURCES[name], parameters, motion.q, motion.qd, motion.qdd, values,
                         position, rotation, motion.velocity, motion.acceleration)


def arm_kinematics(arm: Arm) -> ArmKinematics:
    """The symbolic end-point kinematics of the paper arm ``arm`` (rr, rrrr, arm4r, r2t, urm6), its parameters'
    values (``arm.parameters``) the numbers substituted by :meth:`ArmKinematics.numeric`. Other arms raise
    ``ValueError``."""
    if arm.name not in _BUILDERS:
        raise ValueError(f"no symbolic kinematics for arm {arm.name!r}; allowed: {', '.join(_BUILDERS)}")
    return _arm_kinematics(arm.name, tuple(sorted((key, float(v)) for key, v in arm.parameters.items())))


@cache
def _numeric(name: str, values: tuple[tuple[str, float], ...]) -> NumericKinematics:
    k = _arm_kinematics(name, values)
    subs = k.parameters
    return NumericKinematics(
        n=len(k.q),
        _position=batch_function(list(k.position), [k.q], subs),
        _rotation=batch_function(list(k.rotation), [k.q], subs),
        _velocity=batch_function(list(k.velocity), [k.q, k.qd], subs),
        _acceleration=batch_function(list(k.acceleration), [k.q, k.qd, k.qdd], subs),
    )


# --------------------------------------------------------------------------- LaTeX
@dataclass(frozen=True)
class LatexItem:
    """One printed expression: where the paper prints it, what it is, and its LaTeX."""

    label: str
    source: str
    latex: str


def _latex(expr: sp.Basic) -> str:
    return sp.latex(expr, mat_delim="[")


def latex_table(include_accelerations: bool = True) -> list[LatexItem]:
    """The expressions papers 000 and 003 print, rederived here, as LaTeX with a label each.

    000: Figs. 15–17 (DH form), 22–23 (y-up form), and v_0M, a_0M (§7); 003: eqs. (17),
    (19)–(21) (p4 as corrected), (43)–(49) and (61), (63), (65) (own frame). Set
    ``include_accelerations=False`` to leave out the long a_0M of paper 000.
    """
    items: list[LatexItem] = []
    for form, figs in ((rrrr_dh(), ("Fig. 15", "Fig. 16")), (rrrr_yup(), ("Fig. 22", "Fig. 23"))):
        name = "DH form" if form.form == "dh" else "y-up form (Fig. 20)"
        for axis, expr in zip("xyz", form.r0M, strict=True):
            items.append(LatexItem(f"{axis}_{{0M}}, {name}", f"000 {figs[0]}", _latex(expr)))
        items.append(LatexItem(f"T_{{04}}, {name}", f"000 {figs[1]}", _latex(form.T04)))
    dh = rrrr_dh()
    items.append(LatexItem(r"|\mathbf{r}_{0M}|", "000 Fig. 17", _latex(dh.norm)))
    motion = dh.motion()
    items.append(LatexItem(r"\mathbf{v}_{0M}, DH form", "000 §7", _latex(motion.velocity)))
    if include_accelerations:
        items.append(LatexItem(r"\mathbf{a}_{0M}, DH form", "000 §7", _latex(motion.acceleration)))
    s = r2t()
    for label, source, expr in (
        (r"{}^{0}_{3}[T]", "003 eq. (17)", s.T03),
        (r"{}^{0}_{4}[T]", "003 eq. (19), corrected", s.T04),
        (r"{}^{0}_{4}[R]", "003 eq. (20)", s.R04),
        (r"\overline{p}_4", "003 eq. (21), corrected", s.p4),
        (r"{}^{0}\overline{v}_3", "003 eq. (43)", s.v3),
        (r"{}^{0}\dot{\overline{\omega}}_3", "003 eq. (44), corrected", s.omega3_dot),
        (r"{}^{0}\dot{\overline{v}}_3", "003 eq. (45), corrected", s.v3_dot),
        (r"{}^{0}\overline{\omega}_4", "003 eq. (46)", s.omega4),
        (r"{}^{0}\overline{v}_4", "003 eq. (47), corrected", s.v4),
        (r"{}^{0}\dot{\overline{\omega}}_4", "003 eq. (48)", s.omega4_dot),
        (r"{}^{0}\dot{\overline{v}}_4", "003 eq. (49), corrected", s.v4_dot),
        (r"{}^{3}\dot{\overline{v}}_3", "003 eq. (61), corrected", s.v3_dot_own),
        (r"{}^{4}\overline{v}_4", "003 eqs. (63), (68), corrected", s.v4_own),
        (r"{}^{4}\dot{\overline{v}}_4", "003 eqs. (65), (69), corrected", s.v4_dot_own),
    ):
        items.append(LatexItem(label, source, _latex(expr)))
    return items
