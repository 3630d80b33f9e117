"""Solver layer: the shared problem description, pinograsp's exact branch-and-bound (DAQP node
QPs) and the reference cvxpy MIQP backend (docs/solvers.md).

Solvers never import Pinocchio or Coal; they only see a :class:`~pinograsp.GraspModel`.
"""

from .base import FAILED, INFEASIBLE, NODE_LIMIT, OPTIMAL, TIMEOUT, Mode, RawSolution, SolveStatus
from .bnb import BranchAndBound
from .formulation import Formulation, ScaledData
from .miqp import MIQP_SOLVERS, CvxpyMIQP, available_miqp_solvers, resolve_solver
from .problem import PairKind, Problem, ProblemKind, build_problem
from .solve import Backend, BackendOptions, solve

__all__ = [
    "FAILED",
    "INFEASIBLE",
    "MIQP_SOLVERS",
    "NODE_LIMIT",
    "OPTIMAL",
    "TIMEOUT",
    "Backend",
    "BackendOptions",
    "BranchAndBound",
    "CvxpyMIQP",
    "Formulation",
    "Mode",
    "PairKind",
    "Problem",
    "ProblemKind",
    "RawSolution",
    "ScaledData",
    "SolveStatus",
    "available_miqp_solvers",
    "build_problem",
    "resolve_solver",
    "solve",
]
