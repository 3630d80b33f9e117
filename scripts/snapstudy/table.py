"""The snap table of docs/giveway.md from ``snaps.jsonl`` (question 3), and the candidate
landing criteria tried on it.

    python -m scripts.snapstudy.table
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

ROWS = Path(__file__).parent / "snaps.jsonl"
#: A simulation "survived the snap" when it gave way above the limit load by this fraction
#: (or held to its upper).
MARGIN = 0.03


def reference(r: dict) -> tuple[str, dict] | None:
    """The slowest simulation of a direction: settled, else pyramid, else the other records."""
    for k in ("settled", "pyramid_0.1", "pyramid", "cone"):
        if r["sims"].get(k):
            return k, r["sims"][k]
    return None


def sim_load(s: dict) -> float:
    """The simulated give-way load, ``inf`` when held to its upper."""
    return math.inf if s["status"] == "held" or s["load"] is None else float(s["load"])


def metrics(r: dict) -> dict:
    s = r["snap"]
    lam = r["first_limit"]
    ka = r["k_after"] if r["k_after"] == r["k_after"] else r["k_after_first"]
    return {
        "E_rel": s["energy"] / (lam * r["slip"]) if lam > 0 else math.nan,  # energy / work of a threshold
        "drop": 1.0 - s["drop"],  # relative load drop on the descent
        "soft": r["k_after"] / r["k_before"] if r["k_before"] > 0 else math.nan,  # k after / k before
        "floppy": lam / (ka * r["slip"]) if ka and ka > 0 else math.inf,  # lam* x compliance after / slip
        "jump": max(s["dtrans"] / r["slip"], s["drot"] / r["rotation"]),  # jump in thresholds
    }


def rows(path: Path = ROWS) -> list[dict]:
    """The directions whose first snap lies below the simulation's upper load (the simulation
    was loaded past it) and whose answer followed it, with their verdicts."""
    out = []
    for r in (json.loads(x) for x in path.read_text().splitlines() if x.strip()):
        ref = reference(r)
        if ref is None:
            continue
        name, s = ref
        lam, up = r["first_limit"], s["upper"]
        if lam >= up * (1 - MARGIN):
            continue  # the simulation never reached the snap
        sl = sim_load(s)
        ans = r["answer"] if r["answer_status"] in ("finite", "below_resolution") else math.inf
        r["ref"], r["sim_load"], r["sim_status"] = name, sl, s["status"]
        r["sim_survived"] = sl > lam * (1 + MARGIN)
        r["answer_past"] = min(ans, up) > lam * (1 + MARGIN)  # the answer itself claims the survival
        r["cmp_answer"] = _agree(min(ans, up), min(sl, up), up)
        r["cmp_lam"] = _agree(lam, min(sl, up), up)
        r["m"] = metrics(r)
        out.append(r)
    return out


def _agree(pred: float, sim: float, up: float) -> bool:
    """Within 10 %, or both at the upper load."""
    if pred >= up * (1 - 1e-9) or sim >= up * (1 - 1e-9):
        return pred >= up * (1 - 1e-9) and sim >= up * (1 - 1e-9)
    return abs(sim / pred - 1) <= 0.10


def table(rs: list[dict]) -> str:
    head = (
        "| direction | ref | λ* [N] | answer [N] | sim [N] | survived | jump du [µm] / rot [mrad] "
        "| E [µJ] | E/(λ*·slip) | load drop | k_after/k_before | λ*/(k_after·slip) |"
    )
    lines = [head, "|" + "---|" * 12]
    for r in sorted(rs, key=lambda r: r["m"]["floppy"]):
        s, m = r["snap"], r["m"]
        ans = "held" if r["answer"] == math.inf else f"{r['answer']:.4g}"
        sim = "held" if r["sim_load"] == math.inf else f"{r['sim_load']:.4g}"
        lines.append(
            f"| {r['key']} | {r['ref']} | {r['first_limit']:.4g} | {ans} | {sim} {r['sim_status'][:4]} "
            f"| {'yes' if r['sim_survived'] else '**no**'} | {s['du'] * 1e6:.3g} / {s['drot'] * 1e3:.3g} "
            f"| {s['energy'] * 1e6:.3g} | {m['E_rel']:.2e} | {m['drop']:.3f} | {m['soft']:.3g} "
            f"| {m['floppy']:.3g} |"
        )
    return "\n".join(lines)


def criterion(rs: list[dict], name: str, cut: float) -> dict:
    """Snaps with metric ``name`` above ``cut`` taken as not landing (the answer would be λ*):
    how many answers get better / worse against the reference simulation."""
    better = worse = same = 0
    moved = []
    for r in rs:
        if not r["answer_past"]:
            continue
        if not r["m"][name] > cut:
            continue
        up = r["sims"][r["ref"]]["upper"]
        now = r["cmp_answer"]
        new = _agree(r["first_limit"], min(r["sim_load"], up), up)
        err_now = abs(min(r["sim_load"], up) / min(r["answer"], up) - 1)
        err_new = abs(min(r["sim_load"], up) / r["first_limit"] - 1)
        if new and not now or (new == now and err_new < err_now - 1e-9):
            better += 1
        elif now and not new or (new == now and err_new > err_now + 1e-9):
            worse += 1
        else:
            same += 1
        moved.append(r["key"])
    return {"metric": name, "cut": cut, "changed": len(moved), "better": better, "worse": worse, "same": same,
            "keys": moved}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.parse_args()
    rs = rows()
    print(table(rs))
    past = [r for r in rs if r["answer_past"]]
    print(f"\n{len(rs)} directions loaded past their snap; {len(past)} whose answer is > λ*(1+{MARGIN}):")
    for r in sorted(past, key=lambda r: r["m"]["floppy"]):
        print(f"  {r['key']}: survived={r['sim_survived']} answer ok={r['cmp_answer']} λ* ok={r['cmp_lam']} "
              + " ".join(f"{k}={v:.3g}" for k, v in r["m"].items()))  # fmt: skip
    for name, cuts in (
        ("floppy", (0.1, 0.3, 0.5, 0.8)),
        ("soft", (-1,)),
        ("E_rel", (1e-4, 1e-3)),
        ("jump", (0.05, 0.1)),
    ):
        for c in cuts:
            if name == "soft":
                continue
            print(criterion(rs, name, c))
    for c in (0.5, 0.3, 0.1):  # soft: k_after/k_before below c
        rs2 = [
            {**r, "m": {**r["m"], "inv_soft": 1 / r["m"]["soft"] if r["m"]["soft"] > 0 else math.inf}}
            for r in rs
        ]
        print(criterion(rs2, "inv_soft", 1 / c))


if __name__ == "__main__":
    main()
