"""The :class:`LoadingPath` records of a followed stage and of the path past a limit."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from types import MappingProxyType

import numpy as np

from ...core.axes import PLANAR_AXES
from .audit import audit_failure, path_audit, stacks, unbalanceable
from .events import path_events
from .path import StageRun
from .preload import released_states
from .prepared import Prepared
from .rates import EVENT_RTOL, StageSpec, State, force_scale
from .result import LoadingPath, PathStatus, StopReason
from .statuses import RunStatus


def _arrays(p: Prepared, states: list[State], stacked: dict | None = None) -> dict[str, np.ndarray]:
    """Physical arrays of the states (actuator quantities with the command signs)."""
    qm, m = p.qm, p.model
    k = len(states)
    st = stacks(states) if stacked is None else stacked
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


#: The stop reason of each way a stage can end (:data:`~.result.StopReason`).
STOP_REASONS: Mapping[RunStatus, StopReason] = MappingProxyType(
    {
        RunStatus.END: "load",
        RunStatus.UNBOUNDED: "ray",
        RunStatus.LIMIT: "limit",
        RunStatus.UNSTABLE: "unstable",
        RunStatus.SEGMENT_LIMIT: "segment_limit",
        RunStatus.SINGULAR: "singular",
        RunStatus.RAY_TERMINATION: "ray_termination",
        RunStatus.PIVOT_LIMIT: "pivot_limit",
        RunStatus.INACCURATE: "inaccurate",
        RunStatus.LANDED: "landed",
        RunStatus.UNLOADED: "unloaded",
        RunStatus.MECHANISM: "mechanism",
    }
)


def _status(run: StageRun, p: Prepared, spec: StageSpec) -> tuple[PathStatus, float, StopReason]:
    """(status, limit, stop reason) of a load stage."""
    last = run.states[-1].t
    reason = STOP_REASONS[run.status]
    if run.status in (RunStatus.LIMIT, RunStatus.UNSTABLE):
        scale = force_scale(p.qm, p.start, spec) / max(float(np.abs(p.qm.w_scaled(spec.dw)).max()), 1e-300)
        if last <= EVENT_RTOL * scale:
            return "below_resolution", 0.0, reason
        return "finite", float(last), reason
    if run.status == RunStatus.UNBOUNDED:
        return "unbounded", float("inf"), reason
    if run.status == RunStatus.END:
        return "reached", float(last), reason
    if run.status == RunStatus.SEGMENT_LIMIT:
        return "segment_limit", float(last), reason
    return "no_solution", float(last), reason


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
    stacked = stacks(states)
    arrays = _arrays(p, states, stacked)
    segs = [s for s in run.segments if s.contact]
    k = len(states)
    cs: list[tuple[str, ...]]
    if segs:  # state j: the segment leaving it, the last one past the last segment
        at = segs[:k] + segs[-1:] * (k - len(segs))
        cs, sf, am = [s.contact for s in at], [s.detail for s in at], [s.actuator for s in at]
    else:  # no load segment (up_to=0): the states of the state itself, not "separated"
        cs0, sf0, am0 = released_states(qm, states[0], spec)
        cs, sf, am = [cs0] * k, [sf0] * k, [am0] * k
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
    audit = path_audit(p, states, arrays, d_red, stacked, energy=not lean)
    first_bad = audit_failure(audit, run_loads, arrays, lambda: unbalanceable(m, d_red))
    if first_bad is not None:  # no verdict from a path that is not an equilibrium path
        status, reason, ray = "no_solution", "audit", None
        limit = float(run_loads[max(first_bad - 1, 0)])
    return LoadingPath(
        direction=d6,
        command=p.fc * p.signs,
        variant=p.variant,
        tangential_ratio=p.ratio,
        status=status,
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
        geometries=tuple(s.geo for s in states) if any(s.geo is not None for s in states) else (),
        **arrays,  # type: ignore[arg-type]  # the array fields by name
    )


def continuation_record(
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
        stop_reason=STOP_REASONS[tail],  # how the path past the limit ended (after its last landing)
        snaps=snaps,
        ray=ray,
    )


__all__ = ["build_path", "continuation_record"]
