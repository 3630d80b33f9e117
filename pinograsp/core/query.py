"""The query record: how a largest-load search runs (method, upper limit, steps, search).

One validated, frozen value that scenes (their ``analysis`` block), profiles, sets, batches and
the CLI pass down instead of four loose arguments. Which searches a method supports is its
registry row's business (:func:`pinograsp.analysis.registry.resolve_search`); this record
checks each field on its own. NumPy only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..errors import InvalidInputError
from .methods import bounded as limits_bound
from .methods import method_name
from .settings import DEFAULT_METHOD, Method, Search
from .validate import choice, force
from .validate import steps as n_steps

SEARCHES = tuple(s.value for s in Search)


@dataclass(frozen=True)
class Query:
    """How :func:`~pinograsp.max_resistible_wrench` (and every profile, set and score built on
    it) searches the largest resisted magnitude along a direction.

    Attributes:
        method: ``"quasistatic"`` (default), ``"iterative"``, ``"energetic"`` or ``"prp"``
            (:class:`~pinograsp.core.settings.Method`; the default is
            :data:`~pinograsp.core.settings.DEFAULT_METHOD`).
        upper: Upper limit of the search [N or N·m along the unit direction], in [1e-6, 1e12]
            (and, for the searching methods, within 1e6 times the grasp's force scale, checked
            per query; the quasi-static path's limit is exact: ``upper`` does not decide
            unboundedness there and is not checked against the grasp).
        steps: Search steps, in [1, 60]; resolution ``upper / 2**steps``. The quasi-static
            method (a row of :mod:`pinograsp.core.methods` that is not ``bounded``) does not bisect: any whole
            number >= 1 is accepted and ignored.
        search: ``"auto"`` (the method's default), ``"bisection"``, ``"secant"``, ``"direct"``
            or ``"path"`` (:class:`~pinograsp.core.settings.Search`; ``"path"``: quasi-static,
            where ``upper`` and ``steps`` do not apply).

    Raises:
        InvalidInputError: A field out of its domain (named).
    """

    method: str = Method(DEFAULT_METHOD)
    upper: float = 1e3
    steps: int = 20
    search: Search = Search.AUTO

    def __post_init__(self) -> None:
        object.__setattr__(self, "method", method_name(self.method))
        # domains (docs/errors.md, "Input domains"); against a grasp: analysis.max_wrench.query_within
        object.__setattr__(self, "upper", force("upper", self.upper, "N or N·m"))
        bounded = limits_bound(self.method)  # an exact limit does not bisect (docs/errors.md)
        object.__setattr__(self, "steps", n_steps(self.steps, bounded=bounded))
        object.__setattr__(self, "search", Search(choice("search", self.search, SEARCHES)))

    @property
    def resolution(self) -> float:
        """``upper / 2**steps`` [N or N·m]."""
        return self.upper / 2**self.steps

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data."""
        return {
            "method": str(self.method),
            "upper": self.upper,
            "steps": self.steps,
            "search": self.search.value,
        }


def make_query(
    query: Query | None,
    method: object = DEFAULT_METHOD,
    upper: object = 1e3,
    steps: object = 20,
    search: object = "auto",
) -> Query:
    """``query``, or a :class:`Query` of the loose arguments (each validated once).

    Raises:
        InvalidInputError: ``query`` is not a :class:`Query`, or is given together with loose
            arguments other than their defaults.
    """
    if query is None:
        return Query(method, upper, steps, search)  # type: ignore[arg-type]
    if not isinstance(query, Query):
        raise InvalidInputError("query", f"expected pinograsp.Query or None, got {type(query).__name__}")
    loose = zip((method, upper, steps, search), (DEFAULT_METHOD, 1e3, 20, "auto"))
    if not all(isinstance(a, (str, int, float)) and not isinstance(a, bool) and a == b for a, b in loose):
        raise InvalidInputError("query", "pass either query= or method/upper/steps/search, not both")
    return query


__all__ = ["SEARCHES", "Query", "make_query"]
