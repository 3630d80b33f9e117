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


#: A finite pair agrees when |simulated / predicted − 1| is at most this (validate_quasistatic.WITHIN).
WITHIN = 0.10
#: Column titles of the methods (the old answer λ* beside the default).
TITLE = {"quasistatic": "default (give-way)", "first_limit": "λ* (first limit)"}


def title(m: str) -> str:
    return TITLE.get(m, m)


def _cell(rs: list[dict], m: str) -> tuple[str, str]:
    cmps = [r["cmp"][m] for r in rs]
    same = sum(c["verdict"] == SAME for c in cmps)
    wrong = sum(c["verdict"] == "wrong class" for c in cmps)
    nv = sum(c["verdict"] == "no verdict" for c in cmps)
    notrun = sum(c["verdict"] == "not run" for c in cmps)
    rels = [c["rel"] for c in cmps if c["rel"] is not None]
    med, mx = _stats(rels)
    within = sum(abs(x) <= WITHIN for x in rels)
    err = "—" if med is None else f"{within}/{len(rels)} · {100 * med:.1f} / {100 * mx:.1f}"
    run = f" of {len(cmps) - notrun}" if notrun else ""
    return f"{same} / {wrong} / {nv}{run}", err


def summary_table(rows: list[dict], methods: list[str], friction: str) -> list[str]:
    head = "| set | group | dirs | sim: gave way / gradual / held | " + " | ".join(
        f"{title(m)}: same / wrong / no verdict"
        f" | {title(m)}: within 10 % / finite · \\|diff\\| median / max %"
        for m in methods
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


#: The simulation references by name: the two friction models at the default ramp, and the
#: pyramid at the slowest settled ramp of the ramp study (``SETTLED``).
SETTLED = "settled"
LABELS = {
    "pyramid": "the model's pyramid",
    "cone": "the circular cone",
    SETTLED: "the model's pyramid at the slowest settled ramp",
}


def reference(friction: str) -> str:
    """How a reference was simulated, for the tables' titles."""
    if friction == SETTLED:
        return (
            '`friction="pyramid"`, the ramp study\'s slowest settled `ramp_time` where it ran'
            " ([`validation_ramp.md`](validation_ramp.md)), else 0.02 s"
        )
    return f'`friction="{friction}"`'


def headline_lines(heads: list[dict]) -> list[str]:
    """One line per method and friction model (``validate_quasistatic.headline`` records)."""
    out = []
    for h in heads:
        n, f = h["directions"], h["finite"]
        same = f"{h['same']}/{n} same class ({100 * h['same'] / n:.1f} %)" if n else "not run"
        fin = (
            f"{h['within']}/{f} finite pairs within 10 % ({100 * h['within'] / f:.1f} %), median"
            f" \\|diff\\| {100 * h['median']:.2f} %, max {100 * h['max']:.1f} %"
            if f
            else "no finite pairs"
        )
        out.append(f"- **{title(h['method'])}**, {reference(h['friction'])}: {same}; {fin}")
    return out


def speed_table(rows: list[dict], methods: list[str]) -> list[str]:
    lines = [
        "| set | group | " + " | ".join(f"{title(m)} median / max [s]" for m in methods) + " |",
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


def giveway_text(p: dict[str, Any]) -> str:
    """The default answer's give-way record in words: reason, first limit λ*, snaps survived,
    the object's motion at the give-way against the thresholds, and any note."""
    g = p.get("giveway")
    if not g:
        return ""
    lam = g["first_limit"]
    first = "none (unbounded)" if lam is None or not np.isfinite(lam) else f"{lam:.4g} ({g['first_status']})"
    snaps = ", ".join(f"{a:.4g}→{b:.4g}" for a, b in g["snaps"]) or "none"
    text = (
        f"reason {g['reason']}, first limit {first}, snaps survived {snaps}; at the give-way"
        f" {1e3 * g['translation']:.3g} mm / {np.degrees(g['turned']):.3g}° (thresholds"
        f" {1e3 * g['slip']:.3g} mm / {np.degrees(g['rotation']):.3g}° at {g['stiffness']:.3g} N/m)"
    )
    return text + (f"; {g['note']}" if g.get("note") else "")


def _qs_facts(p: dict[str, Any]) -> str:
    bits = []
    for k in ("segments", "events", "stop_reason"):
        if p.get(k) is not None:
            bits.append(f"{k.replace('_', ' ')} {p[k]}")
    if p.get("final_states"):
        bits.append("final contacts [" + ", ".join(p["final_states"]) + "]")
    if p.get("last_events"):
        bits.append("last events: " + "; ".join(p["last_events"][-2:]))
    if p.get("error") or p.get("path_error"):
        bits.append(str(p.get("error") or p.get("path_error")))
    return "; ".join(bits)


def _flagged(c: dict[str, Any], m: str) -> bool:
    """Listed: a wrong class; for the default answer also no verdict or a magnitude more than
    :data:`WITHIN` apart. The λ* column is not listed (its counts show the change)."""
    if m == "first_limit":
        return False
    if c["verdict"] == "wrong class":
        return True
    return m == "quasistatic" and (
        c["verdict"] == "no verdict" or (c["rel"] is not None and abs(c["rel"]) > WITHIN)
    )


def disagreements(rows: list[dict], methods: list[str]) -> list[str]:
    lines: list[str] = []
    for m in methods:
        if m == "first_limit":
            continue
        items = []
        for r in rows:
            c, p = r["cmp"][m], r["preds"][m]
            if not _flagged(c, m):
                continue
            what = c.get("why", "")
            if c["rel"] is not None:
                what = f"magnitude {100 * c['rel']:+.1f} %"
            text = (
                f"- `{r['case'].key}` ({r['friction']}; {r['case'].grasp}, d = "
                f"[{', '.join(f'{x:.3g}' for x in r['case'].direction)}]): simulated {sim_text(r['sim'])},"
                f" {title(m)} {pred_text(p)} — {what}"
            )
            if m == "quasistatic" and p:
                if r["sim"].get("first_pass"):
                    fp = r["sim"]["first_pass"]
                    text += f" (simulated at upper {r['sim']['upper']:g};"
                    text += f" at {fp['upper']:g}: {fp['status']} {fp['load']})"
                gw = giveway_text(p)
                text += f"; {gw}" if gw else ""
                g = p.get("giveway")
                if g and r["sim"]["status"] != "held":
                    from .validate_quasistatic import path_bounds, trace_load

                    t_, r_ = path_bounds(g)
                    at = trace_load(r["sim"], t_, r_)
                    text += (
                        f"; the simulated ramp moved {1e3 * t_:.3g} mm / {np.degrees(r_):.3g}° at"
                        f" {'—' if at is None else f'{at:.4g}'}"
                    )
                facts = _qs_facts(p)
                text += f"; path: {facts}" if facts else ""
            items.append(text)
        lines += [
            "",
            f"### {title(m)}: {len(items)} {'disagreements' if items else 'disagreements: none'}",
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
            "| direction | simulated | " + " | ".join(f"{title(m)} | diff" for m in methods) + " |",
            "|---|---:|" + "---:|---:|" * len(methods),
        ]
        for r in rs:
            cells = []
            for m in methods:
                c = r["cmp"][m]
                flag = "" if c["verdict"] == SAME else f" **({c['verdict']})**"
                rel = c["rel"]
                cells.append(
                    f"{pred_text(r['preds'][m])}{flag} | {'' if rel is None else f'{100 * rel:+.2f} %'}"
                )
            label = r["case"].label if s == "scenes" else r["case"].key.split("/", 1)[1]
            lines.append(f"| {label} | {sim_text(r['sim'])} | " + " | ".join(cells) + " |")
    return lines


def render(
    rows: list[dict],
    methods: list[str],
    frictions: list[str],
    head: str,
    details: bool = False,
    heads: list[dict] | None = None,
) -> str:
    lines = [
        "## The quasi-static method against the simulation (issue 25)",
        "",
        head,
        "",
        "The quasi-static column is the **default answer itself**, `pg.max_resistible_wrench(model,"
        " command, d, upper=U)` at the simulation record's `upper` U: the load at which the object gives"
        " way by the simulation's thresholds ([`giveway.md`](giveway.md)), no `load_at_displacement` by"
        " hand; λ* (the path's first limit, the answer before the give-way default) beside it."
        " Cells: same class / wrong class / no verdict (of the directions run, where not all were);"
        " finite pairs (both give way, sharply or gradually, not both ≈ 0) within 10 % / all of them ·"
        " |simulated / predicted − 1| median / max. Simulation references:"
        " `scripts/reproduce/data/qs_sim.jsonl`; cases: `scripts/reproduce/qs_cases.py`.",
    ]
    if heads:
        lines += ["", "### Headline", "", *headline_lines(heads)]
    for f in frictions:
        lines += [
            "",
            f"### Simulation with {LABELS[f]} ({reference(f)})",
            "",
            *summary_table(rows, methods, f),
        ]
    speed = [m for m in methods if m != "first_limit"]
    lines += ["", "### Time per direction", "", *speed_table(rows, speed)]
    lines += ["", "### Disagreements (generated)", *disagreements(rows, methods)]
    if details:
        lines += ["", "### Per direction"]
        for f in frictions:
            lines += detail_tables(rows, methods, f)
    return "\n".join(lines) + "\n"
