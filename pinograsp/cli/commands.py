"""Commands about one scene or one query: ``scenes``, ``analyze``, ``max-wrench``, ``preload``,
``optimal-preload``, and ``batch`` (many grasps, one summary). Each ``cmd_*`` takes the parsed
arguments and returns the exit code (docs/cli.md)."""

from __future__ import annotations

import argparse
import json
import signal
import sys
import time
from typing import Any

import numpy as np

import pinograsp as pg

from ..core.methods import bounded, search_text
from ..core.results import format_max_wrench
from ..core.serialize import jsonable, vector_text, wrench_unit
from ..errors import InvalidInputError, plural
from . import options as opt
from .report import (
    Output,
    actuator_table,
    audit_line,
    contact_table,
    model_settings,
    preload_line,
    progress_bar,
    scene_figures,
    scene_header,
    scene_line,
)


def _scene_data(scene: Any) -> dict[str, Any]:
    """``pinograsp scenes NAME --json``: the model, the preload and the analysis block."""
    an = scene.analysis
    return {
        **scene_header(scene),
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
            **model_settings(scene.settings)[0],
        },
    }


def cmd_scenes(args: argparse.Namespace) -> int:
    """``pinograsp scenes [SCENE]``: the built-in scenes, or one scene's settings."""
    if args.scene is None:
        scenes = pg.builtin_scenes()
        if args.json:  # printed by main() once stdout is restored (docs/cli.md)
            args.json_text = json.dumps(scenes, indent=2) + "\n"
            return 0
        width = max((len(k) for k in scenes), default=4)
        for name, desc in scenes.items():
            print(f"{name:{width}s}  {desc}")
        return 0
    scene = opt.load_scene(args.scene)
    if args.json:
        args.json_text = json.dumps(jsonable(_scene_data(scene)), indent=2) + "\n"
        return 0
    an = scene.analysis
    print(scene.summary())
    note = model_settings(scene.settings)[1]
    print(
        f"  analysis: method {an.method}{note}, {search_text(an.method, an.upper, an.steps)}, "
        f"n = {an.n}, plane {','.join(map(str, an.plane))}"
    )
    for key in ("directions", "wrenches"):
        if getattr(an, key):
            print(f"  {key}: " + ", ".join(f"{k} {vector_text(v)}" for k, v in getattr(an, key).items()))
    for k, v in an.preloads.items():
        print(f"  preload {k}: " + ", ".join(f"{a}={x:g}" for a, x in v.items()))
    return 0


def cmd_analyze(args: argparse.Namespace) -> int:
    """``pinograsp analyze SCENE --wrench W``: the passive response to one wrench."""
    scene = opt.load_scene(args.scene)
    out = Output(args)
    command, preload_name = opt.preload(args, scene)
    w = opt.parse_wrench(scene, args.wrench)
    method = opt.method(args, scene)
    settings = opt.settings(args, scene)
    r = pg.passive_response(scene.model, command, w, method, settings=settings)
    model_data, note = model_settings(settings)
    data = {
        "command": "analyze",
        **scene_header(scene),
        "preload": command,
        "preload_name": preload_name,
        **model_data,
        **r.to_dict(scene.model),
    }
    out.print(
        scene_line(scene),
        preload_line(command, preload_name),
        f"wrench: {vector_text(r.wrench)} [N, N·m] (fx, fy, fz, mx, my, mz)",
        f"method: {r.method} ({r.variant}{note})",
        "",
        f"status: {r.status} -> {'RESISTED' if r.resistible else 'NOT RESISTED'} "
        f"({r.iterations} iteration(s), {r.n_solves} solve(s), "
        f"{r.solve_time:.2f} s, {r.solver})",
        "",
        "contact forces on the object (contact frame: normal, tangents):",
        *contact_table(scene.model, r),
        "",
        *actuator_table(scene.model, r),
        "",
        f"net wrench |w + G c|: {np.linalg.norm(r.net_wrench):.3e}",
        audit_line(r),
    )
    out.write_json("analyze.json", data)
    scene_figures(args, out, scene, r if r.resistible else None, "analyze.png")
    out.finish(data)
    return 0


def _verdict(mw: Any, upper: float) -> str:
    """The max resistible magnitude in words, by the search's status."""
    unit = wrench_unit(mw.direction)
    if mw.search == "path":  # the loading path's give-way (or first limit): exact, no resolution
        gw = mw.giveway
        if mw.status == "unbounded":
            return (
                "UNBOUNDED: the loading path has no limit and stays within the give-way thresholds "
                f"up to {upper:g} {unit} (decided exactly), i.e. passively resisted without bound"
                " under this model"
            )
        if mw.status == "below_resolution":
            return f"0 {unit}: the loading path ends at zero load (the grasp gives way at once)"
        if gw is None:
            return f"{format_max_wrench(mw)} {unit} (the loading path's first limit, exact)"
        if mw.status == "above_limit":
            return f">= {upper:g} {unit}: held up to the upper limit before the path stopped"
        return f"{format_max_wrench(mw)} {unit} (the load at which it gives way: {gw.reason}, exact)"
    if mw.status == "unbounded":
        return (
            f"UNBOUNDED: resisted at the upper limit {upper:g} {unit} and without preload, i.e. "
            "passively resisted without bound under this model"
        )
    if mw.status == "above_limit":
        return (
            f">= {upper:g} {unit}: the upper limit is resisted, but the direction is not passively "
            "resisted without bound (raise --upper to find the limit)"
        )
    if mw.status == "below_resolution":
        return (
            f"< {mw.floor:.2g} {unit} (below the resolution and the scheme's tolerance: "
            "not distinguishable from zero)"
        )
    if not bounded(mw.method):  # its row: an exact limit, upper and steps do not shape it
        return f"{format_max_wrench(mw)} {unit} (exact)"
    return f"{format_max_wrench(mw)} {unit} (resolution {mw.resolution:.2g} {unit})"


def cmd_max_wrench(args: argparse.Namespace) -> int:
    """``pinograsp max-wrench SCENE --direction D``: the largest resistible magnitude along D."""
    scene = opt.load_scene(args.scene)
    out = Output(args)
    command, preload_name = opt.preload(args, scene)
    direction, label = opt.parse_direction(scene, args.direction)
    method = opt.method(args, scene)
    upper, steps = opt.upper_steps(args, scene)
    settings = opt.settings(args, scene)
    mw = pg.max_resistible_wrench(scene.model, command, direction, method, upper, steps, settings=settings)
    model_data, note = model_settings(settings)
    data = {
        "command": "max-wrench",
        **scene_header(scene),
        "preload": command,
        "preload_name": preload_name,
        "steps": steps,
        **model_data,
        **mw.to_dict(label),
        "search": mw.search,
    }
    lines = [
        scene_line(scene),
        preload_line(command, preload_name),
        f"direction: {label} = {vector_text(mw.direction)}; method {method}{note}, "
        f"{search_text(method, upper, steps)}",
        "",
        f"max resistible magnitude: {_verdict(mw, upper)}",
        (
            f"loading path: {mw.n_solves} LCP solves, {mw.wall_time:.2f} s"
            if mw.search == "path"
            else f"{mw.search}: {plural('magnitude', len(mw.evidence))} tried, monotone: "
            f"{'yes' if mw.monotone else 'NO'}; {mw.n_solves} solves, {mw.wall_time:.2f} s"
        ),
    ]
    if mw.giveway is not None:
        lines.append(mw.giveway.text(wrench_unit(mw.direction)))
    if mw.response is not None:
        at = "at the limit"
        if mw.unbounded:
            at = "at the path's last breakpoint" if mw.search == "path" else "at the upper limit"
        lines += ["", f"contact forces {at}:", *contact_table(scene.model, mw.response)]
    out.print(*lines)
    out.write_json("max_wrench.json", data)
    png = "max_wrench.png" if mw.response is not None else None
    scene_figures(args, out, scene, mw.response, png)
    out.finish(data)
    return 0


def cmd_preload(args: argparse.Namespace) -> int:
    """``pinograsp preload SCENE``: commands under which the preload alone is in equilibrium."""
    scene = opt.load_scene(args.scene)
    out = Output(args)
    method = opt.method(args, scene)
    choice = pg.equilibrium_preload(
        scene.model,
        method,
        objective=args.objective,
        max_command=args.max_command,
        grip=args.grip,
        settings=opt.settings(args, scene),
    )
    result = choice.to_dict()
    data = {"command": "preload", **scene_header(scene), "preload": result.pop("command"), **result}
    lines = [scene_line(scene), f"method: {method}, objective: {args.objective}", ""]
    lines.append(f"status: {choice.status}: {choice.reason}")
    if choice.command is not None:
        lines += ["", "commands [N·m or N]:"]
        lines += [f"  {k:<24s} {v:12.6g}" for k, v in choice.command.items()]
        lines += ["", "normal forces of the design [N]:"]
        forces = () if choice.normal_forces is None else choice.normal_forces
        lines += [f"  {n:<24s} {f:12.6g}" for n, f in zip(scene.model.contact_names, forces)]
    if choice.released_states:
        lines += ["", "released state at zero load (the preload stage's end):"]
        lines += [f"  {n:<24s} {s}" for n, s in zip(scene.model.contact_names, choice.released_states)]
    out.print(*lines)
    out.write_json("preload.json", data)
    out.finish(data)
    return 0


def cmd_optimal_preload(args: argparse.Namespace) -> int:
    """``pinograsp optimal-preload SCENE -w W ...``: the smallest preload resisting every W, or
    the best split of ``--budget``."""
    scene = opt.load_scene(args.scene)
    out = Output(args)
    method = opt.method(args, scene)
    upper = args.upper if args.upper is not None else 1e3
    _, steps = opt.upper_steps(args, scene)
    wrenches = [opt.parse_wrench(scene, w) for w in args.wrench]
    acts = [a.strip() for a in args.actuators.split(",")] if args.actuators else None
    result = pg.optimal_preload(
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
        settings=opt.settings(args, scene),
    )
    fields = result.to_dict()
    data = {"command": "optimal-preload", **scene_header(scene), "preload": fields.pop("command"), **fields}
    out.print(scene_line(scene), "", result.summary())
    out.write_json("optimal_preload.json", data)
    out.finish(data)
    return 0


def signal_name(signum: int) -> str:
    """``"SIGINT"`` for 2, ..."""
    try:
        return signal.Signals(signum).name
    except ValueError:
        return f"signal {signum}"


def _worst_of(score: object) -> str:
    """What a batch score's ``score`` column is the worst of."""
    if isinstance(score, pg.DisturbanceScore):
        g = score.disturbances
        if isinstance(g, pg.Gravity):
            return f"worst of {len(score.labels)} orientations; multiples of {g.unit}"
        return f"worst of {len(score.labels)} disturbances"
    return "worst axis"


def cmd_batch(args: argparse.Namespace) -> int:
    """``pinograsp batch GRASPS.yaml``: score every grasp of the file; a summary, ``--out`` table.

    ``--out`` is checked before any work; rows are journaled next to it as they finish;
    ``--resume`` keeps the journal's finished rows; Ctrl-C/SIGTERM keeps what finished and
    exits 130/143 (docs/batch.md, "Faults, interruption and resume")."""
    from ..batch.journal import check_output
    from ..batch.pool import Interrupted
    from ..batch.rows import reason_counts

    if args.resume and not args.out:
        raise InvalidInputError("--resume", "needs --out (the table whose journal holds the finished rows)")
    if args.out:
        check_output(args.out, "--out")
    batch = pg.load_grasps(args.grasps)
    options = dict(batch.score)
    for key in ("upper", "steps", "method"):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    score = pg.DisturbanceScore(**options) if "disturbances" in options else pg.WorstAxisScore(**options)
    bar = progress_bar(args, f"batch {args.executor}")
    t0 = time.perf_counter()
    try:
        table = pg.evaluate_grasps(
            list(batch.grasps), score=score, executor=args.executor, workers=args.workers,
            address=args.address, progress=bar, out=args.out, resume=args.resume, timeout=args.timeout,
        )  # fmt: skip
    except Interrupted as exc:
        bar.close()
        kept = f"; kept in {exc.journal} (rerun with --resume to finish)" if exc.journal else ""
        print(f"\npinograsp: interrupted ({signal_name(exc.signum)}): {exc.done} of {exc.total} grasps "
              f"finished{kept}", file=sys.stderr)  # fmt: skip
        return exc.exit_code
    finally:
        bar.close()
    wall = time.perf_counter() - t0
    counts = reason_counts(table)
    by_status = counts.groupby("status", sort=False)["rows"].sum()
    lines = [f"{len(table)} grasps from {args.grasps}: "
             + ", ".join(f"{n} {s}" for s, n in by_status.items())
             + f" ({wall:.1f} s, {len(table) / wall:.2f} grasps/s, executor {args.executor})"]  # fmt: skip
    for r in counts.itertuples():
        if r.status != "ok":
            lines.append(f"  {r.status} {r.reason}: {r.rows}")
    ok = table[table["status"] == "ok"]
    if len(ok):
        q = ok["score"].quantile([0.0, 0.5, 1.0], interpolation="lower").tolist()  # inf-safe: no inf - inf
        gravity = isinstance(score, pg.DisturbanceScore) and isinstance(score.disturbances, pg.Gravity)
        lines.append(f"score{'' if gravity else ' [N]'} of the ok rows ({_worst_of(score)}, {score.method}, "
                     f"upper {score.upper:g}, "
                     f"steps {score.steps}): min {q[0]:.4g}, median {q[1]:.4g}, max {q[2]:.4g}")  # fmt: skip
    if args.out:
        lines.append(f"wrote {args.out}")
    print("\n".join(lines))
    return 0
