"""What the stages and the response assembly need of a session: its model, scaled formulation,
settings and the one path to the solvers (:class:`SolveContext`).

:class:`~pinograsp.analysis.response.Session` implements it; the stages
(:mod:`pinograsp.analysis.stages`) and :mod:`pinograsp.analysis.assemble` only see this
protocol, so they never import the session (and the session may import them).
"""

from __future__ import annotations

from typing import Protocol

from ..core.model import GraspModel
from ..core.settings import Settings
from ..solvers.base import Mode, RawSolution
from ..solvers.formulation import Formulation, ScaledData
from ..solvers.problem import Problem, ProblemKind


class SolveContext(Protocol):
    """A session as the stages see it.

    Attributes:
        model: The model analysed (normal uncertainty applied).
        form: Its scaled formulation.
        settings: The validated settings.
    """

    model: GraspModel
    settings: Settings

    @property
    def form(self) -> Formulation:
        """The scaled formulation (built on first use)."""
        ...

    def solve(
        self, kind: ProblemKind, data: ScaledData, guess: Mode | None = None, t_max: float | None = None
    ) -> RawSolution:
        """Solve one scaled problem of ``kind`` with the settings' backend (``t_max``: the load
        factor's limit of load kinds)."""
        ...

    def solve_fixed_mode(self, problem: Problem, mode: Mode) -> RawSolution:
        """The optimum of ``problem`` with every complementarity pair fixed by ``mode``."""
        ...
