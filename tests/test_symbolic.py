"""Symbolic kinematics (sympy) against the numeric modules, Drake, finite differences and the papers' prints."""

from __future__ import annotations

import functools

import numpy as np
import pytest
import sympy as sp
from helpers import arm_and_plant, assert_rounding_close, random_q

from armlab.kinematics import basic_movements
from armlab.kinematics import symbolic as sym
from armlab.kinematics.basic_movements import T_Z2, T_Z5, rrrr_dh_chain, rrrr_yup_chain
from armlab.kinematics.iterative import iterative_kinematics
from armlab.models import get_arm

N = 100
TOL = 1e-9


@functools.cache
def drake_end_point(name: str, seed: int) -> tuple[np.ndarray, ...]:
    """(q, q̇, q̈, X_WT (N,4,4), v (N,3), a (N,3)) of the tool frame from Drake's own queries.

    Position: CalcRelativeTransform(world, tool); velocity: CalcJacobianTranslationalVelocity·q̇;
    acceleration: the same Jacobian·q̈ + CalcBiasTranslationalAcceleration.
    """
    from pydrake.multibody.tree import JacobianWrtVariable

    arm, plant, ctx = arm_and_plant(name)
    rng = np.random.default_rng(seed)
    q = random_q(arm, rng, N)
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
    world, tool = plant.world_frame(), plant.GetFrameByName(arm.tool_name)
    X, v, a = np.empty((N, 4, 4)), np.empty((N, 3)), np.empty((N, 3))
    for k in range(N):
        plant.SetPositions(ctx, q[k])
        plant.SetVelocities(ctx, qd[k])
        X[k] = plant.CalcRelativeTransform(ctx, world, tool).GetAsMatrix4()
        J = plant.CalcJacobianTranslationalVelocity(ctx, JacobianWrtVariable.kV, tool, np.zeros(3), world, world)
        bias = plant.CalcBiasTranslationalAcceleration(ctx, JacobianWrtVariable.kV, tool, np.zeros(3), world, world)
        v[k] = J @ qd[k]
        a[k] = J @ qdd[k] + bias[:, 0]
    return q, qd, qdd, X, v, a


@pytest.mark.slow
def test_position_rotation_velocity_acceleration_match_numeric_modules_and_drake(arm_name):
    arm, _, _ = arm_and_plant(arm_name)
    q, qd, qdd, X, v, a = drake_end_point(arm_name, 1)
    f = sym.arm_kinematics(get_arm(arm_name)).numeric()
    fk = arm.forward(q)  # the paper's numeric forward kinematics
    motion = iterative_kinematics(arm.table, q, qd, qdd)  # paper 003 eqs. (24)-(27)
    position, rotation = f.position(q), f.rotation(q)
    velocity, acceleration = f.velocity(q, qd), f.acceleration(q, qd, qdd)
    np.testing.assert_allclose(position, fk.tool[:, :3, 3], atol=TOL, rtol=0)
    np.testing.assert_allclose(position, X[:, :3, 3], atol=TOL, rtol=0)
    np.testing.assert_allclose(rotation, fk.tool[:, :3, :3], atol=TOL, rtol=0)
    np.testing.assert_allclose(rotation, X[:, :3, :3], atol=TOL, rtol=0)
    np.testing.assert_allclose(velocity, motion.v_0[:, -1], atol=TOL, rtol=0)
    np.testing.assert_allclose(velocity, v, atol=TOL, rtol=0)
    np.testing.assert_allclose(acceleration, motion.vd_0[:, -1], atol=TOL, rtol=0)
    np.testing.assert_allclose(acceleration, a, atol=TOL, rtol=0)


def test_finite_differences_of_position_and_velocity(arm_name):
    """Central differences along q(τ) = q + q̇ τ + q̈ τ²/2 against the symbolic v and a.

    With h = 1e-5 the truncation error is h²/6·|d³x/dτ³| ≲ 1e-10·(|q̇|³ + …)·(arm size ≤ 1 m)
    and the rounding error about ε·|x|/h ≈ 1e-11, so 1e-7 is a bound with a wide margin
    that still catches any wrong term (those are of order 1).
    """
    q, qd, qdd, *_ = drake_end_point(arm_name, 2)
    f = sym.arm_kinematics(get_arm(arm_name)).numeric()
    h = 1e-5

    def path(tau: float) -> tuple[np.ndarray, np.ndarray]:
        return q + qd * tau + qdd * tau**2 / 2, qd + qdd * tau

    fd_v = (f.position(path(h)[0]) - f.position(path(-h)[0])) / (2 * h)
    np.testing.assert_allclose(fd_v, f.velocity(q, qd), atol=1e-7, rtol=0)
    fd_a = (f.velocity(*path(h)) - f.velocity(*path(-h))) / (2 * h)
    np.testing.assert_allclose(fd_a, f.acceleration(q, qd, qdd), atol=1e-7, rtol=0)


def test_symbolic_basic_movements_equal_the_numeric_ones(rng):
    x = rng.uniform(-5, 5, size=N)
    s = sp.Symbol("s", real=True)
    for name in ("T_Z1", "T_Z2", "T_Z3", "T_Z4", "T_Z5", "T_Z6"):
        f = sym.batch_function(list(getattr(sym, name)(s)), [(s,)])
        numeric = getattr(basic_movements, name)
        np.testing.assert_allclose(f(x[:, None]).reshape(N, 4, 4), numeric(x), atol=1e-15, rtol=0, err_msg=name)


@pytest.mark.parametrize("form", ["dh", "yup"])
def test_rrrr_chain_equals_basic_movements_module(form, rng):
    symbolic = sym.rrrr_dh() if form == "dh" else sym.rrrr_yup()
    numeric = (rrrr_dh_chain if form == "dh" else rrrr_yup_chain)
    q = rng.uniform(-2 * np.pi, 2 * np.pi, size=(N, 4))
    L = rng.uniform(0.1, 1.0, size=(N, 4))
    chain = numeric(q, tuple(L.T))  # each length is a batch too
    for T_sym, T_num in zip(symbolic.chain, chain, strict=True):
        f = sym.batch_function(list(T_sym), [symbolic.q, symbolic.L])
        np.testing.assert_allclose(f(q, L).reshape(N, 4, 4), T_num, atol=1e-12, rtol=0)
    f = sym.batch_function([*symbolic.r0M, symbolic.norm], [symbolic.q, symbolic.L])
    T04 = chain[0] @ chain[1] @ chain[2] @ chain[3]
    np.testing.assert_allclose(f(q, L)[:, :3], T04[:, :3, 3], atol=1e-12, rtol=0)
    np.testing.assert_allclose(f(q, L)[:, 3], np.linalg.norm(T04[:, :3, 3], axis=-1), atol=1e-12, rtol=0)


def test_rrrr_forms_differ_exactly_by_the_base_rotation():
    """x_yup = x_DH, y_yup = z_DH, z_yup = −y_DH, and T04_yup = T_Z4(−π/2)·T04_DH, symbolically."""
    dh, yup = sym.rrrr_dh(), sym.rrrr_yup()
    assert sp.simplify(yup.x0M - dh.x0M) == 0
    assert sp.simplify(yup.y0M - dh.z0M) == 0
    assert sp.simplify(yup.z0M + dh.y0M) == 0
    assert sp.simplify(yup.T04 - sym.T_Z4(-sp.pi / 2) * dh.T04) == sp.zeros(4, 4)
    assert sp.simplify(yup.norm - dh.norm) == 0


def test_eq36_order_does_not_matter(rng):
    """Eq. (36) prints T_Z5(q1)·T_Z2(L1), the m-file of Fig. 21 T_Z2(L1)·T_Z5(q1): they commute."""
    q, L = sp.symbols("q L", real=True)
    assert sym.T_Z5(q) * sym.T_Z2(L) == sym.T_Z2(L) * sym.T_Z5(q)
    x, y = rng.normal(size=2)
    np.testing.assert_allclose(T_Z5(x) @ T_Z2(y), T_Z2(y) @ T_Z5(x), atol=1e-15)


# Paper 000 as printed (Matlab output, Figs. 15 and 22), read through the PDF extraction's
# garbling with the help of Figs. 16 and 23, which print the same entries again.
FIG15 = {
    "x0M": "L2*cos(q1)*cos(q2) + L4*cos(q4)*(cos(q1)*cos(q2)*cos(q3) - cos(q1)*sin(q2)*sin(q3))"
           " - L4*sin(q4)*(cos(q1)*cos(q2)*sin(q3) + cos(q1)*cos(q3)*sin(q2)) + L3*cos(q1)*cos(q2)*cos(q3)"
           " - L3*cos(q1)*sin(q2)*sin(q3)",
    "y0M": "L2*cos(q2)*sin(q1) - L4*cos(q4)*(sin(q1)*sin(q2)*sin(q3) - cos(q2)*cos(q3)*sin(q1))"
           " - L4*sin(q4)*(cos(q2)*sin(q1)*sin(q3) + cos(q3)*sin(q1)*sin(q2)) + L3*cos(q2)*cos(q3)*sin(q1)"
           " - L3*sin(q1)*sin(q2)*sin(q3)",
    "z0M": "L1 + L2*sin(q2) + L4*cos(q4)*(cos(q2)*sin(q3) + cos(q3)*sin(q2))"
           " + L4*sin(q4)*(cos(q2)*cos(q3) - sin(q2)*sin(q3)) + L3*cos(q2)*sin(q3) + L3*cos(q3)*sin(q2)",
}
FIG22 = {
    "x0M": FIG15["x0M"],
    "y0M": FIG15["z0M"],
    "z0M": "L4*cos(q4)*(sin(q1)*sin(q2)*sin(q3) - cos(q2)*cos(q3)*sin(q1)) - L2*cos(q2)*sin(q1)"
           " + L4*sin(q4)*(cos(q2)*sin(q1)*sin(q3) + cos(q3)*sin(q1)*sin(q2)) - L3*cos(q2)*cos(q3)*sin(q1)"
           " + L3*sin(q1)*sin(q2)*sin(q3)",
}


@pytest.mark.parametrize("form, printed", [("dh", FIG15), ("yup", FIG22)], ids=["fig15", "fig22"])
def test_paper_000_printed_components(form, printed):
    symbolic = sym.rrrr_dh() if form == "dh" else sym.rrrr_yup()
    names = {s.name: s for s in (*symbolic.q, *symbolic.L)}
    for key, text in printed.items():
        paper = sp.sympify(text, locals=names)
        assert sp.expand(paper - getattr(symbolic, key)) == 0, key


@pytest.mark.slow
def test_end_point_kinematics_is_the_time_derivative(rng):
    """Paper 000's constant-rate run q_i = ω_i t: d/dt r(ω t) equals v with q̇ = ω, and again for a."""
    dh = sym.rrrr_dh()
    motion = dh.motion()
    omegas = sp.symbols("w1:5", real=True)
    r_t = sym.constant_rate(motion.position, motion, omegas)
    v_t = sym.constant_rate(motion.velocity, motion, omegas)
    a_t = sym.constant_rate(motion.acceleration, motion, omegas)
    assert sp.expand(r_t.diff(sym.t) - v_t) == sp.zeros(3, 1)
    assert sp.expand(v_t.diff(sym.t) - a_t) == sp.zeros(3, 1)
    # the chain rule written out: v = (∂r/∂q) q̇, a = (∂v/∂q) q̇ + (∂v/∂q̇) q̈
    J = motion.position.jacobian(motion.q)
    assert sp.expand(motion.velocity - J * sp.Matrix(motion.qd)) == sp.zeros(3, 1)
    a = motion.velocity.jacobian(motion.q) * sp.Matrix(motion.qd) + motion.velocity.jacobian(motion.qd) * sp.Matrix(
        motion.qdd)
    assert sp.expand(motion.acceleration - a) == sp.zeros(3, 1)


def test_rrrr_constant_rate_run_matches_numeric_time_differences():
    """Figs. 18-19: L = (0.2, 0.4, 0.3, 0.2) m, ω = (7, 0.05, 0.05, 0.05) rad/s, t = 0:0.05:15 s."""
    f = sym.arm_kinematics(get_arm("rrrr")).numeric()
    omega = np.array([7.0, 0.05, 0.05, 0.05])
    t = np.arange(0.0, 15.0 + 1e-12, 0.05)
    q = t[:, None] * omega
    h = 1e-5
    fd = (f.position((t[:, None] + h) * omega) - f.position((t[:, None] - h) * omega)) / (2 * h)
    v = f.velocity(q, np.broadcast_to(omega, q.shape))
    np.testing.assert_allclose(fd, v, atol=1e-7, rtol=0)  # h²/6·|x'''| ≤ 1e-10·7³·0.9 ≈ 3e-8
    a = f.acceleration(q, np.broadcast_to(omega, q.shape), np.zeros_like(q))
    fd_a = (f.velocity((t[:, None] + h) * omega, np.broadcast_to(omega, q.shape))
            - f.velocity((t[:, None] - h) * omega, np.broadcast_to(omega, q.shape))) / (2 * h)
    np.testing.assert_allclose(fd_a, a, atol=1e-6, rtol=0)  # h²/6·|x''''| ≤ 1e-10·7⁴·0.9 ≈ 2e-7


def test_r2t_eq20_rotation_and_corrected_position():
    s = sym.r2t()
    q1, q2, q3 = s.q
    l1, l2, l3, l4, l5 = s.l
    c1, s1 = sp.cos(q1), sp.sin(q1)
    assert s.R04 == sp.Matrix([[-s1, c1, 0], [c1, s1, 0], [0, 0, -1]])  # eq. (20) as printed
    assert sp.expand(s.p4 - sp.Matrix([l3 * c1 - (q3 + l4) * s1, l3 * s1 + (q3 + l4) * c1, l1 + l2 + q2 - l5])) == (
        sp.zeros(3, 1))
    assert s.omega4 == sp.Matrix([0, 0, s.qd[0]])  # eq. (46)
    assert s.omega4_dot == sp.Matrix([0, 0, s.qdd[0]])  # eq. (48)


def test_r2t_end_effector_motion_matches_iterative_algorithm_and_drake():
    arm, _, _ = arm_and_plant("r2t")
    q, qd, qdd, X, v, a = drake_end_point("r2t", 3)
    s = sym.r2t()
    l = np.array([arm.parameters[f"l{i}"] for i in range(1, 6)])
    motion = iterative_kinematics(arm.table, q, qd, qdd)
    R = X[:, :3, :3]
    for key, expected, drake in (
        ("p4", arm.forward(q).tool[:, :3, 3], X[:, :3, 3]),
        ("omega4", motion.w_0[:, -1], None),
        ("v4", motion.v_0[:, -1], v),
        ("omega4_dot", motion.wd_0[:, -1], None),
        ("v4_dot", motion.vd_0[:, -1], a),
        ("v4_own", motion.v_i[:, -1], np.einsum("nji,nj->ni", R, v)),
        ("v4_dot_own", motion.vd_i[:, -1], np.einsum("nji,nj->ni", R, a)),
        ("v3", motion.v_0[:, 2], None),
        ("v3_dot", motion.vd_0[:, 2], None),
        ("omega3_dot", motion.wd_0[:, 2], None),
        ("v3_dot_own", motion.vd_i[:, 2], None),
    ):
        value = sym.batch_function(list(getattr(s, key)), [s.q, s.qd, s.qdd, s.l])(q, qd, qdd, l)
        np.testing.assert_allclose(value, expected, atol=TOL, rtol=0, err_msg=key)
        if drake is not None:
            np.testing.assert_allclose(value, drake, atol=TOL, rtol=0, err_msg=key)


@pytest.mark.slow
def test_latex_table_labels_and_sources():
    items = sym.latex_table(include_accelerations=False)
    sources = {item.source for item in items}
    for expected in ("000 Fig. 15", "000 Fig. 16", "000 Fig. 17", "000 Fig. 22", "000 Fig. 23",
                     "003 eq. (20)", "003 eq. (21), corrected", "003 eq. (47), corrected", "003 eq. (49), corrected"):
        assert expected in sources
    assert len({(item.source, item.label) for item in items}) == len(items)
    assert all(item.latex and "\\" in item.latex for item in items)
    assert not any(r"\mathbf{a}_{0M}" in item.label for item in items)
    r2t_p4 = next(item for item in items if item.source == "003 eq. (21), corrected")
    assert sp.latex(sym.r2t().p4, mat_delim="[") == r2t_p4.latex


def test_batches_of_any_shape_and_bad_input(rng):
    f = sym.arm_kinematics(get_arm("arm4r")).numeric()
    q = rng.normal(size=(3, 5, 4))
    assert f.position(q).shape == (3, 5, 3)
    assert f.rotation(q).shape == (3, 5, 3, 3)
    assert f.acceleration(q, q, q).shape == (3, 5, 3)
    # a single q and a batch go through differently vectorised numpy loops: a few ulps apart, 32 ulps as test_api
    assert_rounding_close(f.position(q[1, 2]), f.position(q)[1, 2], ulps=32)
    with pytest.raises(ValueError, match="expected 4 joint values"):
        f.position(np.zeros(3))
    with pytest.raises(ValueError, match=r"qd\[1\] = nan is not a finite number"):
        f.velocity(np.zeros(4), [0, np.nan, 0, 0])
    with pytest.raises(ValueError, match="no symbolic kinematics for arm 'puma560'"):
        sym.arm_kinematics(get_arm("puma560"))


def test_parameter_overrides_change_the_numbers():
    default = sym.arm_kinematics(get_arm("rr")).numeric().position(np.zeros(2))
    longer = sym.arm_kinematics(get_arm("rr", L2=0.5)).numeric().position(np.zeros(2))
    np.testing.assert_allclose(default, [0.7, 0, 0], atol=1e-15)
    np.testing.assert_allclose(longer, [0.9, 0, 0], atol=1e-15)
