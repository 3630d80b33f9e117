"""Searches for the largest resistible magnitude on the grid ``k * upper / 2**steps``.

Both searches return the same grid cell whenever resistibility is monotone along the ray (the
assumption of the seed paper's bisection): the largest grid magnitude that is resisted, whose
grid neighbour above is not. They differ only in how many magnitudes they try.

* ``bisection`` — the paper's: ``steps`` halvings of ``[0, upper]``.
* ``secant`` — for the iterative scheme, whose not-resisted verdicts carry a number, the net
  wrench the trajectory stalled at, which shrinks roughly linearly towards zero as the magnitude
  approaches the limit from above. The next magnitude is the root of the line through the two
  smallest not-resisted magnitudes and their final net wrenches (bisection until two are
  known), snapped down to the grid; a resisted guess is followed by a probe of the grid point
  just above it (which ends the search when it is not resisted). When a guess fails to
  halve the bracket, the next magnitude is the bracket's midpoint, so the search never takes
  more than about twice the bisection's stages and usually 4–8 instead of ``steps``.

This module never imports a solver.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..core.results import PassiveResponse

#: A test of one magnitude: (resisted?, the response).
Test = Callable[[float], tuple[bool, PassiveResponse]]


def grid_resolution(upper: float, steps: int) -> float:
    """The search grid's step ``upper / 2**steps`` [N or N·m]: the resolution of a searched limit."""
    return float(upper) / 2**steps


def bisection(test: Test, upper: float, steps: int) -> tuple[float, PassiveResponse | None]:
    """The paper's bisection on ``[0, upper]`` (``upper`` known not to be resisted)."""
    lo, hi, best = 0.0, float(upper), None
    for _ in range(int(steps)):
        mid = 0.5 * (lo + hi)
        ok, resp = test(mid)
        if ok:
            lo, best = mid, resp
        else:
            hi = mid
    return lo, best


def _residual(resp: PassiveResponse) -> float | None:
    h = resp.residual_history
    return float(h[-1]) if h and np.isfinite(h[-1]) else None


def secant(
    test: Test,
    upper: float,
    steps: int,
    at_upper: PassiveResponse,
    tolerance: Callable[[float], float] = lambda m: 0.0,
) -> tuple[float, PassiveResponse | None]:
    """Grid-snapped secant (see the module docstring); ``at_upper`` is the not-resisted
    response at ``upper``; ``tolerance(magnitude)`` the scheme's equilibrium tolerance [N] at a
    magnitude (the secant aims at the magnitude where the final net wrench meets it)."""
    res = float(upper) / 2 ** int(steps)
    lo, hi = 0, 2 ** int(steps)  # grid indices: lo resisted (0: the preload), hi not resisted
    best: PassiveResponse | None = None
    stalls: list[tuple[float, float]] = []  # (magnitude, final net wrench) of not-resisted tests
    r_up = _residual(at_upper)
    if r_up is not None:
        stalls.append((float(upper), r_up))
    bisect_next = False
    while hi - lo > 1:
        width = hi - lo
        k, near = _guess(stalls, res, lo, hi, tolerance) if not bisect_next else (None, False)
        if k is None:
            k = (lo + hi) // 2
        ok, resp = test(k * res)
        if ok:
            lo, best = k, resp
            if near and hi - lo > 1:  # probe the cell above: done if it is not resisted
                ok2, resp2 = test((k + 1) * res)
                if ok2:
                    lo, best = k + 1, resp2
                else:
                    hi = k + 1
                    r = _residual(resp2)
                    if r is not None:
                        stalls.append(((k + 1) * res, r))
        else:
            hi = k
            r = _residual(resp)
            if r is not None:
                stalls.append((k * res, r))
        bisect_next = not bisect_next and (hi - lo) * 2 > width
    return lo * res, best


def _guess(
    stalls: list[tuple[float, float]], res: float, lo: int, hi: int, tolerance: Callable[[float], float]
) -> tuple[int | None, bool]:
    """Grid index of the secant root through the two smallest stalled magnitudes, where the
    final net wrench meets the tolerance (None if it falls outside the bracket), and whether the
    root is near enough to them to be worth probing the grid point above it."""
    pts = sorted(stalls)[:2]
    if len(pts) < 2:
        return None, False
    (m1, r1), (m2, r2) = pts
    g1, g2 = r1 - tolerance(m1), r2 - tolerance(m2)
    if not (g2 > g1 > 0 and m2 > m1):
        return None, False
    root = m1 - g1 * (m2 - m1) / (g2 - g1)
    k = int(np.floor(root / res))
    if k <= lo or k >= hi:
        return None, False
    return k, m1 < 2.0 * root
