"""Candidates and their scoring: batches of grasp records scored on the batch executors, the
ranking key, the local search's moves and the removal of near-duplicates (docs/planning.md).

A :class:`Candidate` is a scored grasp record. Its **key** orders candidates: with
``rank_by="passive"`` the worst-case value, then the other values from the worst up (leximin:
of two grasps with the same worst case, the one whose second-worst is larger wins), then
epsilon; with ``"epsilon"`` epsilon first, then the passive key. Ties keep the candidates'
order, so the ranking is a pure function of the scores.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..batch.disturbances import DisturbanceScore
from ..batch.evaluate import evaluate_grasps
from ..batch.grasps import GraspSpec
from ..core.poses import rpy_of
from .approach import moved, pose_distance
from .records import Origin, RankBy


@dataclass(frozen=True)
class Candidate:
    """A scored grasp record.

    Attributes:
        spec: The record (object pose, preload; ``q`` not yet known: auto-closed).
        status: The batch row's status (``"ok"``, ``"no_grasp"``, ``"error"``, ...).
        reason: The row's typed reason (``""`` when ok).
        values: ``{label: value}`` per disturbance (empty unless ok).
        score: Worst case of ``values`` (0 unless ok).
        epsilon: Ferrari–Canny epsilon (0 unless ok).
        command: The preload the row used ``{actuator: value}``.
        origin: Sampled or refined.
        sampled_score: The score of the sampled candidate it descends from.
        snaps: ``{label: load}``: the first snap each answer survived below its value (a
            multiple of the disturbance, as ``values``), for the labels whose answer has one.
    """

    spec: GraspSpec
    status: str
    reason: str
    values: dict[str, float]
    score: float
    epsilon: float
    command: dict[str, float]
    origin: Origin
    sampled_score: float
    snaps: dict[str, float] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """Whether it is a scored grasp."""
        return self.status == "ok"

    def key(self, rank_by: RankBy) -> tuple[float, ...]:
        """The ranking key (larger is better); a candidate that is not a grasp is below all."""
        if not self.ok:
            return (-math.inf,)
        passive = (self.score, *sorted(self.values.values()), self.epsilon)
        return passive if rank_by == "passive" else (self.epsilon, *passive)


def ranked(pool: Sequence[Candidate], rank_by: RankBy) -> list[Candidate]:
    """The candidates best first; ties keep their order in ``pool``."""
    order = sorted(range(len(pool)), key=lambda i: (tuple(-v for v in pool[i].key(rank_by)), i))
    return [pool[i] for i in order]


def score_batch(
    specs: Sequence[GraspSpec],
    score: DisturbanceScore,
    origin: Origin,
    sampled: Sequence[float] | None,
    run: dict[str, Any],
    progress: Callable[[int, int], None] | None,
) -> list[Candidate]:
    """Score grasp records with ``pg.evaluate_grasps`` (``run``: ``executor``, ``workers``) and
    read each row back as a :class:`Candidate` (``sampled``: the sampled scores they descend
    from; ``None``: their own)."""
    if not specs:
        return []
    table = evaluate_grasps(list(specs), score=score, progress=progress, **run)
    columns = [f"max_{a}" for a in score.labels]
    out = []
    for i, (spec, row) in enumerate(zip(specs, table.to_dict("records"))):
        if row["status"] == "ok" and row.get("pruned", 0.0) == 1.0:  # worse than its incumbent
            row = {**row, "status": "pruned", "reason": "below_incumbent"}
        ok = row["status"] == "ok"
        values = {c[4:]: float(row[c]) for c in columns} if ok else {}
        values = {k: v for k, v in values.items() if not math.isnan(v)}
        snaps = {k: float(row[f"snap_{k}"]) for k in values if ok and float(row[f"snap_{k}"]) < math.inf}
        s = float(row["score"]) if ok else 0.0
        command = json.loads(row["command"]) if row["command"] else {}
        origin_score = s if sampled is None else sampled[i]
        eps = float(row["epsilon"]) if ok else 0.0
        status, reason = row["status"], row["reason"]
        out.append(Candidate(spec, status, reason, values, s, eps, command, origin, origin_score, snaps))
    return out


def placed(spec: GraspSpec, T: np.ndarray, **fields: Any) -> GraspSpec:
    """``spec`` with the object at pose ``T`` (hand base frame, 4×4) and other fields changed."""
    obj = spec.object.with_pose(T[:3, 3].tolist(), rpy_of(T[:3, :3]))
    return replace(spec, object=obj, **fields)


@dataclass(frozen=True)
class Steps:
    """Step sizes of the local search around one incumbent: translation [m], rotation [rad],
    preload transfer (fraction of the budget)."""

    translation: float
    rotation: float
    transfer: float

    def halved(self) -> Steps:
        """Every step halved (after a round without improvement)."""
        return Steps(self.translation / 2, self.rotation / 2, self.transfer / 2)


def neighbours(
    c: Candidate, steps: Steps, centre: np.ndarray, budget: float | None, actuators: Sequence[str]
) -> list[GraspSpec]:
    """The local search's moves from ``c``: the object shifted by ``±translation`` and turned by
    ``±rotation`` about the grasp centre along each hand axis (12 poses; an ``"auto"`` preload
    keeps the incumbent's command instead of being designed again), and with a preload budget
    ``transfer * budget`` moved from one actuator to another (``2 * C(na, 2)`` splits)."""
    T = c.spec.object.pose
    # an "auto" preload is not designed again for a pose move: the incumbent's command is kept
    fixed = {"command": tuple(c.command.items())} if c.spec.command == "auto" and c.command else {}
    out = []
    for k in range(3):
        for sign in (1.0, -1.0):
            e = np.zeros(3)
            e[k] = sign
            out.append(placed(c.spec, moved(T, centre, steps.translation * e, np.zeros(3)), **fixed))
            out.append(placed(c.spec, moved(T, centre, np.zeros(3), steps.rotation * e), **fixed))
    if budget is not None and len(actuators) > 1:
        split = dict(c.spec.command) if isinstance(c.spec.command, tuple) else {}
        for a in actuators:
            for b in actuators:
                if a == b:
                    continue
                amount = min(steps.transfer * budget, split.get(b, 0.0))
                if amount <= 0:
                    continue
                new = dict(split)
                new[a], new[b] = new.get(a, 0.0) + amount, new[b] - amount
                out.append(replace(c.spec, command=tuple((n, new.get(n, 0.0)) for n in actuators)))
    return out


def distinct(
    order: Sequence[Candidate], top: int, centre: np.ndarray, translation: float, rotation: float
) -> list[Candidate]:
    """The first ``top`` grasps of ``order`` that are not near-duplicates of an earlier pick: a
    grasp is a near-duplicate when its grasp centre lies within ``translation`` [m] of a pick's
    in the object frame and the hand's orientation within ``rotation`` [rad]."""
    picks: list[Candidate] = []
    for c in order:
        if len(picks) == top or not c.ok:
            break
        T = c.spec.object.pose
        if all(
            not (d <= translation and a <= rotation)
            for d, a in (pose_distance(T, p.spec.object.pose, centre) for p in picks)
        ):
            picks.append(c)
    return picks


def local_search(
    seeds: Sequence[Candidate],
    evaluate: Callable[[list[GraspSpec], list[float], Candidate], list[Candidate]],
    first: Steps,
    rounds: int,
    rank_by: RankBy,
    moves: Callable[[Candidate, Steps], list[GraspSpec]],
) -> list[Candidate]:
    """Deterministic pattern search from each seed: every round scores each incumbent's moves in
    one batch (``evaluate(specs, sampled scores, incumbent)``, which may prune the moves that fall
    below the incumbent); an incumbent moves to its best neighbour when that is strictly better,
    else its steps are halved. Returns every candidate scored (incumbents never get worse)."""
    state = [(c, first) for c in seeds]
    scored: list[Candidate] = []
    for r in range(rounds):
        new_state = []
        for c, s in state:
            b = [replace(m, id=f"{c.spec.id}-r{r}.{i}") for i, m in enumerate(moves(c, s))]
            mine = evaluate(b, [c.sampled_score] * len(b), c)
            scored += mine
            best = ranked([c, *mine], rank_by)[0]
            new_state.append((best, s) if best is not c else (c, s.halved()))
        state = new_state
    return scored
