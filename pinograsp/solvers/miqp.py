"""Mixed-integer QP backend (cvxpy): the passive-response problem with big-M complementarity.

One binary per contact (``y = 1``: touching) and per non-backdrivable actuator (``z = 1``:
moving), as in the seed paper, over the scaled variables of
:mod:`pinograsp.solvers.formulation`. Every big-M-bounded quantity is in scaled force units,
so one constant ``M`` (a cvxpy ``Parameter``) fits all of them. The problem is built once per
model and kind and re-solved with new parameter values (cvxpy DPP caching).
"""

from __future__ import annotations

import time
from typing import Any

import cvxpy as cp
import numpy as np

from ..errors import SolverError, SolverNotAvailableError
from .base import FAILED, INFEASIBLE, OPTIMAL, TIMEOUT, Mode, RawSolution
from .formulation import Formulation, ScaledData

#: cvxpy solvers able to solve mixed-integer QPs, with the package that provides each.
MIQP_SOLVERS = {
    "SCIP": "pyscipopt (installed with pinograsp)",
    "GUROBI": "gurobipy (pip install 'pinograsp[gurobi]')",
    "MOSEK": "mosek",
    "CPLEX": "cplex",
    "XPRESS": "xpress",
    "COPT": "coptpy",
}

#: SCIP settings measured to be 4-12x faster on these problems with identical answers
#: (SOLVER_NOTES): the aggregation cut separator and the MPEC heuristic dominate otherwise.
SCIP_DEFAULTS: dict[str, Any] = {
    "heuristics/mpec/freq": -1,
    "separating/aggregation/freq": -1,
    "numerics/feastol": 1e-8,
}


def available_miqp_solvers() -> list[str]:
    """Names (lower case) of the installed cvxpy MIQP solvers."""
    installed = set(cp.installed_solvers())
    return [s.lower() for s in MIQP_SOLVERS if s in installed]


def resolve_solver(name: str) -> str:
    """Validate a MIQP solver name; raise :class:`SolverNotAvailableError` naming the package."""
    key = str(name).upper()
    if key not in MIQP_SOLVERS:
        raise SolverNotAvailableError(
            f"unknown MIQP solver {name!r}; supported: {[s.lower() for s in MIQP_SOLVERS]}", solver=str(name)
        )
    if key not in cp.installed_solvers():
        raise SolverNotAvailableError(
            f"MIQP solver {name!r} is not installed; install {MIQP_SOLVERS[key]}", solver=str(name)
        )
    return key


class CvxpyMIQP:
    """The big-M MIQP of one problem kind, built once and re-solved with new data.

    Args:
        form: Scaled formulation of the model.
        kind: ``"prp"`` (Alg. 1) or ``"move"`` (Alg. 2, movement-constrained).
        solver: cvxpy solver name (``"scip"``, ``"gurobi"``, ...).
        gamma: Step bound of Alg. 2 (scaled, see :class:`~.fixed_mode.FixedModeQP`).
        time_limit: Per-solve time limit [s].
        options: Extra solver options passed to cvxpy (for SCIP: ``scip_params``).
    """

    def __init__(
        self,
        form: Formulation,
        kind: str,
        solver: str = "scip",
        gamma: float = 1.0,
        time_limit: float = 60.0,
        options: dict[str, Any] | None = None,
    ) -> None:
        self.form, self.kind = form, kind
        self.solver = resolve_solver(solver)
        self.gamma = float(gamma)
        self.time_limit = float(time_limit)
        self.options = dict(options or {})
        f = form
        nc, na = f.nc, f.na
        self.beta = cp.Variable(f.nb, nonneg=True)
        self.qh = cp.Variable(f.nq)
        self.fh = cp.Variable(na)
        self.lam = cp.Variable(f.ncp)
        self.y = cp.Variable(nc, boolean=True)
        nbd = np.flatnonzero(f.nbd)
        self.nbd_idx = nbd
        self.zb = cp.Variable(len(nbd), boolean=True) if len(nbd) else None
        self.w = cp.Parameter(f.nw)
        self.fc = cp.Parameter(na) if na else None
        self.p = cp.Parameter(nc)
        self.M = cp.Parameter(nonneg=True)
        cn = f.E @ self.beta
        cons = []
        if kind == "prp":
            self.obj = cp.Variable(f.nx)
            xterm = f.Kx @ self.obj
            cons.append(f.Gb @ self.beta + self.w == 0)
            objective = cp.sum_squares(cn)
        else:
            self.obj = cp.Variable(1)
            self.kx0 = cp.Parameter(nc)  # Kx @ x0
            self.kxd = cp.Parameter(nc)  # Kx @ direction
            xterm = self.kx0 + cp.multiply(self.kxd, self.obj[0])
            cons += [self.obj >= 0, self.obj <= self.gamma]
            objective = cp.sum_squares(self.w + f.Gb @ self.beta)
        if f.nq:
            hand = f.T @ self.beta
            if na:
                hand = hand - f.Rf @ self.fh
            if f.ncp:
                hand = hand - f.Cl @ self.lam
            cons.append(hand == 0)
        if f.ncp:
            cons.append(f.Cq @ self.qh == 0)
        gap = cn - self.p + xterm
        if f.nq:
            gap = gap - f.Kq @ self.qh
        cons += [gap >= 0, gap <= self.M * (1 - self.y), cn <= self.M * self.y]
        self.cn_expr, self.gap_expr = cn, gap
        if na:
            u = f.Ru @ self.qh
            over = self.fh - self.fc
            self.u_expr, self.over_expr = u, over
            if len(nbd):
                cons += [
                    u[nbd] >= 0,
                    u[nbd] <= self.M * self.zb,
                    over[nbd] >= 0,
                    over[nbd] <= self.M * (1 - self.zb),
                ]
            bdr = np.flatnonzero(f.bdr)
            if len(bdr):
                cons.append(over[bdr] == 0)
            lck = np.flatnonzero(f.lck)
            if len(lck):
                cons.append(u[lck] == 0)
        self.problem = cp.Problem(cp.Minimize(objective), cons)
        self.compile_time = 0.0
        self.n_solves = 0

    def _solver_kwargs(self) -> dict[str, Any]:
        opts = dict(self.options)
        if self.solver == "SCIP":
            params = dict(SCIP_DEFAULTS)
            params["limits/time"] = self.time_limit
            params.update(opts.pop("scip_params", {}))
            opts["scip_params"] = params
        elif self.solver == "GUROBI":
            opts.setdefault("TimeLimit", self.time_limit)
            opts.setdefault("IntFeasTol", 1e-9)
            opts.setdefault("FeasibilityTol", 1e-9)
            opts.setdefault("OutputFlag", 0)
        return opts

    def solve(self, data: ScaledData, M: float) -> RawSolution:
        """Solve with the given scaled data and big-M constant."""
        f = self.form
        self.w.value = data.w
        if self.fc is not None:
            self.fc.value = data.fc
        self.p.value = data.p
        self.M.value = float(M)
        if self.kind == "move":
            self.kx0.value = f.Kx @ data.x0
            self.kxd.value = f.Kx @ data.direction
        t0 = time.perf_counter()
        try:
            self.problem.solve(solver=self.solver, **self._solver_kwargs())
        except cp.error.SolverError as exc:
            # cvxpy raises when the backend stops without a solution, e.g. at its time limit
            dt = time.perf_counter() - t0
            status = TIMEOUT if dt >= 0.99 * self.time_limit else FAILED
            return RawSolution(status=status, solve_time=dt, backend=self.solver.lower(), message=str(exc))
        except Exception as exc:  # backend crashed (licence, memory, ...)
            raise SolverError(
                f"{self.solver} raised {type(exc).__name__}: {exc}", solver=self.solver.lower()
            ) from exc
        dt = time.perf_counter() - t0
        self.n_solves += 1
        st = self.problem.status
        raw_status = ""
        stats = self.problem.solver_stats
        if stats is not None and stats.extra_stats is not None and hasattr(stats.extra_stats, "getStatus"):
            raw_status = str(stats.extra_stats.getStatus())
        if st in (cp.INFEASIBLE, cp.settings.INFEASIBLE_OR_UNBOUNDED):
            return RawSolution(
                status=INFEASIBLE, solve_time=dt, backend=self.solver.lower(), message=raw_status
            )
        if st == cp.OPTIMAL_INACCURATE and raw_status in ("timelimit", "") and self.beta.value is not None:
            # cvxpy maps SCIP's time limit to OPTIMAL_INACCURATE: a time-out, not an answer
            if raw_status == "timelimit":
                return RawSolution(
                    status=TIMEOUT, solve_time=dt, backend=self.solver.lower(), message=raw_status
                )
        if st not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or self.beta.value is None:
            status = TIMEOUT if raw_status == "timelimit" else FAILED
            return RawSolution(
                status=status, solve_time=dt, backend=self.solver.lower(), message=f"{st} {raw_status}"
            )
        lay = f.layout(self.kind)
        z = np.zeros(lay["n"].stop)
        z[lay["beta"]] = self.beta.value
        z[lay["obj"]] = self.obj.value
        if f.nq:
            z[lay["qh"]] = self.qh.value
        if f.na:
            z[lay["fh"]] = self.fh.value
        if f.ncp:
            z[lay["lam"]] = self.lam.value
        touching = tuple(bool(v > 0.5) for v in self.y.value)
        moving = np.zeros(f.na, bool)
        if self.zb is not None:
            moving[self.nbd_idx] = self.zb.value > 0.5
        # largest big-M-bounded quantity relative to M
        vals = [np.abs(self.cn_expr.value), np.abs(self.gap_expr.value)]
        if f.na:
            vals += [np.abs(self.u_expr.value[self.nbd_idx]), np.abs(self.over_expr.value[self.nbd_idx])]
        ratio = max(float(np.max(v, initial=0.0)) for v in vals) / M
        return RawSolution(
            status=OPTIMAL,
            z=z,
            mode=Mode(touching, tuple(bool(v) for v in moving)),
            objective=float(self.problem.value),
            solve_time=dt,
            backend=self.solver.lower(),
            bigm_ratio=ratio,
            message=raw_status,
        )
