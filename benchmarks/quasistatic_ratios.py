"""Speed of the quasi-static method against the paper's methods (issue 25), in one run.

One run measures, on the same directions and in the same process:

- the quasi-static ``max_resistible_wrench`` (``pg.quasistatic_max_wrench`` when the package has
  it, else ``method="quasistatic"``): median and max ms per direction on the pinch, case 1 and
  case 2 (24 plane directions + named) and on seeded random grasps
  (``random_grasp(seed, n_pairs, contacts_per_finger=2)``, 4-40 contacts, 3 seeds x 3 random 6D
  directions, upper 50); segments and events per direction from ``pg.loading_path``;
- the iterative and energetic methods on the first ``--baseline`` directions of each case
  (upper 50, steps 20, ``max_nodes`` per search ``--cap``, a count so that every query
  terminates; a node limit is counted, its time kept): median ms and the ratio to the
  quasi-static median on the same directions;
- a 500-direction 6D ``pg.resistance_set`` of case 2 with the quasi-static method (one process);
- optionally (``--batch N``) ``pg.evaluate_grasps`` on N sampled Barrett grasps with the
  quasi-static ``WorstAxisScore`` and 2 local workers (issue: 1000 grasps in <= 120 s);
- optionally (``--profile``) where the time goes: the top functions of one 16-contact direction.

Timing: each direction once after one warm-up call per case (the first call imports and
builds); CPU time of this process (``time.process_time``: the shared machine's load does not
inflate it; the baselines and the quasi-static method alike), nothing asserted. The per-method
speed table without baselines is ``benchmarks/quasistatic_speed.py`` (h-qs). Usage::

    nice -n 10 python -m benchmarks.quasistatic_ratios [--baseline 4] [--cap 500]
        [--pairs 1,2,3,4,6,10] [--batch 1000] [--profile] [--out FILE.md]
"""

from __future__ import annotations

import argparse
import cProfile
import io
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


def _qs(model: Any, command: np.ndarray, d: np.ndarray, upper: float) -> Any:
    if hasattr(pg, "quasistatic_max_wrench"):
        return pg.quasistatic_max_wrench(model, command, d)
    return pg.max_resistible_wrench(model, command, d, method="quasistatic", upper=upper)


def speed_cases(pairs: list[int]) -> list[tuple[str, Any, np.ndarray, list[np.ndarray], float]]:
    """``(name, model, command, directions, upper)`` of every case timed."""
    out = []
    for name in ("pinch", "case1", "case2"):
        sc = pg.load_scene(name)
        dirs = [np.asarray(d, float) for d in pg.plane_directions(sc.model, sc.analysis.plane, 24)]
        for dn in sc.analysis.directions:
            d = np.asarray(sc.direction(dn), float)
            if not any(np.allclose(d, e) for e in dirs):
                dirs.append(d)
        out.append(
            (name, sc.model, sc.model.command_vector(sc.preload(None)), dirs, float(sc.analysis.upper))
        )
    for n_pairs in pairs:
        for seed in range(3):
            m = pg.examples.random_grasp(seed, n_pairs, contacts_per_finger=2)
            out.append((f"{4 * n_pairs} contacts", m, np.ones(m.na), random_directions(seed), UPPER))
    return out


def time_qs(model: Any, command: np.ndarray, dirs: list[np.ndarray], upper: float) -> dict[str, Any]:
    _qs(model, command, dirs[0], upper)  # warm-up
    ts, statuses, segs, events = [], [], [], []
    for d in dirs:
        t0 = time.process_time()
        try:
            statuses.append(str(_qs(model, command, d, upper).status))
        except pg.PinograspError as exc:
            statuses.append(type(exc).__name__)
        ts.append(time.process_time() - t0)
        if hasattr(pg, "loading_path"):
            try:
                lp = pg.loading_path(model, command, d)
                segs.append(max(len(lp.loads) - 1, 0))
                events.append(len(lp.events))
            except Exception:  # noqa: BLE001 - a failed path is counted through its status above
                pass
    return {"t": ts, "status": statuses, "segments": segs, "events": events}


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
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--out", help="also write the tables to this markdown file")
    args = ap.parse_args()
    pairs = [int(x) for x in args.pairs.split(",")]
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
            },
        )
        r = time_qs(model, cmd, dirs, upper)
        g["qs"] += r["t"]
        g["status"] += r["status"]
        g["seg"] += r["segments"]
        g["ev"] += r["events"]
        k = args.baseline if name in ("pinch", "case1", "case2") else -(-args.baseline // 3)
        base = dirs[:k]
        g["qs_base"] += r["t"][:k]
        for key, meth in (("it", "iterative"), ("en", "energetic")):
            b = time_method(model, cmd, base, meth, args.cap)
            g[key] += b["t"]
            g[f"{key}_lim"] += b["limited"]
        print(f"{name:12s} qs {_ms(r['t'])} ms", flush=True)
    lines = [
        f"_`benchmarks/quasistatic_ratios.py` (CPU time) on {platform.machine()}, pinograsp {pg.__version__}"
        f" ({Path(pg.__file__).parent}); baselines capped at max_nodes={args.cap} per search._",
        "",
        "| case | contacts | directions | quasi-static median / max [ms CPU] | statuses | segments | events |"
        " iterative median [ms] (node limits) | energetic median [ms] (node limits) |"
        " iterative / qs | energetic / qs |",
        "|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|",
    ]
    for name, g in groups.items():
        st = {s: g["status"].count(s) for s in sorted(set(g["status"]))}
        qb = np.median(g["qs_base"]) if g["qs_base"] else np.nan
        ratio = {k: np.median(g[k]) / qb if g[k] else np.nan for k in ("it", "en")}
        lines.append(
            f"| {name} | {g['nc']} | {len(g['qs'])} | {_ms(g['qs'])} | {st} | {_mm(g['seg'])}"
            f" | {_mm(g['ev'])} |"
            f" {_ms(g['it']).split(' /')[0]} ({g['it_lim']}/{len(g['it'])}) | {_ms(g['en']).split(' /')[0]}"
            f" ({g['en_lim']}/{len(g['en'])}) | {ratio['it']:.3g} | {ratio['en']:.3g} |"
        )
    if args.n_set:
        lines += ["", resistance_set_line(args.n_set)]
    if args.batch:
        lines += ["", batch_line(args.batch)]
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
    t0 = time.process_time()
    try:
        rs = pg.resistance_set(sc.model, cmd, n=n, method="quasistatic", upper=UPPER, workers=1)
        how, fin = "pg.resistance_set", int(np.sum(np.isfinite(np.asarray(rs.magnitudes))))
    except pg.InvalidInputError:
        dirs = pg.sphere_points(n, 6, 0)
        mags = [float(_qs(sc.model, cmd, d, UPPER).magnitude) for d in dirs]
        how, fin = (
            "a loop of quasi-static queries over pg.sphere_points (not yet in resistance_set)",
            int(np.sum(np.isfinite(mags))),
        )
    wall = time.process_time() - t0
    text = f"Case 2, {n} directions on the 6D sphere, quasi-static, one process ({how}):"
    return text + f" {wall:.2f} s, {fin} finite."


def batch_line(n: int) -> str:
    import math

    box = pg.ObjectSpec("box", size=(0.1462, 0.05, 0.10), xyz=(0.0, 0.0, 0.0678))
    grasps = pg.sample_grasps(
        "barrett_bh8_282",
        box,
        n,
        0,
        translation=0.005,
        rotation=math.radians(10),
        q_open={"bh_j11": math.pi / 2},
    )
    score = pg.WorstAxisScore(method="quasistatic")
    t0 = time.perf_counter()  # wall time: the work is in the worker processes
    df = pg.evaluate_grasps(grasps, score=score, workers=2)
    wall = time.perf_counter() - t0
    return (
        f"evaluate_grasps: {n} Barrett grasps, quasi-static WorstAxisScore, 2 local workers: {wall:.1f} s"
        f" ({int((df['status'] == 'ok').sum())} ok)."
    )


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
