"""Numerical stability on stiff and extreme cases: runs the stress catalogue, writes its report.

The catalogue is data, ``tests/data/stress_catalogue.yaml``; ``tests/support/stress.py`` reads it and
judges each case (ok / flagged / WRONG, see its docstring); ``tests/test_stability.py`` runs
the same cases and asserts that no case is WRONG. This script writes ``docs/stability.md``.

Usage (from the repository root)::

    python -m tests.support.stability                       # full grid -> docs/stability.md
    python -m tests.support.stability --quick               # the default-test subset only
    python -m tests.support.stability --json out.json       # also dump the outcomes
    python -m tests.support.stability --before before.json  # add a "before the fixes" column
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from .stability_report import write_report
from .stress import Case, Outcome, catalogue, run_case

ROOT = Path(__file__).resolve().parents[2]

REPORT = ROOT / "docs" / "stability.md"


def run(cases: list[Case], progress: bool = True) -> list[Outcome]:
    """Run ``cases`` in order, printing one line per case."""
    out = []
    for i, c in enumerate(cases):
        o = run_case(c)
        out.append(o)
        if progress:
            print(
                f"[{i + 1}/{len(cases)}] {o.verdict:7s} {o.group}: {o.case} ({o.method}, {o.query}) "
                f"{o.answer} vs {o.nominal}  {o.time:.2f}s",
                flush=True,
            )
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="only the default-test subset")
    ap.add_argument("--json", type=Path, help="dump the outcomes as JSON")
    ap.add_argument("--before", type=Path, help="JSON of a run before the fixes (adds a column)")
    ap.add_argument("--report", type=Path, default=REPORT)
    ap.add_argument("--no-report", action="store_true")
    ap.add_argument("--group", help="only this group")
    args = ap.parse_args()
    cases = [
        c for c in catalogue() if (c.quick or not args.quick) and (not args.group or c.group == args.group)
    ]
    t0 = time.perf_counter()
    outcomes = run(cases)
    total = time.perf_counter() - t0
    if args.json:
        args.json.write_text(json.dumps([o.as_dict() for o in outcomes], indent=1, default=float))
    before = json.loads(args.before.read_text()) if args.before else None
    if not args.no_report:
        write_report(outcomes, args.report, before, total)
        print(f"wrote {args.report}")
    bad = [o for o in outcomes if o.verdict == "WRONG"]
    print(
        f"{len(outcomes)} cases, {len(bad)} WRONG ({sum(bool(o.known) for o in bad)} known) in {total:.0f} s"
    )


if __name__ == "__main__":
    main()
