"""Write the shipped non-convex mesh objects (``pinograsp/data/meshes/``) with trimesh.

``torus.stl``: a torus about the z axis, major radius :data:`TORUS_MAJOR` (axis to tube centre)
and minor radius :data:`TORUS_MINOR` (tube), :data:`TORUS_SECTIONS` (around the axis, around the
tube) facets, in metres, binary STL. Used by the built-in scene ``talos_torus`` (docs/scenes.md).

Usage::

    python -m scripts.reproduce.make_meshes
"""

from __future__ import annotations

from pathlib import Path

import trimesh

OUT = Path(__file__).resolve().parents[2] / "pinograsp" / "data" / "meshes"

#: Torus radii [m] and facet counts (around the axis, around the tube).
TORUS_MAJOR = 0.05
TORUS_MINOR = 0.0125
TORUS_SECTIONS = (64, 32)


def torus() -> trimesh.Trimesh:
    """The shipped torus (watertight, outward-wound)."""
    major, minor = TORUS_SECTIONS
    return trimesh.creation.torus(TORUS_MAJOR, TORUS_MINOR, major_sections=major, minor_sections=minor)


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / "torus.stl"
    torus().export(path)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
