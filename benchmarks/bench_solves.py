"""Per-solve and per-direction times of the exact paths on the analytic models.

Prints a markdown table (median of repeated runs) and the machine/versions. Usage:
    python benchmarks/solve_times.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import platform
import statistics
from importlib.metadata import version

import pinograsp as pg
from pinograsp import examples

CASES = {
    "pinch (2 contacts, planar)": (examples.pinch, "fy"),
    "palm (3 contacts, planar)": (examples.palm_pinch, "fy"),
    "wedge (2 contacts, planar)": (lambda: examples.pinch(h=0.01), "fy"),
    "pinch 3D (2 contacts, 8 edges)": (lambda: examples.pinch(planar=False), "fy"),
}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    print(f"machine: {platform.processor() or platform.machine()}, python {platform.python_version()}")
    print("versions: " + ", ".join(f"{p} {version(p)}" for p in ("cvxpy", "pyscipopt", "proxsuite", "numpy")))
    print()
    print(
        "| case | PRP solve [ms] | movement step [ms] | PRP direction [s] (solves) "
        "| iterative direction [s] (solves) | iterative error vs PRP [N] |"
    )
    print("|---|---|---|---|---|---|")
    for name, (factory, d) in CASES.items():
        m = factory()
        t_prp, t_move = [], []
        for _ in range(args.repeat):
            t_prp.append(
                pg.passive_response(m, 1.0, [0, 4.0, 0, 0, 0, 0] if not m.planar else [0, 4.0, 0]).solve_time
            )
        r = pg.passive_response(
            m, 1.0, [3.0, 4.0, 0, 0, 0, 0] if not m.planar else [3.0, 4.0, 0], method="iterative"
        )
        t_move.append(r.solve_time / max(r.n_solves, 1))
        dp, di, np_, ni, ep = [], [], 0, 0, 0.0
        for _ in range(args.repeat):
            a = pg.max_resistible_wrench(m, 1.0, d, method="prp")
            b = pg.max_resistible_wrench(m, 1.0, d, method="iterative")
            dp.append(a.wall_time)
            di.append(b.wall_time)
            np_, ni = a.n_solves, b.n_solves
            ep = (b.magnitude - a.magnitude) if not (a.unbounded or b.unbounded) else float("nan")
        print(
            f"| {name} | {1e3 * statistics.median(t_prp):.1f} | {1e3 * statistics.median(t_move):.1f} | "
            f"{statistics.median(dp):.2f} ({np_}) | {statistics.median(di):.2f} ({ni}) | {ep:+.1e} |"
        )


if __name__ == "__main__":
    main()
