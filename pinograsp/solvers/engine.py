"""The exact solve of one scaled problem: MIQP, big-M audit and retry, fixed-mode polish."""

from __future__ import annotations

import warnings
from dataclasses import replace
from typing import Any

from ..errors import BigMWarning
from .base import OPTIMAL, RawSolution
from .fixed_mode import FixedModeQP
from .formulation import Formulation, ScaledData
from .miqp import CvxpyMIQP

#: A solution whose big-M-bounded quantities reach this fraction of M is re-solved with a
#: larger M (the bound may be cutting off the true optimum, SOLVER_NOTES).
BIGM_TRIGGER = 0.1


class ExactSolver:
    """Solve Alg. 1 / Alg. 2 problems of one model exactly (up to MIQP optimality).

    Each call: solve the big-M MIQP with ``M = bigm``; if any bounded quantity exceeds
    ``BIGM_TRIGGER * M`` re-solve with ``M`` enlarged 100x (at most ``bigm_retries`` times,
    then warn with :class:`BigMWarning` and flag the result); finally polish the solution with
    the fixed-mode QP of its mode so that complementarity holds exactly.
    """

    def __init__(
        self,
        form: Formulation,
        kind: str,
        solver: str = "scip",
        gamma: float = 1.0,
        bigm: float = 1e3,
        bigm_retries: int = 2,
        time_limit: float = 60.0,
        polish: bool = True,
        options: dict[str, Any] | None = None,
    ) -> None:
        self.form, self.kind = form, kind
        self.miqp = CvxpyMIQP(form, kind, solver=solver, gamma=gamma, time_limit=time_limit, options=options)
        self.qp = FixedModeQP(form, kind, gamma=gamma) if polish else None
        self.bigm, self.bigm_retries = float(bigm), int(bigm_retries)
        self.n_miqp = 0
        self.n_qp = 0

    def solve(self, data: ScaledData) -> RawSolution:
        """Exact solve of one problem; see the class docstring."""
        M = self.bigm
        retries = 0
        total = 0.0
        while True:
            sol = self.miqp.solve(data, M)
            self.n_miqp += 1
            total += sol.solve_time
            if sol.status != OPTIMAL or sol.bigm_ratio < BIGM_TRIGGER or retries >= self.bigm_retries:
                break
            M *= 100.0
            retries += 1
        if sol.status != OPTIMAL:
            return replace(sol, solve_time=total, bigm_retries=retries)
        if sol.bigm_ratio >= BIGM_TRIGGER:
            warnings.warn(
                f"MIQP solution uses {sol.bigm_ratio:.0%} of the big-M bound after {retries} enlargements "
                f"(M = {M:.3g} in scaled force units): the answer may be cut off by the bound",
                BigMWarning,
                stacklevel=3,
            )
        if self.qp is not None:
            pol = self.qp.solve(data, sol.mode)
            self.n_qp += 1
            total += pol.solve_time
            if pol.status == OPTIMAL:
                return RawSolution(
                    status=OPTIMAL,
                    z=pol.z,
                    mode=sol.mode,
                    objective=pol.objective,
                    solve_time=total,
                    backend=f"{sol.backend}+proxsuite",
                    bigm_ratio=sol.bigm_ratio,
                    bigm_retries=retries,
                    polished=True,
                )
        return replace(sol, solve_time=total, bigm_retries=retries)
