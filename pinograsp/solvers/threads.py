"""NumPy's BLAS/LAPACK on one thread for the duration of a public query.

The solver's matrices are tiny (tens of rows): threads only cost, and on a loaded machine
OpenBLAS's spinning threads made a case-1 direction 5x slower (0.15 s -> 0.67 s), also when the
limit was toggled around every solve (the threads spin between calls): public queries hold it for
their whole duration (:func:`single_threaded`). One thread also keeps every reduction in one
order.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from contextlib import AbstractContextManager
from typing import Any, ParamSpec, TypeVar

P = ParamSpec("P")
R = TypeVar("R")

_CONTROLLER: list[Any] = []
#: Depth of :func:`single_threaded` calls in this thread (a nested query keeps the outer limit).
_DEPTH = threading.local()


def single_threaded_blas() -> AbstractContextManager[Any]:
    """A context that runs NumPy's BLAS/LAPACK on one thread (the controller is built once,
    8 µs per use)."""
    from threadpoolctl import ThreadpoolController

    if not _CONTROLLER:
        _CONTROLLER.append(ThreadpoolController())
    limiter: AbstractContextManager[Any] = _CONTROLLER[0].limit(limits=1, user_api="blas")
    return limiter


def single_threaded(fn: Callable[P, R]) -> Callable[P, R]:
    """Decorator: run ``fn`` inside :func:`single_threaded_blas` (public queries)."""

    @functools.wraps(fn)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        depth = getattr(_DEPTH, "n", 0)
        if depth:  # inside another public query: BLAS is on one thread already
            return fn(*args, **kwargs)
        _DEPTH.n = 1
        try:
            with single_threaded_blas():
                return fn(*args, **kwargs)
        finally:
            _DEPTH.n = 0

    return wrapper


__all__ = ["single_threaded", "single_threaded_blas"]
