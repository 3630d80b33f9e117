"""The largest wrench magnitude a preloaded grasp resists along one direction (seed paper:
bisection on ``[0, upper]``), and the check that the preload alone is in equilibrium.

Many directions at once: :mod:`pinograsp.analysis.directions`; profiles in a plane:
:mod:`pinograsp.analysis.profile`.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..core.audit import audit_message
from ..core.axes import WRENCH_AXES, wrench_direction
from ..core.model import GraspModel
from ..core.results import MaxWrench, PassiveResponse
from ..core.settings import METHODS, Method, Search, Settings
from ..core.validate import choice, search_bounds
from ..errors import (
    AuditWarning,
    InvalidInputError,
    PreloadNotInEquilibriumError,
    SolverError,
    SolverTimeoutError,
)
from ..solvers.base import SolveStatus
from ..solvers.solve import single_threaded
from .response import PassiveSolver, solver_for
from .search import bisection, secant


def _check(resp: PassiveResponse, magnitude: float) -> bool:
    """The verdict of ``resp`` at ``magnitude``; raise when the solver gave none."""
    if resp.status == "node_limit":
        raise SolverError(
            f"branch-and-bound node limit reached at magnitude {magnitude:.6g} (raise Settings.max_nodes)",
            solver=resp.solver,
            status="node_limit",
        )
    if resp.status == "timeout":
        raise SolverTimeoutError(
            f"solver timed out at magnitude {magnitude:.6g}", solver=resp.solver, status="timeout"
        )
    if resp.status == "failed":
        raise SolverError(
            f"solver failed at magnitude {magnitude:.6g} (no trustworthy verdict)",
            solver=resp.solver,
            status="failed",
        )
    return resp.resistible


def check_preload(solver: PassiveSolver, command: object, method: str) -> PassiveResponse:
    """Solve ``w = 0``; raise :class:`PreloadNotInEquilibriumError` if the preload alone has no
    passive equilibrium."""
    resp = solver.response(command, np.zeros(6), method)
    if not _check(resp, 0.0):
        detail = f"{method} solve at w = 0 returned {resp.status!r}"
        residual = None
        if np.all(np.isfinite(resp.net_wrench)):
            residual = resp.net_wrench
            shown = ", ".join(f"{a}={v:.3g}" for a, v in zip(WRENCH_AXES, residual) if abs(v) > 0)
            detail += f"; net wrench left on the object: {shown or '0'} [N, N·m]"
        elif resp.residual_history:
            detail += f" (net wrench {resp.residual_history[-1]:.3g} N)"
        raise PreloadNotInEquilibriumError(solver.model.command_vector(command).tolist(), detail, residual)
    return resp


@dataclass
class Tally:
    """What one max-wrench query has spent and seen so far (filled in as the search goes).

    Attributes:
        solve_time: Solver wall time [s].
        n_solves: Complementarity problems solved.
        evidence: Every magnitude tried and its verdict, in order.
        flagged: Resisted magnitudes whose solution fails the audit, with that response.
    """

    solve_time: float = 0.0
    n_solves: int = 0
    evidence: list[tuple[float, bool]] = field(default_factory=list)
    flagged: list[tuple[float, PassiveResponse]] = field(default_factory=list)

    def add(self, resp: PassiveResponse) -> None:
        """Count a response's solver time and solves."""
        self.solve_time += resp.solve_time
        self.n_solves += resp.n_solves

    def flag(self, magnitude: float, resp: PassiveResponse) -> None:
        """Keep a resisted response that fails the audit (warned about once, at the end)."""
        if resp.resistible and resp.audit is not None and not resp.audit.ok:
            self.flagged.append((magnitude, resp))


@dataclass(frozen=True)
class _Query:
    """One max-wrench query: what it asks (``direction`` unit, (6,)) and its running tally."""

    solver: PassiveSolver
    command: object
    direction: np.ndarray
    method: str
    upper: float
    steps: int
    search: Search
    floor: float
    t0: float
    tally: Tally

    def test(self, magnitude: float, solver: PassiveSolver | None = None) -> tuple[bool, PassiveResponse]:
        """The verdict at ``magnitude`` [N or N·m] along the direction, recorded in the tally
        (``solver``: another session than the query's, e.g. on a refined model)."""
        with warnings.catch_warnings():  # summarised once, after the search
            warnings.simplefilter("ignore", AuditWarning)
            resp = (solver or self.solver).response(self.command, magnitude * self.direction, self.method)
        self.tally.add(resp)
        ok = _check(resp, magnitude)
        self.tally.evidence.append((magnitude, ok))
        self.tally.flag(magnitude, resp)
        return ok, resp


def _search_kind(search: object, method: str) -> Search:
    """The search ``search`` names for ``method`` (``"auto"`` resolved)."""
    kind = Search(choice("search", search, [x.value for x in Search]))
    if kind is Search.AUTO:
        auto = {Method.ITERATIVE: Search.SECANT, Method.ENERGETIC: Search.DIRECT}
        kind = auto.get(Method(method), Search.BISECTION)
    if kind is Search.DIRECT and method == Method.ITERATIVE:
        raise InvalidInputError(
            "search", "'direct' exists for method='prp' and 'energetic' only (Alg. 3 is a trajectory)"
        )
    if kind is Search.SECANT and method != Method.ITERATIVE:
        raise InvalidInputError(
            "search", "'secant' exists for method='iterative' only (PRP stages carry no residual)"
        )
    return kind


def _floor(solver: PassiveSolver, d: np.ndarray, method: str, upper: float, steps: int) -> float:
    """Smallest magnitude distinguishable from zero: the resolution, and for the iterative
    method at least its equilibrium tolerance ``eps`` along ``d``."""
    floor = float(upper) / 2**steps
    if method == Method.ITERATIVE:
        scale = float(np.linalg.norm(solver.model.reduce_wrench(d) * solver.form.wscale))
        floor = max(floor, solver.settings.eps / scale)
    return floor


def _resisted_without_preload(
    solver: PassiveSolver, command: object, d: np.ndarray, method: str
) -> PassiveResponse:
    """The load ``d`` (unit) under a zero preload: the limit of ``t d`` under ``command`` as
    ``t -> inf`` (the model is positively homogeneous: ``t d`` under ``f_c`` is ``d`` under
    ``f_c / t``). Resisted means passively resisted without bound (docs/accuracy.md)."""
    zero = np.zeros(solver.model.na)
    resp = solver.response(zero, d, method)
    _check(resp, float("inf"))
    return resp


def _audit_warning(q: _Query) -> str | None:
    """The one warning text of the resisted magnitudes that fail the audit (None: none)."""
    if not q.tally.flagged:
        return None
    at, bad = min(q.tally.flagged, key=lambda mr: mr[0])
    e = bad.audit.energy
    why = (
        audit_message(q.method, e)
        if e is not None and not (e.energy_ok and e.displacement_ok)
        else "residuals above the audit tolerance"
    )
    return (
        f"{len(q.tally.flagged)} resisted magnitude(s) from {at:.6g} rest on solutions that fail "
        f"the audit; at {at:.6g}: {why}"
    )


def _finish(q: _Query, magnitude: float, at_upper: bool, response: PassiveResponse | None) -> MaxWrench:
    """The :class:`MaxWrench` of a search that ended at ``magnitude`` (``at_upper``: ``upper``
    itself was resisted; the direction is unbounded only if the zero-preload limit says so)."""
    extra_time = 0.0
    if at_upper:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AuditWarning)
            limit = _resisted_without_preload(q.solver, q.command, q.direction, q.method)
        q.tally.flag(float("inf"), limit)
        extra_time = limit.solve_time
        status = "unbounded" if limit.resistible else "above_limit"
        magnitude = float("inf") if limit.resistible else float(q.upper)
        unbounded = limit.resistible
    else:
        status = "finite" if magnitude >= q.floor and magnitude > 0 else "below_resolution"
        magnitude = magnitude if status == "finite" else 0.0  # a direct solve's 1e-15 is 0
        unbounded = False
    message = _audit_warning(q)
    if message is not None:
        warnings.warn(message, AuditWarning, stacklevel=4)
    return MaxWrench(
        direction=q.direction,
        magnitude=magnitude,
        unbounded=unbounded,
        status=status,
        floor=q.floor,
        upper=float(q.upper),
        resolution=float(q.upper) / 2**q.steps,
        evidence=tuple(q.tally.evidence),
        method=q.method,
        solve_time=q.tally.solve_time + extra_time,
        wall_time=time.perf_counter() - q.t0,
        n_solves=q.tally.n_solves,
        response=response,
        search=q.search.value,
        audit_failures=tuple(sorted(m for m, _ in q.tally.flagged)),
    )


def _direct(q: _Query) -> tuple[float, PassiveResponse]:
    """The exact limit by one load-factor problem, and the response at it: the energetic
    problem's own point there, or (PRP) the response just below it. ``inf``: ``upper``."""
    solver, upper = q.solver, float(q.upper)
    lf = solver.max_load_factor(q.command, q.direction, upper, q.method)
    status, mag = lf.status, lf.magnitude
    q.tally.solve_time += lf.solve_time
    q.tally.n_solves += 1
    backend = solver.settings.backend
    if status in (SolveStatus.TIMEOUT, SolveStatus.FAILED, SolveStatus.NODE_LIMIT):
        cls = SolverTimeoutError if status is SolveStatus.TIMEOUT else SolverError
        raise cls(f"load-factor problem: {status.value}", solver=backend, status=status.value)
    if status is not SolveStatus.OPTIMAL:
        raise PreloadNotInEquilibriumError(
            solver.model.command_vector(q.command).tolist(), "load-factor problem infeasible"
        )
    if lf.response is not None:  # energetic: the point at the limit
        q.tally.evidence.append((float(q.upper) if np.isinf(mag) else mag, True))
        q.tally.flag(mag, lf.response)
        return mag, lf.response
    if np.isinf(mag):
        raise SolverError(
            f"load-factor problem reached the upper limit {upper:g} that the PRP did not resist",
            solver=backend,
            status="failed",
        )
    at = mag * (1.0 - 1e-6)
    ok, resp = q.test(at, solver.plain(lf.model) if lf.model is not None else None)
    if not ok:
        raise SolverError(
            f"load-factor problem found magnitude {mag:.9g} but the {q.method} problem at {at:.9g} "
            "is not resisted",
            solver=backend,
            status="failed",
        )
    return mag, resp


@single_threaded
def max_resistible_wrench(
    model: GraspModel,
    command: object,
    direction: object,
    method: str = "iterative",
    upper: float = 1e3,
    steps: int = 20,
    *,
    settings: Settings | None = None,
    check_preload_first: bool = True,
    search: str = "auto",
    **overrides: object,
) -> MaxWrench:
    """Largest wrench magnitude along ``direction`` that the preloaded grasp resists passively.

    Bisection on ``[0, upper]`` (seed paper: 20 steps, upper 1e3 N). The preload alone is
    checked first (``w = 0``); a grasp whose preload is not in equilibrium raises
    :class:`PreloadNotInEquilibriumError` instead of "resisting 0 N". If ``upper`` itself is
    resisted the direction is reported ``unbounded`` with ``magnitude = inf``.

    Args:
        model: The grasp.
        command: Actuator commands (see :func:`pinograsp.passive_response`).
        direction: Wrench direction: axis name (``"fx"``, ``"-fy"``, ``"mz"``) or vector
            (normalised here).
        method: ``"iterative"`` (default; no wedging artefact), ``"energetic"`` (maximum
            dissipation, one solve per direction; docs/methods.md) or ``"prp"``.
        upper: Upper limit of the search [N or N·m along the unit direction].
        steps: Bisection steps; resolution ``upper / 2**steps``.
        search: ``"auto"`` (default: ``"secant"`` for the iterative method, ``"direct"`` for
            the energetic one, ``"bisection"`` for the PRP), ``"bisection"`` (the paper's),
            ``"secant"`` (iterative only: the same grid cell as the bisection when
            resistibility is monotone along the ray, in fewer stages;
            :mod:`pinograsp.analysis.search`) or ``"direct"`` (PRP, energetic): one complementarity
            problem maximising the load factor, exact instead of ``upper / 2**steps``; the
            response at the limit is then solved at ``magnitude * (1 - 1e-6)``.
        settings, overrides: Solver settings (see :class:`pinograsp.core.settings.Settings`).

    Raises:
        PreloadNotInEquilibriumError, SolverTimeoutError, SolverError, InvalidInputError.
    """
    t0 = time.perf_counter()
    choice("method", method, METHODS)
    solver = solver_for(model, settings, **overrides)
    eps = solver.settings.eps if method == Method.ITERATIVE else None
    upper, steps = search_bounds(model, command, upper, steps, eps)  # domains: docs/errors.md
    d = wrench_direction(model, direction)
    tally = Tally()
    if check_preload_first:
        tally.add(check_preload(solver, command, method))
    kind = _search_kind(search, method)
    q = _Query(
        solver, command, d, method, upper, steps, kind, _floor(solver, d, method, upper, steps), t0, tally
    )
    if kind is Search.DIRECT and method == Method.ENERGETIC:  # one solve decides
        mag, resp = _direct(q)
        return _finish(q, mag, bool(np.isinf(mag)), resp)
    # the upper limit first: an unbounded direction costs one (fast-path) solve, not a search
    ok, resp = q.test(float(upper))
    if ok:
        return _finish(q, float("inf"), True, resp)
    if kind is Search.DIRECT:
        mag, resp = _direct(q)
        return _finish(q, mag, False, resp)
    if kind is Search.SECANT:
        st = solver.settings
        lo, best = secant(q.test, float(upper), int(steps), resp, lambda m: st.eps + st.eps_rel * m)
    else:
        lo, best = bisection(q.test, float(upper), int(steps))
    return _finish(q, lo, False, best)


__all__ = ["Tally", "check_preload", "max_resistible_wrench"]
