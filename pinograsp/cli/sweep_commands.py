"""Commands that sweep many directions: ``profile`` and ``demo`` (a plane of wrench space),
``compare-preloads`` (named directions under named preloads) and ``resistance-set`` (the unit
wrench sphere). Each ``cmd_*`` takes the parsed arguments and returns the exit code
(docs/cli.md)."""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

import pinograsp as pg

from ..core.methods import search_resolution, search_text
from ..core.results import format_max_wrench
from ..core.serialize import direction_text, format_magnitude, runs_text, signed_text, wrench_unit
from ..core.tables import profile_to_csv
from ..errors import InvalidInputError
from . import options as opt
from .report import Output, model_settings, preload_line, progress_bar, scene_header, scene_line


@dataclass(frozen=True)
class _Sweep:
    """What a profile asks: the scene, the preload (commands [N·m or N] and name) and the query
    (method, ``upper`` [N or N·m], ``steps``: :class:`pinograsp.Query`)."""

    scene: Any
    command: dict[str, float]
    preload_name: str | None
    query: pg.Query
    note: str = ""  # the contact-model settings in words (report.model_settings)

    @property
    def method(self) -> str:
        return str(self.query.method)

    @property
    def upper(self) -> float:
        return float(self.query.upper)

    @property
    def steps(self) -> int:
        return int(self.query.steps)


# ---------------------------------------------------------------------------- profile, demo
def cmd_profile(args: argparse.Namespace) -> int:
    """``pinograsp profile SCENE``: max resistible magnitude over ``n`` directions in a plane."""
    scene = opt.load_scene(args.scene)
    command, preload_name = opt.preload(args, scene)
    plane = opt.parse_plane(scene, args.plane)
    n = args.n if args.n is not None else int(scene.analysis.n)
    sweep = _Sweep(scene, command, preload_name, opt.query(args, scene))
    return _profile_report(args, sweep, plane, n, "profile")


def cmd_demo(args: argparse.Namespace) -> int:
    """``pinograsp demo``: ``profile`` of a built-in scene with few directions and steps."""
    scene = opt.load_scene(args.scene)
    command = scene.preload()
    plane = opt.parse_plane(scene, args.plane)
    sweep = _Sweep(scene, command, None, opt.query(args, scene, default_steps=args.demo_steps))
    return _profile_report(args, sweep, plane, args.n, "demo")


def _run_profile(args: argparse.Namespace, sweep: _Sweep, plane: Any, n: int) -> Any:
    """:func:`pinograsp.resistance_profile` with a progress bar."""
    scene = sweep.scene
    bar = progress_bar(args, f"{scene.name} {sweep.method}")
    bar(0, n)
    try:
        return pg.resistance_profile(
            scene.model, sweep.command, plane, n, query=sweep.query,
            settings=opt.settings(args, scene), progress=bar, workers=opt.workers(args),
        )  # fmt: skip
    finally:
        bar.close()


def _normalization(
    args: argparse.Namespace, scene: Any, command: Any, profile: Any, method: str, upper: float, steps: int
) -> float | None:
    """The +b2 value to divide by (``None``: absolute). The scene's ``normalize`` is the default;
    it is dropped with a warning when the reference is unbounded or zero, an explicit
    ``--normalize`` then fails."""
    from ..analysis.profile import reference_magnitude

    want = args.normalize if args.normalize is not None else scene.analysis.normalize
    if not want:
        return None
    reference = True if (want is True or args.normalize) else want
    settings = opt.settings(args, scene)
    try:
        return reference_magnitude(scene.model, command, profile, reference, method, upper, steps, settings)
    except InvalidInputError as exc:
        if exc.name != "normalize":
            raise
        why = str(exc).removeprefix("normalize: ")
        if args.normalize:
            raise InvalidInputError("--normalize", why) from None
        print(f"pinograsp: warning: not normalised: {why}", file=sys.stderr)
        return None


def _profile_lines(sweep: _Sweep, p: Any, norm: float | None, wall: float, runs: list) -> list[str]:
    """The profile as a table, one row per direction, and its unbounded runs."""
    upper, steps = sweep.upper, sweep.steps
    unit = wrench_unit(p.basis[0] + p.basis[1])
    b1, b2 = (direction_text(b) for b in p.basis)
    header = f"{'angle [deg]':>11s}  {'direction':>22s}  {'max [' + unit + ']':>12s}"
    if norm is not None:
        header += f"  {'normalised':>10s}"
    lines = [
        scene_line(sweep.scene),
        preload_line(sweep.command, sweep.preload_name),
        f"profile in the plane ({b1}, {b2}): {len(p.angles)} directions, method {sweep.method}{sweep.note}, "
        f"{search_text(sweep.method, upper, steps, unit)}; {wall:.1f} s",
        "",
        header,
    ]
    deg = np.degrees(p.angles)
    for i, a in enumerate(deg):
        c, s = signed_text(np.cos(p.angles[i])), signed_text(np.sin(p.angles[i]))
        dtxt = f"{c} {b1.lstrip('+')} {s} {b2.lstrip('+')}"
        r = p.results[i]
        if r.status == "failed":  # the direction's query raised (a node limit, a timeout): see below
            lines.append(f"{a:11.1f}  {dtxt:>22s}  {'FAILED':>12s}")
            continue
        row = f"{a:11.1f}  {dtxt:>22s}  {format_max_wrench(r):>12s}"
        if norm is not None:
            row += f"  {format_max_wrench(r, norm):>10s}"
        lines.append(row)
    lines.append("")
    if runs:
        lines.append("unbounded (passively resisted without bound): " + runs_text(runs))
    else:
        lines.append("no unbounded direction")
    if norm is not None:
        res = search_resolution(sweep.method, upper, steps)
        lines.append(f"normalised by the {b2} value {format_magnitude(norm, res, unit)}")
    bad = [f"{deg[i]:g}°" for i, r in enumerate(p.results) if not r.monotone]
    if bad:
        lines.append("non-monotone bisection evidence at: " + ", ".join(bad))
    if p.failures:
        lines.append(f"{len(p.failures)} direction(s) FAILED (no verdict; the others are kept):")
        lines += [f"  {deg[i]:g}° ({status}): {msg}" for i, msg, status in p.failures]
    return lines


def _plot_profile(sweep: _Sweep, p: Any, norm: float | None, path: Path) -> None:
    """The polar plot of the profile, as ``path``."""
    unit = wrench_unit(p.basis[0] + p.basis[1])
    b2 = direction_text(p.basis[1])
    name = sweep.preload_name
    title = f"{sweep.scene.name} ({sweep.method}" + (f", preload {name})" if name else ")")
    if norm is None:
        title += f": max resistible {unit}"
    else:
        title += f"\nnormalised by the {b2} value {norm:.3g} {unit}"
    ax = pg.plot_profile(p, normalize=norm, title=title, labels=[sweep.method])
    pg.save_figure(ax, path, close=True)


def _profile_report(args: argparse.Namespace, sweep: _Sweep, plane: Any, n: int, kind: str) -> int:
    """Run the profile; print its table, write ``--csv``, ``profile.json`` and ``profile.png``."""
    if n < 1:
        raise InvalidInputError("-n", f"must be >= 1, got {n}")
    Output.target(getattr(args, "csv", None), "--csv")  # before the work
    out = Output(args)
    upper, steps = sweep.upper, sweep.steps
    model_data, note = model_settings(opt.settings(args, sweep.scene))
    sweep = replace(sweep, note=note)
    t0 = time.perf_counter()
    p = _run_profile(args, sweep, plane, n)
    norm = _normalization(args, sweep.scene, sweep.command, p, sweep.method, upper, steps)
    wall = time.perf_counter() - t0
    data = {
        "command": kind,
        **scene_header(sweep.scene),
        "preload": sweep.command,
        "preload_name": sweep.preload_name,
        "method": sweep.method,
        **model_data,
        "upper": upper,
        "steps": steps,
        "resolution": search_resolution(sweep.method, upper, steps),
        "unit": wrench_unit(p.basis[0] + p.basis[1]),
        **p.to_dict(norm),
        "statuses": list(p.statuses),
        "failures": [{"index": i, "message": msg, "status": st} for i, msg, st in p.failures],
        "total_time": wall,
    }
    lines = _profile_lines(sweep, p, norm, wall, data["unbounded_runs_deg"])
    csv_path = getattr(args, "csv", None)
    if csv_path is not None:
        table = p if norm is None else replace(p, magnitudes=p.magnitudes / norm, normalized_by=norm)
        out.written.append(profile_to_csv(table, csv_path, name="--csv"))
    out.print(*lines)
    out.write_json("profile.json", data)
    out.figure("profile.png", lambda path: _plot_profile(sweep, p, norm, path))
    out.finish(data)
    return 0


# ---------------------------------------------------------------------------- compare-preloads
def _preload_names(args: argparse.Namespace, scene: Any) -> list[str]:
    """``--preloads a,b`` (each a scene preload), or every named preload; at least two."""
    if args.preloads:
        names = [t.strip() for t in args.preloads.split(",") if t.strip()]
        for nm in names:
            scene.preload(nm)  # UnknownNameError if not a scene preload
    else:
        names = list(scene.analysis.preloads)
    if len(names) < 2:
        raise InvalidInputError(
            "compare-preloads",
            f"scene {scene.name!r} has {len(names)} named preload(s) ({', '.join(names) or 'none'}); "
            "compare-preloads needs at least two (analysis.preloads in the scene file)",
        )
    return names


def _compare_rows(args: argparse.Namespace, scene: Any, names: list[str]) -> tuple[list, str, float, int]:
    """Per direction: its label, the max wrench per preload, and the ratio of the first two
    (``None`` unless both are finite); and the method, ``upper`` and ``steps`` used."""
    dir_texts = args.direction or list(scene.analysis.directions)
    if not dir_texts:
        raise InvalidInputError(
            "compare-preloads",
            f"scene {scene.name!r} has no named directions (analysis.directions); give --direction",
        )
    method = opt.method(args, scene)
    upper, steps = opt.upper_steps(args, scene)
    settings = opt.settings(args, scene)
    rows = []
    for text in dir_texts:
        direction, label = opt.parse_direction(scene, text)
        per = {
            nm: pg.max_resistible_wrench(
                scene.model, scene.preload(nm), direction, method, upper, steps, settings=settings
            )
            for nm in names
        }
        a, b = per[names[0]], per[names[1]]
        # a ratio of bounds (unbounded, >= upper, < resolution) is undefined
        ratio = a.magnitude / b.magnitude if a.status == "finite" and b.status == "finite" else None
        rows.append((label, per, ratio))
    return rows, method, upper, steps


def _compare_lines(scene: Any, names: list[str], rows: list, head: str) -> list[str]:
    """The comparison table: one row per direction, one column per preload, and the ratio."""
    w = max([len("direction"), *(len(r[0]) for r in rows)])
    lines = [
        scene_line(scene),
        *(f"preload {nm}: " + ", ".join(f"{k}={v:g}" for k, v in scene.preload(nm).items()) for nm in names),
        head,
        "",
        "max resistible magnitude [N or N·m] per preload, ratio = " + f"{names[0]} / {names[1]}:",
        f"  {'direction':{w}s}  " + "  ".join(f"{nm:>14s}" for nm in names) + f"  {'ratio':>8s}",
    ]
    for label, per, ratio in rows:
        cells = "  ".join(f"{format_max_wrench(per[nm]):>14s}" for nm in names)
        rtxt = "-" if ratio is None else f"{ratio:.3f}"
        lines.append(f"  {label:{w}s}  {cells}  {rtxt:>8s}")
    return lines


def _plot_comparison(scene: Any, rows: list, method: str, path: Path) -> None:
    """One bar plot per direction (at most three a row), as ``path``."""
    from ..viz.figures import pyplot

    plt = pyplot()
    k = len(rows)
    cols = min(k, 3)
    nrows = math.ceil(k / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 3.6 * nrows), squeeze=False)
    for ax, (label, per, _) in zip(axes.flat, rows):
        pg.plot_preload_comparison(per, ax=ax, title=None)
        ax.set_title(f"{label}\n{ax.get_title()}", fontsize=9)
    for ax in list(axes.flat)[k:]:
        ax.set_visible(False)
    fig.suptitle(f"{scene.name}: max resistible wrench per preload ({method})")
    fig.tight_layout()
    pg.save_figure(fig, path, close=True)


def cmd_compare_preloads(args: argparse.Namespace) -> int:
    """``pinograsp compare-preloads SCENE``: max resistible magnitude per named preload along
    named directions, and the ratio of the first two preloads."""
    scene = opt.load_scene(args.scene)
    out = Output(args)
    names = _preload_names(args, scene)
    t0 = time.perf_counter()
    rows, method, upper, steps = _compare_rows(args, scene, names)
    wall = time.perf_counter() - t0
    data = {
        "command": "compare-preloads",
        **scene_header(scene),
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
    head = f"method {method}, {search_text(method, upper, steps)}; {wall:.1f} s"
    out.print(*_compare_lines(scene, names, rows, head))
    out.write_json("compare_preloads.json", data)
    out.figure("compare_preloads.png", lambda path: _plot_comparison(scene, rows, method, path))
    out.finish(data)
    return 0


# ---------------------------------------------------------------------------- resistance-set
def cmd_resistance_set(args: argparse.Namespace) -> int:
    """``pinograsp resistance-set SCENE``: max resistible magnitude over ``n`` directions on the
    unit wrench sphere, and the Ferrari-Canny epsilon of the same contacts."""
    scene = opt.load_scene(args.scene)
    if args.n < 1:
        raise InvalidInputError("-n", f"must be >= 1, got {args.n}")
    Output.target(args.csv, "--csv")  # before the work
    out = Output(args)
    command, preload_name = opt.preload(args, scene)
    method = opt.method(args, scene)
    upper, steps = opt.upper_steps(args, scene)
    workers = opt.workers(args)
    bar = progress_bar(args, f"{scene.name} {method}")
    try:
        rset = pg.resistance_set(
            scene.model, command, args.n, method, args.length, args.seed, workers, upper, steps,
            opt.settings(args, scene), progress=bar,
        )  # fmt: skip
    finally:
        bar.close()
    eps = pg.ferrari_canny(scene.model, rset.length)
    data = {
        "command": "resistance-set",
        **scene_header(scene),
        "preload": command,
        "preload_name": preload_name,
        "ferrari_canny": eps,
        **rset.to_dict(),
    }
    out.print(
        scene_line(scene),
        preload_line(command, preload_name),
        "",
        rset.summary(),
        f"Ferrari-Canny epsilon of the same contacts: {eps:.4g}",
    )
    if args.csv is not None:
        out.written.append(rset.to_csv(args.csv, name="--csv"))
    out.write_json("resistance_set.json", data)

    def draw(path: Path) -> None:
        fig = pg.plot_resistance_set(rset, title=f"{scene.name}: resistance set ({method})")
        pg.save_figure(fig, path, close=True)

    out.figure("resistance_set.png", draw)
    out.finish(data)
    return 0
