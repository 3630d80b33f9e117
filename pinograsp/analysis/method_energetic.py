"""The energetic method (maximum dissipation, docs/methods.md): Alg. 1's problem plus one slip
magnitude per contact and the pairs that let a friction edge carry force only if it points
most against the slip; one mixed-integer problem, no wedging artefact. Default variant:
preload-first on the iterative scheme's preload stage (whose residual it carries); default
search: one load-factor problem (:attr:`ProblemKind.ENERGETIC_LOAD`) whose optimum is the
equilibrium at the limit."""

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
from .stages import Stage, prp_stage


class EnergeticMethod:
    """Rules of ``method="energetic"`` (:class:`~pinograsp.analysis.protocols.AnalysisMethod`)."""

    name = Method.ENERGETIC
    load_kind: ProblemKind | None = ProblemKind.ENERGETIC
    load_factor_kind: ProblemKind | None = ProblemKind.ENERGETIC_LOAD
    default_variant = Variant.PRELOAD_FIRST
    searches: tuple[Search, ...] = (Search.DIRECT, Search.BISECTION)
    refines = True
    exact = True
    limit_point = True
    preload_method = Method.ITERATIVE
    carries_residual = True
    preload_kept = False

    def stage(
        self, session: SolveContext, w: np.ndarray, fc: np.ndarray, p: np.ndarray, start: Mode | None
    ) -> Stage:
        """The energetic problem at the reduced wrench ``w`` on pre-compression ``p``."""
        return prp_stage(session, w, fc, p, ProblemKind.ENERGETIC)

    def floor(self, session: SolveContext, direction: np.ndarray, upper: float, steps: int) -> float:
        """The search's resolution ``upper / 2**steps``."""
        return grid_resolution(upper, steps)

    def response(self, session: SessionLike, fc: np.ndarray, w6: np.ndarray) -> PassiveResponse:
        """Preload stage (per the variant) and the energetic problem on top."""
        return staged_response(session, self, fc, w6)

    def max_load(self, session: SessionLike, query: LimitQuery) -> MaxWrench:
        """One load-factor problem (or bisection on ``[0, upper]``)."""
        return searched_max_load(query)


ENERGETIC = EnergeticMethod()
