"""Command-line interface ``pinograsp`` (see ``docs/cli.md``).

Sub-commands::

    pinograsp demo [--scene case1] [-n 24] [--out ./pinograsp-out]
    pinograsp scenes [SCENE]
    pinograsp analyze SCENE --wrench fx,fy,fz,mx,my,mz
    pinograsp max-wrench SCENE --direction fy|-fy|1,0,0,0,0,0|<scene direction name>
    pinograsp profile SCENE [--plane fx,fy] [-n 72] [--normalize]
    pinograsp compare-preloads SCENE [--direction NAME ...]
    pinograsp batch GRASPS.yaml [--executor local|ray|dask] [--workers N] [--out results.parquet]
    pinograsp resistance-set SCENE [-n 500] [--csv FILE]

``SCENE`` is a built-in scene name (``pinograsp scenes``) or the path of a scene YAML file.
Common options: ``--method prp|iterative``, ``--upper``, ``--steps``, ``--json`` (the result as
JSON on stdout and nothing else), ``--out DIR`` (plots and JSON files), ``--debug`` (full
tracebacks). Errors are one line ``pinograsp: error: ...`` on stderr; bad input
(:class:`~pinograsp.errors.PinograspError`, bad options) exits with code 2.
"""

from __future__ import annotations

import argparse
import contextlib
import inspect
import json
import math
import os
import sys
import time
import warnings
from collections.abc import Callable, Iterator, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any, TextIO

import numpy as np

from ..core.serialize import (  # noqa: F401  (unbounded_runs: re-exported for scripts importing it from here)
    direction_text,
    format_magnitude,
    format_max_wrench,
    jsonable,
    runs_text,
    unbounded_runs,
    vector_text,
    wrench_unit,
)
from ..errors import InvalidInputError, PinograspError

#: Defaults of ``pinograsp demo``: small enough to finish in well under a minute on 2 cores.
DEMO_SCENE = "case1"
DEMO_N = 24
DEMO_STEPS = 10

#: Options whose value may start with ``-`` (``--direction -fy``, ``--wrench -5,0,0``).
_DASH_VALUE_OPTIONS = ("--direction", "-d", "--wrench", "-w", "--plane", "-p")
_AXES = ("fx", "fy", "fz", "mx", "my", "mz")


# ---------------------------------------------------------------------------- argument parsing
class _UsageError(Exception):
    """A command-line usage error (argparse's ``error``), reported on one line."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        raise _UsageError(message)


def _join_dash_values(argv: Sequence[str]) -> list[str]:
    """``--direction -fy`` -> ``--direction=-fy`` (argparse would take ``-fy`` for an option)."""
    out: list[str] = []
    it = iter(range(len(argv)))
    skip = False
    for i in it:
        if skip:
            skip = False
            continue
        tok = argv[i]
        nxt = argv[i + 1] if i + 1 < len(argv) else None
        if tok in _DASH_VALUE_OPTIONS and nxt is not None and nxt.startswith("-") and len(nxt) > 1:
            out.append(f"{tok}={nxt}")
            skip = True
        else:
            out.append(tok)
    return out


def _common(p: argparse.ArgumentParser, *, out_default: str | None = None) -> None:
    g = p.add_argument_group("common options")
    g.add_argument(
        "--method",
        choices=("prp", "iterative"),
        help="prp (Alg. 1, one MIQP) or iterative (Alg. 2+3, no wedging); default: the scene's",
    )
    g.add_argument(
        "--variant",
        choices=("single-step", "preload-first", "settled-preload"),
        help="load path: preload and load together, preload first (object held still), or the "
        "object settled into the preload first; default: the scene's (docs/design.md)",
    )
    g.add_argument("--upper", type=float, help="bisection upper limit [N or N·m]; default: the scene's")
    g.add_argument(
        "--steps", type=int, help="bisection steps (resolution upper/2**steps); default: the scene's"
    )
    g.add_argument("--solver", help="MIQP backend (default: the scene's, normally scip)")
    g.add_argument("--time-limit", type=float, help="per-MIQP time limit [s]")
    g.add_argument("--json", action="store_true", help="print the result as JSON on stdout (nothing else)")
    g.add_argument(
        "--out",
        default=out_default,
        help="write plots and JSON files to this folder"
        + (f" (default {out_default})" if out_default else " (default: write nothing)"),
    )
    g.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help="show full tracebacks")


def _progress_options(p: argparse.ArgumentParser, workers_default: int | None = None) -> None:
    p.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="progress bar with ETA on stderr (default: when stderr is a terminal)",
    )
    p.add_argument(
        "--workers",
        type=int,
        default=workers_default,
        help="processes for the profile's directions (0: one per CPU; 1: in this process; default "
        + ("0" if workers_default == 0 else "1")
        + ")",
    )


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="pinograsp",
        description="Passive reaction analysis for robot grasps: which disturbances a preloaded "
        "grasp resists without changing its motor commands.",
        epilog="SCENE is a built-in scene name (see 'pinograsp scenes') or a scene YAML file. "
        "Docs: docs/cli.md.",
    )
    parser.add_argument("--debug", action="store_true", help="show full tracebacks")
    sub = parser.add_subparsers(dest="cmd", required=True, metavar="COMMAND")

    p = sub.add_parser(
        "demo",
        help="XY resistance profile of the case1 scene (table, profile.png, profile.json)",
        description="Resistance profile of a built-in grasp in its XY plane (default: the seed paper's "
        "case 1, Barrett hand on a box) with few directions; prints a table and writes profile.png "
        "and profile.json.",
    )
    p.add_argument("--scene", default=DEMO_SCENE, help=f"scene name or file (default {DEMO_SCENE})")
    p.add_argument("-n", type=int, default=DEMO_N, help=f"number of directions (default {DEMO_N})")
    p.add_argument("--plane", "-p", help="profile plane, e.g. fx,fy (default: the scene's)")
    p.add_argument(
        "--normalize",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="divide by the +Y (second axis) value as the paper does (default: the scene's setting)",
    )
    _common(p, out_default="pinograsp-out")
    _progress_options(p, workers_default=0)
    p.set_defaults(func=cmd_demo, demo_steps=DEMO_STEPS)

    s = sub.add_parser("scenes", help="list the built-in scenes (or describe one)")
    s.add_argument("scene", nargs="?", help="show this scene's model, preload and analysis settings")
    s.add_argument("--json", action="store_true", help="print as JSON")
    s.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help="show full tracebacks")
    s.set_defaults(func=cmd_scenes)

    a = sub.add_parser(
        "analyze",
        help="passive response to one wrench: status, contact forces, audit",
        description="Passive response of the preloaded grasp to one external wrench on the object.",
    )
    a.add_argument("scene", metavar="SCENE")
    a.add_argument(
        "--wrench",
        "-w",
        required=True,
        help="fx,fy,fz,mx,my,mz [N, N·m] (planar scenes: also fx,fy,mz), axis=value pairs "
        "(fy=-5,mz=0.1), or the name of one of the scene's wrenches",
    )
    a.add_argument("--preload", help="one of the scene's named preloads (default: the scene's preload)")
    a.add_argument("--html", metavar="FILE", help="write the interactive 3D view (plotly) to FILE")
    _common(a)
    a.set_defaults(func=cmd_analyze)

    m = sub.add_parser(
        "max-wrench",
        help="largest resistible wrench along one direction (bisection)",
        description="Largest wrench magnitude along a direction that the preloaded grasp resists passively.",
    )
    m.add_argument("scene", metavar="SCENE")
    m.add_argument(
        "--direction",
        "-d",
        required=True,
        help="an axis with sign (fy, -fy, mx), a wrench vector 1,0,0,0,0,0, or a scene direction name",
    )
    m.add_argument("--preload", help="one of the scene's named preloads (default: the scene's preload)")
    m.add_argument(
        "--html", metavar="FILE", help="write the interactive 3D view at the limit (plotly) to FILE"
    )
    _common(m)
    m.set_defaults(func=cmd_max_wrench)

    pr = sub.add_parser(
        "profile",
        help="max resistible magnitude over directions in a plane (polar plot)",
        description="Resistance profile: max resistible magnitude over n directions in a plane of "
        "wrench space.",
    )
    pr.add_argument("scene", metavar="SCENE")
    pr.add_argument(
        "--plane",
        "-p",
        help="two axes fx,fy | fx,fz | mx,my ..., two vectors 'v1;v2', or a scene plane name "
        "(default: the scene's plane)",
    )
    pr.add_argument("-n", type=int, help="number of directions (default: the scene's)")
    pr.add_argument(
        "--normalize",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="divide by the value along the plane's second axis (+Y), as the paper does "
        "(default: the scene's setting)",
    )
    pr.add_argument("--preload", help="one of the scene's named preloads (default: the scene's preload)")
    pr.add_argument(
        "--csv",
        metavar="FILE",
        help="also write the profile as CSV: one row per direction (angle, direction, magnitude, status ...)",
    )
    _common(pr)
    _progress_options(pr)
    pr.set_defaults(func=cmd_profile)

    c = sub.add_parser(
        "compare-preloads",
        help="max resistible wrench per named preload of the scene, and their ratio (bar plot)",
        description="For each of the scene's named preloads (analysis.preloads) and named directions "
        "(analysis.directions), the max resistible magnitude, and the ratio of the first two preloads.",
    )
    c.add_argument("scene", metavar="SCENE")
    c.add_argument(
        "--direction",
        "-d",
        action="append",
        help="direction(s) to compare (repeatable; default: every named direction of the scene)",
    )
    c.add_argument("--preloads", help="comma-separated preload names (default: all of the scene's)")
    _common(c)
    c.set_defaults(func=cmd_compare_preloads)

    rs = sub.add_parser(
        "resistance-set",
        help="max resistible magnitude over n directions spread evenly on the unit wrench sphere",
        description="Resistance set: max resistible magnitude over n directions spread evenly on the "
        "unit wrench sphere (torques scaled by the grasp's length scale), its quantiles and worst "
        "direction, and the Ferrari-Canny epsilon of the same contacts (docs/metrics.md).",
    )
    rs.add_argument("scene", metavar="SCENE")
    rs.add_argument("-n", type=int, default=500, help="number of directions (default 500)")
    rs.add_argument("--seed", type=int, default=0, help="seed of the directions (default 0)")
    rs.add_argument("--length", type=float, help="length scaling torques [m] (default: the grasp's own)")
    rs.add_argument("--preload", help="one of the scene's named preloads (default: the scene's preload)")
    rs.add_argument("--csv", metavar="FILE", help="also write one CSV row per direction")
    _common(rs)
    _progress_options(rs)
    rs.set_defaults(func=cmd_resistance_set)

    pl = sub.add_parser(
        "preload",
        help="choose actuator commands under which the grasp is in equilibrium (or say why none)",
        description="Commands under which the preload alone is in equilibrium with every contact "
        "pressing (pg.equilibrium_preload; docs/hands.md, 'Choosing a preload').",
    )
    pl.add_argument("scene", metavar="SCENE")
    pl.add_argument("--objective", choices=("balanced", "least_norm"), default="balanced")
    pl.add_argument("--max-command", type=float, default=1.0, help="bound of every command [N·m or N]")
    pl.add_argument("--grip", type=float, default=1.0, help="least normal force for least_norm [N]")
    _common(pl)
    pl.set_defaults(func=cmd_preload)
    _add_optimal_preload(sub)

    b = sub.add_parser(
        "batch",
        help="score many grasps (GRASPS.yaml) on local processes, Ray or Dask; table out",
        description="pg.evaluate_grasps over the grasps of a GRASPS.yaml (docs/batch.md): one row per "
        "grasp (status, score and its components, contacts, timing, error), written to --out.",
    )
    b.add_argument("grasps", metavar="GRASPS.yaml")
    b.add_argument("--executor", choices=("local", "ray", "dask"), default="local")
    b.add_argument("--workers", type=int, help="processes / Ray tasks / Dask workers (0: one per CPU)")
    b.add_argument("--address", help="existing cluster: Ray 'auto' or ray://..., Dask tcp://host:8786")
    b.add_argument("--out", help="results table: .parquet or .csv (default: print a summary only)")
    b.add_argument("--upper", type=float, help="score search limit [N] (default: the file's score block)")
    b.add_argument("--steps", type=int, help="score search steps (default: the file's score block)")
    b.add_argument("--method", choices=("prp", "iterative"), help="score method (default: the file's)")
    b.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="progress bar with ETA on stderr (default: when stderr is a terminal)",
    )
    b.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help="show full tracebacks")
    b.set_defaults(func=cmd_batch)
    return parser


# ---------------------------------------------------------------------------- helpers
def _load(name_or_path: str) -> Any:
    from ..scenes.loading import load_scene

    return load_scene(name_or_path)


def _method(args: argparse.Namespace, scene: Any) -> str:
    return args.method or scene.analysis.method


def _upper_steps(args: argparse.Namespace, scene: Any, default_steps: int | None = None) -> tuple[float, int]:
    upper = args.upper if args.upper is not None else float(scene.analysis.upper)
    if args.steps is not None:
        steps = args.steps
    elif default_steps is not None:
        steps = default_steps
    else:
        steps = int(scene.analysis.steps)
    if not (math.isfinite(upper) and upper > 0):
        raise InvalidInputError("--upper", f"must be finite and > 0, got {upper!r}")
    if steps < 1:
        raise InvalidInputError("--steps", f"must be >= 1, got {steps}")
    return upper, steps


def _settings(args: argparse.Namespace, scene: Any) -> Any:
    from ..core.settings import make_settings

    over: dict[str, Any] = {}
    if getattr(args, "solver", None):
        over["solver"] = args.solver
    if getattr(args, "time_limit", None) is not None:
        over["time_limit"] = args.time_limit
    if getattr(args, "variant", None):
        over["variant"] = args.variant
    return make_settings(scene.settings, **over)


def _command(args: argparse.Namespace, scene: Any) -> tuple[dict[str, float], str | None]:
    name = getattr(args, "preload", None)
    return scene.preload(name), name


def _floats(text: str, what: str) -> list[float]:
    parts = [t.strip() for t in text.replace(";", ",").split(",")]
    try:
        vals = [float(t) for t in parts]
    except ValueError:
        raise InvalidInputError(
            what, f"expected comma-separated numbers like 0,-5,0,0,0,0, got {text!r}"
        ) from None
    if not all(math.isfinite(v) for v in vals):
        raise InvalidInputError(what, f"contains NaN or inf: {text!r}")
    return vals


def _axis_values(text: str, what: str) -> np.ndarray:
    from ..core.axes import axis_index

    w = np.zeros(6)
    for part in text.split(","):
        if "=" not in part:
            raise InvalidInputError(what, f"mix of axis=value and plain numbers in {text!r}")
        key, _, val = part.partition("=")
        i = axis_index(key.strip())
        try:
            w[i] += float(val)
        except ValueError:
            raise InvalidInputError(what, f"{key.strip()}: expected a number, got {val.strip()!r}") from None
        if not math.isfinite(w[i]):
            raise InvalidInputError(what, f"{key.strip()}: must be finite, got {val.strip()!r}")
    return w


def parse_wrench(scene: Any, text: str) -> np.ndarray:
    """``--wrench``: numbers (6, or 3 for planar scenes), ``axis=value`` pairs, or a scene wrench."""
    text = text.strip()
    named = scene.analysis.wrenches
    if text in named:
        return np.asarray(named[text], dtype=float)
    if not text:
        raise InvalidInputError("--wrench", "empty wrench")
    if "=" in text:
        w = _axis_values(text, "--wrench")
    else:
        if not any(ch.isdigit() for ch in text):
            hint = f"; the scene's wrenches: {', '.join(named)}" if named else ""
            raise InvalidInputError(
                "--wrench", f"expected fx,fy,fz,mx,my,mz (or axis=value pairs), got {text!r}{hint}"
            )
        vals = _floats(text, "--wrench")
        if len(vals) not in (6, 3) or (len(vals) == 3 and not scene.model.planar):
            want = "6 numbers (fx,fy,fz,mx,my,mz)" + (" or 3 (fx,fy,mz)" if scene.model.planar else "")
            raise InvalidInputError("--wrench", f"expected {want}, got {len(vals)} in {text!r}")
        w = vals
    return scene.model.wrench_vector(w, "--wrench")


def parse_direction(scene: Any, text: str) -> tuple[object, str]:
    """``--direction``: a scene direction name, a signed axis (``-fy``), or a vector.

    Returns what :func:`pinograsp.max_resistible_wrench` takes, and a label.
    """
    from ..core.axes import axis_index

    text = text.strip()
    named = scene.analysis.directions
    if text in named:
        return np.asarray(named[text], dtype=float), text
    if "," in text or ";" in text:
        vals = _floats(text, "--direction")
        if len(vals) not in (6, 3) or (len(vals) == 3 and not scene.model.planar):
            raise InvalidInputError("--direction", f"expected 6 numbers, got {len(vals)} in {text!r}")
        return scene.model.wrench_vector(vals, "--direction"), text
    try:
        axis_index(text.lstrip("+-"))
    except PinograspError:
        from ..errors import UnknownNameError

        valid = [*(f"{s}{a}" for a in _AXES for s in ("", "-")), *named]
        raise UnknownNameError("direction", text, valid) from None
    return text, text if text[0] in "+-" else f"+{text}"


def parse_plane(scene: Any, text: str | None) -> tuple[object, object]:
    """``--plane``: ``fx,fy``, a scene plane name, or two vectors ``'v1;v2'``."""
    from ..core.axes import axis_index

    if text is None:
        return tuple(scene.analysis.plane)  # type: ignore[return-value]
    text = text.strip()
    planes = scene.analysis.planes
    if text in planes:
        return tuple(planes[text])  # type: ignore[return-value]
    if ";" in text:
        parts = text.split(";")
        if len(parts) != 2:
            raise InvalidInputError("--plane", f"expected two vectors 'v1;v2', got {text!r}")
        return tuple(_floats(p, "--plane") for p in parts)  # type: ignore[return-value]
    parts = [t.strip() for t in text.split(",")]
    if len(parts) != 2:
        hint = f" or a scene plane ({', '.join(planes)})" if planes else ""
        raise InvalidInputError("--plane", f"expected two axes like fx,fy{hint}, got {text!r}")
    for t in parts:
        axis_index(t.lstrip("+-"))
    return parts[0], parts[1]


class _Output:
    """stdout for humans, or nothing but JSON with ``--json``; files in ``--out``."""

    def __init__(self, args: argparse.Namespace) -> None:
        self.args = args
        self.json = bool(getattr(args, "json", False))
        self.out = Path(args.out) if getattr(args, "out", None) else None
        self.written: list[Path] = []

    def print(self, *lines: str) -> None:
        if not self.json:
            for line in lines:
                print(line)

    def info(self, line: str) -> None:
        """Human information: stdout normally, stderr with --json."""
        print(line, file=sys.stderr if self.json else sys.stdout)

    def path(self, name: str) -> Path | None:
        if self.out is None:
            return None
        self.out.mkdir(parents=True, exist_ok=True)
        return self.out / name

    def write_json(self, name: str, data: dict) -> None:
        p = self.path(name)
        if p is not None:
            p.write_text(json.dumps(jsonable(data), indent=2) + "\n")
            self.written.append(p)

    def figure(self, name: str, draw: Callable[[Path], object]) -> None:
        p = self.path(name)
        if p is not None:
            draw(p)
            self.written.append(p)

    def finish(self, data: dict) -> None:
        if self.json:  # printed by main() once the solvers' stdout is restored
            self.args.json_text = json.dumps(jsonable(data), indent=2) + "\n"
        elif self.written:
            print("\nwrote " + ", ".join(str(p) for p in self.written))


class ProgressBar:
    """A tiny progress bar with elapsed time and ETA, on one stderr line."""

    def __init__(self, label: str, stream: TextIO | None = None, width: int = 28, enabled: bool = True):
        self.label = label
        self.stream = stream if stream is not None else sys.stderr
        self.width = width
        self.enabled = enabled
        self.t0 = time.perf_counter()
        self._last = ""

    @staticmethod
    def clock(seconds: float) -> str:
        if not math.isfinite(seconds):
            return "--:--"
        s = int(round(seconds))
        return (
            f"{s // 3600}:{s % 3600 // 60:02d}:{s % 60:02d}" if s >= 3600 else f"{s // 60:02d}:{s % 60:02d}"
        )

    def text(self, done: int, total: int) -> str:
        elapsed = time.perf_counter() - self.t0
        frac = done / total if total else 1.0
        k = int(round(self.width * frac))
        eta = elapsed / done * (total - done) if done else float("nan")
        return (
            f"{self.label} [{'#' * k}{'.' * (self.width - k)}] {done}/{total} "
            f"{100 * frac:3.0f}%  {self.clock(elapsed)} elapsed, ETA {self.clock(eta)}"
        )

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        line = self.text(done, total)
        pad = " " * max(0, len(self._last) - len(line))
        self.stream.write("\r" + line + pad)
        self.stream.flush()
        self._last = line

    def close(self) -> None:
        if self.enabled and self._last:
            self.stream.write("\n")
            self.stream.flush()


def _progress_enabled(args: argparse.Namespace) -> bool:
    if args.progress is not None:
        return bool(args.progress)
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def _profile_kwargs(args: argparse.Namespace) -> dict[str, Any]:
    """``workers=`` when ``resistance_profile`` accepts it (process-pool profiles)."""
    from ..analysis.max_wrench import resistance_profile

    workers = getattr(args, "workers", None)
    if workers is None:
        return {}
    if workers < 0:
        raise InvalidInputError("--workers", f"must be >= 0 (0: one per CPU), got {workers}")
    if "workers" in inspect.signature(resistance_profile).parameters:
        return {"workers": workers}
    if workers > 1:
        print(
            "pinograsp: warning: this version's resistance_profile has no 'workers' option; running serially",
            file=sys.stderr,
        )
    return {}


# ---------------------------------------------------------------------------- result -> dict
def _scene_header(scene: Any) -> dict[str, Any]:
    return {"scene": scene.name, "scene_file": scene.path, "description": scene.description}


# ---------------------------------------------------------------------------- commands
def cmd_scenes(args: argparse.Namespace) -> int:
    from ..scenes.loading import builtin_scenes

    if args.scene is None:
        scenes = builtin_scenes()
        if args.json:
            print(json.dumps(scenes, indent=2))
            return 0
        width = max((len(k) for k in scenes), default=4)
        for name, desc in scenes.items():
            print(f"{name:{width}s}  {desc}")
        return 0
    scene = _load(args.scene)
    an = scene.analysis
    data = {
        **_scene_header(scene),
        "contacts": list(scene.model.contact_names),
        "joints": list(scene.model.joint_names),
        "actuators": dict(zip(scene.model.actuator_names, scene.model.kinds)),
        "planar": scene.model.planar,
        "preload": scene.command,
        "analysis": {
            "method": an.method,
            "upper": an.upper,
            "steps": an.steps,
            "n": an.n,
            "plane": list(an.plane),
            "planes": {k: list(v) for k, v in an.planes.items()},
            "normalize": an.normalize,
            "directions": an.directions,
            "wrenches": an.wrenches,
            "preloads": an.preloads,
        },
    }
    if args.json:
        print(json.dumps(jsonable(data), indent=2))
        return 0
    print(scene.summary())
    print(
        f"  analysis: method {an.method}, upper {an.upper:g}, {an.steps} steps, "
        f"n = {an.n}, plane {','.join(map(str, an.plane))}"
    )
    for key in ("directions", "wrenches"):
        if getattr(an, key):
            print(f"  {key}: " + ", ".join(f"{k} {vector_text(v)}" for k, v in getattr(an, key).items()))
    for k, v in an.preloads.items():
        print(f"  preload {k}: " + ", ".join(f"{a}={x:g}" for a, x in v.items()))
    return 0


def _contact_table(model: Any, r: Any) -> list[str]:
    d = r.to_dict(model)
    w = max([len("contact"), *(len(c["name"]) for c in d["contacts"])])
    lines = [
        f"  {'contact':{w}s}  {'mode':9s} {'c_n [N]':>10s} {'c_t1 [N]':>10s} {'c_t2 [N]':>10s}"
        f" {'|c_t|/mu c_n':>12s}   world force [N]"
    ]
    for i, c in enumerate(d["contacts"]):
        f = r.contact_forces[i]  # NaN (not None) when there is no solution
        use = c["friction_use"]
        use_s = "—" if use is None else f"{use:.3f}"
        lines.append(
            f"  {c['name']:{w}s}  {c['mode'] or '—':9s} {f[0]:10.4f} {f[1]:10.4f} {f[2]:10.4f} {use_s:>12s}"
            f"   {vector_text(r.contact_forces_world[i])}"
        )
    return lines


def _actuator_table(model: Any, r: Any) -> list[str]:
    d = r.to_dict(model)
    w = max([len("actuator"), *(len(a["name"]) for a in d["actuators"])])
    lines = [f"  {'actuator':{w}s}  {'kind':17s} {'command':>10s} {'force':>10s}  mode"]
    for i, a in enumerate(d["actuators"]):
        lines.append(
            f"  {a['name']:{w}s}  {a['kind'] or '':17s} {r.command[i]:10.4f} {r.actuator_forces[i]:10.4f}"
            f"  {a['mode'] or '—'}"
        )
    return lines


def _audit_line(r: Any) -> str:
    a = r.audit
    if a is None:
        return "audit: none"
    return (
        f"audit: {'ok' if a.ok else 'NOT OK'} (equilibrium {a.equilibrium:.2e} N, hand {a.hand:.2e} N, "
        f"complementarity {a.complementarity:.2e} N, friction {a.friction:.2e} N, "
        f"big-M use {a.bigm_ratio:.1%}{_energy_text(a.energy)})"
    )


def _energy_text(e: Any) -> str:
    if e is None:
        return ""
    text = f"; spring energy {e.spring_energy:.4g} J <= supplied {e.load_work + e.actuator_work:.4g} J"
    if not e.energy_ok:
        text = text.replace("<=", "> (WEDGING)") + f" at {', '.join(e.contacts)}"
    if not e.displacement_ok:
        text += f"; displacements {e.displacement_ratio:.3g}x the spring compressions (ABSURD)"
    return text


def cmd_analyze(args: argparse.Namespace) -> int:
    from ..analysis.response import passive_response

    scene = _load(args.scene)
    out = _Output(args)
    command, preload_name = _command(args, scene)
    w = parse_wrench(scene, args.wrench)
    method = _method(args, scene)
    settings = _settings(args, scene)
    r = passive_response(scene.model, command, w, method, settings=settings)
    data = {
        "command": "analyze",
        **_scene_header(scene),
        "preload": command,
        "preload_name": preload_name,
        **r.to_dict(scene.model),
    }
    out.print(
        f"scene {scene.name!r}: {scene.description}",
        f"preload: {', '.join(f'{k}={v:g}' for k, v in command.items())}"
        + (f" ({preload_name})" if preload_name else ""),
        f"wrench: {vector_text(r.wrench)} [N, N·m] (fx, fy, fz, mx, my, mz)",
        f"method: {r.method} ({r.variant})",
        "",
        f"status: {r.status} -> {'RESISTED' if r.resistible else 'NOT RESISTED'} "
        f"({r.iterations} iteration(s), {r.n_solves} solve(s), "
        f"{r.solve_time:.2f} s, {r.solver})",
        "",
        "contact forces on the object (contact frame: normal, tangents):",
        *_contact_table(scene.model, r),
        "",
        *_actuator_table(scene.model, r),
        "",
        f"net wrench |w + G c|: {np.linalg.norm(r.net_wrench):.3e}",
        _audit_line(r),
    )
    out.write_json("analyze.json", data)
    out.figure("analyze.png", lambda p: _scene_png(scene, r if r.resistible else None, p))
    _scene_html(args, out, scene, r if r.resistible else None)
    out.finish(data)
    return 0


def _scene_png(scene: Any, response: Any, path: Path) -> None:
    from ..viz.viewer import save_png

    save_png(scene, response, path=path, title=f"{scene.name}")


def _scene_html(args: argparse.Namespace, out: _Output, scene: Any, response: Any) -> None:
    """``--html FILE``: the interactive 3D scene (plotly, standalone: works offline)."""
    if getattr(args, "html", None):
        from ..viz.viewer import save_html, scene_figure

        fig = scene_figure(scene, response, title=f"{scene.name}")
        out.written.append(save_html(fig, args.html))


def cmd_max_wrench(args: argparse.Namespace) -> int:
    from ..analysis.max_wrench import max_resistible_wrench

    scene = _load(args.scene)
    out = _Output(args)
    command, preload_name = _command(args, scene)
    direction, label = parse_direction(scene, args.direction)
    method = _method(args, scene)
    upper, steps = _upper_steps(args, scene)
    mw = max_resistible_wrench(
        scene.model, command, direction, method, upper, steps, settings=_settings(args, scene)
    )
    unit = wrench_unit(mw.direction)
    data = {
        "command": "max-wrench",
        **_scene_header(scene),
        "preload": command,
        "preload_name": preload_name,
        "steps": steps,
        **mw.to_dict(label),
    }
    if mw.status == "unbounded":
        verdict = (
            f"UNBOUNDED: resisted at the upper limit {upper:g} {unit} and without preload, i.e. "
            "passively resisted without bound under this model"
        )
    elif mw.status == "above_limit":
        verdict = (
            f">= {upper:g} {unit}: the upper limit is resisted, but the direction is not passively "
            "resisted without bound (raise --upper to find the limit)"
        )
    elif mw.status == "below_resolution":
        verdict = (
            f"< {mw.floor:.2g} {unit} (below the resolution and the scheme's tolerance: "
            "not distinguishable from zero)"
        )
    else:
        verdict = f"{format_max_wrench(mw)} {unit} (resolution {mw.resolution:.2g} {unit})"
    lines = [
        f"scene {scene.name!r}: {scene.description}",
        f"preload: {', '.join(f'{k}={v:g}' for k, v in command.items())}"
        + (f" ({preload_name})" if preload_name else ""),
        f"direction: {label} = {vector_text(mw.direction)}; method {method}, upper {upper:g}, {steps} steps",
        "",
        f"max resistible magnitude: {verdict}",
        f"{mw.search}: {len(mw.evidence)} magnitudes tried, monotone: {'yes' if mw.monotone else 'NO'}; "
        f"{mw.n_solves} solves, {mw.wall_time:.2f} s",
    ]
    if mw.response is not None:
        at = "at the upper limit" if mw.unbounded else "at the limit"
        lines += ["", f"contact forces {at}:", *_contact_table(scene.model, mw.response)]
    out.print(*lines)
    out.write_json("max_wrench.json", data)
    if mw.response is not None:
        out.figure("max_wrench.png", lambda p: _scene_png(scene, mw.response, p))
    _scene_html(args, out, scene, mw.response)
    out.finish(data)
    return 0


def _run_profile(
    args: argparse.Namespace, scene: Any, command: Any, plane: Any, n: int, upper: float, steps: int
) -> Any:
    from ..analysis.max_wrench import resistance_profile

    method = _method(args, scene)
    bar = ProgressBar(f"{scene.name} {method}", enabled=_progress_enabled(args))
    bar(0, n)
    try:
        return resistance_profile(
            scene.model,
            command,
            plane,
            n,
            method,
            upper,
            steps,
            settings=_settings(args, scene),
            progress=bar,
            **_profile_kwargs(args),
        )
    finally:
        bar.close()


def _normalization(
    args: argparse.Namespace, scene: Any, command: Any, profile: Any, method: str, upper: float, steps: int
) -> float | None:
    """The +b2 value to divide by (``None``: absolute). The scene's ``normalize`` is the default;
    it is dropped with a warning when the reference is unbounded or zero, an explicit
    ``--normalize`` then fails."""
    from ..analysis.max_wrench import max_resistible_wrench
    from ..core.axes import wrench_direction

    want = args.normalize if args.normalize is not None else scene.analysis.normalize
    if not want:
        return None
    ref = profile.basis[1] if want is True or args.normalize else want
    ref = wrench_direction(scene.model, ref, "normalize")
    hit = None
    for r, d in zip(profile.results, profile.directions):
        if np.allclose(d, ref, atol=1e-9):
            hit = r
            break
    if hit is None:
        hit = max_resistible_wrench(
            scene.model, command, ref, method, upper, steps, settings=_settings(args, scene)
        )
    if hit.unbounded or not hit.magnitude > 0:
        why = "unbounded" if hit.unbounded else "not resisted"
        if args.normalize:
            raise InvalidInputError(
                "--normalize", f"the reference direction {direction_text(hit.direction)} is {why}"
            )
        print(
            f"pinograsp: warning: not normalised: the reference direction "
            f"{direction_text(hit.direction)} is {why}",
            file=sys.stderr,
        )
        return None
    return float(hit.magnitude)


def _profile_report(
    args: argparse.Namespace,
    scene: Any,
    command: Any,
    preload_name: str | None,
    plane: Any,
    n: int,
    upper: float,
    steps: int,
    kind: str,
) -> int:
    from ..viz.figures import save_figure
    from ..viz.profile_plots import plot_profile

    if n < 1:
        raise InvalidInputError("-n", f"must be >= 1, got {n}")
    out = _Output(args)
    method = _method(args, scene)
    t0 = time.perf_counter()
    p = _run_profile(args, scene, command, plane, n, upper, steps)
    norm = _normalization(args, scene, command, p, method, upper, steps)
    wall = time.perf_counter() - t0
    unit = wrench_unit(p.basis[0] + p.basis[1])
    deg = np.degrees(p.angles)
    data = {
        "command": kind,
        **_scene_header(scene),
        "preload": command,
        "preload_name": preload_name,
        "method": method,
        "upper": upper,
        "steps": steps,
        "resolution": upper / 2**steps,
        "unit": unit,
        **p.to_dict(norm),
        "total_time": wall,
    }
    b1, b2 = (direction_text(b) for b in p.basis)
    header = f"{'angle [deg]':>11s}  {'direction':>22s}  {'max [' + unit + ']':>12s}"
    if norm is not None:
        header += f"  {'normalised':>10s}"
    lines = [
        f"scene {scene.name!r}: {scene.description}",
        f"preload: {', '.join(f'{k}={v:g}' for k, v in command.items())}"
        + (f" ({preload_name})" if preload_name else ""),
        f"profile in the plane ({b1}, {b2}): {n} directions, method {method}, upper {upper:g} {unit}, "
        f"{steps} steps (resolution {upper / 2**steps:.2g} {unit}); {wall:.1f} s",
        "",
        header,
    ]
    for i, a in enumerate(deg):
        c = np.cos(p.angles[i])
        s = np.sin(p.angles[i])
        dtxt = f"{c:+.3f} {b1.lstrip('+')} {s:+.3f} {b2.lstrip('+')}"
        mw = p.results[i]
        row = f"{a:11.1f}  {dtxt:>22s}  {format_max_wrench(mw):>12s}"
        if norm is not None:
            row += f"  {format_max_wrench(mw, norm):>10s}"
        lines.append(row)
    runs = data["unbounded_runs_deg"]
    lines.append("")
    if runs:
        lines.append("unbounded (passively resisted without bound): " + runs_text(runs))
    else:
        lines.append("no unbounded direction")
    if norm is not None:
        lines.append(f"normalised by the {b2} value {format_magnitude(norm, upper / 2**steps, unit)}")
    bad = [f"{deg[i]:g}°" for i, r in enumerate(p.results) if not r.monotone]
    if bad:
        lines.append("non-monotone bisection evidence at: " + ", ".join(bad))
    csv_path = getattr(args, "csv", None)
    if csv_path is not None:
        table = p if norm is None else replace(p, magnitudes=p.magnitudes / norm, normalized_by=norm)
        from ..core.tables import profile_to_csv

        out.written.append(profile_to_csv(table, csv_path, name="--csv"))
    out.print(*lines)
    out.write_json("profile.json", data)

    def draw(path: Path) -> None:
        title = f"{scene.name} ({method}" + (f", preload {preload_name})" if preload_name else ")")
        title += (
            f": max resistible {unit}"
            if norm is None
            else f"\nnormalised by the {b2} value {norm:.3g} {unit}"
        )
        ax = plot_profile(p, normalize=norm, title=title, labels=[method])
        save_figure(ax, path, close=True)

    out.figure("profile.png", draw)
    out.finish(data)
    return 0


def cmd_profile(args: argparse.Namespace) -> int:
    scene = _load(args.scene)
    command, preload_name = _command(args, scene)
    plane = parse_plane(scene, args.plane)
    n = args.n if args.n is not None else int(scene.analysis.n)
    upper, steps = _upper_steps(args, scene)
    return _profile_report(args, scene, command, preload_name, plane, n, upper, steps, "profile")


def cmd_demo(args: argparse.Namespace) -> int:
    scene = _load(args.scene)
    command = scene.preload()
    plane = parse_plane(scene, args.plane)
    upper, steps = _upper_steps(args, scene, default_steps=args.demo_steps)
    args.preload = None
    return _profile_report(args, scene, command, None, plane, args.n, upper, steps, "demo")


def cmd_compare_preloads(args: argparse.Namespace) -> int:
    from ..analysis.max_wrench import max_resistible_wrench
    from ..viz.comparison_plots import plot_preload_comparison
    from ..viz.figures import pyplot, save_figure

    scene = _load(args.scene)
    out = _Output(args)
    preloads = scene.analysis.preloads
    if args.preloads:
        names = [t.strip() for t in args.preloads.split(",") if t.strip()]
        for nm in names:
            scene.preload(nm)  # UnknownNameError if not a scene preload
    else:
        names = list(preloads)
    if len(names) < 2:
        raise InvalidInputError(
            "compare-preloads",
            f"scene {scene.name!r} has {len(names)} named preload(s) ({', '.join(names) or 'none'}); "
            "compare-preloads needs at least two (analysis.preloads in the scene file)",
        )
    dir_texts = args.direction or list(scene.analysis.directions)
    if not dir_texts:
        raise InvalidInputError(
            "compare-preloads",
            f"scene {scene.name!r} has no named directions (analysis.directions); give --direction",
        )
    method = _method(args, scene)
    upper, steps = _upper_steps(args, scene)
    settings = _settings(args, scene)
    t0 = time.perf_counter()
    results: dict[str, dict[str, Any]] = {}
    rows = []
    for text in dir_texts:
        direction, label = parse_direction(scene, text)
        per = {}
        for nm in names:
            per[nm] = max_resistible_wrench(
                scene.model, scene.preload(nm), direction, method, upper, steps, settings=settings
            )
        results[label] = per
        a, b = per[names[0]], per[names[1]]
        if a.status != "finite" or b.status != "finite":
            ratio = None  # a ratio of bounds (unbounded, >= upper, < resolution) is undefined
        else:
            ratio = a.magnitude / b.magnitude
        rows.append((label, per, ratio))
    wall = time.perf_counter() - t0
    data = {
        "command": "compare-preloads",
        **_scene_header(scene),
        "method": method,
        "upper": upper,
        "steps": steps,
        "preloads": {nm: scene.preload(nm) for nm in names},
        "ratio_of": [names[0], names[1]],
        "directions": [
            {
                "label": label,
                "direction": next(iter(per.values())).direction,
                "results": {nm: mw.to_dict(response=False) for nm, mw in per.items()},
                "ratio": ratio,
            }
            for label, per, ratio in rows
        ],
        "total_time": wall,
    }
    w = max([len("direction"), *(len(r[0]) for r in rows)])
    head = f"  {'direction':{w}s}  " + "  ".join(f"{nm:>14s}" for nm in names) + f"  {'ratio':>8s}"
    lines = [
        f"scene {scene.name!r}: {scene.description}",
        *(f"preload {nm}: " + ", ".join(f"{k}={v:g}" for k, v in scene.preload(nm).items()) for nm in names),
        f"method {method}, upper {upper:g}, {steps} steps; {wall:.1f} s",
        "",
        "max resistible magnitude [N or N·m] per preload, ratio = " + f"{names[0]} / {names[1]}:",
        head,
    ]
    for label, per, ratio in rows:
        cells = "  ".join(f"{format_max_wrench(per[nm]):>14s}" for nm in names)
        rtxt = "-" if ratio is None else f"{ratio:.3f}"
        lines.append(f"  {label:{w}s}  {cells}  {rtxt:>8s}")
    out.print(*lines)
    out.write_json("compare_preloads.json", data)

    def draw(path: Path) -> None:
        plt = pyplot()
        k = len(rows)
        cols = min(k, 3)
        nrows = math.ceil(k / cols)
        fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 3.6 * nrows), squeeze=False)
        for ax, (label, per, _) in zip(axes.flat, rows):
            plot_preload_comparison(per, ax=ax, title=None)
            ax.set_title(f"{label}\n{ax.get_title()}", fontsize=9)
        for ax in list(axes.flat)[k:]:
            ax.set_visible(False)
        fig.suptitle(f"{scene.name}: max resistible wrench per preload ({method})")
        fig.tight_layout()
        save_figure(fig, path, close=True)

    out.figure("compare_preloads.png", draw)
    out.finish(data)
    return 0


# ---------------------------------------------------------------------------- entry point
def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:  # noqa: ANN001
    text = " ".join(str(message).split())
    print(f"pinograsp: warning: {text} ({category.__name__})", file=sys.stderr)


@contextlib.contextmanager
def _stdout_to_stderr(enabled: bool) -> Iterator[None]:
    """Send everything written to file descriptor 1 (e.g. SCIP's C-level messages) to stderr,
    so that ``--json`` leaves nothing but the JSON document on stdout."""
    if not enabled:
        yield
        return
    try:
        sys.stdout.flush()
        saved = os.dup(1)
        os.dup2(2, 1)
    except (OSError, ValueError, AttributeError):  # no real fd 1: nothing to protect
        yield
        return
    try:
        yield
    finally:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; returns the exit code (0 ok, 2 bad input or usage, 1 unexpected failure)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    debug = "--debug" in argv
    try:
        args = parser.parse_args(_join_dash_values(argv))
    except _UsageError as exc:
        print(f"pinograsp: error: {exc} (see 'pinograsp --help')", file=sys.stderr)
        return 2
    except SystemExit as exc:  # --help, --version
        return int(exc.code or 0) if not isinstance(exc.code, str) else 2
    debug = bool(getattr(args, "debug", False)) or debug
    with warnings.catch_warnings():
        if not debug:
            warnings.showwarning = _show_warning  # type: ignore[assignment]
        try:
            with _stdout_to_stderr(bool(getattr(args, "json", False))):
                code = int(args.func(args))
            text = getattr(args, "json_text", None)
            if text is not None:
                sys.stdout.write(text)
                sys.stdout.flush()
            return code
        except PinograspError as exc:
            if debug:
                raise
            msg = " ".join(str(exc).split())
            print(f"pinograsp: error: {msg}", file=sys.stderr)
            return 2
        except KeyboardInterrupt:
            if debug:
                raise
            print("\npinograsp: interrupted", file=sys.stderr)
            return 130
        except BrokenPipeError:  # pragma: no cover - e.g. `pinograsp ... | head`
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            return 1
        except Exception as exc:
            if debug:
                raise
            msg = " ".join(f"{type(exc).__name__}: {exc}".split())
            print(
                f"pinograsp: error: unexpected failure: {msg} (run with --debug for the traceback)",
                file=sys.stderr,
            )
            return 1


def cmd_preload(args: argparse.Namespace) -> int:
    from ..analysis.preload import equilibrium_preload

    scene = _load(args.scene)
    out = _Output(args)
    method = _method(args, scene)
    choice = equilibrium_preload(
        scene.model,
        method,
        objective=args.objective,
        max_command=args.max_command,
        grip=args.grip,
        settings=_settings(args, scene),
    )
    result = choice.to_dict()
    data = {"command": "preload", **_scene_header(scene), "preload": result.pop("command"), **result}
    lines = [
        f"scene {scene.name!r}: {scene.description}",
        f"method: {method}, objective: {args.objective}",
        "",
    ]
    lines.append(f"status: {choice.status}: {choice.reason}")
    if choice.command is not None:
        lines += ["", "commands [N·m or N]:"]
        lines += [f"  {k:<24s} {v:12.6g}" for k, v in choice.command.items()]
        lines += ["", "normal forces of the design [N]:"]
        lines += [f"  {n:<24s} {f:12.6g}" for n, f in zip(scene.model.contact_names, choice.normal_forces)]
    out.print(*lines)
    out.write_json("preload.json", data)
    out.finish(data)
    return 0


def _add_optimal_preload(sub: Any) -> None:
    op = sub.add_parser(
        "optimal-preload",
        help="the smallest preload resisting given wrenches, or the best split of a budget",
        description="Smallest actuator commands under which every given wrench is resisted, or "
        "with --budget the split of a preload budget that resists the most along them "
        "(pg.optimal_preload; docs/optimal_preload.md).",
    )
    op.add_argument("scene", metavar="SCENE")
    op.add_argument(
        "-w",
        "--wrench",
        action="append",
        required=True,
        help="a disturbance (repeatable): axis=value pairs (fx=2,mz=0.1), numbers, or a scene wrench",
    )
    op.add_argument("--objective", choices=("max", "sum"), default="max", help="largest or summed command")
    op.add_argument("--budget", type=float, help="split this budget of the objective instead [N·m or N]")
    op.add_argument("--resistance", choices=("min", "sum"), default="min", help="split: what to maximise")
    op.add_argument("--max-command", type=float, default=1.0, help="bound of every command [N·m or N]")
    op.add_argument("--actuators", help="comma-separated actuators to command (default: all driving)")
    op.add_argument("--grid", type=int, help="search: simplex divisions (default by actuator count)")
    op.add_argument("--refine", type=int, default=3, help="search: pattern-search halvings (default 3)")
    _common(op)
    op.set_defaults(func=cmd_optimal_preload)


def cmd_optimal_preload(args: argparse.Namespace) -> int:
    from ..analysis.optimal import optimal_preload

    scene = _load(args.scene)
    out = _Output(args)
    method = _method(args, scene)
    upper = args.upper if args.upper is not None else 1e3
    _, steps = _upper_steps(args, scene)
    wrenches = [parse_wrench(scene, w) for w in args.wrench]
    acts = [a.strip() for a in args.actuators.split(",")] if args.actuators else None
    result = optimal_preload(
        scene.model,
        wrenches,
        method,
        objective=args.objective,
        budget=args.budget,
        resistance=args.resistance,
        max_command=args.max_command,
        actuators=acts,
        grid=args.grid,
        refine=args.refine,
        upper=upper,
        steps=steps,
        settings=_settings(args, scene),
    )
    fields = result.to_dict()
    data = {"command": "optimal-preload", **_scene_header(scene), "preload": fields.pop("command"), **fields}
    out.print(f"scene {scene.name!r}: {scene.description}", "", result.summary())
    out.write_json("optimal_preload.json", data)
    out.finish(data)
    return 0


def cmd_resistance_set(args: argparse.Namespace) -> int:
    from ..analysis.metrics import ferrari_canny
    from ..analysis.resistance_set import resistance_set

    scene = _load(args.scene)
    if args.n < 1:
        raise InvalidInputError("-n", f"must be >= 1, got {args.n}")
    out = _Output(args)
    command, preload_name = _command(args, scene)
    method = _method(args, scene)
    upper, steps = _upper_steps(args, scene)
    workers = getattr(args, "workers", None)
    if workers is not None and workers < 0:
        raise InvalidInputError("--workers", f"must be >= 0 (0: one per CPU), got {workers}")
    bar = ProgressBar(f"{scene.name} {method}", enabled=_progress_enabled(args))
    try:
        rset = resistance_set(
            scene.model, command, args.n, method, args.length, args.seed, workers, upper, steps,
            _settings(args, scene), progress=bar,
        )  # fmt: skip
    finally:
        bar.close()
    eps = ferrari_canny(scene.model, rset.length)
    data = {
        "command": "resistance-set",
        **_scene_header(scene),
        "preload": command,
        "preload_name": preload_name,
        "ferrari_canny": eps,
        **rset.to_dict(),
    }
    out.print(
        f"scene {scene.name!r}: {scene.description}",
        f"preload: {', '.join(f'{k}={v:g}' for k, v in command.items())}"
        + (f" ({preload_name})" if preload_name else ""),
        "",
        rset.summary(),
        f"Ferrari-Canny epsilon of the same contacts: {eps:.4g}",
    )
    if args.csv is not None:
        out.written.append(rset.to_csv(args.csv, name="--csv"))
    out.write_json("resistance_set.json", data)

    def draw(path: Path) -> None:
        from ..viz.figures import save_figure
        from ..viz.set_plots import plot_resistance_set

        fig = plot_resistance_set(rset, title=f"{scene.name}: resistance set ({method})")
        save_figure(fig, path, close=True)

    out.figure("resistance_set.png", draw)
    out.finish(data)
    return 0


def cmd_batch(args: argparse.Namespace) -> int:
    from ..batch.evaluate import WorstAxisScore, evaluate_grasps, output_format, save_results
    from ..batch.files import load_grasps

    if args.out:
        try:
            output_format(args.out)
        except InvalidInputError as exc:
            raise InvalidInputError("--out", str(exc).split(": ", 1)[-1]) from None
    batch = load_grasps(args.grasps)
    options = dict(batch.score)
    for key in ("upper", "steps", "method"):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    score = WorstAxisScore(**options)
    bar = ProgressBar(f"batch {args.executor}", enabled=_progress_enabled(args))
    t0 = time.perf_counter()
    try:
        table = evaluate_grasps(
            list(batch.grasps), score=score, executor=args.executor, workers=args.workers,
            address=args.address, progress=bar,
        )  # fmt: skip
    finally:
        bar.close()
    wall = time.perf_counter() - t0
    ok = table[table["status"] == "ok"]
    lines = [f"{len(table)} grasps from {args.grasps}: {len(ok)} ok, {len(table) - len(ok)} errors "
             f"({wall:.1f} s, {len(table) / wall:.2f} grasps/s, executor {args.executor})"]  # fmt: skip
    for kind, n in table.loc[table["status"] == "error", "error_type"].value_counts().items():
        lines.append(f"  error {kind}: {n}")
    if len(ok) and "score" in ok:
        q = ok["score"].quantile([0.0, 0.5, 1.0]).tolist()
        lines.append(f"score [N] (worst axis, {score.method}, upper {score.upper:g}, steps {score.steps}): "
                     f"min {q[0]:.4g}, median {q[1]:.4g}, max {q[2]:.4g}")  # fmt: skip
    if args.out:
        lines.append(f"wrote {save_results(table, args.out)}")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
