"""The records of a grasp plan: :class:`GraspPlan` (one ranked plan), :class:`PlanCheck` (its
simulation along one disturbance), :class:`PlanTiming` and :class:`GraspPlans` (the answer of
``pg.plan_grasps``). Frozen, with ``to_dict()`` (JSON-ready) and ``summary()``.

Plans as a GRASPS.yaml (docs/batch.md; :func:`write_grasps`): each plan is one explicit grasp (its
object pose, closed configuration ``q`` and preload command), and the file's ``score`` block
names the planner's :class:`~pinograsp.batch.disturbances.DisturbanceScore` options; floats are
written with their shortest round-trip representation, so ``pinograsp batch`` re-scores the
plans to the same numbers, bit for bit."""

from __future__ import annotations

import hashlib
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from ..batch.disturbances import gravity_of
from ..batch.grasps import GraspSpec, ObjectSpec
from ..core.paths import allowed_roots, inside
from ..core.serialize import jsonable

#: Where a plan comes from: a sampled approach, or the local search from one.
Origin = Literal["sampled", "refined"]
#: How plans are ranked: the worst-case passive resistance, or the Ferrari–Canny epsilon.
RankBy = Literal["passive", "epsilon"]


@dataclass(frozen=True)
class PlanCheck:
    """One disturbance of one plan in simulation (``pg.simulate_max_wrench``).

    Attributes:
        label: The disturbance's label (``"+fx"``, ``"w0"``, ...).
        predicted: The plan's value along it (multiple of the disturbance; [N] for the cube).
        simulated: The simulated largest load as the same multiple (``inf`` when held at the
            simulation's upper load).
        status: The simulation's status (``"gave_way"``, ``"held"``, ``"gradual"``).
        ratio: ``simulated / predicted`` (NaN when the prediction is 0 or unbounded).
    """

    label: str
    predicted: float
    simulated: float
    status: str
    ratio: float

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data."""
        return jsonable(self.__dict__)


@dataclass(frozen=True)
class GraspPlan:
    """One ranked grasp plan.

    Attributes:
        rank: 1 = best by the planner's ranking.
        id: The candidate's label (``"c<i>"`` sampled, ``"c<i>-r<k>"`` refined).
        origin: :data:`Origin`.
        spec: The grasp as a batch record (object pose, configuration ``q``, preload command):
            ``pg.evaluate_grasps([plan.spec], score=plans.score)`` gives this plan's numbers.
        object_pose: The object's pose in the hand base frame, 4×4 [m].
        hand_pose: The hand base frame in the object frame, 4×4 [m] (its inverse).
        q: The closed configuration ``{joint: value}`` [rad or m].
        command: The preload ``{actuator: value}`` [N·m or N].
        contact_names: The contacts' link names, (nc,).
        points: Contact points, hand base frame, (nc, 3) [m].
        normals: Contact normals (hand into object), (nc, 3).
        score: The worst case over the disturbances (multiple of a disturbance; [N] for the
            cube's unit forces).
        values: ``{label: value}`` per disturbance (``inf`` unbounded, 0 below resolution).
        worst: The label of the worst disturbance.
        epsilon: Ferrari–Canny epsilon of the contacts [N per N of normal force].
        epsilon_rank: Rank of ``epsilon`` among the returned plans (1 = largest).
        sampled_score: The score of the sampled approach it was refined from (its own if sampled).
        checks: Its simulation per disturbance (``verify``), else empty.
        snaps: ``{label: load}`` for the disturbances whose answer survived a snap on its way
            (the first snap's load, a multiple of the disturbance as ``values``): the
            quasi-static answer past a snap holds for fingers without inertia; heavy fingers may
            carry the object through it (docs/planning.md, "Snaps in plans").
    """

    rank: int
    id: str
    origin: Origin
    spec: GraspSpec
    object_pose: np.ndarray
    hand_pose: np.ndarray
    q: dict[str, float]
    command: dict[str, float]
    contact_names: tuple[str, ...]
    points: np.ndarray
    normals: np.ndarray
    score: float
    values: dict[str, float]
    worst: str
    epsilon: float
    epsilon_rank: int
    sampled_score: float
    checks: tuple[PlanCheck, ...] = ()
    snaps: dict[str, float] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data (the spec as :meth:`GraspSpec.to_dict`)."""
        out = {k: getattr(self, k) for k in self.__dataclass_fields__ if k not in ("spec", "checks")}
        out["spec"] = self.spec.to_dict()
        out["checks"] = [c.to_dict() for c in self.checks]
        return jsonable(out)

    def preload_text(self) -> str:
        """The preload command as ``actuator value`` pairs [N·m or N] (the score is for it)."""
        return ", ".join(f"{a} {v:.4g}" for a, v in self.command.items())

    def summary(self) -> str:
        """One line: rank, score, worst disturbance (and the directions past a snap), epsilon and its
        rank, contacts, preload."""
        snaps = f", {len(self.snaps)} past a snap (from {min(self.snaps.values()):.4g})" if self.snaps else ""
        return (
            f"#{self.rank} {self.id} ({self.origin}): score {self.score:.4g} (worst {self.worst}{snaps}), "
            f"epsilon {self.epsilon:.4g} (rank {self.epsilon_rank}), {len(self.contact_names)} contacts, "
            f"preload {self.preload_text()}"
        )


@dataclass(frozen=True)
class PlanTiming:
    """Wall times [s] of a plan (machine-dependent: not part of the plans' identity).

    Attributes:
        sample: Sampling the approach poses (main process).
        score: Closing, preloading and scoring the sampled candidates (the batch).
        refine: The local search's batches.
        finish: Rebuilding the top plans' configurations and contacts.
        verify: The simulations of ``verify``.
        total: All of it.
    """

    sample: float
    score: float
    refine: float
    finish: float
    verify: float
    total: float

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data."""
        return jsonable(self.__dict__)


@dataclass(frozen=True)
class GraspPlans:
    """The answer of ``pg.plan_grasps``: ranked plans and how they were found.

    Attributes:
        hand: The hand (built-in name or URDF path).
        object: The object (its own frame; the plans hold its pose).
        labels: The disturbances' labels, (k,).
        wrenches: The disturbances, (k, 6) [N, N·m].
        rank_by: :data:`RankBy`.
        seed: The seed of the sampling.
        plans: The plans, best first.
        sampled: Candidates sampled and scored.
        counts: Sampled candidates per batch status (``ok``, ``no_grasp``, ``error``, ...).
        refined: Candidates scored by the local search.
        best_sampled: Best score among the sampled candidates (0 when none is a grasp).
        best: Best score after the refinement (never below ``best_sampled``).
        spearman: Spearman rank correlation of the passive score and epsilon over the ``ok``
            sampled candidates (NaN with fewer than 3, or when one of them is constant).
        score_options: The batch score's options (``disturbances``, ``method``, ``upper``,
            ``steps``): ``pg.DisturbanceScore(**score_options)`` re-scores a plan's spec.
        timing: :class:`PlanTiming`.
    """

    hand: str
    object: ObjectSpec
    labels: tuple[str, ...]
    wrenches: np.ndarray
    rank_by: RankBy
    seed: int
    plans: tuple[GraspPlan, ...]
    sampled: int
    counts: dict[str, int]
    refined: int
    best_sampled: float
    best: float
    spearman: float
    score_options: dict[str, Any]
    timing: PlanTiming

    @property
    def gain(self) -> float:
        """``best - best_sampled``: what the local search added (same unit as the score)."""
        return self.best - self.best_sampled if math.isfinite(self.best) else math.nan

    def to_dict(self, timing: bool = True) -> dict[str, Any]:
        """Plain JSON-ready data (``timing=False``: without the wall times, for comparisons)."""
        out: dict[str, Any] = {k: getattr(self, k) for k in self.__dataclass_fields__}
        out["object"] = {k: v for k, v in self.object.__dict__.items() if v is not None}
        out["plans"] = [p.to_dict() for p in self.plans]
        out["timing"] = self.timing.to_dict() if timing else None
        return jsonable(out)

    def write_grasps(self, path: str | os.PathLike[str]) -> Path:
        """Write the plans as a GRASPS.yaml that ``pinograsp batch`` re-scores to the same numbers
        (:func:`pinograsp.planning.files.write_grasps`); returns the path."""
        return write_grasps(self, path)

    def summary(self) -> str:
        """A few lines: what was searched, the gain of the refinement, each plan."""
        return "\n".join([*self.header(), *(p.summary() for p in self.plans)])

    def header(self) -> list[str]:
        """What was searched, the gain of the refinement, the times (and a gravity set's unit)."""
        counts = ", ".join(f"{n} {s}" for s, n in self.counts.items())
        t = self.timing
        lines = [
            f"{self.hand} on {self.object.name or self.object.shape}: {self.sampled} candidates ({counts}), "
            f"{self.refined} refined; best {self.best_sampled:.4g} -> {self.best:.4g} "
            f"(ranked by {self.rank_by}; Spearman(score, epsilon) {self.spearman:.3g})",
            f"time {t.total:.1f} s: sample {t.sample:.2f}, score {t.score:.1f}, refine {t.refine:.1f}, "
            f"finish {t.finish:.2f}, verify {t.verify:.1f}",
        ]
        d = self.score_options.get("disturbances")
        g = gravity_of(d)
        if g is not None:
            lines.append(
                f"scores: multiples of the weight x {1 + g.margin:g} ({g.weight:.4g} N) in "
                f"{len(self.labels)} orientations; >= 1 holds it in every one"
            )
        return lines


#: GraspSpec fields written only when they differ from these defaults.
_DEFAULTS = {
    f: GraspSpec.__dataclass_fields__[f].default
    for f in ("description", "tolerance", "max_penetration", "edges")
}


def _mesh_reference(file: str, folder: Path) -> str:
    """How a GRASPS file in ``folder`` names the object mesh ``file`` so that ``pinograsp batch``
    may read it (docs/scenes.md, "Paths"): relative to ``folder`` when inside it, absolute in
    another allowed root, else the name of a copy made in ``folder``
    (``<stem>-<sha256[:8]><suffix>`` when a different file already has its name)."""
    src, base = Path(file).resolve(), Path(folder).resolve()
    if inside(src, [str(base)]):
        return os.path.relpath(src, base)
    if inside(src, allowed_roots(base)):
        return str(src)
    data = src.read_bytes()
    dest = base / src.name
    if dest.exists() and dest.read_bytes() != data:
        dest = base / f"{src.stem}-{hashlib.sha256(data).hexdigest()[:8]}{src.suffix}"
    if not dest.exists():
        dest.write_bytes(data)
    return dest.name


def _object(spec: GraspSpec, folder: Path) -> dict[str, Any]:
    o = spec.object
    out: dict[str, Any] = {"shape": o.shape}
    for key in ("size", "radius", "length"):
        if getattr(o, key) is not None:
            v = getattr(o, key)
            out[key] = list(v) if isinstance(v, tuple) else v
    if o.file is not None:
        out.update(file=_mesh_reference(o.file, folder), scale=o.scale)
        if o.convex is not None:
            out["convex"] = o.convex
    out["pose"] = {"xyz": list(o.xyz), "rpy": list(o.rpy)}
    if o.name is not None:
        out["name"] = o.name
    return out


def grasp_entry(spec: GraspSpec, folder: str | os.PathLike[str] = ".") -> dict[str, Any]:
    """One plan as a grasp of a GRASPS.yaml in ``folder`` (plain data; an object mesh outside
    the folder's allowed roots is copied into it, :func:`_mesh_reference`)."""
    d = spec.to_dict()
    hand = d["hand"]
    out: dict[str, Any] = {"id": d["id"], "hand": str(Path(hand).resolve()) if os.sep in hand else hand}
    out["object"] = _object(spec, Path(folder))
    for key in (
        "q",
        "command",
        "mu",
        "stiffness",
        "patches",
        "step",
        "max_steps",
        "max_command",
        "preload_method",
    ):
        out[key] = d[key]
    out["preload_method"] = str(getattr(spec.preload_method, "value", spec.preload_method))
    if d["q_open"] is not None:
        out["q_open"] = d["q_open"]
    for key, default in _DEFAULTS.items():
        if d[key] != default:
            out[key] = str(Path(d[key]).resolve()) if key == "description" else d[key]
    if d["package_dirs"]:
        out["package_dirs"] = [str(Path(p).resolve()) for p in d["package_dirs"]]
    return out


def write_grasps(plans: GraspPlans, path: str | os.PathLike[str]) -> Path:
    """Write the plans as a GRASPS.yaml (``score`` block: the planner's score) and return the path."""
    import yaml

    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    doc = {"score": dict(plans.score_options), "grasps": [grasp_entry(g.spec, p.parent) for g in plans.plans]}
    header = f"# {len(plans.plans)} grasp plans of {plans.hand}: pinograsp batch {p.name} re-scores them\n"
    p.write_text(header + yaml.safe_dump(doc, sort_keys=False))
    return p
