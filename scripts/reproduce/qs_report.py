"""Markdown of the quasi-static validation (``validate_quasistatic.py``): tables and disagreements."""

from __future__ import annotations

from collections import OrderedDict
from typing import Any

import numpy as np

SAME = "same class"


def _pct(x: float | None) -> str:
    return "—" if x is None else f"{100 * x:.2f} %"


def _stats(xs: list[float]) -> tuple[float | None, float | None]:
    a = np.abs(np.array(xs, dtype=float))
    return (float(np.median(a)), float(np.max(a))) if a.size else (None, None)


def sim_text(s: dict[str, Any]) -> str:
    if s["status"] == "held":
        return "held"
    if s["status"] == "gradual":
        return (
            f"gradual {s['onset']:.4g}–{s['load']:.4g}"
            if s.get("onset") is not None
            else f"gradual {s['load']:.4g}"
        )
    return "gave way < first load" if not s["load"] else f"gave way {s['load']:.4g}"


def pred_text(p: dict[str, Any] | None) -> str:
    if p is None:
        return "not run"
    st, mag = p.get("status"), p.get("magnitude")
    if st == "unbounded":
        return "unbounded"
    if st == "above_limit":
        return "≥ upper"
    if st == "below_resolution":
        return "≈ 0"
    if st == "finite" and mag is not None:
        return f"{mag:.4g}"
    return str(st).replace("_", " ")


def _groups(rows: list[dict], friction: str) -> OrderedDict[tuple[str, str], list[dict]]:
    out: OrderedDict[tuple[str, str], list[dict]] = OrderedDict()
    for r in rows:
        if r["friction"] == friction:
            out.setdefault((r["case"].set, r["case"].group), []).append(r)
    return out


def _cell(rs: list[dict], m: str) -> tuple[str, str]:
    cmps = [r["cmp"][m] for r in rs]
    same = sum(c["verdict"] == SAME for c in cmps)
    wrong = sum(c["verdict"] == "wrong class" for c in cmps)
    nv = sum(c["verdict"] == "no verdict" for c in cmps)
    notrun = sum(c["verdict"] == "not run" for c in cmps)
    med, mx = _stats([c["rel"] for c in cmps if c["rel"] is not None])
    n = sum(c["rel"] is not None for c in cmps)
    err = "—" if med is None else f"{100 * med:.1f} / {100 * mx:.1f} ({n})"
    run = f" of {len(cmps) - notrun}" if notrun else ""
    via = sum(c["via"] == "threshold" for c in cmps)
    via_text = f" ({via} at the threshold)" if via else ""
    return f"{same} / {wrong} / {nv}{run}{via_text}", err


def summary_table(rows: list[dict], methods: list[str], friction: str) -> list[str]:
    head = "| set | group | dirs | sim: gave way / gradual / held | " + " | ".join(
        f"{m}: same / wrong / no verdict | {m}: sharp \\|diff\\| median / max % (n)" for m in methods
    )
    lines = [head + " |", "|---|---|---:|---|" + "---:|---:|" * len(methods)]
    groups = _groups(rows, friction)
    totals: OrderedDict[str, list[dict]] = OrderedDict()
    for (s, g), rs in groups.items():
        totals.setdefault(s, []).extend(rs)
        sims = [r["sim"]["status"] for r in rs]
        simc = f"{sims.count('gave_way')} / {sims.count('gradual')} / {sims.count('held')}"
        cells = [x for m in methods for x in _cell(rs, m)]
        lines.append(f"| {s} | {g} | {len(rs)} | {simc} | " + " | ".join(cells) + " |")
    everything = [r for part in totals.values() for r in part]
    for s, rs in [*totals.items(), ("**all**", everything)]:
        sims = [r["sim"]["status"] for r in rs]
        simc = f"{sims.count('gave_way')} / {sims.count('gradual')} / {sims.count('held')}"
        cells = [x for m in methods for x in _cell(rs, m)]
        lines.append(f"| {s} | **total** | {len(rs)} | {simc} | " + " | ".join(cells) + " |")
    return lines


def gradual_table(rows: list[dict], friction: str) -> list[str]:
    """Quasi-static vs the simulation's gradual give-ways through load_at_displacement."""
    lines = [
        "| set | group | gradual in the simulation | same class (at a tenth of the thresholds)"
        " | onset: \\|diff\\| median / max | load: \\|diff\\| median / max"
        " | curve at 1 % of the thresholds: \\|diff\\| median / max (n) | λ* below upper |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for (s, g), rs in _groups(rows, friction).items():
        gr = [r for r in rs if r["sim"]["status"] == "gradual"]
        if not gr:
            continue
        cmps = [r["cmp"]["quasistatic"] for r in gr]
        on = _stats([c["rel_onset"] for c in cmps if c["rel_onset"] is not None])
        ld = _stats([c["rel_lad"] for c in cmps if c["rel_lad"] is not None])
        cv = [c["rel_curve"] for c in cmps if c.get("rel_curve") is not None]
        cu = _stats(cv)
        same = sum(c["verdict"] == SAME for c in cmps)
        via = sum(c["via"] == "threshold" for c in cmps)
        fin = sum(
            (r["preds"]["quasistatic"] or {}).get("status") in ("finite", "below_resolution")
            and ((r["preds"]["quasistatic"] or {}).get("magnitude") or np.inf) < r["sim"]["upper"]
            for r in gr
        )
        lines.append(
            f"| {s} | {g} | {len(gr)} | {same} ({via}) | {_pct(on[0])} / {_pct(on[1])}"
            f" | {_pct(ld[0])} / {_pct(ld[1])} | {_pct(cu[0])} / {_pct(cu[1])} ({len(cv)}) | {fin} |"
        )
    return lines


def speed_table(rows: list[dict], methods: list[str]) -> list[str]:
    lines = [
        "| set | group | " + " | ".join(f"{m} median / max [s]" for m in methods) + " |",
        "|---|---|" + "---:|" * len(methods),
    ]
    seen: OrderedDict[tuple[str, str], dict[str, dict]] = OrderedDict()
    for r in rows:
        seen.setdefault((r["case"].set, r["case"].group), {})[r["case"].key] = r["preds"]
    for (s, g), by_key in seen.items():
        cells = []
        for m in methods:
            ts = [p[m]["time"] for p in by_key.values() if p.get(m) and p[m].get("time") is not None]
            cells.append(f"{np.median(ts):.3g} / {np.max(ts):.3g}" if ts else "—")
        lines.append(f"| {s} | {g} | " + " | ".join(cells) + " |")
    return lines


def _qs_facts(p: dict[str, Any]) -> str:
    bits = []
    for k in ("segments", "events", "stop_reason", "largest_lcp"):
        if p.get(k) is not None:
            bits.append(f"{k.replace('_', ' ')} {p[k]}")
    bad = {k: v for k, v in (p.get("audit") or {}).items() if v > 1e-6}
    if bad:
        bits.append("audit " + ", ".join(f"{k} {v:.2g}" for k, v in bad.items()))
    if p.get("final_states"):
        bits.append("final contacts [" + ", ".join(p["final_states"]) + "]")
    if p.get("final_actuators"):
        bits.append("actuators [" + ", ".join(p["final_actuators"]) + "]")
    if p.get("last_events"):
        bits.append("last events: " + "; ".join(p["last_events"]))
    if p.get("error") or p.get("path_error"):
        bits.append(str(p.get("error") or p.get("path_error")))
    return "; ".join(bits)


def disagreements(rows: list[dict], methods: list[str], big: float = 0.05) -> list[str]:
    lines: list[str] = []
    for m in methods:
        items = []
        for r in rows:
            c, p = r["cmp"][m], r["preds"][m]
            flag = c["verdict"] == "wrong class" or (m == "quasistatic" and c["verdict"] == "no verdict")
            flag = flag or (m == "quasistatic" and c["via"] == "threshold")
            large = c["rel"] is not None and abs(c["rel"]) > big
            if not (flag or (m == "quasistatic" and large)):
                continue
            what = c.get("why", "") if c["verdict"] != SAME else "gives way at the threshold"
            if c["rel"] is not None:
                what = f"magnitude {100 * c['rel']:+.1f} %"
            text = (
                f"- `{r['case'].key}` ({r['friction']}; {r['case'].grasp}, d = "
                f"[{', '.join(f'{x:.3g}' for x in r['case'].direction)}]): simulated {sim_text(r['sim'])},"
                f" {m} {pred_text(p)} — {what}"
            )
            if m == "quasistatic" and p:
                lads = (p.get("lad") or {}).get(r["friction"]) or {}
                if lads:
                    text += "; path load at the sim thresholds / a tenth of them " + " / ".join(
                        str(v) if not isinstance(v, float) else f"{v:.4g}" for v in lads.values()
                    )
                if r["sim"].get("first_pass"):
                    fp = r["sim"]["first_pass"]
                    text += f" (simulated at upper {r['sim']['upper']:g};"
                    text += f" at {fp['upper']:g}: {fp['status']} {fp['load']})"
                facts = _qs_facts(p)
                text += f"; {facts}" if facts else ""
            items.append(text)
        lines += [
            "",
            f"### {m}: {len(items)} {'disagreements' if items else 'disagreements: none'}",
            "",
            *items,
        ]
    return lines


def detail_tables(rows: list[dict], methods: list[str], friction: str) -> list[str]:
    lines: list[str] = []
    for (s, g), rs in _groups(rows, friction).items():
        lines += [
            "",
            f"#### {s} / {g} ({friction})",
            "",
            "| direction | simulated | " + " | ".join(f"{m} | diff" for m in methods) + " |",
            "|---|---:|" + "---:|---:|" * len(methods),
        ]
        for r in rs:
            cells = []
            for m in methods:
                c = r["cmp"][m]
                flag = "" if c["verdict"] == SAME else f" **({c['verdict']})**"
                rel = c["rel"] if c["rel"] is not None else c["rel_onset"]
                cells.append(
                    f"{pred_text(r['preds'][m])}{flag} | {'' if rel is None else f'{100 * rel:+.2f} %'}"
                )
            label = r["case"].label if s == "scenes" else r["case"].key.split("/", 1)[1]
            lines.append(f"| {label} | {sim_text(r['sim'])} | " + " | ".join(cells) + " |")
    return lines


def render(
    rows: list[dict], methods: list[str], frictions: list[str], head: str, details: bool = False
) -> str:
    lines = [
        "## The quasi-static method against the simulation (issue 25)",
        "",
        head,
        "",
        "Cells: same class / wrong class / no verdict (of the directions run, where not all were), and"
        " the sharp give-ways' |simulated / predicted − 1|"
        " (median / max over n directions finite in both, both ≈ 0 excluded). Simulation references:"
        " `scripts/reproduce/data/qs_sim.jsonl`; cases: `scripts/reproduce/qs_cases.py`.",
    ]
    for f in frictions:
        label = "the model's pyramid" if f == "pyramid" else "the circular cone"
        lines += ["", f'### Simulation with {label} (`friction="{f}"`)', "", *summary_table(rows, methods, f)]
        if "quasistatic" in methods:
            lines += [
                "",
                f"Gradual give-ways, quasi-static `load_at_displacement(slip_threshold)` ({f}):",
                "",
                *gradual_table(rows, f),
            ]
    lines += ["", "### Time per direction", "", *speed_table(rows, methods)]
    lines += ["", "### Disagreements (generated)", *disagreements(rows, methods)]
    if details:
        lines += ["", "### Per direction"]
        for f in frictions:
            lines += detail_tables(rows, methods, f)
    return "\n".join(lines) + "\n"
