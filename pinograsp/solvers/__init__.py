"""Solver layer: the shared problem description, pinograsp's exact branch-and-bound (DAQP node
QPs) and the reference cvxpy MIQP backend (docs/solvers.md).

Solvers never import Pinocchio or Coal; they only see a :class:`~pinograsp.GraspModel`.
"""

from ..core.settings import Backend
from .base import FAILED, INFEASIBLE, NODE_LIMIT, OPTIMAL, TIMEOUT, Mode, RawSolution, SolveStatus
from .bnb import BranchAndBound
from .formulation import Formulation, ScaledData
from .miqp import MIQP_SOLVERS, CvxpyMIQP, available_miqp_solvers, resolve_solver
from .problem import PairKind, Problem, ProblemKind, build_problem
from .solve import BACKENDS, Capabilities, SolverBackend, available_backends, make_backend

__all__ = [
    "FAILED",
    "INFEASIBLE",
    "MIQP_SOLVERS",
    "NODE_LIMIT",
    "OPTIMAL",
    "TIMEOUT",
    "BACKENDS",
    "Backend",
    "Capabilities",
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
    "SolverBackend",
    "available_backends",
    "available_miqp_solvers",
    "build_problem",
    "make_backend",
    "resolve_solver",
]
