"""A recorded simulation of the studied plan (docs/giveway.md, question 2).

``pg.simulate_max_wrench`` keeps only the load, translation and rotation of its ramp; this
script drives the same engine (``pinograsp.sim`` internals, read-only: the same options,
preload and release) with a slow ramp and records, every ``every`` steps, the object's pose,
every contact's normal force, slide flag and anchor, and the actuators' ratchet limits.
Constant-load holds from snapshots answer whether a load is held at rest.

    nice -n 10 python -m scripts.snapstudy.simtrace --upper 45 --ramp 0.3 --out /tmp/trace.npz
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from pinograsp.sim.integrator import Engine, moved, preload
from pinograsp.sim.simulate import _inputs, _options, _upper


def _rotvec(run: Engine) -> np.ndarray:
    """The object's rotation from rest as a rotation vector (3,) [rad] (world)."""
    R = run.rot
    cos = min(1.0, max(-1.0, (np.trace(R) - 1.0) / 2.0))
    th = math.acos(cos)
    v = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return v * (0.5 * th / math.sin(th) if th > 1e-12 else 0.5)


def engine(model, command, direction, upper: float, **options) -> tuple[Engine, np.ndarray]:
    """A preloaded engine with the options of ``simulate_max_wrench`` and a recorder on the
    contact law (``run.last``: forces, arms, sliding of the latest step)."""
    grasp, d, cmd, _ = _inputs(model, direction, command)
    up = _upper(grasp, cmd, d, upper)
    opts = _options(grasp, d, up, dict(options))
    run = Engine(grasp, cmd, opts)
    law_forces = run.law.forces

    def recorded(*a):
        out = law_forces(*a)
        run.last = out  # type: ignore[attr-defined]
        return out

    run.law.forces = recorded  # type: ignore[method-assign]
    preload(run)
    return run, d


def sample(run: Engine, load: float) -> dict[str, np.ndarray | float]:
    """One record of the current state."""
    f, arms, sliding = run.last  # type: ignore[attr-defined]
    n = run.law.normals
    cn = np.einsum("ij,ij->i", f, n)
    return {
        "load": load,
        "x": run.data.qpos[:3] - run.rest[:3],
        "r": _rotvec(run),
        "v": float(np.linalg.norm(run.data.qvel[:3])),
        "cn": cn,
        "ft": np.linalg.norm(f - cn[:, None] * n, axis=1),
        "sliding": sliding.astype(float),
        "anchors": run.law.anchors.copy(),
        "u_max": run.u_max.copy(),
        "q": run.data.qpos[run.red.hand_qpos].copy(),
    }


def stack(rows: list[dict]) -> dict[str, np.ndarray]:
    return {k: np.array([r[k] for r in rows]) for k in rows[0]}


def ramp_record(run: Engine, d: np.ndarray, every: int = 20, lo_frac: float = 0.5):
    """Ramp as the simulation does (``upper start exp(t/ramp_time)``) to ``upper``; record
    above ``lo_frac * upper`` every ``every`` steps (every step past 0.1 of a threshold);
    snapshots every 1 % of load. Stops when a threshold is crossed."""
    o = run.opts
    pose = (run.data.qpos[:3].copy(), run.rot.copy())
    n_ramp = math.ceil(o.ramp_time * math.log(1.0 / o.start) / o.timestep)
    rows, snaps, next_snap = [], [], 0.0
    for i in range(n_ramp):
        applied = o.upper * min(1.0, o.start * math.exp(i * o.timestep / o.ramp_time))
        if applied >= lo_frac * o.upper and applied >= next_snap:
            snaps.append((applied, run.snapshot()))
            next_snap = applied * 1.01
        run.step(1.0, applied * d)
        frac = moved(run, pose)
        if applied >= lo_frac * o.upper and (i % every == 0 or frac > 0.1):
            rows.append(sample(run, applied))
        if frac >= 1.0:
            break
    return stack(rows), snaps, pose


def hold_record(run: Engine, d: np.ndarray, start, load: float, pose, every: int = 50):
    """From a snapshot, ramp to ``load`` at the ramp rate and hold it ``hold_time`` (as the
    simulation's constant-load test); the records and whether it held."""
    o = run.opts
    load0, state = start
    run.restore(state)
    n_up = math.ceil(o.ramp_time * math.log(max(load / load0, 1.0)) / o.timestep)
    n_hold = math.ceil(o.hold_time / o.timestep)
    rows, half, frac = [], 0.0, 0.0
    for i in range(n_up + n_hold):
        L = min(load, load0 * math.exp((i + 1) * o.timestep / o.ramp_time))
        run.step(1.0, L * d)
        frac = moved(run, pose)
        if i % every == 0:
            rows.append({**sample(run, L), "t": i * o.timestep})
        if frac >= 1.0:
            return stack(rows), False, frac
        if i == n_up + n_hold // 2:
            half = frac
    return stack(rows), frac - half <= 1e-3, frac


def main() -> None:
    from scripts.snapstudy.common import MINUS_FZ, plan_model

    ap = argparse.ArgumentParser()
    ap.add_argument("--upper", type=float, default=45.0)
    ap.add_argument("--ramp", type=float, default=0.3)
    ap.add_argument("--release", type=float, default=0.05)
    ap.add_argument("--friction", default="pyramid")
    ap.add_argument("--holds", type=float, nargs="*", default=[])
    ap.add_argument("--out", default="/tmp/snap_trace.npz")
    a = ap.parse_args()
    model, command = plan_model()
    t0 = time.process_time()
    run, d = engine(model, command, MINUS_FZ, a.upper, ramp_time=a.ramp, release_time=a.release,
                    friction=a.friction)  # fmt: skip
    pre = sample(run, 0.0)
    rec, snaps, pose = ramp_record(run, d)
    save = {f"ramp_{k}": v for k, v in rec.items()}
    save.update({f"pre_{k}": np.asarray(v) for k, v in pre.items()})
    save["thresholds"] = np.array([run.opts.slip, run.opts.rotation])
    for L in a.holds:
        start = max((s for s in snaps if s[0] <= L), key=lambda s: s[0])
        h, ok, frac = hold_record(run, d, start, L, pose)
        print(f"hold {L:.3f} N: {'held' if ok else 'not held'}, moved {frac:.3f} of a threshold", flush=True)
        save.update({f"hold{L:g}_{k}": v for k, v in h.items()})
        save[f"hold{L:g}_ok"] = np.array([ok, frac])
    np.savez(a.out, **save)
    print(f"cpu {time.process_time() - t0:.1f} s; ramp stopped at {rec['load'][-1]:.3f} N", flush=True)


if __name__ == "__main__":
    main()
