"""The papers' misprints: each printed equation that disagrees with Drake, printed and corrected.

:data:`ERRATA` lists one :class:`Erratum` per misprint found while rederiving the
papers' equations (:mod:`armlab.kinematics.symbolic`). An evaluable entry carries three
numeric callables of a :class:`Sample` (configurations plus Drake's answers there):
``printed`` (the equation as printed), ``corrected`` and ``reference`` (Drake's value of
the same quantity). ``tests/test_errata.py`` checks, at random configurations, that the
corrected form agrees with Drake to 1e-9 and the printed one does not; a report can call
:func:`check` for the same numbers. Entries with ``printed=None`` are misprints that
cannot be evaluated (undefined variables in a printed m-file, a wrong equation label).

The texts in ``papers/`` are PDF extractions; where the extraction itself may be at
fault the description says so.

Drake and sympy are imported only inside the functions that need them.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cache
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.basic_movements import DH_TO_YUP, T_Z5, T_Z6
from armlab.kinematics.batch import as_batch
from armlab.models import get_arm

if TYPE_CHECKING:
    from armlab.models.arm import Arm

__all__ = ["ERRATA", "Erratum", "Sample", "check", "drake_sample", "wrap_angle"]


# --------------------------------------------------------------------------- Drake's answers
@dataclass(frozen=True)
class Sample:
    """Configurations of one arm and Drake's kinematics there.

    Frames are the arm's links 1 … n and its tool (index n), all measured in the world
    frame at each frame's origin: ``pose`` (N, n+1, 4, 4) from ``CalcRelativeTransform``;
    ``omega``, ``v`` = J·q̇ and ``omega_dot``, ``v_dot`` = J·q̈ + bias from
    ``CalcJacobianSpatialVelocity`` and ``CalcBiasSpatialAcceleration``, each (N, n+1, 3).
    """

    arm: Arm
    q: NDArray[np.float64]
    qd: NDArray[np.float64]
    qdd: NDArray[np.float64]
    pose: NDArray[np.float64]
    omega: NDArray[np.float64]
    v: NDArray[np.float64]
    omega_dot: NDArray[np.float64]
    v_dot: NDArray[np.float64]

    @property
    def p(self) -> Mapping[str, float]:
        """The arm's parameters by their paper names (SI)."""
        return self.arm.parameters

    def own(self, frame: int, vectors: NDArray) -> NDArray[np.float64]:
        """``vectors`` (N, 3) in world coordinates projected on frame ``frame``'s own axes."""
        return np.einsum("nji,nj->ni", self.pose[:, frame, :3, :3], vectors)


def drake_sample(arm: Arm, q: ArrayLike, qd: ArrayLike | None = None, qdd: ArrayLike | None = None) -> Sample:
    """Query Drake at each configuration of the batch ``q`` (N, n) with rates ``qd`` and ``qdd`` (default 0)."""
    from pydrake.multibody.tree import JacobianWrtVariable

    q = np.atleast_2d(as_batch(q, arm.n, "q"))
    qd = np.broadcast_to(np.zeros(arm.n) if qd is None else as_batch(qd, arm.n, "qd"), q.shape)
    qdd = np.broadcast_to(np.zeros(arm.n) if qdd is None else as_batch(qdd, arm.n, "qdd"), q.shape)
    plant = arm.make_plant()
    context = plant.CreateDefaultContext()
    world = plant.world_frame()
    joints = [plant.GetJointByName(name) for name in arm.joint_names]  # the arm's joint order in the plant's q, v
    index = np.array([joint.position_start() for joint in joints])
    vindex = np.array([joint.velocity_start() for joint in joints])
    frames = [plant.GetBodyByName(f"link{i}").body_frame() for i in range(1, arm.n + 1)] + [
        plant.GetFrameByName(arm.tool_name)]
    N, F = q.shape[0], len(frames)
    pose = np.empty((N, F, 4, 4))
    V, A = np.empty((N, F, 6)), np.empty((N, F, 6))
    full_q, full_v, full_vd = np.zeros(plant.num_positions()), np.zeros(plant.num_velocities()), np.zeros(
        plant.num_velocities())
    for k in range(N):
        full_q[index], full_v[vindex], full_vd[vindex] = q[k], qd[k], qdd[k]
        plant.SetPositions(context, full_q)
        plant.SetVelocities(context, full_v)
        for f, frame in enumerate(frames):
            pose[k, f] = plant.CalcRelativeTransform(context, world, frame).GetAsMatrix4()
            J = plant.CalcJacobianSpatialVelocity(context, JacobianWrtVariable.kV, frame, np.zeros(3), world, world)
            bias = plant.CalcBiasSpatialAcceleration(
                context, JacobianWrtVariable.kV, frame, np.zeros(3), world, world
            ).get_coeffs()
            V[k, f] = J @ full_v
            A[k, f] = J @ full_vd + bias
    return Sample(arm, q, np.array(qd), np.array(qdd), pose, V[..., :3], V[..., 3:], A[..., :3], A[..., 3:])


# --------------------------------------------------------------------------- the entry
Evaluator = Callable[[Sample], NDArray[np.float64]]


def wrap_angle(x: ArrayLike) -> NDArray[np.float64]:
    """Angles wrapped into (−π, π]."""
    x = np.asarray(x, dtype=float)
    return x - 2 * np.pi * np.ceil((x - np.pi) / (2 * np.pi))


@dataclass(frozen=True)
class Erratum:
    """One misprinted equation: where, what, as printed, as corrected, and how to evaluate both."""

    paper: str
    equation: str
    description: str
    printed_form: str  # LaTeX, as printed (read through the PDF extraction)
    corrected_form: str  # LaTeX
    arm: str | None = None  # the arm whose configurations evaluate it
    overrides: Mapping[str, float] = field(default_factory=dict)  # parameters that make the misprint visible
    printed: Evaluator | None = None
    corrected: Evaluator | None = None
    reference: Evaluator | None = None  # Drake's value of the same quantity
    angle: bool = False  # compare modulo 2π
    #: The samples at which the misprint shows (boolean (N,)); ``None``: at every sample.
    affects: Callable[[Sample], NDArray[np.bool_]] | None = None

    @property
    def evaluable(self) -> bool:
        """True when the printed and corrected forms can be evaluated and compared with Drake."""
        return self.printed is not None

    def errors(self, sample: Sample) -> tuple[float, float]:
        """Largest |printed − Drake| and |corrected − Drake| over the sample (angles modulo 2π)."""
        if self.printed is None or self.corrected is None or self.reference is None:
            raise ValueError(f"{self.paper} {self.equation}: this erratum cannot be evaluated (printed form only)")
        reference = self.reference(sample)
        out = []
        for fn in (self.printed, self.corrected):
            diff = np.asarray(fn(sample), dtype=float) - reference
            out.append(float(np.max(np.abs(wrap_angle(diff) if self.angle else diff))))
        return out[0], out[1]


# --------------------------------------------------------------------------- helpers for the callables
def _cs(q: NDArray, i: int) -> tuple[NDArray, NDArray]:
    """(cos q_i, sin q_i) of joint i (1-based, as in the papers)."""
    return np.cos(q[:, i - 1]), np.sin(q[:, i - 1])


def _stack(*columns: ArrayLike) -> NDArray[np.float64]:
    shape = np.broadcast_shapes(*(np.shape(c) for c in columns))
    return np.stack([np.broadcast_to(c, shape) for c in columns], axis=-1)


@cache
def _symbolic_function(key: str) -> Callable[..., NDArray]:
    """Lambdified expressions of :mod:`armlab.kinematics.symbolic` used as corrected (or printed) forms."""
    import sympy as sp

    from armlab.kinematics import symbolic

    if key.startswith("r2t."):
        s = symbolic.r2t()
        expr = getattr(s, key[4:])
        return symbolic.batch_function(list(expr), [s.q, s.qd, s.qdd, s.l])
    if key.startswith("r2t_k2="):  # p4 with the joint-2 axis of Table 1 as given
        k2 = tuple(int(c) for c in key.split("=")[1].split(","))
        q, l, chain = symbolic.r2t_chain(k2)
        return symbolic.batch_function(list((chain[0] * chain[1] * chain[2] * chain[3])[:3, 3]), [q, l])
    if key.startswith("yup"):  # 000's y-up chain with one basic movement replaced by its printed form
        form = symbolic.rrrr_yup()
        q, L = form.q, form.L
        T01 = form.chain[0]
        if key == "yup:eq37":  # T_Z5(q1) with its middle row printed as zeros
            T_Z5_printed = symbolic.T_Z5(q[0])
            T_Z5_printed[1, 1] = 0
            T01 = symbolic.T_Z2(L[0]) * T_Z5_printed
        elif key == "yup:eq38":  # T_Z2 with the length of its label, L2
            T01 = symbolic.T_Z2(L[1]) * symbolic.T_Z5(q[0])
        chain = (T01,) + form.chain[1:]
        r = (chain[0] * chain[1] * chain[2] * chain[3] * sp.Matrix([0, 0, 0, 1]))[:3, 0]
        return symbolic.batch_function(list(r), [q, L])
    raise KeyError(key)


def _r2t_symbolic(key: str) -> Evaluator:
    def evaluate(s: Sample) -> NDArray:
        l = np.array([s.p[f"l{i}"] for i in range(1, 6)])
        return _symbolic_function(f"r2t.{key}")(s.q, s.qd, s.qdd, l)

    return evaluate


def _r2t_p4_k2(k2: str) -> Evaluator:
    def evaluate(s: Sample) -> NDArray:
        l = np.array([s.p[f"l{i}"] for i in range(1, 6)])
        return _symbolic_function(f"r2t_k2={k2}")(s.q, l)

    return evaluate


def _yup(variant: str) -> Evaluator:
    def evaluate(s: Sample) -> NDArray:
        L = np.array([s.p[f"L{i}"] for i in range(1, 5)])
        return _symbolic_function(f"yup:{variant}")(s.q, L)

    return evaluate


def _tool_position(s: Sample) -> NDArray:
    return s.pose[:, -1, :3, 3]


def _tool_position_yup(s: Sample) -> NDArray:
    """Drake's tool position (DH base frame) in 000's y-up base frame of Fig. 20."""
    return _tool_position(s) @ DH_TO_YUP[:3, :3].T


# ---- paper 003 (r2t): printed forms, read from the text
def _003_p4_printed(s: Sample) -> NDArray:
    """Eqs. (19), (21) as printed."""
    c1, s1 = _cs(s.q, 1)
    q2, q3 = s.q[:, 1], s.q[:, 2]
    l1, l2, l3, l4, l5 = (s.p[f"l{i}"] for i in range(1, 6))
    return _stack(c1 - q3 * s1 + l3 * c1 - l4 * s1, s1 + q3 * c1 + l4 * c1 + l3 * s1, l1 + l2 - l5 + q2)


def _003_v3_dot_printed(s: Sample) -> NDArray:
    """Eq. (45) as printed, the dots misplaced on q1 inside c/s read as c q1, s q1."""
    c1, s1 = _cs(s.q, 1)
    q3 = s.q[:, 2]
    (qd1, _, _), (qdd1, qdd2, qdd3) = s.qd.T, s.qdd.T
    l3 = s.p["l3"]
    return _stack(
        (q3 * s1 - l3 * c1) * qd1**2 - 2 * c1 * qdd3 * qd1 - (q3 * c1 + l3 * s1) * qdd1 - s1 * qdd3,
        (-q3 * c1 - l3 * s1) * qd1**2 - 2 * s1 * qdd3 * qd1 - (q3 * s1 - l3 * c1) * qdd1 + c1 * qdd3,
        qdd2,
    )


def _003_v4_printed(s: Sample) -> NDArray:
    """Eq. (47) as printed: the same as v3 of eq. (43)."""
    c1, s1 = _cs(s.q, 1)
    q3 = s.q[:, 2]
    qd1, qd2, qd3 = s.qd.T
    l3 = s.p["l3"]
    return _stack(-s1 * qd3 - l3 * s1 * qd1 - q3 * c1 * qd1, c1 * qd3 + l3 * c1 * qd1 - q3 * s1 * qd1, qd2)


def _003_v3_dot_own_printed(s: Sample) -> NDArray:
    """Eq. (61) as printed."""
    q3 = s.q[:, 2]
    (qd1, _, _), (qdd1, qdd2, qdd3) = s.qd.T, s.qdd.T
    l3 = s.p["l3"]
    return _stack(-l3 * qd1**2 - 2 * qdd3 * qd1 - q3 * qdd1, l3 * qdd1 - q3 * qd1**2 + qdd3, qdd2)


def _003_v4_own_printed(s: Sample) -> NDArray:
    """Eqs. (63), (68) as printed."""
    c1, s1 = _cs(s.q, 1)
    q3 = s.q[:, 2]
    qd1, qd2, qd3 = s.qd.T
    l3, l4 = s.p["l3"], s.p["l4"]
    return _stack(l3 * qd1 + qd3 + c1 * qd1 + l4 * s1 * qd1, -qd1 * (q3 - s1 + l4 * c1), qd2)


def _003_v4_dot_own_printed(s: Sample) -> NDArray:
    """Eqs. (65), (69) as printed (third row q̈2 as in eq. 69)."""
    c1, s1 = _cs(s.q, 1)
    q3 = s.q[:, 2]
    (qd1, _, _), (qdd1, qdd2, qdd3) = s.qd.T, s.qdd.T
    l3, l4 = s.p["l3"], s.p["l4"]
    return _stack(
        s1 * qd1**2 + c1 * qdd1 + l3 * qdd1 - q3 * qd1**2 + qdd3 - l4 * c1 * qd1**2 + l4 * s1 * qdd1,
        -s1 * qdd1 - l3 * qd1**2 - c1 * qd1**2 - 2 * qd1 * qdd3 - q3 * qdd1 - l4 * s1 * qd1**2 - l4 * c1 * qdd1,
        qdd2,
    )


def _003_R04(q: NDArray) -> NDArray:
    """Eq. (20): ⁰₄[R] = [[−s1, c1, 0], [c1, s1, 0], [0, 0, −1]], (N, 3, 3)."""
    c1, s1 = _cs(q, 1)
    zero = np.zeros_like(c1)
    return np.stack([_stack(-s1, c1, zero), _stack(c1, s1, zero), _stack(zero, zero, zero - 1.0)], axis=-2)


def _003_omega4_own(printed: bool) -> Evaluator:
    """Eqs. (62), (64): ⁴ω4 and ⁴ω̇4 side by side, (N, 6); corrected as ⁰₄[R]ᵀ of eq. (20) times eqs. (46), (48)."""

    def evaluate(s: Sample) -> NDArray:
        zero = np.zeros(len(s.q))
        world = np.concatenate([_stack(zero, zero, s.qd[:, 0]), _stack(zero, zero, s.qdd[:, 0])], axis=-1)
        if printed:
            return world
        R = _003_R04(s.q)
        return np.concatenate([np.einsum("nji,nj->ni", R, world[:, :3]), np.einsum("nji,nj->ni", R, world[:, 3:])],
                              axis=-1)

    return evaluate


def _003_atan2(printed: bool) -> Evaluator:
    """Eq. (22)'s case table for A tan 2(sα; cα), applied to γ_z's sine and cosine in Drake's tool rotation
    (⁰₄[R] = Rz(γ_z) Rx(π): sγ = R21, cγ = R11). α in the table is read as arctan(sα/cα), the principal value;
    a case the printed table does not cover gives NaN."""

    def evaluate(s: Sample) -> NDArray:
        sin, cos = s.pose[:, -1, 1, 0], s.pose[:, -1, 0, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            alpha = np.arctan(sin / cos)
        if printed:
            cases = [(sin >= 0) & (cos > 0), (sin > 0) & (cos < 0), (sin < 0) & (cos < 0), (sin < 0) & (cos >= 0)]
            values = [alpha, np.pi / 2 + alpha, np.pi + alpha, -np.pi / 2 + alpha]
        else:
            cases = [cos > 0, (cos < 0) & (sin >= 0), (cos < 0) & (sin < 0), cos == 0]
            values = [alpha, np.pi + alpha, -np.pi + alpha, np.pi / 2 * np.sign(sin)]
        return np.select(cases, values, default=np.nan)

    return evaluate


def _003_atan2_affects(s: Sample) -> NDArray[np.bool_]:
    """The 2nd and 4th cases of eq. (22): sγ and cγ of opposite signs."""
    return s.pose[:, -1, 1, 0] * s.pose[:, -1, 0, 0] < 0


# ---- paper 004 (urm6): the general formulas of the position vectors, eqs. (7) and (22)
def _004_lengths(s: Sample) -> tuple[NDArray, NDArray, NDArray]:
    """φ1 … φ7 (N, 7; module 7 has no joint), θ2 … θ7 (6,) and |r1| … |r7| (7,)."""
    phi = np.concatenate([s.q, np.zeros((len(s.q), 1))], axis=-1)
    return (phi, np.array([s.p[f"theta{k}"] for k in range(2, 8)]), np.array([s.p[f"r{k}"] for k in range(1, 8)]))


def _004_eq7(printed: bool) -> Evaluator:
    """Eq. (7), p_{i+1} = R_z1(φ) [r + Σ_{k=1..i} Π_{j=1..k} (R_y(j+1)(θ_{j+1}) R_z(j+1)(φ_{j+1})) r_{k+1}] for
    i = 1 … 6, (N, 6, 3): printed with φ = φ_i, r = r_i, corrected with φ1, r1."""

    def evaluate(s: Sample) -> NDArray:
        phi, theta, r = _004_lengths(s)
        z = np.array([0.0, 0.0, 1.0])
        points = []
        for i in range(1, 7):
            total = np.broadcast_to((r[i - 1] if printed else r[0]) * z, (len(s.q), 3)).copy()
            R = np.eye(3)
            for k in range(1, i + 1):
                R = R @ T_Z5(theta[k - 1])[:3, :3] @ T_Z6(phi[:, k])[..., :3, :3]
                total += R @ (r[k] * z)
            lead = T_Z6(phi[:, i - 1] if printed else phi[:, 0])[..., :3, :3]
            points.append(np.einsum("nij,nj->ni", lead, total))
        return np.stack(points, axis=1)

    return evaluate


def _004_eq22(printed: bool) -> Evaluator:
    """Eq. (22), p_{i+1} = T_z1(φ) Π_{j=1..i} (T_y(j+1)(θ_{j+1}, r_j) T_z(j+1)(φ_{j+1})) r_{i+1} for i = 1 … 6,
    (N, 6, 3): printed with φ = φ_i, corrected with φ1."""

    def evaluate(s: Sample) -> NDArray:
        phi, theta, r = _004_lengths(s)
        points = []
        for i in range(1, 7):
            T = T_Z6(phi[:, i - 1] if printed else phi[:, 0])
            for j in range(1, i + 1):
                T_y = T_Z5(theta[j - 1])
                T_y[2, 3] = r[j - 1]  # eq. (10): the displacement r_j along the module's z
                T = T @ T_y @ T_Z6(phi[:, j])
            points.append((T @ np.array([0.0, 0.0, r[i], 1.0]))[..., :3])
        return np.stack(points, axis=1)

    return evaluate


def _004_points_drake(s: Sample) -> NDArray:
    """Drake's positions of the URDF frames p2 … p7 at each configuration, (N, 6, 3)."""
    plant = s.arm.make_plant()
    context = plant.CreateDefaultContext()
    world = plant.world_frame()
    frames = [plant.GetFrameByName(f"p{k}") for k in range(2, 8)]
    out = np.empty((len(s.q), 6, 3))
    for n, q in enumerate(s.q):
        plant.SetPositions(context, q)
        out[n] = [plant.CalcRelativeTransform(context, world, frame).translation() for frame in frames]
    return out


# ---- paper 001 (arm4r): the analytical inverse kinematics, eqs. (5), (10)–(21)
def _001_x_eq5(printed: bool) -> Evaluator:
    def evaluate(s: Sample) -> NDArray:
        (c1, s1), (c2, s2), (c3, s3) = _cs(s.q, 1), _cs(s.q, 2), _cs(s.q, 3)
        a2, a3, d2 = s.p["a2"], s.p["a3"], s.p["d2"]
        third = a3 * (s1 if printed else c1) * s2 * s3  # printed "a3 s1 s2 s3"
        return a3 * c1 * c2 * c3 + a2 * c1 * c2 - third - d2 * s1

    return evaluate


def _001_theta1(printed: bool) -> Evaluator:
    """Eqs. (10)–(11) with the root of the configuration (the sign of c1 px + s1 py = a2 c2 + a3 c23)."""

    def evaluate(s: Sample) -> NDArray:
        px, py = s.pose[:, -1, 0, 3], s.pose[:, -1, 1, 3]
        a2, a3, d2 = s.p["a2"], s.p["a3"], s.p["d2"]
        reach = a2 * np.cos(s.q[:, 1]) + a3 * np.cos(s.q[:, 1] + s.q[:, 2])
        root = np.sign(reach) * np.sqrt(px**2 + py**2 - d2**2)
        phi = np.arctan2(px, py) if printed else np.arctan2(py, px)  # printed "Φ = A tan 2(p_x, p_y)"
        return phi - np.arctan2(d2, root)

    return evaluate


def _001_T03_inverse_times_T04(printed: bool) -> Evaluator:
    """Position column of ⁰₃T⁻¹ · ⁰₄T, eq. (15), with ⁰₄T from Drake; it should equal ³₄T's, (a3, 0, 0)."""

    def evaluate(s: Sample) -> NDArray:
        (c1, s1), (c2, s2), (c3, s3) = _cs(s.q, 1), _cs(s.q, 2), _cs(s.q, 3)
        a2, d2 = s.p["a2"], s.p["d2"]
        zero = np.zeros_like(c1)
        rows = [
            [c1 * c2 * c3 - c1 * s2 * s3, s1 * c2 * c3 - s1 * s2 * s3, -s2 * c3 - c2 * s3, -a2 * c3],
            [-c1 * c2 * s3 - c1 * s2 * c3, -s1 * c2 * s3 - s1 * s2 * c3, s2 * s3 - c2 * c3, a2 * s3],
            [-s1, c1, zero, (d2 if printed else -d2) + zero],  # printed (3, 4) entry "d2"
        ]
        inverse = np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)  # (N, 3, 4)
        return np.einsum("nij,nj->ni", inverse, s.pose[:, -1, :, 3])

    return evaluate


def _001_reference_T34_position(s: Sample) -> NDArray:
    """³₄T's position column from Drake's link-3 and tool poses."""
    X3, X4 = s.pose[:, 2], s.pose[:, -1]
    return np.einsum("nji,nj->ni", X3[:, :3, :3], X4[:, :3, 3] - X3[:, :3, 3])


def _001_s23_c23(printed: bool) -> Evaluator:
    """Eq. (17) with the configuration's θ1, θ3 and Drake's tool position."""

    def evaluate(s: Sample) -> NDArray:
        (c1, s1), (c3, s3) = _cs(s.q, 1), _cs(s.q, 3)
        px, py, pz = s.pose[:, -1, :3, 3].T
        a2, a3 = s.p["a2"], s.p["a3"]
        u = c1 * px + s1 * py
        denominator = (px**2 if printed else pz**2) + u**2  # printed "p_x² + (c1 px + s1 py)²"
        A, B = a3 + a2 * c3, a2 * s3
        return _stack((B * u - A * pz) / denominator, (A * u + B * pz) / denominator)

    return evaluate


def _001_theta23(s: Sample) -> NDArray:
    """Eq. (18) with the configuration's θ1, θ3 and Drake's tool position."""
    (c1, s1), (c3, s3) = _cs(s.q, 1), _cs(s.q, 3)
    px, py, pz = s.pose[:, -1, :3, 3].T
    a2, a3 = s.p["a2"], s.p["a3"]
    u = c1 * px + s1 * py
    return np.arctan2(a2 * s3 * u - (a3 + a2 * c3) * pz, (a3 + a2 * c3) * u + a2 * s3 * pz)


def _001_theta2(printed: bool) -> Evaluator:
    def evaluate(s: Sample) -> NDArray:
        return _001_theta23(s) - s.q[:, 0 if printed else 2]  # printed "θ1 = θ23 − θ3" read as θ2 = θ23 − θ1

    return evaluate


def _001_theta4(printed: bool) -> Evaluator:
    """Eqs. (20)–(21) with the configuration's θ1, θ2 + θ3 and Drake's tool o vector."""

    def evaluate(s: Sample) -> NDArray:
        c1, s1 = _cs(s.q, 1)
        c23, s23 = np.cos(s.q[:, 1] + s.q[:, 2]), np.sin(s.q[:, 1] + s.q[:, 2])
        ox, oy, oz = s.pose[:, -1, :3, 1].T
        first = c1 * c23 * ox + s1 * c23 * oy - s23 * oz  # (1, 2) of eq. (15): −s4
        second = c1 * s23 * ox + s1 * s23 * oy + c23 * oz  # minus (2, 2) of eq. (15): −c4
        return np.arctan2(first, second) if printed else np.arctan2(-first, -second)

    return evaluate


def _000_T04_entry_23(printed: bool) -> Evaluator:
    def evaluate(s: Sample) -> NDArray:
        c1 = np.cos(s.q[:, 0])
        return c1 if printed else -c1

    return evaluate


# --------------------------------------------------------------------------- the list
_ARM4R_OFFSET = {"d2": 0.25}  # 001 prints no lengths; d2 ≠ 0 makes every d2 term visible

ERRATA: tuple[Erratum, ...] = (
    # ------------------------------------------------------------------ paper 003
    Erratum(
        "003", "eqs. (19), (21)",
        "p4 has stray 'c q1' and 's q1' terms (a unit length where there is none); the product "
        "⁰₃[T]·T43 of eqs. (17)-(18) gives p4 = (l3 c1 − (q3 + l4) s1, l3 s1 + (q3 + l4) c1, l1 + l2 + q2 − l5).",
        r"\overline{p}_4 = (c q_1 - q_3 s q_1 + l_3 c q_1 - l_4 s q_1,\; s q_1 + q_3 c q_1 + l_4 c q_1 + l_3 s q_1,"
        r"\; l_1 + l_2 - l_5 + q_2)",
        r"\overline{p}_4 = (l_3 c q_1 - (q_3 + l_4) s q_1,\; l_3 s q_1 + (q_3 + l_4) c q_1,\; l_1 + l_2 - l_5 + q_2)",
        arm="r2t", printed=_003_p4_printed, corrected=_r2t_symbolic("p4"), reference=_tool_position,
    ),
    Erratum(
        "003", "Table 1 (row 2)",
        "The axis of joint 2 is printed k2 = (1, 0, 1), not even a unit vector; eq. (12) says k2 ≡ z2 = (0, 0, 1).",
        r"\overline{k}_2 = (1, 0, 1)",
        r"\overline{k}_2 = (0, 0, 1)",
        arm="r2t", printed=_r2t_p4_k2("1,0,1"), corrected=_r2t_p4_k2("0,0,1"), reference=_tool_position,
    ),
    Erratum(
        "003", "eq. (44)",
        "The angular acceleration of link 3 is printed (0, 0, q̈2); the prismatic joints 2, 3 add none, so it is "
        "(0, 0, q̈1), as eq. (48) then states for link 4.",
        r"{}^0\dot{\overline{\omega}}_3 = (0, 0, \ddot{q}_2)^T",
        r"{}^0\dot{\overline{\omega}}_3 = (0, 0, \ddot{q}_1)^T",
        arm="r2t", printed=lambda s: _stack(0.0, 0.0, s.qdd[:, 1]), corrected=_r2t_symbolic("omega3_dot"),
        reference=lambda s: s.omega_dot[:, 2],
    ),
    Erratum(
        "003", "eq. (45)",
        "The Coriolis term of v̇3 is printed '2·c q̇1·q̈3·q̇1' and '2·s q1·q̈3·q̇1' (an acceleration times a rate); "
        "2·ω × q̇3 k3 of eq. (27) gives 2·c q1·q̇1·q̇3 and 2·s q1·q̇1·q̇3. The extraction also puts the dot on q1 "
        "inside c/s ('c q̇1', 's q̇1'), read here as c q1, s q1. Eq. (49), v̇4 in {0}, is missing from the text.",
        r"{}^0\dot{\overline{v}}_3 = ((q_3 s q_1 - l_3 c q_1)\dot{q}_1^2 - 2 c q_1 \ddot{q}_3 \dot{q}_1"
        r" - (q_3 c q_1 + l_3 s q_1)\ddot{q}_1 - s q_1 \ddot{q}_3,\; -(q_3 c q_1 + l_3 s q_1)\dot{q}_1^2"
        r" - 2 s q_1 \ddot{q}_3 \dot{q}_1 - (q_3 s q_1 - l_3 c q_1)\ddot{q}_1 + c q_1 \ddot{q}_3,\; \ddot{q}_2)",
        r"\ddot{q}_3 \to \dot{q}_3 \text{ in both terms } 2\,c q_1\,\ddot{q}_3\,\dot{q}_1,"
        r"\ 2\,s q_1\,\ddot{q}_3\,\dot{q}_1",
        arm="r2t", printed=_003_v3_dot_printed, corrected=_r2t_symbolic("v3_dot"), reference=lambda s: s.v_dot[:, 2],
    ),
    Erratum(
        "003", "eq. (47)",
        "v4 is printed equal to v3 of eq. (43): the term ω3 × p43 of its own first line, −l4 q̇1 (c q1, s q1, 0), "
        "is missing.",
        r"{}^0\overline{v}_4 = (-s q_1 \dot{q}_3 - l_3 s q_1 \dot{q}_1 - q_3 c q_1 \dot{q}_1,\;"
        r" c q_1 \dot{q}_3 + l_3 c q_1 \dot{q}_1 - q_3 s q_1 \dot{q}_1,\; \dot{q}_2)",
        r"{}^0\overline{v}_4 = (-s q_1 \dot{q}_3 - l_3 s q_1 \dot{q}_1 - (q_3 + l_4) c q_1 \dot{q}_1,\;"
        r" c q_1 \dot{q}_3 + l_3 c q_1 \dot{q}_1 - (q_3 + l_4) s q_1 \dot{q}_1,\; \dot{q}_2)",
        arm="r2t", printed=_003_v4_printed, corrected=_r2t_symbolic("v4"), reference=lambda s: s.v[:, -1],
    ),
    Erratum(
        "003", "eq. (61)",
        "³v̇3 has the same Coriolis misprint as eq. (45): '2·q̈3·q̇1' for 2·q̇1·q̇3.",
        r"{}^3\dot{\overline{v}}_3 = (-l_3 \dot{q}_1^2 - 2 \ddot{q}_3 \dot{q}_1 - q_3 \ddot{q}_1,\;"
        r" l_3 \ddot{q}_1 - q_3 \dot{q}_1^2 + \ddot{q}_3,\; \ddot{q}_2)",
        r"{}^3\dot{\overline{v}}_3 = (-l_3 \dot{q}_1^2 - 2 \dot{q}_3 \dot{q}_1 - q_3 \ddot{q}_1,\;"
        r" l_3 \ddot{q}_1 - q_3 \dot{q}_1^2 + \ddot{q}_3,\; \ddot{q}_2)",
        arm="r2t", printed=_003_v3_dot_own_printed, corrected=_r2t_symbolic("v3_dot_own"),
        reference=lambda s: s.own(2, s.v_dot[:, 2]),
    ),
    Erratum(
        "003", "eqs. (63), (68)",
        "⁴v4 carries the stray c q1, s q1 of eq. (21), has l4 c q1, l4 s q1 where ⁴₀[R]·v4 gives l4, and the sign "
        "of its z row is lost (z4 points down, eq. 20).",
        r"{}^4\overline{v}_4 = (l_3 \dot{q}_1 + \dot{q}_3 + c q_1 \dot{q}_1 + l_4 s q_1 \dot{q}_1,\;"
        r" -\dot{q}_1 (q_3 - s q_1 + l_4 c q_1),\; \dot{q}_2)",
        r"{}^4\overline{v}_4 = (l_3 \dot{q}_1 + \dot{q}_3,\; -\dot{q}_1 (q_3 + l_4),\; -\dot{q}_2)",
        arm="r2t", printed=_003_v4_own_printed, corrected=_r2t_symbolic("v4_own"),
        reference=lambda s: s.own(-1, s.v[:, -1]),
    ),
    Erratum(
        "003", "eqs. (65), (69)",
        "⁴v̇4 carries the stray c q1, s q1 terms, l4 c q1 / l4 s q1 for l4, the Coriolis misprint 2·q̇1·q̈3 and a "
        "lost sign on q̈2.",
        r"{}^4\dot{\overline{v}}_4 = (s q_1 \dot{q}_1^2 + c q_1 \ddot{q}_1 + l_3 \ddot{q}_1 - q_3 \dot{q}_1^2"
        r" + \ddot{q}_3 - l_4 c q_1 \dot{q}_1^2 + l_4 s q_1 \ddot{q}_1,\; -s q_1 \ddot{q}_1 - l_3 \dot{q}_1^2"
        r" - c q_1 \dot{q}_1^2 - 2 \dot{q}_1 \ddot{q}_3 - q_3 \ddot{q}_1 - l_4 s q_1 \dot{q}_1^2"
        r" - l_4 c q_1 \ddot{q}_1,\; \ddot{q}_2)",
        r"{}^4\dot{\overline{v}}_4 = (l_3 \ddot{q}_1 + \ddot{q}_3 - (q_3 + l_4)\dot{q}_1^2,\;"
        r" -l_3 \dot{q}_1^2 - 2 \dot{q}_1 \dot{q}_3 - (q_3 + l_4)\ddot{q}_1,\; -\ddot{q}_2)",
        arm="r2t", printed=_003_v4_dot_own_printed, corrected=_r2t_symbolic("v4_dot_own"),
        reference=lambda s: s.own(-1, s.v_dot[:, -1]),
    ),
    Erratum(
        "003", "eqs. (62), (64)",
        "⁴ω4 and ⁴ω̇4 are printed (0, 0, q̇1) and (0, 0, q̈1) (again in eq. 68); z4 points down (eq. 20, "
        "⁰₄[R]₃₃ = −1), so ⁰₄[R]ᵀ·(0, 0, q̇1) = (0, 0, −q̇1) and likewise −q̈1. Evaluated side by side, (⁴ω4, ⁴ω̇4).",
        r"{}^4\overline{\omega}_4 = (0, 0, \dot{q}_1)^T,\; {}^4\dot{\overline{\omega}}_4 = (0, 0, \ddot{q}_1)^T",
        r"{}^4\overline{\omega}_4 = (0, 0, -\dot{q}_1)^T,\; {}^4\dot{\overline{\omega}}_4 = (0, 0, -\ddot{q}_1)^T",
        arm="r2t", printed=_003_omega4_own(True), corrected=_003_omega4_own(False),
        reference=lambda s: np.concatenate([s.own(-1, s.omega[:, -1]), s.own(-1, s.omega_dot[:, -1])], axis=-1),
    ),
    Erratum(
        "003", "eq. (22)",
        "The case table of A tan 2(sα; cα) gives π/2 + α for sα > 0, cα < 0 and −π/2 + α for sα < 0, cα ≥ 0; "
        "with α = arctan(sα/cα) these are π + α and α (with α = arctan|sα/cα|: π − α and −α). The case "
        "sα = 0, cα < 0, the one eq. (23) uses (A tan 2(0; −1) = π), is in none of the four rows. Evaluated on "
        "γ_z of Drake's tool rotation against eq. (23)'s γ_z = π/2 + q1: wrong exactly in the 2nd and 4th "
        "quadrants.",
        r"\mathrm{A\,tan\,2}(s\alpha; c\alpha) = \alpha,\ \pi/2 + \alpha,\ \pi + \alpha,\ -\pi/2 + \alpha"
        r"\quad (\mathrm{I}, \mathrm{II}, \mathrm{III}, \mathrm{IV})",
        r"\mathrm{A\,tan\,2}(s\alpha; c\alpha) = \alpha,\ \pi + \alpha,\ -\pi + \alpha,\ \alpha"
        r"\quad (\alpha = \arctan(s\alpha / c\alpha))",
        arm="r2t", printed=_003_atan2(True), corrected=_003_atan2(False),
        reference=lambda s: np.pi / 2 + s.q[:, 0], angle=True, affects=_003_atan2_affects,
    ),
    # ------------------------------------------------------------------ paper 004
    Erratum(
        "004", "eq. (7)",
        "The general formula of p_{i+1} starts with R_z1(φ_i) and r_i; eqs. (3)-(6) start every point with "
        "R_z1(φ1) and r1. As printed it is right only for i = 1 (p2); p3 … p7 turn about the wrong angle and "
        "start from the wrong segment. Evaluated for p2 … p7.",
        r"p_{i+1} = R_{z1}(\phi_i) [r_i + \sum_{k=1}^{i} \prod_{j=1}^{k} (R_{y(j+1)}(\vartheta_{j+1})"
        r" R_{z(j+1)}(\phi_{j+1})) r_{k+1}]",
        r"p_{i+1} = R_{z1}(\phi_1) [r_1 + \sum_{k=1}^{i} \prod_{j=1}^{k} (R_{y(j+1)}(\vartheta_{j+1})"
        r" R_{z(j+1)}(\phi_{j+1})) r_{k+1}]",
        arm="urm6", printed=_004_eq7(True), corrected=_004_eq7(False), reference=_004_points_drake,
    ),
    Erratum(
        "004", "eq. (22)",
        "The homogeneous general formula starts with T_z1(φ_i); eqs. (11)-(21) start every point with "
        "T_z1(φ1). As printed it is right only for i = 1 (p2). Evaluated for p2 … p7.",
        r"p_{i+1} = T_{z1}(\phi_i) \prod_{j=1}^{i} (T_{y(j+1)}(\vartheta_{j+1}, r_j) T_{z(j+1)}(\phi_{j+1}))"
        r" r_{i+1}",
        r"p_{i+1} = T_{z1}(\phi_1) \prod_{j=1}^{i} (T_{y(j+1)}(\vartheta_{j+1}, r_j) T_{z(j+1)}(\phi_{j+1}))"
        r" r_{i+1}",
        arm="urm6", printed=_004_eq22(True), corrected=_004_eq22(False), reference=_004_points_drake,
    ),
    # ------------------------------------------------------------------ paper 000
    Erratum(
        "000", "eq. (37)",
        "T_Z5(q1) is printed with its middle row (0 0 0 0); a rotation about y keeps y: (0 1 0 0), as in the "
        "m-file of Fig. 21. With the printed matrix y0M of the y-up form would be L1 for every q.",
        r"T_{Z5}(q_1) = [[c q_1, 0, s q_1, 0], [0, 0, 0, 0], [-s q_1, 0, c q_1, 0], [0, 0, 0, 1]]",
        r"T_{Z5}(q_1) = [[c q_1, 0, s q_1, 0], [0, 1, 0, 0], [-s q_1, 0, c q_1, 0], [0, 0, 0, 1]]",
        arm="rrrr", printed=_yup("eq37"), corrected=_yup("fixed"), reference=_tool_position_yup,
    ),
    Erratum(
        "000", "eq. (38)",
        "The matrix is labelled T_Z2(L2) but holds L1, and eq. (36) uses T_Z2(L1); read as labelled it would lift "
        "the arm by L2.",
        r"T_{Z2}(L_2)",
        r"T_{Z2}(L_1)",
        arm="rrrr", printed=_yup("eq38"), corrected=_yup("fixed"), reference=_tool_position_yup,
    ),
    Erratum(
        "000", "Fig. 16, T04 entry (2, 3)",
        "The DH form's T04 has cos(q1) in row 2, column 3; the z axis of frame 1 (and 4) is (s1, −c1, 0), so the "
        "entry is −cos(q1), as the y-up form's Fig. 23 (row 3 = −row 2 of the DH form) confirms. The minus sign "
        "may have been lost in the PDF extraction.",
        r"T_{04}[2, 3] = \cos(q_1)",
        r"T_{04}[2, 3] = -\cos(q_1)",
        arm="rrrr", printed=_000_T04_entry_23(True), corrected=_000_T04_entry_23(False),
        reference=lambda s: s.pose[:, -1, 1, 2],
    ),
    Erratum(
        "000", "eq. (24)",
        "'after installation q1 = π/2' introduces T_Z4(π/2), whose angle is the DH twist α1 = π/2, not q1.",
        r"q_1 = \pi/2", r"\alpha_1 = \pi/2",
    ),
    Erratum(
        "000", "eq. (48)",
        "Introduced as 'position vector r4M of point M of member 4', eq. (48) repeats T12 = T_Z6(q2) T_Z1(L2); "
        "r4M = [0 0 0 1]ᵀ (eq. 20) is meant.",
        r"T_{12} = T_{Z6}(q_2) T_{Z1}(L_2)", r"r_{4M} = [0\ 0\ 0\ 1]^T",
    ),
    Erratum(
        "000", "Fig. 14 (m-file)",
        "The DH m-file cannot run: T01z4, T12z1, T23z6, T23z1 are used but never defined, the T34 lines are "
        "corrupted, 'T04=T04*T4M' stands for r0M=T04*r4M, and 'x0M=r0M(2,1)' is the y component.",
        r"\texttt{T01=T01z3*T01z6*T01z4}\ (\texttt{T01z4}\ \text{undefined})",
        r"\texttt{T01z4=[1 0 0 0;0 cos(pi/2) -sin(pi/2) 0;0 sin(pi/2) cos(pi/2) 0;0 0 0 1]}, \dots,"
        r"\ \texttt{r0M=T04*r4M}",
    ),
    Erratum(
        "000", "Fig. 21 (m-file)",
        "The y-up m-file writes 'ccs(q1)' for cos(q1) and mixes the names rOM/r0M and xOM/x0M (letter O and "
        "digit 0), so x0M=r0M(1,1) and r_OM=sqrt(xOM^2+…) refer to undefined variables.",
        r"\texttt{ccs(q1)},\ \texttt{rOM=T04*r4M; x0M=r0M(1,1)}",
        r"\texttt{cos(q1)},\ \texttt{r0M=T04*r4M; x0M=r0M(1,1)}",
    ),
    Erratum(
        "000", "eq. (6)",
        "The quintic of θ2 is printed θ2(t) = b1 t³ + b2 t⁴ + …, and the line above it repeats θ1 with b1 for every "
        "coefficient; eq. (4) is meant: θ2(t) = b1 t⁵ + b2 t⁴ + b3 t³ + b4 t² + b5 t + θ2(0).",
        r"\theta_2(t) = b_1 t^3 + b_2 t^4 + b_3 t^3 + b_4 t^2 + b_5 t + \theta_2(0)",
        r"\theta_2(t) = b_1 t^5 + b_2 t^4 + b_3 t^3 + b_4 t^2 + b_5 t + \theta_2(0)",
    ),
    # ------------------------------------------------------------------ paper 001
    Erratum(
        "001", "eq. (5), entry (1, 4)",
        "p_x of T04 is printed with 'a3 s1 s2 s3'; Rz(θ1) applied to eq. (4) gives a3 c1 s2 s3 "
        "(the (2, 4) entry, with s1, is right).",
        r"p_x = a_3 c_1 c_2 c_3 + a_2 c_1 c_2 - a_3 s_1 s_2 s_3 - d_2 s_1",
        r"p_x = a_3 c_1 c_2 c_3 + a_2 c_1 c_2 - a_3 c_1 s_2 s_3 - d_2 s_1",
        arm="arm4r", overrides=_ARM4R_OFFSET, printed=_001_x_eq5(True), corrected=_001_x_eq5(False),
        reference=lambda s: s.pose[:, -1, 0, 3],
    ),
    Erratum(
        "001", "eq. (10)",
        "Φ is printed A tan 2(p_x, p_y); with p_x = ρ cos Φ, p_y = ρ sin Φ it is A tan 2(p_y, p_x), as eq. (11) "
        "then uses. Evaluated through eq. (11), θ1 on the configuration's root.",
        r"\Phi = \mathrm{A\,tan\,2}(p_x, p_y)",
        r"\Phi = \mathrm{A\,tan\,2}(p_y, p_x)",
        arm="arm4r", overrides=_ARM4R_OFFSET, printed=_001_theta1(True), corrected=_001_theta1(False),
        reference=lambda s: s.q[:, 0], angle=True,
    ),
    Erratum(
        "001", "eq. (15), entry (3, 4)",
        "⁰₃T⁻¹ has d2 in row 3, column 4; −R03ᵀ p03 gives −d2. Evaluated as the position column of "
        "⁰₃T⁻¹ ⁰₄T, which must be that of ³₄T, (a3, 0, 0).",
        r"{}^0_3T^{-1}[3, 4] = d_2",
        r"{}^0_3T^{-1}[3, 4] = -d_2",
        arm="arm4r", overrides=_ARM4R_OFFSET, printed=_001_T03_inverse_times_T04(True),
        corrected=_001_T03_inverse_times_T04(False), reference=_001_reference_T34_position,
    ),
    Erratum(
        "001", "eq. (17)",
        "The common denominator of s23 and c23 is printed p_x² + (c1 p_x + s1 p_y)²; solving eq. (16) gives "
        "p_z² + (c1 p_x + s1 p_y)². (It cancels in the A tan 2 of eq. 18.)",
        r"s_{23}, c_{23} = \dots / (p_x^2 + (c_1 p_x + s_1 p_y)^2)",
        r"s_{23}, c_{23} = \dots / (p_z^2 + (c_1 p_x + s_1 p_y)^2)",
        arm="arm4r", overrides=_ARM4R_OFFSET, printed=_001_s23_c23(True), corrected=_001_s23_c23(False),
        reference=lambda s: _stack(np.sin(s.q[:, 1] + s.q[:, 2]), np.cos(s.q[:, 1] + s.q[:, 2])),
    ),
    Erratum(
        "001", "eq. (19)",
        "Printed 'θ1 = θ23 − θ3'; θ2 = θ23 − θ3 is meant (θ23 = θ2 + θ3, eq. 18). Read with θ1 in place of θ3, "
        "θ2 = θ23 − θ1. armlab.kinematics.ik_closed_form.arm4r_ik implements the corrected form.",
        r"\theta_1 = \theta_{23} - \theta_3 \quad(\text{read as } \theta_2 = \theta_{23} - \theta_1)",
        r"\theta_2 = \theta_{23} - \theta_3",
        arm="arm4r", overrides=_ARM4R_OFFSET, printed=_001_theta2(True), corrected=_001_theta2(False),
        reference=lambda s: s.q[:, 1], angle=True,
    ),
    Erratum(
        "001", "eqs. (20)-(21)",
        "Elements (1, 2) and (2, 2) of ³₄T are −s4 and c4, not s4 and … (eq. 20); eq. (21)'s "
        "A tan 2(c1 c23 o_x + s1 c23 o_y − s23 o_z, c1 s23 o_x + s1 s23 o_y + c23 o_z) is A tan 2(−s4, −c4) = θ4 ± π. "
        "Both arguments need a minus sign.",
        r"\theta_4 = \mathrm{A\,tan\,2}(c_1 c_{23} o_x + s_1 c_{23} o_y - s_{23} o_z,\;"
        r" c_1 s_{23} o_x + s_1 s_{23} o_y + c_{23} o_z)",
        r"\theta_4 = \mathrm{A\,tan\,2}(-(c_1 c_{23} o_x + s_1 c_{23} o_y - s_{23} o_z),\;"
        r" -(c_1 s_{23} o_x + s_1 s_{23} o_y + c_{23} o_z))",
        arm="arm4r", overrides=_ARM4R_OFFSET, printed=_001_theta4(True), corrected=_001_theta4(False),
        reference=lambda s: s.q[:, 3], angle=True,
    ),
)


def check(samples: int = 100, seed: int = 0, paper: str | None = None) -> list[tuple[Erratum, float, float]]:
    """``(erratum, printed error, corrected error)`` for every evaluable erratum (of ``paper``, or all), against Drake.

    Each is evaluated at ``samples`` random configurations within the arm's joint limits
    (unlimited joints in ±2π), with rates and accelerations drawn from N(0, 1); each erratum draws
    from its own generator (``seed`` and its place in :data:`ERRATA`), so one paper's errata can be
    checked alone with the numbers a check of all of them gives.
    """
    out = []
    for k, erratum in enumerate(ERRATA):
        if not erratum.evaluable or erratum.arm is None or paper not in (None, erratum.paper):
            continue
        rng = np.random.default_rng([seed, k])
        arm = get_arm(erratum.arm, **erratum.overrides)
        lo, hi = arm.limit_arrays(unlimited=2 * np.pi)
        q = rng.uniform(lo, hi, size=(samples, arm.n))
        sample = drake_sample(arm, q, rng.normal(size=q.shape), rng.normal(size=q.shape))
        out.append((erratum, *erratum.errors(sample)))
    return out
