"""The PRP (seed Alg. 1): one mixed-integer problem per stage, minimise the spring energy
``|c_n|^2`` subject to equilibrium, friction, springs and actuation. Admits the wedging
artefact (docs/methods.md). Default variant: the paper's single step; default search: the
paper's bisection; ``search="direct"``: one load-factor problem (:attr:`ProblemKind.LOAD`)."""

from __future__ import annotations

import numpy as np

from ..solvers.base import Mode
from ..solvers.problem import ProblemKind
from .context import SolveContext
from .method_base import MethodBase
from .stages import Stage, prp_stage


class PrpMethod(MethodBase):
    """Rules of ``method="prp"`` where it differs from :class:`~pinograsp.analysis.method_base.MethodBase`."""

    load_kind = ProblemKind.PRP
    load_factor_kind = ProblemKind.LOAD
    refines = True

    def stage(
        self, session: SolveContext, w: np.ndarray, fc: np.ndarray, p: np.ndarray, start: Mode | None
    ) -> Stage:
        """Alg. 1 at the reduced wrench ``w`` on pre-compression ``p``."""
        return prp_stage(session, w, fc, p)
