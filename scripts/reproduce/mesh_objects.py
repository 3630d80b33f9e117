"""Mesh-mesh contact normals (docs/hands.md, "Mesh objects"): errors against closed forms.

* torus: a mesh fingertip (icosphere, 5 mm) placed at signed distance ``gap`` from the tube at
  angles (theta about the axis, phi about the tube); the smooth torus's contact normal is minus
  the tube's radial direction u(theta, phi). Reported: the error of pinograsp's normal against
  it, and against Coal's own normal for the same fingertip as a ``Convex`` (the mesh's exact
  normal while apart; Coal's normal for an overlap with a BVH surface is unreliable), and the
  cost of one mesh-mesh distance;
* L-shape (two boxes, trimesh union): the fingertip over each flat face, normal = face normal;
* convex decomposition (trimesh + vhacdx) of the torus: hull count, time, how far the hulls'
  surface lies from the torus's.

Usage::

    python -m scripts.reproduce.mesh_objects
"""

from __future__ import annotations

import time

import coal
import numpy as np
import trimesh

from pinograsp.robots.collision import _signed_distance
from pinograsp.robots.objects import _vertices

GAPS = (3.5e-4, 1e-5, -3e-4, -1e-3)  # [m]
RHO = 0.005  # fingertip radius [m]


def bvh(mesh: trimesh.Trimesh) -> coal.BVHModelOBBRSS:
    """A Coal BVH of a trimesh mesh (as RigidObject.from_mesh builds it)."""
    g = coal.BVHModelOBBRSS()
    g.beginModel(len(mesh.faces), len(mesh.vertices))
    tris = coal.StdVec_Triangle()
    tris.extend([coal.Triangle(int(a), int(b), int(c)) for a, b, c in mesh.faces])
    g.addSubModel(_vertices(mesh.vertices), tris)
    g.endModel()
    return g


def angle(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between unit vectors [deg]."""
    return float(np.degrees(np.arccos(np.clip(a @ b, -1.0, 1.0))))


def torus_errors(major: float, minor: float, sections: tuple[int, int], gap: float) -> dict[str, float]:
    """Worst and median normal errors [deg] and depth error [mm] over a grid of torus points."""
    obj = bvh(trimesh.creation.torus(major, minor, major_sections=sections[0], minor_sections=sections[1]))
    tip = trimesh.creation.icosphere(subdivisions=3, radius=RHO)
    tip_bvh, tip_convex = bvh(tip), coal.Convex.convexHull(_vertices(tip.vertices), False, None)
    closed, coal_ref, depth, cost = [], [], [], []
    for th in np.radians([3.0, 20.0, 47.0, 110.0]):
        for ph in np.radians(np.arange(5.0, 360.0, 30.0)):
            er = np.array([np.cos(th), np.sin(th), 0.0])
            u = np.cos(ph) * er + np.array([0.0, 0.0, np.sin(ph)])
            T = coal.Transform3s(np.eye(3), major * er + (minor + RHO + gap) * u)
            t0 = time.perf_counter()
            d, _, _, n = _signed_distance(tip_bvh, T, obj, coal.Transform3s())
            cost.append(time.perf_counter() - t0)
            ref = _signed_distance(tip_convex, T, obj, coal.Transform3s())
            closed.append(angle(n, -u))
            coal_ref.append(angle(n, ref[3]))
            depth.append(abs(d - gap))
    return {
        "closed_max": max(closed),
        "closed_median": float(np.median(closed)),
        "coal_max": max(coal_ref),
        "distance_error_mm": 1e3 * max(depth),
        "ms": 1e3 * float(np.median(cost)),
    }


def l_shape() -> trimesh.Trimesh:
    """An L: two 60 x 20 x 20 mm bars joined at a corner."""
    a = trimesh.creation.box((0.06, 0.02, 0.02))
    a.apply_translation((0.02, 0.0, 0.0))
    b = trimesh.creation.box((0.02, 0.06, 0.02))
    b.apply_translation((0.0, 0.02, 0.0))
    return a.union(b)


def l_errors(gap: float) -> float:
    """Worst normal error [deg] with the fingertip over points of the L's faces."""
    mesh = l_shape()
    obj, tip = bvh(mesh), bvh(trimesh.creation.icosphere(subdivisions=3, radius=RHO))
    pts, faces = trimesh.sample.sample_surface_even(mesh, 60, seed=0)
    worst = 0.0
    for p, f in zip(pts, faces):
        nf = mesh.face_normals[f]
        near_edge = mesh.nearest.on_surface([p + 1e-4 * nf])[1][0] > 1e-4
        if near_edge or np.min(np.abs(mesh.bounds - p[None]), axis=0).min() < RHO + 2e-3:
            continue  # the fingertip would touch an edge or another face first
        T = coal.Transform3s(np.eye(3), p + (RHO + gap) * nf)
        worst = max(worst, angle(_signed_distance(tip, T, obj, coal.Transform3s())[3], -nf))
    return worst


def decomposition() -> tuple[int, float, float, float]:
    """vhacd hulls of the torus: count, seconds, surface points outside / inside the hulls [mm]."""
    mesh = trimesh.creation.torus(0.05, 0.0125, major_sections=64, minor_sections=32)
    t0 = time.perf_counter()
    parts = mesh.convex_decomposition()
    seconds = time.perf_counter() - t0
    hulls = [coal.Convex.convexHull(_vertices(p.vertices), False, None) for p in parts]
    pts, _ = trimesh.sample.sample_surface(mesh, 300, seed=0)
    probe = coal.Sphere(1e-9)
    dev = [
        min(_signed_distance(probe, coal.Transform3s(np.eye(3), p), h, coal.Transform3s())[0] for h in hulls)
        for p in pts
    ]
    return len(parts), seconds, 1e3 * -min(dev), 1e3 * max(dev)


def main() -> None:
    for sections in ((64, 32), (128, 64)):
        for gap in GAPS:
            e = torus_errors(0.05, 0.0125, sections, gap)
            print(
                f"torus {sections} gap {gap * 1e3:+.2f} mm: "
                + ", ".join(f"{k} {v:.3g}" for k, v in e.items())
            )
    for gap in GAPS:
        print(f"L-shape gap {gap * 1e3:+.2f} mm: worst normal error {l_errors(gap):.3g} deg")
    n, s, out, inside = decomposition()
    print(f"vhacd torus: {n} hulls in {s:.1f} s; hulls up to {out:.2f} mm outside, {inside:.2f} mm inside")


if __name__ == "__main__":
    main()
