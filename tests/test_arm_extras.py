"""A paper arm's extras come from its own module: the registry finds it, the generic code asks the arm.

``tests/arm1r.py`` defines a sixth paper arm (a one-joint planar arm with a closed form, a paper motion
and a scheme) and registers it itself; loading, solving, moving and drawing it needs no other module.
The paper arms' own extras (branch counts, pitch, paths), what a user's arm named like a paper arm
gets (none), and the registry's order and refusals.
"""

from __future__ import annotations

import importlib
import sys
import types

import numpy as np
import pytest
from helpers import armlab_main

import armlab
from armlab.models import ARMS, get_arm, register, unregister
from armlab.presentation.draw import default_q, draw_arm, scheme

TOL = 1e-9  # the IK's own check of every solution: FK reaches the target to 1e-9 m


@pytest.fixture
def arm1r():
    """The arm1r module, imported afresh (so that it registers itself); the registry as before afterwards."""
    sys.modules.pop("arm1r", None)
    module = importlib.import_module("arm1r")
    yield module
    unregister("arm1r")
    sys.modules.pop("arm1r", None)


def test_the_paper_arms_are_found_in_the_order_of_their_papers():
    assert list(ARMS) == ["rr", "rrrr", "arm4r", "r2t", "urm6"]
    assert [get_arm(name).name for name in ARMS] == list(ARMS)  # each module builds the arm it is named after


def test_a_sixth_arm_registers_itself_and_is_listed_after_them(arm1r):
    assert list(ARMS)[-1] == "arm1r" and ARMS["arm1r"] is arm1r
    lines = armlab_main("list").stdout.split("library arms")[0].splitlines()  # the paper arms, then the library's
    assert [line.split()[0] for line in lines] == ["rr", "rrrr", "arm4r", "r2t", "urm6", "arm1r"]
    assert lines[-1].startswith("arm1r  1 DOF  R      paper test: a one-joint arm")
    arm = armlab.load("arm1r", L=0.7)
    assert arm.name == "arm1r" and arm.parameters["L"] == 0.7  # exact: the module's own constants, copied
    with pytest.raises(ValueError, match="arm1r: unknown parameter 'L9'; allowed: L, m"):
        armlab.load("arm1r", L9=1.0)


def test_the_sixth_arms_closed_form_is_used(arm1r, monkeypatch, rng):
    """``arm.ik(…, all=True)`` solves arm1r by its own closed form (the numerical solver is not called), also with
    overridden parameters; every solution reaches the target by FK to 1e-9 m."""
    import armlab.kinematics.ik as ik

    def no_numeric(*args, **kwargs):
        raise AssertionError("the numerical solver was called for an arm with a closed form")

    monkeypatch.setattr(ik, "numeric_ik", no_numeric)
    for L in (0.5, 0.8):
        arm = armlab.load("arm1r", L=L)
        for q in rng.uniform(-np.pi, np.pi, size=(20, 1)):
            target = arm.fk(q)[:3, 3]
            (solution,) = arm.ik(target, all=True)
            np.testing.assert_allclose(solution, q, rtol=0, atol=1e-12)  # atan2 of an exact circle point
            np.testing.assert_allclose(arm.fk(solution)[:3, 3], target, rtol=0, atol=TOL)
        with pytest.raises(ValueError, match="out of reach of arm1r: its tip moves on the circle of radius"):
            arm.ik([L + 0.1, 0.0, 0.0])
        with pytest.raises(ValueError, match=r"pitch = 0\.2 is not an option of arm1r's inverse kinematics; it takes "
                                             "none"):
            arm.ik(arm.fk([0.3])[:3, 3], pitch=0.2)


@pytest.mark.slow
def test_the_sixth_arms_paper_motion_and_scheme(arm1r, tmp_path):
    arm = armlab.load("arm1r")
    motion = armlab.paper_motion(arm)
    assert motion.description == "test: a quarter turn in 1 s"
    # exact: the module's own numbers, copied
    np.testing.assert_array_equal(motion.segments[0].q_start, [-np.pi / 4])  # exact: the module's own numbers, copied
    assert armlab.paper_motion(arm, tf=2.0).description == "test: a quarter turn in 2 s"
    with pytest.raises(ValueError, match=r"path 'abcd' is not available for arm1r; paths: rr: abcd"):
        armlab.paper_motion(arm, "abcd")
    # exact: the module's drawn pose, copied
    np.testing.assert_array_equal(default_q(arm), [np.pi / 4])  # exact: the module's drawn pose, copied
    drawn = scheme(arm, default_q(arm))
    assert drawn.table_title.startswith("standard DH") and drawn.table == ["1: 0.5 m, 0°, 0 m, q1"]
    path = draw_arm(arm, default_q(arm), tmp_path / "arm1r.svg")
    assert "arm1r: kinematic scheme at q = (45°) — cf. paper test Fig. 1" in path.read_text()
    assert armlab_main("draw", "arm1r", "--out", str(tmp_path / "cli.png")).returncode == 0


def test_paper_arms_carry_their_closed_forms_paths_and_schemes():
    counts = {name: len(get_arm(name).closed_form.branches) for name in ("rr", "arm4r", "r2t")}
    assert counts == {"rr": 2, "arm4r": 4, "r2t": 2}
    assert get_arm("rrrr").closed_form is None and get_arm("urm6").closed_form is None
    assert dict(get_arm("arm4r").closed_form.options) == {"pitch": "its tool pitch θ2+θ3+θ4"}
    assert [name for name in ARMS if get_arm(name).paths] == ["rr"] and list(get_arm("rr").paths) == ["abcd"]
    assert get_arm("rr", L1=0.5).closed_form is not None  # overridden parameters keep the extras, with them
    np.testing.assert_allclose(get_arm("rr", L1=0.5).ik([0.8, 0.0], all=True), [[0.0, 0.0]], atol=1e-12)
    assert get_arm("r2t").scheme.dh is None and get_arm("arm4r").scheme.dh.convention == "modified"


def test_a_users_arm_named_like_a_paper_arm_has_no_extras(tmp_path):
    """A URDF named rr.urdf is a user's arm called rr: no closed form, paper motion or scheme of paper 000."""
    path = tmp_path / "rr.urdf"
    path.write_text(get_arm("rr").urdf())
    arm = get_arm(str(path))
    assert arm.name == "rr" and (arm.closed_form, arm.motion, dict(arm.paths), arm.scheme) == (None, None, {}, None)
    with pytest.raises(ValueError, match="rr has no paper motion"):
        armlab.paper_motion(arm)
    with pytest.raises(ValueError, match="IK branch 0 is not allowed"):
        from armlab.planning.motions import point_to_joints

        point_to_joints(arm, (0.4, 0.3, 0.0), 0)


def test_register_refuses_a_taken_name_and_a_module_that_is_no_arm():
    impostor = types.ModuleType("somewhere.rr")
    impostor.build, impostor.PAPER, impostor.Parameters = get_arm, "x", object
    with pytest.raises(ValueError, match=r"arm 'rr' is registered already \(by armlab.models.rr\)"):
        register(impostor)
    with pytest.raises(ValueError, match="module nothing is not an arm module: it needs build, PAPER and Parameters"):
        register(types.ModuleType("nothing"))
    assert list(ARMS) == ["rr", "rrrr", "arm4r", "r2t", "urm6"]
