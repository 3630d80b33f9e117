"""The implementations of the method table's rows (docs/design.md, "Adding a method").

Every solver-free fact about a method (name, searches, variants, whether ``upper``/``steps``
apply, help text) is its row of :mod:`pinograsp.core.methods`; every rule that needs a solver
is its :class:`~pinograsp.analysis.method_base.MethodBase` subclass, in the module the row
names, imported here on use. A new method is one row and one module: nothing in this file
changes.
"""

from __future__ import annotations

from importlib import import_module

from ..core.methods import method_names, method_spec
from ..core.settings import Search
from ..errors import InvalidInputError
from .method_base import MethodBase


def available_methods() -> tuple[str, ...]:
    """Names of the methods in the table (:func:`~pinograsp.core.methods.method_names`)."""
    return method_names()


def get_method(name: object) -> MethodBase:
    """The implementation of the method named ``name`` (a string or a
    :class:`~pinograsp.core.settings.Method`), built with its row.

    Raises:
        UnknownChoiceError: ``name`` is not in the table (an ``InvalidInputError`` and an
            ``UnknownNameError`` naming the valid methods).
        InvalidInputError: The row names an implementation that is not a ``MethodBase``
            subclass.
    """
    spec = method_spec(name)
    module, _, attr = spec.implementation.partition(":")
    cls = getattr(import_module(module), attr, None)
    if not (isinstance(cls, type) and issubclass(cls, MethodBase)):
        raise InvalidInputError(
            "implementation",
            f"method {spec.name!r}: implementation {spec.implementation!r} is not a "
            "pinograsp.analysis.method_base.MethodBase subclass (docs/design.md, 'Adding a method')",
        )
    return cls(spec)


def resolve_search(search: object, method: MethodBase) -> Search:
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
        who = [n for n in method_names() if kind in method_spec(n).searches]
        raise InvalidInputError(
            "search",
            f"'{kind}' exists for method={' and '.join(repr(w) for w in who)} only, "
            f"not {method.name!r} (its searches: {[s.value for s in method.searches]})",
        )
    return kind


def refining_methods() -> tuple[str, ...]:
    """Names of the methods that ``Settings.cone_tolerance`` applies to."""
    return tuple(n for n in method_names() if get_method(n).refines)


__all__ = ["available_methods", "get_method", "refining_methods", "resolve_search"]
