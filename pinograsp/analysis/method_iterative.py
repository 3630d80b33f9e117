"""The iterative scheme (seed Alg. 2 inside Alg. 3): the object may only move along the current
net wrench (a step in ``[0, gamma]``), each step minimises the net wrench, repeat until it falls
below ``eps`` (resisted) or stops improving (not resisted). No wedging artefact. Default
variant: preload-first (the object held still while the hand closes); default search: the
grid-snapped secant on the final net wrench (:mod:`pinograsp.analysis.search`)."""

from __future__ import annotations

import numpy as np

from ..solvers.base import Mode
from ..solvers.problem import ProblemKind
from .context import SolveContext
from .method_base import MethodBase
from .search import grid_resolution
from .stages import Stage, iterative_stage


class IterativeMethod(MethodBase):
    """Rules of ``method="iterative"`` where it differs from
    :class:`~pinograsp.analysis.method_base.MethodBase`."""

    load_kind = ProblemKind.MOVE  # a trajectory: no one-solve limit (no load_factor_kind)
    exact = False  # converged to the tolerance eps + eps_rel F

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
