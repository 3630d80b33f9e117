"""Deterministic convex QPs of one :class:`~.problem.Problem` with some pairs fixed (DAQP).

Each node of the branch-and-bound, each fixed-mode solve and each polish is the convex QP::

    minimise |L z + l|^2   subject to   A z = b,   lo <= C z <= up'

where ``up'`` holds a fixed pair's side at its lower bound. It is solved by DAQP, a dual
active-set method in C: single-threaded, no randomisation, so the same input gives the same
bits in every process. The objective is rank deficient (only the contact forces enter it), so
DAQP runs in its proximal mode.

Two refinements make the answer exact and canonical:

* **polish** — the rows that are tight at DAQP's point are taken as equalities and the
  equality-constrained least-squares problem on that face is solved directly (null-space
  method, SVD), which removes the proximal iteration's residual error; the polished point is
  kept only if it satisfies every row and is no worse;
* **least norm** — among the points of the face with the optimal objective the one of least
  Euclidean norm is returned, so that ties (friction edges, joint null spaces) are broken the
  same way for mirror-symmetric grasps.

DAQP's proximal iterations occasionally report a feasible node "infeasible" or "unbounded", or
cycle, on these degenerate problems (a case-1 mode QP was called infeasible that has a point).
So DAQP's answer is taken only when it is a point that passes the feasibility check; its
"infeasible" is confirmed on the strictly convex projection problem (no proximal iterations);
every other outcome is decided by Clarabel (interior point, single-threaded, deterministic),
whose points are accepted only within :data:`MAX_POINT`. Where Clarabel gives no verdict either
(nodes a relative 1e-7 from infeasibility, met by a fine search next to the limit), the least
uniform violation of the rows (an always-feasible LP) decides: above :data:`FEAS_TOL` the node is
infeasible, as the feasibility check defines it.

This module never imports Pinocchio or Coal.
"""

from __future__ import annotations

from dataclasses import dataclass

import daqp
import numpy as np

from ..errors import SolverError
from .base import SolveStatus
from .problem import INF, Problem

#: DAQP's exit flag for a solved problem (2: solved with soft constraints violated).
_SOLVED = (1, 2)
#: DAQP's exit flag for a primal-infeasible problem.
_INFEASIBLE = -1
#: Bound on every variable (scaled force units: multiples of the data's force scale). It keeps
#: DAQP's proximal iterations away from directions of zero cost that the rows leave unbounded
#: (DAQP then reported "unbounded" for a convex QP bounded below); no physical answer is near it.
BOX = INF
#: Clarabel's tolerances, tried in turn (the tight one stalls on some 16-contact hands).
CLARABEL_TOLERANCES = (1e-12, 1e-8)
#: Largest accepted variable (scaled force units): an interior-point "solution" beyond it is a
#: march towards infinity on an infeasible node, not an answer.
MAX_POINT = 1e9
#: Primal feasibility tolerance (scaled force units): a point is accepted within it, and a node
#: whose rows cannot all hold within it is infeasible.
FEAS_TOL = 1e-9
#: Objective values (squared scaled forces) below this are equal: a net wrench of 1e-9 of the
#: force scale is the feasibility tolerance.
OBJ_FLOOR = FEAS_TOL**2
#: Relative rounding allowed on each row's terms when checking a point (DAQP's accumulated
#: error on points with large displacements, e.g. a stiffness ratio of 1e6).
ROUNDING = 1e-12
#: Slack below which a row counts as tight when polishing (scaled force units).
TIGHT_TOL = 1e-9
#: DAQP settings of a node QP (proximal mode: the objective is rank deficient).
DAQP_SETTINGS: dict[str, float] = {"eps_prox": 1e-6, "primal_tol": 1e-9}
#: Further DAQP settings tried, in order, when the first gives no acceptable point.
DAQP_RETRIES: tuple[dict[str, float], ...] = (
    {"eps_prox": -1.0, "primal_tol": 1e-10},
    {"eps_prox": 1e-4, "primal_tol": 1e-10},
)


@dataclass(frozen=True, eq=False)
class QPResult:
    """A convex QP's answer.

    Attributes:
        status: :class:`~.base.SolveStatus`: ``OPTIMAL``, ``INFEASIBLE`` or ``FAILED``.
        z: The point (scaled variables), or None.
        objective: ``|L z + l|^2`` at ``z`` (``inf`` without a point).
        iterations: DAQP iterations over every attempt.
        attempts: DAQP solves made (retries included).
    """

    status: SolveStatus
    z: np.ndarray | None
    objective: float
    iterations: int
    attempts: int

    @property
    def point(self) -> np.ndarray:
        """``z`` of an answer that has one (an optimal one); :class:`~pinograsp.errors.SolverError`
        for an answer without a point."""
        if self.z is None:
            raise SolverError(f"a {self.status.value} QP answer has no point", "bnb", self.status.value)
        return self.z


class NodeQP:
    """The convex QPs of one :class:`Problem` (matrices stacked once, bounds per call)."""

    def __init__(self, problem: Problem) -> None:
        self.p = problem
        P = problem
        self.H = 2.0 * (P.L.T @ P.L)
        self.g = 2.0 * (P.L.T @ P.l)
        #: the friction-edge rows ``beta >= 0`` are passed to DAQP as simple variable bounds
        self.nb = P.rows.beta.stop
        self.vlo = np.full(P.n, -BOX)
        self.vup = np.full(P.n, BOX)
        self.vlo[: self.nb] = 0.0
        self.M = np.ascontiguousarray(np.vstack([P.A, P.C[self.nb :]]))
        self.me = P.A.shape[0]

    def feasible(self, z: np.ndarray, up: np.ndarray, tol: float = FEAS_TOL) -> bool:
        """Whether ``z`` satisfies every row with upper bounds ``up`` within ``tol`` relative to
        plus the rounding of each row's terms (:data:`ROUNDING` times ``|C_i| |z|``)."""
        P = self.p
        tol_rows = tol + ROUNDING * (np.abs(P.C) @ np.abs(z))
        if P.A.shape[0] and np.any(np.abs(P.A @ z - P.b) > tol + ROUNDING * (np.abs(P.A) @ np.abs(z))):
            return False
        v = P.C @ z
        return bool(np.all(v >= P.lo - tol_rows) and np.all(v <= up + tol_rows))

    def solve(self, up: np.ndarray, polish: bool = True) -> QPResult:
        """Solve with the problem's lower bounds and the upper bounds ``up`` (mi,)."""
        P = self.p
        nb = self.nb
        lo = P.lo
        bu = np.concatenate([self.vup, P.b, up[nb:]])
        bl = np.concatenate([self.vlo, P.b, lo[nb:]])
        sense = np.zeros(len(bu), dtype=np.int32)
        sense[P.n : P.n + self.me] = 5
        bu[:nb] = up[:nb]
        x, _, flag, info = daqp.solve(self.H, self.g, self.M, bu, bl, sense, **DAQP_SETTINGS)
        iters, attempts = int(info["iterations"]), 1
        z = np.array(x, float) if flag in _SOLVED and self.feasible(np.asarray(x), up) else None
        if z is None:
            # without a point, feasibility is decided on the strictly convex projection problem
            # (min |z|^2 over the same rows), where DAQP's dual test does not rest on proximal
            # iterations (they report false "infeasible" and cycle on degenerate nodes)
            attempts += 1
            if self.project(up) is None:
                return QPResult(SolveStatus.INFEASIBLE, None, float("inf"), iters, attempts)
        for opts in DAQP_RETRIES if z is None else ():
            # other proximal weights: a point slightly off its rows (1e-8) or a cycle is often
            # settled by them
            x, _, flag, info = daqp.solve(self.H, self.g, self.M, bu, bl, sense, **opts)
            iters, attempts = iters + int(info["iterations"]), attempts + 1
            if flag in _SOLVED and self.feasible(np.asarray(x), up):
                z = np.array(x, float)
                break
        if z is None:
            # DAQP did not find a point ("infeasible" — sometimes falsely on degenerate nodes —,
            # "unbounded", cycling): the interior-point solver decides, with an infeasibility
            # certificate
            attempts += 1
            status, z = self.interior_point(up)
            if status is not SolveStatus.OPTIMAL or z is None:
                return QPResult(status, None, float("inf"), iters, attempts)
        if polish:
            z = self.polish(z, up)
        return QPResult(SolveStatus.OPTIMAL, z, P.objective(z), iters, attempts)

    def project(self, up: np.ndarray) -> np.ndarray | None:
        """The least-norm point of the rows with upper bounds ``up`` (None: DAQP proves there is
        none; a strictly convex QP, so its infeasibility verdict does not rest on proximal
        iterations)."""
        P = self.p
        nb = self.nb
        bu = np.concatenate([self.vup, P.b, up[nb:]])
        bl = np.concatenate([self.vlo, P.b, P.lo[nb:]])
        bu[:nb] = up[:nb]
        sense = np.zeros(len(bu), dtype=np.int32)
        sense[P.n : P.n + self.me] = 5
        x, _, flag, _ = daqp.solve(np.eye(P.n), np.zeros(P.n), self.M, bu, bl, sense)
        return None if flag == _INFEASIBLE else np.asarray(x, float)

    def interior_point(self, up: np.ndarray) -> tuple[SolveStatus, np.ndarray | None]:
        """The node QP by Clarabel (interior point, infeasibility certificates)."""
        import clarabel
        import scipy.sparse as sp

        P = self.p
        fl, fu = P.lo > -INF, up < INF
        G = np.vstack([P.A, -P.C[fl], P.C[fu]])
        h = np.concatenate([P.b, -P.lo[fl], up[fu]])
        cones = [clarabel.ZeroConeT(self.me), clarabel.NonnegativeConeT(int(fl.sum() + fu.sum()))]
        Hs, Gs = sp.csc_matrix(self.H), sp.csc_matrix(G)
        name = ""
        for tol in CLARABEL_TOLERANCES:
            st = clarabel.DefaultSettings()
            st.verbose = False
            st.tol_gap_abs = st.tol_gap_rel = st.tol_feas = tol
            st.max_iter = 400
            sol = clarabel.DefaultSolver(Hs, self.g, Gs, h, cones, st).solve()
            name = str(sol.status)
            if name in ("Solved", "AlmostSolved"):
                z = np.array(sol.x, float)
                if np.abs(z).max(initial=0.0) <= MAX_POINT and self.feasible(z, up, 1e3 * FEAS_TOL):
                    return SolveStatus.OPTIMAL, z
            if name in ("PrimalInfeasible", "AlmostPrimalInfeasible"):
                return SolveStatus.INFEASIBLE, None
        # no verdict (a node at a relative distance ~1e-7 from infeasibility makes the interior
        # point diverge): the least uniform violation of the rows decides, as the feasibility
        # check defines it
        t = self.least_violation(up)
        if t is not None and t > FEAS_TOL:
            return SolveStatus.INFEASIBLE, None
        return SolveStatus.FAILED, None

    def least_violation(self, up: np.ndarray) -> float | None:
        """The least ``t >= 0`` (scaled force units) with ``|A z - b| <= t`` and
        ``lo - t <= C z <= up + t`` for some ``z``: an always-feasible LP (Clarabel), None if it
        fails. ``t > FEAS_TOL`` means no point passes the feasibility check."""
        import clarabel
        import scipy.sparse as sp

        P = self.p
        n = P.n
        fl, fu = P.lo > -INF, up < INF
        col = -np.ones((1, 1))
        blocks = [
            (np.hstack([P.A, np.repeat(col, self.me, 0)]), P.b),
            (np.hstack([-P.A, np.repeat(col, self.me, 0)]), -P.b),
            (np.hstack([-P.C[fl], np.repeat(col, int(fl.sum()), 0)]), -P.lo[fl]),
            (np.hstack([P.C[fu], np.repeat(col, int(fu.sum()), 0)]), up[fu]),
            (np.hstack([np.zeros((1, n)), col]), np.zeros(1)),
        ]
        G = np.vstack([b[0] for b in blocks])
        h = np.concatenate([b[1] for b in blocks])
        q = np.zeros(n + 1)
        q[-1] = 1.0
        st = clarabel.DefaultSettings()
        st.verbose = False
        st.tol_gap_abs = st.tol_gap_rel = st.tol_feas = 1e-12
        st.max_iter = 400
        sol = clarabel.DefaultSolver(
            sp.csc_matrix((n + 1, n + 1)), q, sp.csc_matrix(G), h, [clarabel.NonnegativeConeT(len(h))], st
        ).solve()
        if str(sol.status) not in ("Solved", "AlmostSolved"):
            return None
        return max(float(sol.x[-1]), 0.0)

    def polish(self, z: np.ndarray, up: np.ndarray) -> np.ndarray:
        """The least-norm optimum on the face of rows tight at ``z`` (else ``z`` itself)."""
        P = self.p
        v = P.C @ z
        at_lo = (np.abs(v - P.lo) <= TIGHT_TOL) & (P.lo > -INF)
        at_up = (np.abs(v - up) <= TIGHT_TOL) & (up < INF) & ~at_lo
        Aa = np.vstack([P.A, P.C[at_lo], P.C[at_up]])
        ba = np.concatenate([P.b, P.lo[at_lo], up[at_up]])
        cand = least_norm_lsq(P.L, P.l, Aa, ba)
        if cand is None or not self.feasible(cand, up):
            return z
        if P.objective(cand) > P.objective(z) * (1.0 + 1e-12) + OBJ_FLOOR:
            return z
        return cand

    def least_norm(
        self, z: np.ndarray, up: np.ndarray, first: int | None = None, energy: bool = False
    ) -> np.ndarray | None:
        """Canonical point with the same objective residual ``L z + l`` as ``z`` (a feasible
        optimum), subject to every row with upper bounds ``up``: the largest value of variable
        ``first`` (if given; the iterative scheme's step length), then (``energy``) the least
        spring energy ``|c_n|^2``, then the least norm.

        Returns None if DAQP fails or the point would be worse than ``z``.
        """
        P = self.p
        _, s, Vt = np.linalg.svd(P.L, full_matrices=False)
        r = int(np.sum(s > 1e-12 * max(s[0], 1e-300))) if len(s) else 0
        rows = [P.A, Vt[:r]]
        rhs = [P.b, Vt[:r] @ z]
        if first is not None:
            top = self._largest(z, up, np.vstack(rows), np.concatenate(rhs), first)
            if top is None:
                return None
            e = np.zeros((1, P.n))
            e[0, first] = 1.0
            rows.append(e)
            rhs.append(np.array([top]))
        if energy:
            cn = self._least_energy(z, up, np.vstack(rows), np.concatenate(rhs))
            if cn is not None:
                rows.append(P.C[P.rows.cn])
                rhs.append(cn)
        cand = self._min_norm(np.vstack(rows), np.concatenate(rhs), up)
        if cand is None or not self.feasible(cand, up):
            return None
        if P.objective(cand) > P.objective(z) * (1.0 + 1e-9) + OBJ_FLOOR:
            return None
        return cand

    def _daqp(self, H: np.ndarray, g: np.ndarray, E: np.ndarray, e: np.ndarray, up: np.ndarray, **opt):
        """DAQP on ``min ½ z'Hz + g'z`` s.t. ``E z = e`` and the problem's rows with ``up``.

        ``E z = e`` is first reduced to independent rows (SVD): DAQP refuses dependent equality
        rows (its "overdetermined active set")."""
        P = self.p
        E, e = _independent(E, e)
        M = np.ascontiguousarray(np.vstack([E, P.C]))
        bu = np.concatenate([e, up])
        bl = np.concatenate([e, P.lo])
        sense = np.zeros(len(bu), dtype=np.int32)
        sense[: len(e)] = 5
        sense[len(e) :][up <= P.lo] = 5
        x, _, flag, _ = daqp.solve(H, g, M, bu, bl, sense, **opt)
        return np.array(x, float) if flag in _SOLVED else None

    def _largest(self, z: np.ndarray, up: np.ndarray, E: np.ndarray, e: np.ndarray, j: int) -> float | None:
        """Largest value of variable ``j`` on ``{E z = e} ∩ rows`` (``z`` is a feasible point)."""
        n = self.p.n
        H = np.zeros((n, n))
        H[j, j] = 1.0
        g = np.zeros(n)
        g[j] = -(float(np.max(np.abs(z))) + 1e3)  # pull towards a value beyond any bound
        x = self._daqp(H, g, E, e, up, eps_prox=1e-6)
        if x is None or not self.feasible(x, up):
            return float(z[j])
        return max(float(x[j]), float(z[j]))

    def _least_energy(self, z: np.ndarray, up: np.ndarray, E: np.ndarray, e: np.ndarray) -> np.ndarray | None:
        """Normal forces ``c_n`` (scaled, (nc,)) of least ``|c_n|^2`` on ``{E z = e} ∩ rows``,
        refined on the face of rows tight at DAQP's point (None: keep ``z``'s)."""
        P = self.p
        Cn = P.C[P.rows.cn]
        x = self._daqp(2.0 * Cn.T @ Cn, np.zeros(P.n), E, e, up, eps_prox=1e-6)
        if x is None or not self.feasible(x, up):
            return None
        v = P.C @ x
        tight = ((np.abs(v - P.lo) <= TIGHT_TOL) & (P.lo > -INF)) | (
            (np.abs(v - up) <= TIGHT_TOL) & (up < INF)
        )
        bound = np.where(np.abs(v - P.lo) <= TIGHT_TOL, P.lo, up)
        exact = least_norm_lsq(
            Cn, np.zeros(len(Cn)), np.vstack([E, P.C[tight]]), np.concatenate([e, bound[tight]])
        )
        if (
            exact is not None
            and self.feasible(exact, up)
            and np.sum((Cn @ exact) ** 2) <= np.sum((Cn @ x) ** 2)
        ):
            x = exact
        if np.sum((Cn @ x) ** 2) > np.sum((Cn @ z) ** 2):
            return None
        return Cn @ x

    def _min_norm(self, E: np.ndarray, e: np.ndarray, up: np.ndarray) -> np.ndarray | None:
        n = self.p.n
        return self._daqp(np.eye(n), np.zeros(n), E, e, up, primal_tol=1e-10, iter_limit=5000)


def _independent(E: np.ndarray, e: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """An equivalent system of independent rows (the range of ``E`` by SVD)."""
    if not E.shape[0]:
        return E, e
    U, s, Vt = np.linalg.svd(E, full_matrices=False)
    r = int(np.sum(s > 1e-12 * max(s[0], 1e-300)))
    return s[:r, None] * Vt[:r], U[:, :r].T @ e


def least_norm_lsq(L: np.ndarray, l: np.ndarray, A: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """Least-norm minimiser of ``|L z + l|^2`` subject to ``A z = b`` (None if inconsistent).

    Null-space method: ``z = z0 + N y`` with ``z0`` the least-norm solution of ``A z = b``
    (orthogonal to the null space ``N`` of ``A``) and ``y`` the least-norm minimiser of
    ``|L N y + L z0 + l|`` — so ``z`` has the least norm among all minimisers.
    """
    n = L.shape[1]
    if A.shape[0]:
        U, s, Vt = np.linalg.svd(A, full_matrices=True)
        tol = max(A.shape) * np.finfo(float).eps * (s[0] if len(s) else 0.0)
        r = int(np.sum(s > max(tol, 1e-12)))
        z0 = Vt[:r].T @ ((U[:, :r].T @ b) / s[:r])
        if np.abs(A @ z0 - b).max(initial=0.0) > 1e-9 * max(1.0, np.abs(b).max(initial=0.0)):
            return None
        N = Vt[r:].T
    else:
        z0 = np.zeros(n)
        N = np.eye(n)
    if N.shape[1] == 0:
        return z0
    y, *_ = np.linalg.lstsq(L @ N, -(L @ z0 + l), rcond=None)
    return z0 + N @ y
