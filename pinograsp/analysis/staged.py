"""Responses and load factors of the *staged* methods (prp, iterative, energetic): a preload
stage (per the variant) and a load stage on top of it, assembled into a
:class:`~pinograsp.core.results.PassiveResponse` (docs/design.md, "Variants").

The rules that differ between methods come from their
:class:`~pinograsp.analysis.protocols.MethodRules` record; this module holds what they share.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from ..core.methods import method_variant
from ..core.results import PassiveResponse
from ..core.settings import Method, Settings, Variant
from ..errors import InvalidInputError, SolverError
from ..solvers.base import INFEASIBLE, OPTIMAL
from ..solvers.formulation import ScaledData
from .assemble import build_response, carries_residual
from .protocols import LoadFactor, MethodRules, SessionLike
from .stages import Stage

#: The settled-preload variant's preload stage: Alg. 1 at ``w = 0`` (the object settles).
SETTLED_PRELOAD_METHOD = Method.PRP


def variant_of(settings: Settings, method: MethodRules) -> Variant:
    """The variant ``method`` runs under ``settings`` (its default when none is set)."""
    return method_variant(method.name, settings.variant)


def preload_method_of(method: MethodRules, variant: Variant) -> str:
    """The method whose preload stage ``method`` loads on top of under ``variant``."""
    return SETTLED_PRELOAD_METHOD if variant is Variant.SETTLED_PRELOAD else method.preload_method


def _preload_beta(pre: Stage) -> np.ndarray:
    """Scaled friction-edge weights (nb,) of a converged preload stage (times ``pre.data.F``:
    [N])."""
    raw = pre.raw
    if raw is None or raw.z is None or raw.layout is None:
        raise SolverError("a converged preload stage carries no solution", status="failed")
    return raw.z[raw.layout.beta]


def precompression(session: SessionLike, pre: Stage) -> np.ndarray:
    """Spring pre-compression [N] (nc,) left by a converged preload stage."""
    return session.form.E @ _preload_beta(pre) * pre.data.F


def carried(session: SessionLike, method: MethodRules, pre_method: MethodRules, pre: Stage) -> np.ndarray:
    """The preload stage's own net wrench (reduced, [N, N·m]) that ``method``'s load stage
    balances on top of the load (:attr:`MethodRules.carries_residual`): the held-still
    preload (the iterative scheme's) is an equilibrium only to its tolerance ``eps``, and an
    exact balance of that residual would have to slip the contacts. Zero otherwise and for an
    exact preload."""
    m = session.model
    if not carries_residual(method, pre_method):
        return np.zeros(m.nw)
    beta = _preload_beta(pre) * pre.data.F
    return -(m.G @ (m.D @ beta))


def _preload(
    session: SessionLike, method: MethodRules, variant: Variant, fc: np.ndarray
) -> tuple[MethodRules, Stage, bool]:
    """The preload stage ``method`` loads on under ``variant``, its method and whether this
    call solved it (``fresh``: it counts in this query's time and solves)."""
    pre_method = session.rules(preload_method_of(method, variant))
    fresh = not session.has_preload(fc, pre_method.name)
    return pre_method, session.preload_stage(fc, pre_method.name), fresh


def staged_response(
    session: SessionLike, method: MethodRules, fc: np.ndarray, w6: np.ndarray
) -> PassiveResponse:
    """The response of a staged method to ``w6`` (6,) [N, N·m] under commands ``fc`` (na,)."""
    m = session.model
    w = m.reduce_wrench(w6)
    variant = variant_of(session.settings, method)
    if variant is Variant.SINGLE_STEP:
        stage = method.stage(session, w, fc, np.zeros(m.nc), None)
        return build_response(session, method, variant, w6, fc, stage, None)
    pre_method, pre, fresh = _preload(session, method, variant, fc)
    if not pre.converged:  # not resisted: the preload alone has no equilibrium
        failed = pre if pre_method.name is method.name else replace(pre, raw=None)
        return build_response(session, method, variant, w6, fc, failed, None)
    p = precompression(session, pre)
    start = pre.raw.mode if pre.raw is not None else None
    stage = method.stage(session, w + carried(session, method, pre_method, pre), fc, p, start)
    return build_response(
        session, method, variant, w6, fc, stage, pre, pre_fresh=fresh, pre_method=pre_method
    )


@dataclass(frozen=True)
class _LimitPoint:
    """The load-factor problem's optimum as a stage on top of its preload stage (what the
    response at the limit is assembled from)."""

    stage: Stage
    pre: Stage | None
    pre_method: MethodRules | None
    variant: Variant
    fresh: bool
    at: float  # the magnitude of the point [N or N·m] (``upper`` when unbounded)


def staged_load_factor(
    session: SessionLike, method: MethodRules, fc: np.ndarray, direction: np.ndarray, upper: float
) -> LoadFactor:
    """The largest resistible magnitude along the unit ``direction`` (6,) in one solve of the
    method's load-factor problem (:attr:`MethodRules.load_factor_kind`), commands ``fc``
    (na,) non-negative, pyramids unrefined; for a :attr:`MethodRules.limit_point` method,
    with the response at the limit."""
    lf, point = solve_load_factor(session, method, fc, direction, upper)
    if point is None or not method.limit_point:
        return lf
    w6 = point.at * np.asarray(direction, float)
    resp = build_response(
        session,
        method,
        point.variant,
        w6,
        fc,
        point.stage,
        point.pre,
        pre_fresh=point.fresh,
        pre_method=point.pre_method,
    )
    return replace(lf, response=resp)


def solve_load_factor(
    session: SessionLike, method: MethodRules, fc: np.ndarray, direction: np.ndarray, upper: float
) -> tuple[LoadFactor, _LimitPoint | None]:
    """The load factor (as :func:`staged_load_factor`, without a response) and its optimum as a
    stage (None when not optimal)."""
    kind = method.load_factor_kind
    if kind is None:
        raise InvalidInputError("method", f"{method.name!r} has no one-solve load-factor problem")
    m, f = session.model, session.form
    p = np.zeros(m.nc)
    pre_time = 0.0
    pre, pre_method, fresh = None, None, True
    variant = variant_of(session.settings, method)
    if variant is not Variant.SINGLE_STEP:
        pre_method, pre, fresh = _preload(session, method, variant, fc)
        pre_time = pre.solve_time
        if not pre.converged:
            return LoadFactor(INFEASIBLE, float("nan"), pre_time), None
        p = precompression(session, pre)
        w0 = carried(session, method, pre_method, pre)
    else:
        w0 = np.zeros(m.nw)
    d = m.reduce_wrench(np.asarray(direction, float)) * f.wscale
    data = f.scale_data(w0, fc, p)
    data = ScaledData(data.F, data.w, data.fc, data.p, data.x0, d)
    tmax = float(upper) / data.F
    t0 = time.perf_counter()
    raw = session.solve(kind, data, t_max=tmax)
    raw = replace(raw, solve_time=time.perf_counter() - t0)
    dt = raw.solve_time + pre_time
    if raw.status != OPTIMAL or raw.z is None or raw.layout is None or raw.layout.t is None:
        return LoadFactor(raw.status, float("nan"), dt), None
    t = max(float(raw.z[raw.layout.t]), 0.0)
    at_upper = t >= tmax * (1.0 - 1e-9)
    magnitude = float("inf") if at_upper else t * data.F
    # the load-factor problem's point: an equilibrium of the problem at t d
    at_t = replace(data, w=data.w + t * d)
    stage = Stage(raw, at_t, raw.z[raw.layout.obj], "resisted", True, 1, (), raw.solve_time, 1)
    point = _LimitPoint(stage, pre, pre_method, variant, fresh, float(upper) if at_upper else magnitude)
    return LoadFactor(OPTIMAL, magnitude, dt), point
