"""Inverse kinematics (armlab.kinematics.ik), checked by forward kinematics two ways.

Every solution is put back through the paper's forward kinematics (``arm.forward``) and
through Drake's ``CalcRelativeTransform`` on the arm's URDF plant; both must return the
target to 1e-9 m. Paper values: 000 Table 2 and M0 (§2), 001's targets (2, 0, 0) and
(1, 1, 1.4), and 001's misprinted eq. (19).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from conftest import ARM_NAMES, arm_and_plant, random_q
from hypothesis import given, settings
from hypothesis import strategies as st

from armlab.kinematics.dh import DHRow, DHTable
from armlab.kinematics.ik import arm4r_ik, fit_limits, numeric_ik, r2t_ik, rr_ik, solve
from armlab.models import get_arm
from armlab.models.custom import from_dh
from armlab.models.urdf import JointLimits

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
    for i, lim in enumerate(arm.limits):
        if lim.lower is None:
            assert -np.pi < q[i] <= np.pi, f"{arm.joint_names[i]} = {q[i]} not wrapped to (−π, π]"
        else:
            assert lim.lower <= q[i] <= lim.upper, f"{arm.joint_names[i]} = {q[i]} outside {lim}"


def assert_reaches(arm, solutions: list[np.ndarray], target: np.ndarray) -> None:
    """Every solution within limits and FK∘IK = target (paper FK and Drake FK)."""
    assert solutions, f"no solution for {target}"
    goal = np.append(target, 0.0) if target.size == 2 else target
    for q in solutions:
        assert q.shape == (arm.n,)
        assert_within_limits(arm, q)
        miss = np.abs(tool_position(arm, q) - goal).max()
        assert miss <= TOL, f"{arm.name}: FK(IK({target})) misses by {miss:.3g} m (q = {q})"
        miss_drake = np.abs(drake_tool_position(arm.name, q) - goal).max()
        assert miss_drake <= TOL, f"{arm.name}: Drake FK of IK({target}) misses by {miss_drake:.3g} m"


def same_modulo_2pi(arm, a: np.ndarray, b: np.ndarray) -> bool:
    d = a - b
    d = np.where(arm.revolute, (d + np.pi) % (2 * np.pi) - np.pi, d)
    return bool(np.abs(d).max() < 1e-7)


# ------------------------------------------------------------------ FK∘IK, random targets
@pytest.mark.parametrize("name", ARM_NAMES)
def test_fk_of_ik_returns_100_random_targets(name: str, rng: np.random.Generator) -> None:
    arm = get_arm(name)
    for q in random_q(arm, rng, 100):
        target, pitch = ik_request(arm, q)
        solutions = solve(arm, target, pitch=pitch, all_solutions=True)
        assert_reaches(arm, solutions, target)
        if name in ("rr", "arm4r", "r2t"):  # closed form: the configuration we started from is among them
            assert any(same_modulo_2pi(arm, s, q) for s in solutions), f"{q} not among {solutions}"


@pytest.mark.parametrize("name", ARM_NAMES)
def test_best_solution_is_nearest_to_near(name: str, rng: np.random.Generator) -> None:
    arm = get_arm(name)
    for q in random_q(arm, rng, 10):
        target, pitch = ik_request(arm, q)
        near = fit_limits(arm, q[None, :])[0][0]
        every = solve(arm, target, pitch=pitch, near=near, all_solutions=True)
        distances = [np.linalg.norm(s - near) for s in every]
        assert distances == sorted(distances)
        (best,) = solve(arm, target, pitch=pitch, near=near)
        np.testing.assert_array_equal(best, every[0])
        assert np.linalg.norm(best - near) < 1e-7  # closed forms find q itself; Drake's IK started at q stays


@st.composite
def in_limit_q(draw: st.DrawFn, name: str) -> np.ndarray:
    arm = get_arm(name)
    values = []
    for lim in arm.limits:
        lo, hi = (-2 * np.pi, 2 * np.pi) if lim.lower is None else (lim.lower, lim.upper)
        values.append(draw(st.floats(lo, hi, allow_nan=False, allow_infinity=False)))
    return np.array(values)


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
        np.testing.assert_array_equal(out[i, j], arm4r_ik(targets[i, j], pitch[i, j], 0.7, 0.45, 0.2))
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
        np.testing.assert_array_equal(out[i, j], r2t_ik(targets[i, j], *prm))
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
    np.testing.assert_array_equal(np.round(m0, 4), [0.4652, 0.0135])
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
    np.testing.assert_allclose(numeric_ik(arm, inside, q0=[0.2, 0.3]), q, atol=1e-12)


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
    with pytest.raises(ValueError, match=r"pitch = 0\.3 applies only to arm4r"):
        solve(get_arm("urm6"), [0.1, 0.1, 0.5], pitch=0.3)
    with pytest.raises(ValueError, match=r"near.*expected 4"):
        solve(get_arm("arm4r"), [1.0, 1.0, 1.4], near=[0.0, 0.0])
    with pytest.raises(ValueError, match=r"near\[1\] = nan"):
        solve(get_arm("arm4r"), [1.0, 1.0, 1.4], near=[0.0, np.nan, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"pitch = nan"):
        solve(get_arm("arm4r"), [1.0, 1.0, 1.4], pitch=np.nan)
    with pytest.raises(ValueError, match=r"L2 = -0\.3"):
        rr_ik([0.4, 0.3], 0.4, -0.3)
