"""Past a softening limit: the equilibrium path under displacement control, and the snap.

At a limit point with softening (``dλ < 0`` per unit displacement along the load) a grasp under
a growing load cannot stay quasi-static: it jumps. The simulation (and a real hand) may land a
short distance further on a branch that stiffens again and hold there; whether it "gave way"
depends on how far it jumped. This module follows the equilibrium path beyond the limit under
displacement control (the load may fall) until the load comes back to the limit load — the
*landing* point of the snap, from where the path continues under load control as usual — or
until the load falls to zero or the path stops. :meth:`LoadingPath.load_at_displacement` uses
it; the limit load λ* itself stays the first limit (docs/quasistatic.md, "Continuation and snaps").
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .geometry import GeometryUpdates
from .model import QSModel
from .path import LIMIT_RTOL, StageRun, Trigger, advance, follow, next_event, plan_of, planned
from .rates import Segment, StageCache, StageSpec, classify
from .statuses import RunStatus, SegmentStatus, TriggerKind, run_status

#: Largest number of segments of one descent past a limit (a count).
MAX_DESCENT = 200
#: Largest number of snaps followed.
MAX_SNAPS = 20


def _neutral(qm: QSModel, seg: Segment, size: float) -> bool:
    """Whether ``seg`` (displacement control) keeps the load: ``|dλ|`` per unit displacement
    along the load (``size``: the norm of the stage's scaled load rate) within
    :data:`~.path.LIMIT_RTOL` of the largest contact stiffness — a mechanism along the load,
    which the grasp follows at the limit load (it drifts)."""
    return abs(seg.lam_rate) * size <= LIMIT_RTOL * qm.k_ref


def _descend(qm: QSModel, out: StageRun, seg: Segment, spec: StageSpec, sc: StageCache) -> RunStatus:
    """Follow the path from ``out.states[-1]`` (a limit, leaving segment ``seg``) under
    displacement control until the load is back at the limit (``LANDED``), falls to zero
    (``UNLOADED``) or the path stops; the states are appended to ``out``. A neutral segment
    (a mechanism along the load, :func:`_neutral`) is followed at the limit load to its next
    event (a contact touches, a face is reached): it lands where the grasp stiffens again, and
    is a ``MECHANISM`` when no event lies ahead."""
    st = out.states[-1]
    peak = st.t
    cls = classify(qm, st, spec, sc)
    st.c = cls.forces
    size = float(np.linalg.norm(qm.w_scaled(spec.dw)))  # the scaled load rate's, for _neutral
    for _ in range(MAX_DESCENT):
        if _neutral(qm, seg, size):  # drift at the limit load: rounding of dλ is no load change
            seg = replace(seg, lam_rate=0.0)
        out.segments.append(seg)
        t, trig = next_event(qm, st, spec, cls, seg, sc)
        lam_rate = seg.lam_rate
        if lam_rate == 0.0 and not math.isfinite(t):
            return RunStatus.MECHANISM
        if lam_rate > 0 and (peak - st.t) / lam_rate <= t:
            t, trig = max((peak - st.t) / lam_rate, 0.0), (Trigger(TriggerKind.LANDED, -1),)
        elif lam_rate < 0 and st.t / -lam_rate <= t:
            out.states.append(advance(st, seg, st.t / -lam_rate))
            out.states[-1].geo = qm if qm.KG is not None else None
            out.triggers.append((Trigger(TriggerKind.UNLOADED, -1),))
            return RunStatus.UNLOADED
        if not math.isfinite(t):
            return RunStatus.MECHANISM if lam_rate <= 0 else RunStatus.UNBOUNDED
        st = advance(st, seg, t, geo=qm if qm.KG is not None else None)
        out.states.append(st)
        out.triggers.append(trig)
        if trig and trig[0].kind == TriggerKind.LANDED:
            st.t = peak
            return RunStatus.LANDED
        cls = classify(qm, st, spec, sc)
        st.c = cls.forces
        prev: Segment = seg
        seg = planned(qm, st, spec, cls, "displacement", plan_of(qm, cls, prev), out, sc, (prev.active,))
        if seg.status != SegmentStatus.OK:
            return run_status(seg.status)
    return RunStatus.SEGMENT_LIMIT


def continue_past_limit(
    qm: QSModel, run: StageRun, spec: StageSpec, max_segments: int, geometry: GeometryUpdates | None = None
) -> StageRun | None:
    """The path from the limit state of ``run`` (status ``"limit"``) beyond it: descents
    under displacement control and, after each landing, the load-controlled path to its next
    limit, up to :data:`MAX_SNAPS` snaps. ``status``: ``LANDED`` (``tail``: the status of the
    last load-controlled part), ``UNLOADED`` (the load falls to zero), ``MECHANISM`` (no
    stiffness left) or a failure; ``snaps`` holds ``(limit index, landing index)`` pairs. None
    when the limit is not a softening one (a mechanism along the load: nothing to land on).
    The descents keep the geometry of the limit (``run.model``); the load-controlled parts
    after a landing update it as :func:`~.path.follow` does with ``geometry``."""
    qm = run.model if run.model is not None else qm
    seg = run.segments[-1]
    if seg.control != "displacement":
        return None
    out = StageRun(states=[run.states[-1].copy()], model=qm)
    sc = StageCache.of(qm, spec)
    for _ in range(MAX_SNAPS):
        top = len(out.states) - 1
        status = _descend(qm, out, seg, spec, sc)
        if status != RunStatus.LANDED:
            out.status = status
            return out
        out.snaps.append((top, len(out.states) - 1))
        rest = follow(qm, out.states[-1], spec, max_segments, geometry, sc)  # sc: StageCache.of(qm, spec)
        if rest.model is not None and rest.model is not qm:
            qm, out.model = rest.model, rest.model
            sc = StageCache.of(qm, spec)
        out.states += rest.states[1:]
        out.segments += rest.segments
        out.triggers += rest.triggers
        out.lcp_solves += rest.lcp_solves
        out.status, out.tail = RunStatus.LANDED, rest.status
        last = rest.segments[-1] if rest.segments else None
        if rest.status != RunStatus.LIMIT or last is None or last.control != "displacement":
            return out
        out.segments.pop()  # the limit's segment is the next descent's first
        seg = last
    return out


__all__ = ["MAX_DESCENT", "MAX_SNAPS", "continue_past_limit"]
