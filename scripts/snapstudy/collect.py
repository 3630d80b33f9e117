"""Every validated direction whose default answer followed a landed snap, with its snap
metrics and its cached simulations (docs/giveway.md, "Snaps and the fingers' mass"). No simulation is run.

Sets: the 352 directions of ``validate_quasistatic`` (references: pyramid 0.02 s, cone 0.02 s
and "settled": the ramp study's slowest settled pyramid run where it re-simulated, else the
pyramid record), the six hands of ``hands_converged`` (pyramid, 0.1 s; the ramp study's settled
run where there is one) and the top-5 plans of ``planning_acceptance`` (cone, 0.02 s).

    nice -n 10 python -m scripts.snapstudy.collect [--sets qs,hands,plans] [--out FILE]
"""

from __future__ import annotations

import argparse
import json
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import pinograsp as pg
from scripts.snapstudy.snaps import path_of, snap_metrics, stop_load

OUT = Path(__file__).parent / "snaps.jsonl"


def _k_before(lp, th, d6) -> float:
    """Stiffness along the load of the last path segment before the limit [N/m]."""
    u = (lp.object_displacements - lp.object_displacements[0]) @ d6 * th.scale
    du = u[-1] - u[-2] if len(u) > 1 else math.nan
    return float((lp.loads[-1] - lp.loads[-2]) / du) if len(u) > 1 and du > 0 else math.nan


def _k_after(s) -> float:
    """Secant stiffness along the load from the landing to the next peak [N/m]."""
    ll, uu = s.extra["after_loads"], s.extra["after_u"]
    j = int(np.argmax(ll))
    du = uu[j] - uu[0]
    return float((ll[j] - ll[0]) / du) if j > 0 and du > 0 else math.nan


def _k_after_first(s) -> float:
    """Stiffness of the first segment after the landing [N/m]."""
    ll, uu = s.extra["after_loads"], s.extra["after_u"]
    if len(ll) < 2 or uu[1] <= uu[0]:
        return math.nan
    return float((ll[1] - ll[0]) / (uu[1] - uu[0]))


def record(model, command, d, upper: float) -> dict[str, Any] | None:
    """The snap record of one direction, or None when the answer followed no landed snap."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        p, lp, loc, th, d6 = path_of(model, command, np.asarray(d, float), upper)
    if not loc.giveway.snaps:
        return None
    snaps = snap_metrics(p, lp, th, d6)
    s = snaps[0]
    return {
        "answer": loc.magnitude,
        "answer_status": loc.status,
        "reason": loc.giveway.reason,
        "first_limit": loc.giveway.first_limit,
        "survived": [list(x) for x in loc.giveway.snaps],
        "n_snaps": len(loc.giveway.snaps),
        "slip": th.slip,
        "rotation": th.rotation,
        "length_scale": th.length_scale,
        "snap": {k: v for k, v in s.__dict__.items() if k not in ("extra", "changed")},
        "changed": s.changed,
        "k_before": _k_before(lp, th, d6),
        "k_after": _k_after(s),
        "k_after_first": _k_after_first(s),
        "stop_load": stop_load(s)[0],
        "snaps_all": [[x.limit, x.landing, x.du, x.drot, x.energy] for x in snaps],
    }


def _sim(s: dict | None) -> dict | None:
    if not s:
        return None
    load = s.get("load")
    return {"status": s["status"], "load": None if load in (None, "inf") else float(load),
            "upper": float(s["upper"]), "ramp_time": s.get("ramp_time")}  # fmt: skip


def qs_rows():
    from scripts.reproduce.qs_cases import SETS, cases
    from scripts.reproduce.validate_quasistatic import load_refs, settled_refs

    refs = load_refs(["pyramid", "cone"])
    settled_refs(refs)
    for c in cases(SETS):
        slot = refs.get(c.key, {})
        if not slot:
            continue
        _, model, command = c.build()
        sims = {k: _sim(v) for k, v in slot.items()}
        up = float(slot.get("pyramid", slot.get("cone"))["upper"])
        yield f"qs/{c.key}", model, command, c.direction, up, sims


def hands_rows():
    from scripts.reproduce import ramp_study
    from scripts.reproduce.hands_converged import CACHE

    slow = ramp_study.settled_runs("hands/")
    rows = [json.loads(x) for x in CACHE.read_text().splitlines() if x.strip()]
    scenes: dict[str, Any] = {}
    for r in rows:
        if r["hand"] not in scenes:
            sc = pg.load_scene(r["hand"])
            scenes[r["hand"]] = (sc.model, sc.model.command_vector(sc.preload(None)))
        model, command = scenes[r["hand"]]
        key = f"{r['hand']}/{r['direction']}"
        sims = {"pyramid_0.1": _sim(r)}
        if key in slow:
            sims["settled"] = _sim(slow[key])
        yield f"hands/{key}", model, command, r["d"], float(r["upper"]), sims


def plan_rows():
    from pinograsp.batch.disturbances import cube_directions
    from pinograsp.batch.grasps import build_grasp
    from scripts.reproduce.planning_acceptance import CACHE, spec_of

    labels, dirs = cube_directions()
    data = json.loads(CACHE.read_text())
    for key, pair in data["pairs"].items():
        for i, p in enumerate(pair["plans"]):
            if not p["sims"]:
                continue
            model, command, _ = build_grasp(spec_of(p["spec"]))
            for label, sim in p["sims"].items():
                if str(sim["status"]).startswith("error"):
                    continue
                d = np.zeros(6)
                d[:3] = dirs[labels.index(label)][:3]
                yield (
                    f"plans/{key}/plan{i + 1}/{label}",
                    model,
                    command,
                    d,
                    float(sim["upper"]),
                    {"cone": _sim(sim)},
                )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sets", default="qs,hands,plans")
    ap.add_argument("--out", type=Path, default=OUT)
    a = ap.parse_args()
    gens = {"qs": qs_rows, "hands": hands_rows, "plans": plan_rows}
    n = found = 0
    with a.out.open("w") as fh:
        for name in a.sets.split(","):
            for key, model, command, d, up, sims in gens[name]():
                n += 1
                try:
                    rec = record(model, command, d, up)
                except pg.PinograspError as exc:
                    rec = None
                    print(key, "error", type(exc).__name__, flush=True)
                if rec is None:
                    continue
                found += 1
                fh.write(json.dumps({"key": key, "upper": up, "sims": sims, **rec}, default=float) + "\n")
                fh.flush()
                print(
                    f"{key}: lam* {rec['first_limit']:.4g} answer {rec['answer']:.4g} sims {sims}", flush=True
                )
    print(f"{found} of {n} directions followed a landed snap", flush=True)


if __name__ == "__main__":
    main()
