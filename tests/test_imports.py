"""Lazy imports: `import pinograsp`, the URDF side, `pinograsp scenes` and `--help` load neither
the solvers nor cvxpy (cvxpy alone took 1.0–1.5 s of a 2.0–2.4 s `import pinograsp`)."""

import pytest
from support.probes import loaded

HEAVY = ("cvxpy", "pinograsp.solvers", "pinograsp.analysis.response", "pinograsp.analysis.max_wrench")


def _loaded(code: str) -> list[str]:
    return loaded(code, HEAVY)


@pytest.mark.parametrize(
    "code",
    [
        "import pinograsp",
        "import pinograsp as pg; pg.GraspModel; pg.Contact; pg.MaxWrench",
        "import pinograsp.robots.hand",
        "import pinograsp.core, pinograsp.core.examples",
        "import pinograsp as pg; pg.evaluate_grasps; pg.sample_grasps; pg.load_grasps; pg.GraspSpec",
        "from pinograsp.cli import main; main(['scenes'])",
        "from pinograsp.cli import main\ntry:\n    main(['--help'])\nexcept SystemExit:\n    pass",
    ],
)
def test_light_paths_load_no_solver(code):
    assert _loaded(code) == []


def test_public_names_resolve_lazily():
    import pinograsp as pg

    for name in pg.__all__:
        assert getattr(pg, name) is not None, name
    assert _loaded("import pinograsp as pg; pg.passive_response") == [
        "pinograsp.solvers",
        "pinograsp.analysis.response",
    ]  # the solver side on first use, still without cvxpy (the default branch-and-bound)


def _type_checking_imports() -> dict[str, str]:
    """``{name: module}`` of the ``if TYPE_CHECKING:`` block of ``pinograsp/__init__.py``."""
    import ast
    from pathlib import Path

    import pinograsp as pg

    tree = ast.parse(Path(pg.__file__).read_text())
    block = [n for n in tree.body if isinstance(n, ast.If) and ast.unparse(n.test) == "TYPE_CHECKING"]
    assert len(block) == 1
    out = {}
    for node in block[0].body:
        assert isinstance(node, ast.ImportFrom) and node.level == 1, ast.unparse(node)
        for alias in node.names:
            assert alias.asname == alias.name, f"{alias.name}: re-export it as `{alias.name} as {alias.name}`"
            out[alias.name] = node.module or ""
    return out


def test_type_checkers_see_every_lazy_name():
    """The ``TYPE_CHECKING`` imports (what mypy/pyright see) name exactly the lazily imported names,
    from the same modules: a name added to ``_LAZY`` must be added there too."""
    import pinograsp as pg

    seen = _type_checking_imports()
    expected = {name: module for name, module in pg._LAZY.items()}
    expected.update({name: module.rpartition(".")[0] for name, module in pg._MODULES.items()})
    assert seen == expected
    assert set(pg._LAZY) <= set(pg.__all__)


def test_refinement_warning_and_close_on_are_public():
    import pinograsp as pg
    from pinograsp.errors import RefinementWarning
    from pinograsp.robots.autoclose import close_on

    assert pg.RefinementWarning is RefinementWarning and "RefinementWarning" in pg.__all__
    assert pg.close_on is close_on
