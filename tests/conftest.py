"""Fixtures shared by the test files; helpers (grasps, strategies, the CLI runner, the stress
catalogue) live in ``tests/support/``. Every shared fixture is immutable or module-scoped."""

import pytest

import pinograsp as pg
from pinograsp import examples


@pytest.fixture(scope="session")
def pinch():
    """The analytic pinch of docs/analytic_cases.md (``examples.pinch()``; constants in
    ``support/grasps.py``)."""
    return examples.pinch()


@pytest.fixture(scope="session")
def wedge():
    """The analytic wedge of docs/analytic_cases.md (``examples.wedge()``)."""
    return examples.wedge()


@pytest.fixture(scope="session")
def case1():
    """The paper's case 1 scene (``pg.load_scene("case1")``: model, command, ...)."""
    return pg.load_scene("case1")


@pytest.fixture(scope="module")
def small_hand():
    """The smallest built-in URDF hand, the underactuated two-finger gripper."""
    return pg.Hand.builtin("underactuated_2f")


@pytest.fixture()
def close_figures():
    """Close every matplotlib figure after the test (use with ``pytest.mark.usefixtures``)."""
    yield
    import matplotlib.pyplot as plt

    plt.close("all")
