"""The contracts of the analysis layer: what a method
may ask of a session (:class:`SessionLike`), and the records a max-load query carries
(:class:`LimitQuery`, :class:`Tally`, :class:`LoadFactor`).

A method (``analysis/method_*.py``) subclasses
:class:`~pinograsp.analysis.method_base.MethodRules` and is named by its row of the method table
(:mod:`pinograsp.core.methods`); the session
(:class:`~pinograsp.analysis.response.Session`) implements :class:`SessionLike`. Neither
imports the other: both meet here (docs/design.md, "Adding a method").
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from ..core.methods import MethodSpec
from ..core.model import GraspModel
from ..core.results import MaxWrench, PassiveResponse
from ..core.settings import DEFAULT_METHOD, Search, Settings, Variant
from ..errors import (
    AuditWarning,
    InvalidInputError,
    PreloadNotInEquilibriumError,
    SolverError,
    SolverTimeoutError,
)
from ..solvers.base import Mode, SolveStatus
from ..solvers.problem import ProblemKind
from .context import SolveContext
from .quasistatic.prepared import Prepared
from .search import grid_resolution
from .stages import Stage


@dataclass(frozen=True)
class LoadFactor:
    """Answer of :meth:`SessionLike.max_load_factor`.

    Attributes:
        status: :class:`~pinograsp.solvers.base.SolveStatus`.
        magnitude: Largest resistible magnitude [N or N·m] (``inf``: the search limit).
        solve_time: Wall time [s].
        model: The refined model the answer was found on (``Settings.cone_tolerance``), or None.
        response: For a method whose load-factor point is its own equilibrium
            (:attr:`MethodRules.limit_point`, the energetic one): the equilibrium at the limit
            (at ``magnitude`` or at ``upper``), else None.
    """

    status: SolveStatus
    magnitude: float
    solve_time: float
    model: GraspModel | None = None
    response: PassiveResponse | None = None


class SessionLike(SolveContext, Protocol):
    """A session as a method sees it (implemented by
    :class:`~pinograsp.analysis.response.Session`)."""

    def rules(self, method: str) -> MethodRules:
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

    def loading_grasp(self, command: np.ndarray, variant: str) -> Prepared:
        """The quasi-static method's prepared grasp (preloaded state) of the validated
        ``command`` (na,) and preload path ``variant``, kept per command."""
        ...

    def plain(self, model: GraspModel) -> SessionLike:
        """A session of ``model`` with these settings but no further cone refinement."""
        ...


class MethodRules:
    """One passive-response method as the analysis layer sees it: its row and the rules where
    it differs from the defaults (:class:`~pinograsp.analysis.method_base.MethodBase` adds the
    staged methods' :meth:`response` and :meth:`max_load`).

    Class attributes (override only what differs):
        load_kind: Problem kind of its load stage (the layout its responses are read with), or
            None (no complementarity stages).
        load_factor_kind: Problem kind of its largest load factor in one solve
            (``search="direct"``), or None.
        refines: Whether ``Settings.cone_tolerance`` refines its pyramids.
        exact: Its equilibria are exact (a residual above the audit tolerance makes a resisted
            verdict ``"failed"``); False for a scheme converged to a tolerance (iterative).
        limit_point: Its load-factor problem's optimum is an equilibrium of its own problem (the
            direct search needs no other solve).
        preload_from: Whose preload stage it loads on top of (preload-first variant); None: its
            own.
        carries_residual: Its load stage balances the load plus the net wrench an inexact
            preload stage left (energetic on the iterative preload).
        preload_kept: Its preload check (``max_resistible_wrench``'s verdict at ``w = 0``) is a
            pure function of the session and the commands, so a session makes it once per
            command.
        preload_by_error: Its :meth:`preload_error` hook alone decides the preload check (the
            preload is a path of its own: no zero-load solve is needed to know it holds).

    Attributes:
        spec: Its row of the method table.
    """

    load_kind: ProblemKind | None = None
    load_factor_kind: ProblemKind | None = None
    refines: bool = False
    exact: bool = True
    limit_point: bool = False
    preload_from: str | None = None
    carries_residual: bool = False
    preload_kept: bool = False
    preload_by_error: bool = False

    def __init__(self, spec: MethodSpec) -> None:
        self.spec = spec

    @property
    def name(self) -> str:
        """The name it answers to (its row's)."""
        return self.spec.name

    @property
    def searches(self) -> tuple[Search, ...]:
        """Supported searches of the largest load, the default first (its row's)."""
        return self.spec.searches

    @property
    def default_variant(self) -> Variant:
        """The variant used when ``Settings.variant`` is None (its row's)."""
        return self.spec.default_variant

    @property
    def preload_method(self) -> str:
        """The method whose preload stage it loads on top of (``preload_from``, else itself)."""
        return self.preload_from or self.name

    def stage(
        self, session: SolveContext, w: np.ndarray, fc: np.ndarray, p: np.ndarray, start: Mode | None
    ) -> Stage:
        """One complementarity stage: the reduced wrench ``w`` [N, N·m], commands ``fc`` (na,),
        pre-compression ``p`` (nc,) [N]; ``start`` the mode the grasp is in (speed only).
        Default: refused (:class:`InvalidInputError`), for a method without stages."""
        raise InvalidInputError("method", f"{self.name!r} has no complementarity stages")

    def floor(self, session: SolveContext, direction: np.ndarray, upper: float, steps: int) -> float:
        """Smallest magnitude [N or N·m] distinguishable from zero along ``direction``. Default:
        the resolution ``upper / 2**steps`` of a bounded search, 0 for an exact limit."""
        return grid_resolution(upper, steps) if self.spec.bounded else 0.0

    def preload_error(self, session: SessionLike, command: object) -> PreloadNotInEquilibriumError | None:
        """Its own account of why the preload of ``command`` has no equilibrium (raised by the
        preload check instead of the generic one), or None. Default: None."""
        return None

    def response(self, session: SessionLike, fc: np.ndarray, w6: np.ndarray) -> PassiveResponse:
        """The response to ``w6`` (6,) [N, N·m] under commands ``fc`` (na,), non-negative
        (mirrored) commands and unrefined pyramids (the session handles both)."""
        raise NotImplementedError  # MethodBase: the staged default

    def max_load(self, session: SessionLike, query: LimitQuery) -> MaxWrench:
        """The largest load along ``query.direction`` (the preload is checked already)."""
        raise NotImplementedError  # MethodBase: the searched default


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

    def add(self, resp: PassiveResponse | None) -> None:
        """Count a response's solver time and solves (None: nothing was solved)."""
        if resp is None:
            return
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
    method: MethodRules
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
