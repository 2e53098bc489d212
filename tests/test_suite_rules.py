"""The test suite's own rules: no exact float comparison outside an allow-list, test modules never import each other.

An exact comparison of floats passes on one machine and fails on another when the two numbers come from different
code paths, processes or libraries (a batch and a single call round differently on another CPU). Tests compare
such numbers with ``assert_allclose`` and a stated tolerance (tests/helpers.py). The exact comparisons that remain
are exact by construction (a copy, a constant, an integer-valued or boolean result, IEEE-exact arithmetic) or check
determinism (the same code on the same input in the same process): each is listed in :data:`ALLOWED` with its
reason and carries a comment saying ``exact`` on its line or the line above.
"""

from __future__ import annotations

import ast
import io
import re
import tokenize
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
#: Calls that compare arrays element for element, exactly (numpy's and filecmp's).
EXACT_CALLS = {"assert_array_equal", "array_equal", "array_equiv", "assert_equal", "assert_string_equal"}
#: Calls whose argument, an elementwise ``==``, makes an exact array comparison: ``np.all(a == b)``.
REDUCTIONS = {"all", "any"}

BY_CONSTRUCTION = "exact by construction: a copy or a constant, no arithmetic that could round"
PARSED = "exact by construction: a number parsed from the same decimal text as the literal"
ROUNDED = "np.round(x, k) is an integer over 10ᵏ, correctly rounded like the decimal literal: exact on any CPU"
ZERO = "exact by construction: every term is a product with an exact zero (a planar arm's out-of-plane part)"
IEEE = "one correctly rounded IEEE operation on the same operands: the same bits on any CPU"
TEXT = "text, not numbers: equal or not on any CPU"
DETERMINISM = "determinism: the same code on the same input in the same process"
BOOLEAN = "booleans or integers, not floats"
ZERO_RIM = "exact by construction: the closed form's values on the rims (what the test checks: 0 and ±π exactly)"

#: (file, the comparison's first line of code, without its comment) → why it may be exact.
ALLOWED: dict[tuple[str, str], str] = {
    ('test_arm_extras.py', 'assert arm.name == "arm1r" and arm.parameters["L"] == 0.7'):
        BY_CONSTRUCTION,
    ('test_arm_extras.py', 'np.testing.assert_array_equal(default_q(arm), [np.pi / 4])'):
        BY_CONSTRUCTION,
    ('test_arm_extras.py', 'np.testing.assert_array_equal(motion.segments[0].q_start, [-np.pi / 4])'):
        BY_CONSTRUCTION,
    ('test_ik.py', 'np.testing.assert_array_equal(again, first)'):
        DETERMINISM,
    ('test_install.py', 'assert zipfile.ZipFile(wheel).read(licence[0]).decode() == (ROOT / "LICENSE").read_text()'):
        TEXT,
    ('test_install.py', 'np.testing.assert_array_equal(by_name.fk(q), by_path.fk(q))'):
        DETERMINISM,
    ('test_plant.py', 'assert PlantOptions("+x").gravity == (9.81, 0.0, 0.0)'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'assert PlantOptions("1,2,-3.5").gravity == (1.0, 2.0, -3.5)'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'assert PlantOptions("off").gravity == (0.0, 0.0, 0.0)'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'assert PlantOptions(payload=2).payload == 2.0'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'assert arm.make_plant().time_step() == 0.0'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'assert options.kp == (100.0, 50.0) and options.kd == 20.0 and options.plant.ideal_drives'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'assert plant.time_step() == 1e-3 and plant.num_discrete_state_groups() == 1'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'np.testing.assert_array_equal(PlantOptions().gravity_of(rr), [0, -9.81, 0])'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'np.testing.assert_array_equal(inertia, np.zeros((3, 3)))'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'np.testing.assert_array_equal(efforts, expected)'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'np.testing.assert_array_equal(in_order.MakeActuationMatrix(), np.eye(2))'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'np.testing.assert_array_equal(plant.MakeActuationMatrix(), np.eye(2))'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'np.testing.assert_array_equal(plant.gravity_field().gravity_vector(), [9.81, 0, 0])'):
        BY_CONSTRUCTION,
    ('test_plant.py', 'np.testing.assert_array_equal(plant.gravity_field().gravity_vector(), arm.gravity)'):
        BY_CONSTRUCTION,
    ('test_api.py', 'assert armlab.load("urm6", theta3=0.5).parameters["theta3"] == 0.5'): PARSED,
    ('test_api.py', 'assert motion.duration == 3.0 and motion.joins() == [True]'): IEEE,
    ('test_custom.py', 'assert arm.link_names == ("upper", "fo\'re") and arm.links()[1]["mass"] == 0.5'): PARSED,
    ('test_differential.py', 'np.testing.assert_array_equal(manipulability(J), manipulability(J, default))'):
        DETERMINISM,
    ('test_bounds.py', 'np.testing.assert_array_equal(clamped[[2, 3]], values[[2, 3]])'):
        BY_CONSTRUCTION,
    ('test_bounds.py', 'assert found is not None and found[1] == bound and found[2] == 0.5'):
        BY_CONSTRUCTION,
    ('test_errata.py', 'np.testing.assert_array_equal(wrong, affected)'): BOOLEAN,
    ('test_ik.py', 'np.testing.assert_array_equal(best, every[0])'): DETERMINISM,
    ('test_ik.py', 'np.testing.assert_array_equal(np.round(m0, 4), [0.4652, 0.0135])'): ROUNDED,
    ('test_ik.py', 'np.testing.assert_array_equal(rr_ik([0.7, 0.0], 0.4, 0.3), np.zeros((2, 2)))'): ZERO_RIM,
    ('test_ik.py', 'np.testing.assert_array_equal(inner[:, 1], [np.pi, -np.pi])'): ZERO_RIM,
    ('test_ik.py', 'np.testing.assert_array_equal(target[:3, 3], [*position, 0.0])'): BY_CONSTRUCTION,
    ('test_models.py', 'assert plant.time_step() == 0.0'): BY_CONSTRUCTION,
    ('test_models.py', 'np.testing.assert_array_equal(X, np.eye(4))'): ZERO,
    ('test_models.py', 'np.testing.assert_array_equal(fk.points["M"][:, 2], 0.0)'): ZERO,
    ('test_models.py', 'np.testing.assert_array_equal(arm.table.rows[0].k, (0, 0, 1))'): BY_CONSTRUCTION,
    ('test_quintic.py', 'np.testing.assert_array_equal(np.round(c[:, :3], 4), paper)'): ROUNDED,
    ('test_quintic.py',
     'np.testing.assert_array_equal(np.round(paper_motion(get_arm("rr")).coefficients()[0, :, :3], 4), paper)'):
        ROUNDED,
    ('test_quintic.py', 'np.testing.assert_array_equal(pp.get_segment_times(), motion.breaks)'): BY_CONSTRUCTION,
    ('test_quintic.py',
     'np.testing.assert_array_equal(seg.coefficients(), [[0, 0, 0, 0, 7.0, 0.1], [0, 0, 0, 0, 0.05, 0.2]])'):
        BY_CONSTRUCTION,
    ('test_quintic.py', 'np.testing.assert_array_equal(qdd, 0.0)'): ZERO,
    ('test_quintic.py', 'assert [start for start, _ in runs] == [0.0, 4.0, 6.0]'): IEEE,
    ('test_quintic.py', 'assert seg.tf == 2.0'): BY_CONSTRUCTION,
    ('test_quintic.py', 'np.testing.assert_array_equal(s[1].q0, s[0].qf)'): BY_CONSTRUCTION,
    ('test_replay.py', 'assert viewer.step() and np.array_equal(viewer.q, q0)'): BY_CONSTRUCTION,
    ('test_replay.py', 'assert viewer.q[1] == -1.2'): BY_CONSTRUCTION,
    ('test_replay.py', 'assert join["t"] == 1.0 and join["to"] - join["from"] >= JOIN_PAUSE - 0.05'): BY_CONSTRUCTION,
    ('test_rnea.py', 'np.testing.assert_array_equal(arm.inverse_dynamics(q, qd, qdd, payload=0.5),'): DETERMINISM,
    ('test_simulate.py', 'assert log.t[0] == 0.0 and abs(log.t[-1] - log.motion.duration) < 1e-12'): BY_CONSTRUCTION,
    ('test_simulate.py', 'np.testing.assert_array_equal(off.gravity, [0, 0, 0])'): BY_CONSTRUCTION,
    ('test_simulate.py', 'assert jumps[0] == 0.0 and jumps[-1] == motion.duration'): BY_CONSTRUCTION,
    ('test_formats_in.py',
     'assert lines[2].split()[:2] == ["link1–ball", f"{(np.hypot(0.25, 0.1) - 0.08) * 1000:+.4f}"]'): TEXT,
    ('test_simulate.py', 'np.testing.assert_array_equal(resolve_gravity(rr), [0, -9.81, 0])'): PARSED,
    ('test_simulate.py', 'np.testing.assert_array_equal(resolve_gravity(rr, "default"), [0, -9.81, 0])'): PARSED,
    ('test_simulate.py', 'np.testing.assert_array_equal(resolve_gravity(get_arm("r2t"), None), [0, 0, -9.81])'): PARSED,
    ('test_simulate.py', 'np.testing.assert_array_equal(resolve_gravity(rr, "+x"), [9.81, 0, 0])'): PARSED,
    ('test_simulate.py', 'np.testing.assert_array_equal(resolve_gravity(rr, "1,2,-3.5"), [1, 2, -3.5])'): PARSED,
    ('test_simulate.py', 'np.testing.assert_array_equal(log.tool[:, [2, 5, 8]], 0.0)'): ZERO,
    ('test_simulate.py', 'np.testing.assert_array_equal(log.sample_times(), t)'): BY_CONSTRUCTION,
    ('test_simulate.py', 'np.testing.assert_array_equal(sample_times(2.0, 1e-3), np.arange(2001) * 1e-3)'): IEEE,
    ('test_simulate.py', 'assert t.size == 216 and t[-2] == 214 * 0.007 and t[-1] == 1.5'): IEEE,
    ('test_simulate.py', 'np.testing.assert_array_equal(sample_times(0.3, 0.1), [0.0, 0.1, 0.2, 0.3])'): IEEE,
    ('test_simulate.py', 'np.testing.assert_array_equal(dense.run, periodic.run)'): BOOLEAN,
    ('test_simulate.py', 'assert json.loads((out / "summary.json").read_text())["duration"] == 2.0'): PARSED,
    ('test_simulate.py',
     'assert summary["duration"] == 1.5 and summary["payload_kg"] == 20 and summary["gravity"] == [0, 0, 0]'):
        PARSED,
    ('test_simulate.py', 'assert summary["mode"] == "inverse_dynamics" and summary["integrator"]["max_step"] == 0.002'):
        BY_CONSTRUCTION,
    ('test_simulate.py',
     'assert table.shape[0] == 216 and table[-2, 0] == pytest.approx(1.498) and table[-1, 0] == 1.5'):
        BY_CONSTRUCTION,
    ('test_simulate.py', 'assert json.loads((out / "summary.json").read_text())["gravity"] == [-9.81, 0, 0]'): PARSED,
    ('test_sweep.py', 'assert study.candidates == [(0.2, 30.0), (0.2, 40.0), (0.3, 30.0), (0.3, 40.0)]'): PARSED,
    ('test_sweep.py', 'assert study.settings((0.3, 40.0)) == ({"L2": 0.3, "L1": 0.4}, 0.0, None)'): IEEE,
    ('test_sweep.py', 'assert record["study"]["vary"]["L1"] == {"values": [30.0, 40.0], "unit": "cm"}'): PARSED,
    ('test_workspace.py', 'np.testing.assert_array_equal(lower, -np.pi)'): BY_CONSTRUCTION,
    ('test_workspace.py', 'np.testing.assert_array_equal(upper, np.pi)'): BY_CONSTRUCTION,
    ('test_workspace.py', 'np.testing.assert_array_equal(ws.basis, np.eye(3)[:2])'): BY_CONSTRUCTION,
    ('test_workspace.py',
     'assert ws.dim == 3 and ws.motions == 2 and ws.volume == 0.0 and "curved surface" in ws.summary()["note"]'):
        BY_CONSTRUCTION,
    ('test_dh_file_rules.py', 'assert read_dh_csv(_file(tmp_path, text))[0].rows[0].a == 5.0'):
        PARSED,
    ('test_dh_file_rules.py', 'assert table.n == 2 and [b.mass for b in inertials] == [1.0, 2.0]'):
        PARSED,
    ('test_drives_checks.py', 'assert duty_type(np.full(5, 2.0), np.zeros(5), np.ones(5)) == ("S1", 1.0)'):
        BY_CONSTRUCTION,
    ('test_drives_checks.py', 'assert set(np.unique(gearboxes.life_basis)) == {1.0, 2.0}'):
        BOOLEAN,
    ('test_drives_select.py', 'np.testing.assert_array_equal(~below(smallest, 1.0), feasible)'):
        BOOLEAN,
    ('test_planner.py', 'np.testing.assert_array_equal(again.waypoints, plan.waypoints)'):
        DETERMINISM,
    ('test_servo.py', 'assert read_drive_file(good, ["joint1", "joint2"]).elasticity.stiffness.tolist() == [2e4, 1e4]'):
        PARSED,
    ('test_servo.py', 'assert servo.servo is not None and servo.servo["torque_limit"] == [100.0, 100.0]'):
        BY_CONSTRUCTION,
    ('test_servo.py', 'assert servo["controller"] == "pid" and servo["rate_hz"] == 1000.0'):
        PARSED,
    ('test_servo.py', 'assert servo["current_loop"]["bus_voltage"] == [48.0, 48.0]'):
        PARSED,
    ('test_servo.py',
     'assert study.servo_settings((2.0, 16384.0)) == {"controller": "pd+feedforward", "bandwidth": 5.0,'):
        BY_CONSTRUCTION,
    ('test_servo.py', 'np.testing.assert_array_equal(e.back_emf, e.torque_constant)'):
        BY_CONSTRUCTION,
    ('test_servo.py', 'np.testing.assert_array_equal(e.peak_current, [6.0, 4.0])'):
        PARSED,
    ('test_servo.py', 'np.testing.assert_array_equal(e.resistance, [1.2, 2.0])'):
        PARSED,
    ('test_servo.py', 'np.testing.assert_array_equal(first, again)'):
        DETERMINISM,
    ('test_servo.py', 'np.testing.assert_array_equal(graphs["motor currents i"].values, run.log.current)'):
        BY_CONSTRUCTION,
}


def _comments(text: str) -> dict[int, str]:
    """Line number → the comment on that line."""
    return {tok.start[0]: tok.string for tok in tokenize.generate_tokens(io.StringIO(text).readline)
            if tok.type == tokenize.COMMENT}


def _name(func: ast.expr) -> str:
    return func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""


def _floaty(node: ast.AST) -> bool:
    """``node`` is a float literal or a display of them (``[0.0, 0.1]``, ``214 * 0.007``; a call's own arguments
    do not count), or a file's bytes or text (whose numbers another process may have written)."""
    if isinstance(node, ast.Call):
        return _name(node.func) in ("read_bytes", "read_text")
    if isinstance(node, ast.Constant):
        return isinstance(node.value, float)
    return any(_floaty(child) for child in ast.iter_child_nodes(node))


def _exact(node: ast.AST) -> bool:
    """``node`` compares floats, arrays or file contents exactly (as far as the syntax shows)."""
    if isinstance(node, ast.Call):
        if _name(node.func) in EXACT_CALLS or "filecmp" in ast.unparse(node.func):
            return True
        return _name(node.func) in REDUCTIONS and any(
            isinstance(a, ast.Compare) and any(isinstance(op, ast.Eq | ast.NotEq) for op in a.ops) for a in node.args)
    if isinstance(node, ast.Compare) and any(isinstance(op, ast.Eq | ast.NotEq) for op in node.ops):
        operands = [node.left, *node.comparators]
        if any(isinstance(o, ast.Constant) and isinstance(o.value, str | bytes) for o in operands):
            return False  # a file's text against a literal: text, not numbers
        if any(isinstance(o, ast.Call) and _name(o.func) == "approx" for o in operands):
            return False  # pytest.approx: a tolerance
        return any(_floaty(o) for o in operands)
    if isinstance(node, ast.Attribute) and node.attr == "all" and isinstance(node.value, ast.Compare):
        return any(isinstance(op, ast.Eq | ast.NotEq) for op in node.value.ops)  # (a == b).all()
    return False


def exact_comparisons(path: Path) -> list[tuple[int, str, bool]]:
    """Each exact comparison in ``path``: (line, its first line's code without comment, whether a comment saying
    ``exact`` is on its lines or the line above)."""
    text = path.read_text()
    lines, comments = text.splitlines(), _comments(text)
    found = {}
    for node in ast.walk(ast.parse(text)):
        if _exact(node):
            first, last = node.lineno, node.end_lineno or node.lineno
            commented = any("exact" in comments.get(k, "") for k in range(first - 1, last + 1))
            code = lines[first - 1].removesuffix(comments.get(first, "")).strip()
            found[first, code] = commented or found.get((first, code), False)
    return sorted((line, code, commented) for (line, code), commented in found.items())


@pytest.mark.slow
def test_every_exact_comparison_is_allowed_and_commented() -> None:
    seen, problems = set(), []
    for path in sorted(TESTS.glob("*.py")):
        for line, code, commented in exact_comparisons(path):
            key = (path.name, code)
            seen.add(key)
            if key not in ALLOWED:
                problems.append(f"{path.name}:{line}: exact comparison not on the allow-list: {code}")
            elif not commented:
                problems.append(f"{path.name}:{line}: exact comparison without an 'exact' comment: {code}")
    problems += [f"{file}: stale allow-list entry: {code}" for file, code in sorted(ALLOWED.keys() - seen)]
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("code", [
    "np.testing.assert_array_equal(arm.fk(q[3]), T[3])",
    "assert np.array_equal(a, b)",
    "assert np.all(a == b)",
    "assert (a == b).all()",
    "assert x == 0.5",
    "assert objectives == [0.25, 1.0]",
    "assert mine.read_bytes() == theirs.read_bytes()",
    "assert mine.read_text() == theirs.read_text()",
    "assert filecmp.cmp(mine, theirs, shallow=False)",
])
def test_a_new_exact_comparison_is_caught(tmp_path: Path, code: str) -> None:
    """Each form, added without comment to a test module, is found; with an ``exact`` comment it is found as
    commented (and must still be on the allow-list)."""
    path = tmp_path / "test_new.py"
    path.write_text(f"def test_new():\n    {code}\n")
    assert exact_comparisons(path) == [(2, code, False)]
    path.write_text(f"def test_new():\n    # exact: why\n    {code}\n")
    assert exact_comparisons(path) == [(3, code, True)]


@pytest.mark.parametrize("code", [
    "assert run.returncode == 0",
    "assert path.read_text() == 'mine'",
    "assert len(rows) == 3",
    "np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)",
    "assert abs(x - 0.5) < 1e-9",
])
def test_what_is_not_an_exact_float_comparison(tmp_path: Path, code: str) -> None:
    path = tmp_path / "test_new.py"
    path.write_text(f"def test_new():\n    {code}\n")
    assert exact_comparisons(path) == []


def test_test_modules_do_not_import_each_other() -> None:
    """Shared code lives in helper modules (helpers.py, browser.py, contract.py, replay_pictures.py) and fixtures in
    conftest.py; a test module importing another runs that module's tests' set-up and ties the two together."""
    imports = re.compile(r"^\s*(?:from\s+(test_\w+|conftest|tests\.\w+)\s+import|import\s+(test_\w+|conftest))\b",
                         re.M)
    found = [f"{path.name}: {m.group(0).strip()}" for path in sorted(TESTS.glob("*.py"))
             for m in imports.finditer(path.read_text())]
    assert not found, "\n".join(found)
