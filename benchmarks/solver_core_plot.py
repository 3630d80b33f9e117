"""The figure of ``benchmarks/solver_core.py``, ``docs/img/solver_core.png``."""

from __future__ import annotations

import statistics
from pathlib import Path

import numpy as np
from solver_core_common import q


def plot(res: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    c1 = res["case1"]
    ax = axes[0, 0]
    x = np.arange(len(c1["angles"]))
    wdt = 0.2
    for i, (k, lab, col) in enumerate(
        (
            ("new", "new (secant + jump)", "C0"),
            ("bisection", "new, bisection", "C2"),
            ("noaccel", "new, accelerate=False", "C1"),
            ("old", "old (fc3d54a defaults)", "C3"),
        )
    ):
        ax.bar(x + (i - 1.5) * wdt, [max(r["wall"], 1e-3) for r in c1[k]], wdt, label=lab, color=col)
    ax.set_yscale("log")
    ax.set_xticks(x, [f"{a}°" for a in c1["angles"]])
    ax.set_ylabel("wall time per direction [s]")
    ax.set_title("case 1, iterative, upper 1e3, 20 steps")
    ax.legend(fontsize=8)
    ax = axes[0, 1]
    pr = res["prp"]
    labels = list(pr["new"])
    xs = np.arange(len(labels))
    for k, lab, col, src in (
        ("bnb", "B&B (solver layer)", "C0", "new"),
        ("api", "new passive_response", "C9", "new"),
        ("scip", "SCIP (cvxpy)", "C2", "new"),
        ("wall", "old passive_response", "C3", "old"),
    ):
        med = [1e3 * statistics.median(pr[src][lab_][k]) for lab_ in labels]
        p90 = [1e3 * q(pr[src][lab_][k], 90) for lab_ in labels]
        ax.plot(xs, med, "o-", color=col, label=f"{lab} (median)")
        ax.plot(xs, p90, "x:", color=col, alpha=0.7)
    ax.set_yscale("log")
    ax.set_xticks(xs, [lab.replace(" contacts, ", "\n") for lab in labels], fontsize=8)
    ax.set_ylabel("time per PRP solve [ms] (x: p90)")
    ax.set_title("single PRP solve, random 3D grasps")
    ax.legend(fontsize=8)
    ax = axes[1, 0]
    c2 = res["case2"]
    if c2["dir_walls"]:
        ang = np.arange(c2["n"]) * 360.0 / c2["n"]
        ax.plot(ang, c2["dir_walls"], "o-", ms=3, label=f"new ({c2['wall']:.0f} s total)")
    ax.plot(
        c2["old"]["angles"],
        c2["old"]["dir_walls"],
        "s",
        color="C3",
        label=(
            f"old, {len(c2['old']['dir_walls'])} directions "
            f"(~{c2['summary']['extrap'] / 60:.0f} min for {c2['n']})"
        ),
    )
    ax.set_yscale("log")
    ax.set_xlabel("direction in the XY plane [°]")
    ax.set_ylabel("wall time per direction [s]")
    ax.set_title("case 2 profile (finger1_only, upper 50)")
    ax.legend(fontsize=8)
    ax = axes[1, 1]
    rows = [
        r
        for r in res["agreement"]["rows"]
        if r.get("bnb_status") == "optimal" and r.get("scip_status") == "optimal"
    ]
    for kind, col, mk in (("prp", "C0", "o"), ("move", "C1", "^")):
        rr = [r for r in rows if r["kind"] == kind]
        ax.scatter(
            [max(r["scip_obj"], 1e-30) for r in rr],
            [max(r["bnb_obj"], 1e-30) for r in rr],
            s=8,
            color=col,
            marker=mk,
            label=f"{'PRP' if kind == 'prp' else 'movement step'} ({len(rr)})",
            alpha=0.6,
        )
    bad = [r for r in res["agreement"]["rows"] if r["cls"] == "B&B higher"]
    if bad:
        ax.scatter(
            [max(r["scip_obj"], 1e-30) for r in bad],
            [max(r["bnb_obj"], 1e-30) for r in bad],
            s=40,
            facecolors="none",
            edgecolors="r",
            label=f"B&B higher ({len(bad)})",
        )
    ax.plot([1e-30, 1e3], [1e-30, 1e3], "k:", lw=1)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("SCIP objective (scaled, floor 1e-30)")
    ax.set_ylabel("B&B objective")
    ax.set_title("step optima, B&B vs SCIP (both optimal)")
    ax.legend(fontsize=8)
    fig.suptitle(
        "pinograsp solver core: exact branch-and-bound vs previous implementation vs SCIP (this machine)"
    )
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
