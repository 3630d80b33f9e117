"""The largest wrench magnitude a preloaded grasp resists along one direction (seed paper:
bisection on ``[0, upper]``), and the check that the preload alone is in equilibrium. The
search itself is the method's (:meth:`~pinograsp.analysis.method_base.MethodBase.max_load`;
for the staged methods :mod:`pinograsp.analysis.limit_search`).

Many directions at once: :mod:`pinograsp.analysis.directions`; profiles in a plane:
:mod:`pinograsp.analysis.profile`.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from ..core.axes import WRENCH_AXES, wrench_direction
from ..core.methods import bounded as limits_bound
from ..core.model import GraspModel
from ..core.query import Query, make_query
from ..core.results import MaxWrench, PassiveResponse
from ..core.settings import DEFAULT_METHOD, Settings
from ..core.validate import search_bounds
from ..errors import PreloadNotInEquilibriumError
from ..solvers.threads import single_threaded
from .protocols import LimitQuery, SessionLike, Tally, verdict
from .registry import get_method, resolve_search
from .response import Session, session_for


def check_preload(solver: SessionLike, command: object, method: str) -> PassiveResponse | None:
    """Solve ``w = 0``; raise :class:`PreloadNotInEquilibriumError` if the preload alone has no
    passive equilibrium. A method whose preload is decided by its own account
    (``preload_by_error``: the quasi-static preload path) asks that alone: None is returned."""
    rules = get_method(method)
    if rules.preload_by_error:
        exc = rules.preload_error(solver, command)
        if exc is not None:
            raise exc
        return None
    resp = solver.response(command, np.zeros(6), method)
    if not verdict(resp, 0.0):
        exc = rules.preload_error(solver, command)  # the method's own account, if any
        if exc is not None:
            raise exc
        detail = f"{method} solve at w = 0 returned {resp.status!r}"
        residual = None
        if np.all(np.isfinite(resp.net_wrench)):
            residual = resp.net_wrench
            shown = ", ".join(f"{a}={v:.3g}" for a, v in zip(WRENCH_AXES, residual) if abs(v) > 0)
            detail += f"; net wrench left on the object: {shown or '0'} [N, N·m]"
        elif resp.residual_history:
            detail += f" (net wrench {resp.residual_history[-1]:.3g} N)"
        raise PreloadNotInEquilibriumError(
            solver.model.command_vector(command).tolist(), detail, residual, method=method
        )
    return resp


def query_within(session: Session, command: object, query: Query, *, eps: bool = True) -> np.ndarray:
    """The validated commands (na,) of a query, its ``upper`` checked against the grasp they
    preload: within :data:`~pinograsp.core.validate.LOAD_RATIO` of its force scale; with ``eps``,
    for a method converged to a tolerance (not
    :attr:`~pinograsp.analysis.method_base.MethodBase.exact`), ``Settings.eps`` within
    :data:`~pinograsp.core.validate.EPS_RATIO` of it (docs/errors.md, "Input domains"). A
    method whose limit is exact (:attr:`~pinograsp.core.methods.MethodSpec.bounded` False)
    ignores ``upper`` and ``steps``: only the commands are checked (``upper`` was checked by
    the :class:`Query`).

    Raises:
        InvalidInputError: A bad command, or ``upper`` or ``eps`` out of its domain for this grasp.
    """
    fc = session.model.command_vector(command)
    if not limits_bound(query.method):  # upper does not decide unboundedness, steps do not apply
        return fc
    tolerance = None if not eps or get_method(query.method).exact else session.settings.eps
    search_bounds(session.source, fc, query.upper, query.steps, tolerance)
    return fc


def max_wrench_on(
    session: Session, fc: np.ndarray, d: np.ndarray, query: Query, *, check_preload_first: bool = True
) -> MaxWrench:
    """:func:`max_resistible_wrench` on a session, with validated commands ``fc`` (na,), unit
    direction ``d`` (6,) and query: what profiles, sets and batches call per direction."""
    t0 = time.perf_counter()
    rules = get_method(query.method)
    tally = Tally()
    if check_preload_first and not (rules.preload_kept and session.preload_checked(fc, rules.name)):
        tally.add(check_preload(session, fc, rules.name))
        session.preload_checked(fc, rules.name, passed=rules.preload_kept)
    kind = resolve_search(query.search, rules)
    floor = rules.floor(session, d, query.upper, query.steps)
    q = LimitQuery(session, fc, d, rules, query.upper, query.steps, kind, floor, t0, tally)
    return rules.max_load(session, q)


@single_threaded
def max_resistible_wrench(
    model: GraspModel,
    command: object,
    direction: object,
    method: str = DEFAULT_METHOD,
    upper: float = 1e3,
    steps: int = 20,
    *,
    settings: Settings | None = None,
    check_preload_first: bool = True,
    search: str = "auto",
    session: Session | None = None,
    query: Query | None = None,
    **overrides: object,
) -> MaxWrench:
    """Largest wrench magnitude along ``direction`` that the preloaded grasp resists passively.

    The method's search on ``[0, upper]`` (seed paper: bisection, 20 steps, upper 1e3 N; see
    ``search``). The preload alone is checked first (``w = 0``); a grasp whose preload is not
    in equilibrium raises :class:`PreloadNotInEquilibriumError` instead of "resisting 0 N". If
    ``upper`` itself is resisted the direction is reported ``unbounded`` with
    ``magnitude = inf`` (when the zero-preload limit is resisted too; else ``above_limit``).

    Args:
        model: The grasp.
        command: Actuator commands (see :func:`pinograsp.passive_response`).
        direction: Wrench direction: axis name (``"fx"``, ``"-fy"``, ``"mz"``) or vector
            (normalised here).
        method: ``"quasistatic"`` (default: the loading path followed exactly to its limit
            load, no bisection: ``upper`` and ``steps`` do not apply; docs/design.md, "The
            quasi-static row"), ``"iterative"`` (the paper's scheme; no wedging artefact),
            ``"energetic"`` (maximum dissipation, one solve per direction; docs/methods.md) or
            ``"prp"``.
        upper: Upper limit of the search [N or N·m along the unit direction].
        steps: Bisection steps; resolution ``upper / 2**steps``.
        search: ``"auto"`` (default: ``"secant"`` for the iterative method, ``"direct"`` for
            the energetic one, ``"bisection"`` for the PRP), ``"bisection"`` (the paper's),
            ``"secant"`` (iterative only: the same grid cell as the bisection when
            resistibility is monotone along the ray, in fewer stages;
            :mod:`pinograsp.analysis.search`), ``"path"`` (quasi-static only, its default) or
            ``"direct"`` (PRP, energetic): one complementarity
            problem maximising the load factor, exact instead of ``upper / 2**steps``; the
            response at the limit is then solved at ``magnitude * (1 - 1e-6)``.
        settings, overrides: Solver settings (see :class:`pinograsp.core.settings.Settings`).
        session: A :class:`~pinograsp.Session` of ``model`` the caller owns (its settings rule;
            its preload stages are shared with the caller's other queries).
        query: A :class:`~pinograsp.Query` instead of ``method``, ``upper``, ``steps``,
            ``search``.

    Raises:
        PreloadNotInEquilibriumError, SolverTimeoutError, SolverError, InvalidInputError.
    """
    t0 = time.perf_counter()
    q = make_query(query, method, upper, steps, search)
    solver = session_for(model, session, settings, overrides)
    d = wrench_direction(model, direction)
    fc = query_within(solver, command, q)  # domains: docs/errors.md
    mw = max_wrench_on(solver, fc, d, q, check_preload_first=check_preload_first)
    return replace(mw, wall_time=time.perf_counter() - t0)


__all__ = ["Tally", "check_preload", "max_resistible_wrench", "max_wrench_on", "query_within"]
