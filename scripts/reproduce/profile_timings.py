"""Wall time of the two profiles issue #24 measures: seed case 1 over 72 directions and seed
case 2 over 24 directions, with the iterative method (the scenes' method when #24 measured
them; named since the package default became the quasi-static path), in this process.

Usage: ``python scripts/reproduce/profile_timings.py [--repeat 1]``. Prints one line per profile
with the wall and CPU time [s] (CPU time is the fairer number on a shared machine), the solves
and a digest of the magnitudes (bit-for-bit fingerprint, so that two
trees can be compared for the same answers in the same run).
"""

from __future__ import annotations

import argparse
import hashlib
import time
import warnings

import numpy as np

import pinograsp as pg


def run(name: str, n: int) -> tuple[float, float, str, int]:
    s = pg.load_scene(name)
    a = s.analysis
    c0 = time.process_time()
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        p = pg.resistance_profile(s.model, s.command, a.plane, n, "iterative", a.upper, a.steps)
    dt = time.perf_counter() - t0
    cpu = time.process_time() - c0
    digest = hashlib.sha256(np.asarray(p.magnitudes, float).tobytes()).hexdigest()[:16]
    solves = sum(r.n_solves for r in p.results if r is not None)
    return dt, cpu, digest, solves


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args()
    for _ in range(args.repeat):
        for name, n in (("case1", 72), ("case2", 24)):
            dt, cpu, digest, solves = run(name, n)
            print(
                f"{name} n={n}: wall {dt:.2f} s, cpu {cpu:.2f} s, solves={solves}, "
                f"magnitudes sha256 {digest}",
                flush=True,
            )


if __name__ == "__main__":
    main()
