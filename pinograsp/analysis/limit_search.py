"""The largest load along a direction by searching magnitudes (the staged methods'
:meth:`~pinograsp.analysis.method_base.MethodBase.max_load`): the upper limit first, then the
paper's bisection, the iterative scheme's secant or one load-factor problem (``"direct"``),
and the :class:`~pinograsp.core.results.MaxWrench` of where it ended.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from ..core.audit import audit_message
from ..core.results import MaxWrench, MaxWrenchStatus, PassiveResponse
from ..core.settings import Search
from ..errors import AuditWarning, PreloadNotInEquilibriumError, SolverError, SolverTimeoutError
from ..solvers.base import SolveStatus
from .protocols import LimitQuery, verdict
from .search import bisection, grid_resolution, secant


def searched_max_load(q: LimitQuery) -> MaxWrench:
    """The largest resisted magnitude of ``q`` by its search (docs/accuracy.md)."""
    if q.search is Search.DIRECT and q.method.limit_point:  # one solve decides
        mag, resp = direct(q)
        return finish(q, mag, bool(np.isinf(mag)), resp)
    # the upper limit first: an unbounded direction costs one (fast-path) solve, not a search
    ok, resp = q.test(float(q.upper))
    if ok:
        return finish(q, float("inf"), True, resp)
    if q.search is Search.DIRECT:
        mag, best = direct(q)
        return finish(q, mag, False, best)
    if q.search is Search.SECANT:
        st = q.settings
        lo, found = secant(q.test, float(q.upper), int(q.steps), resp, lambda m: st.eps + st.eps_rel * m)
    else:
        lo, found = bisection(q.test, float(q.upper), int(q.steps))
    return finish(q, lo, False, found)


def resisted_without_preload(q: LimitQuery) -> PassiveResponse:
    """The load along the (unit) direction under a zero preload: the limit of ``t d`` under
    ``command`` as ``t -> inf`` (the model is positively homogeneous: ``t d`` under ``f_c`` is
    ``d`` under ``f_c / t``). Resisted means passively resisted without bound
    (docs/accuracy.md)."""
    zero = np.zeros(q.session.model.na)
    resp = q.session.response(zero, q.direction, q.method.name)
    verdict(resp, float("inf"))
    return resp


def audit_warning(q: LimitQuery) -> str | None:
    """The one warning text of the resisted magnitudes that fail the audit (None: none)."""
    if not q.tally.flagged:
        return None
    at, bad = min(q.tally.flagged, key=lambda mr: mr[0])
    e = bad.audit.energy if bad.audit is not None else None
    why = (
        audit_message(q.method.name, e)
        if e is not None and not (e.energy_ok and e.displacement_ok)
        else "residuals above the audit tolerance"
    )
    return (
        f"{len(q.tally.flagged)} resisted magnitude(s) from {at:.6g} rest on solutions that fail "
        f"the audit; at {at:.6g}: {why}"
    )


def finish(q: LimitQuery, magnitude: float, at_upper: bool, response: PassiveResponse | None) -> MaxWrench:
    """The :class:`MaxWrench` of a search that ended at ``magnitude`` (``at_upper``: ``upper``
    itself was resisted; the direction is unbounded only if the zero-preload limit says so)."""
    extra_time = 0.0
    status: MaxWrenchStatus
    if at_upper:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AuditWarning)
            limit = resisted_without_preload(q)
        q.tally.flag(float("inf"), limit)
        extra_time = limit.solve_time
        status = "unbounded" if limit.resistible else "above_limit"
        magnitude = float("inf") if limit.resistible else float(q.upper)
        unbounded = limit.resistible
    else:
        status = "finite" if magnitude >= q.floor and magnitude > 0 else "below_resolution"
        magnitude = magnitude if status == "finite" else 0.0  # a direct solve's 1e-15 is 0
        unbounded = False
    message = audit_warning(q)
    if message is not None:
        warnings.warn(message, AuditWarning, stacklevel=7)
    note = q.session.model.free_motion_note(q.direction) if status == "below_resolution" else ""
    return MaxWrench(
        direction=q.direction,
        magnitude=magnitude,
        unbounded=unbounded,
        status=status,
        floor=q.floor,
        upper=float(q.upper),
        resolution=grid_resolution(q.upper, q.steps),
        evidence=tuple(q.tally.evidence),
        method=q.method.name,
        solve_time=q.tally.solve_time + extra_time,
        wall_time=time.perf_counter() - q.t0,
        n_solves=q.tally.n_solves,
        response=response,
        search=q.search.value,
        audit_failures=tuple(sorted(m for m, _ in q.tally.flagged)),
        note=note,
    )


#: A direct (load-factor) limit within this fraction of ``upper`` (or within the resolution
#: ``upper / 2**steps`` if coarser) is checked by solving at ``upper`` itself.
NEAR_UPPER = 1e-4


def direct(q: LimitQuery) -> tuple[float, PassiveResponse]:
    """The exact limit by one load-factor problem, and the response at it: the method's own
    point there (:attr:`~pinograsp.analysis.method_base.MethodBase.limit_point`), or the
    response just below it. ``inf``: ``upper``."""
    session, upper = q.session, float(q.upper)
    lf = session.max_load_factor(q.command, q.direction, upper, q.method.name)
    status, mag = lf.status, lf.magnitude
    q.tally.solve_time += lf.solve_time
    q.tally.n_solves += 1
    backend = session.settings.backend
    if status in (SolveStatus.TIMEOUT, SolveStatus.FAILED, SolveStatus.NODE_LIMIT):
        cls = SolverTimeoutError if status is SolveStatus.TIMEOUT else SolverError
        hint = " (raise Settings.max_nodes)" if status is SolveStatus.NODE_LIMIT else ""
        raise cls(f"load-factor problem: {status.value}{hint}", solver=backend, status=status.value)
    if status is not SolveStatus.OPTIMAL:
        raise PreloadNotInEquilibriumError(
            session.model.command_vector(q.command).tolist(), "load-factor problem infeasible"
        )
    near_upper = np.isfinite(mag) and mag >= upper * (1.0 - max(2.0**-q.steps, NEAR_UPPER))
    if near_upper and q.method.limit_point:
        # the problem is bounded by ``upper``: a limit this close to it may be the bound binding
        # within the solver's tolerance (49.99994 of 50 for a MIQP gap of 1e-6), not a finite
        # limit. ``upper`` itself decides: resisted -> the zero-preload limit then says unbounded
        # or above_limit, as when a search finds ``upper`` resisted. (A method without its own
        # limit point reaches ``direct`` only after ``upper`` was tested not resisted.)
        ok, _ = q.test(upper)
        if ok:
            mag = float("inf")
    if lf.response is not None:  # the method's own point at the limit
        q.tally.evidence.append((float(q.upper) if np.isinf(mag) else mag, True))
        q.tally.flag(mag, lf.response)
        return mag, lf.response
    if np.isinf(mag):
        raise SolverError(
            f"load-factor problem reached the upper limit {upper:g} that the {q.method.name} "
            "problem did not resist",
            solver=backend,
            status="failed",
        )
    at = mag * (1.0 - 1e-6)
    ok, resp = q.test(at, session.plain(lf.model) if lf.model is not None else None)
    if not ok:
        raise SolverError(
            f"load-factor problem found magnitude {mag:.9g} but the {q.method.name} problem at "
            f"{at:.9g} is not resisted",
            solver=backend,
            status="failed",
        )
    return mag, resp


__all__ = ["NEAR_UPPER", "audit_warning", "direct", "finish", "searched_max_load"]
