"""Validate any method against the cached simulation references (issue 25 acceptance).

Loads the simulation references (``data/qs_sim.jsonl``, written by ``qs_references.py sim``)
and the cached predictions of the paper's methods (``data/qs_methods.jsonl``), runs the
methods asked for that are not cached (``"quasistatic"`` always live: through
``pg.quasistatic_max_wrench`` when the package has it, else ``pg.max_resistible_wrench(...,
method="quasistatic")``), and compares each direction with the simulation:

- **class**: the simulation holds up to ``upper`` (``held``) or gives way (``gave_way``,
  ``gradual``); a prediction holds when it is ``unbounded``/``above_limit`` or finite at or
  above ``upper``, gives way when finite below it (``below_resolution`` included). Same class,
  wrong class, or **no verdict** (node limit, solver failure, a quasi-static stop without a
  limit, not run);
- **sharp give-ways** (simulation ``gave_way``, prediction finite): ``simulated / predicted - 1``,
  median and max of its absolute value, directions where both are below 1e-3 of ``upper``
  counted apart ("both ≈ 0");
- **gradual give-ways** (simulation ``gradual``, the object sways before it breaks): for the
  quasi-static method the load at which its loading path has moved the simulation's threshold
  ``slip_threshold`` with the contact springs scaled to the simulation's ``stiffness``
  (``LoadingPath.load_at_displacement``), against the simulated load; a path that reaches the
  threshold below ``upper`` is a give-way (same class) even when its limit load is higher.

Writes a markdown section (summary per scene and per contact count, methods side by side, one
table per friction model of the simulation; the disagreements of each method with the
simulation's numbers and, for the quasi-static method, the states where its path ended).

Usage::

    python scripts/reproduce/validate_quasistatic.py [--methods quasistatic,iterative,energetic,prp]
        [--sets scenes,random,backdrivable,lowmu] [--friction pyramid,cone] [--out FILE]
        [--details] [--save-live FILE.jsonl] [--limit N]
"""

from __future__ import annotations

import argparse
import datetime
import json
import platform
import sys
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import pinograsp as pg

sys.path.insert(0, str(Path(__file__).resolve().parent))
from qs_cases import SETS, Case, cases, parse_sets  # noqa: E402
from qs_references import METHODS_FILE, SIM_FILE, predict, read_jsonl  # noqa: E402
from qs_report import render  # noqa: E402

#: Below this fraction of ``upper`` both answers count as "not resisted" (≈ 0).
ZERO = 1e-3
HOLDS = ("unbounded", "above_limit")
GIVES = ("finite", "below_resolution")


def _qs_max_wrench(model: Any, command: np.ndarray, d: np.ndarray, upper: float) -> Any:
    if hasattr(pg, "quasistatic_max_wrench"):
        return pg.quasistatic_max_wrench(model, command, d)
    return pg.max_resistible_wrench(model, command, d, method="quasistatic", upper=upper)


def _path_facts(lp: Any) -> dict[str, Any]:
    """Segments, events and the states where the path ended (whatever the LoadingPath offers)."""
    out: dict[str, Any] = {}
    loads = getattr(lp, "loads", None)
    if loads is not None:
        out["segments"] = max(len(loads) - 1, 0)
    events = getattr(lp, "events", None)
    if events is not None:
        out["events"] = len(events)
        out["last_events"] = [
            str(getattr(e, "summary", lambda e=e: e)()) if callable(getattr(e, "summary", None)) else str(e)
            for e in list(events)[-4:]
        ]
    for name in ("contact_states", "states"):
        states = getattr(lp, name, None)
        if states is not None and len(states):
            out["final_states"] = [str(s) for s in np.asarray(states[-1], dtype=object).ravel()]
            break
    for name in ("actuator_modes",):
        modes = getattr(lp, name, None)
        if modes is not None and len(modes):
            out["final_actuators"] = [str(s) for s in np.asarray(modes[-1], dtype=object).ravel()]
    for name in ("status", "stop_reason", "reason"):
        if getattr(lp, name, None) is not None:
            out[f"path_{name}"] = str(getattr(lp, name))
    return out


def run_quasistatic(case: Case, sims: dict[str, dict[str, Any]], with_path: bool = True) -> dict[str, Any]:
    """One live quasi-static prediction (+ the loading path's facts and load at the sim threshold)."""
    scene, model, command = case.build()
    d = np.asarray(case.direction)
    rec: dict[str, Any] = {"key": case.key, "method": "quasistatic"}
    t0 = time.perf_counter()
    try:
        mw = _qs_max_wrench(model, command, d, case.upper)
    except pg.PinograspError as exc:
        rec.update(
            status="error",
            magnitude=None,
            time=time.perf_counter() - t0,
            error=f"{type(exc).__name__}: {str(exc)[:300]}",
        )
        return rec
    rec.update(status=str(mw.status), magnitude=float(mw.magnitude), time=time.perf_counter() - t0)
    if not (with_path and hasattr(pg, "loading_path")):
        return rec
    try:
        lp = pg.loading_path(model, command, d)
    except pg.PinograspError as exc:
        rec["path_error"] = f"{type(exc).__name__}: {str(exc)[:300]}"
        return rec
    rec.update(_path_facts(lp))
    rec["lad"] = {}
    for fr, sim in sims.items():  # the load at the simulation's give-way threshold, per friction model
        if sim.get("status") in ("gradual", "gave_way") and sim.get("slip_threshold"):
            try:
                lad = lp.load_at_displacement(sim["slip_threshold"], stiffness=sim["stiffness"])
                rec["lad"][fr] = None if lad is None or not np.isfinite(lad) else float(lad)
            except Exception as exc:  # noqa: BLE001 - recorded, the harness goes on
                rec["lad"][fr] = f"{type(exc).__name__}: {str(exc)[:200]}"
    return rec


def run_live(method: str, case: Case, sims: dict[str, dict[str, Any]]) -> dict[str, Any]:
    if method == "quasistatic":
        return run_quasistatic(case, sims)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return predict(case, method)


def classify(pred: dict[str, Any] | None, sim: dict[str, Any], friction: str) -> dict[str, Any]:
    """Verdict of one prediction against one simulation record."""
    out: dict[str, Any] = {"verdict": "no verdict", "rel": None, "rel_gradual": None, "zero": False}
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
    lad = (pred.get("lad") or {}).get(friction)
    if sim["status"] == "gradual" and isinstance(lad, float):
        out["rel_gradual"] = sim["load"] / lad - 1.0 if lad > 0 else None
        if lad < upper:
            p_holds = False  # the path reaches the simulation's threshold below upper
    if p_holds != s_holds:
        out["verdict"] = "wrong class"
        out["why"] = "predicted holds" if p_holds else "simulation holds"
        return out
    out["verdict"] = "same class"
    if not s_holds and mag is not None and np.isfinite(mag):
        if mag <= ZERO * upper and sim["load"] <= ZERO * upper:
            out["zero"] = True
        elif mag > 0 and sim["status"] == "gave_way":
            out["rel"] = sim["load"] / mag - 1.0
    return out


def load_refs(frictions: list[str]) -> dict[str, dict[str, dict[str, Any]]]:
    """key -> friction -> simulation record (errors dropped: no reference)."""
    refs: dict[str, dict[str, dict[str, Any]]] = {}
    for r in read_jsonl(SIM_FILE):
        if r["friction"] in frictions and r["status"] != "error":
            refs.setdefault(r["key"], {})[r["friction"]] = r
    return refs


def collect(
    methods: list[str], sel: list[Case], refs: dict, fresh: bool, save: Path | None
) -> dict[str, dict]:
    """method -> key -> prediction record (cached where available, else live)."""
    cached: dict[str, dict[str, dict]] = {}
    for r in read_jsonl(METHODS_FILE):
        cached.setdefault(r["method"], {})[r["key"]] = r
    preds: dict[str, dict[str, dict]] = {}
    for m in methods:
        preds[m] = {}
        have = {} if fresh or m == "quasistatic" else cached.get(m, {})
        todo = [c for c in sel if c.key not in have]
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--methods", default="quasistatic,iterative,energetic,prp")
    ap.add_argument("--sets", default=",".join(SETS))
    ap.add_argument("--friction", default="pyramid,cone")
    ap.add_argument("--out", help="write the markdown section here (default: print it)")
    ap.add_argument("--details", action="store_true", help="add a per-direction table per group")
    ap.add_argument("--fresh", action="store_true", help="recompute cached methods too")
    ap.add_argument("--save-live", help="append the live predictions to this JSON-lines file")
    ap.add_argument("--limit", type=int, default=0, help="only the first N cases of each set (smoke test)")
    args = ap.parse_args()
    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    frictions = [f.strip() for f in args.friction.split(",") if f.strip()]
    refs = load_refs(frictions)
    sel = []
    for s in parse_sets(args.sets):
        cs = [c for c in cases([s]) if c.key in refs]
        sel += cs[: args.limit] if args.limit else cs
    if not sel:
        raise SystemExit(f"no simulation references in {SIM_FILE}; run qs_references.py sim first")
    t0 = time.perf_counter()
    preds = collect(methods, sel, refs, args.fresh, Path(args.save_live) if args.save_live else None)
    rows = []
    for c in sel:
        for f in frictions:
            sim = refs[c.key].get(f)
            if sim is None:
                continue
            rows.append(
                {
                    "case": c,
                    "friction": f,
                    "sim": sim,
                    "preds": {m: preds[m].get(c.key) for m in methods},
                    "cmp": {m: classify(preds[m].get(c.key), sim, f) for m in methods},
                }
            )
    head = (
        f"_Generated by `python scripts/reproduce/validate_quasistatic.py --methods {','.join(methods)}` on"
        f" {datetime.date.today()} ({time.perf_counter() - t0:.0f} s for the live predictions;"
        f" {platform.machine()}, pinograsp {pg.__version__} from {Path(pg.__file__).parent})._"
    )
    text = render(rows, methods, frictions, head, details=args.details)
    if args.out:
        Path(args.out).write_text(text)
        print(f"wrote {args.out}")
    else:
        print(text)


if __name__ == "__main__":
    main()
