"""``pinograsp plan HAND OBJECT``: grasp plans that resist a disturbance set passively
(``pg.plan_grasps``; docs/planning.md, docs/cli.md)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pinograsp as pg

from ..errors import InvalidInputError
from .report import Output, progress_bar

_SHAPES = {"box": 3, "sphere": 1, "cylinder": 2}
#: The form of each shape's sizes and an example [m] (error messages).
_FORMS = {
    "box": "box:SX,SY,SZ (box:0.05,0.06,0.08)",
    "sphere": "sphere:R (sphere:0.02)",
    "cylinder": "cylinder:R,LENGTH (cylinder:0.02,0.08)",
}


def add_plan(sub: argparse._SubParsersAction) -> None:
    """The ``plan`` sub-command's options."""
    p = sub.add_parser(
        "plan",
        help="plan grasps of an object that resist 26 disturbance directions passively",
        description="Sample approach poses on the object's surface, close the hand, preload, score the "
        "worst-case passive resistance over the 26 directions of a cube, refine the best by a local "
        "search and print the ranked plans (pg.plan_grasps; docs/planning.md). With --out: the plans as "
        "a GRASPS.yaml that 'pinograsp batch' re-scores, their JSON and one picture each.",
    )
    p.add_argument("hand", metavar="HAND", help="built-in hand name or URDF path")
    p.add_argument(
        "object",
        metavar="OBJECT",
        help="box:SX,SY,SZ | sphere:R | cylinder:R,LENGTH [m], or a mesh file (STL/OBJ/PLY, metres)",
    )
    p.add_argument("--n", type=int, default=200, help="approaches sampled (default 200)")
    p.add_argument("--top", type=int, default=5, help="plans returned (default 5)")
    p.add_argument("--verify", type=int, default=0, help="simulate the first K plans (pinograsp[mujoco])")
    p.add_argument("--seed", type=int, default=0, help="seed of the sampling (default 0)")
    p.add_argument("--refine", type=int, default=4, help="best candidates refined (default 4; 0: none)")
    p.add_argument("--rounds", type=int, default=3, help="rounds of the refinement (default 3)")
    p.add_argument("--workers", type=int, default=1, help="local worker processes (0: one per CPU)")
    p.add_argument(
        "--preload", default="auto", help="auto (default), a command for every actuator, or budget=B"
    )
    p.add_argument(
        "--rank-by",
        choices=("passive", "epsilon"),
        default="passive",
        help="rank by the worst-case passive resistance (default) or by the Ferrari-Canny epsilon",
    )
    p.add_argument(
        "--gravity",
        type=float,
        metavar="MASS",
        help="score the object's weight (MASS [kg]) in every orientation instead of the 26 unit forces: "
        "values are multiples of (1 + margin) x the weight, a score >= 1 holds it everywhere",
    )
    p.add_argument("--margin", type=float, help="with --gravity: the safety margin (default 0.5)")
    p.add_argument(
        "--orientations", help="with --gravity: cube26 (default) or a number of directions in [6, 1000]"
    )
    p.add_argument("--mu", type=float, default=0.5, help="friction coefficient (default 0.5)")
    p.add_argument(
        "--edges", type=int, help="friction pyramid edges of every candidate, in [3, 256] (default 16)"
    )
    p.add_argument("--out", metavar="DIR", help="write plans.yaml (GRASPS), plans.json and plan_K.png")
    p.add_argument("--json", action="store_true", help="print the plans as JSON on stdout (nothing else)")
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None, help="progress bar")
    p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help="show full tracebacks")


def parse_object(text: str) -> pg.ObjectSpec:
    """``box:SX,SY,SZ``, ``sphere:R``, ``cylinder:R,LENGTH`` [m] or a mesh file path."""
    shape, _, dims = text.partition(":")
    if shape not in _SHAPES:
        if not Path(text).is_file():
            raise InvalidInputError(
                "OBJECT",
                f"{text!r}: expected box:SX,SY,SZ, sphere:R, cylinder:R,LENGTH [m] or the path of an "
                "existing mesh file (STL/OBJ/PLY, metres); no such shape or file",
            )
        return pg.ObjectSpec("mesh", file=str(Path(text).resolve()))
    try:
        values = [float(v) for v in dims.split(",")]
    except ValueError:
        values = []
    if len(values) != _SHAPES[shape]:
        raise InvalidInputError(
            "OBJECT",
            f"{text!r}: a {shape} takes {_SHAPES[shape]} comma-separated numbers [m]: {_FORMS[shape]}",
        )
    if shape == "box":
        return pg.ObjectSpec("box", size=tuple(values))  # type: ignore[arg-type]
    if shape == "sphere":
        return pg.ObjectSpec("sphere", radius=values[0])
    return pg.ObjectSpec("cylinder", radius=values[0], length=values[1])


def _preload(text: str) -> object:
    if text == "auto":
        return "auto"
    key, _, value = text.partition("=")
    try:
        return {"budget": float(value)} if key == "budget" else float(text)
    except ValueError:
        raise InvalidInputError("--preload", f"expected auto, a number or budget=B, got {text!r}") from None


def _disturbances(args: argparse.Namespace) -> object:
    """``"cube26"``, or a ``pg.Gravity`` from ``--gravity``, ``--margin``, ``--orientations``."""
    if args.gravity is None:
        for flag in ("margin", "orientations"):
            if getattr(args, flag) is not None:
                raise InvalidInputError(f"--{flag}", "applies to --gravity MASS only; give the object's mass")
        return "cube26"
    text = str(args.orientations or "cube26")
    orientations: str | int = int(text) if text.isdigit() else text  # else pg.Gravity names its forms
    margin = 0.5 if args.margin is None else args.margin
    try:
        return pg.Gravity(args.gravity, margin=margin, orientations=orientations)
    except InvalidInputError as exc:  # named by the flag the user typed
        flag = {"mass": "--gravity", "margin": "--margin", "orientations": "--orientations"}.get(
            exc.name, exc.name
        )
        message = str(exc)[len(exc.name) + 2 :]  # InvalidInputError's text is "name: message"
        raise InvalidInputError(flag, f"{message}; see pinograsp plan --help") from None


def cmd_plan(args: argparse.Namespace) -> int:
    """Run ``pinograsp plan``."""
    out = Output(args)
    obj = parse_object(args.object)
    disturbances = _disturbances(args)
    bar = progress_bar(args, f"plan {args.hand}")
    try:
        plans = pg.plan_grasps(
            args.hand, obj, disturbances=disturbances, n=args.n, top=args.top, seed=args.seed,
            preload=_preload(args.preload), workers=args.workers, rank_by=args.rank_by,
            verify=args.verify, mu=args.mu, progress=bar, refine=args.refine, rounds=args.rounds,
            **({} if args.edges is None else {"edges": args.edges}),
        )  # fmt: skip
    finally:
        bar.close()
    lines = [*plans.header(), ""]
    lines.append(
        f"{'rank':>4}  {'id':<24} {'origin':<8} {'score':>9}  {'worst':<10} {'snaps':>5} {'epsilon':>8} "
        f"{'eps rank':>8}  preload"
    )
    for p in plans.plans:
        lines.append(
            f"{p.rank:>4}  {p.id:<24} {p.origin:<8} {p.score:>9.4g}  {p.worst:<10} {len(p.snaps):>5} "
            f"{p.epsilon:>8.4g} {p.epsilon_rank:>8}  {p.preload_text()}"
        )
        for c in p.checks:
            lines.append(
                f"        {c.label:<10} predicted {c.predicted:.4g}, simulated {c.simulated:.4g} ({c.status})"
            )
    g = disturbances if isinstance(disturbances, pg.Gravity) else None
    ylabel = f"largest resisted multiple of {g.unit}" if g else None
    grasps = out.path("plans.yaml")
    if grasps is not None:
        out.written.append(plans.write_grasps(grasps))
        doc = out.path("plans.json")
        assert doc is not None
        doc.write_text(json.dumps(plans.to_dict(), indent=2) + "\n")
        out.written.append(doc)
        for p in plans.plans:
            png = out.path(f"plan_{p.rank}.png")
            assert png is not None
            pg.plot_plan(p, png, ylabel=ylabel)
            out.written.append(png)
        lines.append(f"re-score: pinograsp batch {grasps}")
    out.print(*lines)
    out.finish(plans.to_dict())
    return 0
