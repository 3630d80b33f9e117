"""How the simulation's answer converges with the ramp rate, on the disagreement set.

The validation compares the default answer (``pg.max_resistible_wrench``, the give-way load,
docs/giveway.md) with ``pg.simulate_max_wrench`` at the simulation's default ``ramp_time`` 0.02 s.
This study simulates again, with ``friction="pyramid"`` (the model's own polygon), the same
``upper`` and default thresholds and ``hold_time``, at ``ramp_time`` 0.02, 0.1 and 0.3 s (and
1.0 s where 0.3 still moves by more than :data:`CONVERGED`), every direction where the default
answer disagrees with the simulation in the validation docs:

- ``qs``: the cases of ``scripts/reproduce/qs_cases.py`` whose pyramid record (the refined one
  where there is one: its ``upper``) is of the wrong class or more than 10 % from the default
  answer (docs/validation.md, "Disagreements"); the cached record is the 0.02 s run;
- ``hands``: the built-in hands' directions of ``validate_hands.py`` that disagree with their cached
  (cone) simulation (docs/validation.md, "Built-in hands: every disagreement");
- ``example``: case 2 along +X with its named preloads (docs/validation_quasistatic.md);
- ``control``: agreeing finite pairs of both sets, evenly spaced.

The simulation CPU time is budgeted (``--budget``, seconds); the directions run in the order of
:func:`ordered` (a few of each kind first) and the 1.0 s runs only once every selected direction
has its 0.3 s run, so a cut budget leaves whole directions out, listed as not run. Results are
saved after every simulation in ``ramp_study.json`` next to this file (an interrupted run
resumes), and the report (docs/validation_ramp.md, between the ``ramp-study`` markers) is
written from that file alone.

Usage::

    nice -n 10 python -m scripts.reproduce.ramp_study run [--budget 1500] [--slow-budget 300]
    python -m scripts.reproduce.ramp_study report        # from the JSON, no simulation
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

import pinograsp as pg

from . import validate_hands as vh
from . import validate_quasistatic as vq
from .qs_cases import cases

HERE = Path(__file__).resolve().parent
DATA = HERE / "ramp_study.json"
DOC = HERE.parents[1] / "docs" / "validation_ramp.md"
BEGIN, END = "<!-- ramp-study:start -->", "<!-- ramp-study:end -->"
#: Ramp times [s] run on every selected direction, and the slow one added where needed.
RAMPS = (0.02, 0.1, 0.3)
SLOW = 1.0
#: A direction has converged when its load moves by less than this between two ramp times.
CONVERGED = 0.05
#: Controls: agreeing finite pairs, this many from each source.
CONTROLS = {"qs": 6, "hands": 4}
#: Directions run first (a few of every kind of disagreement), by key prefix, in this order.
FIRST = (
    "example/case2/+fx finger2_only",
    "example/case2/+fx finger1_only",
    "hands/ezgripper/+fy",
    "hands/ezgripper/15°",
    "hands/ezgripper/195°",
    "hands/talos_gripper/+fx",
    "hands/hey5/315°",
    "hands/ability/60°",
    "qs/scenes/case2/165°",
    "qs/scenes/case3/255°",
    "qs/random/n2s1/d0",
    "hands/allegro_left/135°",
    "hands/talos_gripper/+fz",
    "hands/ability/+fx",
    "hands/hey5/240°",
    "hands/ezgripper/75°",
    "qs/lowmu/n3s1/d1",
    "qs/scenes/wedge/45°",
)


def _key(rt: float) -> str:
    return f"{rt:g}"


# ---------------------------------------------------------------- the directions


def _answer_record(pred: dict[str, Any]) -> dict[str, Any]:
    """The default answer's status, magnitude, give-way reason and first limit."""
    g = pred.get("giveway") or {}
    mag = pred.get("magnitude")
    return {
        "status": pred.get("status"),
        "magnitude": None if mag is None or not np.isfinite(mag) else float(mag),
        "reason": g.get("reason"),
        "first_limit": None if g.get("first_limit") is None or not np.isfinite(g["first_limit"]) else
        float(g["first_limit"]),
        "first_status": g.get("first_status"),
    }  # fmt: skip


def _sim_record(sim: dict[str, Any], wall: float | None = None) -> dict[str, Any]:
    load = sim.get("load")
    return {
        "status": sim["status"],
        "load": None if load is None or not np.isfinite(load) else float(load),
        "onset": sim.get("onset"),
        "upper": float(sim["upper"]),
        "wall_time": float(sim.get("wall_time", sim.get("t", 0.0)) if wall is None else wall),
    }


def qs_directions() -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """(disagreements, agreeing finite pairs) of the quasi-static cases against their pyramid
    record, each with the default answer at the record's ``upper`` and the record as the 0.02 s run."""
    refs = vq.load_refs(["pyramid", "cone"])
    bad, good = [], []
    for c in cases():
        ref = refs.get(c.key, {})
        sim = ref.get("pyramid", ref.get("cone"))  # the wedge has its cone record only
        if sim is None:
            continue
        _, model, command = c.build()
        pred = vq._answer(model, command, np.asarray(c.direction), float(sim["upper"]))
        cmp = vq.classify(pred, sim)
        row = {"key": f"qs/{c.key}", "source": "qs", "upper": float(sim["upper"]),
               "answer": _answer_record(pred), "sims": {}}  # fmt: skip
        if "pyramid" in ref:
            row["sims"][_key(0.02)] = {**_sim_record(sim), "cached": True}  # the validation's own run
        else:
            row["reference"] = "cone"
        if cmp["verdict"] != "same class" or (cmp["rel"] is not None and abs(cmp["rel"]) > vq.WITHIN):
            bad.append({**row, "role": "disagreement"})
        elif cmp["rel"] is not None:
            good.append({**row, "role": "control"})
    return bad, good


def hand_directions() -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """(disagreements, agreeing finite pairs) of the built-in hands against their cached (cone)
    simulation; the pyramid runs are all made here."""
    bad, good = [], []
    for name in vh.HANDS:
        rows = json.loads((vh.CACHE / f"{name}.json").read_text())["rows"]
        scene = pg.load_scene(name)
        for (_, d), row in zip(vh.VM._directions(scene, len(rows)), rows):
            pred = vh._predict_live(scene, d)
            sim = {**row["sim"], "upper": float(scene.analysis.upper)}
            cmp = vq.classify(pred, sim)
            rec = {"key": f"hands/{name}/{row['direction']}", "source": "hands", "upper": sim["upper"],
                   "direction": [float(x) for x in d], "answer": _answer_record(pred),
                   "cone_002": _sim_record(sim), "sims": {}}  # fmt: skip
            if cmp["verdict"] != "same class" or (cmp["rel"] is not None and abs(cmp["rel"]) > vq.WITHIN):
                bad.append({**rec, "role": "disagreement"})
            elif cmp["rel"] is not None:
                good.append({**rec, "role": "control"})
    return bad, good


def example_directions() -> list[dict[str, Any]]:
    """Case 2 along +X with its two named preloads (docs/giveway.md's example)."""
    scene = pg.load_scene("case2")
    out = []
    for preload in ("finger1_only", "finger2_only"):
        mw = pg.max_resistible_wrench(scene.model, scene.preload(preload), "fx", upper=50.0)
        pred = {"status": str(mw.status), "magnitude": float(mw.magnitude),
                "giveway": mw.giveway.to_dict() if mw.giveway else {}}  # fmt: skip
        out.append({"key": f"example/case2/+fx {preload}", "source": "example", "role": "example",
                    "upper": 50.0, "answer": _answer_record(pred), "sims": {}})  # fmt: skip
    return out


def _spaced(rows: list[dict[str, Any]], n: int) -> list[dict[str, Any]]:
    if len(rows) <= n:
        return rows
    return [rows[i] for i in np.linspace(0, len(rows) - 1, n).round().astype(int)]


def ordered(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """:data:`FIRST`, then the controls, then the other disagreements in their listed order."""
    out: list[dict[str, Any]] = []
    for prefix in FIRST:
        out += [r for r in rows if r["key"].startswith(prefix) and r not in out][:1]
    out += [r for r in rows if r["role"] == "control" and r not in out]
    return out + [r for r in rows if r not in out]


def select() -> list[dict[str, Any]]:
    qb, qg = qs_directions()
    hb, hg = hand_directions()
    return ordered(
        example_directions() + qb + hb + _spaced(qg, CONTROLS["qs"]) + _spaced(hg, CONTROLS["hands"])
    )


# ---------------------------------------------------------------- the simulations


_CASES: dict[str, dict[str, Any]] = {}


def simulate(row: dict[str, Any], ramp_time: float) -> dict[str, Any]:
    """One pyramid simulation of a direction at ``ramp_time`` [s] (its ``upper``, defaults)."""
    src, key = row["source"], row["key"]
    opts = {"friction": "pyramid", "ramp_time": ramp_time, "upper": row["upper"]}
    t0 = time.process_time()
    if src == "qs":
        case = _CASES.setdefault("all", {f"qs/{c.key}": c for c in cases()})[key]
        scene, model, command = case.build()
        d = np.asarray(case.direction)
        r = pg.simulate_max_wrench(
            scene if scene is not None else model, d, None if scene else command, **opts
        )
    elif src == "hands":
        r = pg.simulate_max_wrench(pg.load_scene(key.split("/")[1]), np.asarray(row["direction"]), **opts)
    else:
        r = pg.simulate_max_wrench(pg.load_scene("case2"), "fx", key.rsplit(" ", 1)[1], **opts)
    return {"status": r.status, "load": float(r.load) if r.load is not None else None,
            "onset": None if r.onset_load is None else float(r.onset_load), "upper": float(r.upper),
            "wall_time": round(time.process_time() - t0, 2), "steps": int(r.steps)}  # fmt: skip


def _save(state: dict[str, Any]) -> None:
    tmp = DATA.with_suffix(".tmp")
    tmp.write_text(json.dumps(state, indent=1, ensure_ascii=False) + "\n")
    tmp.replace(DATA)


def spent(state: dict[str, Any]) -> float:
    """CPU seconds of the simulations run by this study (the cached 0.02 s records excluded)."""
    return sum(s["wall_time"] for r in state["rows"] for k, s in r["sims"].items() if not s.get("cached"))


def run(budget: float, slow_budget: float = 0.0) -> None:
    """Simulate up to ``budget`` CPU seconds at :data:`RAMPS`, then the 1.0 s runs up to
    ``budget + slow_budget``."""
    old = {r["key"]: r["sims"] for r in json.loads(DATA.read_text())["rows"]} if DATA.exists() else {}
    rows = select()  # the runs already made are kept (resume)
    for r in rows:
        r["sims"].update(old.get(r["key"], {}))
    state = {"meta": {"ramps": list(RAMPS), "slow": SLOW, "budget": budget + slow_budget}, "rows": rows}
    _save(state)
    plan = [(r, rt) for r in state["rows"] for rt in RAMPS]
    for r, rt in plan:
        if _key(rt) in r["sims"]:
            continue
        if any(_key(x) not in r["sims"] for x in RAMPS if x < rt) or spent(state) > budget:
            continue
        if rt == RAMPS[0] and spent(state) > budget * 0.85:  # do not open a direction it cannot finish
            continue
        r["sims"][_key(rt)] = simulate(r, rt)
        _save(state)
        s = r["sims"][_key(rt)]
        print(f"[{spent(state):6.0f} s] {r['key']:40s} {rt:<5g} {s['status']:9s} {s['load']!s:>10.8s}"
              f" ({s['wall_time']:.1f} s)", flush=True)  # fmt: skip
    for r in state["rows"]:
        a, b = r["sims"].get(_key(0.1)), r["sims"].get(_key(0.3))
        if (
            a
            and b
            and _key(SLOW) not in r["sims"]
            and change(a, b) > CONVERGED
            and spent(state) < budget + slow_budget
        ):
            r["sims"][_key(SLOW)] = simulate(r, SLOW)
            _save(state)
            print(f"[{spent(state):6.0f} s] {r['key']:40s} {SLOW:<5g} {r['sims'][_key(SLOW)]}", flush=True)


# ---------------------------------------------------------------- the comparison


def change(a: dict[str, Any], b: dict[str, Any]) -> float:
    """Relative change of the simulated load from ``a`` to ``b`` (0 when both hold, inf when one
    holds and the other does not)."""
    ha, hb = a["status"] == "held", b["status"] == "held"
    if ha and hb:
        return 0.0
    if ha != hb or not a["load"] or b["load"] is None:
        return float("inf")
    return abs(b["load"] / a["load"] - 1.0)


def compare(answer: dict[str, Any], sim: dict[str, Any]) -> tuple[str, float | None]:
    """(verdict, simulated / predicted − 1) of the default answer against one run (vq.classify)."""
    c = vq.classify({"status": answer["status"], "magnitude": answer["magnitude"]}, sim)
    if c["verdict"] != "same class":
        return c.get("why", c["verdict"]), None
    if c["rel"] is None:
        return "agrees", None
    return ("agrees" if abs(c["rel"]) <= vq.WITHIN else "differs"), c["rel"]


def assess(row: dict[str, Any]) -> dict[str, Any] | None:
    """Convergence and agreement of one direction (None when its 0.1 or 0.3 s run is missing)."""
    sims = row["sims"]
    if not all(_key(x) in sims for x in RAMPS):
        return None
    conv = None
    if change(sims[_key(0.1)], sims[_key(0.3)]) <= CONVERGED:
        conv = 0.3
    elif _key(SLOW) in sims and change(sims[_key(0.3)], sims[_key(SLOW)]) <= CONVERGED:
        conv = SLOW
    slowest = SLOW if _key(SLOW) in sims else 0.3
    at = conv if conv is not None else slowest
    v0, rel0 = compare(row["answer"], sims[_key(0.02)])
    v1, rel1 = compare(row["answer"], sims[_key(at)])
    if v1 == "agrees":
        trend = "agrees throughout" if v0 == "agrees" else "vanishes"
    elif v0 == "agrees":
        trend = "appears"
    elif rel0 is not None and rel1 is not None:
        trend = (
            "shrinks"
            if abs(rel1) < abs(rel0) - 0.02
            else "grows"
            if abs(rel1) > abs(rel0) + 0.02
            else "stays"
        )
    else:
        trend = "stays" if v0 == v1 else "changes class"
    return {
        "converged": conv,
        "at": at,
        "v002": v0,
        "rel002": rel0,
        "verdict": v1,
        "rel": rel1,
        "trend": trend if conv is not None else f"unsettled ({trend})",
    }


def settled_runs(prefix: str, path: Path | None = None) -> dict[str, dict[str, Any]]:
    """The study's run at the slowest settled (else slowest) ramp of each direction whose key
    starts with ``prefix`` (``"qs/"``, ``"hands/"``), keyed by the rest of the key, with its
    ``ramp_time`` [s]; empty when the study has not been run (``path``: default :data:`DATA`)."""
    path = DATA if path is None else path
    if not path.exists():
        return {}
    out = {}
    for row in json.loads(path.read_text())["rows"]:
        a = assess(row) if row["key"].startswith(prefix) else None
        if a is not None:
            out[row["key"][len(prefix) :]] = {**row["sims"][_key(a["at"])], "ramp_time": a["at"]}
    return out


def _sim_text(s: dict[str, Any] | None) -> str:
    if s is None:
        return "—"
    if s["status"] == "held":
        return "held"
    tag = {"gave_way": "", "gradual": " g"}.get(s["status"], f" {s['status']}")
    return f"{s['load']:.4g}{tag}"


def _ans_text(a: dict[str, Any]) -> str:
    if a["status"] in ("unbounded", "above_limit") or a["magnitude"] is None:
        return a["status"]
    lam = "∞" if a["first_limit"] is None else f"{a['first_limit']:.4g}"
    return f"{a['magnitude']:.4g} ({a['reason']}; λ* {lam})"


def _verdict_text(v: str, rel: float | None) -> str:
    return v if rel is None else f"{v} {100 * rel:+.1f} %"


def table(rows: list[dict[str, Any]]) -> list[str]:
    lines = [
        "| direction | role | upper | default answer (reason; λ*) | 0.02 s | 0.1 s | 0.3 s | 1.0 s"
        " | converged | at 0.02 s | at the slowest converged (else slowest) ramp | trend |",
        "|---|---|---:|---|---:|---:|---:|---:|---|---|---|---|",
    ]
    for r in rows:
        a = assess(r)
        if a is None:
            continue
        s = r["sims"]
        conv = "no" if a["converged"] is None else f"by {a['converged']:g} s"
        lines.append(
            f"| `{r['key']}` | {r['role']} | {r['upper']:g} | {_ans_text(r['answer'])} | "
            + " | ".join(_sim_text(s.get(_key(x))) for x in (*RAMPS, SLOW))
            + f" | {conv} | {_verdict_text(a['v002'], a['rel002'])} | {_verdict_text(a['verdict'], a['rel'])}"
            f" ({a['at']:g} s) | {a['trend']} |"
        )
    return lines


def counts(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Counts over the disagreements (and examples) and the controls that were run."""
    out: dict[str, Any] = {}
    for role in ("disagreement", "example", "control"):
        sel = [r for r in rows if r["role"] == role]
        done = [(r, a) for r in sel if (a := assess(r)) is not None]
        conv = [(r, a) for r, a in done if a["converged"] is not None]
        out[role] = {
            "listed": len(sel),
            "run": len(done),
            "converged_by_0.3": sum(a["converged"] == 0.3 for _, a in done),
            "converged_by_1.0": sum(a["converged"] == SLOW for _, a in done),
            "not_converged": len(done) - len(conv),
            "agree_when_converged": sum(a["verdict"] == "agrees" for _, a in conv),
            "still_disagree_when_converged": sum(a["verdict"] != "agrees" for _, a in conv),
            "agree_at_002": sum(a["v002"] == "agrees" for _, a in done),
            "trends": {
                t: sum(a["trend"] == t for _, a in done) for t in sorted({a["trend"] for _, a in done})
            },
        }
    return out


def render(state: dict[str, Any]) -> list[str]:
    rows = state["rows"]
    c = counts(rows)
    lines = [
        BEGIN,
        "",
        "_Generated by `python -m scripts.reproduce.ramp_study report` from"
        " `scripts/reproduce/ramp_study.json`"
        f" ({spent(state):.0f} s of simulation CPU time, budget {state['meta']['budget']:g} s)._",
        "",
        "| role | listed | run | converged by 0.3 s | by 1.0 s | not converged"
        " | agree at 0.02 s | converged and agree | converged and still disagree | trends |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for role, k in c.items():
        tr = ", ".join(f"{t} {n}" for t, n in k["trends"].items())
        lines.append(
            f"| {role} | {k['listed']} | {k['run']} | {k['converged_by_0.3']} | {k['converged_by_1.0']}"
            f" | {k['not_converged']} | {k['agree_at_002']} | {k['agree_when_converged']}"
            f" | {k['still_disagree_when_converged']} | {tr} |"
        )
    lines += ["", *table(rows), ""]
    missing = [r["key"] for r in rows if assess(r) is None]
    if missing:
        lines += [f"Not run (budget): {len(missing)} — " + ", ".join(f"`{k}`" for k in missing), ""]
    return [*lines, END]


def section(text: str) -> str:
    """The generated section of a document (markers included)."""
    i, j = text.index(BEGIN), text.index(END) + len(END)
    return text[i:j]


def report() -> None:
    state = json.loads(DATA.read_text())
    new = "\n".join(render(state))
    text = DOC.read_text() if DOC.exists() else f"# Validation and the ramp rate\n\n{BEGIN}\n{END}\n"
    DOC.write_text(text.replace(section(text), new))
    print(new)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=("run", "report"))
    ap.add_argument("--budget", type=float, default=1500.0, help="simulation CPU seconds at 0.02-0.3 s")
    ap.add_argument("--slow-budget", type=float, default=300.0, help="more CPU seconds for the 1.0 s runs")
    args = ap.parse_args()
    if args.what == "run":
        run(args.budget, args.slow_budget)
    report()


if __name__ == "__main__":
    main()
