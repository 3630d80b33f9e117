"""The method table: one solver-free row per passive-response method (docs/design.md, "Adding a
method").

Every fact about a method that does not need a solver lives in its :class:`MethodSpec` row:
its name, its searches, whether a query's ``upper``/``steps`` shape its answer, its variants,
whether it has a preload stage, its help text, and where its implementation lives (imported on
use by :func:`pinograsp.analysis.registry.get_method`). Queries, scenes, batch files, the CLI,
the docs and the tests read this table; nothing keeps a second list of methods.

A new built-in method is one row of :data:`BUILT_IN` plus its module; a method defined outside
the package (a plug-in, or a test fixture) is one :func:`register_method` call plus its module.
This module imports no solver.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import InvalidInputError, UnknownChoiceError
from .settings import Method, Search, Variant


@dataclass(frozen=True)
class MethodSpec:
    """One passive-response method as the rest of the package sees it (no solver needed).

    Attributes:
        name: The name users pass as ``method=`` (scenes' ``analysis.method``, ``--method``).
        searches: The searches of its largest load, the default (``search="auto"``) first.
        implementation: Where its :class:`~pinograsp.analysis.method_base.MethodBase` subclass
            lives, ``"package.module:ClassName"`` (imported on use, never at ``import
            pinograsp``).
        help: One line for ``--help`` and error messages (what it solves, in words).
        bounded: Whether a query's ``upper`` and ``steps`` shape its largest loads (a search on
            ``[0, upper]`` with resolution ``upper / 2**steps``). False for a method that finds
            its limit exactly: ``steps`` is then ignored (any whole number >= 1), ``upper`` not
            checked against the grasp's force scale, and the resolution is 0.
        limit_text: For a method that is not ``bounded``: how it finds its limit, in words, as
            the CLI and reports print it (``{upper}`` is replaced by the query's upper and unit).
        variants: The variants (:class:`~pinograsp.core.settings.Variant`) it accepts; any
            other is refused by every entry point with the same error.
        default_variant: The variant used when ``Settings.variant`` is None (one of
            ``variants``).
        preload_stage: Whether it solves the preload alone (``w = 0``) as a stage of its own:
            ``equilibrium_preload``/``optimal_preload`` refuse a method without one.
    """

    name: str
    searches: tuple[Search, ...]
    implementation: str
    help: str
    bounded: bool = True
    limit_text: str = ""
    variants: tuple[Variant, ...] = tuple(Variant)
    default_variant: Variant = Variant.PRELOAD_FIRST
    preload_stage: bool = True

    def __post_init__(self) -> None:
        if not self.searches or any(not isinstance(s, Search) or s is Search.AUTO for s in self.searches):
            raise InvalidInputError(
                "searches", f"must be Search members other than AUTO, got {self.searches!r}"
            )
        if self.default_variant not in self.variants:
            raise InvalidInputError(
                "default_variant", f"{self.default_variant!r} is not one of the variants {self.variants!r}"
            )
        if ":" not in self.implementation:
            raise InvalidInputError(
                "implementation", f"must read 'package.module:ClassName', got {self.implementation!r}"
            )
        if not self.bounded and not self.limit_text:
            raise InvalidInputError(
                "limit_text", "a method whose upper/steps do not apply says how it finds its limit"
            )


#: The package's methods, in the order they are listed to users.
BUILT_IN: tuple[MethodSpec, ...] = (
    MethodSpec(
        name=Method.PRP.value,
        searches=(Search.BISECTION, Search.DIRECT),
        implementation="pinograsp.analysis.method_prp:PrpMethod",
        help="Alg. 1, one MIQP; admits the wedging artefact",
        default_variant=Variant.SINGLE_STEP,
    ),
    MethodSpec(
        name=Method.ITERATIVE.value,
        searches=(Search.SECANT, Search.BISECTION),
        implementation="pinograsp.analysis.method_iterative:IterativeMethod",
        help="Alg. 2+3, the paper's, no wedging",
    ),
    MethodSpec(
        name=Method.ENERGETIC.value,
        searches=(Search.DIRECT, Search.BISECTION),
        implementation="pinograsp.analysis.method_energetic:EnergeticMethod",
        help="maximum dissipation: friction opposes slip, one solve per direction",
    ),
    MethodSpec(
        name=Method.QUASISTATIC.value,
        searches=(Search.PATH,),
        implementation="pinograsp.analysis.method_quasistatic:QuasistaticMethod",
        help="the loading path followed exactly: the limit load without bisection",
        bounded=False,
        limit_text="the load at which the loading path gives way (exact; thresholds scaled by "
        "upper {upper}; steps do not apply)",
        variants=(Variant.PRELOAD_FIRST, Variant.SETTLED_PRELOAD),
    ),
)

#: The table every lookup reads: the built-in rows, then any registered with
#: :func:`register_method`.
_TABLE: dict[str, MethodSpec] = {s.name: s for s in BUILT_IN}


def register_method(spec: MethodSpec) -> None:
    """Add ``spec`` to the method table (a method defined outside the package, e.g. a test
    fixture): from then on every analysis, scene, batch file and the CLI accept its name.

    Raises:
        InvalidInputError: ``spec`` is not a :class:`MethodSpec`, or its name is taken.
    """
    if not isinstance(spec, MethodSpec):
        raise InvalidInputError(
            "spec", f"expected pinograsp.core.methods.MethodSpec, got {type(spec).__name__}"
        )
    if spec.name in _TABLE:
        raise InvalidInputError("spec", f"method {spec.name!r} is registered already")
    _TABLE[spec.name] = spec


def unregister_method(name: str) -> None:
    """Remove a method added by :func:`register_method` (built-in rows stay).

    Raises:
        InvalidInputError: ``name`` is built in or not registered.
    """
    if name in (s.name for s in BUILT_IN) or name not in _TABLE:
        raise InvalidInputError("name", f"{name!r} is not a registered (non-built-in) method")
    del _TABLE[name]


def method_names() -> tuple[str, ...]:
    """The names of every method in the table, in the order they are listed to users."""
    return tuple(_TABLE)


def method_spec(name: object) -> MethodSpec:
    """The row of the method named ``name`` (a string or a :class:`Method`).

    Raises:
        UnknownChoiceError: ``name`` is not in the table (an ``InvalidInputError`` naming the
            valid methods).
    """
    key = name.value if isinstance(name, Method) else name
    if not isinstance(key, str) or key not in _TABLE:
        raise UnknownChoiceError("method", name, method_names())
    return _TABLE[key]


def method_name(name: object, field: str = "method") -> str:
    """``name`` checked against the table: the :class:`Method` member for a built-in method,
    else the registered name (a ``str`` either way).

    Raises:
        InvalidInputError: ``name`` is not in the table; the message names ``field`` and the
            valid methods.
    """
    key = name.value if isinstance(name, Method) else name
    if not isinstance(key, str) or key not in _TABLE:
        raise InvalidInputError(field, f"must be one of {method_names()}, got {name!r}")
    return Method(key) if key in Method._value2member_map_ else key


def bounded(method: object) -> bool:
    """Whether a query's ``upper`` and ``steps`` shape ``method``'s answer
    (:attr:`MethodSpec.bounded`)."""
    return method_spec(method).bounded


def method_variant(method: object, variant: object) -> Variant:
    """The variant ``method`` runs under ``Settings.variant = variant`` (None: its default).
    The one rule every entry point applies (the API, scenes, batch files and the CLI).

    Raises:
        InvalidInputError: ``variant`` is not a variant, or one ``method`` does not accept (the
            message names the ones it does).
    """
    spec = method_spec(method)
    if variant is None:
        return spec.default_variant
    valid = [v.value for v in Variant]
    key = variant.value if isinstance(variant, Variant) else variant
    if not isinstance(key, str) or key not in valid:
        raise InvalidInputError("variant", f"must be one of {tuple(valid)} or None, got {variant!r}")
    v = Variant(key)
    if v not in spec.variants:
        raise InvalidInputError(
            "variant",
            f"{v.value!r} does not apply to method={spec.name!r}: one of "
            f"{[x.value for x in spec.variants]} or None (its default: {spec.default_variant.value!r})",
        )
    return v


def preload_method(method: object, what: str) -> str:
    """``method`` checked against the table for a preload design (``what``: the function that
    asks, e.g. ``"equilibrium_preload"``), which needs a preload stage of its own.

    Raises:
        InvalidInputError: ``method`` is not in the table, or has no preload stage
            (:attr:`MethodSpec.preload_stage`); the message names the methods that have one.
    """
    name = method_name(method)
    if not method_spec(name).preload_stage:
        staged = [n for n in method_names() if _TABLE[n].preload_stage]
        raise InvalidInputError(
            "method",
            f"{str(name)!r} has no preload stage (it solves preload and load together), so "
            f"{what} cannot verify a preload with it: use one of {staged}",
        )
    return name


def search_text(method: object, upper: float, steps: int, unit: str = "") -> str:
    """How ``method`` finds a largest load, in words: ``"upper 1000 N, 20 steps (resolution
    0.00095 N)"`` for a bounded search, else the row's :attr:`MethodSpec.limit_text`."""
    spec = method_spec(method)
    u = f" {unit}" if unit else ""
    if not spec.bounded:
        return spec.limit_text.replace("{upper}", f"{upper:g}{u}")
    return f"upper {upper:g}{u}, {steps} steps (resolution {upper / 2**steps:.2g}{u})"


def search_resolution(method: object, upper: float, steps: int) -> float:
    """The resolution of ``method``'s largest loads [N or N·m]: ``upper / 2**steps``, or 0 for
    a method that is not ``bounded`` (its limit is exact)."""
    return upper / 2**steps if method_spec(method).bounded else 0.0


def methods_help() -> str:
    """Every method with its help line, as ``--method`` lists them."""
    return ", ".join(f"{s.name} ({s.help})" for s in _TABLE.values())


__all__ = [
    "BUILT_IN",
    "MethodSpec",
    "bounded",
    "method_name",
    "method_names",
    "method_spec",
    "method_variant",
    "preload_method",
    "methods_help",
    "register_method",
    "search_resolution",
    "search_text",
    "unregister_method",
]
