"""The report of ``benchmarks/solver_core.py``, ``docs/solver_core.md``."""

from __future__ import annotations

import os
import platform
import statistics
import subprocess
from importlib.metadata import version
from pathlib import Path

from solver_core_agreement import md_agreement
from solver_core_common import BLAS1, OLD_COMMIT, PINCH_CLOSED, ROOT, fmt_mag, fmt_row, q


# =====================================================================================
# report
# =====================================================================================
def md_case1(c1: dict) -> str:
    L = [
        "| direction | new: time [s] | new: magnitude [N] | new: stages | bisection: time [s] | bisection: "
        "magnitude | "
        "accelerate=False: time [s] | accelerate=False: magnitude | old: time [s] | old: magnitude | old: "
        "stages | old/new time |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for n, b, a, o in zip(c1["new"], c1["bisection"], c1["noaccel"], c1["old"]):
        am = "capped" if a["capped"] else (a["error"] or fmt_row(a))
        L.append(
            f"| {n['angle']}° | {n['wall']:.3f} | {n['error'] or fmt_row(n)} | "
            f"{n['stages']} "
            f"| {b['wall']:.3f} | {b['error'] or fmt_row(b)} "
            f"| {a['wall']:.2f}{'+' if a['capped'] else ''} | {am} "
            f"| {o['wall']:.2f} | {fmt_row(o)} | {o['stages']} | "
            f"{o['wall'] / n['wall']:.1f} |"
        )
    med = {k: statistics.median(r["wall"] for r in c1[k]) for k in ("new", "bisection", "noaccel", "old")}
    tot = {k: sum(r["wall"] for r in c1[k]) for k in ("new", "bisection", "noaccel", "old")}
    ratios = [o["wall"] / n["wall"] for n, o in zip(c1["new"], c1["old"])]
    L.append(
        f"| **median** | **{med['new']:.3f}** | | {statistics.median(r['stages'] for r in c1['new'])} "
        f"| **{med['bisection']:.3f}** | | **{med['noaccel']:.2f}** | | **{med['old']:.2f}** | "
        f"| {statistics.median(r['stages'] for r in c1['old'])} | **{med['old'] / med['new']:.1f}** |"
    )
    L.append(
        f"| total | {tot['new']:.2f} | | | {tot['bisection']:.2f} | | {tot['noaccel']:.1f} | | "
        f"{tot['old']:.1f} | | | {tot['old'] / tot['new']:.1f} |"
    )
    c1["summary"] = dict(
        med=med,
        tot=tot,
        ratio_median=med["old"] / med["new"],
        ratio_per_dir_median=statistics.median(ratios),
        ratio_total=tot["old"] / tot["new"],
    )
    return "\n".join(L)


def md_blas(c1: dict) -> str:
    L = [
        "| direction | new, 1 thread [s] | new, default threads [s] | old, 1 thread [s] | old, default "
        "threads [s] "
        "| old/new, default threads |",
        "|---:|---:|---:|---:|---:|---:|",
    ]
    for n, nd, o, od in zip(c1["new"], c1["new_blasd"], c1["old"], c1["old_blasd"]):
        L.append(
            f"| {n['angle']}° | {n['wall']:.3f} | {nd['wall']:.3f} | {o['wall']:.2f} | {od['wall']:.2f} "
            f"| {od['wall'] / nd['wall']:.1f} |"
        )
    med = [statistics.median(r["wall"] for r in c1[k]) for k in ("new", "new_blasd", "old", "old_blasd")]
    L.append(
        f"| **median** | **{med[0]:.3f}** | **{med[1]:.3f}** | **{med[2]:.2f}** | **{med[3]:.2f}** "
        f"| **{med[3] / med[1]:.1f}** |"
    )

    def same(xs, ys):
        return all(
            a.get("status") == b.get("status") and (a["unbounded"] or a["magnitude"] == b["magnitude"])
            for a, b in zip(xs, ys)
        )

    c1["blas_summary"] = dict(
        med=med, same_new=same(c1["new"], c1["new_blasd"]), same_old=same(c1["old"], c1["old_blasd"])
    )
    L += [
        "",
        "Magnitudes with default threads vs 1 thread: new core "
        + ("bit-identical on every direction" if c1["blas_summary"]["same_new"] else "**different**")
        + "; old implementation "
        + (
            "identical on every direction."
            if c1["blas_summary"]["same_old"]
            else "**different on some directions**."
        ),
    ]
    if not c1["blas_summary"]["same_old"]:
        diffs = [
            f"{o['angle']}°: {fmt_row(o)} vs {fmt_row(od)}"
            for o, od in zip(c1["old"], c1["old_blasd"])
            if o.get("status") != od.get("status")
            or (not o["unbounded"] and o["magnitude"] != od["magnitude"])
        ]
        L[-1] += " Old, 1 thread vs default threads: " + "; ".join(diffs) + "."
    return "\n".join(L)


def md_profile(c1: dict) -> str:
    profs = c1["profile"]
    cols = " | ".join(f"{p['angle']}°" for p in profs)
    L = [
        f"| what runs (exclusive shares of the profiled time) | {cols} |",
        "|---" + "|---:" * len(profs) + "|",
    ]
    for key in profs[0]["shares"]:
        L.append(
            f"| {key} | " + " | ".join(f"{100 * p['shares'][key] / p['total']:.0f} %" for p in profs) + " |"
        )
    L.append(
        "| profiled time [s] (cProfile overhead included) | "
        + " | ".join(f"{p['total']:.2f}" for p in profs)
        + " |"
    )
    L.append(
        "| complementarity solves / stages | "
        + " | ".join(f"{p['n_solves']} / {p['stages']}" for p in profs)
        + " |"
    )
    L.append(
        "| DAQP / Clarabel / SVD calls | "
        + " | ".join(f"{p['n_daqp']} / {p['n_clarabel']} / {p['n_svd']}" for p in profs)
        + " |"
    )
    L += ["", f"| where (inclusive, overlapping) | {cols} |", "|---" + "|---:" * len(profs) + "|"]
    for key in profs[0]["where"]:
        L.append(
            f"| {key} | " + " | ".join(f"{100 * p['where'][key] / p['total']:.0f} %" for p in profs) + " |"
        )
    return "\n".join(L)


def md_prp(pr: dict) -> str:
    L = [
        "| grasp (3D, 8 edges) | B&B median / p90 [ms] | B&B, default BLAS threads, median / p90 [ms] "
        "| B&B nodes median / p90 / max | B&B QPs median | SCIP median / p90 [ms] "
        "| new `passive_response` median / p90 [ms] | old `passive_response` median / p90 [ms] | old/new "
        "(public API, median) "
        "| resisted: B&B / SCIP / old |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    pr["summary"] = {}
    for label, r in pr["new"].items():
        o = pr["old"][label]
        bd = pr["bnb_blasd"][label]
        nb = sum(s == "optimal" for s in r["bnb_status"])
        ns = sum(s == "optimal" for s in r["scip_status"])
        no = sum(bool(x) for x in o["resisted"])
        agree = sum((a == "optimal") == bool(c) for a, c in zip(r["bnb_status"], o["resisted"]))
        differ = "" if agree == len(r["bnb"]) else f" ({len(r['bnb']) - agree} verdicts differ new vs old)"
        ratio = statistics.median(o["wall"]) / statistics.median(r["api"])
        pr["summary"][label] = dict(
            bnb_med=1e3 * statistics.median(r["bnb"]),
            bnb_p90=1e3 * q(r["bnb"], 90),
            scip_med=1e3 * statistics.median(r["scip"]),
            scip_p90=1e3 * q(r["scip"], 90),
            api_med=1e3 * statistics.median(r["api"]),
            old_med=1e3 * statistics.median(o["wall"]),
            old_p90=1e3 * q(o["wall"], 90),
            ratio=ratio,
            verdict_agree_old=agree,
            bnbd_med=1e3 * statistics.median(bd),
            bnbd_p90=1e3 * q(bd, 90),
        )
        L.append(
            f"| {label} | {1e3 * statistics.median(r['bnb']):.2f} / {1e3 * q(r['bnb'], 90):.2f} "
            f"| {1e3 * statistics.median(bd):.2f} / {1e3 * q(bd, 90):.2f} "
            f"| {statistics.median(r['nodes']):.0f} / {q(r['nodes'], 90):.0f} / {max(r['nodes'])} | "
            f"{statistics.median(r['qps']):.0f} "
            f"| {1e3 * statistics.median(r['scip']):.1f} / {1e3 * q(r['scip'], 90):.1f} "
            f"| {1e3 * statistics.median(r['api']):.2f} / {1e3 * q(r['api'], 90):.2f} "
            f"| {1e3 * statistics.median(o['wall']):.2f} / {1e3 * q(o['wall'], 90):.2f} | {ratio:.1f} "
            f"| {nb} / {ns} / {no} of {len(r['bnb'])}{differ} |"
        )
    return "\n".join(L)


def md_pinch(pc: dict) -> str:
    L = [
        "| direction | method | closed form [N] | new: median time [ms] | new: magnitude | new: stages | "
        "old: median time [ms] | old: magnitude | old: stages | old/new |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for n, o in zip(pc["new"], pc["old"]):
        tn, to = statistics.median(n["walls"]), statistics.median(o["walls"])
        L.append(
            f"| {n['dir']} | {n['method']} | {PINCH_CLOSED[n['dir']]:.4f} | {1e3 * tn:.1f} | "
            f"{n['error'] or fmt_row(n)} | {n['stages']} | {1e3 * to:.1f} | "
            f"{fmt_row(o)} | {o['stages']} | {to / tn:.1f} |"
        )
    return "\n".join(L)


def md_case2(c2: dict) -> str:
    old = c2["old"]
    n_old = len(old["dir_walls"])
    step = c2["step"]
    new_same = [c2["dir_walls"][i * step] for i in range(n_old)] if c2["dir_walls"] else []
    extrap = old["wall"] * c2["n"] / n_old
    c2["summary"] = dict(extrap=extrap, ratio=extrap / c2["wall"])
    L = [
        f"New core, full profile ({c2['n']} directions, sequential): **{c2['wall']:.1f} s** "
        f"(median {statistics.median(c2['dir_walls']):.2f} s per direction, max {max(c2['dir_walls']):.2f} "
        "s; "
        f"median {statistics.median(c2['stages']):.0f} stages; {sum(c2['unbounded'])} unbounded, "
        f"{c2['status'].count('above_limit')} above_limit)."
        if c2["dir_walls"]
        else f"New core: failed: {c2['error']}",
        "",
        f"Old implementation, measured on {n_old} of the directions (`resistance_profile(..., n={n_old})`, "
        "the same "
        f"directions as every {step}th of the {c2['n']}): {old['wall']:.1f} s, i.e. "
        f"{old['wall'] / n_old:.1f} s per "
        f"direction; **extrapolated to {c2['n']} directions: ~{extrap / 60:.0f} min** ({extrap:.0f} s, an "
        "estimate: the "
        "old mode-guess warm start between 5° neighbours of a full profile may make it somewhat faster than "
        "this). "
        f"Ratio old (extrapolated) / new: **{extrap / c2['wall']:.0f}×**.",
        "",
        "| direction | new: time [s] | new: magnitude [N] | old: time [s] | old: magnitude [N] |",
        "|---:|---:|---:|---:|---:|",
    ]
    for i in range(n_old):
        j = i * step
        nm = fmt_mag(c2["magnitudes"][j], c2["unbounded"][j], c2["status"][j]) if c2["magnitudes"] else "—"
        nt = f"{new_same[i]:.2f}" if new_same else "—"
        L.append(
            f"| {old['angles'][i]:.0f}° | {nt} | {nm} | {old['dir_walls'][i]:.2f} | "
            f"{fmt_mag(old['magnitudes'][i], old['unbounded'][i], old['status'][i])} |"
        )
    return "\n".join(L)


def environment() -> str:
    def git(*a):
        return subprocess.run(["git", "-C", str(ROOT), *a], capture_output=True, text=True).stdout.strip()

    dirty = git("status", "--porcelain", "--", "pinograsp")
    vers = ", ".join(
        f"{p} {version(p)}" for p in ("numpy", "daqp", "clarabel", "cvxpy", "pyscipopt", "proxsuite")
    )
    blas = ", ".join(f"{k}={os.environ.get(k, 'unset')}" for k in BLAS1)
    return (
        f"{platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}; {vers}; {blas}. "
        f"New core: `{git('rev-parse', '--short', 'HEAD')}`"
        + (
            f" with uncommitted changes to {len(dirty.splitlines())} file(s) under `pinograsp/`"
            if dirty
            else ""
        )
        + f"; old: `{OLD_COMMIT}` (subprocess, its defaults: `fast=True, certify=True`, cached `solver_for`)"
    )


READING = """## Reading guide

* **new** is the current default: the exact branch-and-bound over the complementarity pairs
  (DAQP node QPs, Clarabel fallback), the iterative scheme with the subspace jump
  (`accelerate=True`) and the grid-snapped secant search (`search="auto"`). **old** is commit
  `fc3d54a` with its defaults: a ProxSuite fixed-mode QP for a guessed mode, SCIP (cvxpy) when the
  guess fails, and exact certificates of "stopped improving" verdicts. Both run in the same
  process environment, one after the other, never concurrently; the old one in a subprocess with
  `PYTHONPATH` on its worktree. Times are wall-clock times of whole public queries on a 2-core
  machine that other jobs may share (load averages below): ratios measured minutes apart are more
  reliable than absolute numbers.
* **BLAS threads.** Everything runs with `OPENBLAS_NUM_THREADS=1` (both implementations) unless
  a column says "default threads". numpy's OpenBLAS otherwise starts one thread per CPU; on this
  2-core machine, with another process on the second core, its threaded full SVD of a 75×80
  matrix took ~70 ms against ~0.9 ms single-threaded, and the new core calls such SVDs in every
  solve (polish of the optimal face, canonical point). Since `4f58646` the package's public
  queries limit BLAS to one thread themselves (threadpoolctl), so "new, default threads" measures
  that built-in limit; the solver layer called directly (`BranchAndBound`) is not limited, which
  the "B&B, default BLAS threads" column of section 2 shows. Answers do not depend on the threads
  (compared in section 1).
* **stages** = magnitudes tried (`len(evidence)`): the bisection tries `steps + 1`, the secant
  usually fewer. A direction whose magnitude differs between columns is a different answer, not a
  timing effect: the old fast path's verdicts rested on inexact step optima, and
  `accelerate=False` is the paper's scheme step by step, which stalls under the 1 % rule in narrow
  valleys and then calls a resisted load "not resisted" (a smaller finite magnitude, or finite
  instead of unbounded).
* **PRP solves**: "B&B" is the solver layer alone (`build_problem` + `BranchAndBound.solve`),
  "new `passive_response`" the public call (session, scaling, result and audit), "SCIP" the
  reference `CvxpyMIQP` (a new cvxpy problem per solve), "old" the previous public call (after one
  warm-up call on the same model, so its mode guess and compiled cvxpy problem are warm).
* **Agreement**: every problem is solved by the branch-and-bound and by SCIP (big-M 1e3, enlarged
  ×100 up to twice as the engine does). "B&B higher" or a status mismatch would mean the exact
  solver missed an optimum (or SCIP accepted an infeasible point): each is listed with SCIP's point
  violation and with SCIP's own mode re-solved exactly, which tells the two apart.
"""


def write_report(res: dict, out: Path, img: Path, quick: bool) -> str:
    c1, pr, pc, c2, ag = res["case1"], res["prp"], res["pinch"], res["case2"], res["agreement"]
    t_case1, t_prof, t_blas = md_case1(c1), md_profile(c1), md_blas(c1)
    t_prp, t_pinch, t_case2, t_ag = md_prp(pr), md_pinch(pc), md_case2(c2), md_agreement(ag)
    s1 = c1["summary"]
    rel_img = os.path.relpath(img, out.parent)
    text = f"""# Solver core: exact branch-and-bound vs the previous implementation

Generated by `python benchmarks/solver_core.py{" --quick" if quick else ""}` in {res["total"]:.0f} s.
{res["env"]}. Load average (1 min) at start {res["load"][0]:.2f}, at end {res["load"][1]:.2f}.

![solver core]({rel_img})

{READING}
## 1. case 1: iterative max resistible wrench, 8 XY directions (upper 1e3 N, 20 steps)

Median time per direction: new **{1e3 * s1["med"]["new"]:.0f} ms**, old **{s1["med"]["old"]:.2f} s**
(ratio of medians **{s1["ratio_median"]:.1f}×**, median of per-direction ratios
{s1["ratio_per_dir_median"]:.1f}×, total {s1["tot"]["old"]:.1f} s vs {s1["tot"]["new"]:.2f} s =
{s1["ratio_total"]:.1f}×). The bisection instead of the secant: median
{1e3 * s1["med"]["bisection"]:.0f} ms; without the subspace jump: median {s1["med"]["noaccel"]:.2f} s
(each direction capped at {c1["cap"]:.0f} s; "+" marks a capped run). New core: median of
{c1["repeat"]} runs.

{t_case1}

BLAS threads: every number above ran with single-threaded BLAS (`OPENBLAS_NUM_THREADS=1`, see the
reading guide). The same default-search queries with the BLAS library's default threads (one per
CPU), new and old, in subprocesses:

{t_blas}

{t_prof}

Shares are exclusive and add up to 100 %; cProfile's per-call overhead inflates the Python parts.

## 2. Single PRP solve ({pr["n"]} random moderate wrenches per grasp, command 1 per actuator)

{t_prp}

## 3. Pinch (analytic, 2 contacts), upper 100 N, 20 steps

{t_pinch}

## 4. case 2: 72-direction iterative profile (preload `finger1_only`, upper 50 N, 20 steps)

{t_case2}

## 5. Agreement of step optima: branch-and-bound vs SCIP

{t_ag}
"""
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    return text
