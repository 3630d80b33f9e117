"""Regenerate the documented numbers in one command (from the repository root)::

    python -m scripts.reproduce                      # results, validation, performance
    python -m scripts.reproduce results validation   # some of them
    python -m scripts.reproduce all                  # also energetic, resistance-set, batch
    python -m scripts.reproduce --smoke              # every script on a tiny input, to a temp dir

Targets (each a module of this package, run in its own process so that its BLAS settings and
caches are its own):

* ``results`` — ``paper_results``: docs/results.md and the README "Results vs the paper" table;
* ``validation`` — ``validate_mujoco``: docs/validation.md (the marked sections below kept);
* ``quasistatic`` — ``validate_quasistatic``: the quasi-static method against the cached
  simulations, the paper's methods beside it, and λ* against ``tangential_ratio`` on case 1-3
  (docs/validation.md between the ``quasistatic-validation`` markers; ~15 s, the simulations and
  the paper's methods read from ``scripts/reproduce/data/``);
* ``performance`` — ``error_vs_runtime``: docs/error_vs_runtime.md and the README
  "Performance" table;
* ``energetic``, ``resistance-set``, ``batch`` — the measured tables of docs/methods.md,
  docs/resistance_set.md and docs/batch.md (``all`` adds them).

``--smoke`` runs every target with its smallest input and writes into a temporary folder: a
check that the scripts still run, not numbers to publish (the docs and README are untouched).
"""

from __future__ import annotations

import argparse
import importlib.util
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DEFAULT = ("results", "validation", "quasistatic", "performance")
#: Optional packages a target needs beyond the dev extra.
NEEDS = {"batch": ("ray", "distributed")}
EXTRA = ("energetic", "resistance-set", "batch")


def commands(smoke: Path | None) -> dict[str, list[str]]:
    """Module and arguments of each target: the full run, or the smoke run writing under ``smoke``."""
    if smoke is None:
        return {
            "results": ["paper_results"],
            "validation": ["validate_mujoco"],
            "quasistatic": [
                "validate_quasistatic",
                "--methods",
                "quasistatic,energetic,iterative,prp",
                "--ratios",
                "0.1,1,10,100",
                "--doc",
                "docs/validation.md",
            ],
            "performance": ["error_vs_runtime"],
            "energetic": ["energetic"],
            "resistance-set": ["resistance_set"],
            "batch": ["batch_throughput"],
        }
    (smoke / "img").mkdir(parents=True, exist_ok=True)
    return {
        "results": ["paper_results", "--fast", "--cases", "fig1", "--docs", str(smoke), "--no-readme"],
        "validation": [
            "validate_mujoco",
            "--scenes",
            "pinch",
            "-n",
            "2",
            "--out",
            str(smoke / "validation.md"),
        ],
        "quasistatic": [
            "validate_quasistatic",
            "--methods",
            "quasistatic,energetic,iterative,prp",
            "--limit",
            "2",
            "--out",
            str(smoke / "validation_quasistatic.md"),
        ],
        "performance": ["error_vs_runtime", "--quick", "--repeat", "1", "--out", str(smoke / "evr.md")],
        "energetic": ["energetic", "--quick", "--img", str(smoke / "img" / "energetic.png")],
        "resistance-set": ["resistance_set", "--n", "4", "--n-case2", "4", "--workers", "1"],
        "batch": ["batch_throughput", "--n", "2", "--no-write"],
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m scripts.reproduce", description=__doc__.split("\n\n")[0])
    ap.add_argument("targets", nargs="*", help=f"default: {' '.join(DEFAULT)}; 'all' adds {' '.join(EXTRA)}")
    ap.add_argument("--smoke", action="store_true", help="tiny inputs, outputs to a temporary folder")
    args = ap.parse_args(argv)
    targets = list(args.targets) or list(DEFAULT)
    if targets == ["all"]:
        targets = [*DEFAULT, *EXTRA]
    with tempfile.TemporaryDirectory(prefix="pinograsp-reproduce-") as tmp:
        table = commands(Path(tmp) if args.smoke else None)
        unknown = [t for t in targets if t not in table]
        if unknown:
            ap.error(f"unknown target(s) {', '.join(unknown)}; valid: {', '.join(table)}, all")
        for target in targets:
            module, *rest = table[target]
            if args.smoke and target == "resistance-set":
                print("resistance-set --smoke writes docs/resistance_set.md: skipped", flush=True)
                continue
            missing = [m for m in NEEDS.get(target, ()) if importlib.util.find_spec(m) is None]
            if missing:
                print(
                    f"{target}: needs {', '.join(missing)} (pip install -e '.[ray,dask]'): skipped",
                    flush=True,
                )
                continue
            t0 = time.perf_counter()
            print(f"== {target}: python -m scripts.reproduce.{module} {' '.join(rest)}", flush=True)
            rc = subprocess.run(
                [sys.executable, "-m", f"scripts.reproduce.{module}", *rest], cwd=ROOT
            ).returncode
            print(f"== {target}: exit {rc} in {time.perf_counter() - t0:.0f} s", flush=True)
            if rc:
                return rc
    return 0


if __name__ == "__main__":
    sys.exit(main())
