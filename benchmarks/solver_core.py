"""The new solver core (exact branch-and-bound) against the previous implementation and SCIP.

Measures in one run, on this machine:

1. case 1, iterative max resistible wrench along 8 XY directions (upper 1e3, 20 steps): the new
   core (default secant search), the new core with ``search="bisection"`` and with
   ``accelerate=False``, and the previous implementation (commit ``fc3d54a``, its defaults:
   ProxSuite mode-guess fast path with certificates) in a subprocess; where the new core's time
   goes (cProfile);
2. single PRP solves at 4, 8 and 12 contacts, one- and two-link fingers: ``BranchAndBound``,
   the reference ``CvxpyMIQP`` (SCIP), the new public ``pg.passive_response`` and the previous
   implementation's ``pg.passive_response`` (subprocess), with the branch-and-bound's node
   counts;
3. the analytic pinch (``fy`` and ``(1, 1, 0)``, upper 100), iterative and PRP, new vs old;
4. case 2's 72-direction iterative profile (preload ``finger1_only``, upper 50): the new core in
   full; the old one on 6 of the directions, extrapolated;
5. agreement of single step optima (PRP and movement steps, random data and real iteration
   steps) between the branch-and-bound and SCIP on >= 200 grasps.

Writes ``docs/solver_core.md`` and ``docs/img/solver_core.png`` and prints the tables::

    python benchmarks/solver_core.py            # full run (~15 min on 2 cores)
    python benchmarks/solver_core.py --quick    # smoke run (~2 min; report to a temp dir)
    python benchmarks/solver_core.py --reproduce g017-move1   # one agreement problem

The previous implementation is run from a git worktree of ``fc3d54a`` (``--old PATH``; default
``/tmp/pinograsp_old``, or ``/tmp/old`` when that is a worktree of the commit; created with
``git worktree add`` when neither exists) with ``PYTHONPATH`` pointing there.
"""

from __future__ import annotations

import os
import sys

#: Every measurement runs with single-threaded BLAS unless ``--blas-default`` is given (set
#: before numpy is imported; a value the caller exported is kept). numpy's OpenBLAS starts one
#: thread per CPU, and on this 2-core machine its threaded SVDs (the polish and canonical point
#: of every branch-and-bound solve) were 3-80x slower than single-threaded ones whenever another
#: process used the other core, which made the new core's times swing 10x with the machine's
#: load. The default-thread times are measured separately (section 1, 2).
BLAS1 = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
if "--blas-default" not in sys.argv:
    for _k, _v in BLAS1.items():
        os.environ.setdefault(_k, _v)

import argparse  # noqa: E402
import cProfile  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import pstats  # noqa: E402
import signal  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from collections import Counter  # noqa: E402
from importlib.metadata import version  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OLD_COMMIT = "fc3d54a"
ANGLES = (0, 30, 45, 60, 90, 135, 180, 270)
PRP_SIZES = ((4, 1), (4, 2), (8, 1), (8, 2), (12, 1), (12, 2))  # (contacts, contacts per finger)
PINCH_DIRS = {"fy": "fy", "(1,1,0)": [1.0, 1.0, 0.0, 0.0, 0.0, 0.0]}
PINCH_CLOSED = {"fy": 10.0, "(1,1,0)": 10.0 * np.sqrt(2.0)}
#: agreement: B&B objective <= SCIP * (1 + REL) + ABS counts as "agree or lower"
REL, ABS = 1e-6, 1e-12
SCIP_TIME_LIMIT = 30.0


def xy(angle: float) -> list[float]:
    a = np.radians(angle)
    return [float(np.cos(a)), float(np.sin(a)), 0.0, 0.0, 0.0, 0.0]


def q(values, p: float) -> float:
    v = np.asarray(values, float)
    return float(np.percentile(v, p)) if len(v) else float("nan")


def status_of(r) -> str:
    """A MaxWrench's status: the new core's ``status`` (finite, unbounded, above_limit,
    below_resolution), the old one's ``unbounded`` flag."""
    st = getattr(r, "status", None)
    return str(st) if st is not None else ("unbounded" if r.unbounded else "finite")


def fmt_mag(mag: float, unbounded: bool, status: str = "") -> str:
    if status == "above_limit":
        return f"≥ {mag:.4g} (above_limit)"
    if status == "below_resolution":
        return "below resolution"
    return "unbounded" if unbounded else f"{mag:.4g}"


def fmt_row(r: dict) -> str:
    return fmt_mag(r["magnitude"], r["unbounded"], r.get("status", ""))


# =====================================================================================
# the previous implementation, run in a subprocess (old API only below this line)
# =====================================================================================
def api_worker(job_file: str, out_file: str) -> None:
    """Runs in a subprocess with PYTHONPATH = the tree to measure (the old worktree, or this
    one with single-threaded BLAS); public API common to both versions only."""
    job = json.loads(Path(job_file).read_text())
    import pinograsp as pg

    where = str(Path(pg.__file__).resolve())
    if not where.startswith(str(Path(job["root"]).resolve())):
        raise SystemExit(f"worker imported pinograsp from {where}, not {job['root']}")
    out: dict = {"pinograsp_file": where}
    task = WORKER_TASKS.get(job["task"])
    if task is not None:
        out.update(task(job))
    Path(out_file).write_text(json.dumps(out))


def _example_grasps() -> tuple:
    """``(pinch, random_grasp)``: from ``pinograsp.examples``, or in the old tree (fc3d54a), which
    has no such module, from its ``analytic`` and ``synthetic`` modules."""
    try:
        from pinograsp import examples
    except ImportError:
        from pinograsp import analytic, synthetic

        return analytic.pinch, synthetic.random_grasp
    return examples.pinch, examples.random_grasp


def _task_case1(job: dict) -> dict:
    """Case 1, iterative max wrench along ``job["angles"]`` (upper 1e3, 20 steps)."""
    import pinograsp as pg

    sc = pg.load_scene("case1")
    rows = []
    for ang in job["angles"]:
        t0, c0 = time.perf_counter(), time.process_time()
        r = pg.max_resistible_wrench(sc.model, sc.command, xy(ang), "iterative", upper=1e3, steps=20)
        rows.append(
            dict(
                angle=ang,
                wall=time.perf_counter() - t0,
                cpu=time.process_time() - c0,
                magnitude=float(r.magnitude),
                unbounded=bool(r.unbounded),
                status=status_of(r),
                stages=len(r.evidence),
                n_solves=int(r.n_solves),
                n_miqp=int(getattr(r, "n_miqp", -1)),
            )
        )
        print(f"    {job['tag']} case1 {ang:4d} deg: {rows[-1]['wall']:.2f} s", flush=True)
    return {"rows": rows}


def _task_prp(job: dict) -> dict:
    """Single PRP solves on random grasps: wall and solve times, verdicts."""
    import pinograsp as pg

    _, random_grasp = _example_grasps()
    res = {}
    for cfg in job["configs"]:
        m = random_grasp(cfg["seed"], n_pairs=cfg["n_pairs"], contacts_per_finger=cfg["cpf"], planar=False)
        pg.passive_response(m, 1.0, np.zeros(6), method="prp")  # warm-up (cvxpy compile)
        walls, solves, ok, miqp = [], [], [], []
        for w in cfg["wrenches"]:
            t0 = time.perf_counter()
            r = pg.passive_response(m, 1.0, w, method="prp")
            walls.append(time.perf_counter() - t0)
            solves.append(r.solve_time)
            ok.append(bool(r.resistible))
            miqp.append(int(getattr(r, "n_miqp", -1)))
        res[cfg["label"]] = dict(wall=walls, solve=solves, resisted=ok, n_miqp=miqp)
    return {"prp": res}


def _task_prp_bnb(job: dict) -> dict:
    """New tree only: the solver layer's PRP time (branch-and-bound alone)."""
    from pinograsp import examples
    from pinograsp.solvers import BranchAndBound, Formulation, build_problem

    res = {}
    for cfg in job["configs"]:
        m = examples.random_grasp(
            cfg["seed"], n_pairs=cfg["n_pairs"], contacts_per_finger=cfg["cpf"], planar=False
        )
        form = Formulation(m)
        ts = []
        for w in cfg["wrenches"]:
            data = form.scale_data(m.reduce_wrench(np.asarray(w)), m.command_vector(1.0))
            t0 = time.perf_counter()
            BranchAndBound(build_problem(form, "prp", data)).solve()
            ts.append(time.perf_counter() - t0)
        res[cfg["label"]] = ts
    return {"prp": res}


def _task_pinch(job: dict) -> dict:
    """The analytic pinch along ``job["dirs"]``, iterative and PRP (upper 100, 20 steps)."""
    import pinograsp as pg

    pinch, _ = _example_grasps()
    rows = []
    for name, d in job["dirs"].items():
        for method in ("iterative", "prp"):
            ts, mag = [], None
            for _ in range(job["repeat"]):
                m = pinch()
                t0 = time.perf_counter()
                r = pg.max_resistible_wrench(m, 1.0, d, method, upper=100.0, steps=20)
                ts.append(time.perf_counter() - t0)
                mag, unb, st = float(r.magnitude), bool(r.unbounded), len(r.evidence)
            rows.append(
                dict(
                    dir=name,
                    method=method,
                    walls=ts,
                    magnitude=mag,
                    unbounded=unb,
                    stages=st,
                    status=status_of(r),
                )
            )
    return {"rows": rows}


def _task_case2(job: dict) -> dict:
    """Case 2's iterative XY profile (preload ``finger1_only``, upper 50, 20 steps)."""
    import pinograsp as pg

    sc = pg.load_scene("case2")
    cmd = sc.preload("finger1_only")
    t0 = time.perf_counter()
    prof = pg.resistance_profile(sc.model, cmd, ("fx", "fy"), n=job["n"], upper=50.0, steps=20)
    return {
        "wall": time.perf_counter() - t0,
        "angles": [float(np.degrees(a)) for a in prof.angles],
        "magnitudes": [float(x) for x in prof.magnitudes],
        "unbounded": [bool(x) for x in prof.unbounded],
        "status": [status_of(r) for r in prof.results],
        "dir_walls": [float(r.wall_time) for r in prof.results],
    }


WORKER_TASKS = {
    "case1": _task_case1,
    "prp": _task_prp,
    "prp_bnb": _task_prp_bnb,
    "pinch": _task_pinch,
    "case2": _task_case2,
}


def old_root(arg: str | None) -> Path:
    """A worktree of OLD_COMMIT (made if needed)."""

    def at_commit(p: Path) -> bool:
        if not (p / "pinograsp" / "__init__.py").exists():
            return False
        head = subprocess.run(["git", "-C", str(p), "rev-parse", "HEAD"], capture_output=True, text=True)
        full = subprocess.run(
            ["git", "-C", str(ROOT), "rev-parse", OLD_COMMIT], capture_output=True, text=True
        ).stdout.strip()
        return head.returncode == 0 and head.stdout.strip() == full

    cands = [Path(arg)] if arg else [Path("/tmp/pinograsp_old"), Path("/tmp/old")]
    for p in cands:
        if at_commit(p):
            return p
    p = cands[0]
    if p.exists():
        raise SystemExit(f"{p} exists but is not a worktree of {OLD_COMMIT}")
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(p), OLD_COMMIT], check=True)
    return p


def run_old(root: Path, task: str, blas_default: bool = False, tag: str = "old", **job) -> dict:
    """One task of the tree ``root`` (the old worktree by default) in a subprocess (blocking:
    nothing else runs meanwhile); same BLAS threads as this process, or ``blas_default``: the
    library's default threads."""
    with tempfile.TemporaryDirectory() as tmp:
        jf, of = Path(tmp) / "job.json", Path(tmp) / "out.json"
        jf.write_text(json.dumps(dict(job, task=task, root=str(root), tag=tag)))
        env = dict(os.environ, PYTHONPATH=str(root))
        flag = []
        if blas_default:
            for k in BLAS1:
                env.pop(k, None)
            flag = ["--blas-default"]
        subprocess.run(
            [sys.executable, str(Path(__file__).resolve()), "--worker", str(jf), str(of), *flag],
            env=env,
            cwd=tmp,
            check=True,
        )
        return json.loads(of.read_text())


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
        "subspace jumps (`_jump`)": _ct(st, fn("pinograsp/analysis/response.py", "_jump")),
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


# ----------------------------------------------------------------------------- section 5
def agreement_instances(quick: bool) -> list[dict]:
    """Grasps of the agreement test: (id, label, factory, command)."""
    import pinograsp as pg
    from pinograsp import examples
    from pinograsp.core.examples import random_grasp

    combos = [(npairs, 1, pl) for npairs in range(1, 7) for pl in (True, False)]
    combos += [(npairs, 2, pl) for npairs in range(1, 4) for pl in (True, False)]
    per = 1 if quick else 12
    out = []
    gid = 0
    for _ in range(per):
        for npairs, cpf, planar in combos:
            seed = 5000 + gid
            link = "two" if cpf == 2 else "one"
            space = "planar" if planar else "3D"
            label = f"random seed {seed}: {2 * npairs * cpf} contacts, {link}-link, {space}"
            out.append(
                dict(
                    id=f"g{gid:03d}",
                    label=label,
                    factory=(
                        lambda s=seed, a=npairs, b=cpf, c=planar: random_grasp(
                            s, n_pairs=a, contacts_per_finger=b, planar=c
                        )
                    ),
                    command=1.0,
                    code=(
                        f"random_grasp({seed}, n_pairs={npairs}, contacts_per_finger={cpf}, planar={planar})"
                    ),
                )
            )
            gid += 1
    scenes = {}
    for name in ("case1", "case3"):
        sc = pg.load_scene(name)
        scenes[name] = (lambda sc=sc: sc.model, sc.command, f'pg.load_scene("{name}").model')
    scenes["pinch"] = (examples.pinch, 1.0, "examples.pinch()")
    scenes["wedge"] = (examples.wedge, 1.0, "examples.wedge()")
    for rep in range(1 if quick else 8):
        for name, (fac, cmd, code) in scenes.items():
            out.append(
                dict(id=f"g{gid:03d}", label=f"{name} (draw {rep})", factory=fac, command=cmd, code=code)
            )
            gid += 1
    return out


def agreement_problems(inst: dict) -> list[tuple[str, str, object, object, float]]:
    """The problems of one grasp: (name, kind, form, data, gamma)."""
    import pinograsp as pg
    from pinograsp.solvers import BranchAndBound, ScaledData, build_problem

    m = inst["factory"]()
    sess = pg.Session(m)
    form, gamma = sess.form, sess.options.gamma
    fc = m.command_vector(inst["command"])
    rng = np.random.default_rng([int(inst["id"][1:]), 7])
    if rng.uniform() < 0.5 and m.na > 1:
        fc = fc * rng.uniform(0.5, 1.5, size=m.na)  # a random (possibly unbalanced) preload
    F0 = force_scale(form, m, fc)
    # the preload's normal forces (spring pre-compression of the preload-first variant)
    pre = BranchAndBound(build_problem(form, "prp", form.scale_data(np.zeros(m.nw), fc))).solve()
    p = (form.E @ pre.z[form.layout("prp")["beta"]]) * F0 if pre.status == "optimal" else np.zeros(m.nc)
    probs = []
    w1 = rand_wrench(rng, m, F0, 0.05, 2.0)
    probs.append(("prp0", "prp", form, form.scale_data(w1, fc), gamma))
    w2 = rand_wrench(rng, m, F0, 0.05, 2.0)
    probs.append(("prp1", "prp", form, form.scale_data(w2, fc, p), gamma))
    w3 = rand_wrench(rng, m, F0, 0.05, 2.0)
    d3 = form.scale_data(w3, fc, p)
    probs.append(
        ("move0", "move", form, ScaledData(d3.F, d3.w, d3.fc, d3.p, np.zeros(form.nx), d3.w.copy()), gamma)
    )
    w4 = rand_wrench(rng, m, F0, 0.05, 2.0)
    d4 = form.scale_data(w4, fc, p)
    x0 = rng.normal(size=form.nx) * 0.3
    dirn = d4.w + rng.normal(size=form.nx) * 0.5 * max(np.linalg.norm(d4.w), 1e-3)
    probs.append(("move1", "move", form, ScaledData(d4.F, d4.w, d4.fc, d4.p, x0, dirn), gamma))
    # PRP just above and just below the exact limit along a random direction (where the late
    # stages of a bisection solve: the nearly degenerate problems)
    lim = None
    for _ in range(4):  # the PRP often resists everything (locked fingers): try a few directions
        d6 = m.expand_wrench(rand_wrench(rng, m, 1.0, 1.0, 1.0))
        d6 /= np.linalg.norm(d6)
        try:
            lf = sess.max_load_factor(fc, d6, 1e3 * F0)
        except Exception:
            continue
        if lf.status == "optimal" and np.isfinite(lf.magnitude) and lf.magnitude > 0:
            lim = lf.magnitude
            break
    if lim is not None and lim > 0:
        for tag, f in (
            ("edge+5", 1 + 1e-5),
            ("edge-5", 1 - 1e-5),
            ("edge+7", 1 + 1e-7),
            ("edge-7", 1 - 1e-7),
        ):
            probs.append(
                (f"prp{tag}", "prp", form, form.scale_data(m.reduce_wrench(lim * f * d6), fc), gamma)
            )
    # real steps of an iterative trajectory (the B&B drives it; the problems are compared)
    w5 = rand_wrench(rng, m, F0, 0.05, 2.0)
    rec = []
    orig = sess.solve

    def capture(kind, data, guess=None):
        rec.append((str(getattr(kind, "value", kind)), data))
        return orig(kind, data, guess)

    sess.solve = capture  # type: ignore[method-assign]
    try:
        sess.response(fc, m.expand_wrench(w5), "iterative")
    except Exception:  # the trajectory's own failure is not this test's subject
        pass
    steps = [d for k, d in rec if k == "move" and np.any(d.w != 0)]
    if steps:
        for j, i in enumerate(sorted({1 % len(steps), len(steps) // 2, len(steps) - 1})):
            probs.append((f"traj{j}", "move", form, steps[i], gamma))
    return probs


def _violation(P, z) -> float:
    v = P.C @ z
    out = max(
        float(np.abs(P.A @ z - P.b).max(initial=0.0)),
        float(np.maximum(P.lo - v, 0).max(initial=0.0)),
        float(np.maximum(v - P.up, 0).max(initial=0.0)),
    )
    return max(out, float(P.complementarity(z).max(initial=0.0)))


def compare_one(kind, form, data, gamma) -> dict:
    """B&B vs SCIP on one problem, with diagnostics."""
    from pinograsp.solvers import BranchAndBound, build_problem
    from pinograsp.solvers.miqp import CvxpyMIQP

    P = build_problem(form, kind, data, gamma)
    out: dict = {}
    t0 = time.perf_counter()
    try:
        bb = BranchAndBound(P)
        rb = bb.solve()
        out.update(
            bnb_status=str(rb.status.value),
            bnb_obj=float(rb.objective),
            bnb_nodes=bb.stats().nodes,
            bnb_viol=_violation(P, rb.z) if rb.z is not None else float("nan"),
            bnb_msg=rb.message,
        )
    except Exception as exc:
        out.update(
            bnb_status="crash",
            bnb_obj=float("nan"),
            bnb_nodes=0,
            bnb_viol=float("nan"),
            bnb_msg=f"{type(exc).__name__}: {exc}",
        )
        rb = None
    out["bnb_time"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    M, tries = 1e3, 0
    try:
        miqp = CvxpyMIQP(form, kind, gamma=gamma, time_limit=SCIP_TIME_LIMIT)
        while True:  # the engine's big-M enlargement
            rs = miqp.solve(data, M)
            if rs.status != "optimal" or rs.bigm_ratio < 0.1 or tries >= 2:
                break
            M, tries = M * 100, tries + 1
        out.update(
            scip_status=str(rs.status.value),
            scip_obj=float(rs.objective),
            scip_bigm=rs.bigm_ratio,
            scip_M=M,
            scip_msg=rs.message,
        )
        if rs.z is not None:
            out["scip_viol"] = _violation(P, rs.z)
            pol = BranchAndBound(P).solve_mode(rs.mode)  # SCIP's mode, solved exactly
            out["scip_mode_exact"] = (
                float(pol.objective) if pol.status == "optimal" else str(pol.status.value)
            )
    except Exception as exc:
        out.update(scip_status="crash", scip_obj=float("nan"), scip_msg=f"{type(exc).__name__}: {exc}")
    out["scip_time"] = time.perf_counter() - t0
    b, s = out["bnb_status"], out["scip_status"]
    if b != s:
        out["cls"] = "status mismatch"
    elif b != "optimal":
        out["cls"] = "same status (both " + b + ")"
    else:
        bo, so = out["bnb_obj"], out["scip_obj"]
        if bo <= so * (1 + REL) + ABS:
            out["cls"] = "B&B lower" if bo < so * (1 - REL) - ABS else "agree"
        else:
            out["cls"] = "B&B higher"
    return out


def section_agreement(quick: bool) -> dict:
    insts = agreement_instances(quick)
    rows = []
    t0 = time.perf_counter()
    for i, inst in enumerate(insts):
        try:
            probs = agreement_problems(inst)
        except Exception as exc:
            rows.append(
                dict(
                    id=inst["id"],
                    label=inst["label"],
                    name="setup",
                    kind="-",
                    cls="crash",
                    bnb_status="crash",
                    scip_status="-",
                    bnb_msg=f"{type(exc).__name__}: {exc}",
                )
            )
            continue
        for name, kind, form, data, gamma in probs:
            r = compare_one(kind, form, data, gamma)
            r.update(id=inst["id"], label=inst["label"], name=name, kind=kind, code=inst["code"])
            rows.append(r)
        if (i + 1) % 20 == 0 or i + 1 == len(insts):
            el = time.perf_counter() - t0
            print(
                f"  agreement: {i + 1}/{len(insts)} grasps, {len(rows)} problems, {el:.0f} s "
                f"(ETA {el / (i + 1) * (len(insts) - i - 1):.0f} s)",
                flush=True,
            )
    return dict(rows=rows, n_grasps=len(insts), wall=time.perf_counter() - t0)


def reproduce(pid: str) -> None:
    gid, name = pid.split("-", 1)
    for inst in agreement_instances(False):
        if inst["id"] == gid:
            break
    else:
        raise SystemExit(f"no grasp {gid}")
    for n, kind, form, data, gamma in agreement_problems(inst):
        if n == name:
            print(inst["label"], inst["code"], kind)
            print(json.dumps(compare_one(kind, form, data, gamma), indent=1, default=str))
            return
    raise SystemExit(f"no problem {name} for {gid}")


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


def diagnose(r: dict) -> str:
    """Which side a disagreement comes from (B&B feasibility tolerance 1e-9, SCIP's 1e-8)."""
    b, sc_ = r.get("bnb_status"), r.get("scip_status")
    me = r.get("scip_mode_exact")
    bv, sv = r.get("bnb_viol", float("nan")), r.get("scip_viol", float("nan"))
    if b in ("failed", "crash", "node_limit"):
        return f"**B&B {b}**"
    if r["cls"] == "B&B higher":
        mode_same = isinstance(me, float) and me >= r["bnb_obj"] * (1 - 1e-9) - 1e-18
        if sv <= 1e-9:
            what = (
                f"the exact QP of SCIP's mode gives {me:.3g}" if isinstance(me, float) else f"its mode: {me}"
            )
            return (
                "**B&B suboptimal: SCIP's point satisfies every row within the B&B's own 1e-9 and is "
                f"better** ({what}: that convex QP is solved inexactly)"
            )
        if mode_same:
            return (
                f"SCIP's point undercuts only by violating rows by {sv:.0e} (its mode, solved exactly = B&B)"
            )
        return "**B&B missed a better mode**"
    if b == "infeasible" and sc_ == "optimal":
        if me == "infeasible" and sv > 1e-9:
            return f"SCIP accepted a point violating rows by {sv:.0e} (its mode has no exact point)"
        return "**B&B missed a feasible mode**"
    if b == "optimal" and sc_ == "infeasible":
        if bv > 1e-9:
            return f"**B&B accepted a point violating rows by {bv:.1e}** (beyond its 1e-9 tolerance)"
        return "SCIP called a feasible problem infeasible"
    return ""


def _agreement_kind(r: dict) -> str:
    """The problem family of an agreement row (a line of the agreement table)."""
    if r["kind"] == "prp":
        return (
            f"PRP at the exact limit × (1 ± 1e-{r['name'][-1]})"
            if "edge" in r["name"]
            else "PRP, random data"
        )
    return "movement step, real trajectory" if r["name"].startswith("traj") else "movement step, random data"


def _diagnosis_counts(rows: list[dict]) -> Counter:
    return Counter(diagnose(r).split(" by ")[0].split(" (")[0].split(":")[0].replace("**", "") for r in rows)


def _relative_excess(r: dict) -> float:
    return (r["bnb_obj"] - r["scip_obj"]) / max(abs(r["scip_obj"]), 1e-300)


def md_agreement(ag: dict) -> str:
    """The agreement section of the report: counts per problem family, then the details."""
    rows = ag["rows"]
    cls = Counter(r["cls"] for r in rows)
    by_kind: dict[str, Counter] = {}
    for r in rows:
        by_kind.setdefault(_agreement_kind(r), Counter())[r["cls"]] += 1
    cats = ["agree", "B&B lower", "B&B higher", "status mismatch"]
    cats += sorted(c for c in cls if c not in cats)
    L = [
        f"{ag['n_grasps']} grasps, {len(rows)} problems, {ag['wall']:.0f} s. Criterion: both optimal and "
        f'B&B objective ≤ SCIP × (1 + {REL:g}) + {ABS:g} ("agree": within that band both ways; "B&B lower": '
        "below it, i.e. SCIP returned a worse point than its proven optimum claims); the objectives are "
        "SCIP's "
        "own point's (not re-polished).",
        "",
        "| problems | " + " | ".join(cats) + " | total |",
        "|---" + "|---:" * (len(cats) + 1) + "|",
    ]
    for key, c in sorted(by_kind.items()):
        L.append(f"| {key} | " + " | ".join(str(c.get(k, 0)) for k in cats) + f" | {sum(c.values())} |")
    L.append("| **all** | " + " | ".join(f"**{cls.get(k, 0)}**" for k in cats) + f" | **{len(rows)}** |")
    higher = [r for r in rows if r["cls"] == "B&B higher"]
    if higher:
        worst = max(_relative_excess(r) for r in higher)
        L += [
            "",
            f'"B&B higher": {len(higher)} (largest relative excess {worst:.1e}): '
            + "; ".join(f"{k}: {v}" for k, v in _diagnosis_counts(higher).most_common())
            + ". SCIP's point is checked against every row of the problem (max violation) and its own mode "
            "is re-solved exactly by the B&B's convex QP.",
        ]
    L += _loose_text(rows) + _timing_text(rows) + _disagreements(rows) + _lower_table(rows)
    return "\n".join(L)


def _loose_text(rows: list[dict]) -> list[str]:
    """B&B "optimal" answers whose point violates a row beyond the B&B's own tolerance."""
    loose = sorted(
        (r for r in rows if r.get("bnb_status") == "optimal" and r.get("bnb_viol", 0.0) > 1e-9),
        key=lambda r: -r["bnb_viol"],
    )
    nopt = sum(r.get("bnb_status") == "optimal" for r in rows)
    if loose:
        listed = " (" + ", ".join(f"{r['id']}-{r['name']} {r['bnb_viol']:.1e}" for r in loose) + ")"
        if all("edge+" in r["name"] for r in loose):
            listed += ": every one a PRP just beyond the exact limit, which is then called resisted."
        else:
            listed += "."
    else:
        listed = "."
    return [
        "",
        f'B&B answers "optimal" whose point violates some row by more than the B&B\'s own feasibility '
        f"tolerance 1e-9: {len(loose)} of {nopt}" + listed,
    ]


def _timing_text(rows: list[dict]) -> list[str]:
    """Objective differences and times where both solvers are optimal."""
    opt = [r for r in rows if r.get("bnb_status") == "optimal" and r.get("scip_status") == "optimal"]
    if not opt:
        return []
    rel = [
        abs(r["bnb_obj"] - r["scip_obj"]) / max(abs(r["scip_obj"]), 1e-300)
        for r in opt
        if r["scip_obj"] > 1e-9
    ]
    bt = [r["bnb_time"] for r in rows if "bnb_time" in r]
    st = [r["scip_time"] for r in rows if "scip_time" in r]
    return [
        "",
        f"Both optimal: {len(opt)}; relative objective difference where SCIP's objective > 1e-9: median "
        f"{statistics.median(rel):.1e}, max {max(rel):.1e}. Time per problem: B&B median "
        f"{1e3 * statistics.median(bt):.1f} ms (p90 {1e3 * q(bt, 90):.1f}, max {1e3 * max(bt):.0f}); "
        "SCIP median "
        f"{1e3 * statistics.median(st):.1f} ms (p90 {1e3 * q(st, 90):.1f}, max {1e3 * max(st):.0f}). "
        f"Largest B&B node count: {max(r.get('bnb_nodes', 0) for r in rows)}.",
    ]


def _disagreements(rows: list[dict]) -> list[str]:
    """The table of problems where the B&B is higher, the statuses differ or a solver crashed."""
    bad = [r for r in rows if r["cls"] in ("B&B higher", "status mismatch", "crash")]
    if not bad:
        return []
    L = [
        "",
        "Disagreements (reproduce one with `python benchmarks/solver_core.py --reproduce ID`):",
        "",
        "| ID | grasp | class | B&B status / objective | SCIP status / objective | relative excess "
        "| B&B point: max violation | SCIP point: max violation | SCIP's mode solved exactly by the B&B "
        "| diagnosis | B&B message |",
        "|---|---|---|---|---|---:|---:|---:|---|---|---|",
    ]
    for r in bad:
        exc = f"{_relative_excess(r):.2e}" if r["cls"] == "B&B higher" else ""
        me = r.get("scip_mode_exact", "—")
        me = f"{me:.10g}" if isinstance(me, float) else str(me)
        L.append(
            f"| {r['id']}-{r['name']} | {r['label']} | {r['cls']} | {r['bnb_status']} / "
            f"{r.get('bnb_obj', float('nan')):.10g} "
            f"| {r.get('scip_status', '?')} / {r.get('scip_obj', float('nan')):.10g} | {exc} "
            f"| {r.get('bnb_viol', float('nan')):.1e} | {r.get('scip_viol', float('nan')):.1e} | {me} "
            f"| {diagnose(r)} | {r.get('bnb_msg', '')[:80]} |"
        )
    return L + [
        "",
        "Diagnoses: " + "; ".join(f"{k}: {v}" for k, v in _diagnosis_counts(bad).most_common()) + ".",
    ]


def _lower_table(rows: list[dict]) -> list[str]:
    """The five largest "B&B lower" cases."""
    low = [r for r in rows if r["cls"] == "B&B lower"]
    if not low:
        return []
    worst = sorted(low, key=lambda r: -(r["scip_obj"] - r["bnb_obj"]) / max(abs(r["scip_obj"]), 1e-300))[:5]
    L = [
        "",
        "Largest \"B&B lower\" cases (SCIP's point worse than the B&B's optimum):",
        "",
        "| ID | grasp | B&B objective | SCIP objective | SCIP's mode solved exactly |",
        "|---|---|---:|---:|---|",
    ]
    for r in worst:
        me = r.get("scip_mode_exact", "—")
        me = f"{me:.6g}" if isinstance(me, float) else str(me)
        L.append(
            f"| {r['id']}-{r['name']} | {r['label']} | {r['bnb_obj']:.6g} | {r['scip_obj']:.6g} | {me} |"
        )
    return L


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
  timing effect: the old fast path's verdicts rested on inexact step optima (SOLVER_NOTES), and
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="smoke run (~2 min); report to a temp dir")
    ap.add_argument("--old", default=None, help=f"worktree of {OLD_COMMIT}")
    ap.add_argument(
        "--out", default=None, help="report path (default docs/solver_core.md; --quick: a temp dir)"
    )
    ap.add_argument("--repeat", type=int, default=3, help="repetitions of the new core's cheap queries")
    ap.add_argument("--worker", nargs=2, metavar=("JOB", "OUT"), help=argparse.SUPPRESS)
    ap.add_argument("--reproduce", metavar="ID", help="re-run one agreement problem, e.g. g017-move1")
    ap.add_argument("--json", default=None, help="also dump the raw measurements here")
    ap.add_argument("--render", metavar="JSON", help="re-render the report from a --json dump")
    ap.add_argument("--blas-default", action="store_true", help="keep the BLAS library's default threads")
    args = ap.parse_args()
    if args.worker:
        api_worker(*args.worker)
        return
    if args.reproduce:
        reproduce(args.reproduce)
        return
    if args.render:  # re-render the report and plot from a --json dump (no measurement)
        res = json.loads(Path(args.render).read_text())
        out = Path(args.out) if args.out else ROOT / "docs" / "solver_core.md"
        img = out.parent / "img" / "solver_core.png"
        print(write_report(res, out, img, False))
        plot(res, img)
        return
    import pinograsp as pg

    if not str(Path(pg.__file__).resolve()).startswith(str(ROOT)):
        print(f"warning: measuring pinograsp from {pg.__file__}, not {ROOT}", file=sys.stderr)
    root = old_root(args.old)
    if args.quick:
        tmp = Path(tempfile.mkdtemp(prefix="solver_core_"))
        out = Path(args.out) if args.out else tmp / "solver_core.md"
        img = out.parent / "img" / "solver_core.png"
    else:
        out = Path(args.out) if args.out else ROOT / "docs" / "solver_core.md"
        img = (
            (ROOT / "docs" / "img" / "solver_core.png")
            if not args.out
            else out.parent / "img" / "solver_core.png"
        )
    t0 = time.perf_counter()
    load0 = os.getloadavg()[0]
    res: dict = {"env": environment()}
    print(res["env"], flush=True)
    print(f"old implementation: {root}", flush=True)
    repeat = 1 if args.quick else args.repeat
    print("1. case 1, 8 XY directions", flush=True)
    res["case1"] = section_case1(args.quick, root, repeat)
    print("2. single PRP solves", flush=True)
    res["prp"] = section_prp(args.quick, root)
    print("3. pinch", flush=True)
    res["pinch"] = section_pinch(args.quick, root, 3 if args.quick else 5)
    print("4. case 2 profile", flush=True)
    res["case2"] = section_case2(args.quick, root)
    print("5. agreement B&B vs SCIP", flush=True)
    res["agreement"] = section_agreement(args.quick)
    res["total"] = time.perf_counter() - t0
    res["load"] = (load0, os.getloadavg()[0])
    text = write_report(res, out, img, args.quick)  # (also fills the summaries the plot reads)
    plot(res, img)
    print(text)
    if args.json:
        Path(args.json).write_text(json.dumps(res, default=str))
    print(f"wrote {out} and {img} in {res['total']:.0f} s")


if __name__ == "__main__":
    main()
