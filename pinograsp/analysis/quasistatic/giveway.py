"""Where a loading path gives way: the first load at which the object has moved a threshold,
snaps that land followed (docs/giveway.md).

Plain arrays only (a :class:`Trace` per record), so that the path record
(``LoadingPath.load_at_displacement``) and the method's answer read the same walk.
Displacements are the model's (proportional to
``1 / k``): ``scale`` turns them into physical ones at the chosen contact stiffness.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...core.giveway import LINEAR_ROTATION, LINEAR_TRANSLATION


@dataclass(frozen=True)
class Trace:
    """One path record as arrays: loads (k,), object displacements (k, 6), joint displacements
    (k, nq), and on a ray the rates per unit load of both (6,), (nq,) (else None)."""

    loads: np.ndarray
    x: np.ndarray
    q: np.ndarray
    ray_x: np.ndarray | None = None
    ray_q: np.ndarray | None = None


@dataclass(frozen=True)
class Thresholds:
    """Give-way thresholds in physical units: translation [m], rotation [rad], joint [rad] or
    None; ``scale``: physical displacement per model displacement; ``linear``: also end where
    the motion leaves the linearisation's range (:data:`~pinograsp.core.giveway.LINEAR_ROTATION`,
    :data:`~pinograsp.core.giveway.LINEAR_TRANSLATION` of ``length_scale`` [m])."""

    slip: float
    rotation: float
    joint: float | None
    scale: float
    length_scale: float
    linear: bool = True


@dataclass(frozen=True)
class Point:
    """A give-way found on a trace: the load [N or N·m], why, which trace (0 the path, 1 its
    continuation), the breakpoint starting the segment and the step from it (a fraction of the
    segment, or a load increment on a ray)."""

    load: float
    reason: str
    trace: int
    index: int
    step: float
    on_ray: bool = False


#: A give-way criterion: (reason, object slice or None for joints, threshold, per-component).
Channel = tuple[str, slice | None, float, bool]


def _channels(th: Thresholds) -> list[Channel]:
    """(reason, object slice or None for joints, threshold, per-component) of every criterion."""
    out: list[Channel] = [
        ("translation", slice(0, 3), th.slip, False),
        ("rotation", slice(3, 6), th.rotation, False),
    ]
    if th.linear:
        if LINEAR_TRANSLATION * th.length_scale < th.slip:
            out.append(("linearisation", slice(0, 3), LINEAR_TRANSLATION * th.length_scale, False))
        if LINEAR_ROTATION < th.rotation:
            out.append(("linearisation", slice(3, 6), LINEAR_ROTATION, False))
    if th.joint is not None:
        out.append(("joint", None, th.joint, True))
    return out


def _root(a: np.ndarray, b: np.ndarray, lim: float, per_component: bool) -> float:
    """Smallest ``s >= 0`` with ``|a + s b| >= lim`` (Euclidean norm, or any component's
    absolute value when ``per_component``); ``inf`` if never."""
    if per_component:
        best = math.inf
        for ai, bi in zip(a, b):
            if abs(ai) >= lim:
                return 0.0
            if bi != 0.0:
                s = (math.copysign(lim, bi) - ai) / bi
                best = min(best, s) if s >= 0 else best
        return best
    A, B, C = float(b @ b), float(2.0 * (a @ b)), float(a @ a - lim * lim)
    if C >= 0.0:
        return 0.0
    if A == 0.0:
        return math.inf
    disc = math.sqrt(B * B - 4.0 * A * C)  # C < 0: one positive root, computed without cancellation
    return C / (-0.5 * (B + disc)) if B > 0 else (-B + disc) / (2.0 * A)


def _first_on_segment(
    th: Thresholds,
    x0: np.ndarray,
    q0: np.ndarray,
    xa: np.ndarray,
    xb: np.ndarray,
    qa: np.ndarray,
    qb: np.ndarray,
    smax: float,
    channels: list[Channel] | None = None,
) -> tuple[float, str] | None:
    """The first crossing on ``a + s (b - a)`` (``b`` a rate on a ray), ``s`` in [0, smax]
    (``channels``: :func:`_channels` of ``th`` when the caller has them)."""
    best: tuple[float, str] | None = None
    for reason, sl, lim, per in _channels(th) if channels is None else channels:
        if sl is None:
            a, b = (qa - q0) * th.scale, qb * th.scale if math.isinf(smax) else (qb - qa) * th.scale
        else:
            a = (xa[sl] - x0[sl]) * th.scale
            b = xb[sl] * th.scale if math.isinf(smax) else (xb[sl] - xa[sl]) * th.scale
        if a.size == 0:
            continue
        s = _root(a, b, lim, per)
        if s <= smax and (best is None or s < best[0]):
            best = (s, reason)
    return best


#: Breakpoints farther than this fraction below every threshold (:func:`_near`) are inside
#: them beyond any rounding of the segment arithmetic (~1e-15 of a threshold).
_NEAR_RTOL = 1e-6


def _near(
    tr: Trace,
    th: Thresholds,
    x0: np.ndarray,
    q0: np.ndarray,
    channels: list[Channel],
) -> np.ndarray:
    """Per breakpoint of ``tr`` (k,) bool: whether it may be at or past a threshold (within
    :data:`_NEAR_RTOL` of it, or not finite). A segment whose two ends are not is crossed by
    none (the distance from ``(x0, q0)`` is convex along it), so :func:`first_crossing`
    examines only the segments with a flagged end (speed only: the same answer)."""
    near = np.zeros(len(tr.loads), bool)
    for _, sl, lim, per in channels:
        D = (tr.q - q0) * th.scale if sl is None else (tr.x[:, sl] - x0[sl]) * th.scale
        if D.shape[1] == 0:
            continue
        inner = lim * (1.0 - _NEAR_RTOL)
        if per:
            near |= ~(np.abs(D).max(axis=1) < inner)
        else:
            near |= ~(np.sum(D * D, axis=1) < inner * inner)
    return near


def first_crossing(
    tr: Trace, th: Thresholds, x0: np.ndarray, q0: np.ndarray, start: int, stop: int | None, which: int
) -> Point | None:
    """The first load on ``tr`` from breakpoint ``start`` to ``stop`` (default the last, then
    along its ray) where a threshold is reached, measured from ``(x0, q0)``; None if none."""
    last = len(tr.loads) - 1 if stop is None else stop
    chans = _channels(th)
    near = _near(tr, th, x0, q0, chans)[start : last + 1] if last > start else np.zeros(1, bool)
    # a segment with both ends inside every threshold crosses none: only the others
    for j in (start + np.flatnonzero(near[:-1] | near[1:])).tolist():
        hit = _first_on_segment(th, x0, q0, tr.x[j], tr.x[j + 1], tr.q[j], tr.q[j + 1], 1.0, chans)
        if hit is not None:
            s, reason = hit
            return Point(float(tr.loads[j] + s * (tr.loads[j + 1] - tr.loads[j])), reason, which, j, s)
    if stop is None and tr.ray_x is not None:
        rq = tr.ray_q if tr.ray_q is not None else np.zeros_like(tr.q[last])
        hit = _first_on_segment(th, x0, q0, tr.x[last], tr.ray_x, tr.q[last], rq, math.inf, chans)
        if hit is not None:
            return Point(float(tr.loads[last] + hit[0]), hit[1], which, last, hit[0], on_ray=True)
    elif start == last and _beyond(th, x0, q0, tr.x[last], tr.q[last]):  # a single breakpoint
        return Point(float(tr.loads[last]), _reason(th, x0, q0, tr.x[last], tr.q[last]), which, last, 0.0)
    return None


def _beyond(th: Thresholds, x0: np.ndarray, q0: np.ndarray, x: np.ndarray, q: np.ndarray) -> bool:
    """Whether the state ``(x, q)`` is past a threshold."""
    return _first_on_segment(th, x0, q0, x, x, q, q, 0.0) is not None


def _reason(th: Thresholds, x0: np.ndarray, q0: np.ndarray, x: np.ndarray, q: np.ndarray) -> str:
    """The criterion the state ``(x, q)`` is past (:func:`_beyond` is true)."""
    hit = _first_on_segment(th, x0, q0, x, x, q, q, 0.0)
    return "limit" if hit is None else hit[1]


def _peak_before_descent(cont: Trace, land: int) -> int | None:
    """After the last landing: the breakpoint of the largest load when the path falls after
    it (a limit whose snap did not land: the grasp gives way there, and a threshold crossed
    on the falling load beyond it is not a load it resisted); None when it does not fall."""
    peak = land + int(np.argmax(cont.loads[land:]))
    return peak if peak < len(cont.loads) - 1 else None


def walk(
    main: Trace, cont: Trace | None, snaps: tuple[tuple[int, int], ...], th: Thresholds
) -> tuple[Point | None, tuple[tuple[int, int], ...]]:
    """The give-way along a path (``main``, its limit last) and its continuation past the limit
    (``cont``, its breakpoint 0 the limit; ``snaps``: (limit, landing) breakpoints of ``cont``):
    the first threshold crossing on the path; else at each snap, the snap's limit load when a
    state of the jump (the descent to the landing) is past a threshold, or the first crossing
    after the landing. Returns the point (None: no crossing on what was followed) and the snaps
    survived before it."""
    x0, q0 = main.x[0], main.q[0]
    hit = first_crossing(main, th, x0, q0, 0, None if cont is None else len(main.loads) - 1, 0)
    if hit is not None or cont is None:
        return hit, ()
    for n, (top, land) in enumerate(snaps):
        if any(_beyond(th, x0, q0, cont.x[j], cont.q[j]) for j in range(top, land + 1)):
            return Point(float(cont.loads[top]), "limit", 1, top, 0.0), snaps[:n]
        end = snaps[n + 1][0] if n + 1 < len(snaps) else _peak_before_descent(cont, land)
        hit = first_crossing(cont, th, x0, q0, land, end, 1)
        if hit is not None:
            return hit, snaps[: n + 1]
    return None, snaps


__all__ = ["Point", "Thresholds", "Trace", "first_crossing", "walk"]
