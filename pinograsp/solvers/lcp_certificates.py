"""Certificates that a linear complementarity problem has no solution.

``w = M z + q, z >= 0, w >= 0, z^T w = 0`` (:mod:`pinograsp.solvers.lcp`) provably has none
when no ``z >= 0`` keeps ``w >= 0`` at all (Farkas' lemma, any size:
:func:`provably_infeasible`), or when every complementary index set fails
(:func:`provably_unsolvable`, small problems). Used where the loading path stops: a certified
"no continuation" is a verdict (the grasp gives way), an uncertified one is not. NumPy and
SciPy only (LAPACK; HiGHS for the linear programs, deterministic).
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator

import numpy as np

from .lcp import LCPResult, LCPStatus, block_solution

#: Largest LCP whose complementary index sets :func:`provably_unsolvable` enumerates (2^n
#: small solves).
MAX_ENUMERATED = 12
#: Condition number above which a principal block is taken as singular (no certificate).
BLOCK_COND = 1e10
#: Relative margin by which every candidate must fail for the certificate.
MARGIN_RTOL = 1e-9


#: A Farkas certificate must force every ``z >= 0`` with ``M z + q >= 0`` to flows at least
#: this many times the problem's own scale ``max|q| / max|M|`` (none at a physical rate).
FARKAS_SCALE = 1e6


def provably_infeasible(M: np.ndarray, q: np.ndarray) -> bool:
    """True only when no ``z >= 0`` makes ``w = M z + q >= 0`` (so the LCP has no solution,
    complementary or not), whatever the conditioning of ``M``: Farkas' lemma gives a
    ``y >= 0`` with ``M^T y <= 0`` and ``q^T y < 0`` (then ``y^T w <= q^T y < 0`` for every
    ``z >= 0``). ``y`` comes from a small linear program (HiGHS, deterministic) and is
    checked here: ``q^T y`` negative by a margin, and the rounding left in ``M^T y`` so small
    that a feasible ``z`` would need flows :data:`FARKAS_SCALE` times the problem's scale.
    False means "not certified"."""
    from scipy.optimize import linprog

    n = q.size
    if n == 0:
        return False
    res = linprog(
        q,
        A_ub=M.T,
        b_ub=np.zeros(n),
        bounds=[(0.0, 1.0)] * n,
        method="highs",
        options={"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10},
    )
    if res.status != 0 or res.x is None:
        return False
    y = np.maximum(np.asarray(res.x, float), 0.0)
    gap = -float(q @ y)  # > 0 for a certificate
    mscale = max(float(np.abs(M).max(initial=0.0)), 1e-300)
    qscale = float(np.abs(q).max(initial=0.0))
    if not gap > MARGIN_RTOL * qscale * float(y.sum()):
        return False
    leak = float(np.maximum(M.T @ y, 0.0).sum())  # what a large z could still gain
    return leak * FARKAS_SCALE * qscale / mscale <= gap


def _set_infeasible(M: np.ndarray, q: np.ndarray, active: np.ndarray) -> bool:
    """Whether the complementary index set ``active`` (bool (n,)) with a singular block
    ``M_BB`` has provably no point ``z_B >= 0``, ``M_BB z_B + q_B = 0``, ``M_NB z_B + q_N >= 0``
    with flows below :data:`FARKAS_SCALE` times the problem's scale: a linear program in units
    of that scale (HiGHS, tolerances 1e-10 of it, deterministic) found infeasible."""
    from scipy.optimize import linprog

    mscale = max(float(np.abs(M).max(initial=0.0)), 1e-300)
    qscale = float(np.abs(q).max(initial=0.0))
    if qscale == 0.0:
        return False  # z = 0 solves it
    Ms, qs = M / mscale, q / qscale
    B, N = active.nonzero()[0], (~active).nonzero()[0]
    res = linprog(
        np.zeros(len(B)),
        A_ub=-Ms[np.ix_(N, B)] if len(N) else None,
        b_ub=qs[N] if len(N) else None,
        A_eq=Ms[np.ix_(B, B)],
        b_eq=-qs[B],
        bounds=[(0.0, FARKAS_SCALE)] * len(B),
        method="highs",
        options={"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10},
    )
    return res.status == 2  # infeasible


def provably_unsolvable(M: np.ndarray, q: np.ndarray) -> bool:
    """True only when ``w = M z + q, 0 <= z ⟂ w >= 0`` provably has no solution: no ``z >= 0``
    keeps ``w >= 0`` at all (:func:`provably_infeasible`, any size), or every complementary
    index set fails (``n <= MAX_ENUMERATED``): by a margin where its principal block is well
    conditioned, by a linear program where it is singular (:func:`_set_infeasible`: no point
    with flows below :data:`FARKAS_SCALE` times the problem's scale — a continuation only at
    unbounded rates is none). False means "not certified", not "solvable"."""
    n = q.size
    if n == 0:
        return False
    if provably_infeasible(M, q):
        return True
    if n > MAX_ENUMERATED:
        return False
    for kind, active, _ in _index_sets(M, q):
        if kind == "singular":
            if not _set_infeasible(M, q, active):
                return False
        elif kind != "excluded":
            return False
    return True


def _index_sets(
    M: np.ndarray, q: np.ndarray
) -> Iterator[tuple[str, np.ndarray, tuple[np.ndarray, np.ndarray] | None]]:
    """Every complementary index set of a small LCP, by size and then in lexicographic order:
    ``(kind, active (n,) bool, (z, w) or None)``. ``kind``: ``"singular"`` (the principal
    block's condition number above :data:`BLOCK_COND`), ``"failed"`` (its solve failed),
    ``"candidate"`` (``z >= 0`` and ``w >= 0`` within the margin :data:`MARGIN_RTOL` of the
    problem's scale, the point given) or ``"excluded"`` (fails by more than the margin)."""
    n = q.size
    mscale = max(float(np.abs(M).max(initial=0.0)), 1e-300)
    qscale = max(float(np.abs(q).max(initial=0.0)), 1e-300)
    for size in range(n + 1):
        for subset in itertools.combinations(range(n), size):
            active = np.zeros(n, bool)
            active[list(subset)] = True
            if size and np.linalg.cond(M[np.ix_(active, active)]) > BLOCK_COND:
                yield "singular", active, None
                continue
            point = block_solution(M, q, active)
            if point is None:
                yield "failed", active, None
                continue
            z, w = point
            tol = MARGIN_RTOL * max(qscale, mscale * float(np.abs(z).max(initial=0.0)))
            ok = z.min(initial=0.0) >= -tol and w.min(initial=0.0) >= -tol
            yield ("candidate" if ok else "excluded"), active, point


def near_solution(M: np.ndarray, q: np.ndarray) -> LCPResult | None:
    """The first complementary point of a small LCP (``n <= MAX_ENUMERATED``; index sets by
    size, then in lexicographic order) that is a solution within the certificates' margin —
    what rounding keeps Lemke's method and principal pivoting from accepting on a nearly
    degenerate problem (two adjacent friction faces sliding together) — with ``z`` clipped at
    0 and ``w`` recomputed; None when there is none (the same enumeration as
    :func:`provably_unsolvable`: a candidate here is exactly what keeps it from certifying)."""
    if q.size == 0 or q.size > MAX_ENUMERATED:
        return None
    for kind, active, point in _index_sets(M, q):
        if kind == "candidate" and point is not None:
            z = np.maximum(point[0], 0.0)
            w = M @ z + q
            w[active] = 0.0
            return LCPResult(LCPStatus.SOLVED, z, np.maximum(w, 0.0), 0)
    return None


__all__ = [
    "BLOCK_COND",
    "FARKAS_SCALE",
    "MARGIN_RTOL",
    "MAX_ENUMERATED",
    "near_solution",
    "provably_infeasible",
    "provably_unsolvable",
]
