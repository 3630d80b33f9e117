"""The ``pinograsp`` argument parser: one small function per sub-command adds its options
(docs/cli.md lists them).

The parser imports nothing heavy: ``pinograsp --help`` loads neither the solvers nor cvxpy.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence

from ..core.methods import bounded, method_names, methods_help
from ..core.settings import DEFAULT_METHOD, Variant
from .arguments import PRELOAD_HELP, add_direction
from .path_command import add_path
from .plan_command import add_plan

#: Defaults of ``pinograsp demo``: small enough to finish in well under a minute on 2 cores.
DEMO_SCENE = "case1"
DEMO_N = 24
DEMO_STEPS = 10

#: Options whose value may start with ``-`` (``--direction -fy``, ``--wrench -5,0,0``).
_DASH_VALUE_OPTIONS = ("--direction", "-d", "--wrench", "-w", "--plane", "-p")
_PROGRESS_HELP = "progress bar with ETA on stderr (default: when stderr is a terminal)"


class UsageError(Exception):
    """A command-line usage error (argparse's ``error``), reported on one line."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(message)


def join_dash_values(argv: Sequence[str]) -> list[str]:
    """``--direction -fy`` -> ``--direction=-fy`` (argparse would take ``-fy`` for an option)."""
    out: list[str] = []
    skip = False
    for i, tok in enumerate(argv):
        if skip:
            skip = False
            continue
        nxt = argv[i + 1] if i + 1 < len(argv) else None
        if tok in _DASH_VALUE_OPTIONS and nxt is not None and nxt.startswith("-") and len(nxt) > 1:
            out.append(f"{tok}={nxt}")
            skip = True
        else:
            out.append(tok)
    return out


def _debug_option(p: argparse._ActionsContainer) -> None:
    p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help="show full tracebacks")


def _common(p: argparse.ArgumentParser, *, out_default: str | None = None) -> None:
    """The options of every analysis: method, variant, limits, solver, ``--json``, ``--out``."""
    g = p.add_argument_group("common options")
    g.add_argument(
        "--method",
        choices=method_names(),
        help=f"{methods_help()}; default: the scene's analysis.method, else {DEFAULT_METHOD} (the "
        "package default; every built-in scene)",
    )
    g.add_argument(
        "--variant",
        choices=[v.value for v in Variant],
        help="load path: preload and load together, preload first (object held still), or the "
        "object settled into the preload first; default: the scene's (docs/design.md)",
    )
    exact = "/".join(n for n in method_names() if not bounded(n))  # their limits are exact
    g.add_argument(
        "--upper", type=float, help=f"search upper limit [N or N·m] ({exact}: none); default: the scene's"
    )
    g.add_argument(
        "--steps",
        type=int,
        help=f"bisection steps (resolution upper/2**steps; {exact}: none); default: the scene's",
    )
    g.add_argument("--solver", help="MIQP backend (default: the scene's, normally scip)")
    g.add_argument("--time-limit", type=float, help="per-MIQP time limit [s]")
    g.add_argument(
        "--normal-uncertainty",
        type=float,
        metavar="DEG",
        help="worst-case uncertainty of every contact normal [deg]: friction mu -> "
        "tan(atan(mu) - u) in every method (default: the scene's, normally 0)",
    )
    g.add_argument(
        "--cone-tolerance",
        type=float,
        metavar="DEG",
        help="prp/energetic: refine each loaded contact's friction pyramid until the sector holding "
        "its force or slip is at most this wide [deg] (default: the scene's, normally none)",
    )
    g.add_argument(
        "--tangential-ratio",
        type=float,
        metavar="R",
        help="quasistatic: tangential / normal contact stiffness (default: the scene's, normally 1)",
    )
    g.add_argument(
        "--contact-stiffness",
        type=float,
        metavar="N_PER_M",
        help="quasistatic: normal stiffness of the stiffest contact [N/m] (default: the scene's, "
        "normally 1e6, the simulation's)",
    )
    g.add_argument(
        "--limit",
        choices=("giveway", "first"),
        help="quasistatic: report the load at which the grasp gives way (default) or the path's "
        "first limit load",
    )
    g.add_argument("--json", action="store_true", help="print the result as JSON on stdout (nothing else)")
    g.add_argument(
        "--out",
        default=out_default,
        help="write plots and JSON files to this folder"
        + (f" (default {out_default})" if out_default else " (default: write nothing)"),
    )
    _debug_option(g)


def _progress_options(p: argparse.ArgumentParser, workers_default: int | None = None) -> None:
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None, help=_PROGRESS_HELP)
    p.add_argument(
        "--workers",
        type=int,
        default=workers_default,
        help="processes for the profile's directions (0: one per CPU; 1: in this process; default "
        + ("0" if workers_default == 0 else "1")
        + ")",
    )


def _add_demo(sub: argparse._SubParsersAction) -> None:
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
    p.set_defaults(demo_steps=DEMO_STEPS)


def _add_scenes(sub: argparse._SubParsersAction) -> None:
    s = sub.add_parser("scenes", help="list the built-in scenes (or describe one)")
    s.add_argument("scene", nargs="?", help="show this scene's model, preload and analysis settings")
    s.add_argument("--json", action="store_true", help="print as JSON")
    _debug_option(s)


def _add_analyze(sub: argparse._SubParsersAction) -> None:
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
    a.add_argument("--preload", help=PRELOAD_HELP)
    a.add_argument("--html", metavar="FILE", help="write the interactive 3D view (plotly) to FILE")
    _common(a)


def _add_max_wrench(sub: argparse._SubParsersAction) -> None:
    m = sub.add_parser(
        "max-wrench",
        help="largest resistible wrench along one direction (bisection)",
        description="Largest wrench magnitude along a direction that the preloaded grasp resists passively.",
    )
    m.add_argument("scene", metavar="SCENE")
    add_direction(m)
    m.add_argument("--preload", help=PRELOAD_HELP)
    m.add_argument(
        "--html", metavar="FILE", help="write the interactive 3D view at the limit (plotly) to FILE"
    )
    _common(m)


def _add_profile(sub: argparse._SubParsersAction) -> None:
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
    pr.add_argument("--preload", help=PRELOAD_HELP)
    pr.add_argument(
        "--csv",
        metavar="FILE",
        help="also write the profile as CSV: one row per direction (angle, direction, magnitude, status ...)",
    )
    _common(pr)
    _progress_options(pr)


def _add_compare_preloads(sub: argparse._SubParsersAction) -> None:
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


def _add_resistance_set(sub: argparse._SubParsersAction) -> None:
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
    rs.add_argument("--preload", help=PRELOAD_HELP)
    rs.add_argument("--csv", metavar="FILE", help="also write one CSV row per direction")
    _common(rs)
    _progress_options(rs)


def _add_preload(sub: argparse._SubParsersAction) -> None:
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


def _add_optimal_preload(sub: argparse._SubParsersAction) -> None:
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


def _add_batch(sub: argparse._SubParsersAction) -> None:
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
    b.add_argument(
        "--out",
        help="results table: .parquet or .csv, checked before any work; rows are journaled to "
        "OUT.partial.jsonl as they finish and the table is written atomically at the end",
    )
    b.add_argument(
        "--resume",
        action="store_true",
        help="keep the finished rows of OUT.partial.jsonl (an interrupted run) and evaluate the others",
    )
    b.add_argument(
        "--timeout",
        type=float,
        metavar="SECONDS",
        help="opt-in per-grasp wall-clock limit: a grasp still running is a 'timeout' row (machine-"
        "dependent: leave unset for reproducible tables)",
    )
    b.add_argument("--upper", type=float, help="score search limit [N] (default: the file's score block)")
    b.add_argument("--steps", type=int, help="score search steps (default: the file's score block)")
    b.add_argument(
        "--method",
        choices=method_names(),
        help=f"score method: {', '.join(method_names())} (default: the file's score block, else "
        f"{DEFAULT_METHOD})",
    )
    b.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None, help=_PROGRESS_HELP)
    _debug_option(b)


def _add_simulate(sub: argparse._SubParsersAction) -> None:
    sm = sub.add_parser(
        "simulate",
        help="MuJoCo cross-check: ramp a load along a direction until the object gives way",
        description="Simulate the preloaded grasp in MuJoCo (pinograsp[mujoco]), ramp a load along a "
        "direction and report the load at which the object gives way, or that it held up to --upper "
        "(pg.simulate_max_wrench; docs/simulation.md). --compare also runs the scene's analysis.",
    )
    sm.add_argument("scene", metavar="SCENE")
    add_direction(sm)
    sm.add_argument("--preload", help=PRELOAD_HELP)
    sm.add_argument("--upper", type=float, help="largest load [N or N·m]; default: the scene's")
    sm.add_argument(
        "--compare", action="store_true", help="also predict (the scene's analysis) and print the difference"
    )
    sm.add_argument(
        "--method",
        choices=method_names(),
        help=f"method of --compare ({', '.join(method_names())}); default: the scene's "
        f"({DEFAULT_METHOD} unless it names one)",
    )
    g = sm.add_argument_group("simulation options (defaults: docs/simulation.md)")
    g.add_argument("--stiffness", type=float, help="stiffest contact's stiffness [N/m] (default 1e6)")
    g.add_argument("--timestep", type=float, help="integration step [s] (default 1e-4)")
    g.add_argument("--ramp-time", type=float, help="e-folding time of the load ramp [s] (default 0.02)")
    g.add_argument(
        "--release-time",
        type=float,
        help="time over which the held object is released [s] (default 0: at once; 0.05: as the model)",
    )
    g.add_argument(
        "--finger-mass",
        type=float,
        help="each finger's effective mass at its contacts, x the object's (default 1; range 0.1-100)",
    )
    g.add_argument("--slip", type=float, help="translation that counts as giving way [m]")
    g.add_argument("--rotation", type=float, help="rotation that counts as giving way [rad]")
    g.add_argument("--tolerance", type=float, help="relative resolution of the load (default 2e-3)")
    g.add_argument(
        "--settled",
        action="store_true",
        help="let the object move while the fingers close (default: held still, as preload-first)",
    )
    g.add_argument(
        "--friction", choices=("cone", "pyramid"), help="Coulomb cone (default) or the model's pyramid"
    )
    sm.add_argument("--json", action="store_true", help="print the result as JSON on stdout (nothing else)")
    _debug_option(sm)


#: The sub-commands in the order of ``pinograsp --help``; ``args.cmd`` holds the chosen one.
_SUBCOMMANDS = (
    _add_demo,
    _add_scenes,
    _add_analyze,
    _add_max_wrench,
    _add_profile,
    _add_compare_preloads,
    _add_resistance_set,
    _add_preload,
    _add_optimal_preload,
    _add_batch,
    _add_simulate,
    add_path,
    add_plan,
)


def build_parser() -> argparse.ArgumentParser:
    """The ``pinograsp`` parser; its ``error`` raises :class:`UsageError` instead of exiting."""
    parser = _Parser(
        prog="pinograsp",
        description="Passive reaction analysis for robot grasps: which disturbances a preloaded "
        "grasp resists without changing its motor commands.",
        epilog="SCENE is a built-in scene name (see 'pinograsp scenes') or a scene YAML file. "
        "Docs: docs/cli.md.",
    )
    parser.add_argument("--debug", action="store_true", help="show full tracebacks")
    sub = parser.add_subparsers(dest="cmd", required=True, metavar="COMMAND")
    for add in _SUBCOMMANDS:
        add(sub)
    return parser
