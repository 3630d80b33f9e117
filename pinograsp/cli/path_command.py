"""``pinograsp path SCENE -d D``: the quasi-static loading path of a scene along a direction
(docs/cli.md, docs/methods.md "Quasi-static loading path")."""

from __future__ import annotations

import argparse

from ..core.axes import wrench_unit
from ..core.methods import method_spec
from ..core.serialize import vector_text
from ..core.settings import Method
from ..errors import InvalidInputError
from . import options as opt
from .arguments import PRELOAD_HELP, add_direction
from .report import Output, preload_line, scene_header, scene_line


def add_path(sub: argparse._SubParsersAction) -> None:
    """The ``path`` sub-command's options."""
    p = sub.add_parser(
        "path",
        help="quasi-static loading path along a direction: limit load, events, load-displacement curve",
        description="Follow the equilibrium of the preloaded grasp exactly while the load along a "
        "direction grows (the quasi-static loading path: tangential contact springs, Coulomb slip on "
        "the model's friction polygon, ratchets); prints the limit load and the events, and writes "
        "the load-displacement plot and the breakpoints on request.",
    )
    p.add_argument("scene", metavar="SCENE")
    add_direction(p)
    p.add_argument("--preload", help=PRELOAD_HELP)
    p.add_argument(
        "--variant",
        type=lambda v: {"held": "preload-first", "settled": "settled-preload"}.get(v, v),
        choices=[v.value for v in method_spec(Method.QUASISTATIC).variants],
        help="preload, as --variant of the other commands: the object held while the hand closes "
        "(preload-first, the default) or settled into the preload (settled-preload); held and "
        "settled are accepted for them",
    )
    p.add_argument(
        "--tangential-ratio",
        type=float,
        help="tangential / normal contact stiffness (default 1, the simulation's)",
    )
    p.add_argument("--max-segments", type=int, default=5000, help="segment-count limit (default 5000)")
    p.add_argument("--png", metavar="FILE", help="write the load-displacement plot to FILE")
    p.add_argument("--csv", metavar="FILE", help="write the breakpoints to FILE (one row each)")
    p.add_argument("--json", action="store_true", help="print the path as JSON on stdout (nothing else)")
    p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help="show full tracebacks")


def cmd_path(args: argparse.Namespace) -> int:
    """Run ``pinograsp path``."""
    import pinograsp as pg

    png, csv = Output.target(args.png, "--png"), Output.target(args.csv, "--csv")  # before the work
    scene = opt.load_scene(args.scene)
    out = Output(args)
    command, preload_name = opt.preload(args, scene)
    direction, label = opt.parse_direction(scene, args.direction)
    over = {}
    if args.tangential_ratio is not None:
        over["tangential_ratio"] = args.tangential_ratio
    base = {k: getattr(scene.settings, k) for k in ("normal_uncertainty", "tangential_ratio")}
    try:  # the scene's, --tangential-ratio first
        settings = pg.Settings(**{**base, **over}).validated()
    except InvalidInputError as exc:
        if exc.name != "tangential_ratio" or not over:
            raise
        raise InvalidInputError("--tangential-ratio", str(exc).removeprefix("tangential_ratio: ")) from None
    lp = pg.loading_path(
        scene.model,
        command,
        direction,
        variant=args.variant,
        settings=settings,
        max_segments=args.max_segments,
    )
    unit = wrench_unit(lp.direction)
    limit = "unbounded (no event ahead)" if lp.unbounded else f"{lp.limit:.6g} {unit}"
    lines = [
        scene_line(scene),
        preload_line(command, preload_name),
        f"direction: {label} = {vector_text(lp.direction)}; preload {lp.variant}, tangential ratio "
        f"{lp.tangential_ratio:g}",
        "",
        f"status: {lp.status} ({lp.stop_reason})",
        f"limit load: {limit}",
        f"{lp.segments} segments, {len(lp.events)} events, {lp.lcp_solves} LCPs (largest {lp.largest_lcp}), "
        f"{lp.wall_time * 1e3:.3g} ms",
        "events:",
        *("  " + e.text() for e in lp.events),
    ]
    if png is not None:
        ax = pg.plot_loading_path(lp)
        pg.save_figure(ax, png, close=True)
        out.written.append(png)
    if csv is not None:
        lp.to_csv(csv)
        out.written.append(csv)
    out.print(*lines)
    out.finish({**scene_header(scene), "preload_name": preload_name, "label": label, **lp.to_dict()})
    return 0
