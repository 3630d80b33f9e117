"""Linear complementarity problems by Lemke's complementary pivoting (pure NumPy).

Solves ``w = M z + q, z >= 0, w >= 0, z^T w = 0`` for a small dense ``M`` (n, n) and ``q``
(n,). Lemke's method adds an artificial variable ``z0`` with covering vector ``e = 1`` and
pivots complementary pairs until ``z0`` leaves the basis (a solution) or the entering column
has no positive entry (a *ray termination*: for copositive-plus ``M`` — positive semidefinite
included — there is then no solution; for other matrices the method gives no verdict).

Determinism and degeneracy: the leaving row is chosen by the lexicographic minimum-ratio rule
on the rows of the basis inverse (the classical anti-cycling rule), with ratios that agree to a
relative ``1e-12`` treated as ties. The pivots are a function of the data alone; the number of
pivots is limited by a count (``max_pivots``), never by time.

Used by the quasi-static loading path (:mod:`pinograsp.analysis.quasistatic`) for its local
rate problems. NumPy and SciPy only (LAPACK). Certificates that an LCP has no solution:
:mod:`pinograsp.solvers.lcp_certificates`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import numpy as np
from scipy.linalg.lapack import dgesv

_max = np.maximum.reduce  # ``ndarray.max`` without its Python wrapper (the same reduction)
_min = np.minimum.reduce
_fmin = np.fmin.reduce

#: Pivots below this fraction of ``max |M|`` are rounding (nearly equal rows of ``M``), never used.
PIVOT_RTOL = 1e-9
#: Relative tolerance under which two ratios of the minimum-ratio test are a tie.
TIE_RTOL = 1e-12


class LCPStatus(str, Enum):
    """How a Lemke solve ended."""

    #: A solution ``z`` was found.
    SOLVED = "solved"
    #: The entering column had no positive entry (no solution for copositive-plus ``M``).
    RAY = "ray_termination"
    #: The pivot limit was reached (a count).
    PIVOT_LIMIT = "pivot_limit"
    #: The final tableau's point fails the check ``w = M z + q >= 0``, ``z^T w = 0`` (a
    #: nearly singular basis): no trustworthy answer.
    INACCURATE = "inaccurate"


@dataclass(frozen=True)
class LCPResult:
    """Answer of :func:`lemke`.

    Attributes:
        status: :class:`LCPStatus`.
        z: The solution (n,) (zeros when not solved).
        w: ``M z + q`` (n,).
        pivots: Pivots made (the initial one included).
        tie: The solution was not unique on its tight set and the least-norm one was taken
            (:func:`canonical`).
    """

    status: LCPStatus
    z: np.ndarray
    w: np.ndarray
    pivots: int
    tie: bool = False

    @property
    def solved(self) -> bool:
        """Whether a solution was found."""
        return self.status is LCPStatus.SOLVED


def _leaving_row(T: np.ndarray, col: int, rhs: np.ndarray, n: int, tol: float) -> int:
    """Row of the lexicographic minimum ratio for entering column ``col`` (-1: ray)."""
    a = T[:, col]
    rows = (a > tol).nonzero()[0]
    if not rows.size:
        return -1
    ar = a[rows]
    ratios = rhs[rows] / ar  # the rows without a positive entry have ratio inf, never below these
    best = _min(ratios)
    bar = best + TIE_RTOL * max(abs(best), 1.0)
    if not math.isfinite(bar):  # a ratio inf or NaN: the full-length test, as it always was
        return _leaving_row_full(T, col, rhs, n, tol)
    near = ratios <= bar
    if np.count_nonzero(near) == 1:
        return int(rows[near.argmax()])
    cand, ac = rows[near], ar[near]
    # lexicographic rule: rows of the basis inverse (the columns of the initial basis w)
    for j in range(n):
        vals = T[cand, j] / ac
        low = _min(vals)
        keep = vals <= low + TIE_RTOL * max(abs(low), 1.0)
        cand, ac = cand[keep], ac[keep]
        if cand.size == 1:
            break
    return int(cand[0])


def _leaving_row_full(T: np.ndarray, col: int, rhs: np.ndarray, n: int, tol: float) -> int:
    """:func:`_leaving_row` on ratios of all rows (inf where the entry is not positive)."""
    a = T[:, col]
    pos = a > tol
    if not pos.any():
        return -1
    ratios = np.full(a.shape, np.inf)
    np.divide(rhs, a, out=ratios, where=pos)
    best = ratios.min()
    cand = np.flatnonzero(ratios <= best + TIE_RTOL * max(abs(best), 1.0))
    if cand.size == 1:
        return int(cand[0])
    # lexicographic rule: rows of the basis inverse (the columns of the initial basis w)
    for j in range(n):
        vals = T[cand, j] / a[cand]
        low = vals.min()
        cand = cand[vals <= low + TIE_RTOL * max(abs(low), 1.0)]
        if cand.size == 1:
            break
    return int(cand[0])


def block_solution(M: np.ndarray, q: np.ndarray, active: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The complementary point of the index set ``active`` (bool (n,)): ``z`` with ``z_N = 0``
    and ``M_BB z_B = -q_B``, and ``w = M z + q`` with ``w_B = 0`` (the one place this system is
    solved: principal pivoting and the enumeration read it); None when the block is singular.
    Whether the point is a solution (``z >= 0``, ``w >= 0``) is the caller's test."""
    point = _block_point(M, q, -q, np.asarray(active, bool).nonzero()[0])
    return None if point is None else point[:2]


def _block_point(
    M: np.ndarray, q: np.ndarray, negq: np.ndarray, idx: np.ndarray
) -> tuple[np.ndarray, np.ndarray, float] | None:
    """:func:`block_solution` on the indices ``idx`` of the set (``negq = -q``), with
    ``max |z|`` (0 for an empty set); None when the block is singular (speed only: the same
    LAPACK call on the same block, fewer NumPy calls)."""
    z = np.zeros(q.size)
    zmax = 0.0
    if idx.size:
        _, _, zb, info = dgesv(M.take(idx, 0).take(idx, 1), negq[idx])
        if info != 0:
            return None
        zmax = float(_max(np.abs(zb)))  # NaN or inf anywhere: not finite
        if not math.isfinite(zmax):
            return None
        z[idx] = zb
    w = M @ z
    w += q
    w[idx] = 0.0
    return z, w, zmax


def principal_pivoting(
    M: np.ndarray, q: np.ndarray, active: np.ndarray, max_iter: int | None = None, rtol: float = 1e-12
) -> LCPResult | None:
    """Block principal pivoting from the guessed set ``active`` (bool (n,)) of positive ``z``.

    Each step solves ``M_BB z_B = -q_B`` and flips the items that violate ``z_B >= 0`` or
    ``w_N >= 0`` (all at once for three steps, then only the first one: Murty's rule, finite
    for P-matrices). Returns the solution when the signs hold (to ``rtol`` of the data's scale),
    None after ``max_iter`` steps (default ``2 n + 4``) or on a singular block: the caller then
    uses :func:`lemke`. A guess only saves pivots; the answer is checked, never trusted.
    """
    n = q.size
    act = np.array(active, bool)
    limit = 2 * n + 4 if max_iter is None else int(max_iter)
    scales: tuple[float, float] | None = None  # max |q|, max |M|: read at the first negative sign
    negq = -q
    seen: set[bytes] = set()
    for it in range(limit):
        if it >= 3:  # single flips: each set has one successor, so a repeated set cycles to the limit
            key = act.tobytes()
            if key in seen:
                return None
            seen.add(key)
        point = _block_point(M, q, negq, act.nonzero()[0])
        if point is None:
            return None
        z, w, zmax = point
        low = np.fmin(z, w)  # z_N = 0 and w_B = 0 exactly: the sign test needs no mask
        least = _fmin(low, initial=math.inf)  # NaN ignored, as by the comparisons
        if rtol >= 0.0 and not least < 0.0:  # no negative sign: none below -tol either
            return _pivoted_solution(z, w)
        if scales is None:
            scales = (
                max(float(_max(np.abs(q), initial=0.0)), 1e-300),
                _max(np.abs(M), axis=None, initial=0.0),
            )
        qscale, mscale = scales[0], max(float(scales[1]), 1e-300)
        tol = rtol * max(qscale, mscale * zmax)
        if tol >= 0.0:
            if not least < -tol:
                return _pivoted_solution(z, w)
            bad = low < -tol
        else:
            bad = (act & (z < -tol)) | (~act & (w < -tol))
            if not bad.any():
                z[act] = np.maximum(z[act], 0.0)
                return LCPResult(LCPStatus.SOLVED, z, np.maximum(w, 0.0), 0)
        if it < 3:
            act ^= bad
        else:
            j = int(bad.argmax())  # the first violated item
            act[j] = not act[j]
    return None


def _pivoted_solution(z: np.ndarray, w: np.ndarray) -> LCPResult:
    """:func:`principal_pivoting`'s answer: the point with rounding of ``z >= 0``, ``w >= 0`` cut."""
    np.maximum(z, 0.0, out=z)
    return LCPResult(LCPStatus.SOLVED, z, np.maximum(w, 0.0), 0)


def lemke(M: np.ndarray, q: np.ndarray, max_pivots: int | None = None) -> LCPResult:
    """Solve the LCP ``(M, q)`` by Lemke's method with the lexicographic pivoting rule.

    Args:
        M: (n, n) matrix (need not be symmetric).
        q: (n,) vector.
        max_pivots: Pivot limit (a count); default ``50 * (n + 1)``.

    Returns:
        An :class:`LCPResult`; when solved, ``z`` and ``w`` are the basic values of the final
        tableau (nonbasic ones exactly 0, so ``z^T w = 0`` holds exactly).
    """
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float).reshape(-1)
    n = q.size
    if n == 0 or q.min() >= 0.0:
        return LCPResult(LCPStatus.SOLVED, np.zeros(n), q.copy(), 0)
    limit = 50 * (n + 1) if max_pivots is None else int(max_pivots)
    scale = max(float(_max(np.abs(M), axis=None, initial=0.0)), 1e-300)
    tol = PIVOT_RTOL * scale
    small = _pivots_small(M, q, limit, tol) if n <= SMALL else None
    if small is not None:
        status, basis_l, rhs_l, pivots = small
        if status is not LCPStatus.SOLVED:
            return LCPResult(status, np.zeros(n), q.copy(), pivots)
        return _basic_solution(M, q, np.array(basis_l), np.array(rhs_l, dtype=float), pivots)
    # tableau columns: w (0..n-1), z (n..2n-1), z0 (2n); basic variables are stored per row
    T = np.empty((n, 2 * n + 1))
    T[:, :n] = np.eye(n)
    T[:, n : 2 * n] = -M
    T[:, 2 * n] = -1.0
    rhs = q.copy()
    basis = np.arange(n)
    update = np.empty_like(T)
    # initial pivot: z0 enters, the row of the most negative q leaves (ties: lexicographic)
    low = rhs.min()
    cand = np.flatnonzero(rhs <= low + TIE_RTOL * max(abs(low), 1.0))
    row = int(cand[-1])  # the lexicographically smallest perturbed q_i + eps^(i+1)
    col = 2 * n
    pivots = 0
    while True:
        piv = T[row, col]
        T[row] /= piv
        rhs[row] /= piv
        f = T[:, col].copy()
        f[row] = 0.0
        np.multiply(f[:, None], T[row], out=update)
        T -= update
        rhs -= f * rhs[row]
        leaving = int(basis[row])
        basis[row] = col
        pivots += 1
        if leaving == 2 * n:
            break
        col = leaving + n if leaving < n else leaving - n  # the complement enters
        if pivots >= limit:
            return LCPResult(LCPStatus.PIVOT_LIMIT, np.zeros(n), q.copy(), pivots)
        row = _leaving_row(T, col, rhs, n, tol)
        if row < 0:
            return LCPResult(LCPStatus.RAY, np.zeros(n), q.copy(), pivots)
    return _basic_solution(M, q, basis, rhs, pivots)


def _basic_solution(
    M: np.ndarray, q: np.ndarray, basis: np.ndarray, rhs: np.ndarray, pivots: int
) -> LCPResult:
    """The solution of Lemke's final tableau (basic variables ``basis`` (n,), values ``rhs``)."""
    n = q.size
    x = np.zeros(2 * n + 1)
    x[basis] = np.maximum(rhs, 0.0)  # basic values; -1e-16 rounding of a degenerate row is 0
    z, w = x[n : 2 * n].copy(), x[:n].copy()
    if not _verified(M, q, z):
        return LCPResult(LCPStatus.INACCURATE, np.zeros(n), q.copy(), pivots)
    return LCPResult(LCPStatus.SOLVED, z, w, pivots)


#: Largest LCP whose Lemke pivots run on Python floats (:func:`_pivots_small`; speed only).
SMALL = 4


def _pivots_small(
    M: np.ndarray, q: np.ndarray, limit: int, tol: float
) -> tuple[LCPStatus, list[int], list[float], int] | None:
    """:func:`lemke`'s pivoting loop on Python floats for a small LCP: the same IEEE operations,
    element by element and in the same order, as the NumPy loop (so the same bits), without
    NumPy's per-call overhead. Returns (status, basis, basic values, pivots), or None when a
    value is not finite (the NumPy loop then runs, as it always did)."""
    n = q.size
    m = 2 * n + 1
    rhs = q.tolist()
    if not all(math.isfinite(v) for v in rhs):
        return None
    rows = M.tolist()
    T = [[1.0 if j == i else 0.0 for j in range(n)] + [-v for v in rows[i]] + [-1.0] for i in range(n)]
    basis = list(range(n))
    low = min(rhs)
    bar = low + TIE_RTOL * max(abs(low), 1.0)
    row = [i for i in range(n) if rhs[i] <= bar][-1]
    col = 2 * n
    pivots = 0
    while True:
        piv = T[row][col]
        Tr = [v / piv for v in T[row]]
        T[row] = Tr
        rhs[row] = rhs[row] / piv
        f = [T[i][col] for i in range(n)]
        f[row] = 0.0
        T = [[Ti[j] - fi * Tr[j] for j in range(m)] for Ti, fi in zip(T, f)]
        rr = rhs[row]
        rhs = [r - fi * rr for r, fi in zip(rhs, f)]
        leaving = basis[row]
        basis[row] = col
        pivots += 1
        if leaving == 2 * n:
            break
        col = leaving + n if leaving < n else leaving - n  # the complement enters
        if pivots >= limit:
            return LCPStatus.PIVOT_LIMIT, basis, rhs, pivots
        found = _leaving_row_small(T, col, rhs, n, tol)
        if found is None:
            return None
        row = found
        if row < 0:
            return LCPStatus.RAY, basis, rhs, pivots
    return LCPStatus.SOLVED, basis, rhs, pivots


def _leaving_row_small(T: list[list[float]], col: int, rhs: list[float], n: int, tol: float) -> int | None:
    """:func:`_leaving_row` on Python floats (None: a value is not a number; -1: ray)."""
    a = [T[i][col] for i in range(n)]
    pos = [v > tol for v in a]
    if not any(pos):
        return -1
    ratios = [rhs[i] / a[i] if pos[i] else math.inf for i in range(n)]
    if any(r != r for r in ratios):
        return None
    best = min(ratios)
    bar = best + TIE_RTOL * max(abs(best), 1.0)
    cand = [i for i in range(n) if ratios[i] <= bar]
    if len(cand) == 1:
        return cand[0]
    for j in range(n):
        vals = [T[i][j] / a[i] for i in cand]
        if any(v != v for v in vals):
            return None
        low = min(vals)
        bar = low + TIE_RTOL * max(abs(low), 1.0)
        cand = [i for i, v in zip(cand, vals) if v <= bar]
        if len(cand) == 1:
            break
    return cand[0]


def _verified(M: np.ndarray, q: np.ndarray, z: np.ndarray, rtol: float = 1e-8) -> bool:
    """``w = M z + q >= 0`` and ``z^T w = 0`` to ``rtol`` of the data's scale."""
    w = M @ z + q
    zmax = float(_max(z, initial=0.0))
    scale = max(
        float(_max(np.abs(q), initial=0.0)), float(_max(np.abs(M), axis=None, initial=0.0)) * zmax, 1e-300
    )
    return bool(
        _min(w, initial=0.0) >= -rtol * scale
        and _max(np.abs(z * w), initial=0.0) <= rtol * scale * max(zmax, 1e-300)
    )


def canonical(M: np.ndarray, q: np.ndarray, res: LCPResult, rtol: float = 1e-9) -> LCPResult:
    """The least-norm solution over the tight items of a solution ``res``.

    When several solutions share the tight set ``T`` (``z > 0`` or ``w = 0``, e.g. nearly equal
    rows of ``M``), the least-norm ``z_T`` with ``M_TT z_T = -q_T`` is unique and does not depend
    on the order of the items; it is returned when it is nonnegative (else ``res``)."""
    if not res.solved or res.z.size == 0:
        return res
    zmax = max(float(_max(res.z)), 1e-300)
    wscale = max(float(_max(np.abs(q))), float(_max(np.abs(M), axis=None)) * zmax, 1e-300)
    active = res.z > 0
    # a tight item that is not active (NaN never compares true)
    if not np.count_nonzero(np.where(active, np.nan, res.w) <= rtol * wscale):
        return res  # no degenerate item: Lemke's basis makes M_BB nonsingular, z is unique there
    tight = active | (res.w <= rtol * wscale)
    Mt = M[np.ix_(tight, tight)]
    zt = np.linalg.lstsq(Mt, -q[tight], rcond=rtol)[0]
    if zt.min() < -rtol * zmax:
        return res
    z = np.zeros_like(res.z)
    z[tight] = np.maximum(zt, 0.0)
    if not _verified(M, q, z, 1e-8):
        return res
    w = M @ z + q
    w[tight] = 0.0
    return LCPResult(LCPStatus.SOLVED, z, np.maximum(w, 0.0), res.pivots, tie=True)


__all__ = [
    "LCPResult",
    "LCPStatus",
    "block_solution",
    "canonical",
    "lemke",
    "principal_pivoting",
]
