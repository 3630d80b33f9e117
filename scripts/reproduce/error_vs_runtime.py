"""Error against run time of the max-resistible-wrench query, per method and setting.

For each model (analytic pinch and wedge with closed forms; a seeded random 3D grasp; the
built-in paper scenes when they exist) and each configuration of the exact core (PRP bisection
and direct load-factor search; the iterative scheme with the secant or the bisection, with and
without the subspace jump, other eps and gamma; the reference MIQP backend, SCIP), it times the
direction query on a few directions and compares the magnitudes with a reference (closed form
where known, else the exact core's own finest answer: PRP direct load-factor search; iterative
bisection with 30 steps). Then it times the issue's targets: one PRP solve, an iterative
direction query, a 72-direction profile (in this process and with 2 workers) and 500 directions
over the 6D wrench sphere.

Writes ``docs/error_vs_runtime.md`` (tables) and ``docs/img/error_vs_runtime.png`` (Pareto
plot), copies key rows into README.md between the ``perf`` markers, and prints the same tables.
BLAS runs single-threaded (``OPENBLAS_NUM_THREADS=1`` unless exported otherwise or
``--blas-default``; the public queries limit themselves to one thread anyway, see
``docs/solver_core.md``). Usage::

    python -m scripts.reproduce.error_vs_runtime [--repeat 3] [--quick]
"""

from __future__ import annotations

import os
import sys

if "--blas-default" not in sys.argv:  # before numpy is imported (docs/solver_core.md)
    for _k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(_k, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
from importlib.metadata import version  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import pinograsp as pg  # noqa: E402
from pinograsp import examples  # noqa: E402

from .error_vs_runtime_report import fill_readme, plot, reading, write  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
UPPER = 1e3

#: name -> (method, max_resistible_wrench keyword arguments); every configuration runs the exact
#: branch-and-bound unless it names the reference backend
CONFIGS = {
    "PRP bisection, 10 steps": ("prp", dict(steps=10)),
    "PRP bisection, 20 steps": ("prp", dict(steps=20)),
    "PRP bisection, 30 steps": ("prp", dict(steps=30)),
    "PRP direct (1 load-factor solve)": ("prp", dict(search="direct")),
    "PRP reference MIQP (SCIP), 20 steps": ("prp", dict(steps=20, backend="miqp")),
    "iter. secant, 10 steps": ("iterative", dict(steps=10)),
    "iter. secant, 20 steps (its default search)": ("iterative", dict(steps=20)),
    "iter. secant, 30 steps": ("iterative", dict(steps=30)),
    "iter. bisection, 20 steps": ("iterative", dict(steps=20, search="bisection")),
    "iter. accelerate=False, 20 steps": ("iterative", dict(steps=20, accelerate=False)),
    "iter. secant 20, eps 1e-2": ("iterative", dict(steps=20, eps=1e-2)),
    "iter. secant 20, gamma 0.5": ("iterative", dict(steps=20, gamma=0.5)),
    "iter. secant 20, gamma 2": ("iterative", dict(steps=20, gamma=2.0)),
    "iter. reference MIQP (SCIP), 20 steps": ("iterative", dict(steps=20, backend="miqp")),
}
#: the reference backend's iterative scheme (a SCIP solve per movement step) runs on the pinch only
PINCH_ONLY = {"iter. reference MIQP (SCIP), 20 steps"}
#: slow configurations: one repetition
SLOW = {
    "PRP reference MIQP (SCIP), 20 steps",
    "iter. reference MIQP (SCIP), 20 steps",
    "iter. accelerate=False, 20 steps",
}


def models(quick: bool) -> dict[str, tuple]:
    """name -> (factory, command, directions, closed forms {(method, variant): [values]}, analytic)."""
    pf = ("iterative", "preload-first")
    out = {
        "pinch (2 contacts)": (
            examples.pinch,
            1.0,
            ["fy", [1.0, 1.0, 0, 0, 0, 0], [0.3, -1.0, 0, 0, 0, 0]],
            {
                ("prp", "single-step"): [10.0, 10 * np.sqrt(2), 10.0 * np.sqrt(1.09)],
                pf: [10.0, 10 * np.sqrt(2), 10.0 * np.sqrt(1.09)],
            },
            True,
        ),
        "wedge (2 contacts)": (
            lambda: examples.pinch(h=0.01),
            1.0,
            ["fy"],
            {("prp", "single-step"): [np.inf], pf: [6.0]},
            True,
        ),
        "random 3D (4 contacts)": (
            lambda: examples.random_grasp(3, n_pairs=2, planar=False),
            1.0,
            [[1.0, 0.3, -0.2, 0, 0, 0]],
            {},
            False,
        ),
    }
    if not quick:
        try:
            c30 = [np.cos(np.radians(30)), np.sin(np.radians(30)), 0, 0, 0, 0]
            c135 = [np.cos(np.radians(135)), np.sin(np.radians(135)), 0, 0, 0, 0]
            for name, dirs in (("case1", ["fy", c30, c135]), ("case3", ["-fy", "fy"])):
                sc = pg.load_scene(name)
                out[f"{name} ({sc.model.nc} contacts)"] = (
                    lambda sc=sc: sc.model,
                    sc.command,
                    dirs,
                    {},
                    False,
                )
        except Exception as exc:  # scenes not available
            print(f"(paper scenes skipped: {exc})")
    return out


def run(factory, command, d, method, kw, repeat):
    """Median wall time per direction query and the magnitude (fresh model per repeat: no state
    is shared between queries anyway). A solver failure gives magnitude NaN (reported)."""
    times, mag, note = [], None, ""
    for _ in range(repeat):
        m = factory()
        t0 = time.perf_counter()
        try:
            r = pg.max_resistible_wrench(m, command, d, method, upper=UPPER, **kw)
            mag = r.magnitude
            st = str(getattr(r, "status", ""))
            note = st if st in ("above_limit", "below_resolution") else ""
        except pg.PinograspError as exc:
            print(f"    failed: {type(exc).__name__}: {exc}", flush=True)
            mag, note = float("nan"), f"{type(exc).__name__}: {exc}"
        times.append(time.perf_counter() - t0)
    return statistics.median(times), mag, note


def rel_err(a: float, ref: float) -> float:
    if np.isnan(a) or np.isnan(ref):
        return float("nan")
    if np.isinf(ref) or np.isinf(a):
        return 0.0 if np.isinf(ref) and np.isinf(a) else float("inf")
    return abs(a - ref) / max(abs(ref), 1e-12)


#: failures of reference runs (a NaN reference; listed in the report)
REF_FAILURES: list[str] = []


def reference(factory, command, dirs, method, variant) -> list[float]:
    """The exact core's finest answer of the same method and variant: the PRP's direct
    load-factor search (exact); the iterative scheme with the paper's bisection at 30 steps
    (resolution 1e3 / 2^30 = 9e-7 N), default settings otherwise."""
    if method == "prp":
        kw = dict(search="direct", variant=variant)
    else:
        kw = dict(steps=30, search="bisection", variant=variant)
    out = []
    for d in dirs:
        try:
            out.append(pg.max_resistible_wrench(factory(), command, d, method, upper=UPPER, **kw).magnitude)
        except pg.PinograspError as exc:  # reported in the table, not hidden
            print(f"    reference failed: {type(exc).__name__}: {exc}", flush=True)
            REF_FAILURES.append(f"{method} {kw} along {d}: {type(exc).__name__}: {exc}")
            out.append(float("nan"))
    return out


def error_table(repeat: int, quick: bool) -> tuple[list[dict], str]:
    rows = []
    for mname, (factory, command, dirs, closed, is_analytic) in models(quick).items():
        refs: dict[tuple[str, str], list[float]] = dict(closed)
        for cname, (method, kw) in CONFIGS.items():
            if cname in PINCH_ONLY and not mname.startswith("pinch"):
                continue
            variant = kw.get("variant") or ("single-step" if method == "prp" else "preload-first")
            if (method, variant) not in refs:
                refs[(method, variant)] = reference(factory, command, dirs, method, variant)
            reps = 1 if (cname in SLOW or not is_analytic) else repeat
            ts, errs, mags, notes = [], [], [], []
            for d, ref in zip(dirs, refs[(method, variant)]):
                t, mag, note = run(factory, command, d, method, kw, reps)
                ts.append(t)
                errs.append(rel_err(mag, ref))
                mags.append(mag)
                notes.append(note)
            finite = [e for e in errs if np.isfinite(e)]
            rows.append(
                dict(
                    model=mname,
                    config=cname,
                    method=method,
                    time=statistics.median(ts),
                    err=max(errs) if not any(np.isnan(errs)) else float("nan"),
                    n_dirs=len(dirs),
                    n_class=sum(np.isinf(e) for e in errs),
                    n_failed=sum(np.isnan(e) for e in errs),
                    max_finite=max(finite) if finite else 0.0,
                    mags=mags,
                    refs=list(refs[(method, variant)]),
                    notes=notes,
                )
            )
            print(
                f"  {mname:28s} {cname:38s} {1e3 * rows[-1]['time']:9.1f} ms  err {rows[-1]['err']:.2e}",
                flush=True,
            )
    lines = [
        "| model | configuration | median time per direction [ms] | max relative error |",
        "|---|---|---|---|",
    ]
    for r in rows:
        if r["n_failed"]:
            msgs = [n for n in r["notes"] if n and n not in ("above_limit", "below_resolution")]
            if msgs:
                e = f"solver failure on {len(msgs)} of {r['n_dirs']} directions ({msgs[0]})"
            else:
                e = f"reference failed on {r['n_failed']} of {r['n_dirs']} directions"
        elif r["n_class"]:
            e = "1 (classification differs)"
            if r["n_dirs"] > 1:
                e += f" on {r['n_class']} of {r['n_dirs']} directions; others {r['max_finite']:.1e}"
        else:
            e = f"{r['err']:.1e}"
        for st in ("above_limit", "below_resolution"):
            if st in r["notes"]:
                e += f" ({st} on {r['notes'].count(st)})"
        lines.append(f"| {r['model']} | {r['config']} | {1e3 * r['time']:.1f} | {e} |")
    return rows, "\n".join(lines)


def targets(quick: bool) -> str:
    out = ["| target (issue 4) | measured here | seed paper |", "|---|---|---|"]
    rng = np.random.default_rng(0)
    m8 = examples.random_grasp(0, n_pairs=2, contacts_per_finger=2)  # 8 contacts, Barrett-like fingers
    pg.passive_response(m8, 1.0, [0, 0, 0.5, 0, 0, 0], method="prp")
    ts, walls = [], []
    for _ in range(30):
        w = rng.normal(size=6) * [0.3, 0.3, 0.3, 0.005, 0.005, 0.005]
        t0 = time.perf_counter()
        ts.append(pg.passive_response(m8, 1.0, w, method="prp").solve_time)
        walls.append(time.perf_counter() - t0)
    t_ref = [
        pg.passive_response(
            m8, 1.0, rng.normal(size=6) * [0.3, 0.3, 0.3, 0.005, 0.005, 0.005], method="prp", backend="miqp"
        ).solve_time
        for _ in range(5)
    ]
    out.append(
        f"| single PRP solve ≤ 5 ms (random 8 contacts × 8 edges) | {1e3 * statistics.median(ts):.2f} ms "
        f"solver (p90 {1e3 * float(np.percentile(ts, 90)):.2f} ms; whole call "
        f"{1e3 * statistics.median(walls):.2f} ms); "
        f"reference MIQP {1e3 * statistics.median(t_ref):.0f} ms | 10–100 ms per iteration |"
    )
    try:
        scenes = {n: pg.load_scene(n) for n in ("case1", "case2")}
    except Exception:
        scenes = {}
    for name, sc in scenes.items():
        tq = []
        for d in ("fx", "fy") if name == "case1" else ("fx",):
            t0 = time.perf_counter()
            try:
                pg.max_resistible_wrench(sc.model, sc.command, d, "iterative", upper=UPPER)
            except pg.PinograspError:
                pass  # time to a reported failure still counts
            tq.append(time.perf_counter() - t0)
        out.append(
            f"| iterative direction ≤ 50 ms, {name} ({sc.model.nc} contacts), default settings, "
            f"{'+x, +y' if name == 'case1' else '+x'} "
            f"| {' / '.join(f'{1e3 * t:.0f} ms' for t in tq)} "
            "| tens of seconds (0.01–0.1 s × < 50 iterations × 20 steps) |"
        )
    if "case1" in scenes:
        sc = scenes["case1"]
        for method, kw in (("prp", dict(search="direct")), ("iterative", dict())):
            for workers in (None, 2):
                t0 = time.perf_counter()
                try:
                    prof = pg.resistance_profile(
                        sc.model, sc.command, ("fx", "fy"), n=72, method=method, workers=workers, **kw
                    )
                    what = f"{int(prof.unbounded.sum())} unbounded"
                except pg.PinograspError as exc:
                    what = f"stopped: {type(exc).__name__}"
                dt = time.perf_counter() - t0
                out.append(
                    f"| 72-direction profile ≤ 5 s: case1 XY, {method} {kw or ''}, 72 directions, "
                    f'workers={workers or 1} | {dt:.1f} s ({what}) | "prohibitively time consuming" |'
                )
        nd = 100 if quick else 500
        D = rng.normal(size=(nd, 6))
        D[:, 3:] *= 0.02
        t0 = time.perf_counter()
        mags, failed = [], 0
        for d in D:
            try:
                mags.append(
                    pg.max_resistible_wrench(
                        sc.model, sc.command, d, "prp", upper=UPPER, search="direct"
                    ).magnitude
                )
            except pg.PinograspError:  # a solver failure is reported, not a number
                failed += 1
        dt = time.perf_counter() - t0
        out.append(
            f"| {nd} directions over the 6D wrench sphere ≤ 60 s: case1, PRP direct | {dt:.1f} s "
            f"({int(np.isinf(mags).sum())} unbounded, {failed} solver failures reported) | — |"
        )
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="analytic models only, fewer directions")
    ap.add_argument("--out", default=str(ROOT / "docs" / "error_vs_runtime.md"))
    ap.add_argument("--targets-only", action="store_true", help="keep the report's table, rerun the targets")
    ap.add_argument("--blas-default", action="store_true", help="keep the BLAS library's default threads")
    args = ap.parse_args()
    # only the default report updates docs/img and the README block (a --out elsewhere is a trial)
    official = Path(args.out).resolve() == (ROOT / "docs" / "error_vs_runtime.md").resolve()
    if args.targets_only:
        text = Path(args.out).read_text()
        table = text[
            text.index("## Per configuration") + len("## Per configuration") : text.index("## Targets")
        ]
        head = text.split(". ", 1)[1].split(".\n", 1)[0] if ". " in text else ""
        t0 = time.perf_counter()
        tg = targets(args.quick)
        print(tg)
        read = (
            text[text.index("## Reading it") : text.index("## Per configuration")]
            if "## Reading it" in text
            else ""
        )
        write(args, head, table.strip(), tg, time.perf_counter() - t0, read)
        if official:
            fill_readme(Path(args.out))
        return
    t_start = time.perf_counter()
    head = (
        f"machine: {platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}; "
        + ", ".join(f"{p} {version(p)}" for p in ("pin", "numpy", "daqp", "clarabel", "cvxpy", "pyscipopt"))
        + f"; OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}"
        + f"; load average at start {os.getloadavg()[0]:.2f}"
    )
    print(head)
    rows, table = error_table(args.repeat, args.quick)
    print(table, flush=True)
    img = (ROOT / "docs" if official else Path(args.out).parent) / "img" / "error_vs_runtime.png"
    plot(rows, img, CONFIGS)
    read = reading(rows, CONFIGS, REF_FAILURES)
    print(read)
    write(args, head, table, "(running)", time.perf_counter() - t_start, read)
    tg = targets(args.quick)
    print(tg)
    total = time.perf_counter() - t_start
    write(args, head, table, tg, total, read)
    if official:
        fill_readme(Path(args.out))
    print(f"wrote {args.out}, {img}{' and the README block' if official else ''} in {total:.0f} s")


if __name__ == "__main__":
    main()
