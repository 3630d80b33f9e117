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

A flat hand face lying flush on a mesh face, their edges coinciding (a jaw placed exactly at a
block's edge), puts the nearest points on both edges, where the cone holds every direction
between the two faces: :func:`flush_normal` then takes the mesh face that is parallel to a face
of the hand's box through its nearest point — the faces that touch over an area.
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


#: Relative distance (to the box's largest half extent) within which a point lies on a box face.
ON_FACE_RTOL = 1e-9
#: Two unit normals are the same plane's when their dot product is at least this.
PARALLEL = 1.0 - 1e-9


def _box_normals(g: coal.CollisionGeometry, T: coal.Transform3s, point: np.ndarray) -> np.ndarray:
    """Outward unit normals (k, 3) of the faces of ``coal.Box`` ``g`` at pose ``T`` through
    ``point`` (3,) [m] (none for a point off its surface)."""
    R, t = np.asarray(T.getRotation(), dtype=float), np.asarray(T.getTranslation(), dtype=float)
    half = np.asarray(g.halfSide, dtype=float)
    local = R.T @ (np.asarray(point, dtype=float) - t)
    tol = ON_FACE_RTOL * float(half.max())
    out = [s * R[:, i] for i in range(3) for s in (-1.0, 1.0) if abs(local[i] - s * half[i]) <= tol]
    return np.array(out).reshape(-1, 3)


def flush_normal(
    normal: np.ndarray,
    hand: coal.CollisionGeometry,
    T_hand: coal.Transform3s,
    p_hand: np.ndarray,
    g: coal.CollisionGeometry,
    T: coal.Transform3s,
    point: np.ndarray,
) -> np.ndarray:
    """The contact normal into BVH surface ``g`` where a box face of the hand lies flush on one of
    its faces at the nearest points.

    When the nearest point ``point`` on the mesh is on an edge or a vertex (faces of several
    directions) and exactly one of those faces is parallel to a face of the hand's ``coal.Box``
    through its nearest point ``p_hand`` (the two faces touch over an area; only their edges
    meet at the nearest points), that face's inward normal; otherwise ``normal`` unchanged (a
    hand geometry other than a box, a face inside, no flush pair or several).
    """
    if type(hand).__name__ != "Box":
        return normal
    faces = feature_faces(g, T, point)
    inward = -np.array([face_normal(g, T, f) for f in faces]).reshape(-1, 3)
    if len(inward) < 2 or float(np.min(inward @ inward[0])) >= PARALLEL:
        return normal  # inside one face (or faces of one plane): no edge to decide
    box = _box_normals(hand, T_hand, p_hand)
    flush = [n for n in inward if len(box) and float(np.max(box @ n)) >= PARALLEL]
    if not flush or any(float(f @ flush[0]) < PARALLEL for f in flush):
        return normal
    return flush[0] / np.linalg.norm(flush[0])
