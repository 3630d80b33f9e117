"""The runner of the benchmark suite (``python -m benchmarks --help``).

Discovers the benchmark classes of the ``bench_*.py`` modules of this package, runs every
combination of their parameters and prints one markdown table per class: a row per parameter
combination, a column per ``time_*`` method (median of ``repeat`` runs [ms], fastest in
parentheses) and per ``track_*`` method (the value it returns, its unit in the header). Counts,
not wall-clock limits, bound every run (``repeat``); nothing is asserted.
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import itertools
import json
import os
import pkgutil
import platform
import re
import statistics
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from importlib.metadata import version
from pathlib import Path
from typing import Any

PACKAGE = Path(__file__).resolve().parent


@dataclass
class Result:
    """One benchmark class at one parameter combination."""

    benchmark: str
    params: tuple[Any, ...]
    times: dict[str, list[float]] = field(default_factory=dict)
    tracks: dict[str, float] = field(default_factory=dict)
    skipped: str = ""


def benchmark_classes(pattern: str | None = None) -> Iterator[tuple[str, type]]:
    """``(module.Class, class)`` of every benchmark (a class with ``time_*`` or ``track_*``)."""
    for info in sorted(pkgutil.iter_modules([str(PACKAGE)]), key=lambda i: i.name):
        if not info.name.startswith("bench_"):
            continue
        module = importlib.import_module(f"{__package__}.{info.name}")
        for name, cls in inspect.getmembers(module, inspect.isclass):
            if cls.__module__ != module.__name__ or not _methods(cls):
                continue
            full = f"{info.name}.{name}"
            if pattern is None or re.search(pattern, full):
                yield full, cls


def _methods(cls: type) -> list[str]:
    return [m for m in dir(cls) if m.startswith(("time_", "track_")) and callable(getattr(cls, m))]


def _grid(cls: type, quick: bool) -> list[tuple[Any, ...]]:
    params = getattr(cls, "params", [])
    if params and not isinstance(params[0], (list, tuple)):
        params = [params]
    if quick:
        params = [p[:1] for p in params]
    return list(itertools.product(*params)) if params else [()]


def run_one(cls: type, combo: tuple[Any, ...], repeat: int, name: str) -> Result:
    """Set up ``cls`` at ``combo`` and run its ``time_*`` (``repeat`` times) and ``track_*``."""
    out = Result(name, combo)
    bench = cls()
    try:
        if hasattr(bench, "setup"):
            bench.setup(*combo)
    except NotImplementedError as exc:
        out.skipped = str(exc) or "not applicable"
        return out
    for m in _methods(cls):
        fn: Callable[..., Any] = getattr(bench, m)
        if m.startswith("time_"):
            for _ in range(getattr(cls, "warmup", 1)):  # first calls: imports, caches
                fn(*combo)
            runs = []
            for _ in range(getattr(cls, "repeat", repeat)):
                t0 = time.perf_counter()
                fn(*combo)
                runs.append(time.perf_counter() - t0)
            out.times[m] = runs
        else:
            out.tracks[m] = float(fn(*combo))
    if hasattr(bench, "teardown"):
        bench.teardown(*combo)
    return out


def table(cls: type, results: list[Result]) -> str:
    """The markdown table of one benchmark class."""
    names = list(getattr(cls, "param_names", [])) or [f"p{i}" for i in range(len(results[0].params))]
    methods = _methods(cls)
    heads = [
        m.removeprefix("time_") + " [ms]" if m.startswith("time_") else _track_head(cls, m) for m in methods
    ]
    lines = ["| " + " | ".join([*names, *heads]) + " |", "|" + "---|" * len(names) + "---:|" * len(heads)]
    for r in results:
        cells = [str(p) for p in r.params]
        for m in methods:
            if r.skipped:
                cells.append("—")
            elif m in r.times:
                ms = [1e3 * t for t in r.times[m]]
                cells.append(f"{statistics.median(ms):.1f} ({min(ms):.1f})")
            else:
                cells.append(f"{r.tracks[m]:.4g}")
        lines.append("| " + " | ".join(cells) + " |")
    skipped = [f"{r.params}: {r.skipped}" for r in results if r.skipped]
    return "\n".join(lines) + ("\n\nskipped: " + "; ".join(skipped) if skipped else "")


def _track_head(cls: type, m: str) -> str:
    unit = getattr(getattr(cls, m), "unit", "")
    return m.removeprefix("track_") + (f" [{unit}]" if unit else "")


def environment() -> str:
    """Machine and versions, one line."""
    pkgs = ", ".join(f"{p} {version(p)}" for p in ("pinograsp", "numpy", "daqp", "pin"))
    return f"{platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}; {pkgs}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.split("\n\n")[0])
    ap.add_argument("-k", dest="pattern", help="only benchmarks whose module.Class matches this regex")
    ap.add_argument("--quick", action="store_true", help="the first value of every parameter, one run")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each time_* method (default 3)")
    ap.add_argument("--list", action="store_true", help="list the benchmarks and their parameters")
    ap.add_argument("--json", type=Path, help="also write every measurement to this file")
    args = ap.parse_args(argv)
    classes = list(benchmark_classes(args.pattern))
    if args.list:
        for name, cls in classes:
            print(f"{name}: {', '.join(getattr(cls, 'param_names', []))} x {', '.join(_methods(cls))}")
        return 0
    repeat = 1 if args.quick else args.repeat
    print(environment(), end="\n\n", flush=True)
    everything: list[Result] = []
    for name, cls in classes:
        t0 = time.perf_counter()
        results = [run_one(cls, combo, repeat, name) for combo in _grid(cls, args.quick)]
        everything += results
        doc = (inspect.getdoc(cls) or "").split("\n\n")[0].replace("\n", " ")
        print(
            f"## {name}\n\n{doc}\n\n{table(cls, results)}\n\n({time.perf_counter() - t0:.0f} s)\n", flush=True
        )
    if args.json:
        rows = [
            {
                "benchmark": r.benchmark,
                "params": [str(p) for p in r.params],
                "times_s": r.times,
                "tracks": r.tracks,
                "skipped": r.skipped,
            }
            for r in everything
        ]
        args.json.write_text(json.dumps({"environment": environment(), "results": rows}, indent=1))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
