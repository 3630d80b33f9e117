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
