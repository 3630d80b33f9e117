"""Sections 1-4 of ``benchmarks/solver_core.py``: case 1, single PRP solves, the pinch, case 2."""

from __future__ import annotations

import cProfile
import pstats
import signal
import statistics
import time
from pathlib import Path

import numpy as np
from solver_core_common import ANGLES, PINCH_DIRS, PRP_SIZES, ROOT, SCIP_TIME_LIMIT, fmt_row, q, status_of, xy
from solver_core_worker import run_old


# =====================================================================================
# new core (imports deferred so that the old worker never sees them)
# =====================================================================================
class _Capped(Exception):
    pass


def _alarm(_sig, _frame):
    raise _Capped


def timed_query(model, command, d, cap: float | None = None, **kw) -> dict:
    """One max_resistible_wrench query of the new core; ``cap`` [s] stops it (reported)."""
    import pinograsp as pg

    if cap:
        signal.signal(signal.SIGALRM, _alarm)
        signal.setitimer(signal.ITIMER_REAL, cap)
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        r = pg.max_resistible_wrench(model, command, d, **kw)
        row = dict(
            magnitude=float(r.magnitude),
            unbounded=bool(r.unbounded),
            status=status_of(r),
            stages=len(r.evidence),
            n_solves=int(r.n_solves),
            capped=False,
            error="",
        )
    except _Capped:
        row = dict(magnitude=float("nan"), unbounded=False, stages=0, n_solves=0, capped=True, error="")
    except Exception as exc:  # reported, never hidden
        row = dict(
            magnitude=float("nan"),
            unbounded=False,
            stages=0,
            n_solves=0,
            capped=False,
            error=f"{type(exc).__name__}: {exc}",
        )
    finally:
        if cap:
            signal.setitimer(signal.ITIMER_REAL, 0)
    row.update(wall=time.perf_counter() - t0, cpu=time.process_time() - c0)
    return row


# ----------------------------------------------------------------------------- profile
def _edges(st: pstats.Stats, callee_pred, caller_pred) -> float:
    """Total time of calls of a callee (by predicate on its key) from callers (predicate)."""
    tot = 0.0
    for key, (_cc, _nc, _tt, _ct, callers) in st.stats.items():  # type: ignore[attr-defined]
        if not callee_pred(key):
            continue
        for ck, val in callers.items():
            if caller_pred(ck):
                tot += val[3] if len(val) > 3 else 0.0
    return tot


def _ct(st: pstats.Stats, pred) -> float:
    return sum(v[3] for k, v in st.stats.items() if pred(k))  # type: ignore[attr-defined]


class _DaqpShim:
    """``daqp`` with ``solve`` wrapped in a Python function, so that cProfile sees its calls
    (the C extension's function is invisible to it) and their callers."""

    def __init__(self, mod) -> None:
        self._mod = mod

    def __getattr__(self, name):
        return getattr(self._mod, name)

    def solve(self, *a, **kw):  # noqa: D102
        return self._mod.solve(*a, **kw)


def profile_direction(model, command, angle: float) -> dict:
    """cProfile of one direction: exclusive shares by what runs, inclusive ones by B&B stage."""
    import pinograsp as pg
    from pinograsp.solvers import node_qp

    real = node_qp.daqp
    node_qp.daqp = _DaqpShim(real)
    pr = cProfile.Profile()
    t0 = time.perf_counter()
    try:
        pr.enable()
        r = pg.max_resistible_wrench(model, command, xy(angle), "iterative", upper=1e3, steps=20)
        pr.disable()
    finally:
        node_qp.daqp = real
    wall = time.perf_counter() - t0
    st = pstats.Stats(pr)
    total = st.total_tt  # type: ignore[attr-defined]

    def fn(file_end, name):
        return lambda k: k[0].endswith(file_end) and k[2] == name

    nq = "solvers/node_qp.py"
    shim = fn("solver_core.py", "solve")
    daqp_node = _edges(st, shim, fn(nq, "solve"))
    daqp_proj = _edges(st, shim, fn(nq, "project"))
    daqp_canon = _edges(st, shim, fn(nq, "_daqp"))
    clarabel = _ct(st, fn(nq, "interior_point"))
    svd = _ct(st, lambda k: k[2] == "svd" and "linalg" in k[0])
    build = _ct(st, fn("solvers/problem.py", "build_problem")) + _ct(st, fn(nq, "__init__"))
    what = {
        "DAQP: node QPs (incl. retries)": daqp_node,
        "DAQP: infeasibility projections": daqp_proj,
        "DAQP: canonical-point QPs (largest step, least energy, least norm)": daqp_canon,
        "Clarabel fallback": clarabel,
        "numpy SVD (polish, canonical point, independent rows)": svd,
        "problem building (build_problem, NodeQP matrices)": build,
    }
    what["other Python/numpy (B&B tree, feasibility checks, scheme, search, results)"] = total - sum(
        what.values()
    )
    where = {
        "node QPs (`NodeQP.solve`)": _ct(st, fn(nq, "solve")),
        "polish of the optimal face": _ct(st, fn(nq, "polish")),
        "canonical point (`BranchAndBound._canonical`)": _ct(st, fn("solvers/bnb.py", "_canonical")),
        "subspace jumps (`jump`)": _ct(st, fn("pinograsp/analysis/stages.py", "jump")),
    }
    ncalls = {k: v[1] for k, v in st.stats.items()}  # type: ignore[attr-defined]
    return dict(
        angle=angle,
        wall=wall,
        total=total,
        shares=what,
        where=where,
        n_daqp=int(sum(n for k, n in ncalls.items() if shim(k))),
        n_clarabel=int(sum(n for k, n in ncalls.items() if fn(nq, "interior_point")(k))),
        n_svd=int(sum(n for k, n in ncalls.items() if k[2] == "svd" and "linalg" in k[0])),
        n_solves=int(r.n_solves),
        stages=len(r.evidence),
    )


# ----------------------------------------------------------------------------- section 1
def section_case1(quick: bool, root: Path, repeat: int) -> dict:
    import pinograsp as pg

    sc = pg.load_scene("case1")
    angles = (30, 270) if quick else ANGLES
    cap = 15.0 if quick else 40.0
    base = dict(method="iterative", upper=1e3, steps=20)
    new, bis, noacc = [], [], []
    for ang in angles:
        runs = [timed_query(sc.model, sc.command, xy(ang), **base) for _ in range(repeat)]
        row = dict(
            runs[-1],
            angle=ang,
            wall=statistics.median(r["wall"] for r in runs),
            cpu=statistics.median(r["cpu"] for r in runs),
        )
        new.append(row)
        bis.append(dict(timed_query(sc.model, sc.command, xy(ang), search="bisection", **base), angle=ang))
        noacc.append(
            dict(timed_query(sc.model, sc.command, xy(ang), cap=cap, accelerate=False, **base), angle=ang)
        )
        print(
            f"  case1 {ang:4d} deg: new {row['wall']:.3f} s ({fmt_row(row)}), "
            f"bisection {bis[-1]['wall']:.3f} s, accelerate=False {noacc[-1]['wall']:.2f} s"
            f"{' (capped)' if noacc[-1]['capped'] else ''} "
            f"({fmt_row(noacc[-1])})",
            flush=True,
        )
    prof = [profile_direction(sc.model, sc.command, a) for a in ((30,) if quick else (30, 90))]
    print("  old implementation (subprocess) ...", flush=True)
    old = run_old(root, "case1", angles=list(angles))
    print("  default BLAS threads (subprocesses): new, old ...", flush=True)
    newd = run_old(ROOT, "case1", blas_default=True, tag="new, default BLAS threads", angles=list(angles))
    oldd = run_old(root, "case1", blas_default=True, tag="old, default BLAS threads", angles=list(angles))
    return dict(
        angles=list(angles),
        new=new,
        bisection=bis,
        noaccel=noacc,
        old=old["rows"],
        profile=prof,
        cap=cap,
        old_file=old["pinograsp_file"],
        new_blasd=newd["rows"],
        old_blasd=oldd["rows"],
        repeat=repeat,
    )


# ----------------------------------------------------------------------------- section 2
def rand_wrench(rng: np.random.Generator, model, F0: float, lo: float = 0.1, hi: float = 1.0) -> np.ndarray:
    """A random wrench (model coordinates): forces ~ F0 * a, torques ~ F0 * a * length scale,
    ``a`` log-uniform in [lo, hi]."""
    a = float(np.exp(rng.uniform(np.log(lo), np.log(hi))))
    w = rng.normal(size=model.nw) * F0 * a / np.sqrt(model.nw)
    w[(2 if model.planar else 3) :] *= model.length_scale
    return w


def force_scale(form, model, command) -> float:
    return form.scale_data(np.zeros(model.nw), model.command_vector(command)).F


def section_prp(quick: bool, root: Path) -> dict:
    import pinograsp as pg
    from pinograsp.core.examples import random_grasp
    from pinograsp.solvers import BranchAndBound, Formulation, build_problem
    from pinograsp.solvers.miqp import CvxpyMIQP

    n = 5 if quick else 30
    sizes = PRP_SIZES[:4] if quick else PRP_SIZES
    configs, res = [], {}
    for nc, cpf in sizes:
        label = f"{nc} contacts, {'two' if cpf == 2 else 'one'}-link"
        seed = 1000 + 10 * nc + cpf
        m = random_grasp(seed, n_pairs=nc // (2 * cpf), contacts_per_finger=cpf, planar=False)
        assert m.nc == nc
        form = Formulation(m)
        F0 = force_scale(form, m, 1.0)
        rng = np.random.default_rng(seed)
        W = [rand_wrench(rng, m, F0) for _ in range(n)]
        configs.append(
            dict(
                label=label,
                seed=seed,
                n_pairs=nc // (2 * cpf),
                cpf=cpf,
                wrenches=[m.expand_wrench(w).tolist() for w in W],
            )
        )
        miqp = CvxpyMIQP(form, "prp", time_limit=SCIP_TIME_LIMIT)
        miqp.solve(form.scale_data(np.zeros(m.nw), m.command_vector(1.0)), 1e3)  # warm-up
        pg.passive_response(m, 1.0, np.zeros(6), method="prp")  # warm-up
        r = dict(
            bnb=[],
            nodes=[],
            qps=[],
            attempts=[],
            scip=[],
            api=[],
            bnb_status=[],
            scip_status=[],
            api_resisted=[],
            errors=[],
        )
        for w in W:
            data = form.scale_data(w, m.command_vector(1.0))
            t0 = time.perf_counter()
            bb = BranchAndBound(build_problem(form, "prp", data))
            raw = bb.solve()
            r["bnb"].append(time.perf_counter() - t0)
            s = bb.stats()
            r["nodes"].append(s.nodes)
            r["qps"].append(s.qps)
            r["attempts"].append(s.attempts)
            r["bnb_status"].append(str(raw.status.value))
            t0 = time.perf_counter()
            sol = miqp.solve(data, 1e3)
            r["scip"].append(time.perf_counter() - t0)
            r["scip_status"].append(str(sol.status.value))
            t0 = time.perf_counter()
            try:
                resp = pg.passive_response(m, 1.0, m.expand_wrench(w), method="prp")
                r["api_resisted"].append(bool(resp.resistible))
            except Exception as exc:
                r["errors"].append(f"{type(exc).__name__}: {exc}")
                r["api_resisted"].append(None)
            r["api"].append(time.perf_counter() - t0)
        res[label] = r
        print(
            f"  PRP {label:22s}: B&B {1e3 * statistics.median(r['bnb']):7.2f} ms (p90 "
            f"{1e3 * q(r['bnb'], 90):7.2f}), "
            f"SCIP {1e3 * statistics.median(r['scip']):7.1f} ms, nodes median "
            f"{statistics.median(r['nodes'])}",
            flush=True,
        )
    print("  old implementation (subprocess) ...", flush=True)
    old = run_old(root, "prp", configs=configs)["prp"]
    print("  B&B with default BLAS threads (subprocess) ...", flush=True)
    bnbd = run_old(ROOT, "prp_bnb", blas_default=True, tag="new", configs=configs)["prp"]
    return dict(new=res, old=old, n=n, bnb_blasd=bnbd)


# ----------------------------------------------------------------------------- section 3
def section_pinch(quick: bool, root: Path, repeat: int) -> dict:
    from pinograsp import examples

    rows = []
    for name, d in PINCH_DIRS.items():
        for method in ("iterative", "prp"):
            ts, last = [], None
            for _ in range(repeat):
                last = timed_query(examples.pinch(), 1.0, d, method=method, upper=100.0, steps=20)
                ts.append(last["wall"])
            rows.append(
                dict(
                    dir=name,
                    method=method,
                    walls=ts,
                    magnitude=last["magnitude"],
                    unbounded=last["unbounded"],
                    status=last.get("status", ""),
                    stages=last["stages"],
                    error=last["error"],
                )
            )
    old = run_old(root, "pinch", dirs=PINCH_DIRS, repeat=max(1, repeat - 2))
    return dict(new=rows, old=old["rows"])


# ----------------------------------------------------------------------------- section 4
def section_case2(quick: bool, root: Path) -> dict:
    import pinograsp as pg

    sc = pg.load_scene("case2")
    cmd = sc.preload("finger1_only")
    n = 6 if quick else 72
    n_old = 1 if quick else 6

    def progress(done, total):
        if done % max(1, total // 6) == 0:
            print(f"    case2 profile {done}/{total} ({time.perf_counter() - t0:.0f} s)", flush=True)

    t0 = time.perf_counter()
    err = ""
    try:
        prof = pg.resistance_profile(
            sc.model, cmd, ("fx", "fy"), n=n, upper=50.0, steps=20, progress=progress
        )
        mags = [float(x) for x in prof.magnitudes]
        unb = [bool(x) for x in prof.unbounded]
        sts = [status_of(r) for r in prof.results]
        walls = [float(r.wall_time) for r in prof.results]
        stages = [len(r.evidence) for r in prof.results]
    except Exception as exc:
        err = f"{type(exc).__name__}: {exc}"
        mags, unb, walls, stages, sts = [], [], [], [], []
    wall = time.perf_counter() - t0
    print(f"  case2 profile, {n} directions: {wall:.1f} s; old on {n_old} directions ...", flush=True)
    old = run_old(root, "case2", n=n_old)
    return dict(
        n=n,
        wall=wall,
        magnitudes=mags,
        unbounded=unb,
        status=sts,
        dir_walls=walls,
        stages=stages,
        error=err,
        old=old,
        step=n // n_old,
    )
