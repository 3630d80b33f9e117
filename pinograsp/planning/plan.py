"""``pg.plan_grasps``: sample approach poses, close, preload, score, refine, rank (docs/planning.md).

1. **Sample** ``n`` approaches on the object's surface (:mod:`.approach`): a point and its
   normal, a roll about it and a depth, from ``numpy.random.default_rng(seed)``.
2. **Close, preload and score** them as one batch (``pg.evaluate_grasps`` with a
   :class:`~pinograsp.batch.disturbances.DisturbanceScore`: the auto-close, the preload — given,
   ``"auto"`` or a budget split — and the passive answer along every disturbance with the
   package's analysis, plus the Ferrari–Canny epsilon), on the batch executors.
3. **Refine** the best ``refine`` distinct candidates by a deterministic pattern search over the
   hand pose (and the preload split of a budget): :func:`~.search.local_search`.
4. **Rank** everything scored, drop near-duplicates, rebuild the top plans' configurations and
   contacts, and with ``verify=k`` simulate the first ``k`` along every disturbance.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any, cast

import numpy as np

from ..batch.disturbances import DisturbanceScore, Gravity
from ..batch.grasps import GraspSpec, ObjectSpec, build_grasp, grasp_configuration, load_hand
from ..core.settings import DEFAULT_METHOD
from ..core.validate import MAX_SAMPLES, choice, count, finite_number, positive_number, whole_number
from ..errors import InvalidInputError
from ..robots.collision import DEFAULT_TOLERANCE
from .approach import ApproachFrame, OpenHand, aligned_roll, approach_pose, surface_samples
from .records import GraspPlan, GraspPlans, PlanTiming, RankBy
from .screen import PRESSED, PreloadScreen
from .search import Candidate, Steps, distinct, local_search, neighbours, placed, ranked, score_batch
from .verify import verify_plan


def _object(obj: object) -> ObjectSpec:
    """The object in its own frame (a given pose is dropped: the plans place it)."""
    spec = obj if isinstance(obj, ObjectSpec) else ObjectSpec.from_object(obj)
    return spec.with_pose((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))


def _pair(name: str, value: object, lo_ok: bool = False) -> tuple[float, float]:
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence) or len(value) != 2:
        raise InvalidInputError(name, f"expected two numbers, got {value!r}")
    a, b = (finite_number(f"{name}[{i}]", v) for i, v in enumerate(value))
    if (a < 0 if lo_ok else a <= 0) or b < a:
        raise InvalidInputError(name, f"expected 0 {'<=' if lo_ok else '<'} first <= second, got {value!r}")
    return a, b


def _preload(preload: object, actuators: Sequence[str]) -> tuple[Any, float | None]:
    """The records' ``command`` and the budget (``None`` unless ``{"budget": B}``: B split
    equally over the driving actuators to start)."""
    if isinstance(preload, Mapping) and set(preload) == {"budget"}:
        budget = positive_number("preload.budget", preload["budget"])
        if not actuators:
            raise InvalidInputError("preload", "a budget needs driving actuators; the hand has none")
        return tuple((a, budget / len(actuators)) for a in actuators), budget
    if isinstance(preload, Mapping):
        return tuple((str(k), finite_number(f"preload.{k}", v)) for k, v in preload.items()), None
    if isinstance(preload, str):
        return choice("preload", preload, ("auto",)), None
    return finite_number("preload", preload), None


def sample_specs(
    base: GraspSpec, frame: ApproachFrame, n: int, seed: int, standoff: tuple[float, float], hand: Any
) -> list[GraspSpec]:
    """``n`` records of ``base`` at sampled approach poses (ids ``c0``, ``c1``, ...), each
    stopped at the open hand's first touch (:meth:`~.approach.OpenHand.first_touch`)."""
    rng = np.random.default_rng(seed)
    points, normals = surface_samples(base.object, n, rng)
    rolls = rng.uniform(0.0, 2 * math.pi, n)
    depths = (1.0 - rng.uniform(standoff[0], standoff[1], n)) * frame.reach
    pull = (rng.uniform(0.0, 1.0, n) < 0.5).astype(float)  # half through the middle
    aligned, pick = rng.uniform(0.0, 1.0, n) < 0.5, rng.integers(0, 12, n)  # 12: uniform over 4 or 6 options
    touch = rng.uniform(0.0, 1.0, n) < 0.5
    tolerance = DEFAULT_TOLERANCE if base.tolerance is None else float(base.tolerance)
    open_hand = OpenHand(hand, base.q_open, base.object, frame, tolerance)
    out = []
    for i in range(n):
        p, nrm = open_hand.centred(points[i], normals[i], float(pull[i])), normals[i]
        roll = aligned_roll(nrm, int(pick[i])) if aligned[i] else float(rolls[i])
        depth = open_hand.first_touch(p, nrm, roll, float(depths[i]), bool(touch[i]))
        out.append(placed(base, approach_pose(frame, p, nrm, roll, depth), id=f"c{i}"))
    return out


def _spearman(cands: Sequence[Candidate]) -> float:
    ok = [c for c in cands if c.ok]
    if len(ok) < 3:
        return math.nan
    from scipy.stats import spearmanr

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a constant input: NaN, said so in the record
        return float(spearmanr([c.score for c in ok], [c.epsilon for c in ok]).statistic)


def _finish(
    picks: Sequence[Candidate], score: DisturbanceScore, verify: int
) -> tuple[list[GraspPlan], float]:
    """The plans of the picks: configuration, contacts, epsilon rank; the first ``verify``
    simulated. Returns the plans and the simulations' wall time [s]."""
    eps = [c.epsilon for c in picks]
    eps_rank = [1 + sum(e > x for e in eps) + sum(e == x for e in eps[:i]) for i, x in enumerate(eps)]
    plans, t_verify = [], 0.0
    for i, c in enumerate(picks):
        hand, _, q = grasp_configuration(c.spec)
        spec = replace(
            c.spec, q=tuple(zip(hand.joint_names, (float(v) for v in q))), command=tuple(c.command.items())
        )
        model, command, _ = build_grasp(spec)
        T = spec.object.pose
        values = dict(c.values)
        plan = GraspPlan(
            rank=i + 1, id=str(spec.id), origin=c.origin, spec=spec, object_pose=T,
            hand_pose=np.linalg.inv(T), q=dict(cast(Any, spec.q)), command=command,
            contact_names=model.contact_names, points=np.array(model.points),
            normals=np.array(model.frames[:, :, 0]), score=c.score, values=values,
            worst=min(values, key=lambda k: values[k]), epsilon=c.epsilon, epsilon_rank=eps_rank[i],
            sampled_score=c.sampled_score, snaps=dict(c.snaps),
        )  # fmt: skip
        if i < verify:
            t0 = time.perf_counter()
            plan = replace(plan, checks=verify_plan(plan, model, score))
            t_verify += time.perf_counter() - t0
        plans.append(plan)
    return plans, t_verify


def _progress(progress: Callable[[int, int], None] | None, total: int) -> Callable[[int], Any]:
    """A factory of per-batch progress callbacks reporting over the whole plan."""
    done = [0]

    def batch(size: int) -> Callable[[int, int], None] | None:
        if progress is None:
            return None
        start = done[0]
        done[0] += size

        def report(d: int, _t: int) -> None:
            progress(min(start + d, total), total)

        return report

    return batch


def _score_sampled(
    specs: list[GraspSpec], score: DisturbanceScore, run: dict[str, Any], progress: Any
) -> list[Candidate]:
    """The sampled candidates scored; with an ``"auto"`` preload, those whose closed contacts
    cannot even balance each other with every contact pressing (:mod:`.screen`, a linear
    program) are ``no_grasp (no_preload)`` without the preload design."""
    if not specs or specs[0].command != "auto":
        return score_batch(specs, score, "sampled", None, run, progress)
    from ..batch.evaluate import evaluate_grasps

    probe = [replace(s, command=1.0) for s in specs]  # a command only to build the contacts
    rows = evaluate_grasps(probe, score=PreloadScreen(), **run).to_dict("records")
    keep = [i for i, r in enumerate(rows) if r["status"] == "ok" and r["pressed"] > PRESSED]
    scored = dict(zip(keep, score_batch([specs[i] for i in keep], score, "sampled", None, run, progress)))
    out = []
    for i, (spec, row) in enumerate(zip(specs, rows)):
        if i in scored:
            out.append(scored[i])
            continue
        status, reason = (
            (row["status"], row["reason"]) if row["status"] != "ok" else ("no_grasp", "no_preload")
        )
        out.append(Candidate(spec, status, reason, {}, 0.0, 0.0, {}, "sampled", 0.0))
    return out


def _warm() -> None:
    """Import the scoring's modules here, so that forked local workers inherit them instead of
    importing them again for every batch."""
    import importlib

    for name in ("preload", "max_wrench", "metrics", "response"):
        importlib.import_module(f"pinograsp.analysis.{name}")


def _pruning(score: DisturbanceScore, incumbent: Candidate, rank_by: RankBy) -> DisturbanceScore:
    """The score of an incumbent's moves: ranked by the passive score, a move stops at its first
    value below the incumbent's worst case (it cannot rank higher), its directions taken from the
    incumbent's worst up."""
    if rank_by != "passive" or not incumbent.ok:
        return score
    first = tuple(sorted(incumbent.values, key=lambda k: incumbent.values[k]))
    return replace(score, floor=incumbent.score, first=first)


def _whole(*values: object) -> list[int]:
    """The counts of ``plan_grasps`` checked: ``n, top, seed, verify, refine, rounds`` (``n``,
    ``top`` >= 1; ``verify`` in ``[0, top]``; the others >= 0)."""
    n = count("n", values[0], MAX_SAMPLES, what="approaches, checked before sampling")
    top = count("top", values[1], MAX_SAMPLES)
    verify = count("verify", values[3], top, minimum=0, what="at most top")
    seed, refine, rounds = (
        whole_number(k, values[i], 0) for k, i in (("seed", 2), ("refine", 4), ("rounds", 5))
    )
    return [n, top, seed, verify, refine, rounds]


#: Friction pyramid edges of every candidate's model (``GraspSpec.edges``; a model's default is
#: 8). A value past a snap can hang on the pyramid's facets: issue 34's Ability × box plan 5
#: along −fz gives way at 61.1 N with 8 edges, 42.8 N with 16, 41.0 N with 32, and 43.0 N in the
#: simulation with the circular cone (docs/planning.md, "Friction pyramid").
PLAN_EDGES = 16


def _setup(
    hand: str, obj: object, preload: object, method: str, fields: dict[str, Any]
) -> tuple[GraspSpec, ApproachFrame, list[str], float | None, Any]:
    """The base record (object in its own frame, preload), the hand's approach frame, its
    driving actuators, the preload budget (``None`` without one) and the hand."""
    if {"object", "command", "id", "q"} & set(fields):
        raise InvalidInputError("fields", "'object', 'command', 'id' and 'q' are set by plan_grasps")
    # flat and line contacts as patches (a flat pad on a face is one arbitrary point otherwise),
    # friction pyramids of PLAN_EDGES edges (docs/planning.md, "Friction pyramid")
    defaults = {"patches": True, "edges": PLAN_EDGES}
    probe = GraspSpec(hand, _object(obj), preload_method=method, **{**defaults, **fields})
    hand_model = load_hand(probe)
    drivers = [a.name for a in hand_model.actuators if a.kind != "locked"]
    command, budget = _preload(preload, drivers)
    base = replace(probe, command=command)
    return base, ApproachFrame.of_hand(hand_model, base.q_open), drivers, budget, hand_model


def plan_grasps(
    hand: str,
    obj: object,
    *,
    disturbances: object = "cube26",
    n: int = 200,
    top: int = 5,
    preload: object = "auto",
    seed: int = 0,
    workers: int | None = 1,
    rank_by: RankBy = "passive",
    verify: int = 0,
    method: str = DEFAULT_METHOD,
    upper: float = 50.0,
    steps: int = 6,
    refine: int = 4,
    rounds: int = 3,
    step: Sequence[float] = (0.004, math.radians(8.0)),
    standoff: Sequence[float] = (0.0, 1.0),
    duplicate: Sequence[float] = (0.005, math.radians(15.0)),
    executor: object = "local",
    progress: Callable[[int, int], None] | None = None,
    **fields: Any,
) -> GraspPlans:
    """Plan grasps of ``obj`` with ``hand`` that resist the disturbances passively (docs/planning.md).

    Args:
        hand: Built-in hand name or URDF path (as ``pg.GraspSpec.hand``).
        obj: The object (``pg.ObjectSpec`` or a primitive ``pg.RigidObject``); its pose is ignored.
        disturbances: ``"cube26"`` (26 unit forces of a cube's faces, edges, corners, hand base
            frame), ``pg.Gravity(mass, margin=...)`` (the weight x ``1 + margin`` in every
            orientation: values in weights) or wrenches (k, 6) [N, N·m].
        n: Approaches sampled (each closed, preloaded and scored).
        top: Plans returned (fewer when fewer distinct grasps exist).
        preload: ``"auto"`` (``pg.equilibrium_preload``), a command for every actuator,
            ``{actuator: value}`` [N·m or N], or ``{"budget": B}`` (split, refined with the pose).
        seed: Seed of the sampling: the same seed gives the same plans, bit for bit.
        workers, executor, progress: Where the batches run and ``progress(done, total)`` over
            all of them (as ``pg.evaluate_grasps``).
        rank_by: ``"passive"`` (worst-case value, then leximin) or ``"epsilon"`` (Ferrari–Canny).
        verify: Simulate the first ``verify`` plans along every disturbance.
        method, upper, steps: Of each disturbance's ``pg.max_resistible_wrench``.
        refine, rounds: Distinct best candidates refined by the local search (0: none), its rounds.
        step: First translation [m] and rotation [rad] steps of the local search (halved when
            a round does not improve); the preload transfer starts at a quarter of the budget.
        standoff: Range of the sampled distance of the palm from the surface, in units of the
            hand's reach (palm to grasp centre): 0 the palm on the surface, 1 the grasp centre.
        duplicate: Two grasps closer than ``(translation [m], rotation [rad])`` are one.
        **fields: Other ``pg.GraspSpec`` fields of every candidate (``patches`` True here;
            ``edges`` :data:`PLAN_EDGES` here; ``mu``, ``q_open``, ``max_command``, ...).

    Raises:
        InvalidInputError, UnknownNameError, MissingDependencyError (pandas; MuJoCo with ``verify``).
    """
    t0 = time.perf_counter()
    _warm()
    n, top, seed, verify, refine, rounds = _whole(n, top, seed, verify, refine, rounds)
    rank_by = cast(RankBy, choice("rank_by", rank_by, ("passive", "epsilon")))
    step_t, step_r = _pair("step", step)
    standoff_range, dup = _pair("standoff", standoff, lo_ok=True), _pair("duplicate", duplicate, lo_ok=True)
    score = DisturbanceScore(cast(Any, disturbances), method, upper, steps)
    base, frame, drivers, budget, hand_model = _setup(hand, obj, preload, method, fields)
    run = {"executor": executor, "workers": workers}
    batch = _progress(progress, n + rounds * refine * (12 + len(drivers) * (len(drivers) - 1) * bool(budget)))
    specs = sample_specs(base, frame, n, seed, standoff_range, hand_model)
    t1 = time.perf_counter()
    cands = _score_sampled(specs, score, run, batch(n))
    t2 = time.perf_counter()
    seeds = distinct(ranked(cands, rank_by), refine, frame.centre, *dup)
    rescore = lambda s, parents, inc: score_batch(  # noqa: E731
        s, _pruning(score, inc, rank_by), "refined", parents, run, batch(len(s))
    )
    moves_of = lambda c, s: neighbours(c, s, frame.centre, budget, drivers)  # noqa: E731
    refined = local_search(seeds, rescore, Steps(step_t, step_r, 0.25), rounds, rank_by, moves_of)
    t3 = time.perf_counter()
    order = ranked([*cands, *refined], rank_by)
    plans, t_verify = _finish(distinct(order, top, frame.centre, *dup), score, verify)
    t4 = time.perf_counter()
    timing = PlanTiming(t1 - t0, t2 - t1, t3 - t2, t4 - t3 - t_verify, t_verify, t4 - t0)
    return _answer(base, score, rank_by, seed, plans, cands, order, len(refined), timing)


def _answer(
    base: GraspSpec, score: DisturbanceScore, rank_by: RankBy, seed: int, plans: list[GraspPlan],
    cands: list[Candidate], order: list[Candidate], refined: int, timing: PlanTiming,
) -> GraspPlans:  # fmt: skip
    """The record of a plan: its plans, counts, best values before and after the refinement."""
    first = ranked(cands, rank_by)[0]
    primary = (lambda c: c.score) if rank_by == "passive" else (lambda c: c.epsilon)
    return GraspPlans(
        hand=base.hand, object=base.object, labels=score.labels, wrenches=score.wrenches, rank_by=rank_by,
        seed=seed, plans=tuple(plans), sampled=len(cands), counts=_counts(cands), refined=refined,
        best_sampled=primary(first) if first.ok else 0.0, best=primary(order[0]) if order[0].ok else 0.0,
        spearman=_spearman(cands), score_options=_options(score), timing=timing,
    )  # fmt: skip


def _counts(cands: Sequence[Candidate]) -> dict[str, int]:
    out: dict[str, int] = {}
    for c in cands:
        key = c.status if c.ok else f"{c.status} ({c.reason})"
        out[key] = out.get(key, 0) + 1
    return out


def _options(score: DisturbanceScore) -> dict[str, Any]:
    """The score's options as plain data (a GRASPS.yaml ``score`` block)."""
    d = score.disturbances
    if isinstance(d, Gravity):
        kept: object = {"gravity": d.to_dict()}
    else:
        kept = d if isinstance(d, str) else [list(row) for row in d]
    return {
        "disturbances": kept,
        "method": str(score.method.value if hasattr(score.method, "value") else score.method),
        "upper": score.upper,
        "steps": score.steps,
    }
