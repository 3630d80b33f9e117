"""Command-line interface: ``pinograsp demo`` and ``pinograsp scenes``.

``demo`` computes the XY resistance profile of a built-in analytic grasp with both methods,
prints a table, and writes ``profile.json`` and ``profile.png`` to ``--out``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from . import analytic
from .analysis import resistance_profile
from .errors import PinograspError

#: Built-in analytic scenes: name -> (factory, default command, description).
SCENES = {
    "pinch": (analytic.pinch, 1.0, "two single-link fingers, DESIGN §6 (F_max = 2 mu tau0 / (L |sin θ|))"),
    "differential-pinch": (
        lambda: analytic.pinch(differential=True),
        1.0,
        "the pinch driven by one actuator through a differential",
    ),
    "wedge": (lambda: analytic.pinch(h=0.01), 1.0, "diagonally offset contacts: PRP wedging artefact"),
    "palm": (analytic.palm_pinch, 1.0, "the pinch with a palm contact below the object"),
    "coupled-finger": (analytic.coupled_finger, 1.0, "a thumb and a two-link finger with a 1/3 coupling"),
}


def _fmt(v: float) -> str:
    return "unbounded" if np.isinf(v) else f"{v:.4f}"


def cmd_demo(args: argparse.Namespace) -> int:
    factory, command, desc = SCENES[args.scene]
    model = factory()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"scene {args.scene!r}: {desc}")
    print(model.summary())
    profiles = {}
    for method in args.methods.split(","):
        t0 = time.perf_counter()
        profiles[method] = resistance_profile(
            model, command, ("fx", "fy"), n=args.n, method=method, upper=args.upper, steps=args.steps
        )
        print(f"{method}: {args.n} directions in {time.perf_counter() - t0:.2f} s")
    print(f"\n{'angle [deg]':>11} | " + " | ".join(f"{m + ' [N]':>14}" for m in profiles))
    first = next(iter(profiles.values()))
    for i, a in enumerate(first.angles):
        print(
            f"{np.degrees(a):11.1f} | "
            + " | ".join(f"{_fmt(p.magnitudes[i]):>14}" for p in profiles.values())
        )
    data = {
        "scene": args.scene,
        "command": command,
        "upper": args.upper,
        "steps": args.steps,
        "angles_deg": np.degrees(first.angles).tolist(),
        "profiles": {
            m: {
                "magnitude": [None if np.isinf(v) else float(v) for v in p.magnitudes],
                "unbounded": p.unbounded.tolist(),
            }
            for m, p in profiles.items()
        },
    }
    (out / "profile.json").write_text(json.dumps(data, indent=2))
    _plot(profiles, args, out / "profile.png")
    print(f"\nwrote {out / 'profile.json'} and {out / 'profile.png'}")
    return 0


def _plot(profiles: dict, args: argparse.Namespace, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(subplot_kw={"projection": "polar"}, figsize=(5, 5))
    finite = np.concatenate([p.magnitudes[~p.unbounded] for p in profiles.values()])
    rmax = 1.2 * (finite.max() if finite.size else 1.0)
    for method, p in profiles.items():
        r = np.where(p.unbounded, np.nan, p.magnitudes)
        ax.plot(np.append(p.angles, p.angles[0]), np.append(r, r[0]), marker=".", label=method)
        for a in p.angles[p.unbounded]:
            ax.bar(a, rmax, width=2 * np.pi / len(p.angles), alpha=0.15, color="C2")
    ax.set_rmax(rmax)
    ax.set_title(f"{args.scene}: max resistible force in XY [N]\n(shaded: unbounded)")
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def cmd_scenes(args: argparse.Namespace) -> int:
    for name, (_, _, desc) in SCENES.items():
        print(f"{name:20s} {desc}")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="pinograsp", description="Passive reaction analysis for robot grasps."
    )
    parser.add_argument("--debug", action="store_true", help="show full tracebacks")
    sub = parser.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("demo", help="resistance profile of a built-in scene (table, JSON, plot)")
    p.add_argument("--scene", default="pinch", choices=sorted(SCENES))
    p.add_argument("--out", default="pinograsp-out", help="output folder (default ./pinograsp-out)")
    p.add_argument("-n", type=int, default=24, help="number of directions")
    p.add_argument("--methods", default="prp,iterative")
    p.add_argument("--upper", type=float, default=1e3, help="bisection upper limit [N]")
    p.add_argument("--steps", type=int, default=20, help="bisection steps")
    p.set_defaults(func=cmd_demo)
    s = sub.add_parser("scenes", help="list built-in scenes")
    s.set_defaults(func=cmd_scenes)
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except PinograspError as exc:
        if args.debug:
            raise
        print(f"pinograsp: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
