"""The batch's default score, :class:`WorstAxisScore`, and the record of a score that answered
in some directions only (:class:`ScoreValues`, :class:`DirectionFailure`).

A direction that raises a pinograsp error of the ``error`` kind (a solver failure, the
quasi-static path stopping without a verdict, a solver limit: :data:`.rows.REASONS`) does not
drop the others: the score returns every direction that answered, NaN for the one that did
not, its typed reason in ``status_<direction>``, and its worst case ``score`` NaN (the smallest
of the answered directions is only an upper bound of it: the missing one may be smaller). The
row is then ``"partial"`` (:func:`.evaluate.evaluate_one`). An answer about the grasp itself
(``no_grasp``: the preload does not balance, no preload exists) and any other exception (a bug)
still make the whole row, as does a failure of every direction.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

from ..core.methods import bounded as limits_bound
from ..core.methods import method_name
from ..core.query import Query
from ..core.settings import DEFAULT_METHOD, Method
from ..core.validate import force
from ..core.validate import steps as n_steps
from ..errors import PinograspError
from .rows import classify

#: ``status_<direction>`` of a direction that answered.
ANSWERED = "ok"


@dataclass(frozen=True)
class DirectionFailure:
    """One direction of a score that raised instead of answering.

    Attributes:
        direction: Its label (``"+fx"``, ...).
        reason: The typed cause (:data:`.rows.REASONS`: ``"solver_error"``, ``"solver_limit"``, ...).
        error_type: The exception's class name.
        message: The exception's message (one line).
    """

    direction: str
    reason: str
    error_type: str
    message: str

    @classmethod
    def of(cls, direction: str, exc: BaseException) -> DirectionFailure:
        """The failure of ``direction`` that raised ``exc``."""
        return cls(direction, classify(exc)[1], type(exc).__name__, " ".join(str(exc).split()))


class ScoreValues(dict):
    """A score's values ``{name: float}`` with, per direction, ``statuses``
    ``{"status_<direction>": "ok" | reason}`` and the ``failures`` of the directions that did
    not answer (empty: a complete answer). A plain ``dict`` to every other reader."""

    def __init__(
        self,
        values: Mapping[str, float],
        statuses: Mapping[str, str] | None = None,
        failures: tuple[DirectionFailure, ...] = (),
    ) -> None:
        super().__init__(values)
        self.statuses = dict(statuses or {})
        self.failures = tuple(failures)


@dataclass(frozen=True)
class WorstAxisScore:
    """Default score: the worst-case max resistible force over the signed force axes.

    For each of ``±fx, ±fy, ±fz`` (``±fx, ±fy`` for planar models), the max resistible wrench
    magnitude [N] (:func:`pinograsp.max_resistible_wrench` with ``upper``, ``steps``, ``method``;
    ``inf`` when unbounded, ``upper`` when above the limit, 0 below the resolution). Returns
    (a :class:`ScoreValues`) ``score`` (the smallest, [N]), ``unbounded_fraction`` (of the
    axes, in [0, 1]), each axis as ``max_+fx``, ``max_-fx``, ... [N], and each axis's status
    ``status_+fx``, ... (``"ok"``, or the reason it did not answer; ``""`` for the ``±fz`` of a
    planar model). When some axes did not answer (module docstring): their ``max_`` NaN,
    ``score`` and ``unbounded_fraction`` NaN, the answered axes' values as in a complete run.

    Attributes:
        upper: Search limit [N].
        steps: Search steps (resolution ``upper / 2**steps``; small for speed).
        method: ``"quasistatic"`` (default: the loading path's limit per axis; ``upper`` is
            then only the cap of the score and ``steps`` does not apply), ``"iterative"``,
            ``"prp"`` or ``"energetic"`` (maximum dissipation: one load-factor solve per axis,
            ``search="direct"``), kept as a :class:`~pinograsp.core.settings.Method`.
    """

    upper: float = 50.0
    steps: int = 6
    method: Method | str = Method(DEFAULT_METHOD)

    #: The columns of every table scored with it (planar models leave ``max_±fz`` NaN).
    columns: ClassVar[tuple[str, ...]] = (
        "score", "unbounded_fraction", "max_+fx", "max_-fx", "max_+fy", "max_-fy", "max_+fz", "max_-fz",
    )  # fmt: skip
    #: The text columns of every table scored with it: each axis's status.
    status_columns: ClassVar[tuple[str, ...]] = (
        "status_+fx", "status_-fx", "status_+fy", "status_-fy", "status_+fz", "status_-fz",
    )  # fmt: skip
    #: The values of a record that is not a grasp (no contact, no preload, ...): it resists nothing.
    no_grasp: ClassVar[dict[str, float]] = dict.fromkeys(columns, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "method", method_name(self.method))
        object.__setattr__(self, "upper", force("upper", self.upper, "N or N·m"))  # docs/errors.md
        bounded = limits_bound(self.method)  # the loading path does not bisect
        object.__setattr__(self, "steps", n_steps(self.steps, bounded=bounded))

    def __call__(self, model: Any, command: Mapping[str, float]) -> ScoreValues:
        from ..analysis.max_wrench import max_resistible_wrench
        from ..analysis.response import Session

        axes = ("fx", "fy") if model.planar else ("fx", "fy", "fz")
        mags: dict[str, float] = {}
        unbounded = 0
        failures: list[DirectionFailure] = []
        first: PinograspError | None = None
        query = Query(self.method, self.upper, self.steps)
        session = Session(model)  # one per grasp: its preload stage is solved once
        for direction in (s + a for a in axes for s in ("+", "-")):
            try:  # the preload is checked by the first direction that answers
                mw = max_resistible_wrench(
                    model, command, direction.lstrip("+"), session=session, query=query,
                    check_preload_first=len(mags) == len(failures),
                )  # fmt: skip
            except PinograspError as exc:
                if classify(exc)[0] != "error":  # an answer about the grasp: the whole row
                    raise
                first = first or exc
                failures.append(DirectionFailure.of(direction, exc))
                mags[f"max_{direction}"] = math.nan
                continue
            unbounded += bool(mw.unbounded)
            mags[f"max_{direction}"] = 0.0 if mw.status == "below_resolution" else float(mw.magnitude)
        if first is not None and len(failures) == len(mags):  # nothing answered: an error row
            raise first
        done = {f.direction: f.reason for f in failures}
        statuses = {f"status_{d[4:]}": done.get(d[4:], ANSWERED) for d in mags}
        if failures:
            head = {"score": math.nan, "unbounded_fraction": math.nan}
        else:
            head = {"score": min(mags.values()), "unbounded_fraction": unbounded / len(mags)}
        return ScoreValues({**head, **mags}, statuses, tuple(failures))


__all__ = ["ANSWERED", "DirectionFailure", "ScoreValues", "WorstAxisScore"]
