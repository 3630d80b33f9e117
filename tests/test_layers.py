"""The package's layers hold (docs/design.md): imports only point down, no import cycles, the
light entry points load no solver, and no module or function outgrows a newcomer's reading."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from support.probes import loaded

PACKAGE = Path(__file__).resolve().parents[1] / "pinograsp"

#: Rank of each layer (a folder, or a top-level module); a module may import its own layer and
#: lower ranks. ``analysis`` and ``robots`` share a rank and must not import each other.
RANKS = {
    "errors": 0,
    "core": 1,
    "solvers": 2,
    "analysis": 3,
    "robots": 3,
    "scenes": 4,
    "sim": 4.5,
    "batch": 5,
    "planning": 5.5,
    "viz": 6,
    "cli": 7,
    "__init__": 8,
}
#: Layers that call the curated public API (``import pinograsp``) rather than the layers below.
PUBLIC_API_USERS = ("cli",)
#: Longest module [lines] and function [lines, def to last line]; plotting functions may be longer.
MAX_MODULE = 500
MAX_FUNCTION = 80
PLOTTING = ("viz",)


def _modules() -> dict[str, Path]:
    out = {}
    for p in sorted(PACKAGE.rglob("*.py")):
        parts = p.relative_to(PACKAGE).with_suffix("").parts
        out[".".join(parts)] = p
    return out


MODULES = _modules()


def _layer(module: str) -> str:
    return module.split(".")[0]


def _type_checking_lines(tree: ast.AST) -> set[int]:
    lines: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for sub in node.body:
                lines.update(range(sub.lineno, (sub.end_lineno or sub.lineno) + 1))
    return lines


def _resolve(module: str, node: ast.ImportFrom | ast.Import) -> list[str]:
    """The package modules an import statement of ``module`` loads (relative or absolute)."""
    if isinstance(node, ast.Import):
        if any(a.name == "pinograsp" for a in node.names):
            return ["__init__"]
        names = [a.name.removeprefix("pinograsp.") for a in node.names if a.name.startswith("pinograsp.")]
        return [n for n in names if n in MODULES or f"{n}.__init__" in MODULES]
    if node.level:
        pkg = module.split(".")[:-1]
        base = pkg[: len(pkg) - (node.level - 1)]
    elif (node.module or "").startswith("pinograsp"):
        base = []
    else:
        return []
    stem = (node.module or "").removeprefix("pinograsp").lstrip(".")
    target = ".".join(base + ([stem] if stem else []))
    if not target:  # ``from pinograsp import X`` / ``from .. import X`` at the top: the public API
        subs = [a.name for a in node.names if a.name in MODULES or f"{a.name}.__init__" in MODULES]
        return [s if s in MODULES else f"{s}.__init__" for s in subs] or ["__init__"]
    out = []
    for alias in node.names:
        full = f"{target}.{alias.name}" if target else alias.name
        if full in MODULES or f"{full}.__init__" in MODULES:
            out.append(full)
        elif target in MODULES or f"{target}.__init__" in MODULES:
            out.append(target)
    return [o if o in MODULES else f"{o}.__init__" for o in out if o]


def _imports(type_only: bool = False) -> dict[str, set[str]]:
    """Every module's imports of package modules: module level and inside functions; those under
    ``if TYPE_CHECKING:`` only with ``type_only``."""
    graph: dict[str, set[str]] = {}
    for module, path in MODULES.items():
        tree = ast.parse(path.read_text())
        skip = set() if type_only else _type_checking_lines(tree)
        deps: set[str] = set()
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)) and node.lineno not in skip:
                deps.update(d for d in _resolve(module, node) if d != module)
        graph[module] = deps
    return graph


GRAPH = _imports()
#: With the imports of type hints: a cycle there is still two modules that need each other.
GRAPH_WITH_TYPES = _imports(type_only=True)


def test_the_import_parser_sees_the_known_edges():
    assert "core.model" in GRAPH["analysis.response"]
    assert "errors" in GRAPH["core.contact"]
    assert any(d.startswith("solvers") for d in GRAPH["analysis.response"])


def test_imports_point_down():
    upward = []
    for module, deps in GRAPH.items():
        me = _layer(module)
        for dep in deps:
            them = _layer(dep)
            if them == me or (them == "__init__" and me in PUBLIC_API_USERS):
                continue
            if RANKS[them] >= RANKS[me]:
                upward.append(f"{module} -> {dep}")
    assert upward == []


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every import cycle of ``graph``, of any length: the strongly connected components with
    more than one module (Tarjan), each sorted; a module importing itself is not an edge here."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []

    def visit(m: str) -> None:
        index[m] = low[m] = len(index)
        stack.append(m)
        on_stack.add(m)
        for d in sorted(graph.get(m, ())):
            if d not in index:
                visit(d)
                low[m] = min(low[m], low[d])
            elif d in on_stack:
                low[m] = min(low[m], index[d])
        if low[m] == index[m]:
            component = []
            while True:
                x = stack.pop()
                on_stack.discard(x)
                component.append(x)
                if x == m:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for m in sorted(graph):
        if m not in index:
            visit(m)
    return sorted(out)


def test_the_cycle_finder_finds_long_cycles():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": {"f"}, "f": {"e"}, "g": set()}
    assert cycles(graph) == [["a", "b", "c"], ["e", "f"]]
    assert cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


def test_no_import_cycles():
    """Module-level and function-level imports form no cycle, of any length."""
    assert cycles(GRAPH) == []


def test_no_import_cycles_even_for_type_hints():
    """With the imports of type hints (``if TYPE_CHECKING:``) too: a cycle there is still modules
    that need each other (e.g. ``robots``: the hand calls auto-close, so auto-close, collision and
    kinematics read a :class:`~pinograsp.robots.hand_protocol.HandLike`, not the ``Hand``)."""
    assert cycles(GRAPH_WITH_TYPES) == []


def test_no_cycles_between_layers():
    """Folders as nodes (type-hint imports included): no chain of imports between folders comes
    back to where it started."""
    layers: dict[str, set[str]] = {}
    for module, deps in GRAPH_WITH_TYPES.items():
        layers.setdefault(_layer(module), set()).update(
            _layer(d) for d in deps if _layer(d) != _layer(module)
        )
    assert cycles(layers) == []


#: Stand-ins still present while issue 24 item 3 replaces ``solver: Any`` by a typed protocol in
#: the stages and response assembly (branch h-registry). Empty this set when they are gone.
BEING_REPLACED: set[str] = set()


def test_no_any_stand_in_aliases():
    """No module names a type ``X = Any`` (a stand-in that erases a real type to dodge an import)."""
    stand_ins = set()
    for module, path in MODULES.items():
        for node in ast.parse(path.read_text()).body:
            if isinstance(node, ast.Assign) and ast.unparse(node.value) in ("Any", "typing.Any"):
                stand_ins.add(f"{module}: {ast.unparse(node)}")
    assert stand_ins == BEING_REPLACED


def test_the_hand_is_what_the_algorithms_read():
    from pinograsp.robots.hand import Hand
    from pinograsp.robots.hand_protocol import HandLike

    hand = Hand.builtin("underactuated_2f")
    assert isinstance(hand, HandLike)
    assert "robots.hand" not in GRAPH_WITH_TYPES["robots.autoclose"] | GRAPH_WITH_TYPES["robots.collision"]


def test_every_layer_is_a_folder_with_a_docstring():
    for layer in RANKS:
        if layer in ("errors", "__init__"):
            continue
        init = PACKAGE / layer / "__init__.py"
        assert init.exists(), layer
        assert ast.get_docstring(ast.parse(init.read_text())), layer
    assert {_layer(m) for m in MODULES} <= set(RANKS) | {"__main__"}


def test_modules_and_functions_stay_small():
    long_modules = {m: n for m, p in MODULES.items() if (n := len(p.read_text().splitlines())) > MAX_MODULE}
    long_functions = []
    for module, path in MODULES.items():
        if _layer(module) in PLOTTING:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = (node.end_lineno or node.lineno) - node.lineno + 1
                if n > MAX_FUNCTION:
                    long_functions.append(f"{module}.{node.name}: {n}")
    assert long_modules == {}
    assert long_functions == []


@pytest.mark.parametrize(
    "code",
    [
        "import pinograsp.core",
        "import pinograsp.core.model, pinograsp.core.examples, pinograsp.core.settings",
        "import pinograsp.robots.grasp, pinograsp.robots.closing",
        "import pinograsp as pg; pg.load_scene('case1')",
    ],
)
def test_light_entry_points_load_no_cvxpy(code):
    assert loaded(code, ("cvxpy",)) == []


def test_core_and_robots_load_no_solver():
    heavy = ("pinograsp.solvers", "pinograsp.analysis", "cvxpy", "daqp", "proxsuite")
    assert loaded("import pinograsp.core.model, pinograsp.core.examples", heavy) == []
    assert loaded("import pinograsp.robots.grasp, pinograsp.robots.closing", heavy) == []
    assert loaded("import pinograsp.core.model", ("pinocchio", "coal")) == []
