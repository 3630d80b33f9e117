"""The contracts of the analysis layer: what a method
may ask of a session (:class:`SessionLike`), and the records a max-load query carries
(:class:`LimitQuery`, :class:`Tally`, :class:`LoadFactor`).

A method (``analysis/method_*.py``) subclasses
:class:`~pinograsp.analysis.method_base.MethodBase` and is named by its row of the method table
(:mod:`pinograsp.core.methods`); the session
(:class:`~pinograsp.analysis.response.PassiveSolver`) implements :class:`SessionLike`. Neither
imports the other: both meet here (docs/design.md, "Adding a method").
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

import numpy as np

from ..core.model import GraspModel
from ..core.results import PassiveResponse
from ..core.settings import DEFAULT_METHOD, Search, Settings
from ..errors import AuditWarning, SolverError, SolverTimeoutError
from ..solvers.base import SolveStatus
from .context import SolveContext
from .stages import Stage

if TYPE_CHECKING:  # the base class of methods builds on this module's records
    from .method_base import MethodBase


@dataclass(frozen=True)
class LoadFactor:
    """Answer of :meth:`SessionLike.max_load_factor`.

    Attributes:
        status: :class:`~pinograsp.solvers.base.SolveStatus`.
        magnitude: Largest resistible magnitude [N or N·m] (``inf``: the search limit).
        solve_time: Wall time [s].
        model: The refined model the answer was found on (``Settings.cone_tolerance``), or None.
        response: For a method whose load-factor point is its own equilibrium
            (:attr:`MethodBase.limit_point`, the energetic one): the equilibrium at the limit
            (at ``magnitude`` or at ``upper``), else None.
    """

    status: SolveStatus
    magnitude: float
    solve_time: float
    model: GraspModel | None = None
    response: PassiveResponse | None = None


class SessionLike(SolveContext, Protocol):
    """A session as a method sees it (implemented by
    :class:`~pinograsp.analysis.response.PassiveSolver`)."""

    def rules(self, method: str) -> MethodBase:
        """The registered method named ``method``."""
        ...

    def has_preload(self, command: np.ndarray, method: str) -> bool:
        """Whether the preload stage of ``method`` under ``command`` is solved already."""
        ...

    def preload_stage(self, command: np.ndarray, method: str) -> Stage:
        """The preload alone (``w = 0``) solved by ``method``, kept per command."""
        ...

    def response(self, command: object, wrench: object, method: str = DEFAULT_METHOD) -> PassiveResponse:
        """The passive response to ``wrench`` (6,) [N, N·m] under ``command``."""
        ...

    def max_load_factor(
        self, command: object, direction: np.ndarray, upper: float, method: str = "prp"
    ) -> LoadFactor:
        """The largest resistible magnitude along a unit direction in one solve."""
        ...

    def plain(self, model: GraspModel) -> SessionLike:
        """A session of ``model`` with these settings but no further cone refinement."""
        ...


def verdict(resp: PassiveResponse, magnitude: float) -> bool:
    """The verdict of ``resp`` at ``magnitude``; raise when the solver gave none."""
    if resp.status == "node_limit":
        raise SolverError(
            f"branch-and-bound node limit reached at magnitude {magnitude:.6g} (raise Settings.max_nodes)",
            solver=resp.solver,
            status="node_limit",
        )
    if resp.status == "timeout":
        raise SolverTimeoutError(
            f"solver timed out at magnitude {magnitude:.6g}", solver=resp.solver, status="timeout"
        )
    if resp.status == "failed":
        raise SolverError(
            f"solver failed at magnitude {magnitude:.6g} (no trustworthy verdict)",
            solver=resp.solver,
            status="failed",
        )
    return resp.resistible


@dataclass
class Tally:
    """What one max-wrench query has spent and seen so far (filled in as the search goes).

    Attributes:
        solve_time: Solver wall time [s].
        n_solves: Complementarity problems solved.
        evidence: Every magnitude tried and its verdict, in order.
        flagged: Resisted magnitudes whose solution fails the audit, with that response.
    """

    solve_time: float = 0.0
    n_solves: int = 0
    evidence: list[tuple[float, bool]] = field(default_factory=list)
    flagged: list[tuple[float, PassiveResponse]] = field(default_factory=list)

    def add(self, resp: PassiveResponse) -> None:
        """Count a response's solver time and solves."""
        self.solve_time += resp.solve_time
        self.n_solves += resp.n_solves

    def flag(self, magnitude: float, resp: PassiveResponse) -> None:
        """Keep a resisted response that fails the audit (warned about once, at the end)."""
        if resp.resistible and resp.audit is not None and not resp.audit.ok:
            self.flagged.append((magnitude, resp))


@dataclass(frozen=True)
class LimitQuery:
    """One max-wrench query, validated: what it asks and its running tally.

    Attributes:
        session: The session answering it.
        command: Actuator commands as given (validated by the session).
        direction: Unit wrench direction (6,).
        method: The method's rules.
        upper: Search limit [N or N·m along the direction].
        steps: Search steps (resolution ``upper / 2**steps``).
        search: The search (``"auto"`` resolved).
        floor: Smallest magnitude distinguishable from zero.
        t0: ``time.perf_counter()`` at the start (wall time of the result).
        tally: Solves, evidence and audit failures so far.
    """

    session: SessionLike
    command: object
    direction: np.ndarray
    method: MethodBase
    upper: float
    steps: int
    search: Search
    floor: float
    t0: float
    tally: Tally

    @property
    def settings(self) -> Settings:
        """The session's settings."""
        return self.session.settings

    def test(self, magnitude: float, session: SessionLike | None = None) -> tuple[bool, PassiveResponse]:
        """The verdict at ``magnitude`` [N or N·m] along the direction, recorded in the tally
        (``session``: another session than the query's, e.g. on a refined model)."""
        with warnings.catch_warnings():  # summarised once, after the search
            warnings.simplefilter("ignore", AuditWarning)
            resp = (session or self.session).response(
                self.command, magnitude * self.direction, self.method.name
            )
        self.tally.add(resp)
        ok = verdict(resp, magnitude)
        self.tally.evidence.append((magnitude, ok))
        self.tally.flag(magnitude, resp)
        return ok, resp
