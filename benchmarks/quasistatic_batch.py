"""Batch throughput of the quasi-static method (issue 25): ``pg.evaluate_grasps`` on sampled
Barrett grasps (case 1's hand and box, as ``scripts/reproduce/batch_throughput.py``), 26
directions per grasp, 2 local workers.

The score (:class:`CubeScore`) is the worst case over the 26 force directions of the cube's
faces, edges and corners (``(i, j, k) / |(i, j, k)|``, ``i, j, k`` in ``{-1, 0, 1}``, not all 0;
the 6 signed axes of ``pg.WorstAxisScore`` plus the 12 edge and 8 corner diagonals), each a
``pg.max_resistible_wrench(..., method="quasistatic")`` on one session per grasp (its preload
path solved once). Prints the wall time, the rows by status and reason, and the per-grasp time
split from the table's timing columns: building the grasp (hand, auto-close by Pinocchio/Coal,
contacts), the ``"auto"`` preload design, and the analysis (the score). Nothing asserted.

    nice -n 10 python -m benchmarks.quasistatic_batch [--n 1000] [--workers 2] [--seed 0]
"""

from __future__ import annotations

import argparse
import itertools
import os
import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

import pinograsp as pg
from scripts.reproduce.batch_throughput import grasps  # case 1's box, the same sampled grasps


def cube_directions() -> list[tuple[str, np.ndarray]]:
    """The 26 unit force directions ``(i, j, k) / |(i, j, k)|`` (name, (6,) wrench)."""
    out = []
    for ijk in itertools.product((-1, 0, 1), repeat=3):
        if not any(ijk):
            continue
        v = np.zeros(6)
        v[:3] = ijk
        name = "".join(f"{'+' if s > 0 else '-'}f{a}" for s, a in zip(ijk, "xyz") if s)
        out.append((name, v / np.linalg.norm(v)))
    return out


@dataclass(frozen=True)
class CubeScore:
    """Worst-case max resistible force [N] over the 26 cube directions (quasi-static method).

    Returns ``score`` (the smallest magnitude, [N]; ``inf`` when every direction is unbounded),
    ``unbounded_fraction`` (in [0, 1]) and ``directions`` (26). ``upper`` [N] is only the query's
    (the loading path has no search bound)."""

    method: str = "quasistatic"
    upper: float = 50.0

    columns: ClassVar[tuple[str, ...]] = ("score", "unbounded_fraction", "directions")
    no_grasp: ClassVar[dict[str, float]] = {"score": 0.0, "unbounded_fraction": 0.0, "directions": 0.0}

    def __call__(self, model: Any, command: Mapping[str, float]) -> dict[str, float]:
        session = pg.Session(model)
        query = pg.Query(self.method, self.upper, 6)
        mags, unbounded = [], 0
        for k, (_, d) in enumerate(cube_directions()):
            mw = pg.max_resistible_wrench(
                model, command, d, session=session, query=query, check_preload_first=k == 0
            )
            unbounded += bool(mw.unbounded)
            mags.append(0.0 if mw.status == "below_resolution" else float(mw.magnitude))
        return {
            "score": min(mags),
            "unbounded_fraction": unbounded / len(mags),
            "directions": float(len(mags)),
        }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--csv", help="also write the table here")
    args = ap.parse_args()
    batch = grasps(args.n, args.seed)
    load0 = os.getloadavg()
    t0 = time.perf_counter()
    df = pg.evaluate_grasps(batch, score=CubeScore(), workers=args.workers)
    wall = time.perf_counter() - t0
    load1 = os.getloadavg()
    if args.csv:
        df.to_csv(args.csv, index=False)
    print(
        f"evaluate_grasps: {len(df)} Barrett grasps x 26 quasi-static directions, {args.workers} local "
        f"workers: {wall:.1f} s wall ({len(df) / wall:.2f} grasps/s); load average "
        f"{load0[0]:.2f} before, {load1[0]:.2f} after ({os.cpu_count()} CPUs)"
    )
    counts = df.groupby(["status", "reason"]).size()
    print("rows: " + ", ".join(f"{s}/{r or '-'} {c}" for (s, r), c in counts.items()))
    ok = df[df["status"] == "ok"]
    rest = df[df["status"] != "ok"]
    parts = ok[["time_build", "time_preload", "time_score"]].astype(float).sum(axis=1)
    print(
        f"| per grasp [s] ({len(ok)} ok rows; the {len(rest)} others stop in the build or the preload "
        "design and have only a total) | median | mean | sum over rows |"
    )
    print("|---|---:|---:|---:|")
    for x, label in (
        (ok["time_build"], "build (hand, auto-close by Pinocchio/Coal, contacts)"),
        (ok["time_preload"], "preload design (equilibrium_preload)"),
        (ok["time_score"], "analysis (26 quasi-static directions)"),
        (ok["time_total"].astype(float) - parts, "other (row, warnings, JSON)"),
        (ok["time_total"], "total, ok rows"),
        (rest["time_total"], "total, other rows"),
    ):
        x = x.astype(float)
        print(f"| {label} | {x.median():.3f} | {x.mean():.3f} | {x.sum():.1f} |")
    print(
        f"sum of every row's total: {df['time_total'].astype(float).sum():.1f} s (CPU-seconds of the workers)"
    )
    if len(ok):
        per_dir = ok["time_score"].astype(float) / 26
        print(
            f"ok rows: {len(ok)}; analysis per direction median {1e3 * per_dir.median():.2f} ms; "
            f"contacts median {int(ok['n_contacts'].median())} (range {ok['n_contacts'].min()}-"
            f"{ok['n_contacts'].max()}); score finite in {int(np.isfinite(ok['score']).sum())}"
        )


if __name__ == "__main__":
    main()
