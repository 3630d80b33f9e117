"""Issue 34's acceptance for ``pg.plan_grasps`` (docs/planning.md, "Acceptance"), cached.

Three built-in hands (``parallel_jaw``, ``barrett_bh8_282``, ``ability``) × three objects (a box,
a cylinder, the shipped torus mesh). Per pair:

1. **plan**: ``pg.plan_grasps(hand, obj, n=N, top=5, workers=W, seed=0)`` — the counts, the
   refinement gain and the time split;
2. **(a) top-5 in simulation**: each plan's every disturbance (the 26 cube directions) simulated
   with ``pg.simulate_max_wrench`` ramped to 90 % of the plan's predicted worst case: a direction
   holds when the grasp is still in place at that load;
3. **(b) correlation**: the first ``--grasps`` (50) sampled approaches that are grasps (sample
   order, not ranked; the planner's 100 approaches of seed 0, then further chunks of 100 with
   seeds 1, 2, ... until 50 grasps or ``--cap`` (1000) approaches), each simulated along the
   **6 face directions** only (``±fx, ±fy, ±fz``, the load ramped to twice its prediction):
   Spearman of the passive score (worst of the 6 predicted) and of the Ferrari–Canny ε against
   the simulated worst case of the 6.

Every simulation is appended to the JSON cache as it finishes (``--cache``), so the run stops
and resumes anywhere, and the tables regenerate from the cache alone::

    nice python -m scripts.reproduce.planning_acceptance --run --cpu 2400   # ≤ 40 CPU-min of simulations
    python -m scripts.reproduce.planning_acceptance --write                # the tables, from the cache
    nice python -m scripts.reproduce.planning_acceptance --run --redo parallel_jaw   # re-plan pairs

The simulations run in a fixed priority order until the CPU budget is spent: the best plan of
every pair, then 10 sampled grasps of every pair, then plans 2-5, then the remaining grasps.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

import pinograsp as pg
from pinograsp.batch.disturbances import cube_directions

ROOT = Path(__file__).resolve().parents[2]
CACHE = ROOT / "scripts" / "reproduce" / "data" / "planning_acceptance.json"
HANDS = tuple(os.environ.get("PLAN_HANDS", "parallel_jaw,barrett_bh8_282,ability").split(","))
OBJECTS = {
    "box": pg.ObjectSpec("box", size=(0.04, 0.05, 0.07)),
    "cylinder": pg.ObjectSpec("cylinder", radius=0.02, length=0.08),
    "torus": pg.ObjectSpec("mesh", file=str(ROOT / "pinograsp" / "data" / "meshes" / "torus.stl")),
}
FACES = ("+fx", "-fx", "+fy", "-fy", "+fz", "-fz")
BEGIN, END = "<!-- planning-acceptance -->", "<!-- /planning-acceptance -->"
HOLD = 0.9  # fraction of the predicted worst case a plan must hold along every direction


def _load(path: Path) -> dict[str, Any]:
    return json.loads(path.read_text()) if path.is_file() else {"pairs": {}}


def _save(data: dict[str, Any], path: Path) -> None:
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=1, allow_nan=True) + "\n")
    tmp.replace(path)


def _num(v: float) -> float | str:
    return v if math.isfinite(v) else ("inf" if v > 0 else "-inf" if v < 0 else "nan")


def _val(v: Any) -> float:
    return float(v) if not isinstance(v, str) else float(v)


def _rel(spec: dict[str, Any]) -> dict[str, Any]:
    """A spec dict with a mesh file inside the repository stored relative to it (portable cache)."""
    obj = dict(spec["object"])
    if obj.get("file") and Path(obj["file"]).is_relative_to(ROOT):
        obj["file"] = str(Path(obj["file"]).relative_to(ROOT))
    return {**spec, "object": obj}


def spec_of(spec: dict[str, Any]) -> Any:
    """The ``GraspSpec`` of a cached spec dict (a relative mesh file resolved against the repository)."""
    from pinograsp.batch.grasps import GraspSpec, ObjectSpec

    obj = dict(spec["object"])
    if obj.get("file") and not Path(obj["file"]).is_absolute():
        obj["file"] = str(ROOT / obj["file"])
    return GraspSpec(**{**spec, "object": ObjectSpec(**obj)})


def sampled_grasps(
    hand: str, obj: str, n: int, workers: int, grasps: int, cap: int, seed0: int = 0
) -> tuple[list[Any], int]:
    """The first ``grasps`` sampled approaches that are grasps, sampled in chunks of ``n`` with
    the seeds ``seed0, seed0 + 1, ...`` (seed 0: the planner's own sample) until ``grasps`` are
    found or ``cap`` approaches are sampled: the candidates and the approaches sampled."""
    from pinograsp.planning.plan import _score_sampled, _setup, sample_specs

    score = pg.DisturbanceScore()
    base, frame, _, _, hand_model = _setup(hand, OBJECTS[obj], "auto", score.method, {})
    found: list[Any] = []
    seed = seed0
    while len(found) < grasps and (seed - seed0) * n < cap:
        specs = [
            replace(s, id=f"s{seed}-{s.id}")
            for s in sample_specs(base, frame, n, seed, (0.0, 1.0), hand_model)
        ]
        found += [
            c for c in _score_sampled(specs, score, {"executor": "local", "workers": workers}, None) if c.ok
        ]
        seed += 1
    return found[:grasps], (seed - seed0) * n


def _grasp_entry(c: Any) -> dict[str, Any]:
    spec = _rel(replace(c.spec, command=tuple(c.command.items())).to_dict())
    values = {k: _num(c.values[k]) for k in FACES}
    return {"id": str(c.spec.id), "score": _num(c.score), "epsilon": c.epsilon, "values": values,
            "spec": spec, "sims": {}}  # fmt: skip


def plan_pair(hand: str, obj: str, n: int, workers: int, grasps: int, cap: int) -> dict[str, Any]:
    """Plan one pair and collect its top-5 and its first ``grasps`` sampled grasps (as specs)."""
    plans = pg.plan_grasps(hand, OBJECTS[obj], n=n, top=5, workers=workers, seed=0)
    found, approaches = sampled_grasps(hand, obj, n, workers, grasps, cap)
    t = plans.timing
    return {
        "n": n, "workers": workers, "approaches": approaches,
        "counts": plans.counts, "sampled": plans.sampled, "refined": plans.refined,
        "best_sampled": _num(plans.best_sampled), "best": _num(plans.best),
        "timing": {k: getattr(t, k) for k in ("sample", "score", "refine", "finish", "total")},
        "plans": [
            {"id": p.id, "origin": p.origin, "score": _num(p.score), "epsilon": p.epsilon,
             "values": {k: _num(v) for k, v in p.values.items()}, "spec": _rel(p.spec.to_dict()), "sims": {}}
            for p in plans.plans
        ],
        "grasps": [_grasp_entry(c) for c in found],
    }  # fmt: skip


def _simulate(spec: dict[str, Any], label: str, upper: float) -> dict[str, Any]:
    from pinograsp.batch.grasps import build_grasp

    labels, dirs = cube_directions()
    w = np.zeros(6)
    w[:3] = dirs[labels.index(label)][:3]
    model, command, _ = build_grasp(spec_of(spec))
    t0 = time.process_time()
    r = pg.simulate_max_wrench(model, w, command, upper=upper)
    return {"upper": upper, "load": _num(math.inf if r.load is None else float(r.load)),
            "status": str(r.status), "cpu": time.process_time() - t0}  # fmt: skip


def _tasks(data: dict[str, Any], grasps: int) -> list[tuple[int, str, str, int, str]]:
    """(tier, pair, kind, index, label) in priority order."""
    out = []
    for key, pair in data["pairs"].items():
        labels = cube_directions()[0]
        for i, p in enumerate(pair["plans"]):
            if _val(p["score"]) == 0:  # predicted to give at once: nothing to verify
                continue
            out += [(0 if i == 0 else 2, key, "plans", i, a) for a in labels if a in p["values"]]
        for i, _ in enumerate(pair["grasps"][:grasps]):
            out += [(1 if i < 10 else 3, key, "grasps", i, a) for a in FACES]
    return sorted(out, key=lambda t: (t[0], t[3], t[1], t[4]))


def run(args: argparse.Namespace) -> None:
    data = _load(args.cache)
    for key in [k for k in data["pairs"] if any(r == "all" or r in k for r in args.redo)]:
        print("redo", key, flush=True)
        del data["pairs"][key]
    for key in [k for k in data["pairs"] if any(r == "all" or r in k for r in args.redo_plans)]:
        print("re-plan", key, flush=True)  # the sampled grasps and their simulations are kept
        hand, obj = key.split(" × ")
        old = data["pairs"][key]
        new = plan_pair(hand, obj, old["n"], args.workers, 0, args.cap)
        data["pairs"][key] = {**new, "approaches": old["approaches"], "grasps": old["grasps"]}
        _save(data, args.cache)
    for hand in HANDS:
        for obj in OBJECTS:
            key = f"{hand} × {obj}"
            if key not in data["pairs"]:
                print("plan", key, flush=True)
                data["pairs"][key] = plan_pair(hand, obj, args.n, args.workers, args.grasps, args.cap)
                _save(data, args.cache)
    spent = _sim_cpu(data)
    todo = []
    for _, key, kind, i, label in _tasks(data, args.grasps):
        item = data["pairs"][key][kind][i]
        if label in item["sims"]:
            continue
        predicted = _val(item["values"][label])
        if kind == "plans":
            worst = _val(item["score"])
            upper = HOLD * worst if 0 < worst < math.inf else 50.0
        else:
            upper = 2 * predicted if 0 < predicted < math.inf else 50.0
        todo.append((key, kind, i, label, item["spec"], upper))
    import multiprocessing as mp

    with mp.get_context("fork").Pool(args.jobs) as pool:  # results arrive in priority order
        for (key, kind, i, label, _, _), sim in zip(todo, pool.imap(_task, todo)):
            data["pairs"][key][kind][i]["sims"][label] = sim
            spent += sim["cpu"]
            _save(data, args.cache)
            print(
                f"{key} {kind}[{i}] {label}: {sim['status']} load {sim['load']} ({spent:.0f} s)", flush=True
            )
            if spent >= args.cpu:
                print(f"CPU budget spent ({spent:.0f} s)", flush=True)
                pool.terminate()
                break


def _task(task: tuple) -> dict[str, Any]:
    """One simulation of the queue (in a pool worker)."""
    _, _, _, label, spec, upper = task
    try:
        return _simulate(spec, label, upper)
    except Exception as exc:  # a model the simulation refuses: recorded, not lost
        return {"upper": upper, "load": "nan", "status": f"error: {type(exc).__name__}", "cpu": 0.0}


def _sim_cpu(data: dict[str, Any]) -> float:
    """CPU [s] of every simulation in the cache."""
    pairs = data["pairs"].values()
    return sum(s["cpu"] for p in pairs for k in ("plans", "grasps") for g in p[k] for s in g["sims"].values())


def _sig(values: list[float]) -> list[float]:
    """Values to 3 significant digits: values equal to that are ties in a ranking (0.49999 and
    0.5 N, both the friction limit, are one value, not two ranks)."""
    return [float(f"{v:.3g}") for v in values]


def _spearman(x: list[float], y: list[float]) -> float:
    from scipy.stats import spearmanr

    x, y = _sig(x), _sig(y)
    if len(x) < 3 or len(set(x)) < 2 or len(set(y)) < 2:
        return math.nan  # a constant ranking has no correlation
    return float(spearmanr(x, y).statistic)


def _studied(pair: dict[str, Any]) -> tuple[list[dict[str, Any]], int]:
    """The grasps of (b) simulated along all 6 faces, and how many more the simulation refused
    (an error along some face, e.g. a preload it finds out of equilibrium)."""
    full = [g for g in pair["grasps"] if len(g["sims"]) == len(FACES)]
    done = [g for g in full if not any(s["status"].startswith("error") for s in g["sims"].values())]
    return done, len(full) - len(done)


def disagreements(data: dict[str, Any]) -> list[dict[str, Any]]:
    """Per pair with both rankings: the simulated grasp whose passive rank and ε rank differ
    most (ranks 1 = best, ties averaged; ties in the difference: the first in sample order),
    with its simulated rank and the ranking closer to it."""
    from scipy.stats import rankdata

    out = []
    for key, pair in data["pairs"].items():
        done, _ = _studied(pair)
        passive = [min(_val(g["values"][k]) for k in FACES) for g in done]
        eps = [g["epsilon"] for g in done]
        sim = [min(_val(s["load"]) for s in g["sims"].values()) for g in done]
        if len(done) < 3 or len(set(passive)) < 2 or len(set(eps)) < 2:
            continue
        rp, re, rs = (rankdata([-x for x in _sig(v)]) for v in (passive, eps, sim))
        i = int(np.argmax(np.abs(rp - re)))
        dp, de = abs(rp[i] - rs[i]), abs(re[i] - rs[i])
        side = "passive" if dp < de else "ε" if de < dp else "neither"
        hand, obj = key.split(" × ")
        out.append({"pair": key, "index": pair["grasps"].index(done[i]), "id": done[i]["id"],
                    "n": len(done), "passive": passive[i], "epsilon": eps[i], "simulated": sim[i],
                    "ranks": (rp[i], re[i], rs[i]), "side": side,
                    "file": f"img/planning_disagree_{hand}_{obj}.png"})  # fmt: skip
    return out


def render(data: dict[str, Any]) -> None:
    """Draw each disagreement's grasp with ``pg.plot_plan`` (its 6 face values and their
    simulations) into docs/img/."""
    from pinograsp.planning.plan import _finish
    from pinograsp.planning.records import PlanCheck
    from pinograsp.planning.search import Candidate

    for d in disagreements(data):
        g = data["pairs"][d["pair"]]["grasps"][d["index"]]
        values = {k: _val(g["values"][k]) for k in FACES}
        spec = spec_of(g["spec"])
        cand = Candidate(spec, "ok", "", values, min(values.values()), g["epsilon"], dict(spec.command),
                         "sampled", min(values.values()))  # fmt: skip
        (plan,), _ = _finish([cand], pg.DisturbanceScore(), 0)
        plan = replace(plan, rank=round(d["ranks"][0]))  # the title's rank: by the passive score
        checks = []
        for k in FACES:
            sim = _val(g["sims"][k]["load"])
            ratio = sim / values[k] if 0 < values[k] < math.inf else math.nan
            checks.append(PlanCheck(k, values[k], sim, g["sims"][k]["status"], ratio))
        pg.plot_plan(replace(plan, checks=tuple(checks)), ROOT / "docs" / d["file"])
        print("wrote", d["file"], flush=True)


def _rank(r: float) -> str:
    return f"{r:.0f}" if r == int(r) else f"{r:.1f}"


def report(data: dict[str, Any]) -> str:
    """The markdown tables of docs/planning.md, "Acceptance"."""
    a = [
        "| pair | predicted worst case of plans 1-5 [N] | plans predicted 0 | plans simulated "
        "(all directions) | directions simulated | holding at ≥ 90 % of it along every direction |",
        "|---|---|---:|---:|---:|---|",
    ]
    b = [
        "| pair | approaches sampled | grasps found | grasps simulated (6 faces each) | refused by the "
        "simulation | Spearman(passive, simulated) | Spearman(ε, simulated) |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    c = [
        "| pair | sampled ok | best sampled | best after refinement | gain | refined | time split (s) |",
        "|---|---:|---:|---:|---:|---:|---|",
    ]
    for key, pair in data["pairs"].items():
        zero = sum(_val(p["score"]) == 0 for p in pair["plans"])
        full = [p for p in pair["plans"] if len(p["sims"]) == len(p["values"]) > 0]
        held = [p for p in full if all(s["load"] == "inf" for s in p["sims"].values())]
        dirs = sum(len(p["sims"]) for p in pair["plans"])
        worst = [f"{_val(p['score']):.3g}" for p in pair["plans"]]
        a.append(
            f"| {key} | {', '.join(worst)} | {zero} | {len(full)} | {dirs} | {len(held)} / {len(full)} |"
        )
        done, refused = _studied(pair)
        sim = [min(_val(s["load"]) for s in g["sims"].values()) for g in done]
        passive = [min(_val(g["values"][k]) for k in FACES) for g in done]
        eps = [g["epsilon"] for g in done]
        found = f"{pair.get('approaches', pair['sampled'])} | {len(pair['grasps'])}"
        b.append(
            f"| {key} | {found} | {len(done)} | {refused} | {_spearman(passive, sim):.2f} | "
            f"{_spearman(eps, sim):.2f} |"
        )
        t = pair["timing"]
        bs, bb = _val(pair["best_sampled"]), _val(pair["best"])
        if bb == bs:
            gain = "none"
        elif bb == math.inf:
            gain = "to unbounded"
        else:
            gain = f"{bb / bs:.2f}×" if bs > 0 else "from 0"
        ok = pair["counts"].get("ok", 0)
        split = ", ".join(f"{k} {t[k]:.1f}" for k in ("sample", "score", "refine", "total"))
        c.append(
            f"| {key} | {ok} / {pair['sampled']} | {bs:.4g} | {bb:.4g} | {gain} | "
            f"{pair['refined']} | {split} |"
        )
    gave = [
        f"- {key}, plan {i + 1} (predicted worst {_val(p['score']):.4g} N): {label} gave way at "
        f"{_val(sim['load']):.4g} N of {sim['upper']:.4g} N ({sim['status']})"
        for key, pair in data["pairs"].items()
        for i, p in enumerate(pair["plans"])
        for label, sim in p["sims"].items()
        if sim["load"] != "inf"
    ]
    worst = [
        f"- {d['pair']}, grasp {d['id']}: passive score {d['passive']:.3g} N (rank {_rank(d['ranks'][0])} "
        f"of {d['n']}), ε {d['epsilon']:.3g} (rank {_rank(d['ranks'][1])}), simulated worst "
        f"{d['simulated']:.3g} N (rank {_rank(d['ranks'][2])}): the simulation sides with the {d['side']} "
        "ranking. "
        f"![{d['pair']}, grasp {d['id']}]({d['file']})"
        for d in disagreements(data)
    ]
    parts = [
        "(a) Top-5 plans in simulation", "", *a, "", "Directions that gave way:", "", *gave, "",
        "(b) Rank correlation over sampled grasps (6 face directions)", "", *b, "",
        "Where the passive and the ε rankings disagree most (the grasp of each pair whose two ranks "
        "differ most; ranks among the simulated grasps, 1 = best; bars: the 6 predicted face values, "
        "dots: where the simulation gave way, triangles: held):", "", *worst, "",
        "(c) Refinement", "", *c, "",
        f"Simulation CPU in the cache: {_sim_cpu(data) / 60:.1f} min.",
    ]  # fmt: skip
    return "\n".join(parts)


#: Slower ramps tried on a plan direction that gave way below 90 % of its prediction (the ramp
#: study, docs/validation_ramp.md: the default 0.02 s answers gradual give-ways by its dynamics).
#: Release time [s] of the held object in the last slow re-check: gradual, as the model's
#: preload path releases it (docs/simulation.md, ``release_time``; the default 0 drops it).
RELEASE = 0.05
SLOW_RAMPS = (0.3, 1.0)


def slow_check(data: dict[str, Any]) -> list[str]:
    """Re-simulate, at :data:`SLOW_RAMPS` until it holds, every top-5 plan direction that gave
    way below its check load at the default ramp; lines of text (not cached: a few minutes)."""
    from pinograsp.batch.grasps import build_grasp

    labels, dirs = cube_directions()
    out = []
    for key, pair in data["pairs"].items():
        for i, p in enumerate(pair["plans"]):
            for label, sim in p["sims"].items():
                load = _val(sim["load"])
                if not (math.isfinite(load) and load < 0.9999 * sim["upper"]):
                    continue
                model, command, _ = build_grasp(spec_of(p["spec"]))
                w = np.zeros(6)
                w[:3] = dirs[labels.index(label)][:3]
                seen = []
                for rt in SLOW_RAMPS:
                    r = pg.simulate_max_wrench(model, w, command, upper=sim["upper"], ramp_time=rt)
                    seen.append(f"{rt:g} s: {'held' if r.load is None else f'{r.status} {r.load:.4g} N'}")
                    if r.load is None:
                        break
                if r.load is not None:  # the held object released as the model releases it
                    r = pg.simulate_max_wrench(
                        model, w, command, upper=sim["upper"], ramp_time=SLOW_RAMPS[0], release_time=RELEASE
                    )
                    what = "held" if r.load is None else f"{r.status} {r.load:.4g} N"
                    seen.append(f"{SLOW_RAMPS[0]:g} s, release over {RELEASE:g} s: {what}")
                out.append(f"- {key}, plan {i + 1}, {label} (check load {sim['upper']:.4g} N; 0.02 s: "
                           f"{sim['status']} {load:.4g} N): " + "; ".join(seen))  # fmt: skip
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--run", action="store_true", help="plan and simulate what the cache lacks")
    ap.add_argument("--n", type=int, default=100, help="approaches sampled per pair (default 100)")
    ap.add_argument("--grasps", type=int, default=50, help="sampled grasps of the correlation study")
    ap.add_argument(
        "--cap", type=int, default=1000, help="most approaches sampled to find them (default 1000)"
    )
    ap.add_argument(
        "--redo", nargs="*", default=[], help="re-plan the cached pairs naming any of these (all: every pair)"
    )
    ap.add_argument(
        "--redo-plans", nargs="*", default=[], help="re-plan these pairs' top 5, keeping their sampled grasps"
    )
    ap.add_argument("--workers", type=int, default=2, help="planning workers")
    ap.add_argument("--jobs", type=int, default=2, help="simulations run side by side")
    ap.add_argument("--cpu", type=float, default=2400.0, help="simulation CPU budget [s] of this run")
    ap.add_argument("--cache", type=Path, default=CACHE)
    ap.add_argument("--write", action="store_true", help="put the tables into docs/planning.md")
    ap.add_argument("--pictures", action="store_true", help="draw the disagreements into docs/img/")
    ap.add_argument("--slow", action="store_true", help="re-simulate the plans' give-ways at slower ramps")
    args = ap.parse_args()
    if args.slow:
        print("\n".join(slow_check(_load(args.cache))))
        return
    if args.run:
        run(args)
    if args.pictures:
        render(_load(args.cache))
    text = report(_load(args.cache))
    print(text)
    if args.write:
        doc = ROOT / "docs" / "planning.md"
        head, rest = doc.read_text().split(BEGIN, 1)
        doc.write_text(head + BEGIN + "\n" + text + "\n" + END + rest.split(END, 1)[1])


if __name__ == "__main__":
    main()
