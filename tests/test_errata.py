"""The papers' misprints: printed forms disagree with Drake, corrected forms agree to 1e-9."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from helpers import arm_and_plant, random_q

from armlab.kinematics import symbolic as sym
from armlab.models import get_arm
from armlab.papers.errata import ERRATA, Erratum, drake_sample, wrap_angle

N = 100
TOL = 1e-9
EVALUABLE = [e for e in ERRATA if e.evaluable]


def _sample(erratum: Erratum, seed: int):
    arm = get_arm(erratum.arm, **erratum.overrides)
    rng = np.random.default_rng(seed)
    q = random_q(arm, rng, N)
    return drake_sample(arm, q, rng.normal(size=q.shape), rng.normal(size=q.shape))


@pytest.mark.parametrize("erratum", EVALUABLE, ids=[f"{e.paper} {e.equation}" for e in EVALUABLE])
def test_printed_disagrees_with_drake_corrected_agrees(erratum):
    sample = _sample(erratum, 7)
    reference = erratum.reference(sample)
    printed, corrected = erratum.printed(sample), erratum.corrected(sample)
    assert printed.shape == corrected.shape == reference.shape

    def per_sample(value):
        diff = value - reference
        diff = wrap_angle(diff) if erratum.angle else diff
        return np.abs(diff).reshape(N, -1).max(axis=1)

    assert per_sample(corrected).max() < TOL
    wrong = per_sample(printed) > 1e-6
    if erratum.affects is None:
        assert wrong.mean() >= 0.9, f"printed form agrees with Drake at {np.count_nonzero(~wrong)} of {N} samples"
    else:  # wrong exactly where the misprint shows, and that is a good part of the samples
        affected = erratum.affects(sample)
        np.testing.assert_array_equal(wrong, affected)  # exact: boolean masks
        assert 0.2 <= affected.mean() <= 0.8
    printed_error, corrected_error = erratum.errors(sample)
    assert corrected_error < TOL < 1e-3 < printed_error


def test_required_entries_are_listed():
    listed = {(e.paper, e.equation) for e in ERRATA}
    for key in (("003", "eqs. (19), (21)"), ("003", "eq. (45)"), ("001", "eq. (19)"), ("003", "eqs. (62), (64)"),
                ("003", "eq. (22)"), ("004", "eq. (7)"), ("004", "eq. (22)")):
        assert key in listed and next(e for e in ERRATA if (e.paper, e.equation) == key).evaluable, key
    for e in ERRATA:
        assert e.description and e.printed_form and e.corrected_form and e.printed_form != e.corrected_form


def test_text_only_entries_cannot_be_evaluated():
    text_only = [e for e in ERRATA if not e.evaluable]
    assert text_only  # the m-file typos of paper 000
    for e in text_only:
        assert e.corrected is None and e.reference is None
        with pytest.raises(ValueError, match="cannot be evaluated"):
            e.errors(None)


def test_drake_sample_matches_direct_queries_and_locating_frames(rng):
    """The errata's Drake helper: tool pose and motion as in the brief's queries, link frames = paper 003's {i}."""
    from pydrake.multibody.tree import JacobianWrtVariable

    arm, plant, ctx = arm_and_plant("r2t")
    q = random_q(arm, rng, 20)
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
    sample = drake_sample(arm, q, qd, qdd)
    np.testing.assert_allclose(sample.pose, arm.table.frames(q)[:, 1:], atol=TOL, rtol=0)
    world, tool = plant.world_frame(), plant.GetFrameByName(arm.tool_name)
    for k in range(len(q)):
        plant.SetPositions(ctx, q[k])
        plant.SetVelocities(ctx, qd[k])
        X = plant.CalcRelativeTransform(ctx, world, tool).GetAsMatrix4()
        J = plant.CalcJacobianTranslationalVelocity(ctx, JacobianWrtVariable.kV, tool, np.zeros(3), world, world)
        bias = plant.CalcBiasTranslationalAcceleration(ctx, JacobianWrtVariable.kV, tool, np.zeros(3), world, world)
        np.testing.assert_allclose(sample.pose[k, -1], X, atol=TOL, rtol=0)
        np.testing.assert_allclose(sample.v[k, -1], J @ qd[k], atol=TOL, rtol=0)
        np.testing.assert_allclose(sample.v_dot[k, -1], J @ qdd[k] + bias[:, 0], atol=TOL, rtol=0)


def test_003_eq20_R04_and_corrected_p4_equal_drake(rng):
    arm, plant, ctx = arm_and_plant("r2t")
    s = sym.r2t()
    q = random_q(arm, rng, N)
    l = np.array([arm.parameters[f"l{i}"] for i in range(1, 6)])
    R04 = sym.batch_function(list(s.R04), [s.q])(q).reshape(N, 3, 3)
    p4 = sym.batch_function(list(s.p4), [s.q, s.l])(q, l)
    for k in range(N):
        plant.SetPositions(ctx, q[k])
        X = plant.CalcRelativeTransform(ctx, plant.world_frame(), plant.GetFrameByName(arm.tool_name))
        np.testing.assert_allclose(R04[k], X.rotation().matrix(), atol=TOL, rtol=0)
        np.testing.assert_allclose(p4[k], X.translation(), atol=TOL, rtol=0)
    q1 = s.q[0]
    assert s.R04 == sp.Matrix([[-sp.sin(q1), sp.cos(q1), 0], [sp.cos(q1), sp.sin(q1), 0], [0, 0, -1]])


def test_004_general_formulas_at_table1_configuration():
    """Eqs. (7) and (22) as printed at Table 1's configuration: p2 right, p3 off by about 50 mm, p5 by about 0.5 m;
    corrected, both give the points eqs. (1)-(6) give (kinematics.urm) and Drake's frames."""
    from armlab.kinematics.urm import position_vectors
    from armlab.models.urm6 import TABLE1_PHI_DEG

    arm = get_arm("urm6")
    sample = drake_sample(arm, np.radians(TABLE1_PHI_DEG)[None])
    p = arm.parameters
    reference = position_vectors(np.radians(TABLE1_PHI_DEG), [p[f"theta{k}"] for k in range(2, 8)],
                                 [p[f"r{k}"] for k in range(1, 8)])[1:]
    for equation in ("eq. (7)", "eq. (22)"):
        e = next(e for e in ERRATA if (e.paper, e.equation) == ("004", equation))
        drake = e.reference(sample)[0]
        np.testing.assert_allclose(drake, reference, atol=TOL, rtol=0)
        np.testing.assert_allclose(e.corrected(sample)[0], drake, atol=TOL, rtol=0)
        off = np.linalg.norm(e.printed(sample)[0] - drake, axis=-1)  # p2 … p7 (m)
        assert off[0] < TOL and 0.03 < off[1] < 0.08 and 0.3 < off[3] < 0.8, (equation, off)


def test_003_atan2_table_misses_the_case_eq23_uses():
    """Eq. (22)'s printed table has no case for sα = 0, cα < 0, which eq. (23) needs (α_x = A tan 2(0; −1) = π)."""
    from armlab.papers.errata import _003_atan2

    arm = get_arm("r2t")
    from dataclasses import replace

    sample = drake_sample(arm, np.array([[np.pi / 2, 0.1, 0.1]]))  # γ_z = π: sγ = 0, cγ = −1
    sample = replace(sample, pose=np.round(sample.pose, 12) + 0.0)  # cos(π/2) ≈ 6e-17 → exactly 0
    assert sample.pose[0, -1, 1, 0] == 0 and sample.pose[0, -1, 0, 0] == -1
    assert np.isnan(_003_atan2(True)(sample)[0])
    assert abs(wrap_angle(_003_atan2(False)(sample)[0] - np.pi)) < TOL


def test_001_eq19_corrected_form_is_what_the_ik_module_returns(rng):
    """armlab.kinematics.ik_closed_form.arm4r_ik implements θ2 = θ23 − θ3; one of its branches is the sampled q."""
    from armlab.kinematics.ik_closed_form import arm4r_ik

    erratum = next(e for e in ERRATA if (e.paper, e.equation) == ("001", "eq. (19)"))
    sample = _sample(erratum, 11)
    p = sample.arm.parameters
    corrected = erratum.corrected(sample)
    for k in range(10):
        pitch = sample.q[k, 1:].sum()
        solutions = arm4r_ik(sample.pose[k, -1, :3, 3], pitch, p["a2"], p["a3"], p["d2"])
        match = np.all(np.abs(wrap_angle(solutions - sample.q[k])) < 1e-9, axis=1)
        assert match.any()
        assert abs(wrap_angle(solutions[match][0, 1] - corrected[k])) < 1e-9


def test_one_papers_check_gives_the_numbers_of_the_whole_check():
    """Each erratum draws its own samples, so a worker checking one paper's errata reports what a check of all does."""
    from armlab.papers.errata import check

    whole = {id(e): (printed, corrected) for e, printed, corrected in check(5)}
    for paper in {e.paper for e in ERRATA}:
        mine = check(5, paper=paper)
        assert all(e.paper == paper for e, _, _ in mine)
        assert {id(e): (printed, corrected) for e, printed, corrected in mine} == {
            k: v for k, v in whole.items() if any(id(e) == k and e.paper == paper for e in ERRATA)}
    assert len(whole) == sum(e.evaluable and e.arm is not None for e in ERRATA)
