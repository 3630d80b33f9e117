"""The method registry: one row per passive-response method (docs/design.md, "Adding a method").

Every rule that differs between methods — its problem kinds, preload stage, variant and search
defaults, whether it refines pyramids, how it finds the largest load — lives in its module
(``analysis/method_*.py``) as an :class:`~pinograsp.analysis.protocols.AnalysisMethod`; the rest
of the package asks this table. A new method is one module and one row of :data:`METHODS`
(plus its name in :class:`~pinograsp.core.settings.Method`).
"""

from __future__ import annotations

from ..core.settings import Method, Search
from ..errors import InvalidInputError, UnknownChoiceError
from .method_energetic import ENERGETIC
from .method_iterative import ITERATIVE
from .method_prp import PRP
from .method_quasistatic import QUASISTATIC
from .protocols import AnalysisMethod
from .search import grid_resolution

#: The registered methods, in the order they are listed to users.
METHODS: dict[str, AnalysisMethod] = {m.name.value: m for m in (PRP, ITERATIVE, ENERGETIC, QUASISTATIC)}


def available_methods() -> tuple[str, ...]:
    """Names of the registered methods."""
    return tuple(METHODS)


def get_method(name: object) -> AnalysisMethod:
    """The method registered as ``name`` (a string or a
    :class:`~pinograsp.core.settings.Method`).

    Raises:
        UnknownChoiceError: ``name`` is not registered (an ``InvalidInputError`` and an
            ``UnknownNameError`` naming the valid methods).
    """
    key = name.value if isinstance(name, Method) else name
    if not isinstance(key, str) or key not in METHODS:
        raise UnknownChoiceError("method", name, available_methods())
    return METHODS[key]


def resolve_search(search: object, method: AnalysisMethod) -> Search:
    """The search ``search`` names for ``method`` (``"auto"``: the method's default).

    Raises:
        InvalidInputError: An unknown search, or one ``method`` does not support.
    """
    valid = [x.value for x in Search]
    if not isinstance(search, str) or search not in valid:
        raise InvalidInputError("search", f"must be one of {tuple(valid)}, got {search!r}")
    kind = Search(search)
    if kind is Search.AUTO:
        return method.searches[0]
    if kind not in method.searches:
        who = [m.name.value for m in METHODS.values() if kind in m.searches]
        raise InvalidInputError(
            "search",
            f"'{kind}' exists for method={' and '.join(repr(w) for w in who)} only, "
            f"not {method.name.value!r} (its searches: {[s.value for s in method.searches]})",
        )
    return kind


def limits_apply(method: object) -> bool:
    """Whether a query's ``upper`` and ``steps`` shape ``method``'s largest loads (False for a
    method whose one search follows a path to its exact limit: ``"quasistatic"``)."""
    return get_method(method).searches != (Search.PATH,)


def search_resolution(method: object, upper: float, steps: int) -> float:
    """The resolution of ``method``'s largest loads [N or N·m]: ``upper / 2**steps``, or 0 for
    a path method (its limit is exact)."""
    return grid_resolution(upper, steps) if limits_apply(method) else 0.0


def search_text(method: object, upper: float, steps: int, unit: str = "") -> str:
    """How ``method`` finds a largest load, in words: ``"upper 1000 N, 20 steps (resolution
    0.00095 N)"``, or for a path method ``"the load at which the loading path gives way
    (exact; thresholds scaled by upper 1000 N; steps do not apply)"``."""
    if not limits_apply(method):
        u = f" {unit}" if unit else ""
        return (
            f"the load at which the loading path gives way (exact; thresholds scaled by upper "
            f"{upper:g}{u}; steps do not apply)"
        )
    u = f" {unit}" if unit else ""
    return f"upper {upper:g}{u}, {steps} steps (resolution {upper / 2**steps:.2g}{u})"


def refining_methods() -> tuple[str, ...]:
    """Names of the methods that ``Settings.cone_tolerance`` applies to."""
    return tuple(n for n, m in METHODS.items() if m.refines)


__all__ = [
    "METHODS",
    "available_methods",
    "get_method",
    "limits_apply",
    "refining_methods",
    "resolve_search",
    "search_resolution",
    "search_text",
]
