"""Normals of a mesh surface (Coal BVH) at a contact: its faces and the feature's normal cone.

Coal answers the signed distance of a shape (a box, a capsule, a convex mesh) and a BVH surface
triangle by triangle. When the shape overlaps the surface, the normal it gives is the direction
of least translation separating the shape from **one triangle**, as if the triangle were a thin
plate alone in space. Where an edge or a vertex of a finely tessellated curved surface pokes into
a face of the shape, that direction slides the triangle out sideways, across the shape's face:
it lies nearly in the surface (docs/planning.md, "Barrett × torus plan 2": a distal link's side
face cutting the torus tube gave the base x axis, 72° from the tube's normal). A closed surface
cannot be separated that way: the neighbouring triangles follow.

A contact normal between a shape and a surface must lie in the **normal cone** of the surface
feature the contact sits on: the inward normals of the triangles around the nearest point (one
triangle inside a face; two along an edge; the fan around a vertex). :func:`cone_normal` keeps
Coal's normal when it is within that cone (approximated by the circular cone around the faces'
mean normal that holds them all, widened by :data:`CONE_MARGIN`), so a sharp mesh edge against
a finger pad keeps the pad's normal; otherwise it returns the faces' mean inward normal, the
mesh's own estimate of the surface normal at that point.
"""

from __future__ import annotations

import coal
import numpy as np

#: Radius [m] of the probe that collects the triangles around a nearest point.
FEATURE_RADIUS = 1e-7
#: Largest number of triangles collected around a point (a vertex fan is 3 to ~12).
FEATURE_TRIANGLES = 32
#: Angle [rad] by which a normal may leave the cone of the feature's faces and still be kept.
CONE_MARGIN = np.deg2rad(5.0)


def face_normal(g: coal.CollisionGeometry, T: coal.Transform3s, face: int) -> np.ndarray:
    """Unit normal (by the triangle's winding: outward for a consistently wound closed mesh) of
    triangle ``face`` of a BVH, in the frame of ``T``, (3,)."""
    tri = g.tri_indices(face)
    a, b, c = (np.asarray(g.vertex(tri[i]), dtype=float) for i in range(3))
    n = np.cross(b - a, c - a)
    return np.asarray(T.getRotation()) @ (n / np.linalg.norm(n))


def feature_faces(g: coal.CollisionGeometry, T: coal.Transform3s, point: np.ndarray) -> tuple[int, ...]:
    """Indices of the triangles of BVH ``g`` at pose ``T`` within :data:`FEATURE_RADIUS` of
    ``point`` (3,) [m] (same frame as ``T``), sorted: the faces of the feature it lies on."""
    req = coal.CollisionRequest()
    req.num_max_contacts = FEATURE_TRIANGLES
    res = coal.CollisionResult()
    probe = coal.Transform3s(np.eye(3), np.asarray(point, dtype=float))
    coal.collide(coal.Sphere(FEATURE_RADIUS), probe, g, T, req, res)
    return tuple(sorted({int(c.b2) for c in res.getContacts()}))


def cone_normal(
    normal: np.ndarray, g: coal.CollisionGeometry, T: coal.Transform3s, point: np.ndarray
) -> np.ndarray:
    """A contact normal into BVH surface ``g`` at pose ``T`` that lies in the normal cone of the
    surface feature at ``point``.

    Args:
        normal: Coal's unit normal into the surface, (3,).
        g: The surface (a closed, outward-wound BVH mesh).
        T: Its pose.
        point: Coal's nearest point on the surface [m], (3,).

    Returns:
        ``normal`` when it is within :data:`CONE_MARGIN` of the circular cone around the
        feature's mean inward face normal that holds every face normal; else that mean (3,).
        ``normal`` unchanged when no triangle is found at ``point``.
    """
    faces = feature_faces(g, T, point)
    if not faces:
        return normal
    inward = -np.array([face_normal(g, T, f) for f in faces])
    mean = inward.sum(axis=0)
    size = float(np.linalg.norm(mean))
    if size < 1e-9:  # a knife edge (opposite faces): no direction to prefer
        return normal
    mean /= size
    spread = float(np.max(np.arccos(np.clip(inward @ mean, -1.0, 1.0))))
    if float(np.arccos(np.clip(normal @ mean, -1.0, 1.0))) <= spread + CONE_MARGIN:
        return normal
    return mean
