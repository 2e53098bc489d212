"""Values printed in the papers, compared with armlab (and through it, with Drake)."""

from __future__ import annotations

import numpy as np
from helpers import arm_and_plant

from armlab.kinematics.basic_movements import DH_TO_YUP, rrrr_dh_chain, rrrr_point_M, rrrr_yup_chain
from armlab.kinematics.locating import orientation_angles
from armlab.kinematics.urm import position_vectors, position_vectors_homogeneous
from armlab.models import get_arm
from armlab.models.urm6 import TABLE1_PHI_DEG

# Paper 004, Table 2 (mm), both of its models.
TABLE2_MM = np.array([
    [0, 0, 300],
    [62.5000, 16.7468, 541.4814],
    [173.6615, 98.2962, 686.3703],
    [208.0427, 238.3718, 727.5622],
    [197.5341, 266.4384, 822.9657],
    [171.5064, 309.0897, 821.1157],
    [178.0814, 312.0638, 797.1799],
])


def test_004_table2_both_forms_and_drake():
    arm, plant, ctx = arm_and_plant("urm6")
    phi = np.radians(TABLE1_PHI_DEG)
    params = arm.parameters
    theta = np.array([params[f"theta{k}"] for k in range(2, 8)])
    r = np.array([params[f"r{k}"] for k in range(1, 8)])
    p = position_vectors(phi, theta, r)
    np.testing.assert_allclose(position_vectors_homogeneous(phi, theta, r), p, atol=1e-12)
    deviation_mm = np.abs(p * 1000 - TABLE2_MM).max()
    assert deviation_mm < 2e-4, f"paper 004 Table 2 deviates by {deviation_mm:.2e} mm (the paper truncates)"
    plant.SetPositions(ctx, phi)
    for k in range(7):
        drake = plant.CalcRelativeTransform(ctx, plant.world_frame(), plant.GetFrameByName(f"p{k + 1}")).translation()
        np.testing.assert_allclose(p[k], drake, atol=1e-12)


def test_001_eq6_T04_at_zero():
    arm = get_arm("arm4r")
    a2, a3, d2 = (arm.parameters[k] for k in ("a2", "a3", "d2"))
    expected = np.array([[1, 0, 0, a2 + a3], [0, 0, 1, d2], [0, -1, 0, 0], [0, 0, 0, 1]])
    np.testing.assert_allclose(arm.forward(np.zeros(4)).tool, expected, atol=1e-15)
    np.testing.assert_allclose(expected[:3, 3], [2, 0, 0])  # 001's start, "stretched horizontally"


def test_003_eq20_rotation_eq21_corrected_position_and_orientation_angles(rng):
    arm, plant, ctx = arm_and_plant("r2t")
    l1, l2, l3, l4, l5 = (arm.parameters[f"l{i}"] for i in range(1, 6))
    for q in rng.uniform([-np.pi, 0, 0], [np.pi, 0.3, 0.3], size=(100, 3)):
        q1, q2, q3 = q
        s1, c1 = np.sin(q1), np.cos(q1)
        R04 = np.array([[-s1, c1, 0], [c1, s1, 0], [0, 0, -1]])  # eq. (20)
        p4 = np.array([l3 * c1 - (q3 + l4) * s1, l3 * s1 + (q3 + l4) * c1, l1 + l2 + q2 - l5])
        plant.SetPositions(ctx, q)
        X = plant.CalcRelativeTransform(ctx, plant.world_frame(), plant.GetFrameByName("P4"))
        np.testing.assert_allclose(X.rotation().matrix(), R04, atol=1e-12)
        np.testing.assert_allclose(X.translation(), p4, atol=1e-12)
        np.testing.assert_allclose(arm.forward(q).tool[:3, 3], p4, atol=1e-12)
        # eqs. (22)-(23): α_x = π, β_y = 0, γ_z = π/2 + q1 (mod 2π)
        alpha, beta, gamma = orientation_angles(arm.forward(q).tool[:3, :3])
        assert abs(abs(alpha) - np.pi) < 1e-12 and abs(beta) < 1e-12
        assert abs(np.angle(np.exp(1j * (gamma - (np.pi / 2 + q1))))) < 1e-12


def test_000_rr_end_points_of_fig3_by_eqs_1_2_and_drake():
    """M0 and M_fin of Fig. 3: the paper prints only the angles (θ1 −38° → 62°, θ2 98° → 68°) and L1 = 0.4 m,
    L2 = 0.3 m; eqs. (1)-(2), armlab's forward kinematics and Drake's plant give the same points."""
    arm, plant, ctx = arm_and_plant("rr")
    for q in np.radians([[-38.0, 98.0], [62.0, 68.0]]):
        eqs = np.array([0.4 * np.cos(q[0]) + 0.3 * np.cos(q.sum()), 0.4 * np.sin(q[0]) + 0.3 * np.sin(q.sum())])
        M = arm.forward(q).points["M"]
        np.testing.assert_allclose(M[:2], eqs, atol=1e-12)
        plant.SetPositions(ctx, q)
        drake = plant.CalcRelativeTransform(ctx, plant.world_frame(), plant.GetFrameByName(arm.tool_name))
        np.testing.assert_allclose(drake.translation(), M, atol=1e-12)


def test_000_rrrr_two_forms_differ_by_the_base_rotation(rng):
    L = (0.2, 0.4, 0.3, 0.2)
    q = rng.uniform(-np.pi, np.pi, size=(200, 4))
    dh, yup = rrrr_dh_chain(q, L), rrrr_yup_chain(q, L)
    T_dh = dh[0] @ dh[1] @ dh[2] @ dh[3]
    T_yup = yup[0] @ yup[1] @ yup[2] @ yup[3]
    np.testing.assert_allclose(DH_TO_YUP @ T_dh, T_yup, atol=1e-15)
    M_dh, M_yup = rrrr_point_M(dh), rrrr_point_M(yup)
    np.testing.assert_allclose(M_yup, np.stack([M_dh[:, 0], M_dh[:, 2], -M_dh[:, 1]], axis=-1), atol=1e-15)
    assert np.abs(M_yup - M_dh).max() > 0.1  # genuinely different frames
