"""Fixed-mode convex QP (ProxSuite): the passive-response problem with a known mode.

With the complementarity mode fixed (which contacts touch, which actuators move), Alg. 1 and
Alg. 2 become convex QPs over the same variables. pinograsp uses this QP to *polish* every
mixed-integer solution — the polished point satisfies complementarity exactly instead of up to
the MIQP's integrality tolerance times big-M — and the speed issue's fast path uses it with a
guessed mode. All modes share the matrices; only the bounds ``l, u`` change.
"""

from __future__ import annotations

import time

import numpy as np
import proxsuite

from .base import FAILED, INFEASIBLE, OPTIMAL, Mode, RawSolution
from .formulation import Formulation, ScaledData

INF = 1e20


class FixedModeQP:
    """Dense ProxSuite QP for one problem kind (``"prp"`` or ``"move"``) of one model.

    Args:
        form: The model's scaled formulation.
        kind: ``"prp"`` (minimise ``|c_n|^2`` s.t. equilibrium) or ``"move"`` (minimise the
            net wrench, object moving along the previous net wrench with step in [0, gamma]).
        gamma: Step bound of Alg. 2 (scaled: a step changes a spring of the stiffest contact by
            at most ``gamma`` times the current net wrench).
        eps: Absolute accuracy of ProxSuite (scaled units).
    """

    def __init__(self, form: Formulation, kind: str, gamma: float = 1.0, eps: float = 1e-10) -> None:
        self.form, self.kind, self.gamma = form, kind, float(gamma)
        f = form
        lay = form.layout(kind)
        self.lay = lay
        n = lay["n"].stop
        self.n = n
        nb, nq, na, ncp, nc = f.nb, f.nq, f.na, f.ncp, f.nc
        sb, so, sq, sf, sl = lay["beta"], lay["obj"], lay["qh"], lay["fh"], lay["lam"]
        # equality rows
        A = []
        if kind == "prp":
            Aeq = np.zeros((f.nw, n))
            Aeq[:, sb] = f.Gb
            A.append(Aeq)
        Ah = np.zeros((nq, n))
        Ah[:, sb] = f.T
        Ah[:, sf] = -f.Rf
        Ah[:, sl] = -f.Cl
        A.append(Ah)
        Ac = np.zeros((ncp, n))
        Ac[:, sq] = f.Cq
        A.append(Ac)
        self.A = np.vstack(A)
        # inequality rows: beta >= 0 | c_n | gap | u | f | step
        rows = []
        Ib = np.zeros((nb, n))
        Ib[:, sb] = np.eye(nb)
        rows.append(Ib)
        Cn = np.zeros((nc, n))
        Cn[:, sb] = f.E
        rows.append(Cn)
        Cg = np.zeros((nc, n))
        Cg[:, sb] = f.E
        Cg[:, sq] = -f.Kq
        if kind == "prp":
            Cg[:, so] = f.Kx
        rows.append(Cg)  # the step column is filled per solve (depends on the direction)
        Cu = np.zeros((na, n))
        Cu[:, sq] = f.Ru
        rows.append(Cu)
        Cf = np.zeros((na, n))
        Cf[:, sf] = np.eye(na)
        rows.append(Cf)
        if kind == "move":
            Cs = np.zeros((1, n))
            Cs[0, so] = 1.0
            rows.append(Cs)
        self.C = np.vstack(rows)
        o = 0
        self.r_beta = slice(o, o + nb)
        o += nb
        self.r_cn = slice(o, o + nc)
        o += nc
        self.r_gap = slice(o, o + nc)
        o += nc
        self.r_u = slice(o, o + na)
        o += na
        self.r_f = slice(o, o + na)
        o += na
        self.r_step = slice(o, o + (1 if kind == "move" else 0))
        self.H = np.zeros((n, n))
        if kind == "prp":
            self.H[sb, sb] = f.E.T @ f.E
        else:
            self.H[sb, sb] = f.Gb.T @ f.Gb
        self.eps = eps
        self._qp = None

    def bounds(self, data: ScaledData, mode: Mode) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Equality right-hand side and inequality bounds for one mode."""
        f = self.form
        b = np.concatenate([-data.w if self.kind == "prp" else np.zeros(0), np.zeros(f.nq + f.ncp)])
        nrow = self.C.shape[0]
        lo = np.full(nrow, -INF)
        up = np.full(nrow, INF)
        lo[self.r_beta] = 0.0
        touch = np.asarray(mode.touching, bool)
        lo[self.r_cn] = 0.0
        up[self.r_cn] = np.where(touch, INF, 0.0)
        p = data.p.copy()
        if self.kind == "move":
            p = p - f.Kx @ data.x0
        lo[self.r_gap] = p
        up[self.r_gap] = np.where(touch, p, INF)
        mov = np.asarray(mode.moving, bool) & f.nbd
        # actuator displacement
        lo[self.r_u] = np.where(f.bdr, -INF, 0.0)
        up[self.r_u] = np.where(f.bdr, INF, np.where(f.nbd & mov, INF, 0.0))
        # actuator force
        lo[self.r_f] = np.where(f.lck, -INF, data.fc)
        up[self.r_f] = np.where(f.lck, INF, np.where(f.bdr | mov, data.fc, INF))
        if self.kind == "move":
            lo[self.r_step] = 0.0
            up[self.r_step] = self.gamma
        return b, lo, up

    def _matrices(self, data: ScaledData) -> tuple[np.ndarray, np.ndarray]:
        """Inequality matrix and linear cost of one solve (``move`` depends on the data)."""
        g = np.zeros(self.n)
        if self.kind != "move":
            return self.C, g
        f = self.form
        C = self.C.copy()
        C[self.r_gap, self.lay["obj"]] = (f.Kx @ data.direction)[:, None]
        g[self.lay["beta"]] = f.Gb.T @ data.w
        return C, g

    def solve(
        self, data: ScaledData, mode: Mode, max_iter: int = 1000, precondition: bool = True
    ) -> RawSolution:
        """Solve the QP of ``mode``; ``status`` is ``"optimal"`` only if ProxSuite converged and
        the primal residual is below tolerance (ProxSuite rarely certifies infeasibility, so a
        non-converged solve is reported as ``"infeasible"`` when its primal residual is large).

        Args:
            data: Scaled data of the solve.
            mode: The complementarity mode to fix.
            max_iter: ProxSuite iteration cap. A feasible mode converges in ~10–30 iterations;
                an infeasible one runs to the cap (~20 µs per iteration), so the mode-guess path
                uses a small cap and treats "not converged" as "guess failed".
            precondition: Let ProxSuite equilibrate the problem. The formulation is already
                scaled to force units, so the mode-guess path skips it (2–3x faster per solve);
                a guess that does not converge without it falls back to the exact path.
        """
        b, lo, up = self.bounds(data, mode)
        return self._solve(data, mode, b, lo, up, max_iter, precondition)

    def _solve(
        self,
        data: ScaledData,
        mode: Mode,
        b: np.ndarray,
        lo: np.ndarray,
        up: np.ndarray,
        max_iter: int,
        precondition: bool = True,
    ) -> RawSolution:
        f = self.form
        C, g = self._matrices(data)
        t0 = time.perf_counter()
        qp = proxsuite.proxqp.dense.QP(self.n, self.A.shape[0], C.shape[0])
        qp.settings.eps_abs = self.eps
        qp.settings.eps_rel = 0.0
        qp.settings.max_iter = int(max_iter)
        qp.settings.max_iter_in = 100 if max_iter >= 1000 else 30
        qp.settings.eps_primal_inf = 1e-10
        qp.settings.eps_dual_inf = 1e-10
        qp.settings.verbose = False
        qp.init(self.H, g, self.A, b, C, lo, up, compute_preconditioner=precondition)
        qp.solve()
        dt = time.perf_counter() - t0
        st = qp.results.info.status
        z = np.array(qp.results.x)
        # independent primal residual check
        res_eq = np.abs(self.A @ z - b).max(initial=0.0)
        Cz = C @ z
        res_in = max(np.maximum(lo - Cz, 0).max(initial=0.0), np.maximum(Cz - up, 0).max(initial=0.0))
        res = max(res_eq, res_in)
        ok = st == proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED and res < 1e-7
        if not ok:
            status = INFEASIBLE if res >= 1e-7 else FAILED
            return RawSolution(
                status=status, solve_time=dt, backend="proxsuite", message=f"{st}, residual {res:.2e}"
            )
        if self.kind == "move":
            obj = float(np.sum((data.w + f.Gb @ z[self.lay["beta"]]) ** 2))
        else:
            obj = float(np.sum((f.E @ z[self.lay["beta"]]) ** 2))
        return RawSolution(
            status=OPTIMAL,
            z=z,
            mode=mode,
            objective=obj,
            solve_time=dt,
            backend="proxsuite",
            polished=True,
            duals=np.array(qp.results.z),
            message=f"{int(qp.results.info.iter)} iterations",
        )

    def check_local_optimality(
        self,
        data: ScaledData,
        sol: RawSolution,
        tol: float = 1e-9,
        dual_tol: float = 1e-7,
        max_branch_pairs: int = 3,
        precondition: bool = True,
    ) -> tuple[bool, float, RawSolution | None]:
        """Whether a fixed-mode solution is a local optimum of the complementarity problem.

        The fixed-mode QP is convex, so its solution is optimal within its mode. It is a local
        optimum of the full problem iff no mode obtained by switching *biactive* pairs — a contact
        with ``c_n = 0`` and spring gap ``0``; a non-backdrivable actuator with ``u = 0`` and
        ``f = f_c`` — gives a better point (B-stationarity). Cheapest test first:

        1. strong stationarity from ProxSuite's multipliers: at every biactive pair both
           multipliers have the sign of a lower bound (``z <= dual_tol``). Sufficient, not
           necessary: degenerate problems (common: an actuator holding at exactly its command)
           have non-unique multipliers and points that are locally optimal without being
           strongly stationary;
        2. otherwise, if there are at most ``max_branch_pairs`` biactive pairs, the QP of every
           mode obtained by switching a non-empty subset of them is solved (the point is feasible
           in each): the point is locally optimal iff none is better.

        Returns:
            ``(ok, time, better)``: the verdict, the time of the extra QPs [s], and a strictly
            better switched-mode solution when one was found (else None).
        """
        f = self.form
        z = sol.duals
        if z is None or sol.z is None or sol.mode is None:
            return False, 0.0, None
        b, lo, up = self.bounds(data, sol.mode)
        C, _ = self._matrices(data)
        v = C @ sol.z
        cn, gap = v[self.r_cn], v[self.r_gap] - lo[self.r_gap]
        bic = (np.abs(cn) <= tol) & (np.abs(gap) <= tol)
        bia = np.zeros(f.na, bool)
        if f.na:
            u, over = v[self.r_u], v[self.r_f] - lo[self.r_f]
            bia = f.nbd & (np.abs(u) <= tol) & (np.abs(over) <= tol)
        bad_c = bic & ((z[self.r_cn] > dual_tol) | (z[self.r_gap] > dual_tol))
        bad_a = bia & ((z[self.r_u] > dual_tol) | (z[self.r_f] > dual_tol)) if f.na else bia
        if not (bad_c.any() or bad_a.any()):
            return True, 0.0, None
        pairs = [("c", i) for i in np.flatnonzero(bic)] + [("a", i) for i in np.flatnonzero(bia)]
        if len(pairs) > max_branch_pairs:
            return False, 0.0, None
        spent = 0.0
        limit = sol.objective - tol * max(1.0, sol.objective)
        for bits in range(1, 2 ** len(pairs)):
            touching = list(sol.mode.touching)
            moving = list(sol.mode.moving)
            for k, (what, i) in enumerate(pairs):
                if bits >> k & 1:
                    if what == "c":
                        touching[i] = not touching[i]
                    else:
                        moving[i] = not moving[i]
            other = self.solve(data, Mode(tuple(touching), tuple(moving)), precondition=precondition)
            spent += other.solve_time
            if other.status == OPTIMAL and other.objective < limit:
                return False, spent, other
        return True, spent, None
