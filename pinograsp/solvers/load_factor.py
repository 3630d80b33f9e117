"""Direct formulation of Alg. 1's max resistible wrench: one MILP instead of a bisection.

The PRP's verdict is feasibility, which does not depend on the objective. So the largest
resistible magnitude along a direction ``d`` is the optimum of one mixed-integer program::

    maximise t   s.t.   Gb beta + t d̂ = 0,  0 <= t <= t_max,  and every other PRP constraint

(the big-M complementarity of :class:`~.miqp.CvxpyMIQP`, reused constraint by constraint). This
is the supremum of the resistible magnitudes along the ray — the bisection's answer when
resistibility is monotone along the ray, and the true supremum when it is not. There is no
such formulation for the iterative scheme (its verdict is the end of a trajectory).

This module never imports Pinocchio or Coal.
"""

from __future__ import annotations

import time
import warnings

import cvxpy as cp
import numpy as np

from .base import FAILED, INFEASIBLE, OPTIMAL, TIMEOUT
from .formulation import Formulation, ScaledData
from .miqp import CvxpyMIQP, _backend_status, quiet_stdout


class LoadFactorMIQP:
    """``max t`` subject to the PRP constraints with the load ``t d̂``, built once per model.

    Args:
        form: Scaled formulation.
        solver, time_limit, options: As :class:`~.miqp.CvxpyMIQP`.
    """

    def __init__(
        self,
        form: Formulation,
        solver: str = "scip",
        time_limit: float = 60.0,
        options: dict | None = None,
    ) -> None:
        self.form = form
        opts = dict(options or {})
        opts["complementarity"] = "bigm"
        self.base = CvxpyMIQP(form, "prp", solver=solver, time_limit=time_limit, options=opts)
        b = self.base
        self.t = cp.Variable(nonneg=True)
        self.d = cp.Parameter(form.nw)
        self.tmax = cp.Parameter(nonneg=True)
        # the base problem's first constraint is the equilibrium with the fixed load w
        cons = [form.Gb @ b.beta + self.t * self.d == 0, self.t <= self.tmax]
        cons += list(b.problem.constraints[1:])
        self.problem = cp.Problem(cp.Maximize(self.t), cons)

    def solve(self, data: ScaledData, direction: np.ndarray, tmax: float, M: float) -> dict:
        """Largest scaled load factor.

        Args:
            data: Scaled data (commands, pre-compression; ``w`` is ignored).
            direction: Scaled unit load direction ``d̂`` (nw,).
            tmax: Search limit in scaled units.
            M: Big-M constant (scaled force units).

        Returns:
            ``{"status", "t", "mode_touching", "mode_moving", "bigm_ratio", "solve_time"}``.
        """
        b = self.base
        if b.fc is not None:
            b.fc.value = data.fc
        b.p.value = data.p
        b.M.value = float(M)
        self.d.value = np.asarray(direction, float)
        self.tmax.value = float(tmax)
        t0 = time.perf_counter()
        try:
            with quiet_stdout(b.quiet), warnings.catch_warnings():
                warnings.filterwarnings("ignore", message="Solution may be inaccurate")
                self.problem.solve(solver=b.solver, **b._solver_kwargs())
        except cp.error.SolverError as exc:
            dt = time.perf_counter() - t0
            st = TIMEOUT if dt >= 0.99 * b.time_limit else FAILED
            return {"status": st, "t": float("nan"), "solve_time": dt, "message": str(exc)}
        dt = time.perf_counter() - t0
        st = self.problem.status
        if st in (cp.INFEASIBLE, cp.settings.INFEASIBLE_OR_UNBOUNDED):
            return {"status": INFEASIBLE, "t": float("nan"), "solve_time": dt}
        raw = _backend_status(self.problem)
        if raw == "timelimit" or (st == cp.OPTIMAL_INACCURATE and dt >= 0.99 * b.time_limit):
            return {"status": TIMEOUT, "t": float("nan"), "solve_time": dt, "message": raw or str(st)}
        if st != cp.OPTIMAL or self.t.value is None:
            return {"status": FAILED, "t": float("nan"), "solve_time": dt, "message": f"{st} {raw}".strip()}
        ratio = max(
            float(np.max(np.abs(b.cn_expr.value), initial=0.0)) / M,
            float(np.max(np.abs(b.gap_expr.value) / b.m_gap, initial=0.0)) / M,
        )
        return {"status": OPTIMAL, "t": float(self.t.value), "bigm_ratio": ratio, "solve_time": dt}
