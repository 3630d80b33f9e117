"""The segment loop: follow the equilibrium along one stage, event by event.

Each pass: classify the state (:func:`~.rates.classify`), solve the local rate problem under
load control (:func:`~.rates.rates`); if that has no solution (the load has reached a limit, or
the LCP has none), solve it under displacement control: a continuation with ``dλ > 0`` is
followed, ``dλ <= 0`` (softening, or a mechanism along the load) is the **limit**. Then the
next event in closed form: the smallest step at which an inequality that is slack now reaches
zero (a pressed contact's normal force, an open contact's gap, a face of a touching contact's
polygon, a holding actuator's over-force, or the end of the stage). No event ahead: the last
segment is a ray, the stage is **unbounded**.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from .buckling import ray_buckling
from .geometry import GeometryUpdates, moved, spin, step_to_update
from .model import QSModel
from .rates import (
    FULL,
    PRESS,
    RATE_RTOL,
    SEPARATE,
    Classes,
    Segment,
    StageCache,
    StageSpec,
    State,
    classify,
    rates,
    rescaled,
    separated_on,
)
from .snap import no_continuation, unstable_segment
from .statuses import RunStatus, SegmentStatus, TriggerKind, run_status

#: A mechanism along the load: ``dλ`` per unit displacement below this fraction of the
#: largest contact stiffness. Rounding of a degenerate rate problem (zero-force contacts at the
#: start, case 3 at 255°/285°) leaves ``dλ`` of 1e-10 to 1e-9 ``k`` on a mechanism; accepting
#: it as a continuation rescales every rate by 1e9 (a broken path), so the bar is 1e-7.
LIMIT_RTOL = 1e-7
#: Under load control, a stiffness along the load below this fraction of the largest contact
#: stiffness is checked under displacement control (a limit hides there as a huge rate).
SOFT_RTOL = 1e-6
#: Default largest number of segments of one stage (a count, reported when reached).
MAX_SEGMENTS = 5000
#: The reductions of ``ndarray.max``/``min`` without their Python wrappers (the same ufunc).
_amax, _amin = np.maximum.reduce, np.minimum.reduce
#: The stage's end in :func:`next_event`'s arrays: always eligible, at rate -1 (read-only).
_END_OK, _END_RATE, _END_COND = np.ones(1, bool), np.full(1, -1.0), np.full(1, -np.inf)
for _a in (_END_OK, _END_RATE, _END_COND):
    _a.setflags(write=False)


@dataclass(frozen=True)
class Trigger:
    """An inequality reached at the end of a segment: ``kind`` (:class:`~.statuses.TriggerKind`)
    and ``index``: the contact, face (row of :attr:`QSModel.Phi`) or actuator (-1: none)."""

    kind: TriggerKind
    index: int


#: The geometry update's trigger (frozen: shared).
_GEOMETRY = (Trigger(TriggerKind.GEOMETRY, -1),)


@dataclass
class StageRun:
    """What following one stage produced.

    Attributes:
        states: Breakpoint states, the start included.
        segments: ``segments[k]`` is the segment leaving ``states[k]``; one more than the
            segments between breakpoints when the stage ends in a ray (unbounded) or at a
            limit (the state found there).
        triggers: Inequalities reached at each breakpoint after the first.
        status: :class:`~.statuses.RunStatus`: ``END`` (reached ``t_end``), ``UNBOUNDED``,
            ``LIMIT``, ``UNSTABLE``, ``SEGMENT_LIMIT`` or the rate problem's failure; past a
            limit (:func:`~.continuation.continue_past_limit`) also ``LANDED`` (then ``tail``
            says how the load-controlled part after the last landing ended), ``UNLOADED``,
            ``MECHANISM``.
        lcp_solves, pivots, largest_lcp: Work done.
        snaps: Past a limit: ``(limit breakpoint, landing breakpoint)`` of each snap.
        tail: With ``status == LANDED``: the status of the part after the last landing.
        friction_on: A preload closing: the contacts that closed with friction (nc,) bool.
        model: The model the last segment used (re-linearised at a turned object after a
            geometry update; the stage's own model otherwise).
    """

    states: list[State]
    segments: list[Segment] = field(default_factory=list)
    triggers: list[tuple[Trigger, ...]] = field(default_factory=list)
    status: RunStatus = RunStatus.END
    lcp_solves: int = 0
    pivots: int = 0
    largest_lcp: int = 0
    snaps: list[tuple[int, int]] = field(default_factory=list)
    tail: RunStatus | None = None
    friction_on: np.ndarray | None = None
    model: QSModel | None = None


def planned(
    qm: QSModel,
    st: State,
    spec: StageSpec,
    cls: Classes,
    control: str,
    plan0: np.ndarray,
    run: StageRun,
    sc: StageCache,
    hints: tuple[np.ndarray, ...] = (),
    near: bool = False,
) -> Segment:
    """The rate problem with each zero-force contact guessed pressed or separated (``near``:
    as :func:`~.rates.rates`).

    Plans tried in order: ``plan0`` (the history's guess), every zero-force contact separated,
    every one pressed; within a plan a contradicted guess is flipped, and the faces of a
    pressed zero-force contact enter the LCP only once its rates would cross them (an
    active set of faces: at zero force every face is tight, and all of them at once make an
    LCP that Lemke's method may not solve). Last resort: every zero-force contact with both
    its opening and all its faces in the LCP. Each (plan, faces) combination is tried once.
    """
    if not cls.has_zero:  # nothing to guess: one rate problem (no guess or apex face to flag)
        return _counted(run, rates(qm, st, spec, cls, control, plan0, sc, hints, near=near))
    candidates = [plan0]
    for fill in (SEPARATE, PRESS):
        alt = plan0.copy()
        alt[cls.zero] = fill
        candidates.append(alt)
    tried: set[bytes] = set()
    first = None
    for start in candidates:
        plan = start.copy()
        apex = np.zeros(qm.nf, bool)
        while True:
            key = plan.tobytes() + apex.tobytes()
            if key in tried:
                break
            tried.add(key)
            seg = _counted(run, rates(qm, st, spec, cls, control, plan, sc, hints, apex, near))
            first = first or seg
            if seg.status == SegmentStatus.GUESS:
                plan[seg.flip] = np.where(plan[seg.flip] == PRESS, SEPARATE, PRESS)
            elif seg.status == SegmentStatus.APEX:
                apex[seg.add] = True
            else:
                break
            if len(tried) > 8 * (qm.nc + 1):
                break
        if seg.status in (SegmentStatus.OK, SegmentStatus.SINGULAR):
            return seg
    full = _counted(run, rates(qm, st, spec, cls, control, np.full(qm.nc, FULL), sc, near=near))
    if full.status == SegmentStatus.OK or first is None:
        return full
    return first if first.status not in (SegmentStatus.GUESS, SegmentStatus.APEX) else full


def _counted(run: StageRun, seg: Segment) -> Segment:
    """``seg``, with its LCP counted on ``run`` (solves, pivots, the largest size)."""
    run.lcp_solves += 1
    run.pivots += seg.pivots
    run.largest_lcp = max(run.largest_lcp, seg.lcp_size)
    return seg


def plan_of(qm: QSModel, cls: Classes, prev: Segment | None) -> np.ndarray:
    """First guess for the zero-force contacts: one that was separated has just touched
    (pressed), one that was touching has just unloaded (separated)."""
    plan = np.full(qm.nc, PRESS)
    if not (prev is not None and prev.contact and cls.has_zero):
        return plan
    for i in cls.zero.nonzero()[0]:
        plan[i] = PRESS if prev.contact[i] == "separated" else SEPARATE
    return plan


def _solve_segment(
    qm: QSModel,
    st: State,
    spec: StageSpec,
    cls: Classes,
    run: StageRun,
    prev: Segment | None,
    sc: StageCache,
    trig: tuple[Trigger, ...] = (),
) -> Segment:
    """Load control first; displacement control when that fails (limit or continuation)."""
    plan = plan_of(qm, cls, prev)
    hints: tuple[np.ndarray, ...] = ()
    if prev is not None:
        new = [
            qm.nc + tr.index if tr.kind == TriggerKind.FACE else qm.nc + qm.nf + tr.index
            for tr in trig
            if tr.kind in (TriggerKind.FACE, TriggerKind.COMMAND)
        ]
        if new:  # the sorted union, as np.union1d
            both = np.array(sorted(set(prev.active.tolist()).union(new)), dtype=prev.active.dtype)
            hints = (both, prev.active)
        else:
            hints = (prev.active,)
    seg, rays = _controlled(qm, st, spec, cls, run, sc, plan, hints, near=False)
    if not rays:
        return seg
    if no_continuation(qm, spec, cls, sc):
        return unstable_segment()  # certified: no equilibrium path leaves this state
    # not certified: a nearly degenerate rate problem may have a solution within rounding
    again, _ = _controlled(qm, st, spec, cls, run, sc, plan, hints, near=True)
    return seg if again.status == SegmentStatus.RAY_TERMINATION else again


def _controlled(
    qm: QSModel,
    st: State,
    spec: StageSpec,
    cls: Classes,
    run: StageRun,
    sc: StageCache,
    plan: np.ndarray,
    hints: tuple[np.ndarray, ...],
    near: bool,
) -> tuple[Segment, bool]:
    """The segment under load control, else under displacement control (a limit, or its
    continuation rescaled to load control), and whether both ray-terminated (``near``: as
    :func:`~.rates.rates`)."""
    seg = planned(qm, st, spec, cls, "load", plan, run, sc, hints, near)
    _, _, r0, size, loaded = sc.rates
    if not loaded:
        return seg, False
    if seg.status == SegmentStatus.OK:
        along = float(r0 @ seg.dvs[: qm.nx]) / size  # _along of a load-controlled segment, inline
        if along * SOFT_RTOL * qm.k_ref < size and (along > 0.0 or qm.KG is None):
            return seg, False
        # nearly a mechanism along the load, or (with a geometric stiffness) a negative
        # compliance — a limit passed within the last geometry step: decide under
        # displacement control
    alt = planned(qm, st, spec, cls, "displacement", plan, run, sc, (), near)
    if alt.status != SegmentStatus.OK:
        return seg, seg.status == alt.status == SegmentStatus.RAY_TERMINATION
    load_rate = alt.lam_rate * size
    alt.stiffness_rate = load_rate
    if load_rate <= LIMIT_RTOL * qm.k_ref:
        alt.status = SegmentStatus.LIMIT
        return alt, False
    return rescaled(alt, 1.0 / alt.lam_rate), False


def next_event(
    qm: QSModel, st: State, spec: StageSpec, cls: Classes, seg: Segment, sc: StageCache
) -> tuple[float, tuple[Trigger, ...]]:
    """The step to the next event along ``seg`` (``inf``: none) and the inequalities reached."""
    d = qm.d
    tol = cls.tol
    wd, fd = sc.rates[:2]
    rscale = max(float(_amax(np.abs(seg.dc), initial=0.0)), wd, fd, 1e-300)
    rtol = RATE_RTOL * rscale
    staying = ~(seg.separated if seg.separated is not None else separated_on(seg))
    # every inequality of the search as one array (in trigger order: contacts that unload,
    # open contacts that touch, faces, actuators, the stage's end): eligible now (``ok``), its
    # value (``val``) and rate (``rate``); it is reached at ``val / -rate`` when ``cond < -rtol``
    cn, dcn = st.c[::d], seg.dc[::d]
    val: list[ArrayLike] = [cn]  # arrays, and the end's (float,)
    ok, rate, cond = [staying & (cn > tol)], [dcn], [dcn]
    groups = [(TriggerKind.SEPARATES, qm.nc)]
    same = cls.src is st  # what classify computed of this state
    if np.count_nonzero(cls.open):  # only open contacts touch
        dgap = qm.A[:, ::d].T @ seg.dvs
        ok.append(cls.open)
        val.append(cls.gap if same and cls.gap is not None else qm.gaps(st.vs))  # -delta
        rate.append(dgap)
        cond.append(dgap * qm.kn)  # -dgap * kn > rtol, as dgap * kn < -rtol (bit for bit)
        groups.append((TriggerKind.TOUCHES, qm.nc))
    if spec.friction and qm.nf:
        slack = cls.slack if same and cls.slack is not None else qm.Phi @ st.c
        dslack = qm.Phi @ seg.dc
        ok.append(staying[qm.face_contact] & (slack > tol))
        val.append(slack)
        rate.append(dslack)
        cond.append(dslack)
        groups.append((TriggerKind.FACE, qm.nf))
    if qm.na:
        dphi = (seg.df - spec.dfc) * qm.r_norm
        ok.append(qm.nbd & ~cls.act_lcp)
        val.append(cls.phi if same and cls.phi is not None else (st.f - spec.command(st.t)) * qm.r_norm)
        rate.append(dphi)
        cond.append(dphi)
        groups.append((TriggerKind.COMMAND, qm.na))
    if math.isfinite(spec.t_end):  # always reached: ``end / -(-1)`` is ``end``, bit for bit
        ok.append(_END_OK)
        val.append((max(spec.t_end - st.t, 0.0),))
        rate.append(_END_RATE)
        cond.append(_END_COND)
        groups.append((TriggerKind.END, 1))
    if len(ok) > 1:
        ok_a, val_a = np.concatenate(ok), np.concatenate(val)
        rate_a, cond_a = np.concatenate(rate), np.concatenate(cond)
    else:
        ok_a, val_a, rate_a, cond_a = ok[0], cn, dcn, dcn  # the unloading contacts only
    sel = (ok_a & (cond_a < -rtol)).nonzero()[0]
    if not len(sel):
        return float("inf"), ()
    arr = np.maximum(val_a[sel] / -rate_a[sel], 0.0)
    t = float(_amin(arr))
    found = []
    for m in (arr <= t * (1.0 + 1e-9)).nonzero()[0].tolist():
        p = int(sel[m])
        for kind, n in groups:
            if p < n:
                found.append(Trigger(kind, p if kind != TriggerKind.END else -1))  # the end's: -1
                break
            p -= n
    if len(found) == 1:
        return t, (found[0],)
    # a contact that unloads reaches every face at once: keep only its unloading
    gone = {tr.index for tr in found if tr.kind == TriggerKind.SEPARATES}
    trig = tuple(
        tr for tr in found if not (tr.kind == TriggerKind.FACE and int(qm.face_contact[tr.index]) in gone)
    )
    return t, trig


def advance(
    st: State, seg: Segment, t: float, t_end: float | None = None, geo: QSModel | None = None
) -> State:
    """The state after a step ``t`` along ``seg`` (``geo``: the updated geometry the segment
    was solved on, ``State.geo``)."""
    out = State(
        st.vs + t * seg.dvs,
        st.c + t * seg.dc,
        st.f + t * seg.df,
        st.lam_c + t * seg.dlam_c if st.lam_c.size else st.lam_c,  # no coupling: shared empty
        st.hold + t * seg.dhold,
        st.slip + t * seg.dslip,
        st.t + t * seg.lam_rate,
        geo,
    )
    if t_end is not None:
        out.t = t_end
    return out


def _along(qm: QSModel, sc: StageCache, seg: Segment) -> float:
    """The object's displacement along the load per unit load on ``seg`` (scaled; ``nan``
    where the load does not grow)."""
    _, _, r0, size, _ = sc.rates
    if not seg.lam_rate > 0 or size == 0:
        return float("nan")
    return float(r0 @ seg.dvs[: qm.nx]) / size / seg.lam_rate


def _buckling(
    qm: QSModel, st: State, seg: Segment, sc: StageCache, geo: GeometryUpdates | None
) -> float | None:
    """The step along the ray ``seg`` at which the grasp buckles in the load stage
    (:func:`~.buckling.ray_buckling`); ``None``: it does not, or not below ``geo.until``."""
    if geo is None:
        return None
    b = ray_buckling(qm, st, seg, sc, geo)
    return None if b is None or st.t + b * seg.lam_rate > geo.until else b


def _buckled(run: StageRun, qm: QSModel, st: State, seg: Segment, t: float) -> StageRun:
    """``run`` ended where its ray ``seg`` from ``st`` buckles, a step ``t`` ahead
    (:func:`~.buckling.ray_buckling`): a limit, status ``UNSTABLE``."""
    if t > 0.0:
        run.states.append(advance(st, seg, t, None, qm if qm.KG is not None else None))
        run.triggers.append((Trigger(TriggerKind.BUCKLES, -1),))
        run.segments.append(unstable_segment())
    else:
        run.segments[-1] = unstable_segment()
    run.status = RunStatus.UNSTABLE
    return run


def follow(
    qm: QSModel,
    start: State,
    spec: StageSpec,
    max_segments: int = MAX_SEGMENTS,
    geometry: GeometryUpdates | None = None,
    sc: StageCache | None = None,
) -> StageRun:
    """Follow ``spec`` from ``start`` until its end, a limit, a ray or a failure; with
    ``geometry``, re-linearised about the turned object every ``geometry.step`` of rotation
    (``geometry.moved``; :attr:`StageRun.model` is the last model used). ``sc``: the
    caller's ``StageCache.of(qm, spec)``, shared (speed only)."""
    st = start.copy()
    run = StageRun(states=[st], model=qm)
    sc = StageCache.of(qm, spec) if sc is None else sc
    step = geometry.step if geometry is not None else 0.0
    before = None  # the compliance along the load just before the last update
    while True:
        cls = classify(qm, st, spec, sc)
        st.c = cls.forces  # contacts at zero force: exactly 0, anchors forgotten
        seg = _solve_segment(
            qm,
            st,
            spec,
            cls,
            run,
            run.segments[-1] if run.segments else None,
            sc,
            run.triggers[-1] if run.triggers else (),
        )
        run.segments.append(seg)
        if seg.status != SegmentStatus.OK:
            run.status = run_status(seg.status)
            return run
        if geometry is not None and before is not None:
            step, before = geometry.adapted(step, before, _along(qm, sc, seg)), None
        t, trig = next_event(qm, st, spec, cls, seg, sc)
        if geometry is not None:
            t_geo = step_to_update(qm, st, seg.dvs, geometry, seg.lam_rate, step)
            if t_geo < t:
                t, trig = t_geo, _GEOMETRY
        if not math.isfinite(t):
            buckles = _buckling(qm, st, seg, sc, geometry)
            if buckles is not None:
                return _buckled(run, qm, st, seg, buckles)
            run.status = RunStatus.UNBOUNDED
            return run
        ends = trig[-1].kind == TriggerKind.END  # the end is the last trigger when reached
        st = advance(st, seg, t, spec.t_end if ends else None, qm if qm.KG is not None else None)
        run.states.append(st)
        run.triggers.append(trig)
        if ends:
            st.c = classify(qm, st, spec, sc).forces  # contacts that reached zero: exactly 0
            run.status = RunStatus.END
            return run
        if geometry is not None and trig[0].kind == TriggerKind.GEOMETRY:
            b = spin(qm, seg.dvs) * geometry.scale
            per = step / math.sqrt(float(b.dot(b)))  # per step at this rate (np.linalg.norm's arithmetic)
            before = _along(qm, sc, seg)
            qm = moved(qm, st, spec.w0 + st.t * spec.dw, b * per, geometry.scale, seg.dc * per)
            sc = sc.rebased(qm, spec)
            run.model = qm
        if len(run.segments) >= max_segments:
            run.status = RunStatus.SEGMENT_LIMIT
            return run


__all__ = ["MAX_SEGMENTS", "StageRun", "Trigger", "advance", "follow", "next_event"]
