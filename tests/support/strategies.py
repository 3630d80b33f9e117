"""Hypothesis strategies shared by the fuzz tests: random values (NaN, inf, wrong shapes, wrong
types, empty) and the rule every public function keeps: a result or a PinograspError."""

from __future__ import annotations

import math
import os
import warnings

import numpy as np
from hypothesis import HealthCheck, event, settings
from hypothesis import strategies as st

import pinograsp as pg

# The loaded profile (tests/conftest.py: ``ci`` derandomised with no database by default,
# ``explore`` random with a database) decides everything but the count; FUZZ_EXAMPLES overrides it.
FUZZ = settings(
    max_examples=int(os.environ.get("FUZZ_EXAMPLES", settings.default.max_examples)),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large],
)
#: For the expensive tests (solver calls per example): a third of FUZZ.
FAST = settings(FUZZ, max_examples=max(10, FUZZ.max_examples // 3))
#: For the most expensive ones (a MIQP per example).
SLOW = settings(FUZZ, max_examples=max(25, FUZZ.max_examples // 6))

# ------------------------------------------------------------------------------ value strategies
floats = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1.0, -1.0, 0.5, 1e-300, 1e300, -1e300, math.nan, math.inf, -math.inf]),
)
junk = st.one_of(
    st.none(),
    st.booleans(),
    st.text(max_size=5),
    st.binary(max_size=4),
    st.complex_numbers(allow_nan=True, allow_infinity=True),
    st.just(object()),
    st.just({}),
    st.just([]),
    st.just(()),
    st.just({"a": 1}),
    st.just(np.zeros((2, 2, 2))),
    st.just(np.array(["a", "b", "c"])),
    st.just([[1.0, 2.0], [3.0]]),
)
scalars = st.one_of(floats, st.integers(min_value=-(10**20), max_value=10**20), junk)


finite = st.floats(-10.0, 10.0)


def vec(n: int) -> st.SearchStrategy:
    """Half the time ``n`` finite floats, else NaN/inf, the wrong length, type or nesting."""
    good = st.lists(floats, min_size=n, max_size=n)
    valid = st.lists(finite, min_size=n, max_size=n)
    broken = st.one_of(
        good,
        good.map(np.array),
        st.lists(floats, min_size=0, max_size=n + 2),
        st.lists(scalars, min_size=n, max_size=n),
        junk,
        scalars,
    )
    return st.one_of(st.one_of(valid, valid.map(np.array)), broken)


unit = st.sampled_from([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.6, 0.8, 0.0]])
maybe_unit = st.one_of(unit, vec(3))


def jacobians() -> st.SearchStrategy:
    shapes = st.tuples(st.integers(0, 4), st.integers(0, 4))
    arrays = shapes.flatmap(
        lambda s: st.lists(st.lists(floats, min_size=s[1], max_size=s[1]), min_size=s[0], max_size=s[0])
    )
    good = st.lists(st.lists(st.floats(-1, 1), min_size=2, max_size=2), min_size=3, max_size=3)
    return st.one_of(st.none(), good, good, arrays, junk, vec(3))


names = st.one_of(st.none(), st.text(max_size=6), st.integers(-3, 3), junk)


def expect_pinograsp_error(fn, *args, **kwargs):
    """Call ``fn``; only PinograspError subclasses may escape. Returns the result or None."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            out = fn(*args, **kwargs)
        except pg.PinograspError as exc:
            event(type(exc).__name__)  # pytest --hypothesis-show-statistics shows the mix
            return None
    event("valid")
    return out
