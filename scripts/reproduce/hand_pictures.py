"""Pictures of the built-in hand scenes: ``docs/img/hands/<name>.png``.

Each scene at its preload alone (``scene.passive_response(0)``, the scene's method): the hand's
collision geometry, the object, contact forces and friction cones, from a view chosen per hand
so that the object is seen between the fingers (checked by eye).

Usage::

    python scripts/reproduce/hand_pictures.py [name ...]
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

import pinograsp as pg

OUT = Path(__file__).resolve().parents[2] / "docs" / "img" / "hands"

#: name -> (elevation, azimuth) [deg] of the view.
VIEWS = {
    "allegro_left": (15, -30),
    "ezgripper": (10, 20),
    "hey5": (5, -90),
    "ability": (15, -40),
    "dex3": (30, -120),
    "talos_gripper": (5, 5),
    "talos_torus": (35, 20),
    "parallel_jaw_bar": (25, -60),
    "parallel_jaw_box": (25, -60),
}


def picture(name: str) -> Path:
    """Render one scene at its preload to ``OUT/<name>.png``."""
    scene = pg.load_scene(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pg.AuditWarning)
        response = scene.passive_response(np.zeros(6))
    elev, azim = VIEWS[name]
    return pg.save_png(
        scene.model,
        response,
        hand=scene.hand,
        q=scene.q,
        obj=scene.object,
        path=OUT / f"{name}.png",
        title=name,
        elev=elev,
        azim=azim,
    )


def main() -> None:
    for name in sys.argv[1:] or list(VIEWS):
        print(picture(name))


if __name__ == "__main__":
    main()
