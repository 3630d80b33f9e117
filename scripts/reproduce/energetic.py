"""The energetic (maximum-dissipation) method against the iterative scheme, and cone refinement.

Measures in one run, on this machine, with ``upper = 50``:

1. the time per direction (median, p90) of ``pg.max_resistible_wrench`` with
   ``method="iterative"`` (default search: secant) and ``method="energetic"`` (one load-factor
   solve) on the built-in scenes case1, case2 and case3, ``n`` directions of the XY force
   plane each (case3 also at 255° and 285°, where docs/validation.md reports the iterative
   scheme's stall), and the ratio of the medians;
2. their verdicts: status (finite / unbounded / above_limit / below_resolution, or the
   energetic branch-and-bound's ``node_limit``) and the relative difference of finite
   magnitudes; the iterative scheme is re-run with a tight equilibrium tolerance
   (``eps=1e-6, eps_rel=1e-9``) to tell its tolerance from a real difference;
3. accuracy against the finest refinement: the energetic answer with ``cone_tolerance`` None
   (the model's 8-edge pyramid), 8°, 4°, 2°, 1° and 0.5°, its relative error against the 0.5°
   answer, the edge counts, whether the sequence is monotone per direction, and the
   iterative 8-edge answer against the same reference; the 3D pinch along
   ``(0, cos 80°, sin 80°)`` against its closed form 10 N;
4. the effect of the normal uncertainty ``u`` (0, 1°, 2.5°, 5°) on case1, both methods.

case2 runs with fewer directions and ``max_nodes=5000`` (both methods): the energetic
branch-and-bound hits its node limit there (~35-40 s per direction at the default 20000, 7-11 s at 5000).
Prints markdown tables to stdout and saves ``docs/img/energetic_benchmark.png``::

    python -m scripts.reproduce.energetic            # full run (~7 min on 2 cores)
    python -m scripts.reproduce.energetic --quick    # smoke run (~75 s; figure to a temp dir)
"""

from __future__ import annotations

import os
import sys

for _k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # before numpy
    os.environ.setdefault(_k, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import subprocess  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from dataclasses import replace  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import pinograsp as pg  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
UPPER = 50.0
#: The iterative scheme with a tight equilibrium tolerance.
TIGHT = {"eps": 1e-6, "eps_rel": 1e-9}
#: Finite magnitudes this close (relative) count as agreeing.
AGREE = 1e-2
#: A refined magnitude may fall by this much (relative) and still count as monotone.
MONO = 1e-8
PINCH_ANGLE = 80.0
#: case3 directions where the iterative scheme stalls (docs/validation.md); not refined (255°
#: refined at 4° ran into the node limit after ~300 s in a trial run).
EXTRA_CASE3 = (255.0, 285.0)
PINCH_CLOSED = 10.0


def xy(angle: float) -> np.ndarray:
    a = np.radians(angle)
    return np.array([np.cos(a), np.sin(a), 0.0, 0.0, 0.0, 0.0])


def query(model: object, command: object, d: np.ndarray, method: str, **kw: object) -> dict:
    """One ``max_resistible_wrench`` call: status, magnitude [N], wall time [s], edge counts,
    contact states and the warnings it raised (a node limit is a status here)."""
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            r = pg.max_resistible_wrench(model, command, d, method=method, upper=UPPER, **kw)
        except pg.SolverError as e:  # node_limit (branch-and-bound), timeout, failed
            out = {"status": e.status or type(e).__name__, "mag": float("nan"), "edges": None, "states": None}
        else:
            resp = r.response
            out = {
                "status": str(r.status),
                "mag": float(r.magnitude),
                "edges": list(resp.edge_counts) if resp is not None else None,
                "states": list(resp.contact_states) if resp is not None else None,
            }
    out["t"] = time.perf_counter() - t0
    out["warnings"] = sorted({w.category.__name__ for w in caught})
    return out


def fmt(r: dict, digits: int = 5) -> str:
    s = r["status"]
    if s == "finite":
        return f"{r['mag']:.{digits}g}"
    if s == "below_resolution":
        return f"≈0 ({r['mag']:.0e})" if r["mag"] > 0 else "≈0"
    if s == "above_limit":
        return f"≥ {UPPER:g}"
    return s


def rel(a: dict, ref: dict) -> float | None:
    """``a / ref - 1`` when both are finite, else None."""
    if a["status"] == ref["status"] == "finite" and ref["mag"] > 0:
        return a["mag"] / ref["mag"] - 1.0
    return None


def compare(a: dict, ref: dict) -> str:
    """Relative difference of ``a`` against ``ref`` as text, or how their statuses relate."""
    x = rel(a, ref)
    if x is not None:
        return f"{x:+.1e}"
    if a["status"] == ref["status"]:
        return "same"
    return f"{a['status']} vs {ref['status']}"


def agrees(a: dict, b: dict) -> bool:
    x = rel(a, b)
    return a["status"] == b["status"] and (x is None or abs(x) <= AGREE)


def pct(values: list[float], p: float) -> float:
    return float(np.percentile(values, p)) if values else float("nan")


def measure_scene(
    name: str, angles: list[float], tols: list[float | None], extra: dict, unrefined: tuple[float, ...] = ()
) -> dict:
    """Every query of one scene: iterative (default and tight), energetic per cone tolerance
    (only the 8-edge pyramid at the ``unrefined`` angles)."""
    scene = pg.load_scene(name)
    model, command = scene.model, scene.command
    rows = []
    for ang in angles:
        d = xy(ang)
        row = {"angle": ang, "it": query(model, command, d, "iterative", **extra)}
        print(f"{name} {ang:g}°: iterative {fmt(row['it'])} ({row['it']['t']:.2f} s)", end="", flush=True)
        if name != "case2":
            row["tight"] = query(model, command, d, "iterative", **TIGHT, **extra)
        row["en"] = {}
        for tol in tols if ang not in unrefined else [None]:
            kw = dict(extra) if tol is None else {**extra, "cone_tolerance": np.radians(tol)}
            r = query(model, command, d, "energetic", **kw)
            row["en"][str(tol)] = r
            print(f"; E[{tol}] {fmt(r)} ({r['t']:.2f} s)", end="", flush=True)
        print(flush=True)
        rows.append(row)
    return {"name": name, "rows": rows, "tols": [str(t) for t in tols], "extra": extra}


def measure_pinch(tols: list[float | None]) -> list[dict]:
    model = pg.examples.pinch(planar=False)
    a = np.radians(PINCH_ANGLE)
    d = np.array([0.0, np.cos(a), np.sin(a), 0.0, 0.0, 0.0])
    out = [{"tol": "iterative", **query(model, 1.0, d, "iterative")}]
    for tol in tols:
        kw = {} if tol is None else {"cone_tolerance": np.radians(tol)}
        out.append({"tol": str(tol), **query(model, 1.0, d, "energetic", **kw)})
    return out


def measure_uncertainty(angles: list[float], us: list[float]) -> list[dict]:
    """case1 under normal uncertainty ``u`` [deg]: both methods, and the energetic one on the
    shrunk cones alone (the model's ``normal_uncertainty`` reset to 0: no loss of compression
    with slip), which isolates the slip term."""
    scene = pg.load_scene("case1")
    out = []
    for ang in angles:
        for u in us:
            row = {"angle": ang, "u": u}
            for m in ("iterative", "energetic"):
                row[m] = query(scene.model, scene.command, xy(ang), m, normal_uncertainty=np.radians(u))
            shrunk = replace(scene.model.with_normal_uncertainty(np.radians(u)), normal_uncertainty=0.0)
            row["shrink"] = query(shrunk, scene.command, xy(ang), "energetic")
            print(f"case1 {ang:g}° u={u:g}°: {fmt(row['iterative'])} / {fmt(row['energetic'])}", flush=True)
            out.append(row)
    return out


# ------------------------------------------------------------------------------------ tables
def table(head: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def _medians(rows: list[dict], keep: object) -> str:
    sel = [r for r in rows if keep(r["it"]["status"], r["en"]["None"]["status"])]
    if not sel:
        return "—"
    it = np.median([r["it"]["t"] for r in sel])
    en = np.median([r["en"]["None"]["t"] for r in sel])
    return f"{it:.3f} / {en:.3f} ({len(sel)})"


def timing_table(scenes: list[dict]) -> str:
    rows = []
    for s in scenes:
        it = [r["it"]["t"] for r in s["rows"]]
        en = [r["en"]["None"]["t"] for r in s["rows"]]
        nl = sum(r["en"]["None"]["status"] == "node_limit" for r in s["rows"])
        rows.append(
            [
                s["name"] + (f" (max_nodes={s['extra']['max_nodes']})" if s["extra"] else ""),
                str(len(it)),
                f"{np.median(it):.3f} / {pct(it, 90):.3f}",
                f"{np.median(en):.3f} / {pct(en, 90):.3f}",
                f"{np.median(en) / np.median(it):.2f}",
                _medians(s["rows"], lambda a, b: a == b == "unbounded"),
                _medians(s["rows"], lambda a, b: "finite" in (a, b) and "unbounded" not in (a, b)),
                str(nl),
            ]
        )
    head = ["scene", "directions", "iterative median / p90 [s]", "energetic median / p90 [s]"]
    head += ["energetic / iterative (medians)", "unbounded in both: medians it. / en. [s] (n)"]
    head += ["finite in either: medians it. / en. [s] (n)", "energetic node_limit"]
    return table(head, rows)


def agreement_tables(s: dict) -> tuple[str, list[str]]:
    """Per-direction verdicts of one scene, and its disagreements as text."""
    rows, bad = [], []
    tight = "tight" in s["rows"][0]
    for r in s["rows"]:
        it, en = r["it"], r["en"]["None"]
        ok = agrees(en, it)
        line = [f"{r['angle']:g}°", fmt(it)] + ([fmt(r["tight"])] if tight else [])
        line += [fmt(en), compare(en, it), "yes" if ok else "**no**"]
        if tight:
            line.append("yes" if agrees(en, r["tight"]) else "**no**")
        rows.append(line)
        if not ok:
            bad.append(f"{s['name']} {r['angle']:g}°: iterative {fmt(it)}, energetic {fmt(en)}")
    head = ["direction", "iterative"] + (["iterative, eps=1e-6, eps_rel=1e-9"] if tight else [])
    head += ["energetic (8 edges)", "energetic vs iterative", "agree"]
    if tight:
        head.append("agree with tight iterative")
    return table(head, rows), bad


def monotone(seq: list[dict]) -> str:
    if any(r["status"] != seq[0]["status"] for r in seq):
        return "statuses differ"
    if seq[0]["status"] != "finite":
        return "n/a"
    mags = [r["mag"] for r in seq]
    drops = [b / a - 1.0 for a, b in zip(mags, mags[1:]) if b < a * (1.0 - MONO)]
    return "yes" if not drops else f"**no** ({min(drops):+.1e})"


def refinement_table(s: dict) -> str:
    tols = s["tols"]
    head = ["direction", "iterative (8 edges)"] + [
        "E 8 edges" if t == "None" else f"E {float(t):g}°" for t in tols
    ]
    head += [f"edges at {float(tols[-1]):g}°", "monotone"]
    rows = []
    refined = [r for r in s["rows"] if tols[-1] in r["en"]]
    for r in refined:
        ref = r["en"][tols[-1]]
        cells = [f"{r['angle']:g}°", f"{fmt(r['it'])} ({compare(r['it'], ref)})"]
        for t in tols[:-1]:
            cells.append(f"{fmt(r['en'][t], 7)} ({compare(r['en'][t], ref)})")
        cells.append(fmt(ref, 7))
        cells.append(",".join(map(str, ref["edges"])) if ref["edges"] else "—")
        cells.append(monotone([r["en"][t] for t in tols]))
        rows.append(cells)
    times = ["total time [s]", f"{sum(r['it']['t'] for r in refined):.1f}"]
    times += [f"{sum(r['en'][t]['t'] for r in refined):.1f}" for t in tols] + ["", ""]
    return table(head, rows + [times])


def pinch_table(rows: list[dict]) -> str:
    out = []
    for r in rows:
        label = (
            "iterative (8 edges)"
            if r["tol"] == "iterative"
            else ("energetic, 8 edges" if r["tol"] == "None" else f"energetic, {float(r['tol']):g}°")
        )
        err = r["mag"] / PINCH_CLOSED - 1.0 if r["status"] == "finite" else float("nan")
        edges = ",".join(map(str, r["edges"])) if r["edges"] else "—"
        out.append([label, fmt(r, 7), f"{err:+.2e}", edges, f"{r['t']:.3f}"])
    return table(["method", "magnitude [N]", "vs closed form 10 N", "edges", "time [s]"], out)


def uncertainty_table(rows: list[dict]) -> str:
    base = {(r["angle"], m): r[m] for r in rows if r["u"] == 0 for m in ("iterative", "energetic")}
    out = []
    for r in rows:
        cells = [f"{r['angle']:g}°", f"{r['u']:g}°"]
        for m in ("iterative", "energetic"):
            cells.append(f"{fmt(r[m])} ({compare(r[m], base[(r['angle'], m)])})")
        cells.append(compare(r["energetic"], r["iterative"]))
        cells.append(f"{fmt(r['shrink'])} ({compare(r['energetic'], r['shrink'])})")
        cells.append(f"{r['iterative']['t']:.2f} / {r['energetic']['t']:.2f}")
        out.append(cells)
    head = ["direction", "u", "iterative [N] (vs u=0)", "energetic [N] (vs u=0)", "energetic vs iterative"]
    head += ["energetic, shrunk cones only (full vs this)", "time it. / en. [s]"]
    return table(head, out)


def environment() -> str:
    try:
        rev = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=False
        ).stdout.strip()
    except OSError:
        rev = "?"
    return (
        f"pinograsp {rev} ({pg.__file__}), Python {platform.python_version()}, "
        f"{platform.machine()}, {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}, "
        "single-threaded BLAS"
    )


def report(res: dict) -> str:
    parts = [f"# Energetic vs iterative, cone refinement\n\n{res['env']}; upper = {UPPER:g} N.\n"]
    parts.append("## Time per direction\n\n" + timing_table(res["scenes"]))
    bad: list[str] = []
    parts.append(f"## Verdicts (agree: same status, finite magnitudes within {AGREE:.0%})")
    for s in res["scenes"]:
        text, b = agreement_tables(s)
        n_ok = len(s["rows"]) - len(b)
        parts.append(f"### {s['name']}: {n_ok} / {len(s['rows'])} directions agree\n\n{text}")
        bad += b
    parts.append("Disagreements:\n\n" + ("\n".join(f"- {b}" for b in bad) or "- none"))
    parts.append("## Accuracy against the finest refinement (relative error in parentheses)")
    for s in res["scenes"]:
        if len(s["tols"]) > 1:
            parts.append(f"### {s['name']}\n\n" + refinement_table(s))
    parts.append(
        f"## 3D pinch along (0, cos {PINCH_ANGLE:g}°, sin {PINCH_ANGLE:g}°)\n\n" + pinch_table(res["pinch"])
    )
    parts.append("## Normal uncertainty, case1\n\n" + uncertainty_table(res["uncertainty"]))
    parts.append(f"Total {res['total']:.0f} s.")
    return "\n\n".join(parts) + "\n"


# ------------------------------------------------------------------------------------ figure
def _width(tol: str) -> float:
    """Sector width [deg] a tolerance stands for (the 8-edge pyramid's sectors are 45°)."""
    return 45.0 if tol in ("None", "iterative") else float(tol)


def plot(res: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    ax = axes[0]
    for k, s in enumerate(s for s in res["scenes"] if len(s["tols"]) > 1):
        tols = s["tols"][:-1]
        label = s["name"]
        for r in (r for r in s["rows"] if s["tols"][-1] in r["en"]):
            ref = r["en"][s["tols"][-1]]
            errs = [rel(r["en"][t], ref) for t in tols]
            if all(e is not None for e in errs):
                xs = [_width(t) for t in tols]
                ys = [max(abs(e), 1e-13) for e in errs]
                ax.plot(xs, ys, "o-", color=f"C{k}", alpha=0.6, label=label)
                label = None
    pin = [r for r in res["pinch"] if r["tol"] != "iterative"]
    ax.plot(
        [_width(r["tol"]) for r in pin],
        [abs(r["mag"] / PINCH_CLOSED - 1.0) for r in pin],
        "s-k",
        label="3D pinch (vs 10 N)",
    )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.invert_xaxis()
    ax.set_xlabel("cone tolerance [deg] (45: the 8-edge pyramid)")
    ax.set_ylabel("|relative error| vs finest (pinch: vs 10 N)")
    ax.set_title("energetic: refinement")
    ax.legend(fontsize=8)
    ax = axes[1]
    names = [s["name"] for s in res["scenes"]]
    seen: set[str] = set()
    for k, s in enumerate(res["scenes"]):
        for off, key in enumerate(("it", "en")):
            for r in s["rows"]:
                q = r["it"] if key == "it" else r["en"]["None"]
                lab = "iterative" if key == "it" else "energetic"
                style = {"color": "C0" if key == "it" else "C3", "marker": "o"}
                if q["status"] == "node_limit":
                    lab, style = "energetic: node_limit", {"color": "k", "marker": "x"}
                x = k + (off - 0.5) * 0.3
                ax.scatter([x], [q["t"]], s=16, label=None if lab in seen else lab, **style)
                seen.add(lab)
    ax.set_xticks(range(len(names)), names)
    ax.set_yscale("log")
    ax.set_ylabel("wall time per direction [s]")
    ax.set_title(f"max_resistible_wrench, upper {UPPER:g} N (8-edge pyramids)")
    ax.legend(fontsize=8)
    ax = axes[2]
    angles = sorted({r["angle"] for r in res["uncertainty"]})
    for j, ang in enumerate(angles):
        rows = [r for r in res["uncertainty"] if r["angle"] == ang]
        for m, ls, mk in (("iterative", "--", "x"), ("energetic", "-", "o")):
            pts = [(r["u"], r[m]["mag"]) for r in rows if r[m]["status"] == "finite"]
            if pts:
                ax.plot(*zip(*pts), ls, marker=mk, color=f"C{j}", mfc="none", label=f"{ang:g}° {m}")
    ax.set_yscale("log")
    ax.set_xlabel("normal uncertainty u [deg]")
    ax.set_ylabel("max resistible force [N] (finite answers)")
    ax.set_title("case1: normal uncertainty")
    ax.legend(fontsize=7)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="smoke run (~75 s); figure to a temp dir")
    ap.add_argument("-n", type=int, default=12, help="directions of case1 and case3 (default 12)")
    ap.add_argument("--n-case2", type=int, default=6, help="directions of case2 (default 6)")
    ap.add_argument("--case2-nodes", type=int, default=5000, help="max_nodes on case2 (default 5000)")
    ap.add_argument("--img", default=None, help="figure path (default docs/img/energetic_benchmark.png)")
    ap.add_argument("--json", default=None, help="also dump the raw measurements here")
    args = ap.parse_args()
    if not str(Path(pg.__file__).resolve()).startswith(str(ROOT)):
        print(f"warning: measuring pinograsp from {pg.__file__}, not {ROOT}", file=sys.stderr)
    if args.quick:
        n, n2, nodes, tols = 4, 2, 2000, [None, 4.0, 1.0]
        unc_angles, us = [30.0], [0.0, 2.5]
        img = (
            Path(args.img)
            if args.img
            else Path(tempfile.mkdtemp(prefix="energetic_")) / "energetic_benchmark.png"
        )
    else:
        n, n2, nodes, tols = args.n, args.n_case2, args.case2_nodes, [None, 8.0, 4.0, 2.0, 1.0, 0.5]
        unc_angles, us = [0.0, 30.0, 60.0, 90.0], [0.0, 1.0, 2.5, 5.0]
        img = Path(args.img) if args.img else ROOT / "docs" / "img" / "energetic_benchmark.png"
    t0 = time.perf_counter()
    res: dict = {"env": environment()}
    print(res["env"], flush=True)
    grid = [360.0 * k / n for k in range(n)]
    res["scenes"] = [
        measure_scene("case1", grid, tols, {}),
        measure_scene("case3", grid + [a for a in EXTRA_CASE3 if a not in grid], tols, {}, EXTRA_CASE3),
        measure_scene("case2", [360.0 * k / n2 for k in range(n2)], [None], {"max_nodes": nodes}),
    ]
    res["pinch"] = measure_pinch(tols)
    res["uncertainty"] = measure_uncertainty(unc_angles, us)
    res["total"] = time.perf_counter() - t0
    text = report(res)
    plot(res, img)
    print("\n" + text)
    if args.json:
        Path(args.json).write_text(json.dumps(res, default=str))
    print(f"figure: {img}; {res['total']:.0f} s")


if __name__ == "__main__":
    main()
