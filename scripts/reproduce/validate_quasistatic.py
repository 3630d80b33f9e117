"""Validate any method against the cached simulation references (issue 25 acceptance).

Loads the simulation references (``data/qs_sim.jsonl``, written by ``qs_references.py sim``)
and the cached predictions of the paper's methods (``data/qs_methods.jsonl``), runs the
methods asked for that are not cached (``"quasistatic"`` always live: the **default answer
itself**, ``pg.max_resistible_wrench(model, command, d, upper=U)`` — the load at which the
object gives way by the simulation's own thresholds, docs/giveway.md — at the ``upper`` U of the
simulation record), and compares each direction with the simulation:

- **class**: the simulation holds up to ``upper`` (``held``) or gives way (``gave_way``,
  ``gradual``); a prediction holds when it is ``unbounded``/``above_limit`` or finite at or
  above ``upper``, gives way when finite below it (``below_resolution`` included). Same class,
  wrong class, or **no verdict** (node limit, solver failure, a quasi-static stop without a
  verdict, not run);
- **magnitudes** where both give way (sharp and gradual simulated give-ways alike):
  ``simulated / predicted - 1``; the share within 10 %, median and max of its absolute value;
  directions where both are below 1e-3 of ``upper`` counted apart ("both ≈ 0");
- the old answer λ* (the loading path's first limit, ``MaxWrench.giveway.first_limit``) in the
  column ``first_limit`` beside the default, compared the same way, so the change is visible.

Writes a markdown section (the headline counts, a summary per scene and per contact count,
methods side by side, one table per friction model of the simulation; the disagreements of each
method with the simulation and, for the default answer, its give-way record: reason, first
limit, snaps, the object's motion at the give-way, and the states where its path ended).

Usage::

    python -m scripts.reproduce.validate_quasistatic [--methods quasistatic,iterative,energetic,prp]
        [--sets scenes,random,backdrivable,lowmu] [--friction pyramid,cone] [--out FILE]
        [--details] [--save-live FILE.jsonl] [--limit N]
"""

from __future__ import annotations

import argparse
import datetime
import json
import platform
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import pinograsp as pg

from .qs_cases import SETS, Case, cases, parse_sets
from .qs_references import METHODS_FILE, SIM_FILE, predict, read_jsonl
from .qs_report import SETTLED, render

#: Below this fraction of ``upper`` both answers count as "not resisted" (≈ 0).
ZERO = 1e-3
HOLDS = ("unbounded", "above_limit")
GIVES = ("finite", "below_resolution")


def _path_facts(lp: Any) -> dict[str, Any]:
    """Work, stop reason, last events and the states where the path ended (LoadingPath fields)."""
    out: dict[str, Any] = {
        "segments": int(getattr(lp, "segments", max(len(lp.loads) - 1, 0))),
        "events": len(lp.events),
        "path_status": str(lp.status),
        "stop_reason": str(getattr(lp, "stop_reason", "")),
        "largest_lcp": int(getattr(lp, "largest_lcp", 0)),
        "limit": float(lp.limit),
    }
    text = [e.text() if hasattr(e, "text") else str(e) for e in lp.events]
    out["last_events"] = text[-4:]
    if len(lp.contact_states):
        out["final_states"] = [str(s) for s in lp.contact_states[-1]]
    if len(getattr(lp, "actuator_modes", ())):
        out["final_actuators"] = [str(s) for s in lp.actuator_modes[-1]]
    names = getattr(lp, "contact_names", ())
    if names and "final_states" in out:
        out["final_states"] = [f"{n} {s}" for n, s in zip(names, out["final_states"])]
    audit = getattr(lp, "audit", None) or {}
    out["audit"] = {k: float(np.max(np.abs(v))) for k, v in audit.items() if np.size(v)}
    return out


def trace_load(sim: dict[str, Any], slip: float, rotation: float) -> float | None:
    """Applied load of the simulated ramp where the object first moved ``slip`` [m] or turned
    ``rotation`` [rad], interpolated in log-load between the cached trace samples; None when
    the trace never gets there."""
    tr = sim.get("trace") or {}
    a, t, r = (np.array([np.nan if v is None else v for v in tr.get(k, [])], dtype=float)
               for k in ("applied", "translation", "rotation"))  # fmt: skip
    if a.size < 2:
        return None
    u = np.fmax(t / slip, r / rotation)
    hit = np.flatnonzero(u >= 1.0)
    if not hit.size or hit[0] == 0 or not (a[hit[0] - 1] > 0):
        return None
    j = hit[0]
    s = (1.0 - u[j - 1]) / (u[j] - u[j - 1])
    return float(np.exp(np.log(a[j - 1]) + s * (np.log(a[j]) - np.log(a[j - 1]))))


def path_bounds(g: dict[str, Any]) -> tuple[float, float]:
    """The translation [m] and rotation [rad] at which the default answer's path gives way at
    the latest: the thresholds, or the linearisation's range where that is tighter
    (docs/giveway.md; the length scale is ``slip / rotation`` for the default thresholds)."""
    from pinograsp.core.giveway import LINEAR_ROTATION, LINEAR_TRANSLATION

    ell = g["slip"] / g["rotation"]
    return min(g["slip"], LINEAR_TRANSLATION * ell), min(g["rotation"], LINEAR_ROTATION)


def _answer(model: Any, command: Any, d: np.ndarray, upper: float) -> dict[str, Any]:
    """The default answer ``pg.max_resistible_wrench(model, command, d, upper=upper)`` (the
    give-way load, docs/giveway.md) and its record: reason, first limit λ*, snaps survived,
    the object's motion at the give-way, the stiffness and thresholds used."""
    t0 = time.perf_counter()
    try:
        mw = pg.max_resistible_wrench(model, command, d, upper=upper)
    except pg.PinograspError as exc:
        return {"status": "error", "magnitude": None, "time": time.perf_counter() - t0,
                "error": f"{type(exc).__name__}: {str(exc)[:300]}"}  # fmt: skip
    out: dict[str, Any] = {
        "status": str(mw.status),
        "magnitude": float(mw.magnitude),
        "time": time.perf_counter() - t0,
        "method": str(mw.method),
        "answer": "giveway" if mw.giveway is not None else "first",
    }
    g = mw.giveway
    if g is not None:
        out["giveway"] = {
            "reason": g.reason,
            "first_limit": float(g.first_limit),
            "first_status": g.first_status,
            "snaps": [list(map(float, s)) for s in g.snaps],
            "translation": float(g.translation),
            "turned": float(g.turned),
            "stiffness": float(g.stiffness),
            "slip": float(g.slip),
            "rotation": float(g.rotation),
            "note": g.note,
        }
    return out


def first_limit(rec: dict[str, Any] | None) -> dict[str, Any] | None:
    """The old answer λ* (the path's first limit) of a default-answer record, as a prediction
    record (status, magnitude): ``None`` where the record has no give-way record."""
    g = (rec or {}).get("giveway")
    if not g:
        return None
    st, lam = g["first_status"], g["first_limit"]
    if st == "unbounded" or lam is None or not np.isfinite(lam):
        return {"status": "unbounded", "magnitude": float("inf")}
    if st in ("finite", "below_resolution"):
        return {"status": "finite" if lam > 0 else "below_resolution", "magnitude": float(lam)}
    return {"status": st, "magnitude": float(lam)}


def at_upper(pred: dict[str, Any] | None, sim: dict[str, Any]) -> dict[str, Any] | None:
    """The default answer computed at the simulation record's ``upper`` (a refined record's own,
    else the case's): the thresholds scale with ``upper`` in both."""
    if pred is None or "by_upper" not in pred:
        return pred
    base = {k: v for k, v in pred.items() if k != "by_upper"}
    return {**base, **pred["by_upper"].get(_ukey(sim["upper"]), {})}


def _ukey(upper: float) -> str:
    return f"{float(upper):.6g}"


def run_quasistatic(case: Case, sims: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """The live default answer of one case at the case's ``upper`` and at the ``upper`` of each
    simulation record that differs (a refinement pass), with the loading path's facts."""
    scene, model, command = case.build()
    d = np.asarray(case.direction)
    rec: dict[str, Any] = {"key": case.key, "method": "quasistatic"}
    rec.update(_answer(model, command, d, case.upper))
    uppers = {_ukey(s["upper"]): float(s["upper"]) for s in sims.values() if s.get("upper")}
    rec["by_upper"] = {_ukey(case.upper): {k: v for k, v in rec.items() if k not in ("key", "method")}}
    for k, up in uppers.items():
        if k not in rec["by_upper"]:
            rec["by_upper"][k] = _answer(model, command, d, up)
    try:
        rec.update(_path_facts(pg.loading_path(model, command, d)))
    except pg.PinograspError as exc:
        rec["path_error"] = f"{type(exc).__name__}: {str(exc)[:200]}"
    return rec


def ratio_study(sel: list[Case], ratios: list[float], energetic: dict[str, dict]) -> list[str]:
    """λ* against ``tangential_ratio`` on the scenes' directions, and against the energetic method
    (the paper's rigid friction with maximum dissipation) where that one finishes."""
    lines = [
        "| scene | tangential_ratio | finite / unbounded / ≈ 0 / no verdict"
        " | median / max \\|λ* / λ*(ratio 1) − 1\\| | vs energetic: same class"
        " | median / max \\|λ* / energetic − 1\\| (n) | median ms |",
        "|---|---:|---|---:|---:|---:|---:|",
    ]
    base: dict[str, float] = {}
    for r in sorted(ratios, key=lambda x: x != 1.0):
        settings = pg.Settings(tangential_ratio=r, limit="first")  # λ*, the first limit
        for scene in dict.fromkeys(c.group for c in sel):
            cs = [c for c in sel if c.group == scene]
            counts = {"finite": 0, "unbounded": 0, "below_resolution": 0, "other": 0}
            rel1, rele, same, ts = [], [], 0, []
            for c in cs:
                _, model, command = c.build()
                t0 = time.perf_counter()
                try:
                    mw = pg.quasistatic_max_wrench(model, command, np.asarray(c.direction), settings=settings)
                    st, mag = str(mw.status), float(mw.magnitude)
                except pg.PinograspError:
                    st, mag = "error", float("nan")
                ts.append(time.perf_counter() - t0)
                counts[st if st in counts else "other"] += 1
                if r == 1.0:
                    base[c.key] = mag
                elif st == "finite" and np.isfinite(base.get(c.key, np.nan)) and base[c.key] > 0:
                    rel1.append(mag / base[c.key] - 1.0)
                e = energetic.get(c.key)
                if e and e.get("status") in ("finite", "unbounded", "below_resolution"):
                    same += (e["status"] == "unbounded") == (st == "unbounded")
                    if st == "finite" and e["status"] == "finite" and e["magnitude"]:
                        rele.append(mag / e["magnitude"] - 1.0)
            a1, ae = np.abs(rel1), np.abs(rele)
            f1 = f"{100 * np.median(a1):.2f} / {100 * np.max(a1):.2f} %" if a1.size else "—"
            fe = f"{100 * np.median(ae):.2f} / {100 * np.max(ae):.2f} % ({ae.size})" if ae.size else "—"
            cnt = " / ".join(str(v) for v in counts.values())
            lines.append(f"| {scene} | {r:g} | {cnt} | {f1} | {same} | {fe} | {1e3 * np.median(ts):.2f} |")
    return lines


#: The column of the old answer λ*, the path's first limit (``MaxWrench.giveway.first_limit``).
FIRST = "first_limit"


def methods_shown(methods: list[str]) -> list[str]:
    """The methods' columns: λ* right after the quasi-static default where that one is run."""
    out = []
    for m in methods:
        out.append(m)
        if m == "quasistatic":
            out.append(FIRST)
    return out


def run_live(method: str, case: Case, sims: dict[str, dict[str, Any]]) -> dict[str, Any]:
    if method == "quasistatic":
        return run_quasistatic(case, sims)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return predict(case, method)


def classify(pred: dict[str, Any] | None, sim: dict[str, Any]) -> dict[str, Any]:
    """Verdict of one prediction against one simulation record.

    The class is the prediction's load against ``upper``: it holds when ``unbounded`` /
    ``above_limit`` or finite at or above ``upper``, gives way when finite below it, with "≈ 0"
    (below :data:`ZERO` of ``upper``: not resisted at all) a class of its own among the
    give-ways. ``rel``: simulated give-way load / predicted − 1 wherever both give way (sharp
    and gradual simulated give-ways alike: the default answer is the give-way load by the
    simulation's own thresholds, docs/giveway.md); ``sharp``: whether the simulation gave way
    sharply. No rescue: the answer compared is the prediction's magnitude itself.
    """
    out: dict[str, Any] = {"verdict": "no verdict", "rel": None, "zero": False,
                           "sharp": sim["status"] == "gave_way"}  # fmt: skip
    if pred is None:
        out["verdict"] = out["why"] = "not run"
        return out
    status, mag = pred.get("status"), pred.get("magnitude")
    upper = float(sim["upper"])
    if status in HOLDS or (status == "finite" and mag is not None and mag >= upper * (1 - 1e-9)):
        p_holds = True
    elif status in GIVES and mag is not None:
        p_holds = False
    else:
        out["why"] = str(status)
        return out
    s_holds = sim["status"] == "held"
    if p_holds != s_holds:
        out["verdict"] = "wrong class"
        out["why"] = "predicted holds" if p_holds else "simulation holds"
        return out
    out["verdict"] = "same class"
    if s_holds:
        return out
    small = mag <= ZERO * upper
    sim_small = sim["load"] <= ZERO * upper
    if small and sim_small:
        out["zero"] = True
    elif small != sim_small:  # "not resisted at all" vs a real load: its own class
        out["verdict"] = "wrong class"
        out["why"] = "predicted ≈ 0" if small else "simulated ≈ 0"
    elif mag > 0:
        out["rel"] = sim["load"] / mag - 1.0
    return out


#: A finite pair agrees when |simulated / predicted − 1| is at most this.
WITHIN = 0.10


def headline(rows: list[dict], method: str, friction: str) -> dict[str, Any]:
    """Counts of one method against one friction model's simulations: directions, same class,
    finite pairs (both give way, not both ≈ 0), those within :data:`WITHIN`, median and max
    |rel|."""
    cmps = [r["cmp"][method] for r in rows if r["friction"] == friction and method in r["cmp"]]
    ran = [c for c in cmps if c["verdict"] != "not run"]
    rel = np.abs([c["rel"] for c in ran if c["rel"] is not None])
    return {
        "method": method,
        "friction": friction,
        "directions": len(ran),
        "same": sum(c["verdict"] == "same class" for c in ran),
        "wrong": sum(c["verdict"] == "wrong class" for c in ran),
        "no_verdict": sum(c["verdict"] == "no verdict" for c in ran),
        "finite": int(rel.size),
        "within": int(np.sum(rel <= WITHIN)),
        "median": float(np.median(rel)) if rel.size else None,
        "max": float(np.max(rel)) if rel.size else None,
    }


def load_refs(frictions: list[str]) -> dict[str, dict[str, dict[str, Any]]]:
    """key -> friction -> simulation record (errors dropped: no reference; planar scenes: the cone
    record serves as the pyramid's)."""
    refs: dict[str, dict[str, dict[str, Any]]] = {}
    for r in read_jsonl(SIM_FILE):  # a refinement pass (qs_references.refine_upper) replaces the first
        if r["friction"] in frictions and r["status"] != "error":
            slot = refs.setdefault(r["key"], {})
            if r.get("refined") or not slot.get(r["friction"], {}).get("refined"):
                if r.get("refined") and r["friction"] in slot:
                    r = {
                        **r,
                        "first_pass": {k: slot[r["friction"]].get(k) for k in ("status", "load", "upper")},
                    }
                slot[r["friction"]] = r
    planar = {c.key for c in cases(["scenes"]) if c.planar}
    for key in planar & set(refs):  # one simulation serves both friction models (qs_references)
        if "pyramid" in frictions and "cone" in refs[key] and "pyramid" not in refs[key]:
            refs[key]["pyramid"] = refs[key]["cone"]
    return refs


def settled_refs(refs: dict[str, dict[str, dict[str, Any]]]) -> None:
    """Add to ``refs`` the ``"settled"`` reference of each case with a pyramid record: the ramp
    study's run at its slowest settled (else slowest) ramp where the study ran the direction
    (``scripts/reproduce/ramp_study.json``), else the pyramid record itself (0.02 s)."""
    from . import ramp_study  # it imports this module

    slow = ramp_study.settled_runs("qs/")
    for key, slot in refs.items():
        if "pyramid" in slot:
            slot[SETTLED] = slow.get(key, slot["pyramid"])


def collect(
    methods: list[str], sel: list[Case], refs: dict, fresh: bool, save: Path | None, live: bool = False
) -> dict[str, dict]:
    """method -> key -> prediction record: the quasi-static method live, the paper's methods from
    the cache (``qs_references.py methods``; live for the missing ones only when ``live``)."""
    cached: dict[str, dict[str, dict]] = {}
    for r in read_jsonl(METHODS_FILE):
        cached.setdefault(r["method"], {})[r["key"]] = r
    preds: dict[str, dict[str, dict]] = {}
    for m in methods:
        preds[m] = {}
        have = {} if fresh or m == "quasistatic" else cached.get(m, {})
        todo = [c for c in sel if c.key not in have and (m == "quasistatic" or live)]
        t0 = time.perf_counter()
        for i, c in enumerate(todo):
            rec = run_live(m, c, refs.get(c.key, {}))
            preds[m][c.key] = rec
            if save is not None:
                with save.open("a") as fh:
                    fh.write(json.dumps(rec, default=str) + "\n")
            if (i + 1) % 25 == 0:
                print(f"  {m}: {i + 1}/{len(todo)} live ({time.perf_counter() - t0:.0f} s)", flush=True)
        keys = {c.key for c in sel}
        preds[m].update({k: v for k, v in have.items() if k in keys})
    return preds


def _source() -> str:
    """Where pinograsp was imported from, with its git commit (and whether the tree is dirty)."""
    import subprocess

    where = Path(pg.__file__).resolve().parent
    try:
        git = ["git", "-C", str(where)]
        head = subprocess.run(
            [*git, "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True
        )
        dirty = subprocess.run(
            [*git, "status", "--porcelain", "--", "."], capture_output=True, text=True, check=True
        )
        head, dirty = head.stdout.strip(), dirty.stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return str(where)
    return f"{where} at {head}{' (uncommitted changes)' if dirty else ''}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--methods", default="quasistatic,iterative,energetic,prp")
    ap.add_argument("--sets", default=",".join(SETS))
    ap.add_argument(
        "--friction",
        default=f"pyramid,cone,{SETTLED}",
        help=f"references: pyramid, cone (the default ramp), {SETTLED} (the pyramid, settled ramp)",
    )
    ap.add_argument("--out", help="write the markdown section here (default: print it)")
    ap.add_argument("--doc", help="put the section into this file between the quasi-static markers")
    ap.add_argument("--details", action="store_true", help="add a per-direction table per group")
    ap.add_argument("--fresh", action="store_true", help="recompute cached methods too")
    ap.add_argument("--live", action="store_true", help="run the paper's methods where not cached (slow)")
    ap.add_argument("--save-live", help="append the live predictions to this JSON-lines file")
    ap.add_argument("--limit", type=int, default=0, help="only the first N cases of each set (smoke test)")
    ap.add_argument("--explain", help="print the simulation records and the loading path of one case key")
    ap.add_argument("--ratios", default="", help="also tabulate λ* for these tangential ratios on case 1-3")
    args = ap.parse_args()
    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    frictions = [f.strip() for f in args.friction.split(",") if f.strip()]
    refs = load_refs([f for f in frictions if f != SETTLED] + (["pyramid"] if SETTLED in frictions else []))
    if SETTLED in frictions:
        settled_refs(refs)
    if args.explain:
        explain(args.explain, refs)
        return
    sel = []
    for s in parse_sets(args.sets):
        cs = [c for c in cases([s]) if c.key in refs]
        sel += cs[: args.limit] if args.limit else cs
    if not sel:
        raise SystemExit(f"no simulation references in {SIM_FILE}; run qs_references.py sim first")
    t0 = time.perf_counter()
    preds = collect(
        methods, sel, refs, args.fresh, Path(args.save_live) if args.save_live else None, args.live
    )
    rows = []
    shown = methods_shown(methods)
    for c in sel:
        for f in frictions:
            sim = refs[c.key].get(f)
            if sim is None:
                continue
            p = {m: preds[m].get(c.key) for m in methods}
            if "quasistatic" in p:  # the default answer at the record's upper, and its λ*
                p["quasistatic"] = at_upper(p["quasistatic"], sim)
                p[FIRST] = first_limit(p["quasistatic"])
            rows.append(
                {
                    "case": c,
                    "friction": f,
                    "sim": sim,
                    "preds": p,
                    "cmp": {m: classify(p[m], sim) for m in shown},
                }
            )
    head = (
        f"_Generated by `python -m scripts.reproduce.validate_quasistatic --methods {','.join(methods)}"
        + (f" --ratios {args.ratios}" if args.ratios else "")
        + "` on"
        f" {datetime.date.today()} ({time.perf_counter() - t0:.0f} s for the live predictions;"
        f" {platform.machine()}, pinograsp {pg.__version__} from {_source()}). How the directions are"
        " chosen and compared, and every class disagreement and the largest magnitude difference"
        " explained: [`validation_quasistatic.md`](validation_quasistatic.md)._"
    )
    # the settled reference re-simulated the default answer's disagreements only: its headline
    # is the default's (and λ*'s), the other methods' stay against the 0.02 s records
    heads = [
        headline(rows, m, f) for f in frictions for m in shown if f != SETTLED or m in ("quasistatic", FIRST)
    ]
    text = render(rows, shown, frictions, head, details=args.details, heads=heads)
    for h in heads:
        print(h)
    if args.ratios:
        cached = {r["key"]: r for r in read_jsonl(METHODS_FILE) if r["method"] == "energetic"}
        scenes = [c for c in cases(["scenes"]) if c.group in ("case1", "case2", "case3")]
        ratios = [float(x) for x in args.ratios.split(",")]
        text += "\n### λ* and the tangential stiffness (case 1-3)\n\n" + "\n".join(
            ratio_study(scenes, ratios, cached)
        )
        text += "\n"
    if args.out:
        Path(args.out).write_text(text)
        print(f"wrote {args.out}")
    if args.doc:
        put_section(Path(args.doc), text)
        print(f"updated {args.doc}")
    if not (args.out or args.doc):
        print(text)


def explain(key: str, refs: dict[str, dict[str, dict[str, Any]]]) -> None:
    """The simulation records (no trace) and the loading path's summary of one case."""
    case = next((c for c in cases() if c.key == key), None)
    if case is None:
        raise SystemExit(f"unknown case {key!r}")
    print(case)
    for f, sim in refs.get(key, {}).items():
        print(f, {k: v for k, v in sim.items() if k != "trace"})
    _, model, command = case.build()
    lp = pg.loading_path(model, command, np.asarray(case.direction))
    print(lp.summary())
    rec = run_quasistatic(case, refs.get(key, {}))
    for f, sim in refs.get(key, {}).items():
        a = at_upper(rec, sim) or {}
        print(f"default answer at upper {sim['upper']:g} ({f}): {a.get('status')} {a.get('magnitude')}"
              f" {a.get('giveway')}")  # fmt: skip


START, END = "<!-- quasistatic-validation:start -->", "<!-- quasistatic-validation:end -->"


def put_section(path: Path, text: str) -> None:
    """Replace the text between :data:`START` and :data:`END` in ``path`` (appended when absent;
    ``validate_mujoco.py`` rewrites the rest of docs/validation.md and keeps this section)."""
    old = path.read_text() if path.exists() else ""
    block = f"{START}\n{text}{END}\n"
    if START in old and END in old:
        new = old[: old.index(START)] + block + old[old.index(END) + len(END) :].lstrip("\n")
    else:
        new = old.rstrip("\n") + "\n\n" + block
    path.write_text(new)


if __name__ == "__main__":
    main()
