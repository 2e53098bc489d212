"""Paper 000's trajectories: quintic coefficients, Drake's PiecewisePolynomial, paper motions, bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import ARM_NAMES, random_q

from armlab.kinematics.quintic import (
    ConstantRate,
    Motion,
    PolynomialSegment,
    QuinticSegment,
    evaluate_coefficients,
    quintic_coefficients,
    to_piecewise_polynomial,
)
from armlab.models import get_arm
from armlab.models.rr import ABCD_POINTS
from armlab.planning.motions import paper_motion, point_to_joints, read_segments


def test_paper_000_coefficients_to_4_decimals():
    """§3: a1 = 0.3272, a2 = −1.6362, a3 = 2.1817, b1 = −0.0982, b2 = 0.4909, b3 = −0.6545 (paper values)."""
    paper = np.array([[0.3272, -1.6362, 2.1817], [-0.0982, 0.4909, -0.6545]])
    c = quintic_coefficients(np.radians([-38.0, 98.0]), np.radians([62.0, 68.0]), 2.0)
    np.testing.assert_array_equal(np.round(c[:, :3], 4), paper)  # exact: rounded to the paper's 4 decimals
    np.testing.assert_allclose(c[:, 3:5], 0.0, atol=1e-15)  # a4 = a5 = b4 = b5 = 0
    np.testing.assert_allclose(c[:, 5], np.radians([-38.0, 98.0]), rtol=0, atol=1e-15)  # a6 = θ(0)
    # and the same numbers through the paper motion armlab simulate runs for rr
    # exact: as above
    np.testing.assert_array_equal(np.round(paper_motion(get_arm("rr")).coefficients()[0, :, :3], 4), paper)


def test_coefficients_match_the_closed_form(rng):
    """The matrix solve of eqs. (3)–(6) vs the textbook closed form a1 = 6Δ/T⁵, a2 = −15Δ/T⁴, a3 = 10Δ/T³."""
    q0, qf = rng.uniform(-3, 3, (50, 4)), rng.uniform(-3, 3, (50, 4))
    for tf in (0.1, 2.0, 15.0):
        c = quintic_coefficients(q0, qf, tf)
        d = qf - q0
        expected = np.stack([6 * d / tf**5, -15 * d / tf**4, 10 * d / tf**3, 0 * d, 0 * d, q0], axis=-1)
        np.testing.assert_allclose(c, expected, rtol=1e-9, atol=1e-12 * max(1.0, 1 / tf**5))


def test_rest_to_rest_boundary_conditions(rng):
    q0, qf, tf = rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3), 1.7
    c = quintic_coefficients(q0, qf, tf)
    for tau, q in ((0.0, q0), (tf, qf)):
        np.testing.assert_allclose(evaluate_coefficients(c, np.array(tau)), q, atol=1e-12)
        np.testing.assert_allclose(evaluate_coefficients(c, np.array(tau), 1), 0.0, atol=1e-12)
        np.testing.assert_allclose(evaluate_coefficients(c, np.array(tau), 2), 0.0, atol=1e-11)


def test_derivatives_match_finite_differences(rng):
    c = quintic_coefficients(rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3), 2.0)
    tau, h = np.linspace(0.1, 1.9, 19)[:, None], 1e-5
    for d in (1, 2):
        fd = (evaluate_coefficients(c, tau + h, d - 1) - evaluate_coefficients(c, tau - h, d - 1)) / (2 * h)
        np.testing.assert_allclose(evaluate_coefficients(c, tau, d), fd, atol=1e-8)


def _mixed_motion() -> Motion:
    arm = get_arm("rr")
    abcd = paper_motion(arm, "abcd")
    last = abcd.segments[-1]
    return Motion(abcd.segments + (ConstantRate(last.q_end, np.array([0.3, -0.2]), 1.5, "spin"),))


def test_piecewise_polynomial_equals_the_closed_form():
    """Drake's PiecewisePolynomial reproduces q, q̇, q̈ of every segment exactly (1e-12)."""
    motion = _mixed_motion()
    pp = to_piecewise_polynomial(motion)
    np.testing.assert_array_equal(pp.get_segment_times(), motion.breaks)  # exact: the breaks handed to Drake
    t = np.concatenate([np.linspace(0, motion.duration, 777), motion.breaks])
    closed = motion.evaluate(t)
    for d in range(3):
        drake = np.array([pp.EvalDerivative(ti, d)[:, 0] for ti in t])
        np.testing.assert_allclose(drake, closed[d], rtol=0, atol=1e-12)


def test_constant_rate_is_q0_plus_omega_t():
    seg = ConstantRate(np.array([0.1, 0.2]), np.array([7.0, 0.05]), 15.0)
    # exact: the rate and start as given
    np.testing.assert_array_equal(seg.coefficients(), [[0, 0, 0, 0, 7.0, 0.1], [0, 0, 0, 0, 0.05, 0.2]])
    t = np.linspace(0, 15, 31)
    q, qd, qdd = Motion((seg,)).evaluate(t)
    np.testing.assert_allclose(q, seg.q0 + np.outer(t, seg.omega), atol=1e-12)
    np.testing.assert_allclose(qd, np.broadcast_to(seg.omega, qd.shape), atol=1e-15)
    np.testing.assert_array_equal(qdd, 0.0)  # exact: a line's second derivative
    np.testing.assert_allclose(seg.q_end, [105.1, 0.95])


def test_table_2_segments_start_and_end_at_the_exact_ik_angles():
    """Paper 000 Table 2 (A–B, B–C, C–D, D–A), with 74° exactly 2·atan(3/4) = 73.7398°."""
    arm = get_arm("rr")
    motion = paper_motion(arm, "abcd")
    assert motion.labels == ["A-B", "B-C", "C-D", "D-A"]
    phi = 2 * np.arctan2(0.3, 0.4)  # the paper's 74°
    assert abs(np.degrees(phi) - 73.7398) < 5e-5
    table2 = {  # (θ10, θ20) → (θ1tf, θ2tf), exact
        "A-B": ((-phi, np.pi / 2), (0.0, 0.0)),
        "B-C": ((0.0, 0.0), (phi, -np.pi / 2)),
        "C-D": ((0.0, np.pi / 2), (0.0, np.pi)),
        "D-A": ((0.0, -np.pi), (0.0, -np.pi / 2)),
    }
    paper_deg = {"A-B": ((-74, 90), (0, 0)), "B-C": ((0, 0), (74, -90)), "C-D": ((0, 90), (0, 180)),
                 "D-A": ((0, -180), (0, -90))}
    ends = {"A-B": ("A", "B"), "B-C": ("B", "C"), "C-D": ("C", "D"), "D-A": ("D", "A")}
    for seg in motion.segments:
        for q, exact, deg, point in zip((seg.q0, seg.qf), table2[seg.label], paper_deg[seg.label],
                                        ends[seg.label], strict=True):
            # B = (0.7, 0) lies on the outer rim: in floating point 0.4 + 0.3 > 0.7 by 1e-16, and θ2 = arccos(1 − ε)
            # ≈ √(2ε) amplifies that to ~3e-8 rad, so B is exact only to √eps; everywhere else to round-off.
            tol = 1e-7 if point == "B" else 1e-12
            np.testing.assert_allclose(q, exact, rtol=0, atol=tol)
            np.testing.assert_allclose(np.degrees(q), deg, atol=0.27)  # the paper rounds to whole degrees
            np.testing.assert_allclose(arm.forward(q).points["M"][:2], ABCD_POINTS[point], atol=1e-12)


def test_abcd_runs_split_where_the_joints_jump():
    motion = paper_motion(get_arm("rr"), "abcd")
    assert motion.joins() == [True, False, False]  # C and A are left on the other branch, D at θ2 = −180° not +180°
    runs = motion.runs()
    assert [start for start, _ in runs] == [0.0, 4.0, 6.0]  # exact: sums of integer-valued durations
    assert [m.labels for _, m in runs] == [["A-B", "B-C"], ["C-D"], ["D-A"]]


@pytest.mark.parametrize("name", ARM_NAMES)
def test_paper_motions_are_within_limits_and_rest_to_rest(name):
    arm = get_arm(name)
    motion = paper_motion(arm)
    motion.check_limits(arm)
    t = np.linspace(0, motion.duration, 301)
    q, qd, _ = motion.evaluate(t)
    arm.check_q(q)
    if name != "rrrr":
        np.testing.assert_allclose(qd[[0, -1]], 0.0, atol=1e-12)


def test_arm4r_motion_goes_from_2_0_0_to_1_1_1p4():
    """Paper 001 §3: the tool from (2, 0, 0) to (1, 1, 1.4) m in 2 s, pitch kept."""
    arm = get_arm("arm4r")
    seg = paper_motion(arm).segments[0]
    assert seg.tf == 2.0  # exact: the paper's 2 s
    np.testing.assert_allclose(arm.forward(seg.q0).tool[:3, 3], [2, 0, 0], atol=1e-12)
    np.testing.assert_allclose(arm.forward(seg.qf).tool[:3, 3], [1, 1, 1.4], atol=1e-9)
    assert abs(seg.q0[1:].sum() - seg.qf[1:].sum()) < 1e-12  # the same pitch θ2 + θ3 + θ4


def test_bad_input_is_a_clear_error():
    arm = get_arm("rr")
    q = np.zeros(2)
    for tf in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match=r"tf = .* positive finite"):
            QuinticSegment(q, q, tf)
        with pytest.raises(ValueError, match="positive finite"):
            quintic_coefficients(q, q, tf)
    with pytest.raises(ValueError, match="not a finite number"):
        QuinticSegment(np.array([0.0, np.nan]), q, 1.0)
    with pytest.raises(ValueError, match="end has 3 joint values"):
        QuinticSegment(q, np.zeros(3), 1.0)
    with pytest.raises(ValueError, match="at least one segment"):
        Motion(())
    outside = Motion((QuinticSegment(q, np.array([0.0, 5.0]), 1.0, "X"),))
    with pytest.raises(ValueError, match=r"segment X end: .*joint2 = 5 rad is outside its limits"):
        outside.check_limits(arm)
    with pytest.raises(ValueError, match="has 2 joints; rrrr has 4"):
        outside.check_limits(get_arm("rrrr"))
    with pytest.raises(ValueError, match="path 'abcd' is not available for arm4r"):
        paper_motion(get_arm("arm4r"), "abcd")
    with pytest.raises(ValueError, match="branch"):
        point_to_joints(get_arm("arm4r"), (1.0, 1.0, 1.4), branch=0)


def test_a_segment_starting_on_a_limit_within_round_off_is_still_checked_after():
    """A sample within round-off outside a limit (a segment end) passes; a later dip far outside does not."""
    arm = get_arm("rr")
    lower = arm.limit_arrays()[0][0]
    # joint 1: θ = 2τ² − 2τ + lower − 1e-13, its minimum lower − 0.5 − 1e-13 at τ = 0.5; joint 2 at 0
    dip = PolynomialSegment(np.array([[0, 0, 0, 2.0, -2.0, lower - 1e-13], [0, 0, 0, 0, 0, 0.0]]), 1.0, "D")
    with pytest.raises(ValueError, match=r"segment D at t = 0.5 s: .*joint1 = .* rad is outside its limits"):
        Motion((dip,)).check_limits(arm)
    edge = PolynomialSegment(np.array([[0, 0, 0, 0, 0, lower - 1e-13], [0, 0, 0, 0, 0, 0.0]]), 1.0, "E")
    Motion((edge,)).check_limits(arm)  # within round-off of the limit throughout: on it


def test_segments_file(tmp_path, rng):
    """A file with joint ends, Cartesian ends on chosen branches, a continued start and constant rates."""
    arm = get_arm("rr")
    spec = {"deg": True, "segments": [
        {"label": "one", "from": [-38, 98], "to": [62, 68], "tf": 2},
        {"to_point": [0.4, 0.3], "to_branch": 1, "tf": 1.5},
        {"from_point": [0.4, 0.3], "from_branch": 0, "to_point": [0.1, 0.0], "to_branch": 0, "tf": 1},
        {"rate": [10, -20], "tf": 0.5},
    ]}
    path = tmp_path / "segments.json"
    path.write_text(json.dumps(spec))
    motion = read_segments(arm, path)
    s = motion.segments
    assert [type(x).__name__ for x in s] == ["QuinticSegment", "QuinticSegment", "QuinticSegment", "ConstantRate"]
    np.testing.assert_allclose(s[0].q0, np.radians([-38, 98]))
    np.testing.assert_array_equal(s[1].q0, s[0].qf)  # exact: a segment starts where the last ended
    np.testing.assert_allclose(s[1].qf, [2 * np.arctan2(0.3, 0.4), -np.pi / 2], atol=1e-12)
    np.testing.assert_allclose(s[2].q0, [0.0, np.pi / 2], atol=1e-12)
    np.testing.assert_allclose(s[3].omega, np.radians([10, -20]))
    assert motion.joins() == [True, False, False]  # the rates start at ω, not at rest: a velocity jump
    np.testing.assert_allclose(motion.breaks, [0, 2, 3.5, 4.5, 5.0])

    bad = [
        ({"segments": []}, "non-empty list"),
        ({"segments": [{"to": [0, 0], "tf": 1}]}, "first segment needs"),
        ({"segments": [{"from": [0, 0], "to": [0, 0]}]}, "needs \"tf\""),
        ({"segments": [{"from": [0, 0], "to": [0, 0], "tf": 0}]}, "tf = 0 s is not allowed"),
        ({"segments": [{"from": [0, 0], "to": [0, 0], "rate": [1, 1], "tf": 1}]}, "exactly one of"),
        ({"segments": [{"from": [0, 0, 0], "to": [0, 0], "tf": 1}]}, "has 3 values; rr has 2"),
        ({"segments": [{"from": [0, 0], "to": [0, 300], "tf": 1}], "deg": True}, "outside its limits"),
        ({"segments": [{"from": [0, 0], "to_point": [2, 0], "tf": 1}]}, "out of reach"),
        ({"segments": [{"from": [0, 0], "to": [0, 1], "tf": 1, "speed": 3}]}, "unknown key"),
        ({"segments": [{"from": [0, 0], "to": [30, 40], "tf": 1}], "deg": "no"}, 'deg" = "no" must be true or'),
        ({"segments": [{"from": [0, 0], "to": ["0", 1], "tf": 1}]}, r'to = \["0", 1\] must be a list of numbers'),
        ({"segments": [{"from": [0, 0], "to_point": {"x": 1}, "tf": 1}]}, 'to_point = {"x": 1} must be a list'),
        ({"segments": [{"from": [0, 0], "to_point": [0.4, 0.3], "to_branch": 1.0, "tf": 1}]}, "to_branch = 1.0 is not"),
        ({"segments": [{"from": [0, 0], "to_point": [0.4, 0.3], "to_branch": True, "tf": 1}]}, "to_branch = true"),
        ({"segments": [{"from": [0, 0], "to_point": [0.4, 0.3, 0.1], "to_branch": 0, "tf": 1}]}, "z = 0.1 is not"),
        ({"segments": [{"from": [0, 0], "to_point": [0.4], "to_branch": 0, "tf": 1}]}, "has 1 values; rr takes x,y"),
    ]
    for data, message in bad:
        path.write_text(json.dumps(data))
        with pytest.raises(ValueError, match=message):
            read_segments(arm, path)
    path.write_text("{not json")
    with pytest.raises(ValueError, match="not valid JSON"):
        read_segments(arm, path)
    with pytest.raises(ValueError, match="cannot read it"):
        read_segments(arm, tmp_path / "missing.json")
    path.write_text(json.dumps({"segments": [{"from": [0, 0, 0, 0], "to_point": [1, 1, 1.4], "to_pitch": "x",
                                              "tf": 1}]}))
    with pytest.raises(ValueError, match='to_pitch = "x" must be a finite number'):
        read_segments(get_arm("arm4r"), path)


def test_random_segments_stay_within_limits(rng):
    """A rest-to-rest quintic is monotone, so in-limit ends keep every sample in limits."""
    for name in ARM_NAMES:
        arm = get_arm(name)
        q0, qf = random_q(arm, rng, 2)
        motion = Motion((QuinticSegment(q0, qf, 1.3),))
        motion.check_limits(arm)
        q = motion.evaluate(np.linspace(0, 1.3, 101))[0]
        assert np.all((q >= np.minimum(q0, qf) - 1e-12) & (q <= np.maximum(q0, qf) + 1e-12))
