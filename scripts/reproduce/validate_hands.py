"""Built-in hands against the simulation: every method vs ``pg.simulate_max_wrench``.

For each built-in hand scene (``allegro_left``, ``ezgripper``, ``hey5``, ``ability``, ``dex3``,
``talos_gripper``): 24 directions in the scene's plane (``analysis.plane``, every 15°, which
holds its named directions into the palm, pull out and sideways), one simulation each (the
defaults of docs/simulation.md) and the prediction of each method (``scene.max_resistible_wrench``
with the scene's settings; energetic capped at ``max_nodes=ENERGETIC_NODES``, a node limit being
no verdict). The paper's methods were run on the 12 directions at multiples of 30° only (the
iterative method takes up to ~24 s per direction on the Allegro): ``--extend`` simulates the
directions of ``-n`` that a hand's cache lacks and marks the paper methods "not run" there, keeping
the cached rows; the report counts each method over the directions it was run on. The
quasi-static prediction (``method="quasistatic"``, milliseconds per direction) is not cached:
the report computes it live against the cached simulations, so it always shows the code
it runs with; a limit λ* above the scene's ``upper`` counts as "held up to upper" (the
simulation tests no further). Classes and differences as ``scripts/reproduce/validate_mujoco.py``
(whose comparison and tables this script reuses). Results are cached per hand in
``scripts/reproduce/validate_hands/`` so that the report can be rewritten without solving
again; the report replaces the section between ``<!-- hands:begin -->`` and
``<!-- hands:end -->`` of ``docs/validation.md``.

Usage (2 cores shared: run it niced)::

    nice python scripts/reproduce/validate_hands.py [--hands ezgripper,dex3] [-n 24]
    nice python scripts/reproduce/validate_hands.py --extend -n 24   # simulate only what the cache lacks
    python scripts/reproduce/validate_hands.py --report     # from the cache only
"""

from __future__ import annotations

import argparse
import datetime
import importlib.util
import json
import platform
import time
import warnings
from pathlib import Path

import numpy as np

import pinograsp as pg

ROOT = Path(__file__).resolve().parents[2]
CACHE = Path(__file__).resolve().parent / "validate_hands"
DOC = ROOT / "docs" / "validation.md"
HANDS = ("allegro_left", "ezgripper", "hey5", "ability", "dex3", "talos_gripper")
#: Node limit of each energetic prediction (a count, so that a query is capped without a clock).
ENERGETIC_NODES = 2000
BEGIN, END = "<!-- hands:begin -->", "<!-- hands:end -->"


def _validate_mujoco():  # type: ignore[no-untyped-def]
    """benchmarks/validate_mujoco.py as a module (its comparison, summaries and tables)."""
    path = ROOT / "scripts" / "reproduce" / "validate_mujoco.py"
    spec = importlib.util.spec_from_file_location("validate_mujoco", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.ENERGETIC_NODES = ENERGETIC_NODES
    return module


VM = _validate_mujoco()


def _predict(scene: object, d: np.ndarray, method: str) -> dict:
    """The validate_mujoco prediction, with any pinograsp error recorded as a status."""
    t0 = time.perf_counter()
    try:
        return VM._predict(scene, d, method)
    except pg.PinograspError as exc:
        return {"status": type(exc).__name__, "magnitude": float("nan"), "upper": 0.0, "wedging": False,
                "wedge_from": None, "t": time.perf_counter() - t0, "error": str(exc)[:300]}  # fmt: skip


#: The method computed live in the report (not cached), shown first.
LIVE = "quasistatic"


#: The old answer λ* (the path's first limit) beside the default, as a column of its own.
FIRST = "first_limit"
#: A finite pair agrees when |simulated / predicted − 1| is at most this.
WITHIN = 0.10


def _predict_live(scene: object, d: np.ndarray) -> dict:
    """The default answer itself, ``scene.max_resistible_wrench(d)`` (the give-way load at the
    scene's ``upper``, docs/giveway.md), as a cached method's record with its give-way record; a
    finite load above ``upper`` is ``"above_limit"`` (the simulation is not asked beyond it)."""
    t0 = time.perf_counter()
    upper = float(scene.analysis.upper)  # type: ignore[attr-defined]
    try:
        mw = scene.max_resistible_wrench(d)  # type: ignore[attr-defined]
    except pg.PinograspError as exc:
        return {"status": type(exc).__name__, "magnitude": float("nan"), "upper": upper, "wedging": False,
                "wedge_from": None, "t": time.perf_counter() - t0, "error": str(exc)[:300]}  # fmt: skip
    pred = {"status": str(mw.status), "magnitude": float(mw.magnitude), "upper": upper, "wedging": False,
            "wedge_from": None, "t": time.perf_counter() - t0, "method": str(mw.method)}  # fmt: skip
    if pred["status"] == "finite" and pred["magnitude"] > upper:
        pred["status"] = "above_limit"
    if mw.giveway is not None:
        pred["giveway"] = mw.giveway.to_dict()
    return pred


def _first_pred(pred: dict) -> dict:
    """λ* of a live record (``giveway.first_limit``) as a prediction record of its own."""
    g = pred.get("giveway") or {}
    lam, st = g.get("first_limit"), g.get("first_status", pred["status"])
    out = {**{k: pred[k] for k in ("upper", "wedging", "wedge_from", "t")}, "status": st}
    if st == "unbounded" or lam is None:
        out.update(status="unbounded", magnitude=float("inf"))
    else:
        out["magnitude"] = float(lam)
        if st == "finite" and lam > out["upper"]:
            out["status"] = "above_limit"
    return out


def _matches(label: str, row: dict) -> bool:
    """Whether a cached row is the direction ``label`` (its label, or its label and a name)."""
    return row["direction"] == label or row["direction"].startswith(label + " (")


def add_live(name: str, rows: list[dict], n: int = 12) -> list[dict]:
    """``rows`` (cached) with the live default answer and its λ* on each row, each with its verdict
    against the cached simulation (``VM._compare``: no rescue, the answer itself) (the rows are
    the directions of :func:`run_hand`, in order)."""
    scene = pg.load_scene(name)
    dirs = VM._directions(scene, n)
    if len(dirs) != len(rows) or any(not _matches(lab, r) for (lab, _), r in zip(dirs, rows)):
        raise ValueError(f"{name}: the cached directions do not match -n {n}; rerun the hand")
    out = []
    for (_, d), row in zip(dirs, rows):
        pred = _predict_live(scene, d)
        first = _first_pred(pred)
        for p in (pred, first):
            p["verdict"], p["rel"] = VM._compare(p, row["sim"])
        out.append({**row, LIVE: pred, FIRST: first})
    return out


_PRED_TEXT = VM._pred_text


def _pred_text(p: dict) -> str:
    """A prediction's cell ("not run" where the method was not run in that direction)."""
    return "not run" if p.get("verdict") == "not run" else _PRED_TEXT(p)


VM._pred_text = _pred_text


def _named_label(scene: object, label: str, d: np.ndarray) -> str:
    """A direction's label with the scene's name for it, if it has one."""
    for key, named in scene.analysis.directions.items():  # type: ignore[attr-defined]
        if np.allclose(named, d) and key not in label:
            label = f"{label} ({key})"
    return label


#: A paper method's cell in a direction added by ``--extend`` (simulated, not predicted).
NOT_RUN = {"status": "not_run", "magnitude": float("nan"), "upper": 0.0, "wedging": False, "wedge_from": None,
           "t": 0.0, "verdict": "not run", "rel": None}  # fmt: skip


def extend_hand(name: str, n: int, rows: list[dict]) -> list[dict]:
    """The cached ``rows`` with the directions of ``-n n`` they lack, in the order of
    :func:`run_hand`: the new ones simulated only, the paper methods marked "not run" (they
    cost seconds to minutes per direction; the quasi-static column is live). The cached rows
    are kept as they are."""
    scene = pg.load_scene(name)
    out = []
    for label, d in VM._directions(scene, n):
        old = [r for r in rows if _matches(label, r)]
        if old:
            out.append(old[0])
            continue
        row = {"direction": _named_label(scene, label, d), "sim": VM._simulate(scene, d)}
        row.update({m: dict(NOT_RUN) for m in VM.METHODS})
        out.append(row)
        print(
            f"{name} {row['direction']:28s} sim {VM._sim_text(row['sim'])} ({row['sim']['t']:.2f} s)",
            flush=True,
        )
    if sum(any(r is o for o in out) for r in rows) != len(rows):
        raise ValueError(f"{name}: cached directions that are not among -n {n}; rerun the hand")
    return out


def run_hand(name: str, n: int) -> list[dict]:
    """One row per direction: the simulation and each method's prediction and verdict."""
    scene = pg.load_scene(name)
    rows = []
    for label, d in VM._directions(scene, n):
        label = _named_label(scene, label, d)
        row = {"direction": label, "sim": VM._simulate(scene, d)}
        for m in VM.METHODS:
            pred = _predict(scene, d, m)
            if pred["status"] not in ("node_limit", "failed", "timeout") and "error" in pred:
                pred["verdict"], pred["rel"] = "no verdict", None
            else:
                pred["verdict"], pred["rel"] = VM._compare(pred, row["sim"])
            row[m] = pred
        rows.append(row)
        print(f"{name} {label:28s} sim {VM._sim_text(row['sim'])} ({row['sim']['t']:.2f} s)  "
              + "  ".join(f"{m} {VM._pred_text(row[m])} ({row[m]['t']:.2f} s) {row[m]['verdict']}"
                          for m in VM.METHODS), flush=True)  # fmt: skip
    return rows


def _facts(name: str) -> str:
    """Contacts, joints, actuators, couplings and the preload of a hand's scene."""
    s = pg.load_scene(name)
    m = s.model
    cmd = ", ".join(f"{k} {v:.3g}" for k, v in s.command.items() if v)
    return f"{m.nc} contacts, {m.nq} joints, {m.na} actuators, {m.ncp} couplings; preload {cmd}"


def report(results: dict[str, list[dict]], meta: dict[str, dict]) -> list[str]:
    """The markdown section: summary per hand and method, one table per hand, disagreements
    (the live quasi-static column first: ``VM.METHODS`` is this script's own copy)."""
    if LIVE not in VM.METHODS:
        VM.METHODS = (LIVE, FIRST, *VM.METHODS)
    summaries = summarize_all(results)
    when = ", ".join(f"{k} {v['date']} ({v['elapsed']:.0f} s{_extended(v)})" for k, v in meta.items())
    n = {len(rows) for rows in results.values()}
    ran = {sum(r["iterative"]["verdict"] != "not run" for r in rows) for rows in results.values()}
    lines = [
        BEGIN,
        "",
        "## Built-in hands",
        "",
        f"_Generated by `nice python scripts/reproduce/validate_hands.py` ({when}; {meta_machine(meta)})._"
        " Each hand's built-in scene (`pg.load_scene(name)`, pictures in `docs/img/hands/`),"
        f" {'/'.join(map(str, sorted(n)))} directions in its plane (every {360 // max(n)}°), which holds its"
        " named directions (into the palm, pull out, sideways); the simulation and the quasi-static method"
        f" in all of them, the paper's methods in the {'/'.join(map(str, sorted(ran)))} at multiples of"
        f' {360 // max(ran)}° ("not run" in the others, which were simulated only: `--extend`), so their'
        " counts are over those. Same"
        f" procedure and classes as above; energetic capped at `max_nodes={ENERGETIC_NODES}` (a node limit,"
        " or a solver failure, is no verdict). The quasi-static column is the default answer itself,"
        " `scene.max_resistible_wrench(d)` (the load at which the object gives way by the simulation's"
        " thresholds at the scene's `upper`, [`giveway.md`](giveway.md); no `load_at_displacement` by hand),"
        f" computed live when the report is written ({_live_stamp()}) against the cached simulations"
        " (the default circular cone, `pg.simulate_max_wrench(scene, d)`); a load above `upper` counts as"
        " held. Column `first_limit`: the path's first limit λ*, the answer before the give-way default."
        " Why the methods disagree, and which to trust:"
        " [`hands.md`](hands.md#when-the-methods-disagree).",
        "",
    ]
    lines += [f"- {name}: {_facts(name)}" for name in results]
    lines += ["", *VM._summary_table(summaries), ""]
    lines += [f"- {VM.summary_line(s)}" for s in summaries]
    lines += ["", "Default answer and λ* in short:", "", *qs_table(results)]
    for name, rows in results.items():
        lines += [line.replace("## ", "### ", 1) for line in _scene_table(name, rows)]
    lines += [line.replace("## Class", "### Built-in hands: class", 1) for line in VM._disagreements(results)]
    lines += ["", "### Built-in hands: every disagreement of the default answer (generated)", ""]
    lines += qs_disagreements(results) or ["None."]
    return [*lines, "", END]


def _scene_table(name: str, rows: list[dict]) -> list[str]:
    """``VM._scene_table``; a method not run in a direction has no class to differ there."""
    return [line.replace("not run **(class differs)**", "not run") for line in VM._scene_table(name, rows)]


def _extended(meta: dict) -> str:
    """The time of the directions a hand's cache was extended with (simulated only), if any."""
    ext = meta.get("extended")
    return (
        ""
        if not ext
        else f"; {len(ext['simulated only'])} simulated only {ext['date']}, {ext['elapsed']:.0f} s"
    )


def summarize_all(results: dict[str, list[dict]]) -> list[dict]:
    """``VM.summarize`` per hand and method over the directions the method was run on."""
    return [
        VM.summarize(name, m, [r for r in rows if r[m]["verdict"] != "not run"])
        for name, rows in results.items()
        for m in VM.METHODS
    ]


def qs_counts(rows: list[dict], m: str) -> dict:
    """Same class, finite pairs (both give way, not both ≈ 0), those within :data:`WITHIN`,
    median |rel| of one column over ``rows``."""
    same = ("both hold", "both give way", "both ≈ 0")
    rel = np.abs(
        [r[m]["rel"] for r in rows if r[m]["verdict"] == "both give way" and r[m]["rel"] is not None]
    )
    return {
        "directions": len(rows),
        "same": sum(r[m]["verdict"] in same for r in rows),
        "finite": int(rel.size),
        "within": int(np.sum(rel <= WITHIN)),
        "median": float(np.median(rel)) if rel.size else None,
    }


def qs_table(results: dict[str, list[dict]]) -> list[str]:
    """Per hand and over all: the default answer and λ* side by side."""
    lines = [
        "| hand | directions | default: same class | default: within 10 % / finite"
        " | default: median \\|diff\\|"
        " | λ*: same class | λ*: within 10 % / finite | λ*: median \\|diff\\| |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    every = [r for rows in results.values() for r in rows]
    for name, rows in [*results.items(), ("**all**", every)]:
        cells = []
        for m in (LIVE, FIRST):
            c = qs_counts(rows, m)
            cells += [f"{c['same']}", f"{c['within']} / {c['finite']}", VM._pct(c["median"])]
        lines.append(f"| {name} | {len(rows)} | " + " | ".join(cells) + " |")
    return lines


def qs_disagreements(results: dict[str, list[dict]]) -> list[str]:
    """Every direction where the default answer's class differs or its load is more than
    :data:`WITHIN` from the simulated one, with its give-way record."""
    out = []
    for name, rows in results.items():
        for r in rows:
            p = r[LIVE]
            bad = p["verdict"] in ("predicted holds", "simulation holds", "no verdict")
            if not (bad or (p["rel"] is not None and abs(p["rel"]) > WITHIN)):
                continue
            what = p["verdict"] if bad else f"{100 * p['rel']:+.1f} %"
            g = p.get("giveway") or {}
            text = (
                f"- {name} {r['direction']}: simulated {VM._sim_text(r['sim'])}, default {VM._pred_text(p)}"
                f" (λ* {VM._pred_text(r[FIRST])}) — {what}"
            )
            if g:
                snaps = ", ".join(f"{a:.4g}→{b:.4g}" for a, b in g["snaps"]) or "none"
                text += (
                    f"; reason {g['reason']}, snaps survived {snaps}, at the give-way"
                    f" {1e3 * g['translation']:.3g} mm / {np.degrees(g['turned']):.3g}° (thresholds"
                    f" {1e3 * g['slip']:.3g} mm / {np.degrees(g['rotation']):.3g}°)"
                )
            out.append(text)
    return out


def _live_stamp() -> str:
    """Date and code of the live column."""
    return f"{datetime.date.today()}, pinograsp {pg.__version__} at {_commit()}"


def _commit() -> str:
    """The checkout's commit (short), or "unknown"."""
    import subprocess

    try:
        out = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                             text=True, check=True)  # fmt: skip
        return out.stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def meta_machine(meta: dict[str, dict]) -> str:
    """Machine and, where recorded, the code the cached results were computed with."""
    keys = sorted({v["machine"] for v in meta.values()} | {v["code"] for v in meta.values() if "code" in v})
    return "; ".join(keys)


def write_doc(lines: list[str]) -> None:
    text = DOC.read_text()
    block = "\n".join(lines) + "\n"
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        text = head + block + rest.split(END, 1)[1].lstrip("\n")
    else:
        text = text.rstrip("\n") + "\n\n" + block
    DOC.write_text(text)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--hands", default=",".join(HANDS))
    ap.add_argument("-n", type=int, default=24, help="directions in each hand's plane (default 24)")
    ap.add_argument("--report", action="store_true", help="only rewrite the report from the cache")
    ap.add_argument("--extend", action="store_true",
                    help="simulate only the directions of -n missing from each hand's cache (the paper"
                    " methods marked 'not run'), keeping the cached rows")  # fmt: skip
    args = ap.parse_args()
    CACHE.mkdir(parents=True, exist_ok=True)
    warnings.simplefilter("ignore")
    if not args.report:
        for name in args.hands.split(","):
            t0 = time.perf_counter()
            machine = f"{platform.machine()}, pinograsp {pg.__version__}"
            now = {"date": str(datetime.date.today()), "machine": machine}
            if args.extend:
                data = json.loads((CACHE / f"{name}.json").read_text())
                rows, meta = extend_hand(name, args.n, data["rows"]), data["meta"]
                added = [r["direction"] for r in rows if r["iterative"]["verdict"] == "not run"]
                meta["n"] = args.n
                elapsed, code = time.perf_counter() - t0, f"pinograsp at {_commit()}"
                meta["extended"] = {**now, "elapsed": elapsed, "code": code, "simulated only": added}
            else:
                rows = run_hand(name, args.n)
                meta = {**now, "elapsed": time.perf_counter() - t0, "n": args.n}
            (CACHE / f"{name}.json").write_text(
                json.dumps({"meta": meta, "rows": rows}, indent=1, default=float)
            )
    results, meta = {}, {}
    for name in HANDS:
        f = CACHE / f"{name}.json"
        if f.is_file():
            data = json.loads(f.read_text())
            n = data["meta"].get("n", 12)
            results[name], meta[name] = add_live(name, data["rows"], n), data["meta"]
    write_doc(report(results, meta))
    for s in summarize_all(results):
        print(VM.summary_line(s))


if __name__ == "__main__":
    main()
