"""Inverse kinematics (armlab.kinematics.ik, its closed forms and numerical solver), checked by forward kinematics
two ways.

Every solution is put back through the paper's forward kinematics (``arm.forward``) and
through Drake's ``CalcRelativeTransform`` on the arm's URDF plant; both must return the
target to 1e-9 m (and a pose's orientation to 1e-9 rad). Paper values: 000 Table 2 and M0
(§2), 001's targets (2, 0, 0) and (1, 1, 1.4), and 001's misprinted eq. (19). Full poses:
a PUMA 560-like DH arm (spherical wrist) has all 8 branches found; closest distances of
unreachable targets against the geometry of a DH arm with a shoulder offset.
"""

from __future__ import annotations

import re
import subprocess
import sys

import numpy as np
import pytest
from helpers import ARM_NAMES, arm_and_plant, random_q
from hypothesis import given, settings
from hypothesis import strategies as st

from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.ik import solve, target_pose
from armlab.kinematics.ik_closed_form import arm4r_ik, r2t_ik, rr_ik
from armlab.kinematics.ik_numeric import numeric_ik
from armlab.kinematics.ik_target import fit_limits, pose, rotation_log
from armlab.kinematics.locating import rotation_about
from armlab.models import get_arm
from armlab.models.read_dh import from_dh
from armlab.models.write_urdf import JointLimits

TOL = 1e-9


def tool_position(arm, q: np.ndarray) -> np.ndarray:
    """The paper's FK: tool origin (..., 3)."""
    return arm.forward(q).tool[..., :3, 3]


def drake_tool_position(name: str, q: np.ndarray) -> np.ndarray:
    """Drake's FK of the arm's URDF: the tool frame's origin in the world, by CalcRelativeTransform."""
    arm, plant, context = arm_and_plant(name)
    full = np.zeros(plant.num_positions())
    for i, joint in enumerate(arm.joint_names):
        full[plant.GetJointByName(joint).position_start()] = q[i]
    plant.SetPositions(context, full)
    X = plant.CalcRelativeTransform(context, plant.world_frame(), plant.GetFrameByName(arm.tool_name))
    return X.translation()


def ik_request(arm, q: np.ndarray) -> tuple[np.ndarray, float | None]:
    """(target, pitch) that configuration ``q`` reaches: rr's target is (x, y); arm4r's pitch θ2+θ3+θ4."""
    p = tool_position(arm, q)
    if arm.name == "rr":
        return p[:2], None
    if arm.name == "arm4r":
        return p, float(q[1] + q[2] + q[3])
    return p, None


def assert_within_limits(arm, q: np.ndarray) -> None:
    """Solutions ``(n,)`` or ``(k, n)`` within the limits; unlimited revolute joints wrapped to (−π, π]."""
    lower, upper = arm.limit_arrays()
    wrap = np.isinf(lower) & arm.revolute
    lower, upper = np.where(wrap, -np.pi, lower), np.where(wrap, np.pi, upper)
    bad = (q < lower) | (q > upper) | (wrap & (q == -np.pi))
    assert not bad.any(), f"{arm.name}: {np.asarray(q)[bad.any(axis=-1)] if q.ndim > 1 else q} outside the limits"


def assert_reaches(arm, solutions: list[np.ndarray], target: np.ndarray) -> None:
    """Every solution within limits and FK∘IK = target (paper FK and Drake FK)."""
    assert solutions, f"no solution for {target}"
    goal = np.append(target, 0.0) if target.size == 2 else target
    q = np.array(solutions)
    assert q.shape == (len(solutions), arm.n)
    assert_within_limits(arm, q)
    miss = np.abs(tool_position(arm, q) - goal).max(axis=-1)
    assert miss.max() <= TOL, f"{arm.name}: FK(IK({target})) misses by {miss.max():.3g} m (q = {q[miss.argmax()]})"
    for s in q:
        miss_drake = np.abs(drake_tool_position(arm.name, s) - goal).max()
        assert miss_drake <= TOL, f"{arm.name}: Drake FK of IK({target}) misses by {miss_drake:.3g} m"


def same_modulo_2pi(arm, a: np.ndarray, b: np.ndarray) -> bool:
    d = a - b
    d = np.where(arm.revolute, (d + np.pi) % (2 * np.pi) - np.pi, d)
    return bool(np.abs(d).max() < 1e-7)


# ------------------------------------------------------------------ FK∘IK, random targets
#: numeric IK (urm6, rrrr) takes seconds per 100 targets: slow, test_property_fk_of_ik_is_target_within_limits
#: checks the same FK∘IK at the same TOL for them
@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in ("urm6", "rrrr") else n
                                  for n in ARM_NAMES])
def test_fk_of_ik_returns_100_random_targets(name: str, rng: np.random.Generator) -> None:
    arm = get_arm(name)
    for q in random_q(arm, rng, 100):
        target, pitch = ik_request(arm, q)
        solutions = solve(arm, target, pitch=pitch, all_solutions=True)
        assert_reaches(arm, solutions, target)
        if arm.closed_form is not None:  # rr, arm4r, r2t: the configuration we started from is among them
            assert any(same_modulo_2pi(arm, s, q) for s in solutions), f"{q} not among {solutions}"


@pytest.mark.slow
@pytest.mark.parametrize("name", ARM_NAMES)
def test_best_solution_is_nearest_to_near(name: str, rng: np.random.Generator) -> None:
    arm = get_arm(name)
    for q in random_q(arm, rng, 10):
        target, pitch = ik_request(arm, q)
        near = fit_limits(arm, q[None, :])[0][0]
        every = solve(arm, target, pitch=pitch, near=near, all_solutions=True)
        d = np.array(every) - near
        unlimited = arm.revolute & np.isinf(arm.limit_arrays()[0])  # an unlimited angle's difference modulo 2π
        distances = np.linalg.norm(np.where(unlimited, (d + np.pi) % (2 * np.pi) - np.pi, d), axis=-1)
        assert np.all(np.diff(distances) >= 0)
        (best,) = solve(arm, target, pitch=pitch, near=near)
        np.testing.assert_array_equal(best, every[0])  # exact: the same solve of the same target in this process
        assert np.linalg.norm(best - near) < 1e-7  # closed forms find q itself; Drake's IK started at q stays


@st.composite
def in_limit_q(draw: st.DrawFn, name: str) -> np.ndarray:
    arm = get_arm(name)
    values = []
    for lim in arm.limits:
        lo, hi = (-2 * np.pi, 2 * np.pi) if lim.lower is None else (lim.lower, lim.upper)
        values.append(draw(st.floats(lo, hi, allow_nan=False, allow_infinity=False)))
    return np.array(values)


@pytest.mark.slow
@pytest.mark.parametrize("name", ARM_NAMES)
@settings(max_examples=25, deadline=None)
@given(data=st.data())
def test_property_fk_of_ik_is_target_within_limits(name: str, data: st.DataObject) -> None:
    arm = get_arm(name)
    q = data.draw(in_limit_q(name))
    target, pitch = ik_request(arm, q)
    assert_reaches(arm, solve(arm, target, pitch=pitch, all_solutions=True), target)


@settings(max_examples=60, deadline=None)
@given(x=st.floats(-0.8, 0.8), y=st.floats(-0.8, 0.8))
def test_property_rr_reachable_iff_in_annulus(x: float, y: float) -> None:
    """rr's limits (±3π/2) admit every angle: solve succeeds exactly on the annulus 0.1 ≤ |t| ≤ 0.7."""
    arm = get_arm("rr")
    target = np.array([x, y])
    distance = np.hypot(x, y)
    if 0.1 + 1e-9 < distance < 0.7 - 1e-9:
        assert_reaches(arm, solve(arm, target, all_solutions=True), target)
    elif distance < 0.1 - 1e-9 or distance > 0.7 + 1e-9:
        with pytest.raises(ValueError, match=r"out of reach.*annulus"):
            solve(arm, target)


@settings(max_examples=40, deadline=None)
@given(q=st.lists(st.floats(-3 * np.pi / 2, 3 * np.pi / 2), min_size=2, max_size=2))
def test_property_rr_both_branches(q: list[float]) -> None:
    """Both branches of rr_ik reach the target; branch 0 has θ2 ≥ 0, branch 1 θ2 ≤ 0."""
    arm = get_arm("rr")
    target = tool_position(arm, np.array(q))[:2]
    branches = rr_ik(target, 0.4, 0.3)
    assert branches[0, 1] >= 0 >= branches[1, 1]
    np.testing.assert_allclose(tool_position(arm, branches)[:, :2], [target, target], rtol=0, atol=TOL)


def test_rr_batch_and_nan_only_for_unreachable(rng: np.random.Generator) -> None:
    arm = get_arm("rr")
    qs = random_q(arm, rng, 50).reshape(5, 10, 2)
    targets = tool_position(arm, qs)[..., :2]
    out = rr_ik(targets, 0.4, 0.3)
    assert out.shape == (5, 10, 2, 2)
    for b in (0, 1):
        np.testing.assert_allclose(tool_position(arm, out[..., b, :])[..., :2], targets, rtol=0, atol=TOL)
    targets[2, 3] = (0.9, 0.0)
    with pytest.raises(ValueError, match=r"target \(0\.9, 0\) is out of reach.*0\.1 m ≤ \|target\| ≤ 0\.7 m"):
        rr_ik(targets, 0.4, 0.3)
    out = rr_ik(targets, 0.4, 0.3, strict=False)
    nan = np.isnan(out).any(axis=(-1, -2))
    assert nan[2, 3] and nan.sum() == 1 and np.isnan(out[2, 3]).all()
    with pytest.raises(ValueError, match=r"\(0\.05, 0\)"):  # one target: never NaN
        rr_ik([0.05, 0.0], 0.4, 0.3, strict=False)


def test_arm4r_and_r2t_batches_equal_one_point_at_a_time(rng: np.random.Generator) -> None:
    """The closed forms over a (4, 5) grid of targets: each entry as solved alone, NaN only where unreachable."""
    arm = get_arm("arm4r", a2=0.7, a3=0.45, d2=0.2)
    qs = random_q(arm, rng, 20).reshape(4, 5, 4)
    targets, pitch = tool_position(arm, qs), qs[..., 1] + qs[..., 2] + qs[..., 3]
    out = arm4r_ik(targets, pitch, 0.7, 0.45, 0.2)
    assert out.shape == (4, 5, 4, 4)
    for i, j in np.ndindex(4, 5):
        # a batch and a single target go through differently vectorised numpy loops (a few ulps apart), which
        # arccos/arctan2 may amplify near a rim: 1e-12 rad, a thousandth of the 1e-9 the solutions are held to
        np.testing.assert_allclose(out[i, j], arm4r_ik(targets[i, j], pitch[i, j], 0.7, 0.45, 0.2), rtol=0, atol=1e-12)
    np.testing.assert_allclose(tool_position(arm, out), np.broadcast_to(targets[..., None, :], out.shape[:-1] + (3,)),
                               rtol=0, atol=TOL)
    targets[1, 2] = (3.0, 0.0, 0.0)
    with pytest.raises(ValueError, match=r"target \(3, 0, 0\) is out of reach of arm4r"):
        arm4r_ik(targets, pitch, 0.7, 0.45, 0.2)
    nan = np.isnan(arm4r_ik(targets, pitch, 0.7, 0.45, 0.2, strict=False)).any(axis=(-1, -2))
    assert nan[1, 2] and nan.sum() == 1

    r2t = get_arm("r2t")
    prm = [r2t.parameters[f"l{i}"] for i in range(1, 6)]
    targets = tool_position(r2t, random_q(r2t, rng, 12).reshape(3, 4, 3))
    out = r2t_ik(targets, *prm)
    assert out.shape == (3, 4, 2, 3)
    for i, j in np.ndindex(3, 4):
        np.testing.assert_allclose(out[i, j], r2t_ik(targets[i, j], *prm), rtol=0, atol=1e-12)  # as arm4r's above
    targets[0, 1] = (0.01, 0.0, 1.0)  # inside the arm offset l3 = 0.1 m
    nan = np.isnan(r2t_ik(targets, *prm, strict=False)).any(axis=(-1, -2))
    assert nan[0, 1] and nan.sum() == 1


# ------------------------------------------------------------------ paper values
# Paper 000, Table 2: segment endpoint angles (deg), by target and branch.
TABLE2 = {
    "A": ((0.4, -0.3), 0, (-74.0, 90.0)),
    "B": ((0.7, 0.0), 0, (0.0, 0.0)),
    "C (reached)": ((0.4, 0.3), 1, (74.0, -90.0)),
    "C (left)": ((0.4, 0.3), 0, (0.0, 90.0)),
    "D (reached)": ((0.1, 0.0), 0, (0.0, 180.0)),
    "D (left)": ((0.1, 0.0), 1, (0.0, -180.0)),
}


@pytest.mark.parametrize("label", TABLE2)
def test_paper000_table2(label: str) -> None:
    target, branch, paper_deg = TABLE2[label]
    theta = np.degrees(rr_ik(target, 0.4, 0.3)[branch])
    # Exact values: θ2 from the law of cosines; θ1 = atan2(y, x) − atan2(L2 s2, L1 + L2 c2), which at
    # A and C (θ2 = ±90°) is ∓2·atan2(0.3, 0.4) = ∓73.7398°; the paper rounds to whole degrees.
    exact_theta1 = np.sign(paper_deg[0]) * 2 * np.degrees(np.arctan2(0.3, 0.4))
    assert abs(theta[0] - exact_theta1) < 1e-4 and abs(theta[1] - paper_deg[1]) < 1e-4, (label, theta)
    if paper_deg[0] != 0:
        assert abs(abs(theta[0]) - 73.7398) < 1e-4, theta
    deviation = theta[0] - paper_deg[0]
    assert abs(deviation) < 0.5, (
        f"{label}: θ1 = {theta[0]:.4f}° vs paper's {paper_deg[0]:g}°: deviation {deviation:+.4f}° "
        "is more than the paper's rounding to whole degrees"
    )


def test_paper000_m0_is_fk_of_start_angles() -> None:
    """§2: M0 ≈ (0.4652, 0.0135) m = FK(−38°, 98°); IK of M0 returns those angles on branch 0."""
    arm = get_arm("rr")
    m0 = tool_position(arm, np.radians([-38.0, 98.0]))[:2]
    np.testing.assert_array_equal(np.round(m0, 4), [0.4652, 0.0135])  # exact: rounded to the paper's 4 decimals
    np.testing.assert_allclose(np.degrees(rr_ik(m0, 0.4, 0.3)[0]), [-38.0, 98.0], rtol=0, atol=1e-9)
    # From the paper's rounded M0 (±5e-5 m), the angles agree within the rounding's effect (≈0.01°).
    np.testing.assert_allclose(np.degrees(rr_ik([0.4652, 0.0135], 0.4, 0.3)[0]), [-38.0, 98.0], atol=0.02)


def test_paper001_targets() -> None:
    arm = get_arm("arm4r")
    stretched = solve(arm, [2.0, 0.0, 0.0], pitch=0.0, all_solutions=True)
    assert any(np.abs(q).max() < 1e-12 for q in stretched), stretched  # "stretches horizontally", q = 0
    target = np.array([1.0, 1.0, 1.4])
    solutions = solve(arm, target, all_solutions=True)  # pitch defaults to 0, "the same state"
    assert_reaches(arm, solutions, target)
    assert len(solutions) == 4
    # Paper 001's stop values are garbled except their start, θ1 = π/4.
    assert abs(solutions[0][0] - np.pi / 4) < 1e-12, solutions[0]
    for q in solutions:
        assert abs(q[1] + q[2] + q[3]) < 1e-12  # pitch 0


def test_paper001_eq19_misprint(rng: np.random.Generator) -> None:
    """Eq. (19) is printed "θ1 = θ23 − θ3"; θ2 = θ23 − θ3 is right; θ2 = θ23 − θ1 is wrong."""
    arm = get_arm("arm4r")
    for q in random_q(arm, rng, 20):
        target, pitch = ik_request(arm, q)
        for t1, t2, t3, t4 in arm4r_ik(target, pitch, 1.0, 1.0, 0.0):
            t23 = t2 + t3  # eq. (18)
            right = np.array([t1, t23 - t3, t3, t4])
            misread = np.array([t1, t23 - t1, t3, t4])  # θ2 = θ23 − θ1
            as_printed = np.array([t23 - t3, t2, t3, t4])  # θ1 overwritten by θ23 − θ3
            assert np.abs(tool_position(arm, right) - target).max() <= TOL
            # The wrist circle (θ2 ↦ p for fixed θ1, θ3) and the z rotation (θ1 ↦ p) are one-to-one
            # mod 2π, so each misreading moves the tool unless its angle error is a multiple of 2π.
            if abs(np.sin((t3 - t1) / 2)) > 1e-3:
                assert np.abs(tool_position(arm, misread) - target).max() > 1e-6
            if abs(np.sin((t2 - t1) / 2)) * np.hypot(target[0], target[1]) > 1e-3:
                assert np.abs(tool_position(arm, as_printed) - target).max() > 1e-6


def test_arm4r_with_other_lengths_and_offset(rng: np.random.Generator) -> None:
    """The derivation holds for d2 ≠ 0 and a2 ≠ a3 (eq. 11's two roots differ then)."""
    arm = get_arm("arm4r", a2=0.7, a3=0.45, d2=0.2)
    for q in random_q(arm, rng, 50):
        target, pitch = ik_request(arm, q)
        rows = arm4r_ik(target, pitch, 0.7, 0.45, 0.2)
        np.testing.assert_allclose(tool_position(arm, rows), np.tile(target, (4, 1)), rtol=0, atol=TOL)
        np.testing.assert_allclose(rows[:, 1] + rows[:, 2] + rows[:, 3], pitch, atol=1e-12)


def test_r2t_closed_form_two_branches(rng: np.random.Generator) -> None:
    arm = get_arm("r2t")
    prm = arm.parameters
    for q in random_q(arm, rng, 20):
        target = tool_position(arm, q)
        rows = r2t_ik(target, prm["l1"], prm["l2"], prm["l3"], prm["l4"], prm["l5"])
        np.testing.assert_allclose(tool_position(arm, rows), np.tile(target, (2, 1)), rtol=0, atol=TOL)
        assert rows[0, 2] + prm["l4"] >= 0 >= rows[1, 2] + prm["l4"]


# ------------------------------------------------------------------ errors
@pytest.mark.parametrize(
    ("name", "target", "shown"),
    [("rr", (1.0, 0.0), "(1, 0)"), ("rr", (0.05, 0.0, 0.0), "(0.05, 0)"), ("arm4r", (5.0, 0.0, 0.0), "(5, 0, 0)"),
     ("r2t", (0.0, 0.0, 0.8), "(0, 0, 0.8)"), ("urm6", (1.0, 0.0, 0.0), "(1, 0, 0)")],
)
def test_unreachable_target(name: str, target: tuple, shown: str) -> None:
    with pytest.raises(ValueError, match=rf"target {re.escape(shown)} is out of reach"):
        solve(get_arm(name), target)


def test_arm4r_target_only_outside_theta2_limit() -> None:
    """Below the shoulder every solution needs θ2 in the gap (45°, 135°) of θ2 ∈ [−225°, 45°] (mod 360°)."""
    arm = get_arm("arm4r")
    azimuth = np.radians(60.0)
    target = np.array([0.3 * np.cos(azimuth), 0.3 * np.sin(azimuth), -1.9])
    candidates = arm4r_ik(target, np.pi / 2, 1.0, 1.0, 0.0)
    np.testing.assert_allclose(tool_position(arm, candidates), np.tile(target, (4, 1)), atol=TOL)  # reachable
    theta2 = np.degrees(candidates[:, 1]) % 360
    assert np.all((theta2 > 45) & (theta2 < 135)), theta2
    with pytest.raises(ValueError, match=r"target \(0\.15, 0\.259808, -1\.9\) is reachable by arm4r only "
                                         r"outside its joint limits: joint2 = .*\[-225°, 45°\]") as info:
        solve(arm, target, pitch=np.pi / 2)
    assert "joint1" not in str(info.value)


def test_numeric_target_only_outside_limits() -> None:
    """A user DH arm (planar 2R, θ2 ∈ [0, 0.5]): Drake reaches FK(0, 1.5) only without limits."""
    table = DHTable((DHRow(1.0, 0.0, 0.0, 0.0), DHRow(1.0, 0.0, 0.0, 0.0)), "standard")
    arm = from_dh(table, [JointLimits(-3.0, 3.0, 10.0, 1.0), JointLimits(0.0, 0.5, 10.0, 1.0)], name="planar2")
    target = tool_position(arm, np.array([0.0, 1.5]))
    with pytest.raises(ValueError, match=r"reachable by planar2 only outside its joint limits: joint2 = "):
        solve(arm, target)
    inside = tool_position(arm, np.array([0.2, 0.3]))
    (q,) = solve(arm, inside, near=[0.2, 0.3])
    assert np.abs(tool_position(arm, q) - inside).max() <= TOL and 0 <= q[1] <= 0.5
    np.testing.assert_allclose(numeric_ik(arm, inside, q0=[0.2, 0.3])[0], q, atol=1e-12)  # row 0: from q0


@pytest.mark.parametrize("name", ARM_NAMES)
@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_target(name: str, bad: float) -> None:
    target = [0.3, bad] if name == "rr" else [0.3, bad, 0.1]
    with pytest.raises(ValueError, match=str(bad)):
        solve(get_arm(name), target)


@pytest.mark.parametrize(("name", "target"), [("rr", [0.1]), ("rr", [0.1, 0.2, 0.0, 0.4]), ("arm4r", [1.0, 2.5]),
                                              ("r2t", [1.0, 2.0, 3.0, 4.0]), ("urm6", [0.25])])
def test_wrong_number_of_coordinates(name: str, target: list[float]) -> None:
    with pytest.raises(ValueError, match=re.escape(str(target))):
        solve(get_arm(name), target)


def test_other_bad_requests() -> None:
    with pytest.raises(ValueError, match=r"z = 0\.5"):
        solve(get_arm("rr"), [0.4, 0.3, 0.5])
    with pytest.raises(ValueError, match=r"pitch = 0\.3 is not an option of urm6's inverse kinematics; it takes none"):
        solve(get_arm("urm6"), [0.1, 0.1, 0.5], pitch=0.3)
    with pytest.raises(ValueError, match=r"near.*expected 4"):
        solve(get_arm("arm4r"), [1.0, 1.0, 1.4], near=[0.0, 0.0])
    with pytest.raises(ValueError, match=r"near\[1\] = nan"):
        solve(get_arm("arm4r"), [1.0, 1.0, 1.4], near=[0.0, np.nan, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"pitch = nan"):
        solve(get_arm("arm4r"), [1.0, 1.0, 1.4], pitch=np.nan)
    with pytest.raises(ValueError, match=r"L2 = -0\.3"):
        rr_ik([0.4, 0.3], 0.4, -0.3)


# ------------------------------------------------------------------ workspace boundary (rr)
def test_rr_exact_on_the_rims() -> None:
    """The half-angle form gives θ2 = 0 exactly at B = (0.7, 0) (arccos gave ∓6e-7°) and ±π at (0.1, 0)."""
    # exact: the half-angle form's 0 on the outer rim
    np.testing.assert_array_equal(rr_ik([0.7, 0.0], 0.4, 0.3), np.zeros((2, 2)))
    inner = rr_ik([0.1, 0.0], 0.4, 0.3)
    np.testing.assert_array_equal(inner[:, 1], [np.pi, -np.pi])  # exact: ±π on the inner rim
    assert np.abs(inner[:, 0]).max() < 1e-15
    arm = get_arm("rr")
    for target in ([0.7, 0.0], [0.1, 0.0], [0.0, -0.7]):  # singular: the two branches coincide, returned once
        (q,) = solve(arm, target, all_solutions=True)
        assert np.abs(tool_position(arm, q)[:2] - target).max() <= TOL
    result = subprocess.run([sys.executable, "-m", "armlab", "ik", "rr", "--target", "0.7,0", "--all"],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0 and result.stdout.splitlines() == ["q (SI) = +0.000000  +0.000000"], result


# ------------------------------------------------------------------ full poses
def drake_tool_pose(arm, plant, q: np.ndarray) -> np.ndarray:
    """Drake's FK of the arm's URDF: the tool frame's pose in the world (4×4), by CalcRelativeTransform."""
    context = plant.CreateDefaultContext()
    full = np.zeros(plant.num_positions())
    for i, joint in enumerate(arm.joint_names):
        full[plant.GetJointByName(joint).position_start()] = q[i]
    plant.SetPositions(context, full)
    return plant.CalcRelativeTransform(context, plant.world_frame(), plant.GetFrameByName(arm.tool_name)).GetAsMatrix4()


def pose_miss(T: np.ndarray, target: np.ndarray) -> tuple[float, float]:
    """(position miss in m, orientation miss in rad = the angle θ of R_targetᵀ R), independently of rotation_log:
    |R − I|_F = 2√2 sin(θ/2) (accurate for small θ, unlike arccos of the trace) and cos θ = (tr R − 1)/2."""
    R = target[:3, :3].T @ T[:3, :3]
    s = np.linalg.norm(R - np.eye(3)) / np.sqrt(2)  # 2 sin(θ/2)
    sin_theta = s * np.sqrt(max(1 - s**2 / 4, 0.0))  # 2 sin(θ/2) cos(θ/2)
    return float(np.linalg.norm(T[:3, 3] - target[:3, 3])), float(np.arctan2(sin_theta, (np.trace(R) - 1) / 2))


def assert_reaches_pose(arm, plant, solutions: list[np.ndarray], target: np.ndarray) -> None:
    """Every solution within limits and reaching the pose to 1e-9 m and 1e-9 rad, by the arm's FK and by Drake's."""
    assert solutions
    for q in solutions:
        assert_within_limits(arm, q)
        for how, T in (("arm.forward", arm.forward(q).tool), ("Drake", drake_tool_pose(arm, plant, q))):
            miss = pose_miss(T, target)
            assert miss[0] <= TOL and miss[1] <= TOL, f"{arm.name}: {how} of {q} misses the pose by {miss}"


#: The PUMA 560's joint limits in the Robotics Toolbox (±deg).
PUMA560_LIMITS_DEG = (160.0, 110.0, 135.0, 266.0, 100.0, 266.0)


def puma560(limited: bool = False):
    """The PUMA 560 of the Robotics Toolbox (standard DH, m, rad); joints unlimited (so all 8 branches count)
    unless ``limited``."""
    a, d = (0.0, 0.4318, 0.0203, 0.0, 0.0, 0.0), (0.0, 0.0, 0.15005, 0.4318, 0.0, 0.0)
    alpha = (np.pi / 2, 0.0, -np.pi / 2, np.pi / 2, -np.pi / 2, 0.0)
    table = DHTable(tuple(DHRow(a[i], alpha[i], d[i], 0.0) for i in range(6)), "standard")
    if limited:
        limits = [JointLimits(-np.radians(v), np.radians(v), 10.0, 1.0) for v in PUMA560_LIMITS_DEG]
        return from_dh(table, limits, name="puma560_limited")
    return from_dh(table, [JointLimits(None, None, 10.0, 1.0)] * 6, name="puma560")


@pytest.mark.slow
def test_puma560_all_eight_branches(rng: np.random.Generator) -> None:
    """A 6R arm with a spherical wrist: 4 arm branches (shoulder, elbow) × 2 wrist flips for generic poses.

    The wrist flip is checked independently: (θ4 + π, −θ5, θ6 + π) gives the same wrist rotation.
    """
    arm = puma560()
    plant = arm.make_plant()
    for q in rng.uniform(-np.pi, np.pi, size=(12, 6)):
        target = arm.forward(q).tool
        solutions = solve(arm, target, all_solutions=True)
        assert len(solutions) == 8, f"{len(solutions)} branches for the pose of {q}"
        assert_reaches_pose(arm, plant, solutions, target)
        flipped = q + [0.0, 0.0, 0.0, np.pi, 0.0, np.pi]
        flipped[4] = -q[4]
        for expected in (q, flipped):
            assert any(same_modulo_2pi(arm, s, expected) for s in solutions), f"{expected} not among {solutions}"
        nearest = solve(arm, target, near=q)[0]
        assert same_modulo_2pi(arm, nearest, q)


@pytest.mark.slow
def test_puma560_within_its_joint_limits(rng: np.random.Generator) -> None:
    """With the Robotics Toolbox's limits the solver returns exactly those of the 8 branches that fit the limits
    (by fit_limits, 2π shifts allowed): the search within the limits loses none of them."""
    free, limited = puma560(), puma560(limited=True)
    bound = np.radians(PUMA560_LIMITS_DEG)
    for q in rng.uniform(-bound, bound, size=(5, 6)):
        target = free.forward(q).tool
        fitted, violations = fit_limits(limited, np.array(solve(free, target, all_solutions=True)))
        expected = fitted[[v is None for v in violations]]
        solutions = solve(limited, target, all_solutions=True)
        assert len(solutions) == len(expected) >= 1
        assert all(any(same_modulo_2pi(limited, s, e) for s in solutions) for e in expected)
        assert_within_limits(limited, np.array(solutions))
        assert any(same_modulo_2pi(limited, s, q) for s in solutions)


def test_puma560_from_a_dh_csv(tmp_path) -> None:
    """The same arm read from a DH table file (angles in radians), through the CLI with --rpy in degrees."""
    rows = ["type,a,alpha,d,theta,lower,upper", "R,0,1.5707963267948966,0,0,,", "R,0.4318,0,0,0,,",
            "R,0.0203,-1.5707963267948966,0.15005,0,,", "R,0,1.5707963267948966,0.4318,0,,",
            "R,0,-1.5707963267948966,0,0,,", "R,0,0,0,0,,"]
    path = tmp_path / "puma.csv"
    path.write_text("\n".join(rows) + "\n")
    q = np.radians([20.0, -30.0, 40.0, 50.0, -60.0, 70.0])
    target = puma560().forward(q).tool
    rpy = np.degrees(rotation_rpy(target[:3, :3]))
    result = subprocess.run(
        [sys.executable, "-m", "armlab", "ik", str(path), "--target=" + ",".join(str(float(v)) for v in target[:3, 3]),
         "--rpy=" + ",".join(str(float(v)) for v in rpy), "--deg", "--all", "--json"],
        capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    import json

    solutions = np.array(json.loads(result.stdout)["solutions"])
    assert solutions.shape == (8, 6)
    assert any(same_modulo_2pi(puma560(), s, q) for s in solutions)


def rotation_rpy(R: np.ndarray) -> np.ndarray:
    """(roll, pitch, yaw) of R = Rz(y)·Ry(p)·Rx(r), by Drake's RollPitchYaw."""
    from pydrake.math import RollPitchYaw, RotationMatrix

    return RollPitchYaw(RotationMatrix(R)).vector()


@pytest.mark.slow
@pytest.mark.parametrize("name", ARM_NAMES)
def test_full_pose_of_random_configurations(name: str, rng: np.random.Generator) -> None:
    """Every paper arm, full-pose targets from FK of random configurations: all solutions reach the pose, and the
    configuration the pose came from is among them (closed forms + orientation check, or the numerical solver)."""
    arm, plant, _ = arm_and_plant(name)
    for q in random_q(arm, rng, 10):
        target = arm.forward(q).tool
        solutions = solve(arm, target, all_solutions=True)
        assert_reaches_pose(arm, plant, solutions, target)
        assert any(same_modulo_2pi(arm, s, q) for s in solutions), f"{q} not among {solutions}"


@pytest.mark.slow
def test_urm6_full_pose_branches_are_distinct(rng: np.random.Generator) -> None:
    arm = get_arm("urm6")
    for q in random_q(arm, rng, 5):
        target = arm.forward(q).tool
        solutions = np.array(solve(arm, target, all_solutions=True))
        d = solutions[:, None, :] - solutions[None, :, :]
        d = np.abs((d + np.pi) % (2 * np.pi) - np.pi).max(axis=-1)
        assert np.all(d[~np.eye(len(solutions), dtype=bool)] > 1e-6), "a solution is returned twice"
        distances = np.linalg.norm(solutions, axis=1)  # urm6's joints are unlimited: wrapped to (−π, π]
        assert np.all(np.diff(distances) >= 0)  # nearest to near = 0 first


def test_pose_and_rotation_log_against_drake(rng: np.random.Generator) -> None:
    """pose(): R = Rz(y)·Ry(p)·Rx(r) as Drake's RollPitchYaw; rotation_log() as Drake's AngleAxis, near 0 and π too."""
    from pydrake.math import RollPitchYaw, RotationMatrix

    for rpy in rng.uniform(-np.pi, np.pi, size=(20, 3)):
        np.testing.assert_allclose(pose([0.1, 0.2, 0.3], rpy)[:3, :3],
                                   RollPitchYaw(rpy).ToRotationMatrix().matrix(), rtol=0, atol=1e-15)
    for angle in [0.0, 1e-12, 1e-7, 0.3, np.pi / 2, 2.0, 3.0, np.pi - 1e-7, np.pi - 1e-12, np.pi]:
        k = rng.normal(size=3)
        k /= np.linalg.norm(k)
        R = rotation_about(k, angle)
        omega = rotation_log(R)
        axis_angle = RotationMatrix(R).ToAngleAxis()
        expected = axis_angle.angle() * axis_angle.axis()
        if angle > np.pi - 1e-6:  # ±π·k are the same rotation
            expected = expected * np.sign(expected @ omega)
        np.testing.assert_allclose(omega, expected, rtol=0, atol=2e-15 + 1e-8 * (angle > 3.0))
        np.testing.assert_allclose(rotation_about(omega / max(np.linalg.norm(omega), 1e-300), np.linalg.norm(omega)),
                                   R, rtol=0, atol=1e-15)
    batch = rotation_about([0.0, 0.0, 1.0], np.linspace(-3, 3, 7))
    np.testing.assert_allclose(rotation_log(batch)[:, 2], np.linspace(-3, 3, 7), rtol=0, atol=1e-15)
    # one rotation (in scalars) as the same rotation in a batch (numpy), at every angle above, about random axes
    axes = rng.normal(size=(10, 3))
    batch = np.array([rotation_about(k / np.linalg.norm(k), angle) for k, angle in
                      zip(axes, [0.0, 1e-12, 1e-7, 0.3, np.pi / 2, 2.0, 3.0, np.pi - 1e-7, np.pi - 1e-12, np.pi],
                          strict=True)])
    np.testing.assert_allclose(np.array([rotation_log(R) for R in batch]), rotation_log(batch), rtol=0, atol=1e-15)


def test_arm4r_pose_sets_the_pitch() -> None:
    """arm4r's θ1 and pitch come from the pose's rotation R04 = Rz(θ1)·Rx(−90°)·Rz(pitch); a pitch too is refused."""
    arm, plant, _ = arm_and_plant("arm4r")
    # Rz(45°)·Ry(0.3)·Rx(−90°) = Rz(45°)·Rx(−90°)·Rz(0.3) (Rx(−90°) takes z to y): θ1 = 45°, pitch 0.3
    target = target_pose(arm, [1.0, 1.0, 1.4], [-np.pi / 2, 0.3, np.pi / 4])
    solutions = solve(arm, target, all_solutions=True)
    assert_reaches_pose(arm, plant, solutions, target)
    assert len(solutions) == 2  # elbow up and down; the other θ1 root turns the tool z axis around
    for q in solutions:
        assert abs(q[0] - np.pi / 4) < 1e-12 and abs(q[1] + q[2] + q[3] - 0.3) < 1e-12
    with pytest.raises(ValueError, match=r"a pitch \(here 0\.1 rad\) is not allowed with a pose target"):
        solve(arm, target, pitch=0.1)
    tilted = target_pose(arm, [1.0, 1.0, 1.4], [-np.pi / 2 + 0.2, 0.3, np.pi / 4])  # tool z axis not horizontal
    with pytest.raises(ValueError, match=r"position is reachable, but not with this orientation"):
        solve(arm, tilted)


@pytest.mark.parametrize(("matrix", "message"), [
    (np.diag([1.0, 1.0, 1.0 + 1e-6, 1.0]), r"not orthonormal \(\|RᵀR − I\| = 2e-06"),
    (np.diag([1.0, 1.0, -1.0, 1.0]), r"determinant −1"),
    (np.vstack([np.eye(4)[:3], [0.0, 0.0, 1.0, 1.0]]), r"last row \[0\.0, 0\.0, 1\.0, 1\.0\]"),
    (np.where(np.eye(4) == 1, np.nan, 0.0), r"target\[0\] = nan"),
])
def test_bad_pose(matrix: np.ndarray, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        solve(get_arm("urm6"), matrix)


# ------------------------------------------------------------------ position-only on a user's 3-DOF arm
def shoulder_arm():
    """Standard DH: a vertical base joint, the shoulder 0.5 m up, two 0.5 m links: reach = a ball about (0, 0, 0.5)."""
    table = DHTable((DHRow(0.0, np.pi / 2, 0.5, 0.0), DHRow(0.5, 0.0, 0.0, 0.0), DHRow(0.5, 0.0, 0.0, 0.0)))
    return from_dh(table, [JointLimits(None, None, 10.0, 1.0)] * 3, name="shoulder3")


@pytest.mark.slow
def test_three_dof_dh_arm_both_elbow_branches(rng: np.random.Generator) -> None:
    """Four branches: elbow flip (θ2 + θ3, −θ3 for equal links) and reaching over (θ1 + π, π − θ2, −θ3) of each."""
    arm = shoulder_arm()
    for q in rng.uniform(-np.pi, np.pi, size=(20, 3)):
        target = tool_position(arm, q)
        solutions = solve(arm, target, all_solutions=True)
        assert len(solutions) == 4
        for s in solutions:
            assert np.abs(tool_position(arm, s) - target).max() <= TOL
        elbow = np.array([q[0], q[1] + q[2], -q[2]])
        for expected in (q, elbow, [q[0] + np.pi, np.pi - q[1], -q[2]], [elbow[0] + np.pi, np.pi - elbow[1], q[2]]):
            assert any(same_modulo_2pi(arm, s, np.asarray(expected)) for s in solutions), (expected, solutions)


@pytest.mark.parametrize("target", [(2.0, 0.0, 0.0), (0.0, -1.5, 3.0), (0.3, 0.2, 0.5), (1e5, 0.0, 0.0)])
def test_unreachable_closest_distance(target: tuple) -> None:
    """The tool reaches the ball of radius a2 + a3 = 1 m about the shoulder s = (0, 0, 0.5) (a2 = a3: no hole), so
    from outside it gets no closer than |t − s| − 1. The reported distance is the minimum over q (to the 6 printed
    digits), not the miss of one start (issue 9: such an arm at (2, 0, 0) was reported 2.02 m away)."""
    arm = shoulder_arm()
    t = np.array(target)
    gap = np.linalg.norm(t - [0.0, 0.0, 0.5]) - 1.0
    if gap <= 0:
        assert np.abs(tool_position(arm, solve(arm, t)[0]) - t).max() <= TOL
        return
    with pytest.raises(ValueError, match=r"out of reach of shoulder3: the tool gets no closer than ([\d.e+]+) m") as e:
        solve(arm, t)
    reported = float(re.search(r"no closer than ([\d.e+]+) m", str(e.value)).group(1))
    assert abs(reported - gap) <= 5e-6 * gap, (reported, gap)


@pytest.mark.parametrize(("argv", "message"), [
    (("urm6", "--target=1e308,0,0"), "target x 1e308 is out of range: allowed -1e6 ≤ x, y, z ≤ 1e6 m"),
    (("rrrr", "--target=-1e308,0,0"), "target x -1e308 is out of range: allowed -1e6 ≤ x, y, z ≤ 1e6 m"),
    (("rr", "--target=0.5,1e300"), "target y 1e300 is out of range: allowed -1e6 ≤ x, y, z ≤ 1e6 m"),
    (("SHOULDER", "--target=0,0,1e7"), "target z 1e7 is out of range: allowed -1e6 ≤ x, y, z ≤ 1e6 m"),
    (("arm4r", "--target=1,1,1.4", "--pitch=1e308"), "pitch 1e308 is out of range: allowed -1e6 ≤ angle ≤ 1e6 rad"),
    (("urm6", "--target=0.2,0.2,0.6", "--rpy=0,1e300,0", "--deg"),
     "rpy 1.74533e298 is out of range: allowed -1e6 ≤ angle ≤ 1e6 rad"),
    (("urm6", "--target=0.2,0.2,0.6", "--near=1e308,0,0,0,0,0"),
     "--near 1e308 is out of range: allowed -1e6 ≤ q ≤ 1e6 rad or m"),
])
def test_huge_values_are_a_range_error(argv: tuple, message: str, tmp_path) -> None:
    """One line on stderr naming the value, exit 2, no traceback and no RuntimeWarning (warnings are errors here);
    before, 1e308 gave an overflow traceback and a pitch of 1e308 a wrong answer (θ4 = 0)."""
    shoulder = tmp_path / "shoulder.csv"
    shoulder.write_text("type,a,alpha,d,theta,lower,upper\nR,0,1.5707963267948966,0.5,0,,\nR,0.5,0,0,0,,\n"
                        "R,0.5,0,0,0,,\n")
    argv = tuple(str(shoulder) if a == "SHOULDER" else a for a in argv)
    result = subprocess.run([sys.executable, "-W", "error", "-m", "armlab", "ik", *argv],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2, result.stderr
    assert result.stderr.startswith(f"armlab: error: {message}") and result.stderr.count("\n") == 1, result.stderr


def test_pose_with_an_orientation_the_arm_cannot_take(rng: np.random.Generator) -> None:
    """rrrr (4 joints) at a reachable position with its orientation tilted by 0.3 rad about the tool x axis: the error
    says the position is reachable but not the orientation, and how close the closest pose found is."""
    arm = get_arm("rrrr")
    q = random_q(arm, rng, 1)[0]
    target = arm.forward(q).tool @ pose([0.0, 0.0, 0.0], [0.3, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"target pose \(.*\) m, rpy \(.*\) rad is out of reach of rrrr: its position "
                                         r"is reachable, but not with this orientation \(the closest pose found from "
                                         r"256 starts is ([\d.e+-]+) m and ([\d.e+-]+) rad away\)") as info:
        solve(arm, target)
    metres, radians = map(float, re.findall(r"is ([\d.e+-]+) m and ([\d.e+-]+) rad away", str(info.value))[0])
    assert 0 <= metres and 0 < radians <= 0.3 + 1e-9  # the pose the target was tilted from is 0.3 rad away


def test_rr_pose_target_in_its_plane() -> None:
    """rr's tool orientation is Rz(θ1 + θ2): a planar pose (yaw only) selects one branch; a roll is out of reach."""
    arm, plant, _ = arm_and_plant("rr")
    for q in (np.array([-0.6, 1.7]), np.array([1.2, -0.9])):
        position = tool_position(arm, q)[:2]
        target = target_pose(arm, position, [0.0, 0.0, q.sum()])
        np.testing.assert_array_equal(target[:3, 3], [*position, 0.0])  # exact: the position copied into the pose
        (solution,) = solve(arm, target, all_solutions=True)
        assert same_modulo_2pi(arm, solution, q)
        assert_reaches_pose(arm, plant, [solution], target)
    with pytest.raises(ValueError, match=r"reachable, but not with this orientation"):
        solve(arm, target_pose(arm, position, [0.1, 0.0, q.sum()]))


@settings(max_examples=200, deadline=None)
@given(value=st.floats(-1e3, 1e3) | st.sampled_from([k * np.pi for k in range(-301, 302, 2)])
       .map(lambda v: float(np.nextafter(v, np.random.default_rng(0).choice([-10.0, 10.0])))))
def test_property_unlimited_angles_wrapped_into_minus_pi_pi(value: float) -> None:
    """fit_limits wraps an unlimited revolute angle into (−π, π] exactly (no ulp beyond π), same angle modulo 2π."""
    arm = get_arm("rrrr")  # joint1 unlimited
    wrapped = fit_limits(arm, np.array([[value, 0.0, 0.0, 0.0]]))[0][0, 0]
    assert -np.pi < wrapped <= np.pi, repr(wrapped)
    assert abs(np.sin(wrapped) - np.sin(value)) < 1e-12 and abs(np.cos(wrapped) - np.cos(value)) < 1e-12


def test_cli_help_says_what_all_means_for_a_numerical_arm() -> None:
    result = subprocess.run([sys.executable, "-m", "armlab", "ik", "--help"], capture_output=True, text=True,
                            timeout=120)
    text = " ".join(result.stdout.split())
    assert "every distinct solution found from 256 starts of the numerical solver" in text
    assert "R = Rz(yaw)·Ry(pitch)·Rx(roll) as in URDF" in text


@pytest.mark.slow
def test_urm6_every_solution_drakes_ik_finds_is_among_ours(rng: np.random.Generator) -> None:
    """Drake's InverseKinematics (position and orientation constraints on the tool frame, SNOPT/IPOPT) from 64
    random starts: each solution it reports lies within Drake's own accuracy (a few mrad) of one of ours, and our
    solutions are further apart than that; so Drake finds no branch we miss."""
    from pydrake.math import RotationMatrix
    from pydrake.multibody.inverse_kinematics import InverseKinematics
    from pydrake.solvers import Solve

    arm, plant, _ = arm_and_plant("urm6")
    index = np.array([plant.GetJointByName(name).position_start() for name in arm.joint_names])
    tool = plant.GetFrameByName(arm.tool_name)
    for q in random_q(arm, rng, 2):
        target = arm.forward(q).tool
        ours = np.array(solve(arm, target, all_solutions=True))
        ik = InverseKinematics(plant)
        ik.AddPositionConstraint(tool, np.zeros(3), plant.world_frame(), target[:3, 3] - 1e-9, target[:3, 3] + 1e-9)
        ik.AddOrientationConstraint(plant.world_frame(), RotationMatrix(target[:3, :3]), tool, RotationMatrix(), 1e-9)
        drake = []
        for start in rng.uniform(-np.pi, np.pi, size=(64, arm.n)):
            guess = np.zeros(plant.num_positions())
            guess[index] = start
            result = Solve(ik.prog(), guess)
            if result.is_success():
                drake.append(result.GetSolution(ik.q())[index])
        assert len(drake) >= 8
        d = np.array(drake)[:, None, :] - ours[None, :, :]
        d = np.abs((d + np.pi) % (2 * np.pi) - np.pi).max(axis=-1)  # (drake, ours), modulo 2π
        separation = np.abs((ours[:, None] - ours[None] + np.pi) % (2 * np.pi) - np.pi).max(axis=-1)
        separation = separation[~np.eye(len(ours), dtype=bool)].min(initial=np.inf)
        assert d.min(axis=1).max() < min(0.03, separation / 4), (d.min(axis=1), separation)


def test_far_near_is_a_range_error_and_a_wrapped_near_counts_modulo_2pi() -> None:
    """near beyond ±1e6 is refused in one line; for unlimited joints near and near + 2π give the same order."""
    arm = get_arm("urm6")
    q = np.radians([15.0, 30.0, 50.0, 130.0, -130.0, -20.0])
    target = arm.forward(q).tool
    with pytest.raises(ValueError, match=r"near 1e308 is out of range: allowed -1e6 ≤ q ≤ 1e6 rad or m"):
        solve(arm, target, near=[1e308, 0, 0, 0, 0, 0])
    shifted = solve(arm, target, near=q + 2 * np.pi * np.array([3, -1, 0, 2, 0, -5]), all_solutions=True)
    np.testing.assert_allclose(shifted, solve(arm, target, near=q, all_solutions=True), rtol=0, atol=1e-12)
    assert same_modulo_2pi(arm, shifted[0], q)


def test_solutions_tied_in_distance_are_in_lexicographic_order_whatever_the_round_off() -> None:
    """arm4r's (1, 1, 1.4): its two elbows with θ1 = 45° are equally far from q = 0 (to round-off, which differs
    between machines). Ties within ORDER_TOL go by q in lexicographic order (θ2 = −50.4° first), and moving
    ``near`` by 1e-12 in any joint, which breaks the tie either way by far more than an ulp, keeps that order."""
    from armlab.kinematics.ik import ORDER_TOL

    arm = get_arm("arm4r")
    first = np.array(solve(arm, [1.0, 1.0, 1.4], all_solutions=True))
    distance = np.linalg.norm(first, axis=-1)
    assert abs(distance[0] - distance[1]) <= ORDER_TOL and abs(first[0, 0] - first[1, 0]) <= 1e-12  # a tie, one θ1
    assert first[0, 1] < first[1, 1]
    np.testing.assert_allclose(np.degrees(first[:2, 1]), [-50.449793, -38.971452], atol=1e-6)  # the README's order
    for joint in range(arm.n):
        for step in (-1e-12, 1e-12):
            near = np.zeros(arm.n)
            near[joint] = step
            again = np.array(solve(arm, [1.0, 1.0, 1.4], near=near, all_solutions=True))
            np.testing.assert_array_equal(again, first)  # exact: the same closed form of the same target
