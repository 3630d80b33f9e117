"""Public entry points of the quasi-static method: :func:`loading_path`,
:func:`quasistatic_max_wrench` and :func:`quasistatic_response` (the whole interface a method
registry needs)."""

from __future__ import annotations

import time
import weakref
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from ...core.axes import PLANAR_AXES, wrench_direction
from ...core.model import GraspModel
from ...core.settings import Settings, make_settings
from ...core.validate import MAX_FORCE, MAX_PATH_SEGMENTS, count, load_within, number_in
from ...errors import InvalidInputError
from ...solvers.threads import single_threaded
from .continuation import continue_past_limit
from .events import path_events
from .model import QSModel, build_qs_model
from .path import MAX_SEGMENTS, StageRun, follow
from .preload import preload_path, preload_path_of, released_states
from .rates import EVENT_RTOL, StageSpec, State, force_scale
from .result import LoadingPath, PathStatus
from .statuses import RunStatus

_CACHE: weakref.WeakKeyDictionary[GraspModel, dict] = weakref.WeakKeyDictionary()


@dataclass(frozen=True)
class Prepared:
    """A model ready for paths: the analysed model (normal uncertainty, actuator signs), its
    :class:`QSModel`, the commands (na,) and their signs, the preloaded state."""

    model: GraspModel
    qm: QSModel
    fc: np.ndarray
    signs: np.ndarray
    start: State
    preload_runs: tuple[StageRun, ...]
    variant: str
    ratio: float
    #: Records that are pure functions of the prepared grasp (the zero-load response), kept
    #: with it: only time is saved.
    memo: dict = field(default_factory=dict, compare=False, repr=False)


_VALID: dict[Settings, Settings] = {}


def checked_settings(settings: Settings | None) -> Settings:
    """``settings`` validated (:func:`make_settings`), kept per value (a frozen record)."""
    if settings is None or isinstance(settings, Settings):
        try:
            hit = _VALID.get(settings or Settings())
        except TypeError:  # an unhashable field value: validate (and reject) it
            hit = None
        if hit is not None:
            return hit
    s = make_settings(settings)
    if len(_VALID) < 256:
        _VALID[s] = s
    return s


def _ratio(settings: Settings) -> float:
    return float(getattr(settings, "tangential_ratio", 1.0))


def _variant(variant: object, settings: Settings) -> str:
    return preload_path_of(variant, settings.variant)  # the one variant rule (core.methods)


def prepare(
    model: GraspModel, command: object, settings: Settings, variant: str, max_segments: int = MAX_SEGMENTS
) -> Prepared:
    """The analysed model and its preloaded state (kept per model, settings and command: a
    pure function of them; only time is saved)."""
    if not isinstance(model, GraspModel):
        raise InvalidInputError("model", f"expected pinograsp.GraspModel, got {type(model).__name__}")
    if settings.cone_tolerance is not None:
        raise InvalidInputError(
            "cone_tolerance",
            "the quasi-static method follows the model's own friction polygon; refine the model's "
            "pyramids yourself (pinograsp.core.cones.refined) or leave cone_tolerance=None",
        )
    analysed = model.with_normal_uncertainty(settings.normal_uncertainty)
    fc = analysed.command_vector(command)
    signs = np.where(fc < 0, -1.0, 1.0)
    ratio = _ratio(settings)
    key = (
        float(settings.normal_uncertainty),
        ratio,
        tuple(signs.tolist()),
        variant,
        tuple(np.abs(fc).tolist()),
    )
    per_model = _CACHE.setdefault(model, {})
    if key not in per_model:
        m = analysed.with_actuator_signs(signs) if np.any(signs < 0) else analysed
        qm = build_qs_model(m, ratio)
        start, runs = preload_path(qm, np.abs(fc), variant, max_segments)
        per_model[key] = Prepared(m, qm, np.abs(fc), signs, start, tuple(runs), variant, ratio)
    return per_model[key]


def _stacks(states: list[State]) -> dict[str, np.ndarray]:
    """The states' fields stacked, one row per state (read by :func:`_arrays` and :func:`_audit`)."""
    return {
        "vs": np.array([s.vs for s in states]),
        "c": np.array([s.c for s in states]),
        "f": np.array([s.f for s in states]),
        "lam": np.array([s.lam_c for s in states]),
        "slip": np.array([s.slip for s in states]),
        "t": np.array([s.t for s in states]),
    }


def _arrays(p: Prepared, states: list[State], stacks: dict | None = None) -> dict[str, np.ndarray]:
    """Physical arrays of the states (actuator quantities with the command signs)."""
    qm, m = p.qm, p.model
    k = len(states)
    st = _stacks(states) if stacks is None else stacks
    vs = st["vs"].reshape(k, qm.nv)
    x = vs[:, : qm.nx] / qm.S[: qm.nx]
    q = vs[:, qm.nx :] / qm.S[qm.nx :]
    x6 = np.zeros((k, 6))
    x6[:, list(PLANAR_AXES) if m.planar else slice(None)] = x  # m.expand_twist of every row
    c = np.zeros((k, qm.nc, 3))
    c[:, :, : qm.d] = st["c"].reshape(k, qm.nc, qm.d)
    slip = st["slip"].reshape(k, qm.nc, qm.d)
    frames = np.asarray(m.frames)[:, :, : qm.d]
    slip_w = np.einsum("ijk,tik->tij", frames, slip)
    f = st["f"].reshape(k, qm.na) * p.signs
    u = (q @ np.asarray(m.R)).reshape(k, qm.na) * p.signs if qm.na else np.zeros((k, 0))
    lam = st["lam"].reshape(k, qm.ncp)
    return {
        "object_displacements": x6,
        "joint_displacements": q,
        "actuator_displacements": u,
        "actuator_forces": f,
        "coupling_forces": lam,
        "contact_forces": c,
        "contact_slip": slip_w,
    }


def _audit(
    p: Prepared,
    states: list[State],
    arrays: dict[str, np.ndarray],
    d_red: np.ndarray,
    stacks: dict | None = None,
    energy: bool = True,
) -> dict:
    """Equilibrium, hand and friction residuals per breakpoint; energy balance per segment
    (without ``energy``: an empty array, for a lean record)."""
    qm, m = p.qm, p.model
    st = _stacks(states) if stacks is None else stacks
    ell = m.length_scale
    wscale = np.ones(qm.nx)
    wscale[(2 if m.planar else 3) :] = 1.0 / ell
    C = st["c"]  # (k, ncd)
    t = st["t"]
    Fa = st["f"].reshape(len(states), qm.na)
    Lc = st["lam"].reshape(len(states), qm.ncp)
    VS = st["vs"]
    SL = st["slip"]
    eq = np.linalg.norm((C @ np.asarray(m.G).T + t[:, None] * d_red) * wscale, axis=1)
    if qm.nq:
        tau = C @ np.asarray(m.J) - Fa @ np.asarray(m.R).T - Lc @ np.asarray(m.C)
        hand = np.abs(tau / qm.lever).max(axis=1)
    else:
        hand = np.zeros(len(states))
    fr = np.maximum(0.0, -(C @ qm.Phi.T).min(axis=1, initial=0.0)) if qm.nf else np.zeros(len(states))
    if not energy:
        return {"equilibrium": eq, "hand": hand, "friction": fr, "energy": np.zeros(0)}
    d = qm.d
    Cc = C.reshape(len(states), qm.nc, d)
    elastic = np.sum(Cc[:, :, 0] ** 2 / (2 * qm.kn), axis=1)
    if d > 1:
        inv_kt = np.where(qm.kt > 0, 1.0 / np.where(qm.kt > 0, qm.kt, 1.0), 0.0)
        elastic = elastic + np.sum(np.sum(Cc[:, :, 1:] ** 2, axis=2) * inv_kt / 2, axis=1)
    dV = np.diff(VS, axis=0)
    dx = dV[:, : qm.nx] / qm.S[: qm.nx]
    w_load = 0.5 * (t[1:] + t[:-1]) * (dx @ d_red)
    if qm.na:
        du = (dV[:, qm.nx :] / qm.S[qm.nx :]) @ np.asarray(m.R)
        w_act = np.sum(0.5 * (Fa[1:] + Fa[:-1]) * du, axis=1)
    else:
        w_act = 0.0
    diss = -np.sum(0.5 * (C[1:] + C[:-1]) * np.diff(SL, axis=0), axis=1)
    energy = w_load + w_act - np.diff(elastic) - diss
    return {"equilibrium": eq, "hand": hand, "friction": fr, "energy": np.asarray(energy, float)}


#: Audit bar of a reported path: equilibrium, joint balance and polygon residuals at a breakpoint
#: above this fraction of the path's force scale (a sound path has ~1e-12) mean the rate
#: problem's answer was not an equilibrium path (a degenerate LCP accepted): never a verdict.
AUDIT_RTOL = 1e-6


#: A unit load's part that no contact force can balance (:func:`unbalanceable`) up to this size
#: [N per N] is rounding of the contact geometry (the SO-101 ball: 1.3e-6 along the free spin
#: about its contact chord), allowed in the audit's equilibrium residual at each load.
UNBALANCED_RTOL = 1e-5


def unbalanceable(model: GraspModel, d_red: np.ndarray) -> float:
    """The part of the unit load ``d_red`` (nx,) that no contact force can balance, in the
    audit's rows (torques over the length scale) [N per unit load]: 0 when the contacts
    constrain every object motion; where they leave a free motion (two contacts: the spin about
    their chord), the load's rounding-level component along it (auto-closed contact points are
    1e-8 m off a common line), which the rate problem leaves to its least-norm solution when it
    is within its range tolerance (``system.RANGE_RTOL``)."""
    nt = 2 if model.planar else 3
    ws = np.ones(model.nw)
    ws[nt:] = 1.0 / model.length_scale
    Gs = np.asarray(model.G, float) * ws[:, None]
    ds = np.asarray(d_red, float) * ws
    c = np.linalg.lstsq(Gs, -ds, rcond=None)[0]
    return float(np.linalg.norm(Gs @ c + ds))


def _audit_failure(
    audit: dict, loads: np.ndarray, arrays: dict[str, np.ndarray], rest: float | Callable[[], float] = 0.0
) -> int | None:
    """Index of the first breakpoint whose audit fails (None: all pass); ``rest``: the unit
    load's unbalanceable part (:func:`unbalanceable`), allowed in the equilibrium residual at
    each load when it is rounding (at most :data:`UNBALANCED_RTOL`); a callable is evaluated
    only when the audit fails without that allowance (which only ever loosens the bar)."""
    if callable(rest):
        if _audit_failure(audit, loads, arrays, 0.0) is None:
            return None
        rest = rest()
    c = arrays["contact_forces"]
    force = max(float(np.abs(c).max(initial=0.0)), float(np.abs(loads).max(initial=0.0)), 1e-300)
    bad = ~np.isfinite(arrays["object_displacements"]).all(axis=1) | ~np.isfinite(loads)
    allow = np.abs(loads) * rest * 2.0 if rest <= UNBALANCED_RTOL else 0.0
    for key in ("equilibrium", "hand", "friction"):
        r = np.asarray(audit[key], float)
        bad |= ~(r <= AUDIT_RTOL * force + (allow if key == "equilibrium" else 0.0))
    return int(np.argmax(bad)) if bad.any() else None


def _status(run: StageRun, p: Prepared, spec: StageSpec) -> tuple[str, float, str]:
    """(status, limit, stop reason) of a load stage."""
    last = run.states[-1].t
    if run.status in (RunStatus.LIMIT, RunStatus.UNSTABLE):
        scale = force_scale(p.qm, p.start, spec) / max(float(np.abs(p.qm.w_scaled(spec.dw)).max()), 1e-300)
        if last <= EVENT_RTOL * scale:
            return "below_resolution", 0.0, run.status.value
        return "finite", float(last), run.status.value
    if run.status == RunStatus.UNBOUNDED:
        return "unbounded", float("inf"), "ray"
    if run.status == RunStatus.END:
        return "reached", float(last), "load"
    if run.status == RunStatus.SEGMENT_LIMIT:
        return "segment_limit", float(last), "segment_limit"
    return "no_solution", float(last), run.status.value


def _seg_rates(p: Prepared, seg, x0: np.ndarray | None) -> dict[str, np.ndarray]:
    """A segment's rates per unit load in the arrays' units (for the ray)."""
    tmp = State(seg.dvs, seg.dc, seg.df, seg.dlam_c, seg.dhold, seg.dslip, 0.0)
    arr = _arrays(p, [tmp])
    return {k: v[0] for k, v in arr.items()}


def build_path(
    p: Prepared, d6: np.ndarray, run: StageRun, spec: StageSpec, wall: float, lean: bool = False
) -> LoadingPath:
    """The :class:`LoadingPath` record of a load stage; ``lean``: without its events, its
    stiffness per segment and its energy balance (for an answer that reads only the limit and
    the states, as the max-wrench query; the equilibrium, hand and friction audit that turns a
    broken path into ``no_solution`` stays)."""
    m, qm = p.model, p.qm
    status, limit, reason = _status(run, p, spec)
    states = run.states
    stacks = _stacks(states)
    arrays = _arrays(p, states, stacks)
    segs = [s for s in run.segments if s.contact]
    k = len(states)
    cs, sf, am = [], [], []
    if not segs:  # no load segment (up_to=0): the states of the state itself, not "separated"
        cs0, sf0, am0 = released_states(qm, states[0], spec)
    for j in range(k):
        seg = segs[min(j, len(segs) - 1)] if segs else None
        cs.append(seg.contact if seg else cs0)
        sf.append(seg.detail if seg else sf0)
        am.append(seg.actuator if seg else am0)
    x = arrays["object_displacements"]
    run_loads = np.array([st.t for st in states])
    stiff = np.zeros(0)
    if not lean:  # the stiffness along d per segment
        dl, ds = np.diff(run_loads), np.diff((x - x[0]) @ d6)
        stiff = np.divide(dl, ds, out=np.full(len(dl), np.inf), where=np.abs(ds) > 0)
    ray = None
    if status == "unbounded":
        ray = _seg_rates(p, run.segments[-1], x[0])
        along = float(ray["object_displacements"] @ d6)
        stiff = stiff if lean else np.append(stiff, 1.0 / along if along > 0 else np.inf)
    d_red = m.reduce_wrench(d6)
    audit = _audit(p, states, arrays, d_red, stacks, energy=not lean)
    first_bad = _audit_failure(audit, run_loads, arrays, lambda: unbalanceable(m, d_red))
    if first_bad is not None:  # no verdict from a path that is not an equilibrium path
        status, reason, ray = "no_solution", "audit", None
        limit = float(run_loads[max(first_bad - 1, 0)])
    return LoadingPath(
        direction=d6,
        command=p.fc * p.signs,
        variant=p.variant,
        tangential_ratio=p.ratio,
        status=status,  # type: ignore[arg-type]
        limit=limit,
        stop_reason=reason,
        loads=run_loads,
        stiffness=stiff,
        contact_states=tuple(cs),
        sliding_faces=tuple(sf),
        actuator_modes=tuple(am),
        events=() if lean else path_events(qm, run, status),
        ray=ray,
        audit=audit,
        segments=len(states) - 1,
        lcp_solves=run.lcp_solves + sum(r.lcp_solves for r in p.preload_runs),
        pivots=run.pivots,
        largest_lcp=run.largest_lcp,
        preload_segments=sum(len(r.states) - 1 for r in p.preload_runs),
        ties=sum(bool(sg.tie) for sg in run.segments),
        contact_names=m.contact_names,
        joint_names=m.joint_names,
        actuator_names=m.actuator_names,
        length_scale=float(m.length_scale),
        model_stiffness=float(np.max(m.k)),
        wall_time=wall,
        **arrays,  # type: ignore[arg-type]  # the array fields by name
    )


@single_threaded
def loading_path(
    model: GraspModel,
    command: object,
    direction: object,
    *,
    variant: str | None = None,
    settings: Settings | None = None,
    max_segments: int = MAX_SEGMENTS,
    up_to: float | None = None,
    continuation: bool = True,
) -> LoadingPath:
    """Follow the equilibrium of the preloaded grasp as the load ``λ direction`` grows from 0
    (the quasi-static loading path, docs/methods.md).

    Args:
        model: The grasp.
        command: Actuator commands (as for :func:`pinograsp.passive_response`) [N·m or N].
        direction: Wrench direction: axis name (``"fy"``, ``"-mz"``) or vector (normalised).
        variant: Preload, in the variant vocabulary of every entry point: ``"preload-first"``
            (default, as the simulation's: object held, friction off while the commands ramp,
            then released; the path's name ``"held"``) or ``"settled-preload"`` (object free,
            friction on; ``"settled"``); None: ``Settings.variant``. ``"single-step"`` is
            refused, as by ``max_resistible_wrench(method="quasistatic")``.
        settings: :class:`~pinograsp.Settings`: ``tangential_ratio`` (tangential / normal
            contact stiffness, default 1) and ``normal_uncertainty`` apply.
        max_segments: Segment-count limit of each stage (a count in [1, 1e6]; status
            ``"segment_limit"``).
        up_to: Stop at this load [N or N·m] (status ``"reached"`` when the path gets there),
            in [0, 1e12] and within 1e6 times the grasp's force scale (docs/errors.md).
        continuation: At a softening limit, also follow the path past it to the snap's
            landing and on (:attr:`LoadingPath.continuation`).

    Returns:
        The :class:`LoadingPath`.

    Raises:
        PreloadNotInEquilibriumError: The preload path reaches a limit before its end.
        InvalidInputError: Bad model, command, direction, variant or settings.
    """
    t0 = time.perf_counter()
    s = checked_settings(settings)
    v = _variant(variant, s)
    max_segments = count("max_segments", max_segments, MAX_PATH_SEGMENTS, what="each segment one LCP")
    if not isinstance(continuation, (bool, np.bool_)):  # "no" is truthy: docs/errors.md
        raise InvalidInputError("continuation", f"expected True or False, got {continuation!r}")
    p = prepare(model, command, s, v, int(max_segments))
    d6 = wrench_direction(model, direction)
    if up_to is not None:  # a load: the domains of every load (docs/errors.md, "Input domains")
        up_to = number_in("up_to", up_to, 0.0, MAX_FORCE, "N or N·m")
        load_within(model, model.command_vector(command), "up_to", up_to * d6)
    return run_path(p, d6, int(max_segments), up_to, continuation, t0)


def unit_again(d6: np.ndarray) -> np.ndarray:
    """:func:`~pinograsp.core.axes.wrench_direction`'s arithmetic on a direction (6,) it has
    already validated and normalised (the same bits, without validating it again)."""
    d = d6 / float(np.abs(d6).max())
    return d / float(np.linalg.norm(d))


def run_path(
    p: Prepared,
    d6: np.ndarray,
    max_segments: int,
    up_to: float | None,
    continuation: bool,
    t0: float,
    lean: bool = False,
) -> LoadingPath:
    """The load stage of a prepared grasp along the unit direction ``d6`` (6,) as a
    :class:`LoadingPath` (see :func:`loading_path`); ``lean``: without its events, stiffness
    and energy balance (see :func:`build_path`)."""
    d_red = p.model.reduce_wrench(d6)
    t_end = float("inf") if up_to is None else float(up_to)
    spec = StageSpec(np.zeros(p.qm.nx), d_red, p.fc, np.zeros(p.qm.na), t_end, held=False, friction=True)
    run = (
        follow(p.qm, p.start, spec, max_segments)
        if t_end > 0
        else StageRun(states=[p.start.copy()], status=RunStatus.END)
    )
    cont = None
    if run.status == RunStatus.LIMIT and up_to is None and continuation:
        more = continue_past_limit(p.qm, run, spec, max_segments)
        if more is not None:
            cont = _continuation(p, d6, more, spec, lean)
    lp = build_path(p, d6, run, spec, time.perf_counter() - t0, lean)
    return replace(lp, continuation=cont) if cont is not None else lp


def _continuation(
    p: Prepared, d6: np.ndarray, more: StageRun, spec: StageSpec, lean: bool = False
) -> LoadingPath:
    """The :class:`LoadingPath` record of the path past a softening limit (``lean``: as
    :func:`build_path`)."""
    cont = build_path(
        p,
        d6,
        StageRun(states=more.states, segments=more.segments, triggers=more.triggers, status=RunStatus.END),
        spec,
        0.0,
        lean,
    )
    snaps = tuple(more.snaps)
    if cont.stop_reason == "audit":
        return replace(cont, snaps=snaps)
    tail = more.tail if more.status == RunStatus.LANDED and more.tail is not None else more.status
    status: PathStatus
    if not snaps:
        status = "finite" if more.status in (RunStatus.UNLOADED, RunStatus.MECHANISM) else "no_solution"
        limit = float(more.states[0].t)
    elif tail == RunStatus.UNBOUNDED:
        status, limit = "unbounded", float("inf")
    elif tail == RunStatus.LIMIT:
        status, limit = "finite", float(more.states[-1].t)
    elif tail in (RunStatus.UNLOADED, RunStatus.MECHANISM):  # gave way past the last landing: its peak
        status, limit = "finite", max(float(s.t) for s in more.states[snaps[-1][1] :])
    else:
        status, limit = "no_solution", float(more.states[-1].t)
    ray = _seg_rates(p, more.segments[-1], None) if status == "unbounded" else None
    return replace(
        cont,
        status=status,
        limit=limit,
        stop_reason=tail.value,  # how the path past the limit ended (after its last landing)
        snaps=snaps,
        ray=ray,
    )


__all__ = ["Prepared", "loading_path", "prepare", "run_path", "unit_again"]
