"""The one boundary rule (:mod:`armlab.bounds`): every comparison of a computed value with a bound goes through it,
values within its slack of a bound pass and values beyond by more fail at each boundary, on both sides, and each
paper's paths nudged by a few ulps at every sample give the same verdicts, rows and tables.

The guard reads every module of the package with ast (as tests/test_layers.py does): an ordering comparison
(``<``, ``<=``, ``>``, ``>=``) whose operands' text names a bound (:data:`STEMS`, :data:`WORDS`: limit, tolerance,
margin, clearance, σ, reach, effort, peak, lo/hi …) is a comparison made by hand, unless it is in
``armlab/bounds.py`` or one of its lines ends with ``# not a bound: <reason>`` (a count, a user's given value
against its accepted range, a figure's layout, a switch between two formulas …). A mark on a line with no such
comparison is stale, and fails too.
"""

from __future__ import annotations

import ast
import csv
import io
import re
from pathlib import Path

import numpy as np
import pytest
from helpers import ROOT, assert_same_numbers, is_program, package_modules
from hypothesis import given, settings
from hypothesis import strategies as st

from armlab.bounds import SLACK, above, allowance, below, clamp, outside, tolerated, within
from armlab.diagrams.drives import _first_exceeding
from armlab.kinematics.cartesian import ToolPath, arc_path
from armlab.kinematics.ik import solve_branch
from armlab.kinematics.ik_closed_form import rr_ik
from armlab.kinematics.ik_path import solve_path
from armlab.kinematics.quintic import Motion, QuinticSegment
from armlab.models import get_arm
from armlab.models.rr import ABCD_POINTS
from armlab.papers import paper_000
from armlab.papers.report_rows import compare
from armlab.papers.reproduce import PAPERS, _script
from armlab.planning.timing import limit_curve
from armlab.sizing.select import CHECKS, Evaluation

# ----------------------------------------------------------------------------------------------- the guard
#: Words that name a bound, as the start of an identifier's word (``limits``, ``POSITION_TOL``, ``sigma_min``).
STEMS = ("limit", "bound", "tol", "margin", "clearance", "thresh", "sigma", "singular", "reach", "effort", "peak",
         "slack", "rated", "lower", "upper", "deviation", "distance", "gap", "miss", "inner", "outer")
#: Words that name a bound only whole (``lo`` but not ``local``).
WORDS = ("lo", "hi", "low", "high", "lowest", "highest")
ORDERING = (ast.Lt, ast.LtE, ast.Gt, ast.GtE)
MARK = re.compile(r"#\s*not a bound:\s*\S")


def _names_a_bound(text: str) -> bool:
    """Whether source text has a word (split at underscores, dots, quotes, digits …) of the bound vocabulary."""
    return any(word.startswith(STEMS) or word in WORDS for word in (w.lower() for w in re.findall(r"[A-Za-z]+", text)))


def _ordering_comparisons(source: str) -> list[ast.Compare]:
    """Every comparison in ``source`` with an ordering operator whose operands' text names a bound."""
    return [node for node in ast.walk(ast.parse(source)) if isinstance(node, ast.Compare)
            and any(isinstance(op, ORDERING) for op in node.ops) and _names_a_bound(ast.unparse(node))]


def hand_comparisons(source: str) -> list[tuple[int, str]]:
    """(line, text) of each comparison of a value with a bound made by hand in ``source``: an ordering comparison
    naming a bound none of whose lines ends with ``# not a bound: <reason>``."""
    lines = source.splitlines()
    return [(node.lineno, ast.unparse(node)) for node in _ordering_comparisons(source)
            if not any(MARK.search(lines[k - 1]) for k in range(node.lineno, (node.end_lineno or node.lineno) + 1))]


def stale_marks(source: str) -> list[int]:
    """Lines marked ``# not a bound:`` that carry no ordering comparison naming a bound."""
    covered = {k for node in _ordering_comparisons(source) for k in range(node.lineno, (node.end_lineno or 0) + 1)}
    return [k for k, line in enumerate(source.splitlines(), start=1) if MARK.search(line) and k not in covered]


def _library() -> dict[str, Path]:
    """The modules the rule holds in: all of the package but armlab.bounds and the programs (benchmarks,
    examples)."""
    return {module: path for module, path in package_modules().items()
            if module != "armlab.bounds" and not is_program(module)}


def test_no_module_compares_a_value_with_a_bound_by_hand():
    """Every comparison with a bound in the library goes through armlab.bounds or says why it is not one."""
    modules = _library()
    assert len(modules) > 60 and "armlab.kinematics.ik_path" in modules and "armlab.cli.kinematics" in modules
    bad = [f"{path.relative_to(ROOT)}:{line}: {text}" for path in modules.values()
           for line, text in hand_comparisons(path.read_text())]
    assert not bad, ("comparisons with a bound made by hand (use armlab.bounds, or end the line with "
                     "'# not a bound: <reason>'):\n" + "\n".join(bad))


def test_no_mark_is_stale():
    """A ``# not a bound:`` mark stands on a comparison it excuses (so marks do not outlive their code), and the
    marks are in use (the vocabulary finds comparisons to excuse: the test above is not vacuous)."""
    modules = _library()
    stale = [f"{path.relative_to(ROOT)}:{line}" for path in modules.values() for line in stale_marks(path.read_text())]
    assert not stale, "'# not a bound:' marks on lines without a comparison naming a bound:\n" + "\n".join(stale)
    assert sum(len(_ordering_comparisons(path.read_text())) for path in modules.values()) >= 15


@pytest.mark.parametrize(("source", "caught"), [
    ("bad = q > upper", 1),
    ("bad = (q < lower) | (q > upper)", 2),
    ("ok = error <= POSITION_TOL", 1),
    ("singular = sigma[:, -1] < 1e-6", 1),
    ("touching = row['distance'] < 0", 1),
    ("x = lo <= value <= hi", 1),
    ("if clearance.min() >= 0:\n    pass", 1),
    ("def f(limits):\n    return [v for v in values if v > limits.effort]", 1),
    ("def f(limits):\n    return [v for v in limits.effort if v > 3]", 0),  # the operands name no bound
    ("ok = (value\n      <= limit)  # not a bound: a count", 0),
    ("ok = value <= limit  # not a bound: a user's given value", 0),
    ("ok = value <= limit  # not a bound:", 1),  # a mark without its reason
    ("ok = value <= limit  # a bound", 1),
    ("ok = above(value, limit)", 0),
    ("ok = value == limit", 0),  # equality is not an ordering comparison
    ("ok = local < 3", 0),  # "lo" only as a whole word
    ("ok = total > count", 0),
])
def test_hand_comparisons_are_caught(source, caught):
    """The check sees each ordering comparison naming a bound, and lets through only a marked one."""
    assert len(hand_comparisons(source)) == caught


@pytest.mark.parametrize(("source", "stale"), [
    ("x = 1  # not a bound: nothing compared", [1]),
    ("ok = count > 3  # not a bound: a count", [1]),  # no bound named: the mark excuses nothing
    ("ok = limit > 3  # not a bound: a count", []),
    ("ok = (limit\n      > 3)  # not a bound: a count", []),
])
def test_stale_marks_are_caught(source, stale):
    assert stale_marks(source) == stale


# ------------------------------------------------------------------------------------- the rule, as properties
BOUNDS = st.floats(-1e6, 1e6) | st.sampled_from([0.0, 1.0, -1.0, 1e-3, 4.71238898038469, -4.71238898038469])
ON = st.floats(0.0, 0.5)  # a share of the allowance: on the bound
BEYOND = st.floats(2.0, 1e6)  # a multiple of the allowance: beyond it


@settings(max_examples=200)
@given(bound=BOUNDS, share=ON, beyond=BEYOND)
def test_a_value_within_the_slack_is_on_its_bound_and_one_beyond_is_beyond(bound, share, beyond):
    a = float(allowance(bound))
    assert a >= SLACK and np.isclose(a, SLACK * max(1.0, abs(bound)))
    for sign in (1.0, -1.0):  # a hair inside or a hair outside: on it either way
        on = bound + sign * share * a
        assert not above(on, bound) and not below(on, bound) and within(on, bound, bound)
        assert not outside(on, bound, bound)
    assert above(bound + beyond * a, bound) and not below(bound + beyond * a, bound)
    assert below(bound - beyond * a, bound) and not above(bound - beyond * a, bound)
    assert outside(bound + beyond * a, -np.inf, bound) and outside(bound - beyond * a, bound, np.inf)


@settings(max_examples=200)
@given(lower=BOUNDS, width=st.floats(0.0, 1e3), share=ON, beyond=BEYOND)
def test_clamp_moves_a_value_on_a_bound_onto_it_and_leaves_one_beyond(lower, width, share, beyond):
    upper = lower + width
    values = np.array([lower - share * allowance(lower), upper + share * allowance(upper),
                       lower - beyond * allowance(lower), upper + beyond * allowance(upper), (lower + upper) / 2])
    clamped = clamp(values, lower, upper)
    assert np.all((clamped[[0, 1, 4]] >= lower) & (clamped[[0, 1, 4]] <= upper))
    np.testing.assert_array_equal(clamped[[2, 3]], values[[2, 3]])  # exact: returned as they are (np.where's copy)
    assert within(values, lower, upper).tolist() == [True, True, False, False, True]


@settings(max_examples=200)
@given(tolerance=st.floats(1e-15, 1e3), share=ON, beyond=BEYOND)
def test_a_tolerance_allows_its_slack_relative_to_itself(tolerance, share, beyond):
    """1e-12 stays 1e-12 (not 1e-9): the slack of a tolerance is relative to it."""
    assert tolerated(tolerance * (1 + share * SLACK), tolerance) and tolerated(0.0, tolerance)
    assert not tolerated(tolerance * (1 + beyond * SLACK), tolerance)


@pytest.mark.parametrize(("check", "expected"), [
    (lambda: above(np.nan, 1.0), True), (lambda: below(np.nan, 1.0), True),
    (lambda: outside(np.nan, -1.0, 1.0), True), (lambda: within(np.nan, -1.0, 1.0), False),
    (lambda: tolerated(np.nan, 1.0), False),
    (lambda: above(np.inf, np.inf), False), (lambda: below(-np.inf, -np.inf), False),
    (lambda: within(1e300, -np.inf, np.inf), True), (lambda: above(1.0, -np.inf), True),
    (lambda: float(allowance(np.inf)), 0.0),
])
def test_nan_passes_no_bound_and_an_infinite_bound_bounds_nothing_finite(check, expected):
    assert check() == expected


@given(st.floats(-1e6, 1e6), st.floats(0.0, 0.5), st.floats(2.0, 1e6))
def test_one_number_and_an_interval_follow_the_same_rule(bound, share, beyond):
    """above_value/below_value (one float) and Interval's methods (allowances made once) answer as above/below/
    outside, on a bound, within its allowance, beyond it, for NaN and against infinite bounds."""
    from armlab.bounds import Interval, above_value, below_value

    a = float(allowance(bound))
    values = [bound, bound + share * a, bound - share * a, bound + beyond * a, bound - beyond * a, np.nan, np.inf]
    for other in (bound, np.inf, -np.inf):
        for value in values:
            assert above_value(value, other) == bool(above(value, other))
            assert below_value(value, other) == bool(below(value, other))
    interval = Interval([bound, -np.inf], [bound + 1.0, np.inf])
    for value in values:
        v = np.array([value, value])
        for ours, theirs in ((interval.outside(v), outside(v, interval.lower, interval.upper)),
                             (interval.above_upper(v), above(v, interval.upper)),
                             (interval.above_lower(v), above(v, interval.lower)),
                             (interval.below_upper(v), below(v, interval.upper))):
            assert not np.logical_xor(ours, theirs).any()  # booleans: the same answers


def test_the_functions_broadcast_a_batch_against_per_joint_bounds():
    lower, upper = np.array([-1.0, 0.0]), np.array([1.0, 2e9])
    q = np.array([[-1.0 - 1e-10, 2e9 * (1 + 5e-10)], [-1.0 - 1e-8, 2e9 * (1 + 5e-9)]])
    assert outside(q, lower, upper).tolist() == [[False, False], [True, True]]
    assert clamp(q, lower, upper).shape == q.shape


# ------------------------------------------------------------------------------- the rule at each boundary
def _sides(bound: float, share: float, beyond: float) -> tuple[list[float], list[float]]:
    """(values on ``bound`` within the slack, both sides; values beyond it by more, both sides)."""
    a = float(allowance(bound))
    return [bound - share * a, bound + share * a], [bound - beyond * a, bound + beyond * a]


@settings(max_examples=40, deadline=None)
@given(joint=st.sampled_from([0, 1]), end=st.sampled_from([0, 1]), share=ON, beyond=st.floats(2.0, 1e4))
def test_a_joint_limit_of_arm_check_q_and_of_a_motion(joint, end, share, beyond):
    """Arm.check_q and Motion.check_limits: a joint on its limit within the slack passes, beyond it does not."""
    arm = get_arm("rr")
    limit = arm.limit_arrays()[end][joint]
    on, off = _sides(limit, share, beyond)
    outward = 1 if end else 0  # the value past the limit, of each pair
    for value, passes in ((on[0], True), (on[1], True), (off[outward], False), (off[1 - outward], True)):
        q = np.zeros(2)
        q[joint] = value
        motion = Motion((QuinticSegment(np.zeros(2), q, 1.0),))
        if passes:
            arm.check_q(q)
            motion.check_limits(arm)
        else:
            with pytest.raises(ValueError, match="outside its limits"):
                arm.check_q(q)
            with pytest.raises(ValueError, match=r"segment .* end: .*outside its limits"):
                motion.check_limits(arm)


@settings(max_examples=40, deadline=None)
@given(rim=st.sampled_from([(0.1, 0), (0.7, 1)]), share=ON, beyond=st.floats(2.0, 1e4))
def test_the_reach_of_a_closed_form(rim, share, beyond):
    """rr_ik's annulus 0.1 m ≤ |target| ≤ 0.7 m: a target on a rim within the slack is reached, beyond it not."""
    radius, away = rim  # the rim, and which value beyond it is out of reach (inside the inner, outside the outer)
    on, off = _sides(radius, share, beyond)
    for distance in on:
        assert np.all(np.isfinite(rr_ik([distance, 0.0], 0.4, 0.3)))
    with pytest.raises(ValueError, match="out of reach"):
        rr_ik([off[away], 0.0], 0.4, 0.3)


@settings(max_examples=60, deadline=None)
@given(paper=st.sampled_from([0.0, 12.5, -98.0, 727.5622]), tol=st.sampled_from([0.5, 5e-5, 2e-4, 1e-9]),
       side=st.sampled_from([0, 1]), share=ON, beyond=BEYOND)
def test_the_tolerance_of_a_report_row(paper, tol, side, share, beyond):
    """compare(): armlab's value on an end of [paper − tol, paper + tol] (a deviation of exactly half a printed
    digit) matches, within the slack on either side of that end; beyond it, the row differs."""
    end = (paper - tol, paper + tol)[side]
    on, off = _sides(end, share, beyond)
    assert all(compare("000", "q", paper, value, tol).kind == "matches" for value in on)
    assert compare("000", "q", paper, off[side], tol).kind == "differs"


@settings(max_examples=40, deadline=None)
@given(share=ON, beyond=st.floats(2.0, 1e6))
def test_a_drive_sizing_check(share, beyond):
    """A motor's check passes with its ratio limit/value on 1 within the slack, fails beyond."""
    a = float(allowance(1.0))
    ratios = np.ones((len(CHECKS), 3))
    ratios[0] = [1 - share * a, 1 + share * a, 1 - beyond * a]
    ev = Evaluation(np.zeros(3, int), np.zeros(3, int), ratios, {}, np.empty((len(CHECKS), 0)),
                    np.empty((len(CHECKS), 0)), np.empty(0), np.empty((len(CHECKS), 0), int))
    assert ev.feasible.tolist() == [True, True, False]


@settings(max_examples=40, deadline=None)
@given(kind=st.sampled_from(["velocity", "effort"]), side=st.sampled_from([0, 1]), share=ON, beyond=BEYOND)
def test_a_simulated_run_against_its_velocity_and_effort_limits(kind, side, share, beyond):
    """diagrams.drives: a run's value on its limit within the slack is within it; beyond, it is reported."""
    limit = {"velocity": 3.0, "effort": 40.0}[kind]
    lower, upper = -limit, limit
    bound = (lower, upper)[side]
    on, off = _sides(bound, share, beyond)
    t = np.array([0.0, 0.5, 1.0])
    for value in on:
        assert _first_exceeding(t, np.array([0.0, value, 0.0]), lower, upper) is None
    found = _first_exceeding(t, np.array([0.0, off[side], 0.0]), lower, upper)
    assert found is not None and found[1] == bound and found[2] == 0.5  # exact: the limit and a sample time, copied


@settings(max_examples=40, deadline=None)
@given(side=st.sampled_from([0, 1]), share=ON, beyond=BEYOND)
def test_a_timing_constraint_with_the_path_at_rest(side, share, beyond):
    """limit_curve: a constraint on the path at rest (gravity against an effort limit) on its limit is feasible,
    beyond it NaN (even ṡ = 0 breaks it)."""
    lo, hi = np.array([-2.0, -40.0]), np.array([2.0, 40.0])
    a, b = np.array([[1.0, 0.0]]), np.zeros((1, 2))
    on, off = _sides((lo[1], hi[1])[side], share, beyond)
    for value in on:
        assert not np.isnan(limit_curve(a, b, np.array([[0.0, value]]), lo, hi)[0])
    assert np.isnan(limit_curve(a, b, np.array([[0.0, off[side]]]), lo, hi)[0])


# ------------------------------------------------------------------------------- paths nudged by a few ulps
#: How the samples are nudged: every entry up by :data:`ULPS` ulps, every entry down, each by a random number in
#: [−ULPS, ULPS]. One of "up" and "down" moves a value computed from the samples outward across a bound it sits on
#: (to first order, the other inward), so a bound compared by hand fails under one of them.
NUDGES = ("up", "down", "random")
ULPS = 4


def nudged(values: np.ndarray, how: str, rng: np.random.Generator) -> np.ndarray:
    """``values`` with every entry moved by :data:`ULPS` ulps (np.nextafter) as ``how`` (:data:`NUDGES`) says."""
    x = np.array(values, dtype=float)
    steps = {"up": np.full(x.shape, ULPS), "down": np.full(x.shape, -ULPS),
             "random": rng.integers(-ULPS, ULPS + 1, size=x.shape)}[how]
    for k in range(1, ULPS + 1):
        x = np.where(steps >= k, np.nextafter(x, np.inf), np.where(steps <= -k, np.nextafter(x, -np.inf), x))
    return x


def test_paper_000_circle_nudged_by_ulps_stays_within_joint_2s_limit(rng):
    """Paper 000's whole circle ends on joint 2's limit (−270°): its tool samples nudged by a few ulps (what another
    OpenBLAS kernel's rounding does) still give a path within the limits, every time, with the end exactly on it."""
    arm = get_arm("rr")
    centre, _ = paper_000._circle(ABCD_POINTS)
    path = arc_path(np.append(centre, 0.0), [0.0, 0.0, 1.0], ABCD_POINTS["A"], 2 * np.pi)
    s = np.linspace(0.0, 1.0, 4 * paper_000.ARC_SAMPLES)
    samples = path.points(s)
    start = solve_branch(arm, path.start, 0)
    lower, upper = arm.limit_arrays()
    base = solve_path(arm, "the arc", s, *samples, start)
    assert tolerated(abs(base.q[-1, 1] - lower[1]), 1e-9)  # the case: the circle ends on the limit
    for how in (*NUDGES, "random", "random"):
        joints = solve_path(arm, "the arc", s, *(nudged(v, how, rng) for v in samples), start)
        assert np.all((joints.q >= lower) & (joints.q <= upper))  # on the limit, not round-off beyond it
        assert np.abs(joints.q - base.q).max() < 1e-9  # the same path (the nudge moves it by round-off only)
        for q in (nudged(joints.q, how, rng), nudged(base.q, how, rng)):
            arm.check_q(q)  # the joints themselves nudged: still on the limit


def _nudging(monkeypatch: pytest.MonkeyPatch, how: str, rng: np.random.Generator) -> None:
    """Every motion's and every tool path's samples nudged as ``how`` says (Motion.evaluate, ToolPath.points: where
    each paper samples its paths) until ``monkeypatch`` undoes it."""
    evaluate, points = Motion.evaluate, ToolPath.points
    monkeypatch.setattr(Motion, "evaluate", lambda self, t, orders=3: tuple(
        nudged(v, how, rng) for v in evaluate(self, t, orders)))
    monkeypatch.setattr(ToolPath, "points", lambda self, s: tuple(nudged(v, how, rng) for v in points(self, s)))


def _tables(folder: Path) -> dict[str, list[list[str]]]:
    """A paper's tables (its CSV files, rows.csv among them) as rows of cells."""
    return {path.name: list(csv.reader(io.StringIO(path.read_text()))) for path in sorted(folder.glob("*.csv"))}


@pytest.mark.slow
@pytest.mark.parametrize("paper", PAPERS)
def test_a_paper_with_its_paths_nudged_gives_the_same_verdicts_rows_and_tables(paper, tmp_path, monkeypatch, rng):
    """Each paper run (fast) as it is and with every sample of its paths nudged by a few ulps, each way of
    :data:`NUDGES`: the same rows (verdicts exactly, numbers to 1e-12) and tables. A table's numbers agree to 1e-8
    relative: the true arcs of paper 000 pass the singular configurations B and D, where q'' comes from the
    samples' differences, which amplify a nudge of the samples (≈ 1e-16 relative) by 1/h² ≈ 1e7 (h: the 1/3204
    sample step)."""
    script = _script(paper)
    base = script.run(tmp_path / "base", fast=True, progress=lambda line: None)
    tables = _tables(tmp_path / "base")
    assert "rows.csv" in tables
    for how in NUDGES:
        with monkeypatch.context() as patch:
            _nudging(patch, how, rng)
            moved = script.run(tmp_path / how, fast=True, progress=lambda line: None)
        assert [row.verdict.split(":")[0] for row in moved] == [row.verdict.split(":")[0] for row in base], how
        assert_same_numbers(moved, base, where=how)
        assert_same_numbers(_tables(tmp_path / how), tables, rtol=1e-8, atol=1e-12, where=how)
