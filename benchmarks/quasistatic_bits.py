"""Bit-for-bit answers of the quasi-static method over the speed benchmarks' directions: a guard
for speed work (an optimisation must not change one bit of λ*).

Writes one line per direction: case, direction index, status, λ* as ``float.hex``, a hash of
the path's loads (every breakpoint's load, ``float.hex``), of the response's contact forces and
of the whole ``MaxWrench`` and ``LoadingPath`` records (``to_dict()`` without timings), from
``pg.max_resistible_wrench(..., method="quasistatic")`` and ``pg.loading_path``. With
``--compare OLD`` it reports how many directions changed (per field) and the largest relative
change of λ*. Directions: those of ``benchmarks.quasistatic_ratios`` (pinch, cases 1-3: 24
plane + named; random 4-40 contacts: 3 seeds x 3) plus 6 more random ones per random grasp, and
the first sampled Barrett grasps of ``benchmarks/quasistatic_batch.py`` (26 directions each).
The reference run of an older tree: run this file from a directory whose ``pinograsp`` is that
tree's (``python -m`` puts the current directory first on the path).

    python -m benchmarks.quasistatic_bits --out /tmp/bits_after.txt [--compare /tmp/bits_before.txt]
"""

from __future__ import annotations

import argparse
import hashlib
from pathlib import Path

import numpy as np

import pinograsp as pg

from .quasistatic_ratios import scene_directions


def cases() -> list[tuple[str, object, np.ndarray, list[np.ndarray]]]:
    """``(name, model, command, directions)``."""
    out = []
    for name in ("pinch", "case1", "case2", "case3"):
        sc = pg.load_scene(name)
        out.append((name, sc.model, sc.model.command_vector(sc.preload(None)), scene_directions(sc)))
    for n_pairs in (1, 2, 3, 4, 6, 10):
        for seed in range(3):
            m = pg.examples.random_grasp(seed, n_pairs, contacts_per_finger=2)
            rng = np.random.default_rng(1000 + seed)
            dirs = [d / np.linalg.norm(d) for d in (rng.standard_normal(6) for _ in range(3))]
            dirs += [rng.normal(size=6) for _ in range(6)]
            out.append((f"{4 * n_pairs} contacts seed {seed}", m, np.ones(m.na), dirs))
    out += barrett_cases()
    return out


def barrett_cases(n: int = 30) -> list[tuple[str, object, object, list[np.ndarray]]]:
    """The first ``n`` sampled Barrett grasps of the batch benchmark that build and preload, with
    its 26 cube directions (``benchmarks/quasistatic_batch.py``)."""
    from benchmarks.quasistatic_batch import cube_directions, grasps
    from pinograsp.batch.grasps import build_grasp

    out = []
    dirs = [d for _, d in cube_directions()]
    for g in grasps(n, 0):
        try:
            model, command, _ = build_grasp(g)
        except pg.PinograspError:
            continue
        out.append((f"barrett {g.id}", model, command, dirs))
    return out


def _hash(a: np.ndarray) -> str:
    return hashlib.sha1(" ".join(float(x).hex() for x in np.ravel(a)).encode()).hexdigest()[:16]


def _record(x: object) -> str:
    """A hash of a result record's ``to_dict()`` without its timings (every other field, floats
    as ``float.hex``)."""

    def norm(v: object) -> object:
        if isinstance(v, dict):
            return {k: norm(w) for k, w in sorted(v.items()) if "time" not in k}
        if isinstance(v, (list, tuple)):
            return [norm(w) for w in v]
        if isinstance(v, np.ndarray):
            return norm(v.tolist())
        if isinstance(v, (float, np.floating)):
            return float(v).hex()
        return repr(v)

    return hashlib.sha1(repr(norm(x.to_dict())).encode()).hexdigest()[:16]  # type: ignore[attr-defined]


def lines() -> list[str]:
    out = []
    for name, model, cmd, dirs in cases():
        for i, d in enumerate(dirs):
            try:
                mw = pg.max_resistible_wrench(model, cmd, d, method="quasistatic")
                lp = pg.loading_path(model, cmd, d)
                forces = mw.response.contact_forces if mw.response is not None else np.zeros(0)
                out.append(
                    f"{name}\t{i}\t{mw.status}\t{float(mw.magnitude).hex()}\t{_hash(lp.loads)}\t{_hash(forces)}"
                    f"\t{_record(mw)}\t{_record(lp)}"
                )
            except pg.PinograspError as exc:
                out.append(f"{name}\t{i}\t{type(exc).__name__}\t-\t-\t-\t-\t-")
    return out


def compare(old: list[str], new: list[str]) -> str:
    """How many directions changed, by field, and the largest relative change of λ*."""
    if len(old) != len(new):
        return f"different direction counts: {len(old)} before, {len(new)} after"
    changed = {"status": 0, "lambda": 0, "loads": 0, "forces": 0, "max-wrench record": 0, "path record": 0}
    worst = 0.0
    for a, b in zip(old, new):
        fa, fb = a.split("\t"), b.split("\t")
        keys = ("status", "lambda", "loads", "forces", "max-wrench record", "path record")
        for j, k in enumerate(keys, start=2):
            changed[k] += fa[j] != fb[j]
        if fa[3] != fb[3] and "-" not in (fa[3], fb[3]):
            x, y = float.fromhex(fa[3]), float.fromhex(fb[3])
            if np.isfinite(x) and np.isfinite(y):
                worst = max(worst, abs(x - y) / max(abs(x), 1e-300))
            else:
                worst = float("inf")
    return (
        f"{len(new)} directions; changed: "
        + ", ".join(f"{k} {v}" for k, v in changed.items())
        + f"; largest relative change of lambda* {worst:.3g}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--compare", help="a previous --out file")
    args = ap.parse_args()
    new = lines()
    Path(args.out).write_text("\n".join(new) + "\n")
    print(f"wrote {len(new)} lines to {args.out}")
    if args.compare:
        print(compare(Path(args.compare).read_text().splitlines(), new))


if __name__ == "__main__":
    main()
