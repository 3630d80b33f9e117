"""Reference backend: the passive-response problem as a mixed-integer QP through cvxpy.

The problem is read from the one :class:`~pinograsp.solvers.problem.Problem` description that
every backend shares: one binary per complementarity pair (``y = 1``: the pair's side 1 — a
contact's spring gap, an actuator's over-force — is held at its bound, i.e. the contact touches
or the actuator moves), as in the seed paper. pinograsp's own exact solver
(:mod:`pinograsp.solvers.bnb`) is the default; this backend (SCIP, or Gurobi when installed)
cross-checks it.

**Big-M from the problem's own scale.** Every big-M-bounded quantity is in scaled force units,
so one constant ``M`` (a cvxpy ``Parameter``) fits the *forces* (normal forces, actuator
over-forces). The *displacement-like* quantities — the spring gap of a separated contact and
the displacement of an actuator — are measured in the stiffness of their own contact or joint,
while the motion that makes them large is set by the **softest** spring: a separated contact
of stiffness ``k_i`` has a gap of order ``(k_i / k_min) F``. Their rows get
``M · k_i / k_min`` (gap) and ``M · max_j kq_j / k_min`` (actuator displacement, over the joints
it drives) instead of ``M``. With uniform stiffness every factor is 1. Without these factors a
stiffness ratio of 1e4 between the two contacts of a pinch made every solution of a resistible
load exceed ``M`` and the MIQP answered "infeasible" (docs/stability.md).

**Infeasibility is verified.** An ``M`` that is too small cuts off solutions and turns a
feasible problem into an "infeasible" one — a silently wrong "not resisted". When the MIQP is
infeasible, it is re-solved once with ``M × VERIFY_FACTOR`` (``verify_infeasible=True``, the
default); a solution found then is returned (the caller's big-M audit sees its ratio), and a
second "infeasible" is reported with the ``M`` that was verified in ``RawSolution.message``.

**Indicator constraints** (``complementarity="indicator"``, SCIP only): the complementarity is
modelled with SCIP indicator constraints on a PySCIPOpt model built for each solve — no ``M``
at all, exact for any stiffness (1.5–4× slower, docs/solvers.md). ``M`` is then ignored and
``bigm_ratio`` is 0.

**Empty rows.** cvxpy's SCIP interface silently drops a constraint row without any variable
(``0 = b``): an equilibrium row that no contact can produce (a ``mu = 0`` pinch under a
tangential load, a torque about the line through every contact) would be ignored and the solver
would answer "optimal" for a load nothing resists. Such rows are checked before solving
(:meth:`~pinograsp.solvers.problem.Problem.empty_rows`).

**Time limits** are the one wall-clock element of pinograsp and exist only in this reference
backend: a solve stopped by its time limit is reported as ``timeout``, never retried with other
settings (a retry would make the answer depend on the machine's speed).

A point returned by the verifying solve is accepted only if some bounded quantity really
exceeds ``GENUINE × M``: a point that fits inside the first bound would have been found by the
first solve, so it can only come from the integrality tolerance times the larger ``M`` (leaky
complementarity — seen on a rotated 3D pinch 0.1 % above its limit) and the verdict stays
"infeasible".

**Quiet.** With ``quiet=True`` (default) a solve runs inside
:func:`~pinograsp.solvers.quiet.quiet_stdout`, which drops SCIP's "without GMP" line.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.settings import COMPLEMENTARITIES, MIQP_SOLVERS, Complementarity
from ..errors import InvalidInputError, SolverError, SolverNotAvailableError
from .base import FAILED, INFEASIBLE, OPTIMAL, TIMEOUT, Mode, RawSolution
from .formulation import Formulation, ScaledData
from .problem import INF, Problem, ProblemKind, build_problem
from .quiet import quiet_stdout

if TYPE_CHECKING:
    import cvxpy


class _Cvxpy:
    """cvxpy, imported on first use (1–1.5 s): ``import pinograsp``, the scene listing and the
    default branch-and-bound never need it."""

    def __getattr__(self, name: str) -> Any:
        import cvxpy

        return getattr(cvxpy, name)


cp = _Cvxpy()


#: SCIP settings measured to be 4-12x faster on these problems with identical answers
#: (docs/solvers.md): the aggregation cut separator and the MPEC heuristic dominate otherwise.
SCIP_DEFAULTS: dict[str, Any] = {
    "heuristics/mpec/freq": -1,
    "separating/aggregation/freq": -1,
    "numerics/feastol": 1e-8,
}

#: Extra SCIP settings of the indicator model: with strong dual reductions SCIP 10 declared
#: feasible indicator models "infeasible" (a pinch movement step whose feasible point it accepts
#: once the binaries are fixed); without them every answer matched the big-M model.
INDICATOR_PARAMS: dict[str, Any] = {"misc/allowstrongdualreds": False}
#: An "infeasible" MIQP is re-solved with M multiplied by this before it is trusted.
VERIFY_FACTOR = 100.0
#: A solution of the verifying solve counts only if some bounded quantity exceeds this fraction
#: of the first M (otherwise the first solve would have found it: an integrality artefact).
GENUINE = 0.5


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


def _second_attempt(first: RawSolution, again: RawSolution, note: str) -> RawSolution:
    """``again`` as the answer of a solve that needed a second attempt: both attempts' time, and
    ``note`` (why) before its message."""
    return replace(
        again, solve_time=first.solve_time + again.solve_time, message=f"{note}; {again.message}".strip("; ")
    )


def _backend_status(problem: cvxpy.Problem) -> str:
    """The backend's own status string after a cvxpy solve (``""`` when not exposed).

    cvxpy 1.9 keeps SCIP's result as a dict in ``solver_stats.extra_stats`` (``scip_status``);
    older versions stored the PySCIPOpt model itself.
    """
    stats = problem.solver_stats
    extra = getattr(stats, "extra_stats", None) if stats is not None else None
    if isinstance(extra, dict):
        if "scip_status" in extra:
            return str(extra["scip_status"])
        status = getattr(extra.get("model"), "getStatus", None)
        return str(status()) if status is not None else ""
    status = getattr(extra, "getStatus", None)
    return str(status()) if status is not None else ""


def _mode(problem: Problem, y: np.ndarray) -> Mode:
    return problem.mode_of((np.asarray(y) > 0.5).astype(np.int8))


def bigm_ratio(problem: Problem, z: np.ndarray, M: float) -> float:
    """Largest big-M-bounded pair side at ``z`` as a fraction of its own bound ``M * factor``."""
    if not len(problem.pairs):
        return 0.0
    v = problem.C @ z - problem.lo
    sides = np.abs(v[problem.pairs]) / (M * problem.bigm_factor)
    return float(sides.max())


class CvxpyMIQP:
    """The MIQP of one problem kind of one model, read from :class:`Problem` at every solve.

    Args:
        form: Scaled formulation.
        kind: ``"prp"`` (Alg. 1), ``"move"`` (Alg. 2, movement-constrained) or ``"load"``
            (Alg. 1's largest load factor along a direction).
        solver: cvxpy solver name (``"scip"``, ``"gurobi"``, ...).
        gamma: Step bound of Alg. 2 (scaled).
        time_limit: Per-solve time limit [s]; hitting it gives status ``timeout``.
        options: Extra solver options passed to cvxpy (for SCIP: ``scip_params``). The keys
            ``"complementarity"``, ``"verify_infeasible"`` and ``"quiet"`` are taken out and
            used as the keyword arguments below.
        complementarity: ``"bigm"`` (default) or ``"indicator"`` (SCIP indicator constraints,
            no big-M; needs ``solver="scip"``).
        verify_infeasible: Re-solve an infeasible big-M MIQP once with ``M × VERIFY_FACTOR``
            before reporting infeasibility.
        quiet: Drop SCIP's "without GMP" line (see the module docstring).
    """

    def __init__(
        self,
        form: Formulation,
        kind: str,
        solver: str = "scip",
        gamma: float = 1.0,
        time_limit: float = 60.0,
        options: dict[str, Any] | None = None,
        *,
        complementarity: str = "bigm",
        verify_infeasible: bool = True,
        quiet: bool = True,
    ) -> None:
        try:
            self.kind = ProblemKind(kind)
        except ValueError:
            valid = [k.value for k in ProblemKind]
            raise InvalidInputError("kind", f"must be one of {valid}, got {kind!r}") from None
        self.form = form
        self.solver = resolve_solver(solver)
        self.gamma = float(gamma)
        self.time_limit = float(time_limit)
        opts = dict(options or {})
        complementarity = str(opts.pop("complementarity", complementarity))
        self.verify_infeasible = bool(opts.pop("verify_infeasible", verify_infeasible))
        self.quiet = bool(opts.pop("quiet", quiet))
        self.options = opts
        if complementarity not in COMPLEMENTARITIES:
            raise InvalidInputError(
                "complementarity", f"must be one of {COMPLEMENTARITIES}, got {complementarity!r}"
            )
        if complementarity == Complementarity.INDICATOR and self.solver != "SCIP":
            raise InvalidInputError(
                "complementarity",
                f"indicator constraints are implemented for solver 'scip' only, not {solver!r}",
            )
        self.complementarity = Complementarity(complementarity)

    def problem(self, data: ScaledData, t_max: float = 1.0) -> Problem:
        """The shared problem description of one solve."""
        return build_problem(self.form, self.kind, data, self.gamma, t_max)

    # ------------------------------------------------------------------ options
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

    # ------------------------------------------------------------------ solving
    def solve(self, data: ScaledData, M: float, t_max: float = 1.0) -> RawSolution:
        """Solve with the given scaled data and big-M constant (ignored with indicators).

        An infeasible big-M solve is re-solved once with ``M × VERIFY_FACTOR`` when
        ``verify_infeasible`` is set (see the module docstring). ``t_max`` is the load-factor
        limit of kind ``"load"``.
        """
        return self.solve_problem(self.problem(data, t_max), M)

    def solve_problem(self, P: Problem, M: float) -> RawSolution:
        """Solve the built problem ``P`` with the big-M constant ``M`` (see :meth:`solve`)."""
        backend = self.solver.lower()
        bad = P.empty_rows()
        if bad:
            return RawSolution(
                status=INFEASIBLE,
                backend=backend,
                message=f"no contact force can produce the wrench component(s) {', '.join(bad)}",
            )
        if self.complementarity is Complementarity.INDICATOR:
            return self._solve_indicator(P)
        sol = self._solve_bigm(P, float(M))
        if sol.status == INFEASIBLE and self.verify_infeasible:
            M2 = float(M) * VERIFY_FACTOR
            again = self._solve_bigm(P, M2)
            total = sol.solve_time + again.solve_time
            if again.status == INFEASIBLE:
                return RawSolution(
                    status=INFEASIBLE,
                    solve_time=total,
                    backend=backend,
                    message=f"infeasible with M = {M:.3g} and verified with M = {M2:.3g}",
                )
            if again.status == OPTIMAL and again.bigm_ratio * VERIFY_FACTOR < GENUINE:
                # every bounded quantity fits in the first M, so the first solve would have
                # found this point were it feasible: it lives on the integrality tolerance
                # times the larger M (leaky complementarity), not beyond M
                return RawSolution(
                    status=INFEASIBLE,
                    solve_time=total,
                    backend=backend,
                    message=(
                        f"infeasible with M = {M:.3g}; the solve with M = {M2:.3g} found only a point "
                        f"within the first bound ({again.bigm_ratio * VERIFY_FACTOR:.2g} M): "
                        "an integrality artefact"
                    ),
                )
            return _second_attempt(sol, again, f"infeasible with M = {M:.3g}, solved with M = {M2:.3g}")
        return sol

    def _solve_bigm(self, P: Problem, M: float) -> RawSolution:
        """One big-M solve of ``P``."""
        backend = self.solver.lower()
        z = cp.Variable(P.n)
        y = cp.Variable(len(P.pairs), boolean=True)
        cons = []
        if P.A.shape[0]:
            cons.append(P.A @ z == P.b)
        Cz = P.C @ z
        lo_rows = np.flatnonzero(P.lo > -INF)
        up_rows = np.flatnonzero(P.up < INF)
        cons += [Cz[lo_rows] >= P.lo[lo_rows], Cz[up_rows] <= P.up[up_rows]]
        if len(P.pairs):
            s0 = P.C[P.pairs[:, 0]] @ z - P.lo[P.pairs[:, 0]]
            s1 = P.C[P.pairs[:, 1]] @ z - P.lo[P.pairs[:, 1]]
            cons += [
                s0 <= cp.multiply(M * P.bigm_factor[:, 0], y),
                s1 <= cp.multiply(M * P.bigm_factor[:, 1], 1 - y),
            ]
        prob = cp.Problem(cp.Minimize(cp.sum_squares(P.L @ z + P.l)), cons)
        t0 = time.perf_counter()
        try:
            with quiet_stdout(self.quiet), warnings.catch_warnings():
                # cvxpy warns "Solution may be inaccurate" on SCIP's time/gap limits: the
                # status is read and reported below instead
                warnings.filterwarnings("ignore", message="Solution may be inaccurate")
                prob.solve(solver=self.solver, **self._solver_kwargs())
        except cp.error.SolverError as exc:
            # cvxpy raises when the backend stops without a solution, e.g. at its time limit
            dt = time.perf_counter() - t0
            status = TIMEOUT if dt >= 0.99 * self.time_limit else FAILED
            return RawSolution(status=status, solve_time=dt, backend=backend, message=str(exc))
        except Exception as exc:  # backend crashed (licence, memory, ...)
            raise SolverError(f"{self.solver} raised {type(exc).__name__}: {exc}", solver=backend) from exc
        dt = time.perf_counter() - t0
        st = prob.status
        raw_status = _backend_status(prob)
        if st in (cp.INFEASIBLE, cp.settings.INFEASIBLE_OR_UNBOUNDED):
            return RawSolution(status=INFEASIBLE, solve_time=dt, backend=backend, message=raw_status)
        if raw_status == "timelimit" or (st == cp.OPTIMAL_INACCURATE and dt >= 0.99 * self.time_limit):
            # cvxpy maps SCIP's time limit to OPTIMAL_INACCURATE: a time-out, not an answer
            return RawSolution(status=TIMEOUT, solve_time=dt, backend=backend, message=raw_status or str(st))
        if st == cp.OPTIMAL_INACCURATE and raw_status not in ("", "optimal"):
            # gap/node limits and the like: the point is not proven optimal
            return RawSolution(status=FAILED, solve_time=dt, backend=backend, message=f"{st} {raw_status}")
        if st not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or z.value is None:
            return RawSolution(status=FAILED, solve_time=dt, backend=backend, message=f"{st} {raw_status}")
        zv = np.asarray(z.value, float)
        yv = np.asarray(y.value, float) if len(P.pairs) else np.zeros(0)
        return RawSolution(
            status=OPTIMAL,
            z=zv,
            mode=_mode(P, yv),
            objective=P.objective(zv),
            solve_time=dt,
            backend=backend,
            bigm_ratio=bigm_ratio(P, zv, M),
            message=raw_status,
            layout=P.layout,
        )

    # ---------------------------------------------------------- indicator constraints
    def _solve_indicator(self, P: Problem) -> RawSolution:
        """Solve with SCIP indicator constraints (no big-M): a PySCIPOpt model per solve."""
        from pyscipopt import Model, quicksum

        t0 = time.perf_counter()
        mdl = Model()
        mdl.hideOutput(True)
        inf = mdl.infinity()
        z = [mdl.addVar(lb=-inf, ub=inf, name=f"z{i}") for i in range(P.n)]

        def lin(coef: np.ndarray) -> Any:
            return quicksum(float(coef[j]) * z[j] for j in np.flatnonzero(coef))

        for r in range(P.A.shape[0]):
            mdl.addCons(lin(P.A[r]) == float(P.b[r]))
        rows = [lin(P.C[r]) for r in range(P.C.shape[0])]
        for r, e in enumerate(rows):
            if P.lo[r] > -INF:
                mdl.addCons(e >= float(P.lo[r]))
            if P.up[r] < INF:
                mdl.addCons(e <= float(P.up[r]))
        # objective: t >= |L z + l|^2
        t = mdl.addVar(lb=0.0, ub=inf, name="t")
        aux = []
        for k in range(P.L.shape[0]):
            a = mdl.addVar(lb=-inf, ub=inf, name=f"e{k}")
            mdl.addCons(a == lin(P.L[k]) + float(P.l[k]))
            aux.append(a)
        mdl.addCons(quicksum(a * a for a in aux) <= t)
        mdl.setObjective(t, "minimize")
        ys = []
        for k, (i, j) in enumerate(P.pairs):
            y = mdl.addVar(vtype="B", name=f"y{k}")
            ys.append(y)
            mdl.addConsIndicator(rows[j] <= float(P.lo[j]), binvar=y, activeone=True)
            mdl.addConsIndicator(rows[i] <= float(P.lo[i]), binvar=y, activeone=False)
        params = dict(SCIP_DEFAULTS)
        params.update(INDICATOR_PARAMS)
        params["limits/time"] = self.time_limit
        params.update(self.options.get("scip_params", {}))
        mdl.setParams(params)
        try:
            with quiet_stdout(self.quiet):
                mdl.optimize()
        except Exception as exc:  # pragma: no cover - backend crash
            raise SolverError(f"SCIP raised {type(exc).__name__}: {exc}", solver="scip") from exc
        dt = time.perf_counter() - t0
        status = str(mdl.getStatus())
        backend = "scip-indicator"
        if status in ("infeasible", "inforunbd"):
            return RawSolution(status=INFEASIBLE, solve_time=dt, backend=backend, message=status)
        if status == "timelimit":
            return RawSolution(status=TIMEOUT, solve_time=dt, backend=backend, message=status)
        if status != "optimal" or mdl.getNSols() == 0:
            return RawSolution(status=FAILED, solve_time=dt, backend=backend, message=status)
        sol = mdl.getBestSol()
        if sol is None:
            return RawSolution(status=FAILED, solve_time=dt, backend=backend, message="no solution stored")
        zv = np.array([sol[v] for v in z])
        yv = np.array([sol[y] for y in ys])
        return RawSolution(
            status=OPTIMAL,
            z=zv,
            mode=_mode(P, yv),
            objective=P.objective(zv),
            solve_time=dt,
            backend=backend,
            bigm_ratio=0.0,
            message=status,
            layout=P.layout,
        )
