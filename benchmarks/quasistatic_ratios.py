"""Speed of the quasi-static method against the paper's methods (issue 25), in one run.

One run measures, on the same directions and in the same process:

- ``pg.max_resistible_wrench(..., method="quasistatic", session=...)``, one session per grasp
  (its preload path solved once, in the warm-up call, reported as "first"): median and max ms
  per direction on the pinch and cases 1-3 (24 plane directions + named) and on seeded random
  grasps (``random_grasp(seed, n_pairs, contacts_per_finger=2)``, 4-40 contacts, 3 seeds x 3
  random 6D directions, upper 50); segments and events (contact and actuator state changes) per
  direction from ``pg.loading_path``;
- the iterative and energetic methods on the first ``--baseline`` directions of each case
  (upper 50, steps 20, ``max_nodes`` per search ``--cap``, a count so that every query
  terminates; a node limit is counted, its time kept): median ms and the ratio to the
  quasi-static median on the same directions;
- a 500-direction 6D ``pg.resistance_set`` of case 2 with the quasi-static method (one process);
- optionally (``--batch N``) ``pg.evaluate_grasps`` on N sampled Barrett grasps, 26 quasi-static
  directions each, 2 local workers (``benchmarks/quasistatic_batch.py``; issue: 1000 grasps in
  <= 120 s);
- optionally (``--split``) where the time goes per direction (pinch, case 2, 16 contacts): the
  path's segments (rate problems: linear part, LCP, segment record; classification and events),
  the path record and its audit, the response record, the preload check and the rest (query,
  session, validation);
- optionally (``--profile``) the top functions of one 16-contact direction (cProfile).

Timing: each direction once after one warm-up call per case (the first call imports and
builds); CPU time of this process (``time.process_time``: the shared machine's load does not
inflate it; the baselines and the quasi-static method alike), nothing asserted. The per-method
speed table without baselines is ``benchmarks/quasistatic_speed.py`` (h-qs). Usage::

    nice -n 10 python -m benchmarks.quasistatic_ratios [--baseline 4] [--cap 500]
        [--pairs 1,2,3,4,6,10] [--repeat 1] [--split] [--batch 1000] [--profile] [--out FILE.md]
"""

from __future__ import annotations

import argparse
import collections
import cProfile
import io
import os
import platform
import pstats
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import pinograsp as pg
from scripts.reproduce.qs_cases import random_directions

UPPER = 50.0


def _qs(model: Any, command: np.ndarray, d: np.ndarray, upper: float, session: Any = None) -> Any:
    return pg.max_resistible_wrench(model, command, d, method="quasistatic", upper=upper, session=session)


def scene_directions(sc: Any) -> list[np.ndarray]:
    """A built-in scene's 24 directions in its plane and its named ones not among them."""
    dirs = [np.asarray(d, float) for d in pg.plane_directions(sc.model, sc.analysis.plane, 24)]
    for dn in sc.analysis.directions:
        d = np.asarray(sc.direction(dn), float)
        if not any(np.allclose(d, e) for e in dirs):
            dirs.append(d)
    return dirs


def speed_cases(pairs: list[int]) -> list[tuple[str, Any, np.ndarray, list[np.ndarray], float]]:
    """``(name, model, command, directions, upper)`` of every case timed."""
    out = []
    for name in ("pinch", "case1", "case2", "case3"):
        sc = pg.load_scene(name)
        dirs = scene_directions(sc)
        out.append(
            (name, sc.model, sc.model.command_vector(sc.preload(None)), dirs, float(sc.analysis.upper))
        )
    for n_pairs in pairs:
        for seed in range(3):
            m = pg.examples.random_grasp(seed, n_pairs, contacts_per_finger=2)
            out.append((f"{4 * n_pairs} contacts", m, np.ones(m.na), random_directions(seed), UPPER))
    return out


def time_qs(
    model: Any, command: np.ndarray, dirs: list[np.ndarray], upper: float, repeat: int = 1
) -> dict[str, Any]:
    session = pg.Session(model)
    t0 = time.process_time()
    _qs(model, command, dirs[0], upper, session)  # warm-up: the preload path, once per session
    first = time.process_time() - t0
    ts, statuses, segs, events = [], [], [], []
    for d in dirs:
        best = float("inf")
        for _ in range(repeat):  # the fastest of ``repeat`` runs: the least disturbed by other load
            t0 = time.process_time()
            try:
                status = str(_qs(model, command, d, upper, session).status)
            except pg.PinograspError as exc:
                status = type(exc).__name__
            best = min(best, time.process_time() - t0)
        statuses.append(status)
        ts.append(best)
        if hasattr(pg, "loading_path"):
            try:
                lp = pg.loading_path(model, command, d)
                segs.append(lp.segments)
                events.append(sum(e.kind in ("contact", "actuator") for e in lp.events))
            except Exception:  # noqa: BLE001 - a failed path is counted through its status above
                pass
    return {"t": ts, "status": statuses, "segments": segs, "events": events, "first": first}


def time_method(
    model: Any, command: np.ndarray, dirs: list[np.ndarray], method: str, cap: int
) -> dict[str, Any]:
    ts, limited = [], 0
    for d in dirs:
        t0 = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                pg.max_resistible_wrench(
                    model, command, d, method=method, upper=UPPER, steps=20, max_nodes=cap
                )
            except pg.SolverError:
                limited += 1
        ts.append(time.process_time() - t0)
    return {"t": ts, "limited": limited}


def _ms(ts: list[float]) -> str:
    return f"{1e3 * np.median(ts):.3g} / {1e3 * np.max(ts):.3g}" if ts else "—"


def _mm(xs: list[int]) -> str:
    return f"{int(np.median(xs))} ({min(xs)}–{max(xs)})" if xs else "—"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--pairs", default="1,2,3,4,6,10", help="n_pairs of the random grasps (4 n_pairs contacts)"
    )
    ap.add_argument("--baseline", type=int, default=4, help="directions per case for the iterative/energetic")
    ap.add_argument("--cap", type=int, default=500, help="max_nodes per search of the iterative/energetic")
    ap.add_argument(
        "--n-set", type=int, default=500, help="directions of the case-2 resistance set (0: skip)"
    )
    ap.add_argument("--batch", type=int, default=0, help="Barrett grasps for evaluate_grasps (0: skip)")
    ap.add_argument("--split", action="store_true", help="where the time goes per direction")
    ap.add_argument(
        "--repeat",
        type=int,
        default=1,
        help="quasi-static: time each direction this many times, keep the fastest",
    )
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--out", help="also write the tables to this markdown file")
    args = ap.parse_args()
    pairs = [int(x) for x in args.pairs.split(",")]
    load0 = os.getloadavg()
    groups: dict[str, dict[str, list]] = {}
    for name, model, cmd, dirs, upper in speed_cases(pairs):
        g = groups.setdefault(
            name,
            {
                "qs": [],
                "qs_base": [],
                "status": [],
                "seg": [],
                "ev": [],
                "it": [],
                "en": [],
                "it_lim": 0,
                "en_lim": 0,
                "nc": model.nc,
                "first": [],
            },
        )
        r = time_qs(model, cmd, dirs, upper, args.repeat)
        g["qs"] += r["t"]
        g["status"] += r["status"]
        g["seg"] += r["segments"]
        g["ev"] += r["events"]
        g["first"].append(r["first"])
        k = args.baseline if name in ("pinch", "case1", "case2", "case3") else -(-args.baseline // 3)
        base = dirs[:k]
        g["qs_base"] += r["t"][:k]
        for key, meth in (("it", "iterative"), ("en", "energetic")):
            b = time_method(model, cmd, base, meth, args.cap)
            g[key] += b["t"]
            g[f"{key}_lim"] += b["limited"]
        print(f"{name:12s} qs {_ms(r['t'])} ms", flush=True)
    lines = [
        f"_`benchmarks/quasistatic_ratios.py` (CPU time) on {platform.machine()}, pinograsp {pg.__version__}"
        f" ({Path(pg.__file__).parent}); baselines capped at max_nodes={args.cap} per search;"
        f" load average {load0[0]:.2f} at the start, {os.getloadavg()[0]:.2f} at the end"
        f" ({os.cpu_count()} CPUs); quasi-static times the fastest of {args.repeat} run(s) per direction._",
        "",
        "| case | contacts | directions | quasi-static median / max [ms CPU] | first (preload path) [ms] |"
        " statuses | segments | events |"
        " iterative median [ms] (node limits) | energetic median [ms] (node limits) |"
        " iterative / qs | energetic / qs |",
        "|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|",
    ]
    for name, g in groups.items():
        st = {s: g["status"].count(s) for s in sorted(set(g["status"]))}
        qb = np.median(g["qs_base"]) if g["qs_base"] else np.nan
        ratio = {k: np.median(g[k]) / qb if g[k] else np.nan for k in ("it", "en")}
        lines.append(
            f"| {name} | {g['nc']} | {len(g['qs'])} | {_ms(g['qs'])} | {1e3 * np.median(g['first']):.3g} |"
            f" {st} | {_mm(g['seg'])}"
            f" | {_mm(g['ev'])} |"
            f" {_ms(g['it']).split(' /')[0]} ({g['it_lim']}/{len(g['it'])}) | {_ms(g['en']).split(' /')[0]}"
            f" ({g['en_lim']}/{len(g['en'])}) | {ratio['it']:.3g} | {ratio['en']:.3g} |"
        )
    if args.n_set:
        lines += ["", resistance_set_line(args.n_set)]
    if args.batch:
        lines += ["", batch_line(args.batch)]
    if args.split:
        lines += ["", *split_table()]
    if args.profile:
        lines += [
            "",
            "Where the time goes (16 contacts, seed 0, direction 0, cumulative):",
            "",
            "```",
            profile(),
            "```",
        ]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        Path(args.out).write_text(text)


def resistance_set_line(n: int) -> str:
    """``pg.resistance_set`` of case 2 with the quasi-static method (or, while the method is not
    in the registry, the same sphere directions one by one through the quasi-static entry)."""
    sc = pg.load_scene("case2")
    cmd = sc.model.command_vector(sc.preload(None))
    out = []
    for workers in (1, 2):
        t0, c0 = time.perf_counter(), time.process_time()
        rs = pg.resistance_set(sc.model, cmd, n=n, method="quasistatic", upper=UPPER, workers=workers)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        mags = np.asarray(rs.magnitudes, float)
        out.append(
            f"{workers} worker{'s' if workers > 1 else ''}: {wall:.2f} s wall"
            + (f" ({cpu:.2f} s CPU)" if workers == 1 else "")
            + f", {int(np.sum(np.isfinite(mags)))} finite, {int(np.sum(np.isinf(mags)))} unbounded"
        )
    return (
        f"`pg.resistance_set` of case 2, {n} directions on the 6D sphere, quasi-static: "
        + "; ".join(out)
        + "."
    )


def batch_line(n: int) -> str:
    from benchmarks.quasistatic_batch import CubeScore, grasps

    t0 = time.perf_counter()  # wall time: the work is in the worker processes
    df = pg.evaluate_grasps(grasps(n, 0), score=CubeScore(), workers=2)
    wall = time.perf_counter() - t0
    return (
        f"evaluate_grasps: {n} Barrett grasps x 26 quasi-static directions, 2 local workers: {wall:.1f} s"
        f" ({int((df['status'] == 'ok').sum())} ok; `benchmarks/quasistatic_batch.py` splits the time)."
    )


#: What ``--split`` times: (module, function, label); nested entries are inside the ones above.
SPLIT = (
    ("pinograsp.analysis.quasistatic.api", "follow", "path: segments (all)"),
    ("pinograsp.analysis.quasistatic.rates", "linear_part", "- rate problem: linear part (reduced Cholesky)"),
    (
        "pinograsp.analysis.quasistatic.rates",
        "_solve_lcp",
        "- rate problem: LCP (pivoting, Lemke, canonical)",
    ),
    ("pinograsp.analysis.quasistatic.rates", "_segment", "- rate problem: segment record"),
    ("pinograsp.analysis.quasistatic.rates", "_check_guesses", "- rate problem: zero-force guesses"),
    ("pinograsp.analysis.quasistatic.path", "classify", "- classification of each breakpoint"),
    ("pinograsp.analysis.quasistatic.path", "next_event", "- next event (closed form)"),
    ("pinograsp.analysis.quasistatic.api", "build_path", "path record (arrays, audit, events)"),
    ("pinograsp.analysis.quasistatic.answers", "response_at", "response record at the limit"),
    ("pinograsp.analysis.max_wrench", "check_preload", "preload check (kept zero-load response)"),
)


def split_table() -> list[str]:
    """Where the time goes per direction (wall time of each part, patched timers; the rest is
    the query, session and validation plumbing)."""
    import importlib

    acc: collections.Counter[str] = collections.Counter()
    saved = []
    for mod_name, fn, label in SPLIT:
        mod = importlib.import_module(mod_name)
        orig = getattr(mod, fn)
        saved.append((mod, fn, orig))

        def timed(*a: Any, _f: Any = orig, _l: str = label, **k: Any) -> Any:
            t0 = time.perf_counter()
            try:
                return _f(*a, **k)
            finally:
                acc[_l] += time.perf_counter() - t0

        setattr(mod, fn, timed)
    rows = {}
    try:
        for name, model, cmd, dirs, upper in speed_cases([4]):
            if name not in ("pinch", "case2", "16 contacts") or (name in rows and name != "16 contacts"):
                continue
            session = pg.Session(model)
            _qs(model, cmd, dirs[0], upper, session)
            acc.clear()
            t0 = time.perf_counter()
            for d in dirs:
                _qs(model, cmd, d, upper, session)
            total = time.perf_counter() - t0
            prev = rows.get(name, (collections.Counter(), 0.0, 0))
            rows[name] = (prev[0] + acc, prev[1] + total, prev[2] + len(dirs))
    finally:
        for mod, fn, orig in saved:
            setattr(mod, fn, orig)
    names = list(rows)
    out = [
        "Where the time goes [ms per direction, wall, timers in place] (pinch, case 2, 16 contacts):",
        "",
        "| part | " + " | ".join(names) + " |",
        "|---|" + "---:|" * len(names),
    ]
    loop = {
        n: rows[n][0]["path: segments (all)"]
        - sum(rows[n][0][lb] for _, _, lb in SPLIT if lb.startswith("-"))
        for n in names
    }
    for k, (_, _, label) in enumerate(SPLIT):
        out.append(
            f"| {label} | " + " | ".join(f"{1e3 * rows[n][0][label] / rows[n][2]:.3f}" for n in names) + " |"
        )
        if label.startswith("-") and not SPLIT[k + 1][2].startswith("-"):
            out.append(
                "| - rest of the segment loop (plans, hints, steps) | "
                + " | ".join(f"{1e3 * loop[n] / rows[n][2]:.3f}" for n in names)
                + " |"
            )
    rest = [rows[n][1] - sum(rows[n][0][lb] for _, _, lb in SPLIT if not lb.startswith("-")) for n in names]
    out.append(
        "| rest (query, session, validation) | "
        + " | ".join(f"{1e3 * r / rows[n][2]:.3f}" for r, n in zip(rest, names))
        + " |"
    )
    out.append("| total | " + " | ".join(f"{1e3 * rows[n][1] / rows[n][2]:.3f}" for n in names) + " |")
    return out


def profile() -> str:
    m = pg.examples.random_grasp(0, 4, contacts_per_finger=2)
    d = random_directions(0)[0]
    _qs(m, np.ones(m.na), d, UPPER)
    pr = cProfile.Profile()
    pr.enable()
    for _ in range(5):
        _qs(m, np.ones(m.na), d, UPPER)
    pr.disable()
    s = io.StringIO()
    pstats.Stats(pr, stream=s).sort_stats("cumulative").print_stats(15)
    return "\n".join(s.getvalue().splitlines()[:40])


if __name__ == "__main__":
    main()
