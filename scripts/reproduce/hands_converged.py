"""The built-in hands against a converged simulation: the model's own friction polygon and a
slow ramp (issue 31's validation; docs/validation_quasistatic.md, "The hands at the model's
polygon and a slow ramp").

``validate_hands.py`` caches the simulations of the six hands at the simulation's defaults (the
circular cone, ``ramp_time`` 0.02 s). The ramp study (docs/validation_ramp.md) found that fast
ramp answering grasps that snap or sway by the dynamics of the ramp, and the cone is not the
model's polygon. This script simulates the same 24 directions per hand with
``friction="pyramid"`` and ``ramp_time`` 0.1 s (the study's compromise: within 5 % of the
settled load in 27 of 29 directions), caches them as JSON lines (resumable), and compares the
default answer, computed live, with them.

    nice -n 10 python -m scripts.reproduce.hands_converged run [--hands allegro_left,...]
    python -m scripts.reproduce.hands_converged report [--settled]

``--settled``: the directions the ramp study re-simulated more slowly, at their slowest settled
ramp (0.3 or 1.0 s) instead of 0.1 s.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

import pinograsp as pg

from . import validate_hands as vh

CACHE = Path(__file__).parent / "data" / "hands_converged.jsonl"
RAMP = 0.1
FRICTION = "pyramid"


def _done() -> dict[tuple[str, str], dict]:
    if not CACHE.exists():
        return {}
    rows = [json.loads(line) for line in CACHE.read_text().splitlines() if line.strip()]
    return {(r["hand"], r["direction"]): r for r in rows}


def run(hands: list[str]) -> None:
    """Simulate what the cache lacks, one direction at a time, appending each as it finishes."""
    done = _done()
    for name in hands:
        scene = pg.load_scene(name)
        command = scene.model.command_vector(scene.preload(None))
        upper = float(scene.analysis.upper)
        for label, d in vh.VM._directions(scene, 24):
            if (name, label) in done:
                continue
            t0 = time.process_time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = pg.simulate_max_wrench(
                    scene.model, d, command, upper=upper, friction=FRICTION, ramp_time=RAMP
                )
            row = {"hand": name, "direction": label, "d": [float(v) for v in d], "upper": upper,
                   "status": str(r.status), "load": None if r.load is None else float(r.load),
                   "cpu": time.process_time() - t0}  # fmt: skip
            with CACHE.open("a") as fh:
                fh.write(json.dumps(row) + "\n")
            print(name, label, row["status"], row["load"], f"{row['cpu']:.1f} s", flush=True)


def _verdict(mw: pg.MaxWrench, row: dict) -> tuple[str, float | None]:
    """Same class and, for a finite pair, simulated / predicted − 1."""
    upper = row["upper"]
    held = (
        mw.status == "unbounded"
        or mw.status == "above_limit"
        or (mw.status == "finite" and mw.magnitude >= upper)
    )
    sim_held = row["status"] == "held"
    if held and sim_held:
        return "both hold", None
    if held != sim_held:
        return ("predicted holds" if held else "simulation holds"), None
    rel = row["load"] / float(mw.magnitude) - 1.0 if mw.magnitude > 0 else float("inf")
    return "both give way", rel


def settled(done: dict[tuple[str, str], dict]) -> dict[tuple[str, str], dict]:
    """``done`` with each direction the ramp study re-simulated replaced by its run at the
    slowest settled (else slowest) ramp when that is slower than :data:`RAMP`
    (docs/validation_ramp.md)."""
    from . import ramp_study

    out = dict(done)
    for label, rec in ramp_study.settled_runs("hands/").items():
        hand, direction = label.split("/", 1)
        key = (hand, direction.split(" ")[0])  # "+fy (sideways)": "+fy"
        if key in done and rec["ramp_time"] > RAMP:
            out[key] = {**done[key], **rec}
    return out


def report(slow: bool = False) -> list[str]:
    """Per hand: same class, finite pairs within 10 %, median |diff|; every disagreement
    (``slow``: against :func:`settled`)."""
    done = settled(_done()) if slow else _done()
    lines = [
        "| hand | directions simulated | same class | finite pairs within 10 % | median \\|diff\\| |",
        "|---|---:|---:|---:|---:|",
    ]
    notes, tot = [], [0, 0, 0, 0]
    for name in vh.HANDS:
        scene = pg.load_scene(name)
        same = n = within = 0
        rels = []
        for label, d in vh.VM._directions(scene, 24):
            row = done.get((name, label))
            if row is None:
                continue
            n += 1
            mw = scene.max_resistible_wrench(d)
            verdict, rel = _verdict(mw, row)
            ok = verdict in ("both hold", "both give way")
            same += ok
            if rel is not None:
                rels.append(abs(rel))
                within += abs(rel) <= vh.WITHIN
            if not ok or (rel is not None and abs(rel) > vh.WITHIN):
                sim = "held" if row["status"] == "held" else f"{row['status']} {row['load']:.4g}"
                what = verdict if rel is None else f"{100 * rel:+.1f} %"
                why = mw.giveway.reason if mw.giveway else ""
                head = f"- {name} {label}: simulated {sim}, default {mw.magnitude:.4g}"
                notes.append(f"{head} ({mw.status}, {why}) — {what}")
        med = f"{100 * float(np.median(rels)):.1f} %" if rels else "—"
        lines.append(f"| {name} | {n} | {same} | {within} / {len(rels)} | {med} |")
        tot = [tot[0] + n, tot[1] + same, tot[2] + within, tot[3] + len(rels)]
    lines.append(f"| **all** | {tot[0]} | {tot[1]} | {tot[2]} / {tot[3]} | |")
    return lines + [""] + notes


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=("run", "report"))
    ap.add_argument("--hands", default=",".join(vh.HANDS))
    ap.add_argument("--settled", action="store_true", help="report against the ramp study's settled ramps")
    args = ap.parse_args()
    if args.what == "run":
        run(args.hands.split(","))
    else:
        print("\n".join(report(args.settled)))


if __name__ == "__main__":
    main()
