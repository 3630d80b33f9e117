import pytest

from pinograsp import examples

A, L, MU, TAU = 0.05, 0.1, 0.5, 1.0


@pytest.fixture(scope="session")
def pinch():
    return examples.pinch(a=A, L=L, mu=MU)
