"""Lemke's method (pinograsp/solvers/lcp.py) on small LCPs with known answers."""

import itertools

import numpy as np
import pytest

from pinograsp.solvers.lcp import LCPStatus, block_solution, lemke


def brute_force(M, q):
    """Every solution of a small LCP by enumerating the complementary bases."""
    n = len(q)
    out = []
    for active in itertools.product([False, True], repeat=n):
        a = np.array(active)
        z = np.zeros(n)
        if a.any():
            try:
                z[a] = np.linalg.solve(M[np.ix_(a, a)], -q[a])
            except np.linalg.LinAlgError:
                continue
        w = M @ z + q
        if z.min() >= -1e-10 and w.min() >= -1e-10:
            out.append(z)
    return out


def check(M, q, res):
    assert res.status is LCPStatus.SOLVED
    w = M @ res.z + q
    assert res.z.min() >= 0.0 and res.w.min() >= 0.0
    np.testing.assert_allclose(res.w, w, atol=1e-12 * max(1.0, np.abs(w).max()))
    assert float(res.z @ res.w) == 0.0  # nonbasic values are exact zeros


def test_two_by_two_known_solution():
    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    q = np.array([-5.0, -6.0])
    r = lemke(M, q)
    check(M, q, r)
    np.testing.assert_allclose(r.z, [4.0 / 3.0, 7.0 / 3.0], rtol=1e-14)


def test_trivial_when_q_nonnegative():
    r = lemke(np.eye(3), np.array([1.0, 0.0, 2.0]))
    assert r.solved and r.pivots == 0 and not r.z.any()


def test_one_active():
    M, q = np.eye(2), np.array([-1.0, 2.0])
    r = lemke(M, q)
    check(M, q, r)
    np.testing.assert_array_equal(r.z, [1.0, 0.0])
    np.testing.assert_array_equal(r.w, [0.0, 2.0])


@pytest.mark.parametrize("seed", range(20))
def test_p_matrix_unique_solution_matches_enumeration(seed):
    rng = np.random.default_rng(seed)
    n = 5
    A = rng.normal(size=(n, n))
    M = A @ A.T + 0.5 * np.eye(n) + 0.3 * (A - A.T)  # positive definite (nonsymmetric): a P-matrix
    q = rng.normal(size=n)
    r = lemke(M, q)
    check(M, q, r)
    sols = brute_force(M, q)
    assert len(sols) == 1
    np.testing.assert_allclose(r.z, sols[0], atol=1e-12)


def test_degenerate_ties_terminate():
    # q has ties and M is singular positive semidefinite: the lexicographic rule must not cycle
    M = np.array([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    q = np.array([-1.0, -1.0, -1.0])
    r = lemke(M, q)
    check(M, q, r)
    assert r.z[0] + r.z[1] == pytest.approx(1.0) and r.z[2] == pytest.approx(1.0)


def test_ray_termination_when_infeasible():
    # w1 = z2 - 1, w2 = -z1 - 1 < 0 for every z >= 0: no solution
    r = lemke(np.array([[0.0, 1.0], [-1.0, 0.0]]), np.array([-1.0, -1.0]))
    assert r.status is LCPStatus.RAY and not r.solved
    r = lemke(np.array([[-1.0]]), np.array([-1.0]))
    assert r.status is LCPStatus.RAY


def test_pivot_limit_is_a_count():
    rng = np.random.default_rng(3)
    A = rng.normal(size=(6, 6))
    M, q = A @ A.T + np.eye(6), -np.abs(rng.normal(size=6)) - 1.0
    r = lemke(M, q, max_pivots=1)
    assert r.status is LCPStatus.PIVOT_LIMIT and r.pivots == 1
    assert lemke(M, q).solved


def test_order_independent_solution():
    rng = np.random.default_rng(7)
    A = rng.normal(size=(6, 6))
    M = A @ A.T + np.eye(6)
    q = rng.normal(size=6)
    z = lemke(M, q).z
    perm = rng.permutation(6)
    zp = lemke(M[np.ix_(perm, perm)], q[perm]).z
    np.testing.assert_allclose(zp, z[perm], rtol=1e-12, atol=1e-14)


def test_block_solution_is_the_complementary_point_of_an_index_set():
    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    q = np.array([-5.0, -6.0])
    z, w = block_solution(M, q, np.array([True, True]))
    np.testing.assert_allclose(z, lemke(M, q).z, rtol=1e-14)  # (4/3, 7/3): the solution
    assert np.array_equal(w, [0.0, 0.0])
    z, w = block_solution(M, q, np.array([True, False]))  # z1 = 5/2, w2 = 5/2 - 6 < 0: not one
    np.testing.assert_allclose(z, [2.5, 0.0], rtol=1e-15)
    np.testing.assert_allclose(w, [0.0, -3.5], rtol=1e-15)
    assert block_solution(np.zeros((2, 2)), q, np.array([True, True])) is None  # a singular block


@pytest.mark.parametrize("seed", range(10))
def test_principal_pivoting_from_any_guess_matches_lemke(seed):
    from pinograsp.solvers.lcp import principal_pivoting

    rng = np.random.default_rng(100 + seed)
    n = 6
    A = rng.normal(size=(n, n))
    M = A @ A.T + 0.5 * np.eye(n) + 0.2 * (A - A.T)
    q = rng.normal(size=n)
    ref = lemke(M, q).z
    for _ in range(5):
        r = principal_pivoting(M, q, rng.random(n) < 0.5)
        assert r is not None
        check(M, q, r)
        np.testing.assert_allclose(r.z, ref, atol=1e-12)


@pytest.mark.parametrize("seed", range(4))
def test_leaving_row_on_positive_entries_matches_the_full_length_test(seed):
    """The minimum-ratio test on the positive entries only picks the same row as the test on
    ratios of all rows (inf where not positive), ties and lexicographic rule included."""
    from pinograsp.solvers.lcp import _leaving_row, _leaving_row_full

    rng = np.random.default_rng(seed)
    n = 6
    picked = set()
    for _ in range(300):
        T = np.round(rng.normal(size=(n, 2 * n + 1)), 1)  # rounded: many exact ties
        rhs = np.abs(np.round(rng.normal(size=n), 1))
        for col in range(n, 2 * n + 1):
            row = _leaving_row(T, col, rhs, n, 1e-9)
            assert row == _leaving_row_full(T, col, rhs, n, 1e-9)
            picked.add(row)
    assert -1 in picked and len(picked) == n + 1  # rays and every row occur
