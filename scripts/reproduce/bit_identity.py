"""Bit-identity check of pinograsp's answers over a fixed list of queries (issue #24 acceptance).

Every query prints one line ``name<TAB>canonical json``: the result's dataclass fields walked
recursively, every float written with ``float.hex`` (bit for bit), wall-clock fields
(``solve_time``, ``wall_time``, ``time_*``) left out (they are not answers). Each query runs in
this process in a fixed order; the script is deterministic (the same code gives the same
file, fresh process or not).

Usage::

    python scripts/reproduce/bit_identity.py OUT.txt            # write the lines
    python scripts/reproduce/bit_identity.py --check [OUT.txt]  # compare with the baseline

``--check`` compares against ``scripts/reproduce/data/bit_identity_baseline.txt`` and exits 1
on any difference, naming the queries that differ (``--baseline FILE``: another file). Runtime
about two minutes on one core.

Baselines: ``bit_identity_before_registry.txt`` holds the answers of the code before the registry
refactor (issue #24, commit 5ead8d0); the refactor matched it 81/81. Issues #26 and #27 then
changed six answers on purpose, so ``bit_identity_baseline.txt`` was regenerated after them:
``equilibrium_preload`` on pinch (prp, iterative), wedge and case 1 (one homogeneous solve scaled
to the bound: case 1 was a raw Clarabel error and is now "found", the others move in the last
digits of the normal forces) and the two batch rows (new ``reason`` and ``max_±fz`` columns, the
longer built-in scene list in an error message). Update the baseline only with such a list.

Methods: every query names its method (the baseline holds the paper's methods' answers; the
package default became ``"quasistatic"`` after it, so a query relying on the default would
change). Counts: ``n_solves`` is kept. A profile or set that shares one session per worker block solves
the preload stage once per block, so its per-direction ``n_solves`` may be smaller than when
every direction built its own session; such rows are compared with ``n_solves`` dropped
(``COUNT_FREE``), every other field bit for bit.
"""

from __future__ import annotations

import argparse
import dataclasses
import enum
import json
import sys
import time
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

import pinograsp as pg
from pinograsp.core import examples

BASELINE = Path(__file__).with_name("data") / "bit_identity_baseline.txt"
#: Fields that are wall-clock measurements, not answers.
TIME_FIELDS = {"solve_time", "wall_time", "seconds"}
#: Queries whose per-direction solve counts may change when a block shares one session.
COUNT_FREE = ("profile", "set", "score")
#: Fields added after the baseline (compared only where the baseline has them): a profile's
#: ``failures`` (issue #27 item 9), empty when every direction answered.
ADDED = {"profile": ("failures",)}
#: Record fields added after the baseline, by record type (absent from the baseline, so left out
#: of every comparison): the audit's ``equilibrium_tolerance`` (issue #27 item 4), ``pull`` and
#: ``finite`` (issue #26: untrusted numbers fail the audit; a change of ``audit.ok`` still shows
#: in the answers that read it) and a max-wrench ``note`` (issue #27 item 13).
ADDED_FIELDS = {"Audit": ("equilibrium_tolerance", "pull", "finite"), "MaxWrench": ("note",)}


def canon(x: object, depth: int = 0) -> object:
    """A JSON-ready, bit-exact image of ``x`` (floats as ``float.hex``)."""
    if depth > 12:
        return "<deep>"
    if isinstance(x, bool) or x is None:
        return x
    if isinstance(x, enum.Enum):
        return canon(x.value, depth + 1)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x).hex()
    if isinstance(x, str):
        return x
    if isinstance(x, np.ndarray):
        return (
            [canon(v, depth + 1) for v in x.tolist()]
            if x.dtype != object
            else [canon(v, depth + 1) for v in x]
        )
    if isinstance(x, dict):
        return {str(k): canon(v, depth + 1) for k, v in x.items() if not _is_time(str(k))}
    if isinstance(x, (list, tuple)):
        return [canon(v, depth + 1) for v in x]
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        out = {"__type__": type(x).__name__}
        for f in dataclasses.fields(x):
            if _is_time(f.name):
                continue
            out[f.name] = canon(getattr(x, f.name), depth + 1)
        return out
    if hasattr(x, "to_dict"):
        return canon(x.to_dict(), depth + 1)
    return repr(x)


def _is_time(name: str) -> bool:
    return name in TIME_FIELDS or name.startswith("time_")


def _scene(name: str) -> pg.Scene:
    return pg.load_scene(name)


def _pinch() -> tuple[object, object]:
    return examples.pinch(), 1.0


def queries() -> list[tuple[str, Callable[[], object]]]:
    """The fixed list (name, thunk)."""
    out: list[tuple[str, Callable[[], object]]] = []
    methods = ("prp", "iterative", "energetic")
    scenes = {
        "pinch": ("fy", "-fy", "fx", [0.3, 1.0, 0, 0, 0, 0.02]),
        "wedge": ("fy", "-fy"),
        "case1": ("fy", "-fy", "fx"),
        "case3": ("fy", "-fx"),
        "fig1": ("-fy",),
    }
    for sc, dirs in scenes.items():
        for method in methods:
            for d in dirs:
                label = d if isinstance(d, str) else "vec"

                def q(sc: str = sc, d: object = d, method: str = method) -> object:
                    s = _scene(sc)
                    a = s.analysis
                    return pg.max_resistible_wrench(s.model, s.command, d, method, a.upper, 12)

                out.append((f"mw/{sc}/{method}/{label}", q))
    # case 2: cheap directions only
    for method in ("prp", "iterative"):

        def q2(method: str = method) -> object:
            s = _scene("case2")
            return pg.max_resistible_wrench(s.model, s.command, "fx", method, 50.0, 10)

        out.append((f"mw/case2/{method}/fx", q2))
    # passive responses
    for sc, w in (("pinch", [0.0, 5.0, 0, 0, 0, 0]), ("case1", [0.0, 3.0, 0.0, 0, 0, 0]), ("fig1", None)):
        for method in methods:

            def qr(sc: str = sc, w: object = w, method: str = method) -> object:
                s = _scene(sc)
                ww = s.analysis.wrenches["push_palm"] if w is None else w
                return pg.passive_response(s.model, s.command, ww, method)

            out.append((f"response/{sc}/{method}", qr))

    def variants() -> object:
        m, c = _pinch()
        return [
            pg.passive_response(m, c, [0.2, 4.0, 0.0], meth, variant=v)
            for meth in methods
            for v in ("single-step", "preload-first", "settled-preload")
        ]

    out.append(("response/pinch/variants", variants))

    def mirrored() -> object:
        m = examples.pinch()
        return pg.passive_response(m, {"left": 1.0, "right": 1.0}, [0.0, -3.0, 0.0], "prp", backend="bnb")

    out.append(("response/pinch/explicit-bnb", mirrored))
    # the reference backend (cvxpy + SCIP) where it is cheap
    for method, search in (
        ("prp", "bisection"),
        ("prp", "direct"),
        ("iterative", "auto"),
        ("energetic", "auto"),
    ):

        def qm(method: str = method, search: str = search) -> object:
            m, c = _pinch()
            return pg.max_resistible_wrench(m, c, "fy", method, 50.0, 8, search=search, backend="miqp")

        out.append((f"miqp/pinch/{method}/{search}", qm))
    # the default search depth (20 steps)
    for sc, method, d in (
        ("case1", "iterative", "fy"),
        ("case3", "iterative", "-fx"),
        ("pinch", "prp", "fy"),
    ):

        def q20(sc: str = sc, method: str = method, d: str = d) -> object:
            s = _scene(sc)
            return pg.max_resistible_wrench(s.model, s.command, d, method, s.analysis.upper, 20)

        out.append((f"mw20/{sc}/{method}/{d}", q20))
    # searches
    for search, method in (
        ("bisection", "iterative"),
        ("bisection", "prp"),
        ("direct", "prp"),
        ("bisection", "energetic"),
    ):

        def qs(search: str = search, method: str = method) -> object:
            s = _scene("case1")
            return pg.max_resistible_wrench(s.model, s.command, "fy", method, 50.0, 10, search=search)

        out.append((f"search/case1/{method}/{search}", qs))

    def refined() -> object:
        s = _scene("case1")
        return pg.max_resistible_wrench(s.model, s.command, "fy", "prp", 50.0, 10, cone_tolerance=0.2)

    out.append(("mw/case1/prp/fy/cone_tolerance", refined))

    def settled() -> object:
        s = _scene("case3")
        return pg.max_resistible_wrench(
            s.model, s.command, "fy", "iterative", 50.0, 10, variant="settled-preload"
        )

    out.append(("mw/case3/iterative/fy/settled", settled))
    # profiles
    for sc, method, n in (
        ("pinch", "iterative", 8),
        ("case1", "iterative", 6),
        ("case1", "energetic", 6),
        ("wedge", "prp", 8),
    ):

        def qp(sc: str = sc, method: str = method, n: int = n) -> object:
            s = _scene(sc)
            return pg.resistance_profile(
                s.model, s.command, n=n, method=method, upper=s.analysis.upper, steps=10
            )

        out.append((f"profile/{sc}/{method}/{n}", qp))

    def normalized() -> object:
        s = _scene("case1")
        return pg.resistance_profile(
            s.model, s.command, n=4, method="iterative", upper=50.0, steps=10, normalize=True
        )

    out.append(("profile/case1/iterative/normalized", normalized))
    # sets and scores
    for method in ("iterative", "prp", "energetic"):

        def qset(method: str = method) -> object:
            m, c = _pinch()
            return pg.resistance_set(m, c, n=10, method=method, upper=50.0, steps=10)

        out.append((f"set/pinch/{method}", qset))

    def score() -> object:
        s = _scene("wedge")
        return pg.grasp_score(s.model, s.command, n=8, method="iterative", upper=50.0, steps=8)

    out.append(("score/wedge/iterative", score))
    # preloads
    for method in ("iterative", "prp"):

        def qe(method: str = method) -> object:
            return pg.equilibrium_preload(examples.pinch(), method)

        out.append((f"equilibrium_preload/pinch/{method}", qe))

    def qe_case1() -> object:  # an error (Clarabel fails on this model): errors are answers too
        s = _scene("case1")
        return pg.equilibrium_preload(s.model, "iterative", max_command=0.5)

    out.append(("equilibrium_preload/case1/iterative", qe_case1))

    def qe_wedge() -> object:
        return pg.equilibrium_preload(_scene("wedge").model, "iterative")

    out.append(("equilibrium_preload/wedge/iterative", qe_wedge))
    for method, kw in (("prp", {}), ("iterative", {}), ("prp", {"objective": "sum", "budget": 1.0})):

        def qo(method: str = method, kw: dict = kw) -> object:
            return pg.optimal_preload(examples.pinch(), [[0.0, 5.0, 0.0]], method, **kw)

        out.append((f"optimal_preload/pinch/{method}/{sorted(kw)}", qo))

    def qo_wedge() -> object:
        s = _scene("wedge")
        return pg.optimal_preload(s.model, ["fy", "-fx"], "prp", upper=100.0, steps=10)

    out.append(("optimal_preload/wedge/prp", qo_wedge))

    # batch rows
    def batch() -> object:
        score_fn = pg.WorstAxisScore(upper=20, steps=4, method="iterative")
        df = pg.evaluate_grasps(
            ["pinch", {"scene": "wedge", "id": "w"}, "no_such_scene"], score=score_fn, workers=1
        )
        keep = [c for c in df.columns if not _is_time(str(c))]
        return {c: list(df[c]) for c in keep}

    out.append(("batch/pinch-wedge-missing", batch))

    def batch_energetic() -> object:
        score_fn = pg.WorstAxisScore(upper=20, steps=4, method="energetic")
        df = pg.evaluate_grasps(["pinch", "case1"], score=score_fn, workers=1)
        keep = [c for c in df.columns if not _is_time(str(c))]
        return {c: list(df[c]) for c in keep}

    out.append(("batch/pinch-case1-energetic", batch_energetic))
    return out


def run(only: str | None = None) -> list[str]:
    lines = []
    for name, thunk in queries():
        if only and only not in name:
            continue
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                value = canon(thunk())
            except Exception as exc:  # an error is an answer too
                value = {"error": type(exc).__name__, "message": str(exc)}
        dt = time.perf_counter() - t0
        print(f"{dt:7.2f} s  {name}", file=sys.stderr, flush=True)
        lines.append(f"{name}\t{json.dumps(value, sort_keys=True)}")
    return lines


def _drop_added_value(x: object) -> object:
    """``x`` (a decoded value) without the record fields of :data:`ADDED_FIELDS`."""
    if isinstance(x, dict):
        added = ADDED_FIELDS.get(str(x.get("__type__")), ())
        return {k: _drop_added_value(v) for k, v in x.items() if k not in added}
    if isinstance(x, list):
        return [_drop_added_value(v) for v in x]
    return x


def _drop_counts(line: str) -> str:
    name, _, body = line.partition("\t")
    if not name.startswith(COUNT_FREE):
        return name + "\t" + json.dumps(_drop_added_value(json.loads(body)), sort_keys=True)
    added = ADDED.get(name.split("/")[0], ())

    def strip(x: object) -> object:
        if isinstance(x, dict):
            return {k: strip(v) for k, v in x.items() if k != "n_solves"}
        if isinstance(x, list):
            return [strip(v) for v in x]
        return x

    value = strip(_drop_added_value(json.loads(body)))
    if isinstance(value, dict):
        value = {k: v for k, v in value.items() if not (k in added and v == [])}
    return name + "\t" + json.dumps(value, sort_keys=True)


def _drop_added(line: str) -> str:
    """``line`` without the record fields of :data:`ADDED_FIELDS`."""
    name, _, body = line.partition("\t")

    def strip(x: object) -> object:
        if isinstance(x, dict):
            added = ADDED_FIELDS.get(str(x.get("__type__")), ())
            return {k: strip(v) for k, v in x.items() if k not in added}
        if isinstance(x, list):
            return [strip(v) for v in x]
        return x

    return name + "\t" + json.dumps(strip(json.loads(body)), sort_keys=True)


def compare(lines: list[str], baseline: list[str]) -> list[str]:
    """Names of the queries whose lines differ (counts dropped where allowed, added fields left out)."""
    a = {ln.split("\t", 1)[0]: _drop_added(ln) for ln in lines}
    b = {ln.split("\t", 1)[0]: _drop_added(ln) for ln in baseline}
    bad = sorted(set(a) ^ set(b))
    for k in sorted(set(a) & set(b)):
        if a[k] != b[k] and _drop_counts(a[k]) != _drop_counts(b[k]):
            bad.append(k)
    return bad


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", help="write the lines to this file")
    ap.add_argument("--check", action="store_true", help="compare with the committed baseline")
    ap.add_argument("--only", help="run only queries whose name contains this")
    ap.add_argument("--baseline", type=Path, default=BASELINE, help="baseline file for --check")
    args = ap.parse_args()
    t0 = time.perf_counter()
    lines = run(args.only)
    if args.out:
        Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"{len(lines)} queries in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    if args.check:
        base = args.baseline.read_text().splitlines()
        if args.only:
            names = {ln.split("\t", 1)[0] for ln in lines}
            base = [ln for ln in base if ln.split("\t", 1)[0] in names]
        bad = compare(lines, base)
        if bad:
            print(f"DIFFERENT ({len(bad)}): " + ", ".join(bad), file=sys.stderr)
            return 1
        print(f"bit-identical: {len(lines)} queries", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
