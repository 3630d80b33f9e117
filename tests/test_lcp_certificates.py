"""Certificates that an LCP has no solution (pinograsp/solvers/lcp_certificates.py): small
problems decided by hand, one at twenty items by Farkas' lemma."""

import numpy as np

from pinograsp.solvers.lcp import LCPStatus, lemke
from pinograsp.solvers.lcp_certificates import near_solution, provably_infeasible, provably_unsolvable


def _faces_and_actuator(q_faces: list[float]) -> tuple[np.ndarray, np.ndarray]:
    """Two faces whose flows cancel (the face block [[1, -1], [-1, 1]] is singular: 1^T M_FF = 0)
    and an actuator item that lifts both faces' slack rates (column 0.5) while its own rate
    does not depend on them: the shape of the parallel jaw's cylinder at +fx."""
    M = np.array([[1.0, -1.0, 0.5], [-1.0, 1.0, 0.5], [0.0, 0.0, 4.0]])
    return M, np.array([*q_faces, 0.0])


def test_singular_blocks_are_decided_by_a_linear_program():
    """q_F = (-0.1, -0.1): by hand, no index set works — {} and {a}: w_F = q_F < 0; {f1}: z1 = 0.1,
    w2 = -0.2; {f1, a}: w_a = 4 z_a = 0 forces z_a = 0, then as {f1}; {f1, f2} (singular):
    z1 - z2 = 0.1 and z2 - z1 = 0.1 contradict; {f1, f2, a} (singular): z_a = 0.2 from the face
    rows, but w_a = 4 z_a = 0.8 != 0. Certified, though two blocks are singular (it was not)."""
    M, q = _faces_and_actuator([-0.1, -0.1])
    assert np.linalg.matrix_rank(M[:2, :2]) == 1
    assert lemke(M, q).status == LCPStatus.RAY
    assert provably_unsolvable(M, q)
    # feasible (z_a = 0.2 keeps w >= 0) but never complementary: Farkas alone does not decide
    assert not provably_infeasible(M, q)


def test_a_singular_block_with_a_solution_is_not_certified():
    """q_F = (-0.1, 0.1): {f1, f2} is consistent (z1 = z2 + 0.1, z = (0.1, 0, 0) with w = 0): a
    solution, so no certificate."""
    M, q = _faces_and_actuator([-0.1, 0.1])
    z = np.array([0.1, 0.0, 0.0])
    w = M @ z + q
    assert (w >= -1e-15).all() and abs(z @ w) < 1e-15
    assert not provably_unsolvable(M, q)
    assert not provably_infeasible(M, q)


def test_farkas_certificate_at_any_size():
    """Twenty items whose slack rates sum to a negative constant whatever the flows (1^T M = 0,
    1^T q < 0): no z >= 0 keeps every w >= 0 — beyond the enumeration's 12 items."""
    rng = np.random.default_rng(0)
    A = rng.normal(size=(20, 20))
    M = A - A.mean(axis=0)  # every column sums to 0
    q = -np.abs(rng.normal(size=20))
    assert np.allclose(M.sum(axis=0), 0.0)
    assert provably_infeasible(M, q) and provably_unsolvable(M, q)
    assert not provably_infeasible(M, np.abs(q))  # z = 0 is a solution


def test_near_solution_is_what_keeps_the_certificate_from_certifying():
    """The same enumeration: where the certificate holds there is no near solution; where a
    singular-free index set solves it, that point comes back, complementary and nonnegative."""
    M, q = _faces_and_actuator([-0.1, -0.1])
    assert provably_unsolvable(M, q) and near_solution(M, q) is None
    rng = np.random.default_rng(3)
    for _ in range(20):  # P-matrices: one solution each, which the enumeration finds
        A = rng.normal(size=(5, 5))
        M = A @ A.T + 0.5 * np.eye(5)
        q = rng.normal(size=5)
        res = near_solution(M, q)
        assert res is not None and res.solved and not provably_unsolvable(M, q)
        w = M @ res.z + q
        assert res.z.min() >= 0 and w.min() >= -1e-12 and abs(res.z @ w) <= 1e-12
        np.testing.assert_allclose(res.z, lemke(M, q).z, atol=1e-12)
    assert near_solution(np.zeros((13, 13)), -np.ones(13)) is None  # beyond the enumeration
