"""One entry point for solving a passive-response problem with the chosen backend.

* ``Backend.BNB`` (default): pinograsp's exact branch-and-bound (:mod:`.bnb`), deterministic,
  no time limits, canonical (least-norm) optimum.
* ``Backend.MIQP``: the reference mixed-integer QP through cvxpy (:mod:`.miqp`; SCIP, or Gurobi
  when installed), with big-M audit and enlargement; its mode is then re-solved exactly by the
  same fixed-mode QP as the branch-and-bound, so both backends report points of the same kind.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, replace
from typing import Any

from ..core.settings import MAX_NODES, Backend
from ..errors import BigMWarning
from .base import OPTIMAL, Mode, RawSolution
from .bnb import BranchAndBound
from .formulation import Formulation, ScaledData
from .problem import ProblemKind, build_problem

#: A solution whose big-M-bounded quantities reach this fraction of M is re-solved with a
#: larger M (the bound may be cutting off the true optimum).
BIGM_TRIGGER = 0.1


@dataclass(frozen=True)
class BackendOptions:
    """What a backend needs besides the data.

    Attributes:
        backend: :class:`Backend`.
        gamma: Step bound of Alg. 2 (scaled).
        max_nodes: Node limit of the branch-and-bound (a count).
        solver: cvxpy MIQP solver of the reference backend.
        time_limit: Per-MIQP time limit [s] (reference backend only).
        bigm: Initial big-M constant (scaled force units, reference backend only).
        bigm_retries: Enlargements (x100 each) of big-M when a solution reaches 10 % of it.
        miqp_options: Extra options of :class:`~.miqp.CvxpyMIQP`.
    """

    backend: Backend = Backend.BNB
    gamma: float = 1.0
    max_nodes: int = MAX_NODES
    solver: str = "scip"
    time_limit: float = 60.0
    bigm: float = 1e3
    bigm_retries: int = 2
    miqp_options: tuple[tuple[str, Any], ...] = ()


def solve(
    form: Formulation,
    kind: ProblemKind,
    data: ScaledData,
    options: BackendOptions,
    guess: Mode | None = None,
    cache: dict | None = None,
) -> RawSolution:
    """Solve one problem; ``guess`` is an incumbent mode (speed only).

    ``cache`` (owned by the caller) keeps the reference backend's cvxpy objects between calls.
    """
    t0 = time.perf_counter()
    if options.backend is Backend.BNB:
        problem = build_problem(form, kind, data, options.gamma)
        raw = BranchAndBound(problem, options.max_nodes).solve(guess)
    else:
        raw = _solve_miqp(form, kind, data, options, cache if cache is not None else {})
    return replace(raw, solve_time=time.perf_counter() - t0)


_CONTROLLER: list = []


def single_threaded_blas():
    """A context that runs NumPy's BLAS/LAPACK on one thread.

    The solver's matrices are tiny (tens of rows): threads only cost, and on a loaded machine
    OpenBLAS's spinning threads made a case-1 direction 5x slower (0.15 s -> 0.67 s), also when
    the limit was toggled around every solve (the threads spin between calls): public queries
    hold it for their whole duration (:func:`single_threaded`). One thread also keeps every
    reduction in one order. The controller is built once (8 µs per use)."""
    from threadpoolctl import ThreadpoolController

    if not _CONTROLLER:
        _CONTROLLER.append(ThreadpoolController())
    return _CONTROLLER[0].limit(limits=1, user_api="blas")


def _solve_miqp(
    form: Formulation, kind: ProblemKind, data: ScaledData, options: BackendOptions, cache: dict
) -> RawSolution:
    from .miqp import CvxpyMIQP

    key = ("miqp", kind)
    if key not in cache:
        cache[key] = CvxpyMIQP(
            form,
            kind.value,
            solver=options.solver,
            gamma=options.gamma,
            time_limit=options.time_limit,
            options=dict(options.miqp_options),
        )
    miqp = cache[key]
    M, retries = options.bigm, 0
    while True:
        sol = miqp.solve(data, M)
        if sol.status != OPTIMAL or sol.bigm_ratio < BIGM_TRIGGER or retries >= options.bigm_retries:
            break
        M *= 100.0
        retries += 1
    if sol.status != OPTIMAL:
        return replace(sol, bigm_retries=retries)
    if sol.bigm_ratio >= BIGM_TRIGGER:
        warnings.warn(
            f"MIQP solution uses {sol.bigm_ratio:.0%} of the big-M bound after {retries} enlargements "
            f"(M = {M:.3g} in scaled force units): the answer may be cut off by the bound",
            BigMWarning,
            stacklevel=4,
        )
    problem = build_problem(form, kind, data, options.gamma)
    pol = BranchAndBound(problem).solve_mode(sol.mode)
    if pol.status != OPTIMAL:
        return replace(sol, bigm_retries=retries)
    return replace(
        pol,
        backend=f"{sol.backend}+polish",
        bigm_ratio=sol.bigm_ratio,
        bigm_retries=retries,
        message=sol.message,
    )


def single_threaded(fn):
    """Decorator: run ``fn`` inside :func:`single_threaded_blas` (public queries)."""
    import functools

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        with single_threaded_blas():
            return fn(*args, **kwargs)

    return wrapper
