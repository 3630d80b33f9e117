"""The iterative scheme (seed Alg. 2 inside Alg. 3): the object may only move along the current
net wrench (a step in ``[0, gamma]``), each step minimises the net wrench, repeat until it falls
below ``eps`` (resisted) or stops improving (not resisted). No wedging artefact. Default
variant: preload-first (the object held still while the hand closes); default search: the
grid-snapped secant on the final net wrench (:mod:`pinograsp.analysis.search`)."""

from __future__ import annotations

import numpy as np

from ..core.results import MaxWrench, PassiveResponse
from ..core.settings import Method, Search, Variant
from ..solvers.base import Mode
from ..solvers.problem import ProblemKind
from .context import SolveContext
from .limit_search import searched_max_load
from .protocols import LimitQuery, SessionLike
from .search import grid_resolution
from .staged import staged_response
from .stages import Stage, iterative_stage


class IterativeMethod:
    """Rules of ``method="iterative"`` (:class:`~pinograsp.analysis.protocols.AnalysisMethod`)."""

    name = Method.ITERATIVE
    load_kind: ProblemKind | None = ProblemKind.MOVE
    load_factor_kind: ProblemKind | None = None  # a trajectory: no one-solve limit
    default_variant = Variant.PRELOAD_FIRST
    searches: tuple[Search, ...] = (Search.SECANT, Search.BISECTION)
    refines = False
    exact = False  # converged to the tolerance eps + eps_rel F
    limit_point = False
    preload_method = Method.ITERATIVE
    carries_residual = False
    preload_kept = False

    def stage(
        self, session: SolveContext, w: np.ndarray, fc: np.ndarray, p: np.ndarray, start: Mode | None
    ) -> Stage:
        """Alg. 3 from the (pre)loaded state; ``start`` is the first step's incumbent mode."""
        return iterative_stage(session, w, fc, p, start=start)

    def floor(self, session: SolveContext, direction: np.ndarray, upper: float, steps: int) -> float:
        """The resolution, and at least the equilibrium tolerance ``eps`` along ``direction``."""
        floor = grid_resolution(upper, steps)
        scale = float(np.linalg.norm(session.model.reduce_wrench(direction) * session.form.wscale))
        return max(floor, session.settings.eps / scale)

    def response(self, session: SessionLike, fc: np.ndarray, w6: np.ndarray) -> PassiveResponse:
        """Preload stage (per the variant) and Alg. 3 on top."""
        return staged_response(session, self, fc, w6)

    def max_load(self, session: SessionLike, query: LimitQuery) -> MaxWrench:
        """Secant (or bisection) on ``[0, upper]``."""
        return searched_max_load(query)


ITERATIVE = IterativeMethod()
