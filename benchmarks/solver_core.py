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

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import solver_core_common  # noqa: F401  (first: single-threaded BLAS before numpy)
from solver_core_agreement import reproduce, section_agreement
from solver_core_common import OLD_COMMIT, ROOT
from solver_core_measure import section_case1, section_case2, section_pinch, section_prp
from solver_core_plot import plot
from solver_core_report import environment, write_report
from solver_core_worker import api_worker, old_root


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
