"""Hostile but ordinary input to every command: a result, or one line ``armlab: error: …`` and exit 2.

Cases are rows of tables, one class each (issue 13): CLI numbers, segments files, resource limits.
Each runs ``armlab.cli.main`` in a private sandbox (:class:`contract.Sandbox`) under a timeout and
checks the contract of :func:`contract.check` and that nothing but the intended output was left.
Property-based tests (hypothesis) drive the parsers with generated text: numbers and vectors,
joint values, segments files and DH tables. Output folders and streams: ``test_outputs.py``;
signals: ``test_signals.py``.
"""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest
from contract import Sandbox, check
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from armlab.files import MAX_INPUT_BYTES
from armlab.models import get_arm
from armlab.planning.motions import read_segments
from armlab.values import joint_values, parse_floats

pytestmark = pytest.mark.timeout(120)


@pytest.fixture
def box(tmp_path, monkeypatch, capsys) -> Sandbox:
    return Sandbox(tmp_path, monkeypatch, capsys)


# ---- CLI numbers: (argv, exit code, fragment of the error line, or of stdout on success) -------------------------
SIM = ("simulate", "rr", "--out", "run")
LINE = ("plan", "rr", "line", "--from", "0.5,0.3", "--to", "0.3,0.5")
CLI_NUMBERS = [
    (("fk", "rr", "--q", "1e309,0"), 2, "--q: '1e309' is not a finite number"),
    (("fk", "rr", "--q", "-1e309,0"), 2, "'-1e309' is not a finite number"),
    (("fk", "rr", "--q", "nan,0"), 2, "'nan' is not a finite number"),
    (("fk", "rr", "--q", "0,-Infinity"), 2, "'-Infinity' is not a finite number"),
    (("fk", "rr", "--q", ""), 2, "'' is not a number"),
    (("fk", "rr", "--q", ","), 2, "'' is not a number"),
    (("fk", "rr", "--q", "1,,2"), 2, "'' is not a number"),
    (("fk", "rr", "--q", "0x1,0"), 2, "'0x1' is not a number"),
    (("fk", "rr", "--q", "1e,0"), 2, "'1e' is not a number"),
    (("fk", "rr", "--q", "1;2"), 2, "'1;2' is not a number"),
    (("fk", "rr", "--q", "9" * 400 + ",0"), 2, "is not a finite number"),
    (("fk", "rr", "--q", "1e308,0"), 2, "joint1 = 1e+308 rad is outside its limits"),
    (("fk", "rr", "--q", "-1e308,0"), 2, "joint1 = -1e+308 rad is outside its limits"),
    (("fk", "r2t", "--q", "0,1e308,0"), 2, "joint2 = 1e+308 m is outside its limits"),
    (("fk", "rr", "--q", "0,0,0"), 2, "rr has 2 joints, got 3 values"),
    (("simulate", "rr", "--tf", "1e308", "--out", "run"), 2, "--tf 1e308 is out of range: allowed 1e-6 ≤ tf ≤ 1e6 s"),
    (("fk", "rrrr", "--q", "1e308,0,0,0"), 2, "--q 1e308 is out of range: allowed -1e6 ≤ q ≤ 1e6 rad or m"),
    (("fk", "rr", "--q", "0,0", "--qd", "1e308,1e308"), 2, "--qd 1e308 is out of range: allowed -10000 ≤ q̇"),
    (("fk", "rr", "--q", "0,0", "--qdd", "0,-1e7"), 2, "--qdd -1e7 is out of range: allowed -1e6 ≤ q̈ ≤ 1e6"),
    (("fk", "rr", "--q", "0,0", "--qd", "1,2,3"), 2, "--qd: rr has 2 joints, got 3 values"),
    (("fk", "rr", "--q", "1e-320,-0"), 0, "tool"),
    (("ik", "rr", "--target", "1e309,0"), 2, "'1e309' is not a finite number"),
    (("ik", "urm6", "--target", "1e308,0,0"), 2, "out of range"),
    (("ik", "rrrr", "--target", "-1e308,0,0"), 2, "out of range"),
    (("ik", "rr", "--target", "1e-320,0"), 2, "out of reach"),
    (("ik", "rr", "--target", "0.5,0.2", "--near", "1e308,0"), 2, "joint1 = 1e+308 rad is outside its limits"),
    ((*SIM, "--kp", "1e308", "--kd", "1e308"), 2, "--kp 1e308 is out of range: allowed 0 ≤ kp ≤ 1e6"),
    (("simulate", "rr", "--kd", "1e308", "--out", "run"), 2, "--kd 1e308 is out of range: allowed 0 ≤ kd ≤ 10000"),
    (("simulate", "rr", "--ki", "1e308", "--out", "run"), 2, "--ki 1e308 is out of range: allowed 0 ≤ ki ≤ 1e8"),
    (("simulate", "rr", "--kp", "100,1e7", "--out", "run"), 2, "--kp 1e7 is out of range"),
    (("simulate", "rr", "--kp", "-1", "--out", "run"), 2, "--kp -1 is out of range"),
    ((*SIM, "--kp", "-1e-3"), 2, "--kp -0.001 is out of range"),
    ((*SIM, "--kd", "-inf"), 2, "--kd: '-inf' is not a finite number"),
    (("simulate", "rr", "--kp", "nan", "--out", "run"), 2, "--kp: 'nan' is not a finite number"),
    (("simulate", "rr", "--kp", "1,2,3", "--out", "run"), 2, "--kp has 3 values; give one value or 2"),
    ((*SIM, "--gravity", "1e308,0,0"), 2, "gravity 1e308,0,0 (|g| = 1e308) is out of range"),
    (("simulate", "rr", "--gravity", "-60,-60,-60", "--out", "run"), 2, "|g| = 103.923) is out of range"),
    (("simulate", "rr", "--gravity", "1,2", "--out", "run"), 2, "give 3 finite numbers"),
    (("simulate", "rr", "--gravity", "up", "--out", "run"), 2, "'up' is not a number"),
    (("simulate", "rr", "--gravity", "0,0,inf", "--out", "run"), 2, "'inf' is not a finite number"),
    ((*SIM, "--payload", "1e6"), 2, "--payload 1e6 is out of range: allowed 0 ≤ payload ≤ 1000 kg"),
    (("simulate", "rr", "--payload", "-1", "--out", "run"), 2, "--payload -1 is out of range"),
    (("simulate", "rr", "--payload", "nan", "--out", "run"), 2, "--payload nan is out of range"),
    (("simulate", "rr", "--payload", "1e400", "--out", "run"), 2, "--payload inf is out of range"),
    (("simulate", "rr", "--payload", "ten", "--out", "run"), 2, "invalid float value: 'ten'"),
    ((*SIM, "--accuracy", "1e-300"), 2, "--accuracy 1e-300 is out of range: allowed 1e-12 ≤"),
    (("simulate", "rr", "--accuracy", "0", "--out", "run"), 2, "--accuracy 0 is out of range"),
    (("simulate", "rr", "--accuracy", "-1e-6", "--out", "run"), 2, "--accuracy -1e-6 is out of range"),
    (("simulate", "rr", "--accuracy", "nan", "--out", "run"), 2, "--accuracy nan is out of range"),
    (("simulate", "rr", "--accuracy", "1", "--out", "run"), 2, "--accuracy 1 is out of range"),
    (("simulate", "rr", "--dt", "nan", "--out", "run"), 2, "log period = nan s is not allowed"),
    (("simulate", "rr", "--dt", "0", "--out", "run"), 2, "log period = 0.0 s is not allowed"),
    (("simulate", "rr", "--dt", "1e308", "--out", "run"), 2, "longer than the motion"),
    (("simulate", "rr", "--tf", "0", "--out", "run"), 2, "a duration must be a positive finite number"),
    (("simulate", "rr", "--tf", "-inf", "--out", "run"), 2, "'-inf' is not a finite number"),
    (("simulate", "rr", "--tf", "1,2", "--out", "run"), 2, "--tf 1,2: give one duration"),
    (("simulate", "rr", "--from", "0,0", "--to", "1e308,0", "--out", "run"), 2, "joint1 = 1e+308 rad is outside"),
    (("diagram", "rr", "--kp", "1e308", "--out", "d.dot"), 2, "--kp 1e308 is out of range"),
    (("diagram", "rr", "--payload", "1001", "--out", "d.dot"), 2, "--payload 1001 is out of range"),
    (("diagram", "rr", "--out", "d.svg/"), 2, "--out 'd.svg/': ends with '/', a folder; give a file name"),
    (("simulate", "rr", "--out", "r" * 300), 2, "its name is 300 bytes long; at most 200"),
    (("view", "rr", "--duration", "nan"), 2, "--duration: nan is not a positive number"),
    (("view", "rr", "--duration", "-1"), 2, "--duration: -1.0 is not a positive number"),
    (("view", "rr", "--port", "99999"), 2, "--port: 99999 is not allowed"),
    (("view", "rr", "--port", "1e3"), 2, "invalid int value: '1e3'"),
    (("view", "rr", "--q", "1e308,0"), 2, "joint1 = 1e+308 rad is outside its limits"),
    (("workspace", "rr", "--samples", "nan"), 2, "--samples: 'nan' is not a whole number"),
    (("workspace", "rr", "--samples", "10"), 2, "--samples 10 is not allowed: give a whole number 1000 … 1e9"),
    (("workspace", "rr", "--samples", "1e308"), 2, "--samples 1e308 is not allowed: give a whole number 1000 … 1e9"),
    (("workspace", "rr", "--samples", "1e10"), 2, "--samples 1e10 is not allowed"),
    (("workspace", "rr", "--resolution", "0"), 2, "--resolution 0 is out of range: allowed 1e-6 ≤ h ≤ 100 m"),
    (("workspace", "rr", "--resolution", "1e308"), 2, "--resolution 1e308 is out of range: allowed 1e-6 ≤ h ≤ 100"),
    (("workspace", "rr", "--resolution", "-inf"), 2, "--resolution -inf is out of range"),
    (("workspace", "rr", "--resolution", "nan"), 2, "--resolution nan is out of range"),
    (("workspace", "rr", "--seed", "1e308"), 2, "--seed: invalid int value: '1e308'"),
    (("workspace", "rr", "--seed", "-1"), 2, "--seed -1 is not allowed: give a whole number 0 … 4294967295"),
    (("workspace", "rr", "--seed", "4294967296"), 2, "--seed 4294967296 is not allowed"),
    # issue 36 item 6: counts bounded in the range table, before any work
    ((*LINE, "--tf", "1", "--samples", "100000000"), 2, "--samples 1e8 is out of range: allowed 2 ≤ samples ≤ 100000"),
    ((*LINE, "--fastest", "--grid", "1000000"), 2, "--grid 1e6 is out of range: allowed 3 ≤ grid ≤ 100000"),
    # issue 36 item 11: one plain-decimal rule for every number given as text
    ((*SIM, "--payload", "1_0"), 2, "--payload: invalid float value: '1_0'"),
    (("fk", "rr", "--q", "1_0,0"), 2, "--q: '1_0' is not a number"),
    (("size", "rr", "--safety-factor", "1_5"), 2, "--safety-factor: invalid float value: '1_5'"),
    (("workspace", "rr", "--samples", "1_000_000"), 2, "--samples: '1_000_000' is not a number"),
    ((*LINE, "--tf", "1", "--samples", "1_000"), 2, "--samples: invalid int value: '1_000'"),
    (("fk", "rr", "--q", "\u0661,0"), 2, "--q: '\u0661' is not a number"),
    # issue 36 item 15
    (("size", "rr", "--rate", "1e9"), 2, "--rate 1e9 is out of range: allowed 1 ≤ rate ≤ 10000 Hz"),
    # issue 36 item 16
    ((*LINE, "--tf", "1e-300"), 2, "--tf 1e-300 is out of range: allowed 1e-6 ≤ tf ≤ 1e6 s"),
    (("plan", "rr", "arc", "--centre", "0,0", "--axis", "0,0,1", "--from", "0.5,0", "--angle", "1e308", "--tf", "1"), 2,
     "--angle 1e308 is out of range: allowed -1e6 ≤ angle ≤ 1e6 rad"),
    # issue 36 item 19: argparse gave parse_floats a list
    (("fk", "rr", "--q=--"), 2, "--q: '--' is not a number"),
    # issue 36 item 22: the option and its value, not numpy's words
    (("simulate", "rr", "--from", "0,0", "--to", "1,1", "--tf", "1e-300", "--out", "run"), 2,
     "--tf 1e-300 is out of range"),
    (("simulate", "rr", "--from", "0,0", "--to", "1,1", "--tf", "1e-100", "--out", "run"), 2,
     "--tf 1e-100 is out of range"),
    (("plan", "rr", "line", "--from", "0.5,0.3", "--to", "1e308,0.5", "--tf", "1"), 2,
     "--to 1e308 is out of range: allowed -1e6 ≤ x, y, z ≤ 1e6 m"),
    ((*LINE, "--fastest", "--velocity=1e-300"), 2, "--velocity 1e-300 is out of range: allowed 1e-6 ≤ limit ≤ 10000"),
    ((*LINE, "--fastest", "--velocity=1e-5"), 2, "the time-optimal timing takes 49281.8 s, more than the 1000 s"),
    (("size", "rr", "--payload=1000.001"), 2, "--payload 1000.001 is out of range: allowed 0 ≤ payload ≤ 1000 kg"),
    # issue 36 item 23: empty or inapplicable options are errors, one duration rule for plan and simulate
    (("size", "rr", "--out", ""), 2, "--out '': give a folder name"),
    ((*LINE, "--tf", "1", "--simulate", ""), 2, "--simulate '': give a folder name"),
    (("fk", "rr", "--q", "0,0", "--tool", ""), 2, "--tool '': give a link's name"),
    ((*LINE, "--tf", "1e-9"), 2, "--tf 1e-9 is out of range: allowed 1e-6 ≤ tf ≤ 1e6 s"),
    (("simulate", "rr", "--from", "0,0", "--to", "1,1", "--tf", "1e-9", "--dt", "1e-10", "--out", "run"), 2,
     "--tf 1e-9 is out of range: allowed 1e-6 ≤ tf ≤ 1e6 s"),
    ((*LINE, "--tf", "1", "--through", "1,1", "2,2", "3,3"), 2, "--through: not an option of 'plan ARM line'"),
    # issue 36, also: a tool path's limit violation says by how much, in the joint's unit
    (("plan", "r2t", "line", "--from", "0.3,0.2,0.9", "--to", "0.3,0.2,0.5", "--tf", "1"), 2,
     "(joint2 = -0.002 m, 0.002 m below its lower limit)"),
]
#: Values at the ends of the allowed ranges: a result.
CLI_NUMBERS_ACCEPTED = [
    (("diagram", "rr", "--kp", "1e6", "--kd", "1e4", "--ki", "1e8", "--gravity", "0,0,-100", "--payload", "1000",
      "--out", "d.dot"), 0, "wrote d.dot"),
    (("diagram", "rr", "--kp", "0", "--kd", "0", "--gravity", "off", "--payload", "0", "--out", "d.dot"), 0, "wrote"),
    # issue 36 item 21: a negative value among --through's three points
    (("plan", "rr", "arc", "--through", "0.5,0.3", "0.2,0.5", "-0.3,0.5", "--tf", "1"), 0, "joints to"),
    ((*LINE, "--tf", "1e-6"), 0, "joints to"),  # the smallest duration
]


@pytest.mark.parametrize(("argv", "code", "fragment"), CLI_NUMBERS + CLI_NUMBERS_ACCEPTED,
                         ids=lambda v: " ".join(v)[:60] if isinstance(v, tuple) else None)
def test_cli_numbers(box, argv, code, fragment):
    check(box.main(*argv), code, fragment)
    assert box.debris("d.dot") == []


def test_option_help_states_the_ranges(box):
    out = box.main("simulate", "--help")
    text = " ".join(out.out.split())
    for fragment in ("0 ≤ kp ≤ 1e6 1/s²", "0 ≤ kd ≤ 10000 1/s", "0 ≤ ki ≤ 1e8 1/s³", "0 ≤ |g| ≤ 100 m/s²",
                     "0 ≤ payload ≤ 1000 kg", "1e-12 ≤ accuracy ≤ 0.1"):
        assert fragment in text


def test_plan_and_size_help_state_the_ranges(box):
    """Issue 36 items 6, 15, 22: the maxima of the counts and the rate, and the smallest duration, quoted in --help."""
    for command, fragments in ((("plan", "--help"), ("2 ≤ samples ≤ 100000", "3 ≤ grid ≤ 100000", "1e-6 ≤ tf ≤ 1e6 s")),
                               (("size", "--help"), ("1 ≤ rate ≤ 10000 Hz",))):
        text = " ".join(box.main(*command).out.split())
        for fragment in fragments:
            assert fragment in text


# ---- the Python API: the same checks, as ValueError: (keyword arguments of armlab.simulate, message fragment) ------
API_SIMULATE = [
    ({"kp": 1e308}, "kp 1e308 is out of range: allowed 0 ≤ kp ≤ 1e6"),
    ({"kd": [20, -1]}, "kd -1 is out of range"),
    ({"ki": float("nan")}, "ki nan is out of range"),
    ({"payload": 1e6}, "payload 1e6 is out of range: allowed 0 ≤ payload ≤ 1000 kg"),
    ({"payload": "x"}, "payload 'x' is not allowed"),
    ({"gravity": [1e308, 0, 0]}, "gravity 1e308,0,0 (|g| = 1e308) is out of range"),
    ({"gravity": [0, 0, float("inf")]}, "give 3 finite numbers"),
    ({"gravity": "up"}, "'up' is not a number"),
    ({"accuracy": 1e-300}, "accuracy 1e-300 is out of range: allowed 1e-12 ≤ accuracy ≤ 0.1"),
    ({"divergence_tolerance": -1}, "divergence tolerance = -1 is not allowed"),
]


@pytest.mark.parametrize(("kwargs", "fragment"), API_SIMULATE, ids=str)
def test_api_simulate(kwargs, fragment):
    import armlab

    arm = armlab.load("rr")
    with pytest.raises(ValueError) as error:
        armlab.simulate(arm, armlab.quintic(arm, [0, 0], [0.1, 0.1], 0.2), **kwargs)
    _one_line_error(error.value, fragment)


@pytest.mark.parametrize("motion", [None, "abc", [0.0, 1.0]], ids=repr)
def test_api_simulate_names_a_motion_that_is_not_one(motion):
    import armlab

    with pytest.raises(TypeError, match=f"motion: expected a Motion .*, got {type(motion).__name__}$"):
        armlab.simulate(armlab.load("rr"), motion)


#: Values of the wrong type for the API (issue 24, item 7): (call on arm = armlab.load("rr"), message fragment).
API_TYPES = [
    (lambda armlab, arm: arm.fk(np.array([0.1 + 1j, 0.0])), "q: expected real numbers, got dtype complex128"),
    (lambda armlab, arm: arm.fk(np.array([True, False])), "q: expected real numbers, got dtype bool"),
    (lambda armlab, arm: arm.fk(["0.1", "0"]), "q: expected real numbers, got dtype <U3"),
    (lambda armlab, arm: arm.inverse_dynamics([0, 0], [0, 0], [0j, 0]), "expected real numbers, got dtype complex"),
    (lambda armlab, arm: armlab.quintic(arm, [0, 0], [0.1, 0.1], tf="2"), "tf: expected a real number, got str"),
    (lambda armlab, arm: armlab.simulate(arm, armlab.quintic(arm, [0, 0], [0.1, 0.1], 0.2), payload="2"),
     "payload '2' is not allowed"),
    (lambda armlab, arm: armlab.simulate(arm, armlab.quintic(arm, [0, 0], [0.1, 0.1], 0.2), payload=True),
     "payload: expected a real number, got bool"),
    (lambda armlab, arm: arm.ik([0.5, 0.2], all="yes"), "all: expected True or False, got str"),
    (lambda armlab, arm: armlab.load("urm6", r1=True), "urm6: parameter r1 = True: expected a real number, got bool"),
    (lambda armlab, arm: armlab.load("urm6", theta3="x"),
     "urm6: parameter theta3 = 'x': expected a real number, got str"),
    # issue 36 items 29 and 32: ik refuses bools as fk does; None is named as None
    (lambda armlab, arm: arm.ik([True, False]), "target: expected real numbers, got dtype bool"),
    (lambda armlab, arm: armlab.quintic(arm, None, [1, 1], 1), "segment: start is None: give the joint values"),
    (lambda armlab, arm: armlab.quintic(arm, [0, 0], [True, False], 1), "end: expected real numbers, got dtype bool"),
]


@pytest.mark.parametrize(("call", "fragment"), API_TYPES, ids=lambda v: v if isinstance(v, str) else None)
def test_api_refuses_values_of_the_wrong_type(call, fragment):
    import armlab

    with pytest.raises(TypeError) as error:
        call(armlab, armlab.load("rr"))
    _one_line_error(error.value, fragment)


@pytest.mark.parametrize(("name", "override", "fragment"), [
    ("rr", {"L1": 1e300}, "rr: parameter L1 = 1e+300 is out of range: allowed |L1| ≤ 1e+12"),
    ("urm6", {"theta3": 1e300}, "parameter theta3 = 1e+300 is out of range"),
    ("urm6", {"theta3": float("nan")}, "parameter theta3 = nan is out of range"),
    ("ur5", {"d1": 0.1}, "ur5: takes no parameters (got d1)"),  # a library arm
    ("example:arm3r", {"L1": 5.0}, "example:arm3r: takes no parameters (got L1)"),  # a DH table file's arm
    ("tests/data/two_link.urdf", {"L1": 5.0}, "tests/data/two_link.urdf: takes no parameters (got L1)"),
])
def test_load_checks_its_overrides(name, override, fragment):
    import armlab

    with pytest.raises(ValueError) as error:
        armlab.load(name, **override)
    _one_line_error(error.value, fragment)


#: An arm's methods: (method of armlab.load("rr"), its arguments, message fragment).
API_ARM = [
    ("fk", ([0, 5],), "joint2 = 5 rad is outside its limits"),
    ("fk", ([0, 0, 0],), "expected 2 joint values"),
    ("jacobian", ([float("nan"), 0],), "q[0] = nan is not a finite number"),
    ("tool_motion", ([0, 0], [0, 0], [0, 2e6]), "qdd 2e6 is out of range"),
    ("inverse_dynamics", ([0, 0], [1e308, 0], [0, 0]), "qd 1e308 is out of range"),
    ("inverse_dynamics", ([0, 0], [0, 0], [0, 0, 0]), "qdd has shape (3,)"),
    ("inverse_dynamics", ([[0, 0]] * 2, [[0, 0]] * 3, [0, 0]), "q, qd and qdd have shapes that do not fit together (q "
     "(2, 2), qd (3, 2), qdd (2,))"),
    ("manipulability", ([0, 0], "sideways"), "axes"),
    ("ik", ([1e308, 0],), "out of range"),
    ("ik", ([0.9, 0],), "out of reach"),
]


#: The API's motions (issue 36 items 22 and 30): (call, message fragment of the one-line ValueError).
API_MOTIONS = [
    (lambda armlab: armlab.quintic(armlab.load("rr"), [0, 0], [1, 1], 1e-300),
     "tf 1e-300 is out of range: allowed 1e-6 ≤ tf ≤ 1e6 s"),  # numpy's LinAlgError before
    (lambda armlab: armlab.quintic(armlab.load("urm6"), np.zeros(6), np.full(6, 2e6), 1),
     "q 2e6 is out of range: allowed -1e6 ≤ q ≤ 1e6"),  # an unlimited joint held to ±1e6, as fk holds it
    (lambda armlab: armlab.line(armlab.load("rr"), [0.5, 0.3], [1e308, 0.5], 1), "line end 1e308"),
    (lambda armlab: armlab.arc(armlab.load("rr"), centre=[0, 0], axis=[0, 0, 1], start=[0.5, 0], angle=1e308, tf=1),
     "arc angle 1e308 is out of range"),
    (lambda armlab: armlab.line(armlab.load("rr"), [0.5, 0.3], [0.3, 0.5], 1, samples=10**8),
     "samples 1e8 is out of range: allowed 2 ≤ samples ≤ 100000"),
]


@pytest.mark.parametrize(("call", "fragment"), API_MOTIONS, ids=lambda v: v if isinstance(v, str) else None)
def test_api_motions(call, fragment):
    import armlab

    with pytest.raises(ValueError) as error:
        call(armlab)
    _one_line_error(error.value, fragment)


def test_a_run_saved_to_a_number_names_the_argument():
    """Issue 36 item 32: ``run.save(5)`` raised pathlib's TypeError text."""
    import armlab

    arm = armlab.load("rr")
    run = armlab.simulate(arm, armlab.quintic(arm, [0, 0], [0.1, 0.1], 0.05), log_period=0.01)
    with pytest.raises(TypeError) as error:
        run.save(5)
    _one_line_error(error.value, "out: expected a folder's name (a str or a pathlib.Path), got int 5")


@pytest.mark.parametrize(("method", "args", "fragment"), API_ARM, ids=str)
def test_api_arm_methods(method, args, fragment):
    import armlab

    with pytest.raises(ValueError) as error:
        getattr(armlab.load("rr"), method)(*args)
    _one_line_error(error.value, fragment)


# ---- segments files: (file content, exit code, fragment) -- run as `armlab simulate rr --segments seg.json` ------
def _seg(**spec) -> str:
    return json.dumps({"segments": [{"tf": 0.2, "from": [0, 0], "to": [0.1, 0.1], **spec}]})


SEGMENT_FILES = [
    ("", 2, "not valid JSON"),
    ("{", 2, "not valid JSON"),
    ("[" * 10_000 + "]" * 10_000, 2, "not valid JSON: nested too deeply"),
    ('{"segments": ' * 10_000 + "[]" + "}" * 10_000, 2, "nested too deeply"),
    ('{"segments": [{"tf": 1, "from": ' + "[" * 5000 + "]" * 5000 + "}]}", 2, "nested too deeply"),
    (b"\xff\xfe{}", 2, "it is not UTF-8 text"),
    ("[]", 2, 'expected an object with a non-empty list "segments"'),
    ('{"segments": []}', 2, 'non-empty list "segments"'),
    ('{"segments": {}}', 2, 'non-empty list "segments"'),
    ('{"segments": [1]}', 2, "segment 1: expected an object"),
    (json.dumps({"deg": "yes", "segments": [{"tf": 1}]}), 2, '"deg" = "yes" must be true or false'),
    (_seg(tf="2"), 2, 'tf = "2" must be a finite number'),
    (_seg(tf=True), 2, "tf = true must be a finite number"),
    (_seg(tf=None), 2, "tf = null must be a finite number"),
    (_seg(tf=[2]), 2, "tf = [2] must be a finite number"),
    (_seg(tf=0), 2, "a duration must be a positive finite number"),
    (_seg(tf=-1), 2, "a duration must be a positive finite number"),
    (_seg().replace("0.2", "NaN"), 2, "tf = NaN must be a finite number"),
    (_seg().replace("0.2", "1e999"), 2, "tf = Infinity must be a finite number"),
    (_seg().replace("0.2", "1" + "0" * 5000), 2, "tf = Infinity must be a finite number"),
    (json.dumps({"segments": [{"from": [0, 0], "to": [0.1, 0.1]}]}), 2, 'needs "tf"'),
    (_seg(speed=1), 2, "unknown key(s) speed"),
    (_seg(**{"from": [0, 0, 0]}), 2, "from has 3 values; rr has 2 joints"),
    (_seg(**{"from": ["a", 0]}), 2, "must be a list of numbers"),
    (_seg(**{"from": [True, 0]}), 2, "must be a list of numbers"),
    (_seg(**{"from": []}), 2, "must be a list of numbers"),
    (_seg().replace("[0, 0]", "[1e999, 0]"), 2, "has a value that is not a finite number"),
    (_seg().replace("[0, 0]", "[1" + "0" * 400 + ", 0]"), 2, "has a value that is not a finite number"),
    (_seg(**{"from": [10, 0]}), 2, "outside its limits"),
    (_seg(from_point=[0.4, 0.3]), 2, "give 'from' or 'from_point', not both"),
    (_seg(rate=[1, 1]), 2, 'give exactly one of "to", "to_point" or "rate"'),
    (json.dumps({"segments": [{"tf": 1, "to": [0.1, 0.1]}]}), 2, 'the first segment needs "from" or "from_point"'),
    (json.dumps({"segments": [{"tf": 1, "from": [0, 0], "to_point": [0.4, 0.3], "to_branch": 2}]}), 2,
     "to_branch = 2 is not allowed"),
    (json.dumps({"segments": [{"tf": 1, "from": [0, 0], "to_point": [0.4, 0.3], "to_branch": True}]}), 2,
     "to_branch = true is not allowed"),
    (json.dumps({"segments": [{"tf": 1, "from": [0, 0], "to_point": [5, 5]}]}), 2, "to_point"),
    (json.dumps({"segments": [{"tf": 1, "from": [0, 0], "to_point": [0.4, 0.3], "to_pitch": "x"}]}), 2,
     'to_pitch = "x" must be a finite number'),
    (_seg(label=["a"] * 3), 0, "segments from seg.json"),
    # issue 36 item 6: a tool path's IK samples are bounded (1e8: gigabytes)
    (json.dumps({"segments": [{"tf": 1, "from_point": [0.5, 0.3], "line_to": [0.3, 0.5], "samples": 100_000_000}]}),
     2, "segment 1: samples 1e8 is out of range: allowed 2 ≤ samples ≤ 100000"),
    # issue 36 item 9: a misspelt top-level key is refused, as a segment's are (it simulated radians)
    (json.dumps({"degs": True, "segments": [{"from": [1, 2], "to": [2, 1], "tf": 2}]}), 2,
     "unknown key(s) degs; allowed: deg, segments"),
    # issue 36 item 8: a documented maximum, checked before any segment is read (1 000 took 41 s)
    (json.dumps({"segments": [{"from": [0, 0], "to": [0.1, 0.1], "tf": 0.05}]
                 + [{"to": [0.1 * (k % 2), 0.1 * (k % 2)], "tf": 0.05} for k in range(200)]}), 2,
     "201 segments, more than the 200 allowed"),
]


@pytest.mark.parametrize(("content", "code", "fragment"), SEGMENT_FILES, ids=lambda v: repr(v)[:40])
def test_segments_files(box, content, code, fragment):
    box.write("seg.json", content)
    check(box.main("simulate", "rr", "--segments", "seg.json", "--dt", "0.01", "--out", "run"), code, fragment)
    assert box.debris(*(["run"] if code == 0 else [])) == []


# ---- sizing inputs (issue 36 items 8, 12, 13, 14, 24, 25): (files, options, fragment) -- `armlab size rr … --out sz`:
# one line, exit 2, and no sz/ nor its temporary left (the output folder is made before the catalogues are read)
MOTORS = "name,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgcm2,mass_kg\n"
GEARBOXES = "name,ratio,efficiency,rated_torque_Nm,peak_torque_Nm,max_input_speed_rpm,input_inertia_kgcm2,mass_kg\n"
CYCLE = {"steps": [{"segments": [{"from": [0, 0], "to": [1, 1], "tf": 1}]}]}


def _cases(**case) -> dict[str, str]:
    return {"cases.json": json.dumps([{"mass": 1.0} | case])}


SIZING_FILES = [
    # item 24: an error during the sizing (the catalogues are read there) left .sz.PID.X.tmp behind
    ({"m.csv": MOTORS.replace("mass_kg", "weight_kg") + "m1,10,30,3000,5000,1,2\n"}, ("--motors", "m.csv"),
     "unknown column 'weight_kg'"),
    (_cases(inertia=5), ("--load-cases", "cases.json"), '"inertia" = 5 must be a list of 3 rows of 3 numbers'),
    (_cases(offset=5), ("--load-cases", "cases.json"), '"offset" = 5 must be a list of 3 numbers'),
    (_cases(inertia=[1, 2, 3]), ("--load-cases", "cases.json"), '"inertia" = [1, 2, 3] must be a list of 3 rows'),
    (_cases(offset=[1e300, 0, 0]), ("--load-cases", "cases.json"), "offset 1e300 is out of range"),
    (_cases(inertia=[[1e300, 0, 0], [0, 1e300, 0], [0, 0, 1e300]]), ("--load-cases", "cases.json"),
     "(|I| = 1e300) is out of range: allowed 0 ≤ |I| ≤ 1e6 kg·m²"),
    (_cases(inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), ("--load-cases", "cases.json"), "is not symmetric"),
    (_cases(name="a\nb"), ("--load-cases", "cases.json"), "name 'a\\nb' is not allowed: a name holds no control"),
    (_cases(name="x" * 100_000), ("--load-cases", "cases.json"), "(100,000 characters) is not allowed: at most 100"),
    ({"cases.json": json.dumps([{"mass": 1.0}] * 101)}, ("--load-cases", "cases.json"),
     "101 load cases, more than the 100 allowed"),
    ({}, ("--payload", ",".join(["1"] * 101)), "101 load cases, more than the 100 allowed"),
    ({}, ("--safety-factor", "1e308"), "safety factor 1e+308 is not allowed: 1 ≤ S ≤ 100"),
    ({"cycle.json": json.dumps({"steps": [*CYCLE["steps"], {"dwell": 1e308}]})}, ("--duty-cycle", "cycle.json"),
     "dwell 1e308 is out of range: allowed 0 ≤ dwell ≤ 1e6 s"),
    ({"cycle.json": json.dumps({"steps": [*CYCLE["steps"], *[{"dwell": 0.1}] * 200]})}, ("--duty-cycle", "cycle.json"),
     "201 segments and dwells, more than the 200 allowed"),
    ({"m.csv": MOTORS + "m1,10,30,3000,5000,1e308,2\n"}, ("--motors", "m.csv"),
     "rotor_inertia_kgcm2 1e308 is out of range: allowed 1e-12 ≤ value ≤ 1e12"),
    ({"g.csv": GEARBOXES + "g1,1e-300,0.9,100,200,5000,1,1\n"}, ("--gearboxes", "g.csv"),
     "ratio 1e-300 is out of range"),
    ({"m.csv": MOTORS.replace("\n", ",mass_kg\n") + "m1,10,30,3000,5000,1,2,3\n"}, ("--motors", "m.csv"),
     "column 'mass_kg' is given twice"),
    ({"m.csv": MOTORS + "x" * 131_073 + ",10,30,3000,5000,1,2\n"}, ("--motors", "m.csv"),
     "m.csv cannot be read as CSV: field larger than field limit (131072)"),
    ({"m.csv": MOTORS + '"m\n1",10,30,3000,5000,1,2\n'}, ("--motors", "m.csv"), "name 'm\\n1' is not allowed"),
    ({"m.csv": MOTORS + "x" * 100_000 + ",10,30,3000,5000,1,2\n"}, ("--motors", "m.csv"), "at most 100"),
    ({"m.csv": MOTORS + "m1,10,30,3000,5000," + "1" * 1000 + "x,2\n"}, ("--motors", "m.csv"),
     "rotor_inertia_kgcm2 = '1111111111"),
]


@pytest.mark.parametrize(("files", "options", "fragment"), SIZING_FILES, ids=lambda v: str(v)[:40])
def test_sizing_files(box, files, options, fragment):
    for name, content in files.items():
        box.write(name, content)
    outcome = box.main("size", "rr", *options, "--out", "sz")
    check(outcome, 2, fragment)
    assert len(outcome.err) < 800, outcome.err  # the values as typed cut (a catalogue's allowed columns: 650)
    assert box.debris() == []


# ---- sweep options (issue 24, items 14, 18, 20, 21): (options, fragment) -- refused before the folder is made
SWEEP_OPTIONS = [
    (("--workers", "100000"), "--workers 100000: at most"),
    (("--scheduler", "tcp://"), "--scheduler 'tcp://': give HOST:PORT (a port 1 … 65535) after tcp://"),
    (("--scheduler", "tcp://127.0.0.1:abc"), "give HOST:PORT"),
    (("--scheduler", "tcp://127.0.0.1:0"), "give HOST:PORT"),
    (("--scheduler", "inproc://x"), "inproc:// lives inside one process; give tcp://HOST:PORT"),
    (("--scheduler", "ucx://127.0.0.1:8786"), "ucx:// is not available in this Dask"),
    (("--scheduler", "tls://127.0.0.1:8786"), "tls:// needs Dask's TLS settings"),
    (("--scheduler", "http://x" + "y" * 10_000), "--scheduler 'http://xyyyyy"),
    pytest.param(("--scheduler", "tcp://127.0.0.1:1"), "cannot connect", marks=pytest.mark.slow),  # 10 s timeout
]


@pytest.mark.parametrize(("options", "fragment"), SWEEP_OPTIONS, ids=lambda v: " ".join(v)[:40])
def test_sweep_options(box, options, fragment):
    box.write("study.json", json.dumps({"arm": "rr", "vary": {"L1": {"values": [0.3, 0.4]}}, "evaluate": ["reach"],
                                        "samples": 5000}))
    outcome = box.main("sweep", "study.json", "--out", "sw", *options)
    check(outcome, 2, fragment)
    assert len(outcome.err) < 300 and box.debris() == []  # one short line; no sw/ made


# ---- study files: (content, exit code, fragment) -- `armlab sweep study.json --out out`, refused before any work
def _study(**change) -> str:
    return json.dumps({"arm": "rr", "vary": {"L1": {"values": [0.3, 0.4]}}, "evaluate": ["reach"], "samples": 5000}
                      | change)


STUDY_FILES = [
    ("[" * 10_000 + "]" * 10_000, 2, "study study.json: not valid JSON: nested too deeply"),
    ('{"arm": "rr", "vary": ' * 10_000 + "{}" + "}" * 10_000, 2, "nested too deeply"),
    (b"\xff{}", 2, "it is not UTF-8 text"),
    (_study(vary={"L1": {"from": 0.1, "to": 0.5, "steps": 10**9}}), 2, "steps = 1,000,000,000 is more than the 10,000"),
    (_study(vary={"L1": {"from": 0.1, "to": 0.5, "steps": 1e9}}), 2, "steps = 1000000000.0 must be a whole number 1 …"),
    (_study(vary={"L1": {"from": 0.1, "to": 0.5, "steps": 101}, "L2": {"values": list(range(1, 101))}}), 2,
     "vary makes 10,100 candidates (101 × 100), more than the 10,000"),
    (_study(vary={"L1": {"values": [0.3, 1e308]}}), 2, "vary.L1: 1e+308 is out of range: allowed |L1| ≤ 1e+12"),
    (_study(vary={"L1": {"from": -1e13, "to": 1, "steps": 2}}), 2, "vary.L1: -1e+13 is out of range"),
    (_study(samples=10**11), 2, "samples 1e11 is not allowed: give a whole number 1000 … 1e9"),
    (_study(samples=1e11), 2, "samples 1e11 is not allowed"),
    (_study(seed=-1), 2, "seed -1 is not allowed: give a whole number 0 … 4294967295"),
    (_study(resolution=1e308), 2, "resolution 1e308 is out of range: allowed 1e-6 ≤ h ≤ 100 m"),
    (_study(evaluate=["peak_torque"], vary={"tf": {"values": [1, 1e308]}}), 2, "tf 1e308 is out of range"),
    (_study(evaluate=["peak_torque"], vary={"payload": {"values": [1e6]}}), 2, "payload 1e6 is out of range"),
    (_study(evaluate=["peak_torque"], tf=1e-5), 2, "log period = 0.001 s is longer than the motion (1e-05 s)"),
    (_study(evaluate=["peak_torque"], tf=1e-5, simulate=True), 2, "log period = 0.001 s is longer than the motion"),
    (_study(evaluate=["peak_torque"], tf=1e-9), 2, "tf 1e-9 is out of range: allowed 1e-6 ≤ tf ≤ 1e6 s"),  # issue 36
    (_study(evaluate=["peak_torque"], tf=1e5, simulate=True), 2, "100,000,001 log samples, more than the 1,000,000"),
    # issue 36 item 31: a long value is echoed cut (the list was echoed whole, a 9 KB line)
    (_study(evaluate=["reach"] * 1000), 2, '"reach", "reach", "rea… repeats an objective'),
    (_study(evaluate=["x" * 10_000]), 2, "evaluate: unknown objective 'xxxxxxxx"),
]


@pytest.mark.parametrize(("content", "code", "fragment"), STUDY_FILES, ids=lambda v: repr(v)[:40])
@pytest.mark.timeout(60)
def test_study_files(box, content, code, fragment):
    box.write("study.json", content)
    outcome = box.main("sweep", "study.json", "--out", "out")
    check(outcome, code, fragment)
    assert len(outcome.err) < 400, outcome.err  # the value as typed, cut (issue 36 item 31)
    assert box.debris() == []


# ---- arm files through the CLI (the models' own tables: tests/test_custom.py, test_security.py): --------------
# (file name, content, argv with {} for the file, exit code, fragment)
DH = "type,a,alpha,d,theta,lower,upper\n"
DEEP_URDF = ('<robot name="x"><link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/>'
             '<child link="b"/><limit lower="-1" upper="1"/></joint>' + "<x>" * 5000 + "</x>" * 5000 + "</robot>")
ARM_FILES = [
    ("empty.csv", DH, ("show", "{}"), 2, "empty.csv: the DH table has no rows"),
    ("nan.csv", DH + "R,nan,0,0,0,-1,1\n", ("fk", "{}", "--q", "0"), 2, "a = 'nan' is not a finite number"),
    ("rev.csv", DH + "R,0.5,0,0,0,1,-1\n", ("show", "{}"), 2, "lower = 1.0 must be below upper = -1.0"),
    ("huge.csv", DH + "R,1e308,0,0,0,-1,1\nR,1e308,0,0,0,-1,1\n", ("fk", "{}", "--q", "0,0"), 2, ""),
    ("kin.csv", DH + "R,0.5,0,0,0,-1,1\n", ("simulate", "{}", "--out", "run"), 2, "kin is a kinematic arm"),
    ("kin.csv", DH + "R,0.5,0,0,0,-1,1\n", ("fk", "{}", "--q", "0.5"), 0, "tool"),
    ("bad.urdf", "not xml", ("show", "{}"), 2, "bad.urdf is not valid XML"),
    ("rev.urdf", '<robot name="x"><link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/>'
     '<child link="b"/><limit lower="1" upper="-1"/></joint></robot>', ("show", "{}"), 2, "the limits are reversed"),
    ("bin.csv", b"\xff\xfe\x00", ("show", "{}"), 2, "bin.csv"),
    # issue 24, item 22: messages that say what is wrong
    ("kin.csv", DH + "R,0.5,0,0,0,-1,1\n", ("diagram", "{}", "--out", "d.dot"), 2,
     "kin is a kinematic arm (its file gives no masses): armlab diagram"),
    ("heavy.csv", "type,a,alpha,d,theta,lower,upper,mass,cx\nR,0.5,0,0,0,-3,3,1e12,-0.25\nR,0.4,0,0,0,-3,3,0.5,-0.2\n",
     ("simulate", "{}", "--from", "0,0", "--to", "0.1,0.1", "--tf", "0.2", "--out", "run"), 2,
     "heavy: the mass matrix is too ill-conditioned to simulate: its eigenvalues span"),
    # issue 24, items 9 and 16: a workspace voxels cannot measure is one line, not a wrong number or a traceback
    ("far.csv", DH + "R,1e12,0,0,0,-3,3\nR,0.4,0,0,0,-3,3\n", ("workspace", "{}", "--samples", "1000"), 2,
     "far: the tool point reaches up to 1e+12 m, beyond 1e+06 m"),
    ("tiny.csv", DH + "R,1e-300,0,0,0,-3,3\nR,1e-300,0,0,0,-3,3\n", ("workspace", "{}", "--samples", "1000"), 2,
     "less than the smallest voxel edge 1e-06 m"),
    ("still.urdf", '<robot name="still"><link name="a"/><link name="b"><inertial><mass value="1"/><inertia ixx="1" '
     'iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link><joint name="j" type="revolute"><parent link="a"/>'
     '<child link="b"/><origin xyz="0.5 0 0"/><axis xyz="0 0 1"/><limit lower="0" upper="0"/></joint></robot>',
     ("workspace", "{}", "--samples", "1000"), 2, "the tool point does not move"),
    # issue 36, item 17: elements nested deeper than Python's recursion limit
    *[("deep.urdf", DEEP_URDF, argv, 2, "deep.urdf (URDF): elements nested more than 256 deep are not allowed")
      for argv in (("show", "{}"), ("simulate", "{}", "--out", "run"))],
    # issue 36, item 25: 150 000 unconnected links named in a line of bounded length
    ("many.urdf", '<robot name="x">' + "".join(f'<link name="l{k}"/>' for k in range(150_000)) + "</robot>",
     ("show", "{}"), 2, "a serial arm has one root link, found 150000: 'l0', 'l1', 'l2' and 149997 more"),
    # issue 36 item 18: a damper stiffer than the explicit integrator follows is refused up front (1e12 ended in
    # Drake's "Detected NaN in the actuation input port"; open loop, 1e6 in "Times must be at least 2.2e-16 apart")
    ("d.csv", "gear_ratio,viscous\n100,1e12\n80,0\n", ("simulate", "rr", "--tf", "0.5", "--drives", "{}", "--out",
                                                       "run"), 2,
     "d.csv: viscous 1e12 is out of range: allowed 0 ≤ B ≤ 10000 N·m·s/rad"),
    ("d.csv", "gear_ratio,viscous_motor\n100,10\n80,0\n", ("simulate", "rr", "--mode", "inverse_dynamics", "--drives",
                                                            "{}", "--out", "run"), 2,
     "viscous_motor (joint side: G²·B_m) 100000 is out of range"),
]


@pytest.mark.parametrize(("name", "content", "argv", "code", "fragment"), ARM_FILES, ids=lambda v: str(v)[:30])
def test_arm_files(box, name, content, argv, code, fragment):
    box.write(name, content)
    check(box.main(*(a.replace("{}", name) for a in argv)), code, fragment)
    assert box.debris() == []


# ---- a sample of the cases above as real processes: exit code, stderr and the interpreter's exit as a user sees
SAMPLE = [*CLI_NUMBERS[::8], *CLI_NUMBERS_ACCEPTED[:1]]


@pytest.mark.parametrize(("argv", "code", "fragment"), SAMPLE, ids=lambda v: " ".join(v)[:40] if isinstance(v, tuple)
                         else None)
def test_cli_numbers_as_processes(box, argv, code, fragment):
    check(box.run(*argv), code, fragment)
    assert box.debris("d.dot") == []


@pytest.mark.parametrize(("content", "code", "fragment"), [SEGMENT_FILES[2], SEGMENT_FILES[11]], ids=["deep", "tf"])
def test_segments_files_as_processes(box, content, code, fragment):
    box.write("seg.json", content)
    check(box.run("simulate", "rr", "--segments", "seg.json", "--out", "run"), code, fragment)
    assert box.debris() == []


# ---- resource limits: files that are too big, endless, or not files; (make the path, exit code, fragment) ---------
def _fifo(box: Sandbox) -> str:
    os.mkfifo(box.cwd / "fifo")
    box.keep()
    return "fifo"


def _huge(box: Sandbox) -> str:
    box.write("huge.json", '{"segments": [' + " " * MAX_INPUT_BYTES + "]}")
    return "huge.json"


def _folder(box: Sandbox) -> str:
    box.mkdir("folder")
    return "folder"


RESOURCE_LIMITS = [
    (lambda box: "/dev/zero", 2, "/dev/zero: cannot read it: not a regular file"),
    (lambda box: "/dev/stdin", 2, "not a regular file"),
    (_fifo, 2, "fifo: cannot read it: not a regular file"),
    (_folder, 2, "folder: cannot read it: not a regular file"),
    (_huge, 2, "larger than 10 MB"),
    (lambda box: "missing.json", 2, "missing.json: cannot read it: No such file or directory"),
]


#: Work that cannot finish (the estimate made before the run): (argv, exit code, fragment).
WORK_LIMITS = [
    ((*SIM, "--tf", "1e6"), 2, "more than the 1,000,000 allowed"),
    ((*SIM, "--dt", "1e-9"), 2, "2,000,000,001 log samples"),
    (("simulate", "urm6", "--from", "0,0,0,0,0,0", "--to", "1e6,0,0,0,0,0", "--out", "run"), 2, "integrator steps"),
]


@pytest.mark.parametrize(("argv", "code", "fragment"), WORK_LIMITS, ids=lambda v: " ".join(v)[:50]
                         if isinstance(v, tuple) else None)
@pytest.mark.timeout(30)
def test_work_limits(box, argv, code, fragment):
    check(box.main(*argv), code, fragment)
    assert box.debris() == []


@pytest.mark.timeout(30)
def test_a_segments_file_with_endless_work(box):
    box.write("seg.json", json.dumps({"segments": [{"tf": 1e7, "from": [0, 0], "to": [0.1, 0.1]}]}))
    check(box.main("simulate", "rr", "--segments", "seg.json", "--out", "run"), 2, "allowed")
    assert box.debris() == []


@pytest.mark.parametrize(("make", "code", "fragment"), RESOURCE_LIMITS, ids=lambda v: getattr(v, "__name__", None))
@pytest.mark.timeout(30)
def test_resource_limits(box, make, code, fragment):
    check(box.main("simulate", "rr", "--segments", make(box), "--out", "run"), code, fragment)
    assert box.debris() == []


# ---- property-based: the parsers give a result or a one-line ValueError ----------------------------------------
def _one_line_error(error: ValueError, *fragments: str) -> None:
    text = str(error)
    assert text and "\n" not in text, text
    for fragment in fragments:
        assert fragment in text


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet=st.sampled_from("0123456789.,-+eEinfatxINF _\u0661 "), max_size=40))
def test_parse_floats_property(text):
    try:
        values = parse_floats(text, "--v")
    except ValueError as error:
        _one_line_error(error, "--v")
        return
    assert len(values) == text.count(",") + 1
    assert all(isinstance(v, float) and math.isfinite(v) for v in values)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=1, max_size=8))
def test_parse_floats_round_trips_every_float(values):
    text = ",".join(repr(v) for v in values)
    if all(math.isfinite(v) for v in values):
        assert parse_floats(text, "--v") == values
    else:
        with pytest.raises(ValueError, match="is not a finite number"):
            parse_floats(text, "--v")


ARMS = {name: get_arm(name) for name in ("rr", "r2t", "urm6")}


@settings(max_examples=200, deadline=None)
@given(st.sampled_from(sorted(ARMS)), st.lists(st.floats(width=64), min_size=1, max_size=7), st.booleans())
def test_joint_values_property(name, values, deg):
    arm = ARMS[name]
    try:
        q = joint_values(arm, ",".join(repr(v) for v in values), deg)
    except ValueError as error:
        _one_line_error(error)
        return
    lo, hi = arm.limit_arrays(unlimited=np.inf)
    assert q.shape == (arm.n,) and np.all(np.isfinite(q)) and np.all((lo - 1e-12 <= q) & (q <= hi + 1e-12))


_json = st.recursive(
    st.none() | st.booleans() | st.floats(allow_nan=False) | st.integers() | st.text(max_size=5),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(max_size=5), children, max_size=4),
    max_leaves=12,
)
_value = st.one_of(_json, st.lists(st.floats(-3, 3), min_size=1, max_size=3))
_segment = st.fixed_dictionaries({}, optional={
    key: _value for key in ("tf", "from", "to", "rate", "from_point", "to_point", "to_branch", "label", "x")
})


@pytest.mark.slow
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.one_of(_json, st.fixed_dictionaries({"segments": st.lists(_segment, max_size=3)},
                                              optional={"deg": _json})))
def test_read_segments_property(tmp_path, data):
    path = tmp_path / "seg.json"
    path.write_text(json.dumps(data))
    try:
        motion = read_segments(ARMS["rr"], path)
    except ValueError as error:
        _one_line_error(error, "--segments")
        return
    assert motion.duration > 0 and np.all(np.isfinite([s.q_end for s in motion.segments]))


_cell = st.one_of(st.sampled_from(["", "R", "T", "r", "0", "0.5", "-1", "90", "1e308", "nan", "inf", "x", '"', "1,2"]),
                  st.floats().map(repr))
_dh_lines = st.lists(st.lists(_cell, min_size=0, max_size=8).map(",".join), max_size=6)


@pytest.mark.slow
@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.sampled_from(["type,a,alpha,d,theta,lower,upper", "type,a,alpha,d,theta,lower,upper,mass",
                        "a,b", "", "# units: deg\ntype,a,alpha,d,theta,lower,upper"]), _dh_lines)
def test_read_dh_csv_property(tmp_path, header, lines):
    """The models helper's DH reader: a table or a one-line ValueError naming the file."""
    from armlab.models.read_dh import read_dh_csv

    path = tmp_path / "arm.csv"
    path.write_text("\n".join([header, *lines]) + "\n")
    try:
        table, limits, _ = read_dh_csv(path)
    except ValueError as error:
        _one_line_error(error, str(path))
        return
    assert len(table.rows) == len(limits) > 0


_spec = st.fixed_dictionaries({}, optional={
    "from": _value, "to": _value, "steps": st.one_of(st.integers(-3, 12), _json), "values": _value,
    "unit": st.sampled_from(["deg", "rad", "m", "kg", "s", "furlong"]),
})
_near_valid_study = st.fixed_dictionaries(
    {"arm": st.just("rr"),
     "vary": st.fixed_dictionaries({"L1": st.fixed_dictionaries({"from": st.floats(-1, 2), "to": st.floats(-1, 2),
                                                                 "steps": st.integers(-1, 6)})}),
     "evaluate": st.just(["reach"])},
    optional={"samples": st.integers(0, 20_000), "seed": st.integers(-2, 5), "resolution": st.floats(-1, 1)},
)
_study = _near_valid_study | st.fixed_dictionaries(
    {"arm": st.one_of(st.sampled_from(["rr", "urm6", "puma", "arm.csv"]), _json),
     "vary": st.one_of(st.dictionaries(st.sampled_from(["L1", "L2", "theta3", "payload", "tf", "zz"]), _spec,
                                       max_size=2), _json),
     "evaluate": st.one_of(st.lists(st.sampled_from(["reach", "workspace_volume", "peak_torque", "nope"]),
                                    max_size=3), _json)},
    optional={"samples": st.one_of(st.integers(0, 5000), _json), "seed": _json, "payload": _json, "tf": _json,
              "simulate": _json, "resolution": _json},
)


@pytest.mark.slow
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(_study)
def test_load_study_property(tmp_path, data):
    """The analysis helper's study files (``armlab sweep STUDY.json``): a study or a one-line ValueError."""
    from armlab.analysis.study import load_study

    path = tmp_path / "study.json"
    path.write_text(json.dumps(data))
    try:
        study = load_study(path)
    except ValueError as error:
        _one_line_error(error, str(path))
        return
    assert study.candidates


# ---- echoed values are cut to a readable length (issue 24, item 21) ----------------------------------------------
def test_a_huge_input_is_echoed_cut(box):
    import armlab

    with pytest.raises(ValueError) as error:
        armlab.load("urm6").ik(np.zeros((100_000, 3)))
    assert "has 300000 values" in str(error.value) and len(str(error.value)) < 300
    key = "k" * 1_000_000
    box.write("study.json", json.dumps({"arm": "rr", "vary": {"L1": {"values": [0.3]}}, "evaluate": ["reach"],
                                        key: 1}))
    outcome = box.main("sweep", "study.json", "--out", "sw")
    check(outcome, 2, "unknown key 'kkkk")
    assert len(outcome.err) < 400
    box.write("seg.json", json.dumps({"segments": [{"tf": 0.2, "from": [0, 0], "to": [0.1, 0.1], key: 1}]}))
    outcome = box.main("simulate", "rr", "--segments", "seg.json", "--out", "run")
    check(outcome, 2, "unknown key(s) kkkk")
    assert len(outcome.err) < 400
