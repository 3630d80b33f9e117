"""The energetic method (maximum dissipation, docs/methods.md): Alg. 1's problem plus one slip
magnitude per contact and the pairs that let a friction edge carry force only if it points
most against the slip; one mixed-integer problem, no wedging artefact. Default variant:
preload-first on the iterative scheme's preload stage (whose residual it carries); default
search: one load-factor problem (:attr:`ProblemKind.ENERGETIC_LOAD`) whose optimum is the
equilibrium at the limit."""

from __future__ import annotations

import numpy as np

from ..core.settings import Method
from ..solvers.base import Mode
from ..solvers.problem import ProblemKind
from .context import SolveContext
from .method_base import MethodBase
from .stages import Stage, prp_stage


class EnergeticMethod(MethodBase):
    """Rules of ``method="energetic"`` where it differs from
    :class:`~pinograsp.analysis.method_base.MethodBase`."""

    load_kind = ProblemKind.ENERGETIC
    load_factor_kind = ProblemKind.ENERGETIC_LOAD
    refines = True
    limit_point = True
    preload_from = Method.ITERATIVE.value
    carries_residual = True

    def stage(
        self, session: SolveContext, w: np.ndarray, fc: np.ndarray, p: np.ndarray, start: Mode | None
    ) -> Stage:
        """The energetic problem at the reduced wrench ``w`` on pre-compression ``p``."""
        return prp_stage(session, w, fc, p, ProblemKind.ENERGETIC)
