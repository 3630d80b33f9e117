"""The implementation side of a method: :class:`MethodBase`, whose defaults a method overrides
only where it differs (docs/design.md, "Adding a method").

A method is its row in the table (:class:`~pinograsp.core.methods.MethodSpec`: name, searches,
variants, whether ``upper``/``steps`` apply, ...) and a subclass of :class:`MethodBase` named
by that row, built with it by :func:`~pinograsp.analysis.registry.get_method`. The defaults are
those of a *staged* method (a preload stage and a load stage of complementarity problems,
:mod:`pinograsp.analysis.staged`, searched by :mod:`pinograsp.analysis.limit_search`): such a
method declares its problem kinds and writes :meth:`MethodBase.stage`. A method that answers
otherwise (a path, one LP) overrides :meth:`MethodBase.response` and :meth:`MethodBase.max_load`.
"""

from __future__ import annotations

import numpy as np

from ..core.methods import MethodSpec
from ..core.results import MaxWrench, PassiveResponse
from ..core.settings import Search, Variant
from ..errors import InvalidInputError, PreloadNotInEquilibriumError
from ..solvers.base import Mode
from ..solvers.problem import ProblemKind
from .context import SolveContext
from .limit_search import searched_max_load
from .protocols import LimitQuery, SessionLike
from .search import grid_resolution
from .staged import staged_response
from .stages import Stage


class MethodBase:
    """One passive-response method: its row and the rules where it differs from the defaults.

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

    def response(self, session: SessionLike, fc: np.ndarray, w6: np.ndarray) -> PassiveResponse:
        """The response to ``w6`` (6,) [N, N·m] under commands ``fc`` (na,), non-negative
        (mirrored) commands and unrefined pyramids (the session handles both). Default: the
        preload stage (per the variant) and the load stage on top."""
        return staged_response(session, self, fc, w6)

    def max_load(self, session: SessionLike, query: LimitQuery) -> MaxWrench:
        """The largest load along ``query.direction`` (the preload is checked already).
        Default: the query's search (bisection, secant or one load-factor problem) on
        ``[0, upper]``."""
        return searched_max_load(query)

    def preload_error(self, session: SessionLike, command: object) -> PreloadNotInEquilibriumError | None:
        """Its own account of why the preload of ``command`` has no equilibrium (raised by the
        preload check instead of the generic one), or None. Default: None."""
        return None


__all__ = ["MethodBase"]
