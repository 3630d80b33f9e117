"""The PRP (seed Alg. 1): one mixed-integer problem per stage, minimise the spring energy
``|c_n|^2`` subject to equilibrium, friction, springs and actuation. Admits the wedging
artefact (docs/methods.md). Default variant: the paper's single step; default search: the
paper's bisection; ``search="direct"``: one load-factor problem (:attr:`ProblemKind.LOAD`)."""

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


class PrpMethod:
    """Rules of ``method="prp"`` (:class:`~pinograsp.analysis.protocols.AnalysisMethod`)."""

    name = Method.PRP
    load_kind: ProblemKind | None = ProblemKind.PRP
    load_factor_kind: ProblemKind | None = ProblemKind.LOAD
    default_variant = Variant.SINGLE_STEP
    searches: tuple[Search, ...] = (Search.BISECTION, Search.DIRECT)
    refines = True
    exact = True
    limit_point = False
    preload_method = Method.PRP
    carries_residual = False
    preload_kept = False

    def stage(
        self, session: SolveContext, w: np.ndarray, fc: np.ndarray, p: np.ndarray, start: Mode | None
    ) -> Stage:
        """Alg. 1 at the reduced wrench ``w`` on pre-compression ``p``."""
        return prp_stage(session, w, fc, p)

    def floor(self, session: SolveContext, direction: np.ndarray, upper: float, steps: int) -> float:
        """The search's resolution ``upper / 2**steps``."""
        return grid_resolution(upper, steps)

    def response(self, session: SessionLike, fc: np.ndarray, w6: np.ndarray) -> PassiveResponse:
        """Preload stage (per the variant) and Alg. 1 on top."""
        return staged_response(session, self, fc, w6)

    def max_load(self, session: SessionLike, query: LimitQuery) -> MaxWrench:
        """Bisection (or one load-factor problem) on ``[0, upper]``."""
        return searched_max_load(query)


PRP = PrpMethod()
