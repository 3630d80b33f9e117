"""Typed states of the path's records (docs/quasistatic.md): how a rate problem ended, how a
stage ended, and which inequality a segment reached. String-valued enums: each member equals
its value (``SegmentStatus.OK == "ok"``), so records print and serialise as before."""

from __future__ import annotations

from enum import Enum


class _Text(str, Enum):
    """A string-valued enum that prints as its value (messages, f-strings, JSON)."""

    def __str__(self) -> str:
        return str(self.value)

    def __format__(self, spec: str) -> str:
        return format(str(self.value), spec)


class SegmentStatus(_Text):
    """How the local rate problem at a state ended (:attr:`~.rates.Segment.status`)."""

    #: Rates found: the segment is followed.
    OK = "ok"
    #: No continuation with a growing load (``dλ <= 0`` under displacement control).
    LIMIT = "limit"
    #: Certified: no equilibrium path leaves the state (:mod:`~.snap`); the grasp snaps.
    UNSTABLE = "unstable"
    #: A zero-force contact's guess (pressed or separated) is contradicted by its own rates:
    #: tried again with the guess flipped (never a path's status).
    GUESS = "guess"
    #: A face of a zero-force contact left out of the LCP is crossed: tried again with it
    #: (never a path's status).
    APEX = "apex"
    #: The linear part has no solution (the load outside the system's range).
    SINGULAR = "singular"
    #: Lemke's method: ray termination, the pivot limit, or an inaccurate final basis.
    RAY_TERMINATION = "ray_termination"
    PIVOT_LIMIT = "pivot_limit"
    INACCURATE = "inaccurate"


class RunStatus(_Text):
    """How following a stage ended (:attr:`~.path.StageRun.status`; a continuation past a
    limit adds ``LANDED``, ``UNLOADED`` and ``MECHANISM``)."""

    #: The stage's end (``t_end``) was reached.
    END = "end"
    #: The last segment is a ray with no event ahead.
    UNBOUNDED = "unbounded"
    #: A limit load (``dλ <= 0`` under displacement control) or a certified snap.
    LIMIT = "limit"
    UNSTABLE = "unstable"
    #: The segment-count limit (a count) was reached.
    SEGMENT_LIMIT = "segment_limit"
    #: The rate problem failed (:class:`SegmentStatus`'s failures).
    SINGULAR = "singular"
    RAY_TERMINATION = "ray_termination"
    PIVOT_LIMIT = "pivot_limit"
    INACCURATE = "inaccurate"
    #: Past a limit: the load came back to the limit load (the snap's landing).
    LANDED = "landed"
    #: Past a limit: the load fell to zero (nothing to land on).
    UNLOADED = "unloaded"
    #: Past a limit: no stiffness left along the load and no event ahead.
    MECHANISM = "mechanism"


class TriggerKind(_Text):
    """An inequality reached at the end of a segment (:attr:`~.path.Trigger.kind`)."""

    #: A pressed contact's normal force reaches zero.
    SEPARATES = "separates"
    #: An open contact's gap closes.
    TOUCHES = "touches"
    #: A touching contact's force reaches a face of its friction polygon.
    FACE = "face"
    #: A holding actuator's force comes down to its command.
    COMMAND = "command"
    #: The stage's end.
    END = "end"
    #: The object turned a geometry step: the model is re-linearised (``geometry.moved``).
    GEOMETRY = "geometry"
    #: The tangent stiffness on a ray stops holding a motion (:mod:`~.buckling`).
    BUCKLES = "buckles"
    #: Past a limit: the load is back at the limit load.
    LANDED = "landed"
    #: Past a limit: the load reached zero.
    UNLOADED = "unloaded"


def run_status(status: SegmentStatus) -> RunStatus:
    """The stage's status when a segment's rate problem ends it."""
    return RunStatus(status.value)


__all__ = ["RunStatus", "SegmentStatus", "TriggerKind", "run_status"]
