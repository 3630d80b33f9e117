"""Solver layer: scaled formulation, MIQP backends (cvxpy), fixed-mode QPs (ProxSuite).

Solvers never import Pinocchio or Coal; they only see a :class:`~pinograsp.GraspModel`.
"""

from .base import FAILED, INFEASIBLE, OPTIMAL, TIMEOUT, Mode, RawSolution
from .engine import ExactSolver
from .fixed_mode import FixedModeQP
from .formulation import Formulation, ScaledData
from .miqp import MIQP_SOLVERS, CvxpyMIQP, available_miqp_solvers, resolve_solver

__all__ = [
    "FAILED",
    "INFEASIBLE",
    "MIQP_SOLVERS",
    "OPTIMAL",
    "TIMEOUT",
    "CvxpyMIQP",
    "ExactSolver",
    "FixedModeQP",
    "Formulation",
    "Mode",
    "RawSolution",
    "ScaledData",
    "available_miqp_solvers",
    "resolve_solver",
]
