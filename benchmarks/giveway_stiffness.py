"""How the default answer moves with the contact stiffness (docs/giveway.md, "How answers move
with the stiffness"; issue 31).

For the built-in scenes — case 1, case 2 along +X with both named preloads, case 3, the pinch
(their named directions) and the six built-in hands (their named directions: into the palm,
pull out, sideways) — the default answer ``scene.max_resistible_wrench(d, settings=...)`` (the
give-way load at the scene's ``upper``) with ``Settings.contact_stiffness`` 1e4, 1e5, 1e6 (the
default, the simulation's) and 1e7 N/m, the give-way reason at each, and the path's first limit
λ* at the default stiffness beside them (λ* depends on the stiffness only through the object's
turning: the geometry is followed as the object turns by the physical rotation, larger on softer
contacts; docs/quasistatic.md, "Large rotations"). Deterministic: no clock, no randomness; the
table is printed (and written with ``--out``). Usage::

    python -m benchmarks.giveway_stiffness [--stiffness 1e4,1e5,1e6,1e7] [--scenes case1,ezgripper]
        [--out FILE.md]
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path

import numpy as np

import pinograsp as pg

STIFFNESS = (1e4, 1e5, 1e6, 1e7)
SCENES = ("case1", "case2", "case3", "pinch", "allegro_left", "ezgripper", "hey5", "ability", "dex3",
          "talos_gripper")  # fmt: skip
#: Case 2's question (the paper's ratio): +X with each named preload.
CASE2 = (("x", "finger1_only"), ("x", "finger2_only"))
#: Reasons abbreviated in the table.
SHORT = {"limit": "lim", "translation": "tr", "rotation": "rot", "joint": "jt", "linearisation": "lin",
         "held": "held"}  # fmt: skip


def queries(name: str) -> list[tuple[str, str | None, np.ndarray]]:
    """``(label, preload name or None, direction)`` of one scene."""
    scene = pg.load_scene(name)
    if name == "case2":
        return [(f"+fx, {p}", p, np.asarray(scene.direction(d), float)) for d, p in CASE2]
    return [(d, None, np.asarray(scene.direction(d), float)) for d in scene.analysis.directions]


def answer(scene: pg.Scene, d: np.ndarray, preload: str | None, k: float) -> tuple[str, float]:
    """The default answer's cell at contact stiffness ``k`` [N/m] and its first limit λ*."""
    settings = pg.Settings(contact_stiffness=k)
    try:
        mw = scene.max_resistible_wrench(d, preload, settings=settings)
    except pg.PinograspError as exc:
        return type(exc).__name__, math.nan
    g = mw.giveway
    lam = math.nan if g is None else g.first_limit
    if mw.status == "unbounded":
        return "unbounded", lam
    if mw.status == "above_limit":
        return f"≥ {mw.upper:g}", lam
    snaps = f", {len(g.snaps)} snaps" if g is not None and g.snaps else ""
    why = "" if g is None else f" ({SHORT.get(g.reason, g.reason)}{snaps})"
    return f"{mw.magnitude:.4g}{why}", lam


def table(scenes: tuple[str, ...], stiffness: tuple[float, ...]) -> list[str]:
    """The markdown table: one row per scene and direction."""
    lines = [
        "| scene | direction | upper | "
        + " | ".join(f"{k:.0e} N/m" for k in stiffness)
        + " | λ* (first limit) |",
        "|---|---|---:|" + "---:|" * (len(stiffness) + 1),
    ]
    for name in scenes:
        scene = pg.load_scene(name)
        for label, preload, d in queries(name):
            cells, lams = [], []
            for k in stiffness:
                c, lam = answer(scene, d, preload, k)
                cells.append(c)
                lams.append(lam)
            lam = lams[stiffness.index(1e6)] if 1e6 in stiffness else lams[0]
            lam_text = "unbounded" if math.isinf(lam) else ("—" if math.isnan(lam) else f"{lam:.4g}")
            lines.append(
                f"| {name} | {label} | {scene.analysis.upper:g} | " + " | ".join(cells) + f" | {lam_text} |"
            )
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--stiffness", default=",".join(f"{k:g}" for k in STIFFNESS))
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--out", help="also write the table to this file")
    args = ap.parse_args(argv)
    stiffness = tuple(float(x) for x in args.stiffness.split(","))
    warnings.simplefilter("ignore")
    lines = table(tuple(args.scenes.split(",")), stiffness)
    lines += [
        "",
        "Cells: the give-way load [N or N·m] and why (lim: a limit whose snap does not land, tr / rot:"
        " the translation / rotation threshold crossed gradually, lin: the linearisation's range,"
        " with the snaps survived), `unbounded` (held within the thresholds to any load) or"
        " `≥ upper`. λ* at 1e6 N/m (the default): it moves with the stiffness only where the"
        " object turns (its geometry is followed as it turns, by a rotation larger on softer contacts).",
    ]
    text = "\n".join(lines) + "\n"
    print(text, end="")
    if args.out:
        Path(args.out).write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
