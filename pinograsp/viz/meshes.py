"""Triangle meshes of the 3D scene view: Coal collision geometries as trimesh meshes, cones, and
the merging of several meshes into one (vertices (n, 3) [m], faces (m, 3))."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np


def transform(vertices: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Vertices (n, 3) [m] moved by the homogeneous transform ``T`` (4, 4)."""
    return vertices @ T[:3, :3].T + T[:3, 3]


def cone(
    apex: np.ndarray, axis: np.ndarray, height: float, radius: float, sections: int = 24
) -> tuple[np.ndarray, np.ndarray]:
    """Open cone surface: apex, unit axis; returns vertices (sections + 1, 3), faces (sections, 3)."""
    a = axis / np.linalg.norm(axis)
    helper = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(a, helper)
    u /= np.linalg.norm(u)
    v = np.cross(a, u)
    t = 2.0 * np.pi * np.arange(sections) / sections
    ring = apex + height * a + radius * (np.cos(t)[:, None] * u + np.sin(t)[:, None] * v)
    verts = np.vstack([apex, ring])
    k = np.arange(sections)
    faces = np.column_stack([np.zeros(sections, int), 1 + k, 1 + (k + 1) % sections])
    return verts, faces


def merge(parts: Sequence[tuple[np.ndarray, np.ndarray, str]]) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """One mesh of several ``(vertices, faces, label)`` parts, one label per vertex."""
    verts, faces, labels, off = [], [], [], 0
    for v, f, lab in parts:
        verts.append(v)
        faces.append(f + off)
        labels += [lab] * len(v)
        off += len(v)
    if not verts:
        return np.zeros((0, 3)), np.zeros((0, 3), int), []
    return np.vstack(verts), np.vstack(faces), labels


def geometry_mesh(geometry: object) -> Any:
    """A ``trimesh.Trimesh`` of a Coal collision geometry in its own frame (``None`` if unsupported).

    Boxes, spheres, cylinders, capsules, cones, ellipsoids, convex hulls and BVH meshes are
    supported; planes and half-spaces (unbounded) are not.
    """
    import coal
    import trimesh

    g = geometry
    if isinstance(g, coal.Box):
        return trimesh.creation.box(extents=2.0 * np.asarray(g.halfSide, dtype=float))
    if isinstance(g, coal.Sphere):
        return trimesh.creation.icosphere(subdivisions=2, radius=float(g.radius))
    if isinstance(g, coal.Ellipsoid):
        m = trimesh.creation.icosphere(subdivisions=2, radius=1.0)
        m.vertices = m.vertices * np.asarray(g.radii, dtype=float)
        return m
    if isinstance(g, coal.Capsule):
        return trimesh.creation.capsule(
            height=2.0 * float(g.halfLength), radius=float(g.radius), count=[16, 16]
        )
    if isinstance(g, coal.Cylinder):
        return trimesh.creation.cylinder(
            radius=float(g.radius), height=2.0 * float(g.halfLength), sections=24
        )
    if isinstance(g, coal.Cone):
        m = trimesh.creation.cone(radius=float(g.radius), height=2.0 * float(g.halfLength), sections=24)
        m.apply_translation([0.0, 0.0, -float(g.halfLength)])
        return m
    if isinstance(g, coal.ConvexBase):
        pts = np.asarray(g.points(), dtype=float).reshape(-1, 3)
        return trimesh.convex.convex_hull(pts)
    if isinstance(g, coal.BVHModelBase):
        verts = np.asarray(g.vertices(), dtype=float).reshape(-1, 3)
        tris = [g.tri_indices(i) for i in range(int(g.num_tris))]
        faces = np.array([[t[0], t[1], t[2]] for t in tris], dtype=int).reshape(-1, 3)
        return trimesh.Trimesh(verts, faces, process=False)
    return None


__all__ = ["cone", "geometry_mesh", "merge", "transform"]
