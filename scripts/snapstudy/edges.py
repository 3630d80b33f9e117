"""Pyramid edges against the circular cone: the default answer with 8 and 16 friction-pyramid
edges per contact, compared with the cone simulations (cached; ``--extra N`` runs at most N new
cone simulations past the snaps, below).

For every direction with a **cone** simulation reference: the 352 directions of
``validate_quasistatic`` (``scripts/reproduce/data/qs_sim.jsonl``, the refined record where there
is one, as ``validate_quasistatic.load_refs``) and the top-5 plans of ``planning_acceptance``
(``scripts/reproduce/data/planning_acceptance.json``, cone, 0.02 s ramp). The hands of
``hands_converged`` have pyramid references only: skipped. Each grasp is rebuilt with 16 edges
and nothing else changed:

- scenes: ``pg.load_scene(name, edges=16)`` (planar scenes always use 2 edges: their answers at
  8 and 16 edges are the same model, computed once);
- random grasps: ``pg.examples.random_grasp(..., edges=16)`` (the same draws: edges take no
  randomness);
- plans: ``grasp_configuration(spec)`` then ``grasp_model_from_scene(..., edges=16)`` with the
  options of ``build_grasp`` and the cached plan's command (fixed, not re-designed).

The answer is the default ``pg.max_resistible_wrench(model, command, d, upper=U)`` at the cone
record's ``upper`` U, classified against the cone record by ``validate_quasistatic.classify``
(same class; ``simulated / predicted - 1`` where both give way). The snap subset is
``snaps.jsonl`` (directions whose 8-edge answer followed a landed snap), split by whether the
cone simulation survived the snap (``table.MARGIN``: gave way above ``first_limit * 1.03`` or held).

Timing: median CPU time per direction of the default answer in a ``pg.Session`` (after one
warm-up call), inside ``single_threaded_blas()``, at 8 and 16 edges, on case 1 and case 2 (24
plane directions, upper 1e3, as ``benchmarks/quasistatic_speed.py``) and its 16-contact random
grasps (``random_grasp(seed, 4, contacts_per_finger=2)``, seeds 0-2, 6 directions each); each
direction timed ``--repeat`` times, the fastest kept.

``--extra``: the snap-landed directions (``snaps.jsonl``) whose cone record does not test the snap
(the hands: no cone record; the record's upper below the snap; or held to its upper past the snap),
λ* ≤ 100 N, simulated with the cone at ``max(2 λ*, upper)`` (``2 upper`` when held), default
ramp (the hands and two Ability plan-5 directions also at 0.1 s), answers recomputed at that upper.

Results are cached in ``edges.json`` next to this file; the tables regenerate from it.

    nice -n 10 python -m scripts.snapstudy.edges [--sets qs,plans] [--extra 40] [--timing] [--fresh]
"""

from __future__ import annotations

import argparse
import json
import math
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import pinograsp as pg

CACHE = Path(__file__).parent / "edges.json"
EDGES = (8, 16)


# ----------------------------------------------------------------------------- the directions
def _sim(s: dict[str, Any]) -> dict[str, Any]:
    load = s.get("load")
    return {"status": str(s["status"]), "upper": float(s["upper"]),
            "load": None if load in (None, "inf") else float(load)}  # fmt: skip


def _same_contacts(a: Any, b: Any) -> None:
    """The two models differ by their pyramids only."""
    assert a.nc == b.nc and np.allclose(a.points, b.points) and np.allclose(a.frames, b.frames)
    assert np.allclose(a.mu, b.mu) and np.allclose(a.k, b.k) and np.allclose(a.J, b.J)


def qs_items():
    """(key, set, group, {edges: model}, command, d, cone record) of the validated directions."""
    from scripts.reproduce.qs_cases import SETS, cases
    from scripts.reproduce.validate_quasistatic import load_refs

    refs = load_refs(["cone"])
    built: dict[str, dict[int, Any]] = {}
    for c in cases(SETS):
        sim = refs.get(c.key, {}).get("cone")
        if sim is None:
            continue
        gkey = json.dumps(c.spec, sort_keys=True)
        if gkey not in built:
            _, m8, command = c.build()
            if "scene" in c.spec:
                m16 = m8 if m8.planar else pg.load_scene(c.spec["scene"], edges=16).model
            else:
                kw = dict(c.spec)
                m16 = pg.examples.random_grasp(kw.pop("seed"), kw.pop("n_pairs"), edges=16, **kw)
            _same_contacts(m8, m16)
            built[gkey] = {8: m8, 16: m16, "command": command}
        b = built[gkey]
        yield f"qs/{c.key}", c.set, c.group, b, b["command"], np.asarray(c.direction), _sim(sim)


def plan_items():
    """The same for the top-5 plans' cube directions (force part only)."""
    from pinograsp.batch.disturbances import cube_directions
    from pinograsp.batch.grasps import _contact_options, build_grasp, grasp_configuration
    from pinograsp.robots.grasp import grasp_model_from_scene
    from scripts.reproduce.planning_acceptance import CACHE as PLANS
    from scripts.reproduce.planning_acceptance import spec_of

    labels, dirs = cube_directions()
    data = json.loads(PLANS.read_text())
    for pair, entry in data["pairs"].items():
        for i, p in enumerate(entry["plans"]):
            sims = {k: s for k, s in (p["sims"] or {}).items() if not str(s["status"]).startswith("error")}
            if not sims:
                continue
            spec = spec_of(p["spec"])
            m8, command, _ = build_grasp(spec)
            hand, obj, q = grasp_configuration(spec)
            m16 = grasp_model_from_scene(
                hand, q, obj, mu=spec.mu, stiffness=spec.stiffness, patches=spec.patches, edges=16,
                **_contact_options(spec),
            )  # fmt: skip
            _same_contacts(m8, m16)
            b = {8: m8, 16: m16}
            for label, sim in sims.items():
                d = np.zeros(6)
                d[:3] = dirs[labels.index(label)][:3]
                yield (
                    f"plans/{pair}/plan{i + 1}/{label}",
                    "plans",
                    pair.split(" × ")[0],
                    b,
                    command,
                    d,
                    _sim(sim),
                )


# ---------------------------------------------------------------------------------- answers
def answer(model: Any, command: Any, d: np.ndarray, upper: float) -> dict[str, Any]:
    """The default answer and the facts compared (status, load, first limit, snaps, CPU time)."""
    t0 = time.process_time()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mw = pg.max_resistible_wrench(model, command, d, upper=upper)
    except pg.PinograspError as exc:
        return {"status": "error", "magnitude": None, "time": time.process_time() - t0,
                "error": f"{type(exc).__name__}: {str(exc)[:200]}"}  # fmt: skip
    out: dict[str, Any] = {"status": str(mw.status), "magnitude": float(mw.magnitude),
                           "time": time.process_time() - t0}  # fmt: skip
    g = mw.giveway
    if g is not None:
        out.update(
            first_limit=float(g.first_limit), reason=g.reason, snaps=[list(map(float, s)) for s in g.snaps]
        )
    return out


def load_cache() -> dict[str, Any]:
    return json.loads(CACHE.read_text()) if CACHE.exists() else {"answers": {}, "timing": {}}


def save_cache(cache: dict[str, Any]) -> None:
    CACHE.write_text(json.dumps(cache, indent=0, default=float, allow_nan=True) + "\n")


def run_answers(cache: dict[str, Any], sets: list[str], fresh: bool) -> None:
    gens = {"qs": qs_items, "plans": plan_items}
    ans = cache["answers"]
    n = 0
    t0 = time.perf_counter()
    for name in sets:
        for key, set_, group, models, command, d, sim in gens[name]():
            if key in ans and not fresh:
                continue
            rec: dict[str, Any] = {"set": set_, "group": group, "sim": sim, "planar": bool(models[8].planar),
                                   "direction": [float(x) for x in d]}  # fmt: skip
            rec["8"] = answer(models[8], command, d, sim["upper"])
            rec["16"] = rec["8"] if models[16] is models[8] else answer(models[16], command, d, sim["upper"])
            ans[key] = rec
            n += 1
            if n % 50 == 0:
                save_cache(cache)
                print(f"  {n} directions ({time.perf_counter() - t0:.0f} s)", flush=True)
        save_cache(cache)


# ------------------------------------------------------------------------ extra cone sims
#: Snap-landed directions whose cone record stops short of the snap are re-simulated past it
#: when the snap's load is at most this [N] (at ``upper = max(2 λ*, the record's upper)``).
LAM_MAX = 100.0


def extra_targets(ans: dict[str, Any]) -> dict[str, tuple[float, str]]:
    """key -> (new upper, why) of the snap-landed directions without a cone simulation past the
    snap: the hands (pyramid references only; the scene's upper), those whose cone record's
    upper is below the snap (``table.MARGIN``; new upper ``max(2 λ*, upper)``) and those whose
    cone record held past the snap to its upper (new upper ``2 upper``): λ* ≤ :data:`LAM_MAX`."""
    from scripts.snapstudy.table import MARGIN

    out = {}
    for r in (json.loads(x) for x in (Path(__file__).parent / "snaps.jsonl").read_text().splitlines() if x):
        lam, rec = r["first_limit"], ans.get(r["key"])
        if rec is None:
            out[r["key"]] = (float(r["upper"]), "no cone reference")
        elif lam > LAM_MAX:
            continue
        elif lam >= rec["sim"]["upper"] * (1 - MARGIN):
            out[r["key"]] = (
                float(f"{max(2 * lam, rec['sim']['upper']):.3g}"),
                "snap beyond the record's upper",
            )
        elif rec["sim"]["status"] == "held":
            out[r["key"]] = (
                float(f"{2 * rec['sim']['upper']:.3g}"),
                "held past the snap to the record's upper",
            )
    return out


def hand_items(keys: set[str]):
    """(key, {edges: model}, command, d) of the ``hands_converged`` directions among ``keys``."""
    from scripts.reproduce.hands_converged import CACHE as HANDS

    for r in (json.loads(x) for x in HANDS.read_text().splitlines() if x.strip()):
        key = f"hands/{r['hand']}/{r['direction']}"
        if key in keys:
            sc = pg.load_scene(r["hand"])
            models = {8: sc.model, 16: pg.load_scene(r["hand"], edges=16).model}
            _same_contacts(models[8], models[16])
            yield key, models, sc.model.command_vector(sc.preload(None)), np.asarray(r["d"], float)


#: Directions also simulated with a 0.1 s ramp (besides the hands): the 8- and 16-edge answers
#: straddle the 0.02 s cone simulation.
SLOW_CHECK = ("plans/ability × box/plan5/-fx-fz", "plans/ability × box/plan5/-fx-fy-fz")


def _sims_wanted(key: str) -> dict[str, dict[str, float]]:
    slow = key.startswith("hands/") or key in SLOW_CHECK
    return {"cone": {}, **({"cone_0.1": {"ramp_time": 0.1}} if slow else {})}


def run_extra(cache: dict[str, Any], limit: int) -> None:
    """Cone simulations (default ramp; the hands and :data:`SLOW_CHECK` also at 0.1 s) past the
    snap of the snap-landed directions lacking one, with the answers at their upper."""
    targets = extra_targets(cache["answers"])
    extra = cache.setdefault("extra", {})
    todo = {k: v for k, v in targets.items() if set(_sims_wanted(k)) - set(extra.get(k, {}).get("sims", {}))}
    items = [(k, m, c, d) for k, _, _, m, c, d, _ in [*qs_items(), *plan_items()] if k in todo]
    items += list(hand_items(set(todo)))
    runs = 0
    for key, models, command, d in items:
        upper, why = todo[key]
        rec = extra.get(key) or {"upper": upper, "why": why, "sims": {}}
        for name, kw in _sims_wanted(key).items():
            if name in rec["sims"] or runs >= limit:
                continue
            t0 = time.process_time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = pg.simulate_max_wrench(models[8], d, command, upper=upper, **kw)
            runs += 1
            rec["sims"][name] = {"status": str(r.status), "upper": upper, "cpu": time.process_time() - t0,
                                 "load": None if r.load is None else float(r.load)}  # fmt: skip
        if "cone" not in rec["sims"]:
            continue
        for e in EDGES:
            rec.setdefault(str(e), answer(models[e], command, d, upper))
        extra[key] = rec
        save_cache(cache)
        print(
            f"  {key} at {upper:g}: {rec['sims']} 8: {rec['8']['magnitude']} 16: {rec['16']['magnitude']}",
            flush=True,
        )


# ----------------------------------------------------------------------------------- timing
def timing_grasps() -> list[tuple[str, Any, Any, Any, list[np.ndarray]]]:
    """(label, model 8, model 16, command, directions) as in benchmarks/quasistatic_speed.py."""
    plane = [
        np.array([np.cos(a), np.sin(a), 0, 0, 0, 0]) for a in np.linspace(0, 2 * np.pi, 24, endpoint=False)
    ]
    out = []
    for name in ("case1", "case2"):
        s = pg.load_scene(name)
        out.append((name, s.model, pg.load_scene(name, edges=16).model, s.preload(None), plane))
    for seed in range(3):
        rng = np.random.default_rng(1000 + seed)
        dirs = [rng.normal(size=6) for _ in range(6)]
        m8 = pg.examples.random_grasp(seed, 4, contacts_per_finger=2)
        m16 = pg.examples.random_grasp(seed, 4, contacts_per_finger=2, edges=16)
        out.append((f"random 16 (seed {seed})", m8, m16, 1.0, dirs))
    return out


def run_timing(cache: dict[str, Any], repeat: int) -> None:
    """Both edge counts interleaved direction by direction (the same machine load for both),
    each call repeated ``repeat`` times, the fastest kept."""
    from pinograsp.solvers.threads import single_threaded_blas

    res = {}
    for label, m8, m16, command, dirs in timing_grasps():
        row: dict[str, Any] = {"contacts": m8.nc, "directions": len(dirs)}
        models = {"8": m8, "16": m16}
        times: dict[str, list[float]] = {"8": [], "16": []}
        with single_threaded_blas(), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sessions = {e: pg.Session(m) for e, m in models.items()}
            for e, m in models.items():  # warm-up: the preload path, once per session
                pg.max_resistible_wrench(m, command, dirs[0], upper=1e3, session=sessions[e])
            for d in dirs:
                best = {"8": math.inf, "16": math.inf}
                for _ in range(repeat):
                    for e, m in models.items():
                        t0 = time.process_time()
                        pg.max_resistible_wrench(m, command, d, upper=1e3, session=sessions[e])
                        best[e] = min(best[e], time.process_time() - t0)
                for e in times:
                    times[e].append(best[e])
        for e in times:
            row[e] = {"median": float(np.median(times[e])), "times": times[e]}
        row["ratio"] = row["16"]["median"] / row["8"]["median"]
        row["ratio_per_direction"] = float(np.median(np.divide(times["16"], times["8"])))
        res[label] = row
        print(f"  {label}: 8 {1e3 * row['8']['median']:.2f} ms, 16 {1e3 * row['16']['median']:.2f} ms, "
              f"ratio {row['ratio']:.2f}", flush=True)  # fmt: skip
    cache["timing"] = {"repeat": repeat, "grasps": res}
    save_cache(cache)


# ----------------------------------------------------------------------------------- tables
def _cmp(rec: dict[str, Any], e: str) -> dict[str, Any]:
    from scripts.reproduce.validate_quasistatic import classify

    return classify(rec[e], rec["sim"])


def summary(recs: list[dict[str, Any]], e: str) -> dict[str, Any]:
    cs = [_cmp(r, e) for r in recs]
    rel = np.abs([c["rel"] for c in cs if c["rel"] is not None])
    return {
        "n": len(cs),
        "same": sum(c["verdict"] == "same class" for c in cs),
        "wrong": sum(c["verdict"] == "wrong class" for c in cs),
        "nov": sum(c["verdict"] == "no verdict" for c in cs),
        "finite": int(rel.size),
        "within": int(np.sum(rel <= 0.10)),
        "median": float(np.median(rel)) if rel.size else math.nan,
        "signed": float(np.median([c["rel"] for c in cs if c["rel"] is not None])) if rel.size else math.nan,
        "max": float(np.max(rel)) if rel.size else math.nan,
        "errors": sum(r[e]["status"] == "error" for r in recs),
    }


def _pct(x: float) -> str:
    return "—" if x != x else f"{100 * x:.1f} %"


def table(groups: dict[str, list[dict[str, Any]]]) -> str:
    lines = [
        "| set | dirs | edges | same class | wrong | no verdict | both give way | within 10 % "
        "| median \\|err\\| "
        "| median err | max \\|err\\| | errors |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, recs in groups.items():
        for e in ("8", "16"):
            s = summary(recs, e)
            lines.append(
                f"| {name} | {s['n']} | {e} | {s['same']} | {s['wrong']} | {s['nov']} | {s['finite']} "
                f"| {s['within']} ({_pct(s['within'] / s['finite'] if s['finite'] else math.nan)}) "
                f"| {_pct(s['median'])} | {_pct(s['signed'])} | {_pct(s['max'])} | {s['errors']} |"
            )
    return "\n".join(lines)


def _paired(recs: list[dict[str, Any]]) -> str:
    """Directions where both edge counts give way with the simulation: which is closer."""
    better = worse = tie = 0
    for r in recs:
        a, b = _cmp(r, "8"), _cmp(r, "16")
        if a["rel"] is None or b["rel"] is None:
            continue
        da, db = abs(a["rel"]), abs(b["rel"])
        if db < da - 1e-3:
            better += 1
        elif db > da + 1e-3:
            worse += 1
        else:
            tie += 1
    cls = sum(
        (_cmp(r, "16")["verdict"] == "same class") - (_cmp(r, "8")["verdict"] == "same class") for r in recs
    )
    return f"16 closer {better}, 8 closer {worse}, within 0.1 pt {tie}; same-class change {cls:+d}"


def snap_groups(ans: dict[str, Any]) -> dict[str, list[dict[str, Any]]]:
    from scripts.snapstudy.table import MARGIN

    rows = [
        json.loads(x) for x in (Path(__file__).parent / "snaps.jsonl").read_text().splitlines() if x.strip()
    ]
    out: dict[str, list[dict[str, Any]]] = {"snap: cone survived": [], "snap: cone gave way at it": [],
                                            "snap: beyond the cone's upper": []}  # fmt: skip
    missing = []
    for r in rows:
        rec = ans.get(r["key"])
        if rec is None:
            missing.append(r["key"])
            continue
        s, lam = rec["sim"], r["first_limit"]
        load = math.inf if s["status"] == "held" or s["load"] is None else s["load"]
        if lam >= s["upper"] * (1 - MARGIN):
            out["snap: beyond the cone's upper"].append(rec)
        elif load > lam * (1 + MARGIN):
            out["snap: cone survived"].append(rec)
        else:
            out["snap: cone gave way at it"].append(rec)
    out["snap: all with a cone reference"] = [rec for g in list(out.values()) for rec in g]
    if missing:
        print(f"snap directions without a cone reference (skipped): {missing}")
    return out


def _as_rec(x: dict[str, Any]) -> dict[str, Any]:
    """An extra record as an answers record against its default-ramp cone simulation."""
    return {
        "sim": x["sims"]["cone"],
        "8": x["8"],
        "16": x["16"],
        "set": "extra",
        "group": "extra",
        "planar": False,
    }


def extra_table(ex: dict[str, Any]) -> str:
    """One row per re-simulated direction: the new upper, the simulations and both answers."""
    lines = ["| direction | why | upper | cone sim (0.02 s) | cone 0.1 s | 8 edges | err 8 | 16 edges "
             "| err 16 |",
             "|---|---|---:|---|---|---:|---:|---:|---:|"]  # fmt: skip

    def sim(s: dict[str, Any] | None) -> str:
        return "—" if s is None else "held" if s["load"] is None else f"{s['status']} {s['load']:.4g}"

    def err(c: dict[str, Any]) -> str:
        return f"{100 * c['rel']:+.1f} %" if c["rel"] is not None else c["verdict"]

    for k, x in ex.items():
        r = _as_rec(x)
        lines.append(
            f"| {k} | {x['why']} | {x['upper']:g} | {sim(x['sims']['cone'])} "
            f"| {sim(x['sims'].get('cone_0.1'))} | {x['8']['magnitude']:.4g} | {err(_cmp(r, '8'))} "
            f"| {x['16']['magnitude']:.4g} | {err(_cmp(r, '16'))} |"
        )
    return "\n".join(lines)


def report(cache: dict[str, Any]) -> str:
    ans = cache["answers"]
    recs = list(ans.values())
    groups: dict[str, list[dict[str, Any]]] = {"all": recs}
    for s in dict.fromkeys(r["set"] for r in recs):
        groups[s] = [r for r in recs if r["set"] == s]
    groups["qs 3D (not planar)"] = [r for r in recs if r["set"] != "plans" and not r["planar"]]
    for g in dict.fromkeys(r["group"] for r in recs if r["set"] == "plans"):
        groups[f"plans: {g}"] = [r for r in recs if r["set"] == "plans" and r["group"] == g]
    sg = snap_groups(ans)
    text = ["### Default answer vs cone simulation, 8 and 16 edges", "", table(groups), "",
            "### The snap-landed directions (snaps.jsonl)", "", table(sg), "", "### Paired", ""]  # fmt: skip
    for name, rs in {**groups, **sg}.items():
        text.append(f"- {name}: {_paired(rs)}")
    ex = {k: v for k, v in cache.get("extra", {}).items()}
    if ex:
        text += ["", "### The snap-landed directions re-simulated past the snap (cone)", "",
                 extra_table(ex), "",
                 "Snap subset with the new cone simulations where run (else the cone record):", "",
                 table(snap_groups({**ans, **{k: {**ans.get(k, {}), **_as_rec(v)} for k, v in ex.items()}})),
                 ""]  # fmt: skip
    text += ["", "### CPU time per direction of the answers above (no Session)", "",
             "| set | dirs | 8 edges median ms | 16 edges median ms | ratio of medians | sum 16 / sum 8 |",
             "|---|---:|---:|---:|---:|---:|"]  # fmt: skip
    for name, rs in groups.items():
        t8, t16 = (np.array([r[e]["time"] for r in rs]) for e in ("8", "16"))
        text.append(f"| {name} | {len(rs)} | {1e3 * np.median(t8):.2f} | {1e3 * np.median(t16):.2f} "
                    f"| {np.median(t16) / np.median(t8):.2f} | {t16.sum() / t8.sum():.2f} |")  # fmt: skip
    t = cache.get("timing", {}).get("grasps")
    if t:
        text += ["", "### Time per direction in a Session (CPU, single-threaded BLAS)", "",
                 "| grasp | contacts | dirs | 8 edges ms | 16 edges ms | 16 / 8 | median of 16 / 8 per dir |",
                 "|---|---:|---:|---:|---:|---:|---:|"]  # fmt: skip
        for label, r in t.items():
            text.append(f"| {label} | {r['contacts']} | {r['directions']} | {1e3 * r['8']['median']:.2f} "
                        f"| {1e3 * r['16']['median']:.2f} | {r['ratio']:.2f} "
                        f"| {r.get('ratio_per_direction', math.nan):.2f} |")  # fmt: skip
    return "\n".join(text)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", default="", help="compute the answers of these sets (qs, plans) not cached")
    ap.add_argument("--fresh", action="store_true", help="recompute cached answers too")
    ap.add_argument("--timing", action="store_true", help="run the timing comparison")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--extra", type=int, default=0, help="run at most N cone simulations past the snaps")
    a = ap.parse_args()
    cache = load_cache()
    if a.sets:
        run_answers(cache, [s.strip() for s in a.sets.split(",") if s.strip()], a.fresh)
    if a.extra:
        run_extra(cache, a.extra)
    if a.timing:
        run_timing(cache, a.repeat)
    print(report(cache))


if __name__ == "__main__":
    main()
