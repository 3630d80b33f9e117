"""Fixtures shared by the test files and the hypothesis profiles; helpers (grasps, strategies,
the CLI runner, the stress catalogue) live in ``tests/support/``. Every shared fixture is
immutable or module-scoped.

Hypothesis profiles (``HYPOTHESIS_PROFILE``, default ``ci``; docs/errors.md, "Tests that cannot
fail by chance"):

* ``ci``: derandomised (examples derived from each test's source, the same in every process and
  clone), no example database, a bounded number of examples and no deadline (limits are counts,
  never wall-clock): the default suite and ``.ci/run`` pass or fail the same way every time.
* ``explore``: random examples with the local database (``.hypothesis/``), many examples; run on
  demand to look for new failures, e.g. ``HYPOTHESIS_PROFILE=explore pytest
  tests/test_fuzz_constructors.py tests/test_fuzz_api.py --hypothesis-seed=7``. Every failure
  found becomes an explicit ``@example`` or a plain regression test.
"""

import os

import pytest
from hypothesis import HealthCheck, settings
from hypothesis.database import DirectoryBasedExampleDatabase

import pinograsp as pg
from pinograsp import examples

_SUPPRESS = [HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large]
settings.register_profile(
    "ci",
    derandomize=True,
    database=None,
    max_examples=150,
    deadline=None,
    print_blob=True,
    suppress_health_check=_SUPPRESS,
)
settings.register_profile(
    "explore",
    derandomize=False,
    database=DirectoryBasedExampleDatabase(".hypothesis/examples"),
    max_examples=1000,
    deadline=None,
    print_blob=True,
    suppress_health_check=_SUPPRESS,
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


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
