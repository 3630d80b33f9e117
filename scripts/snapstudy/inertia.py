"""Does the simulated give-way past the snap depend on the fingers' mass? (docs/giveway.md,
"Snaps and the fingers' mass"; docs/simulation.md, "Finger mass")

``pg.simulate_max_wrench(..., finger_mass=r)`` on the studied plan along -fz: the model's
pyramid, the held object released over 0.05 s, ramp 0.3 s.

    nice -n 10 python -m scripts.snapstudy.inertia --ratios 0.1 0.5 1 3
"""

from __future__ import annotations

import argparse
import time

import pinograsp as pg
from scripts.snapstudy.common import MINUS_FZ, plan_model


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--ratios", type=float, nargs="*", default=[0.1, 0.5, 1.0, 3.0])
    ap.add_argument("--friction", default="pyramid")
    ap.add_argument("--ramp", type=float, default=0.3)
    ap.add_argument("--upper", type=float, default=70.0)
    a = ap.parse_args()
    model, command = plan_model()
    for r in a.ratios:
        t = time.process_time()
        res = pg.simulate_max_wrench(
            model,
            MINUS_FZ,
            command,
            upper=a.upper,
            friction=a.friction,
            ramp_time=a.ramp,
            release_time=0.05,
            finger_mass=r,
        )
        print(f"finger_mass {r:g}: {res.status} {res.load}  [{time.process_time() - t:.0f} s]", flush=True)


if __name__ == "__main__":
    main()
