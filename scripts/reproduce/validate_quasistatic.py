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
from .qs_report import render

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


def _lad(lp: Any, sim: dict[str, Any], fraction: float = 1.0) -> float | str | None:
    """The path's load at ``fraction`` of the simulation's give-way thresholds (translation of
    the reference point and rotation, the contact springs scaled to its stiffness)."""
    rot = sim.get("rotation_threshold")
    try:
        lad = lp.load_at_displacement(
            fraction * sim["slip_threshold"],
            stiffness=sim["stiffness"],
            rotation=None if rot is None else fraction * rot,
        )
    except Exception as exc:  # noqa: BLE001 - recorded, the harness goes on
        return f"{type(exc).__name__}: {str(exc)[:200]}"
    return float(lad) if lad is not None else None


#: Fraction of the simulation's thresholds where the load-displacement curves are compared.
CURVE = 0.01


def trace_load(sim: dict[str, Any], fraction: float = CURVE) -> float | None:
    """Applied load of the simulated ramp where the object first moved ``fraction`` of a
    threshold (translation or rotation), interpolated in log-load between trace samples."""
    tr = sim.get("trace") or {}
    a, t, r = (np.array([np.nan if v is None else v for v in tr.get(k, [])], dtype=float)
               for k in ("applied", "translation", "rotation"))  # fmt: skip
    if a.size < 2:
        return None
    u = np.fmax(t / sim["slip_threshold"], r / sim["rotation_threshold"]) / fraction
    hit = np.flatnonzero(u >= 1.0)
    if not hit.size or hit[0] == 0 or not (a[hit[0] - 1] > 0):
        return None
    j = hit[0]
    s = (1.0 - u[j - 1]) / (u[j] - u[j - 1])
    return float(np.exp(np.log(a[j - 1]) + s * (np.log(a[j]) - np.log(a[j - 1]))))


def _lads(lp: Any, sim: dict[str, Any]) -> dict[str, Any]:
    """At the thresholds (the simulation's give-way), at a tenth of them (its onset) and at
    :data:`CURVE` of them (the load-displacement curves, small motions)."""
    return {"thr": _lad(lp, sim), "onset": _lad(lp, sim, 0.1), "curve": _lad(lp, sim, CURVE)}


def run_quasistatic(case: Case, sims: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """One live quasi-static prediction: the loading path, its limit as a MaxWrench, its facts
    and its load at the simulation's give-way threshold (per friction model simulated)."""
    scene, model, command = case.build()
    d = np.asarray(case.direction)
    rec: dict[str, Any] = {"key": case.key, "method": "quasistatic"}
    t0 = time.perf_counter()
    try:
        if hasattr(pg, "loading_path"):
            lp = pg.loading_path(model, command, d)
            mw = pg.quasistatic_max_wrench(model, command, d, path=lp)
        else:  # through the method registry only
            lp, mw = None, pg.max_resistible_wrench(model, command, d, method="quasistatic", upper=case.upper)
    except pg.PinograspError as exc:
        rec.update(
            status="error",
            magnitude=None,
            time=time.perf_counter() - t0,
            error=f"{type(exc).__name__}: {str(exc)[:300]}",
        )
        return rec
    rec.update(status=str(mw.status), magnitude=float(mw.magnitude), time=time.perf_counter() - t0)
    if lp is not None:
        rec.update(_path_facts(lp))
        rec["lad"] = {fr: _lads(lp, sim) for fr, sim in sims.items() if sim.get("slip_threshold")}
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
        settings = pg.Settings(tangential_ratio=r)
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


def run_live(method: str, case: Case, sims: dict[str, dict[str, Any]]) -> dict[str, Any]:
    if method == "quasistatic":
        return run_quasistatic(case, sims)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return predict(case, method)


def classify(pred: dict[str, Any] | None, sim: dict[str, Any], friction: str) -> dict[str, Any]:
    """Verdict of one prediction against one simulation record.

    The class is the prediction's limit load against ``upper``, with "≈ 0" (below
    :data:`ZERO` of ``upper``: not resisted at all) a class of its own among the give-ways.
    For a prediction with a loading path, a give-way of the simulation also counts as the
    same class when the path moves as far as the simulation's own criterion below ``upper``
    (``via = "threshold"``): its thresholds for a sharp give-way, a tenth of them for a
    gradual one (the simulation calls a give-way gradual when the object has moved more than
    a tenth of a threshold at the largest load it holds). Magnitudes: ``rel`` (sharp
    give-ways) simulated / predicted λ* - 1; ``rel_lad`` simulated load / the path's load at
    the thresholds - 1; ``rel_onset`` the simulation's onset load / the path's load at a
    tenth of the thresholds - 1; ``rel_curve`` the ramp's load where the object had moved
    :data:`CURVE` of a threshold / the path's load there - 1.
    """
    out: dict[str, Any] = {"verdict": "no verdict", "rel": None, "rel_lad": None, "rel_onset": None,
                           "rel_curve": None, "zero": False, "via": None}  # fmt: skip
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
    lads = (pred.get("lad") or {}).get(friction) or {}
    thr, onset = lads.get("thr"), lads.get("onset")
    if not s_holds and isinstance(thr, float) and thr > 0 and sim["load"]:
        out["rel_lad"] = sim["load"] / thr - 1.0
    if sim["status"] == "gradual" and isinstance(onset, float) and onset > 0 and sim.get("onset"):
        out["rel_onset"] = sim["onset"] / onset - 1.0
    curve, at = lads.get("curve"), trace_load(sim)
    if isinstance(curve, float) and curve > 0 and at is not None and np.isfinite(curve):
        out["rel_curve"] = at / curve - 1.0
    crit = onset if sim["status"] == "gradual" else thr
    if not s_holds and p_holds and isinstance(crit, float) and crit < upper:
        p_holds, out["via"] = False, "threshold"
    if p_holds != s_holds:
        out["verdict"] = "wrong class"
        out["why"] = "predicted holds" if p_holds else "simulation holds"
        return out
    out["verdict"] = "same class"
    if s_holds:
        return out
    small = (mag if out["via"] is None else crit) <= ZERO * upper
    sim_small = sim["load"] <= ZERO * upper
    if small and sim_small:
        out["zero"] = True
    elif small != sim_small:  # "not resisted at all" vs a real load: its own class
        out["verdict"] = "wrong class"
        out["why"] = "predicted ≈ 0" if small else "simulated ≈ 0"
    elif sim["status"] == "gave_way" and out["via"] is None and mag > 0:
        out["rel"] = sim["load"] / mag - 1.0
    return out


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
    ap.add_argument("--friction", default="pyramid,cone")
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
    refs = load_refs(frictions)
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
        f"_Generated by `python -m scripts.reproduce.validate_quasistatic --methods {','.join(methods)}"
        + (f" --ratios {args.ratios}" if args.ratios else "")
        + "` on"
        f" {datetime.date.today()} ({time.perf_counter() - t0:.0f} s for the live predictions;"
        f" {platform.machine()}, pinograsp {pg.__version__} from {_source()}). How the directions are"
        " chosen and compared, and every class disagreement and the largest magnitude difference"
        " explained: [`validation_quasistatic.md`](validation_quasistatic.md)._"
    )
    text = render(rows, methods, frictions, head, details=args.details)
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
    for f, sim in refs.get(key, {}).items():
        print(f"load at the {f} simulation's thresholds / a tenth of them: {_lads(lp, sim)}")


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
