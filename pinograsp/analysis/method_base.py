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

from ..core.results import MaxWrench, PassiveResponse
from .limit_search import searched_max_load
from .protocols import LimitQuery, MethodRules, SessionLike
from .staged import staged_response


class MethodBase(MethodRules):
    """A method's implementation: :class:`~pinograsp.analysis.protocols.MethodRules` (its row,
    its flags with their defaults, ``stage``, ``floor``, ``preload_error``) plus the defaults of a
    *staged* method for :meth:`response` and :meth:`max_load`. Subclass it and override only
    what differs."""

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


__all__ = ["MethodBase"]
