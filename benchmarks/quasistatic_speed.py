"""Speed of the quasi-static loading path: median CPU time per direction, segments, events and
LCP sizes on the pinch, the paper's cases 1-3 and seeded random grasps (4-40 contacts).

Prints a Markdown table. CPU time (``time.process_time``) per direction of a lone
``pg.quasistatic_max_wrench`` call (which prepares the grasp and solves its preload path again
each time) and of ``pg.max_resistible_wrench`` in a :class:`pinograsp.Session` (the preload kept
per command, as profiles, resistance sets and batches run); the first call of a grasp (with its
preload) reported apart. No timed asserts: this is a measurement.

    python benchmarks/quasistatic_speed.py [--quick]
"""

from __future__ import annotations

import argparse
import collections
import time

import numpy as np

import pinograsp as pg


def _plane(n: int = 24) -> list[np.ndarray]:
    return [
        np.array([np.cos(a), np.sin(a), 0, 0, 0, 0]) for a in np.linspace(0, 2 * np.pi, n, endpoint=False)
    ]


#: The built-in hands measured with ``--hands`` (24 directions in each scene's plane, at its
#: ``upper``: the load of interest, which bounds the geometry updates).
HANDS = ("allegro_left", "ezgripper", "ability", "talos_gripper")


def hand_grasps() -> list[tuple[str, object, object, list[np.ndarray], float]]:
    """(label, model, command, directions, upper) of the built-in hands."""
    from pinograsp.core.axes import plane_directions

    out = []
    for name in HANDS:
        s = pg.load_scene(name)
        dirs = list(plane_directions(s.model, s.analysis.plane, 24))
        out.append((name, s.model, s.model.command_vector(s.preload(None)), dirs, float(s.analysis.upper)))
    return out


def grasps(quick: bool) -> list[tuple[str, object, object, list[np.ndarray]]]:
    """(label, model, command, directions)."""
    out = [("pinch", pg.examples.pinch(), 1.0, [d[[0, 1, 5]] for d in _plane()])]
    for name in ("case1", "case2", "case3"):
        s = pg.load_scene(name)
        out.append((name, s.model, s.preload(None), _plane()))
    pairs = (1, 2, 4) if quick else (1, 2, 3, 4, 6, 10)
    for n_pairs in pairs:
        for seed in range(3):
            m = pg.examples.random_grasp(seed, n_pairs, contacts_per_finger=2)
            rng = np.random.default_rng(1000 + seed)
            out.append(
                (
                    f"random {4 * n_pairs} (seed {seed})",
                    m,
                    1.0,
                    [rng.normal(size=6) for _ in range(3 if quick else 6)],
                )
            )
    return out


def measure(model, command, dirs, upper: float = 1e3) -> dict:
    t0 = time.process_time()
    pg.quasistatic_max_wrench(model, command, dirs[0], upper=upper)  # the preload path, once
    first = time.process_time() - t0
    times, segs, events, lcp, statuses = [], [], [], [], collections.Counter()
    session = pg.Session(model)  # as profiles, sets and batches run: the preload kept per command
    pg.max_resistible_wrench(model, command, dirs[0], upper=upper, session=session)
    in_session = []
    for d in dirs:
        t0 = time.process_time()
        r = pg.quasistatic_max_wrench(model, command, d, upper=upper)
        times.append(time.process_time() - t0)
        t0 = time.process_time()
        pg.max_resistible_wrench(model, command, d, upper=upper, session=session)
        in_session.append(time.process_time() - t0)
        lp = pg.loading_path(model, command, d)
        segs.append(lp.segments)
        events.append(sum(e.kind in ("contact", "actuator") for e in lp.events))
        lcp.append(lp.largest_lcp)
        statuses[r.status] += 1
    return {
        "first": first,
        "median": float(np.median(times)),
        "session": float(np.median(in_session)),
        "max": float(np.max(times)),
        "segments": (int(np.median(segs)), int(np.max(segs))),
        "events": (int(np.median(events)), int(np.max(events))),
        "lcp": int(np.max(lcp)),
        "statuses": dict(statuses),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="fewer random grasps and directions")
    ap.add_argument("--hands", action="store_true", help="also the built-in hands at their scene's upper")
    args = ap.parse_args()
    print(
        "| grasp | contacts | directions | median ms/dir | in a session | max ms | first (with preload) ms "
        "| segments med/max | events med/max | largest LCP | statuses |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---|---|---:|---|")
    rows = [(*g, 1e3) for g in grasps(args.quick)] + (hand_grasps() if args.hands else [])
    for label, m, fc, dirs, upper in rows:
        r = measure(m, fc, dirs, upper)
        print(
            f"| {label} | {m.nc} | {len(dirs)} | {r['median'] * 1e3:.2f} | {r['session'] * 1e3:.2f} | "
            f"{r['max'] * 1e3:.1f} | "
            f"{r['first'] * 1e3:.1f} | {r['segments'][0]}/{r['segments'][1]} | "
            f"{r['events'][0]}/{r['events'][1]} | {r['lcp']} | "
            f"{', '.join(f'{k} {v}' for k, v in sorted(r['statuses'].items()))} |"
        )


if __name__ == "__main__":
    main()
