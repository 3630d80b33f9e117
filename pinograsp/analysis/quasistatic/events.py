"""Typed event records of a loading path: what changed, where, at which load."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from .model import QSModel
from .path import StageRun, Trigger
from .rates import Segment
from .statuses import RunStatus, TriggerKind

#: What an event is about.
EventKind = Literal["contact", "actuator", "limit", "unbounded", "stop"]


@dataclass(frozen=True)
class PathEvent:
    """One change along the loading path.

    Attributes:
        load: Load factor λ at the event [N or N·m along the direction].
        kind: ``"contact"`` or ``"actuator"`` (a state changed), ``"limit"`` (no continuation
            with growing load: the limit load), ``"unbounded"`` (the last segment is a ray
            with no event ahead) or ``"stop"`` (the path stopped without a verdict).
        name: The contact or actuator ('' for path-level events).
        index: Its index in the model's contacts / actuators (-1 for path-level events).
        before: State before (``"sticking"``, ``"sliding (face 3)"``, ``"sliding (vertex
            2|3)"``, ``"separated"``; ``"moving"``, ``"holding"``, ...).
        after: State after.
        cause: The inequalities reached at this load, as text (e.g. ``"face 2 of f1"``).
        breakpoint: Index of the breakpoint of :class:`LoadingPath` where it happens.
    """

    load: float
    kind: EventKind
    name: str
    index: int
    before: str
    after: str
    cause: str = ""
    breakpoint: int = 0

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data."""
        return {
            "load": self.load,
            "kind": self.kind,
            "name": self.name,
            "index": self.index,
            "before": self.before,
            "after": self.after,
            "cause": self.cause,
            "breakpoint": self.breakpoint,
        }

    def text(self) -> str:
        """One line: ``λ=…: name before -> after (cause)``."""
        what = f"{self.name}: {self.before} -> {self.after}" if self.name else self.after
        why = f" ({self.cause})" if self.cause else ""
        return f"λ = {self.load:.6g}: {what}{why}"


def contact_label(seg: Segment, i: int) -> str:
    """State of contact ``i`` on ``seg`` as text."""
    state = seg.contact[i]
    faces = seg.detail[i]
    if state != "sliding":
        return state
    if len(faces) == 1:
        return f"sliding (face {faces[0]})"
    return "sliding (vertex " + "|".join(str(f) for f in faces) + ")"


def trigger_text(qm: QSModel, tr: Trigger) -> str:
    """An inequality reached, as text."""
    m = qm.model
    if tr.kind == TriggerKind.SEPARATES:
        return f"{m.contact_names[tr.index]} unloaded"
    if tr.kind == TriggerKind.TOUCHES:
        return f"{m.contact_names[tr.index]} touched"
    if tr.kind == TriggerKind.FACE:
        i = int(qm.face_contact[tr.index])
        return f"face {int(qm.face_index[tr.index])} of {m.contact_names[i]} reached"
    if tr.kind == TriggerKind.COMMAND:
        return f"{m.actuator_names[tr.index]} back at its command"
    if tr.kind == TriggerKind.GEOMETRY:
        return "geometry updated at the turned object"
    if tr.kind == TriggerKind.BUCKLES:
        return "the grasp buckles: a motion no spring holds, against its compressed contacts"
    return "end of stage"


def path_events(qm: QSModel, run: StageRun, status: str) -> tuple[PathEvent, ...]:
    """The events of a load stage: state changes between consecutive segments, then the end."""
    m = qm.model
    out: list[PathEvent] = []
    segs = [s for s in run.segments if s.contact]
    for k in range(1, len(run.states)):
        if k >= len(segs):
            break
        prev, new = segs[k - 1], segs[k]
        if prev.contact == new.contact and prev.detail == new.detail and prev.actuator == new.actuator:
            continue  # the same labels: no event (speed only)
        load = run.states[k].t
        cause = "; ".join(trigger_text(qm, tr) for tr in run.triggers[k - 1])
        pairs = zip(prev.contact, new.contact, prev.detail, new.detail)
        for i, (c0, c1, f0, f1) in enumerate(pairs):
            if c0 == c1 and f0 == f1:
                continue
            a, b = contact_label(prev, i), contact_label(new, i)
            if a != b:
                out.append(PathEvent(load, "contact", m.contact_names[i], i, a, b, cause, k))
        for j in range(qm.na if prev.actuator != new.actuator else 0):
            a, b = prev.actuator[j], new.actuator[j]
            if a != b:
                out.append(PathEvent(load, "actuator", m.actuator_names[j], j, a, b, cause, k))
    last = len(run.states) - 1
    load = run.states[-1].t
    cause = "; ".join(trigger_text(qm, tr) for tr in run.triggers[-1]) if run.triggers else ""
    if status in ("finite", "below_resolution"):
        what = "limit load"
        if run.status == RunStatus.UNSTABLE:
            what += " (no quasi-static continuation: the grasp snaps)"
        out.append(PathEvent(load, "limit", "", -1, "", what, cause, last))
    elif status == "unbounded":
        out.append(PathEvent(load, "unbounded", "", -1, "", "no event ahead: unbounded", "", last))
    elif status != "end":
        out.append(PathEvent(load, "stop", "", -1, "", f"stopped: {status}", cause, last))
    return tuple(out)


__all__ = ["EventKind", "PathEvent", "contact_label", "path_events"]
