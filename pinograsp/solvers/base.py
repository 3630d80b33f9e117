"""Common types of the solver layer: the raw scaled solution and the mode of a solution."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .formulation import Layout


class SolveStatus(str, Enum):
    """Outcome of one solve at the solver boundary (a ``str`` enum: members equal their value)."""

    #: A proven optimum (within the backend's relative tolerance).
    OPTIMAL = "optimal"
    #: No point satisfies the constraints.
    INFEASIBLE = "infeasible"
    #: The backend's time limit (reference MIQP backends only) stopped it.
    TIMEOUT = "timeout"
    #: The node limit (a count) stopped the branch-and-bound: not proven optimal.
    NODE_LIMIT = "node_limit"
    #: The backend failed (numerical trouble, crash): no trustworthy answer.
    FAILED = "failed"


# Short names of the members.
OPTIMAL = SolveStatus.OPTIMAL
INFEASIBLE = SolveStatus.INFEASIBLE
TIMEOUT = SolveStatus.TIMEOUT
NODE_LIMIT = SolveStatus.NODE_LIMIT
FAILED = SolveStatus.FAILED


@dataclass(frozen=True)
class Mode:
    """A complementarity mode: which contacts touch and which actuators move.

    Attributes:
        touching: (nc,) True where the contact spring is compressed (``c_n = k delta``).
        moving: (na,) True where a non-backdrivable actuator moves at its command (``f = f_c``);
            meaningless (False) for backdrivable and locked actuators.
        edges: Energetic problems only, one per friction edge with a tangential part: True
            where the edge may carry force (it points most against the contact's slip), False
            where its weight is zero; empty otherwise.
    """

    touching: tuple[bool, ...]
    moving: tuple[bool, ...]
    edges: tuple[bool, ...] = ()


@dataclass(frozen=True, eq=False)
class RawSolution:
    """A solution of one scaled problem (see :mod:`pinograsp.solvers.formulation`).

    Attributes:
        status: :class:`SolveStatus`.
        z: Scaled variables, or None when there is no solution.
        mode: Complementarity mode of the solution, or None.
        objective: Scaled objective value.
        solve_time: Wall time in the backend [s].
        backend: Name of the backend that produced ``z``.
        bigm_ratio: Largest ``|value| / M`` over the big-M-bounded quantities (0 if no big-M).
        bigm_retries: How many times the big-M constants were enlarged.
        polished: Whether ``z`` comes from the exact fixed-mode QP (exact complementarity).
        message: Extra backend information.
        layout: The problem's variable layout (``raw.layout.beta``), or None without ``z``.
    """

    status: SolveStatus
    z: np.ndarray | None = None
    mode: Mode | None = None
    objective: float = float("nan")
    solve_time: float = 0.0
    backend: str = ""
    bigm_ratio: float = 0.0
    bigm_retries: int = 0
    polished: bool = False
    message: str = ""
    layout: Layout | None = None
