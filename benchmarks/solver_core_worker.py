"""The previous implementation (and this tree) measured in a subprocess: ``solver_core.py --worker``.

Only numpy, the standard library and the public API common to both trees are imported at
module level: the worker runs with ``PYTHONPATH`` set to the old tree.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from solver_core_common import BLAS1, OLD_COMMIT, ROOT, status_of, xy


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
            [
                sys.executable,
                str(Path(__file__).resolve().with_name("solver_core.py")),
                "--worker",
                str(jf),
                str(of),
                *flag,
            ],
            env=env,
            cwd=tmp,
            check=True,
        )
        return json.loads(of.read_text())
