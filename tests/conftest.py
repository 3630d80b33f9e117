import pytest

from pinograsp import examples


@pytest.fixture(scope="session")
def pinch():
    """The analytic pinch of docs/analytic_cases.md (``examples.pinch()``, constants in ``grasps.py``)."""
    return examples.pinch()
