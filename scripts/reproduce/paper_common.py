"""Shared parts of ``scripts/reproduce/paper_results.py``: records, run settings, cached solves,
text helpers."""

from __future__ import annotations

import argparse
import hashlib
import pickle
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

import pinograsp as pg
from pinograsp.core import serialize

#: Directions whose Y (resp. second-axis) component is below this count as "along ±X".
TOL = 1e-9
#: The method of the paper's results: the seed paper's iterative scheme (Alg. 2 in Alg. 3), named
#: here because the package default (and so the built-in scenes', which name no method) is the
#: quasi-static loading path; the published numbers stay the paper's method's.
PAPER_METHOD = "iterative"


@dataclass(frozen=True)
class Row:
    """One line of the summary table."""

    case: str
    question: str
    paper: str
    ours: str
    agrees: str  # "yes" / "partly" / "no" / "n/a"
    seconds: float
    quasistatic: str = ""  # the same question answered by method="quasistatic" (its own column)


@dataclass
class Case:
    """One case's summary rows, details (markdown) and run time [s], filled in as it runs."""

    name: str
    rows: list[Row] = field(default_factory=list)
    details: list[str] = field(default_factory=list)
    seconds: float = 0.0
    settings: str = ""


@dataclass(frozen=True)
class RunSettings:
    """The search settings of one case: the scene's, or fewer directions and steps (``--fast``)."""

    method: str
    upper: float
    steps: int
    n: int
    workers: int | None


# ---------------------------------------------------------------------------- text
def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def fmt(m: float, unbounded: bool = False, unit: str = "N", digits: int = 3) -> str:
    if unbounded or not np.isfinite(m):
        return "unbounded"
    return f"{m:.{digits}g} {unit}"


def deg_list(angles: np.ndarray) -> str:
    return ", ".join(f"{a:g}°" for a in np.round(np.degrees(angles), 1))


def runs_text(deg: np.ndarray, mask: np.ndarray) -> str:
    """The runs of ``mask`` over the angles ``deg`` [°], e.g. ``"190°–350°"``."""
    return serialize.runs_text(serialize.unbounded_runs(deg, mask))


def vec_text(w: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:g}" for x in w) + ")"


def settings_text(s: RunSettings) -> str:
    return (
        f"method `{s.method}`, upper limit {s.upper:g}, {s.steps} bisection steps "
        f"(resolution {s.upper / 2**s.steps:.2g}), n = {s.n} directions per profile"
    )


def progress_log(label: str, total: int) -> Any:
    """A ``progress(done, total)`` callback logging one line per quarter of the directions."""
    t0 = time.perf_counter()

    def report(done: int, total: int) -> None:
        if done and (done == total or done * 4 // total != (done - 1) * 4 // total):
            log(f"{label}: {done}/{total} directions, {time.perf_counter() - t0:.0f} s")

    return report


# ---------------------------------------------------------------------------- scenes and settings
def scene_settings(scene: Any, args: argparse.Namespace) -> RunSettings:
    """The run settings of one case: ``args.method`` when given (the quasi-static column), else the
    paper's method (:data:`PAPER_METHOD`), with the scene's upper limit, steps and n."""
    a = scene.analysis
    method = getattr(args, "method", None) or PAPER_METHOD
    if args.fast:
        return RunSettings(method, a.upper, min(a.steps, 8), min(a.n, 16), args.workers)
    return RunSettings(method, a.upper, a.steps, a.n, args.workers)


def load(name: str) -> Any | None:
    try:
        return pg.load_scene(name)
    except pg.UnknownNameError:
        return None


def find_direction(scene: Any, target: np.ndarray, fallback: str) -> tuple[Any, str]:
    for k, v in scene.analysis.directions.items():
        if np.allclose(v, target):
            return np.asarray(v), k
    return fallback, fallback


def missing(name: str) -> Case:
    c = Case(name)
    c.rows.append(Row(name, "scene", "-", f"built-in scene `{name}` not available", "n/a", 0.0))
    c.details.append(f"The built-in scene `{name}` is not available in this checkout; nothing was computed.")
    return c


# ---------------------------------------------------------------------------- cached solves
#: Where computed profiles and bisections are kept (``--reuse`` reads them back).
CACHE: dict[str, Any] = {"dir": None, "reuse": False}


def _source_digest() -> str:
    """Digest of the package's source and data: a cached answer is reused only for the same code."""
    h = hashlib.sha256()
    root = Path(pg.__file__).resolve().parent
    for f in sorted(root.rglob("*")):
        if f.is_file() and f.suffix in (".py", ".yaml", ".urdf"):
            h.update(f.relative_to(root).as_posix().encode())
            h.update(f.read_bytes())
    return h.hexdigest()


def _cache_key(scene: Any, *parts: Any) -> str:
    h = hashlib.sha256()
    h.update(Path(scene.path).read_bytes())
    for extra in scene.data.get("extends", ()), pg.__version__, SOURCE_DIGEST:
        h.update(repr(extra).encode())
    for p in parts:
        h.update(repr(np.round(np.asarray(p, dtype=float), 12).tolist() if _numeric(p) else p).encode())
    return f"{scene.name}-{h.hexdigest()[:16]}"


SOURCE_DIGEST = _source_digest()


def _numeric(p: Any) -> bool:
    try:
        np.asarray(p, dtype=float)
        return not isinstance(p, (str, dict))
    except (TypeError, ValueError):
        return False


def cached(key: str, compute: Any) -> Any:
    """``compute()``, stored under ``key`` in the cache folder; read back with ``--reuse``."""
    folder = CACHE["dir"]
    if folder is None:
        return compute()
    path = Path(folder) / f"{key}.pickle"
    if CACHE["reuse"] and path.is_file():
        with path.open("rb") as fh:
            return pickle.load(fh)
    value = compute()
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("wb") as fh:
        pickle.dump(value, fh)
    return value


def profile(scene: Any, s: RunSettings, plane: Any, command: Any = None, label: str = "") -> Any:
    """The scene's resistance profile in ``plane`` (cached)."""
    cmd = scene.command if command is None else command
    key = _cache_key(
        scene, "profile", tuple(map(str, plane)), sorted(cmd.items()), s.method, s.upper, s.steps, s.n
    )
    return cached(key, lambda: _profile(scene, s, plane, cmd, label))


def _profile(scene: Any, s: RunSettings, plane: Any, command: Any, label: str) -> Any:
    return pg.resistance_profile(
        scene.model,
        command,
        plane,
        s.n,
        s.method,
        s.upper,
        s.steps,
        settings=scene.settings,
        progress=progress_log(f"{scene.name} {label or plane}", s.n),
        workers=s.workers,
    )


def max_wrench(
    scene: Any,
    command: Any,
    direction: Any,
    s: RunSettings,
    method: str | None = None,
    variant: str | None = None,
) -> Any:
    """The scene's max resistible wrench along ``direction`` (cached)."""
    m = method or s.method
    d = pg.wrench_direction(scene.model, direction)
    parts = (m, s.upper, s.steps) if variant is None else (m, s.upper, s.steps, variant)
    key = _cache_key(scene, "max", d, sorted(dict(command).items()), *parts)
    settings = scene.settings if variant is None else replace(scene.settings, variant=variant)
    return cached(
        key,
        lambda: pg.max_resistible_wrench(scene.model, command, d, m, s.upper, s.steps, settings=settings),
    )


# ---------------------------------------------------------------------------- mirror symmetry
def mirror_index(n: int, i: int) -> int:
    """Index of the direction mirrored across the second axis (angle π − θ), for n directions."""
    return (n // 2 - i) % n


def symmetry(p: Any) -> tuple[int, int, float]:
    """Mirror symmetry across the plane's second axis (x -> -x): verdict mismatches, pairs
    compared, largest relative difference of finite magnitude pairs."""
    n = len(p.angles)
    if n % 2:
        return 0, 0, float("nan")
    bad, pairs, worst = 0, 0, 0.0
    for i in range(n):
        j = mirror_index(n, i)
        if j <= i:
            continue
        pairs += 1
        if p.unbounded[i] != p.unbounded[j]:
            bad += 1
        elif not p.unbounded[i]:
            a, b = p.magnitudes[i], p.magnitudes[j]
            if max(a, b) > 0:
                worst = max(worst, abs(a - b) / max(a, b))
    return bad, pairs, worst


def mismatched_pairs(p: Any) -> list[tuple[float, float]]:
    """Mirror pairs (θ, 180° − θ) whose verdicts (finite / unbounded) differ, in degrees."""
    n = len(p.angles)
    out = []
    for i in range(n):
        j = mirror_index(n, i)
        if j > i and p.unbounded[i] != p.unbounded[j]:
            out.append((float(np.degrees(p.angles[i]).round(1)), float(np.degrees(p.angles[j]).round(1))))
    return out
