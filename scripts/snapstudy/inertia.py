"""Does the simulated give-way past the snap depend on the fingers' inertia? (question 2)

The simulation gives each hand joint an armature ``mass x reach^2`` (docs/simulation.md): a
finger that follows the object has about the object's mass at its contact. This script runs
``simulate_max_wrench``'s procedure (engine, preload, ramp, refine: pinograsp.sim internals,
read-only) with the hand's armatures scaled by a factor, on the studied plan along -fz.

    nice -n 10 python -m scripts.snapstudy.inertia --scales 0.3 1 3
"""

from __future__ import annotations

import argparse
import time

from pinograsp.sim.integrator import ramp, refine
from scripts.snapstudy.common import MINUS_FZ, plan_model
from scripts.snapstudy.simtrace import engine


def give_way(scale: float, friction: str, ramp_time: float, upper: float = 45.0) -> tuple[float | None, str]:
    model, command = plan_model()
    import pinograsp.sim.integrator as integ

    orig = integ.Engine.__init__

    def scaled(self, *a, **k):  # the hand's armatures scaled after the model is built
        orig(self, *a, **k)
        dofs = self.red.hand_dof
        self.red.model.dof_armature[dofs] *= scale
        self.mj.mj_setConst(self.red.model, self.data)  # the armature enters through the constants

    integ.Engine.__init__ = scaled
    try:
        run, d = engine(
            model, command, MINUS_FZ, upper, ramp_time=ramp_time, release_time=0.05, friction=friction
        )
    finally:
        integ.Engine.__init__ = orig
    found = ramp(run, d)
    if not found.crossed:
        return None, "held"
    load, frac, _ = refine(run, d, found)
    return load, "gradual" if frac >= 0.1 else "gave_way"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--scales", type=float, nargs="*", default=[0.3, 1.0, 3.0])
    ap.add_argument("--friction", default="pyramid")
    ap.add_argument("--ramp", type=float, default=0.3)
    a = ap.parse_args()
    for s in a.scales:
        t = time.process_time()
        load, status = give_way(s, a.friction, a.ramp)
        print(
            f"armature x{s:g} ({a.friction}, ramp {a.ramp:g} s): {status} {load}"
            f"  [{time.process_time() - t:.0f} s]",
            flush=True,
        )


if __name__ == "__main__":
    main()
