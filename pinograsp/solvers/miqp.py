"""Mixed-integer QP backend (cvxpy): the passive-response problem with big-M complementarity.

One binary per contact (``y = 1``: touching) and per non-backdrivable actuator (``z = 1``:
moving), as in the seed paper, over the scaled variables of
:mod:`pinograsp.solvers.formulation`. The problem is built once per model and kind and
re-solved with new parameter values (cvxpy DPP caching).

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
at all, exact for any stiffness (1.5–4× slower, SOLVER_NOTES). ``M`` is then ignored and
``bigm_ratio`` is 0.

**Empty rows.** cvxpy's SCIP interface silently drops a constraint row without any variable
(``0 = b``): an equilibrium row that no contact can produce (a ``mu = 0`` pinch under a
tangential load, a torque about the line through every contact) would be ignored and the solver
would answer "optimal" for a load nothing resists. Such rows are checked here before solving.

A point returned by the verifying solve is accepted only if some bounded quantity really
exceeds ``GENUINE × M``: a point that fits inside the first bound would have been found by the
first solve, so it can only come from the integrality tolerance times the larger ``M`` (leaky
complementarity — seen on a rotated 3D pinch 0.1 % above its limit) and the verdict stays
"infeasible".

**Quiet.** SCIP's LP solver prints ``Cannot set feasibility tolerance to small value ...
without GMP`` straight to the process's stderr when it tightens its tolerance on hard
problems. With ``quiet=True`` (default) the solve runs with file descriptors 1 and 2
redirected; that line is dropped and any other output is forwarded to ``sys.stdout`` /
``sys.stderr``.
"""

from __future__ import annotations

import os
import sys
import tempfile
import threading
import time
import warnings
from contextlib import contextmanager
from dataclasses import replace
from typing import Any

import cvxpy as cp
import numpy as np

from ..errors import InvalidInputError, SolverError, SolverNotAvailableError
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

#: Share of ``time_limit`` given to the first SCIP attempt of a big-M solve.
SCIP_FIRST_TRY = 0.1

#: SCIP settings of the second attempt after a time-out. With ``feastol = 1e-8`` SCIP's
#: spatial branching on the quadratic objective occasionally stalls on movement steps whose
#: load is far beyond the limit (seed case 3, torque about X: > 60 s, where SCIP's default
#: 1e-6 solves in 0.1 s). The point is polished by the exact fixed-mode QP afterwards, so the
#: looser tolerance changes only which mode is found, never the accuracy of the forces.
SCIP_RETRY: dict[str, Any] = {"numerics/feastol": 1e-6, "randomization/randomseedshift": 1}

#: Extra SCIP settings of the indicator model: with strong dual reductions SCIP 10 declared
#: feasible indicator models "infeasible" (a pinch movement step whose feasible point it accepts
#: once the binaries are fixed); without them every answer matched the big-M model.
INDICATOR_PARAMS: dict[str, Any] = {"misc/allowstrongdualreds": False}
#: Ways to model the complementarity constraints.
COMPLEMENTARITY = ("bigm", "indicator")
#: An "infeasible" MIQP is re-solved with M multiplied by this before it is trusted.
VERIFY_FACTOR = 100.0
#: A solution of the verifying solve counts only if some bounded quantity exceeds this fraction
#: of the first M (otherwise the first solve would have found it: an integrality artefact).
GENUINE = 0.5
#: A wrench component that no contact can produce makes the equilibrium infeasible when its
#: scaled magnitude exceeds this (the same tolerance as the equilibrium audit).
EMPTY_ROW_TOL = 1e-9
#: Lines of backend output that carry no information for pinograsp users (dropped when quiet).
NOISE = ("without GMP - using",)


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


_FD_LOCK = threading.Lock()


@contextmanager
def quiet_stdout(enabled: bool = True):
    """Redirect file descriptors 1 and 2 around a backend call; drop :data:`NOISE` lines and
    forward the rest to ``sys.stdout`` / ``sys.stderr``.

    Solver libraries write to the C-level streams (SoPlex's "without GMP" line goes to stderr),
    which ``contextlib.redirect_stdout`` cannot catch. A lock makes concurrent threads take turns
    (the redirection is process-wide).
    """
    if not enabled:
        yield
        return
    streams = ((1, sys.stdout), (2, sys.stderr))
    with _FD_LOCK:
        for _, stream in streams:
            try:
                stream.flush()
            except Exception:  # pragma: no cover - a closed or exotic stream
                pass
        saved: list[tuple[int, int, object, object]] = []
        try:
            for fd, stream in streams:
                try:
                    keep = os.dup(fd)
                except OSError:  # pragma: no cover - no such descriptor (embedded interpreters)
                    continue
                tmp = tempfile.TemporaryFile(mode="w+b")
                os.dup2(tmp.fileno(), fd)
                saved.append((fd, keep, tmp, stream))
            yield
        finally:
            texts = []
            for fd, keep, tmp, stream in saved:
                try:
                    stream.flush()  # type: ignore[attr-defined]
                except Exception:  # pragma: no cover
                    pass
                os.dup2(keep, fd)
                os.close(keep)
                tmp.seek(0)  # type: ignore[attr-defined]
                texts.append((tmp.read().decode(errors="replace"), stream))  # type: ignore[attr-defined]
                tmp.close()  # type: ignore[attr-defined]
            for text, stream in texts:
                kept = [ln for ln in text.splitlines(keepends=True) if not any(n in ln for n in NOISE)]
                if kept:
                    stream.write("".join(kept))  # type: ignore[attr-defined]


#: The same context manager under a name that says what it covers.
quiet_output = quiet_stdout


def _bigm_factors(form: Formulation) -> tuple[np.ndarray, np.ndarray]:
    """Per-row big-M factors (>= 1) of the spring gaps (nc,) and actuator displacements (na,)."""
    m = form.model
    kmin = float(m.k.min())
    gap = np.maximum(m.k / kmin, 1.0)
    if form.na:
        reach = np.abs(m.R) > 0  # (nq, na)
        u = np.array([max(float(form.kq[reach[:, a]].max(initial=kmin)) / kmin, 1.0) for a in range(form.na)])
    else:
        u = np.zeros(0)
    return gap, u


def _second_attempt(first: RawSolution, again: RawSolution, note: str) -> RawSolution:
    """``again`` as the answer of a solve that needed a second attempt: both attempts' time, and
    ``note`` (why) before its message."""
    return replace(
        again, solve_time=first.solve_time + again.solve_time, message=f"{note}; {again.message}".strip("; ")
    )


def _backend_status(problem: cp.Problem) -> str:
    """The backend's own status string after a cvxpy solve (``""`` when not exposed).

    cvxpy 1.9 keeps SCIP's result as a dict in ``solver_stats.extra_stats`` (``scip_status``);
    older versions stored the PySCIPOpt model itself.
    """
    stats = problem.solver_stats
    extra = getattr(stats, "extra_stats", None) if stats is not None else None
    if isinstance(extra, dict):
        if "scip_status" in extra:
            return str(extra["scip_status"])
        model = extra.get("model")
        return str(model.getStatus()) if hasattr(model, "getStatus") else ""
    if hasattr(extra, "getStatus"):
        return str(extra.getStatus())
    return ""


class CvxpyMIQP:
    """The MIQP of one problem kind, built once and re-solved with new data.

    Args:
        form: Scaled formulation of the model.
        kind: ``"prp"`` (Alg. 1) or ``"move"`` (Alg. 2, movement-constrained).
        solver: cvxpy solver name (``"scip"``, ``"gurobi"``, ...).
        gamma: Step bound of Alg. 2 (scaled, see :class:`~.fixed_mode.FixedModeQP`).
        time_limit: Per-solve time limit [s].
        options: Extra solver options passed to cvxpy (for SCIP: ``scip_params``). The keys
            ``"complementarity"``, ``"verify_infeasible"`` and ``"quiet"`` are taken out and
            used as the keyword arguments below (so callers that only forward ``options`` can
            set them).
        complementarity: ``"bigm"`` (default) or ``"indicator"`` (SCIP indicator constraints,
            no big-M; needs ``solver="scip"``).
        verify_infeasible: Re-solve an infeasible big-M MIQP once with ``M × VERIFY_FACTOR``
            before reporting infeasibility.
        quiet: Drop SCIP's "without GMP" line (see the module docstring).
        rel_gap: Relative optimality gap at which the backend may stop (SCIP ``limits/gap``,
            Gurobi ``MIPGap``); 0 (default) asks for a proven optimum. A solve stopped by this
            gap is returned as optimal with ``message="gaplimit"``: its objective is then within
            a factor ``1 + rel_gap`` of the optimum (used to certify stalls, where only a 1 %
            improvement matters).
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
        rel_gap: float = 0.0,
    ) -> None:
        if kind not in ("prp", "move"):
            raise InvalidInputError("kind", f"must be 'prp' or 'move', got {kind!r}")
        self.form, self.kind = form, kind
        self.solver = resolve_solver(solver)
        self.gamma = float(gamma)
        self.time_limit = float(time_limit)
        opts = dict(options or {})
        complementarity = str(opts.pop("complementarity", complementarity))
        self.verify_infeasible = bool(opts.pop("verify_infeasible", verify_infeasible))
        self.quiet = bool(opts.pop("quiet", quiet))
        self.rel_gap = float(opts.pop("rel_gap", rel_gap))
        if not (0.0 <= self.rel_gap < 1.0):
            raise InvalidInputError("rel_gap", f"must be in [0, 1), got {self.rel_gap!r}")
        self.options = opts
        if complementarity not in COMPLEMENTARITY:
            raise InvalidInputError(
                "complementarity", f"must be one of {COMPLEMENTARITY}, got {complementarity!r}"
            )
        if complementarity == "indicator" and self.solver != "SCIP":
            raise InvalidInputError(
                "complementarity",
                f"indicator constraints are implemented for solver 'scip' only, not {solver!r}",
            )
        self.complementarity = complementarity
        f = form
        nc, na = f.nc, f.na
        nbd = np.flatnonzero(f.nbd)
        self.nbd_idx = nbd
        self.m_gap, self.m_u = _bigm_factors(f)
        #: equilibrium rows no contact force can produce (prp only; see module docstring)
        self.empty_rows = (
            np.flatnonzero(~np.any(np.abs(f.Gb) > 0, axis=1)) if kind == "prp" else np.zeros(0, int)
        )
        self.compile_time = 0.0
        self.n_solves = 0
        self.n_retries = 0  # SCIP time-outs re-run with SCIP_RETRY
        self.last_M = float("nan")
        if complementarity == "indicator":
            self.problem = None
            return
        self.beta = cp.Variable(f.nb, nonneg=True)
        self.qh = cp.Variable(f.nq)
        self.fh = cp.Variable(na)
        self.lam = cp.Variable(f.ncp)
        self.y = cp.Variable(nc, boolean=True)
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
        cons += [gap >= 0, gap <= cp.multiply(self.m_gap, self.M * (1 - self.y)), cn <= self.M * self.y]
        self.cn_expr, self.gap_expr = cn, gap
        if na:
            u = f.Ru @ self.qh
            over = self.fh - self.fc
            self.u_expr, self.over_expr = u, over
            if len(nbd):
                cons += [
                    u[nbd] >= 0,
                    u[nbd] <= cp.multiply(self.m_u[nbd], self.M * self.zb),
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

    # ------------------------------------------------------------------ options
    def _solver_kwargs(self, time_limit: float | None = None, retry: bool = False) -> dict[str, Any]:
        opts = dict(self.options)
        time_limit = self.time_limit if time_limit is None else float(time_limit)
        if self.solver == "SCIP":
            params = dict(SCIP_DEFAULTS)
            if retry:
                params.update(SCIP_RETRY)
            params["limits/time"] = time_limit
            if self.rel_gap > 0:
                params["limits/gap"] = self.rel_gap
            params.update(opts.pop("scip_params", {}))
            opts["scip_params"] = params
        elif self.solver == "GUROBI":
            opts.setdefault("TimeLimit", time_limit)
            if self.rel_gap > 0:
                opts.setdefault("MIPGap", self.rel_gap)
            opts.setdefault("IntFeasTol", 1e-9)
            opts.setdefault("FeasibilityTol", 1e-9)
            opts.setdefault("OutputFlag", 0)
        return opts

    # ------------------------------------------------------------------ solving
    def solve(self, data: ScaledData, M: float) -> RawSolution:
        """Solve with the given scaled data and big-M constant (ignored with indicators).

        An infeasible big-M solve is re-solved once with ``M × VERIFY_FACTOR`` when
        ``verify_infeasible`` is set (see the module docstring).
        """
        backend = self.solver.lower()
        if len(self.empty_rows):
            bad = self.empty_rows[np.abs(data.w[self.empty_rows]) > EMPTY_ROW_TOL]
            if len(bad):
                self.n_solves += 1
                names = ", ".join(self._row_name(int(r)) for r in bad)
                return RawSolution(
                    status=INFEASIBLE,
                    backend=backend,
                    message=f"no contact force can produce the wrench component(s) {names}",
                )
        if self.complementarity == "indicator":
            return self._solve_indicator(data)
        sol = self._solve_bigm(data, float(M))
        if sol.status == INFEASIBLE and self.verify_infeasible:
            M2 = float(M) * VERIFY_FACTOR
            again = self._solve_bigm(data, M2)
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

    def _row_name(self, r: int) -> str:
        names = ("fx", "fy", "mz") if self.form.model.planar else ("fx", "fy", "fz", "mx", "my", "mz")
        return names[r]

    def _solve_bigm(self, data: ScaledData, M: float) -> RawSolution:
        """One big-M solve. SCIP gets :data:`SCIP_FIRST_TRY` of the time limit with the tight
        default tolerances; on a time-out it is re-run for the rest of the limit with
        :data:`SCIP_RETRY` (see there). The solution is polished by the caller either way."""
        if self.solver != "SCIP" or "numerics/feastol" in self.options.get("scip_params", {}):
            return self._solve_bigm_once(data, M, self.time_limit, False)
        first = self._solve_bigm_once(data, M, SCIP_FIRST_TRY * self.time_limit, False)
        if first.status != TIMEOUT:
            return first
        again = self._solve_bigm_once(data, M, (1.0 - SCIP_FIRST_TRY) * self.time_limit, True)
        self.n_retries += 1
        note = f"timed out after {first.solve_time:.3g} s with feastol 1e-8; re-run with {SCIP_RETRY}"
        return _second_attempt(first, again, note)

    def _solve_bigm_once(self, data: ScaledData, M: float, time_limit: float, retry: bool) -> RawSolution:
        f = self.form
        backend = self.solver.lower()
        self.w.value = data.w
        if self.fc is not None:
            self.fc.value = data.fc
        self.p.value = data.p
        self.M.value = float(M)
        self.last_M = float(M)
        if self.kind == "move":
            self.kx0.value = f.Kx @ data.x0
            self.kxd.value = f.Kx @ data.direction
        t0 = time.perf_counter()
        try:
            with quiet_stdout(self.quiet), warnings.catch_warnings():
                # cvxpy warns "Solution may be inaccurate" on SCIP's time/gap limits: the
                # status is read and reported below instead
                warnings.filterwarnings("ignore", message="Solution may be inaccurate")
                self.problem.solve(solver=self.solver, **self._solver_kwargs(time_limit, retry))
        except cp.error.SolverError as exc:
            # cvxpy raises when the backend stops without a solution, e.g. at its time limit
            dt = time.perf_counter() - t0
            status = TIMEOUT if dt >= 0.99 * time_limit else FAILED
            return RawSolution(status=status, solve_time=dt, backend=backend, message=str(exc))
        except Exception as exc:  # backend crashed (licence, memory, ...)
            raise SolverError(f"{self.solver} raised {type(exc).__name__}: {exc}", solver=backend) from exc
        dt = time.perf_counter() - t0
        self.n_solves += 1
        st = self.problem.status
        raw_status = _backend_status(self.problem)
        if st in (cp.INFEASIBLE, cp.settings.INFEASIBLE_OR_UNBOUNDED):
            return RawSolution(status=INFEASIBLE, solve_time=dt, backend=backend, message=raw_status)
        if raw_status == "timelimit" or (st == cp.OPTIMAL_INACCURATE and dt >= 0.99 * time_limit):
            # cvxpy maps SCIP's time limit to OPTIMAL_INACCURATE: a time-out, not an answer
            return RawSolution(status=TIMEOUT, solve_time=dt, backend=backend, message=raw_status or str(st))
        gap_stop = raw_status == "gaplimit" and self.rel_gap > 0
        if st == cp.OPTIMAL_INACCURATE and raw_status not in ("", "optimal") and not gap_stop:
            # gap/node limits and the like: the point is not proven optimal
            return RawSolution(status=FAILED, solve_time=dt, backend=backend, message=f"{st} {raw_status}")
        if st not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or self.beta.value is None:
            return RawSolution(status=FAILED, solve_time=dt, backend=backend, message=f"{st} {raw_status}")
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
        # largest big-M-bounded quantity relative to its own bound
        ratios = [
            np.abs(self.cn_expr.value) / M,
            np.abs(self.gap_expr.value) / (M * self.m_gap),
        ]
        if f.na:
            nbd = self.nbd_idx
            ratios += [
                np.abs(self.u_expr.value[nbd]) / (M * self.m_u[nbd]),
                np.abs(self.over_expr.value[nbd]) / M,
            ]
        ratio = max(float(np.max(v, initial=0.0)) for v in ratios)
        return RawSolution(
            status=OPTIMAL,
            z=z,
            mode=Mode(touching, tuple(bool(v) for v in moving)),
            objective=float(self.problem.value),
            solve_time=dt,
            backend=backend,
            bigm_ratio=ratio,
            message=raw_status,
        )

    # ---------------------------------------------------------- indicator constraints
    def _solve_indicator(self, data: ScaledData) -> RawSolution:
        """Solve with SCIP indicator constraints (no big-M): a PySCIPOpt model per solve."""
        from pyscipopt import Model, quicksum

        f = self.form
        lay = f.layout(self.kind)
        n = lay["n"].stop
        t0 = time.perf_counter()
        mdl = Model()
        mdl.hideOutput(True)
        inf = mdl.infinity()
        z = []
        for i in range(n):
            lb = 0.0 if i < f.nb else -inf
            z.append(mdl.addVar(lb=lb, ub=inf, name=f"z{i}"))
        if self.kind == "move":
            mdl.chgVarLb(z[lay["obj"].start], 0.0)
            mdl.chgVarUb(z[lay["obj"].start], self.gamma)

        def lin(coef: np.ndarray, sl: slice) -> Any:
            idx = np.flatnonzero(coef)
            return quicksum(float(coef[j]) * z[sl.start + j] for j in idx)

        sb, so, sq, sf, sl = lay["beta"], lay["obj"], lay["qh"], lay["fh"], lay["lam"]
        # equality rows
        if self.kind == "prp":
            for r in range(f.nw):
                mdl.addCons(lin(f.Gb[r], sb) == -float(data.w[r]))
        for j in range(f.nq):
            expr = lin(f.T[j], sb) - lin(f.Rf[j], sf) - lin(f.Cl[j], sl)
            mdl.addCons(expr == 0.0)
        for r in range(f.ncp):
            mdl.addCons(lin(f.Cq[r], sq) == 0.0)
        # objective: t >= sum of squares
        t = mdl.addVar(lb=0.0, ub=inf, name="t")
        if self.kind == "prp":
            es = [lin(f.E[i], sb) for i in range(f.nc)]
        else:
            es = [lin(f.Gb[r], sb) + float(data.w[r]) for r in range(f.nw)]
        aux = []
        for k, e in enumerate(es):
            a = mdl.addVar(lb=-inf, ub=inf, name=f"e{k}")
            mdl.addCons(a == e)
            aux.append(a)
        mdl.addCons(quicksum(a * a for a in aux) <= t)
        mdl.setObjective(t, "minimize")
        # spring gaps and contact complementarity
        p = data.p
        kxt = f.Kx @ data.x0 if self.kind == "move" else None
        kxd = f.Kx @ data.direction if self.kind == "move" else None
        ys = []
        for i in range(f.nc):
            cn = lin(f.E[i], sb)
            gap = cn - float(p[i]) - lin(f.Kq[i], sq)
            if self.kind == "prp":
                gap = gap + lin(f.Kx[i], so)
            else:
                gap = gap + float(kxt[i]) + float(kxd[i]) * z[so.start]
            mdl.addCons(gap >= 0.0)
            y = mdl.addVar(vtype="B", name=f"y{i}")
            ys.append(y)
            mdl.addConsIndicator(gap <= 0.0, binvar=y, activeone=True)
            mdl.addConsIndicator(cn <= 0.0, binvar=y, activeone=False)
        zs = {}
        for a in range(f.na):
            u = lin(f.Ru[a], sq)
            over = z[sf.start + a] - float(data.fc[a])
            if f.nbd[a]:
                mdl.addCons(u >= 0.0)
                mdl.addCons(over >= 0.0)
                zb = mdl.addVar(vtype="B", name=f"m{a}")
                zs[a] = zb
                mdl.addConsIndicator(over <= 0.0, binvar=zb, activeone=True)
                mdl.addConsIndicator(u <= 0.0, binvar=zb, activeone=False)
            elif f.bdr[a]:
                mdl.addCons(over == 0.0)
            else:
                mdl.addCons(u == 0.0)
        params = dict(SCIP_DEFAULTS)
        params.update(INDICATOR_PARAMS)
        params["limits/time"] = self.time_limit
        if self.rel_gap > 0:
            params["limits/gap"] = self.rel_gap
        params.update(self.options.get("scip_params", {}))
        mdl.setParams(params)
        try:
            with quiet_stdout(self.quiet):
                mdl.optimize()
        except Exception as exc:  # pragma: no cover - backend crash
            raise SolverError(f"SCIP raised {type(exc).__name__}: {exc}", solver="scip") from exc
        dt = time.perf_counter() - t0
        self.n_solves += 1
        status = str(mdl.getStatus())
        backend = "scip-indicator"
        if status in ("infeasible", "inforunbd"):
            return RawSolution(status=INFEASIBLE, solve_time=dt, backend=backend, message=status)
        if status == "timelimit":
            return RawSolution(status=TIMEOUT, solve_time=dt, backend=backend, message=status)
        gap_stop = status == "gaplimit" and self.rel_gap > 0
        if (status != "optimal" and not gap_stop) or mdl.getNSols() == 0:
            return RawSolution(status=FAILED, solve_time=dt, backend=backend, message=status)
        sol = mdl.getBestSol()
        zv = np.array([sol[v] for v in z])
        touching = tuple(bool(sol[y] > 0.5) for y in ys)
        moving = tuple(bool(a in zs and sol[zs[a]] > 0.5) for a in range(f.na))
        if self.kind == "prp":
            obj = float(np.sum((f.E @ zv[sb]) ** 2))
        else:
            obj = float(np.sum((data.w + f.Gb @ zv[sb]) ** 2))
        return RawSolution(
            status=OPTIMAL,
            z=zv,
            mode=Mode(touching, moving),
            objective=obj,
            solve_time=dt,
            backend=backend,
            bigm_ratio=0.0,
            message=status,
        )
