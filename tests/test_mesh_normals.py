"""Contact normals of shapes overlapping a mesh surface (pinograsp/robots/mesh_normals.py).

Regression input: the acceptance's Barrett × torus plan 2 (docs/planning.md, "What the tables
say"), whose distal link 23 (a box) cuts the torus tube with its side face. Coal's normal there
was the base x axis (the direction that slides one triangle out of the box's side face), 72°
from the tube's normal; the analysis then predicted >= 50 N along every direction while the
simulation of the same model gave way at ~0 along 16 of the 26.
"""

from __future__ import annotations

from pathlib import Path

import coal
import numpy as np
import pytest
import trimesh

import pinograsp as pg
from pinograsp.batch.grasps import GraspSpec, ObjectSpec, build_grasp
from pinograsp.core.poses import rotation_rpy
from pinograsp.robots.mesh_normals import CONE_MARGIN, cone_normal, feature_faces

TORUS = Path(pg.__file__).parent / "data" / "meshes" / "torus.stl"
R_MAJOR, R_TUBE = 0.05, 0.0125  # the shipped torus [m], axis along its z

PLAN_2 = GraspSpec(
    hand="barrett_bh8_282",
    object=ObjectSpec(
        "mesh",
        file=str(TORUS),
        xyz=(0.004000000000004576, 0.00044844423996842403, 0.052546823216605296),
        rpy=(0.7109394710519266, 0.2742036121686274, -3.122044617650954),
    ),
    q={"bh_j11": 0.0, "bh_j12": 1.1100000000000003, "bh_j13": 0.37000000000000016, "bh_j21": 0.0,
       "bh_j22": 1.1400000000000008, "bh_j23": 0.38000000000000017, "bh_j32": 0.4500000000000002,
       "bh_j33": 0.14999999999999997},
    command={"spread": 0.0, "f1": 0.931713, "f2": 1.0, "f3": 0.167894},
)  # fmt: skip


def _torus_inward(point: np.ndarray) -> np.ndarray:
    """Closed-form inward normal of the torus at the pose of PLAN_2, base frame, (3,)."""
    obj = PLAN_2.object
    R, t = rotation_rpy(obj.rpy), np.asarray(obj.xyz)
    p = R.T @ (point - t)
    ring = R_MAJOR * np.array([p[0], p[1], 0.0]) / np.hypot(p[0], p[1])
    out = (p - ring) / np.linalg.norm(p - ring)
    return -(R @ out)


def test_plan_2_normals_follow_the_torus():
    model, _, _ = build_grasp(PLAN_2)
    assert model.contact_names == ("bh_finger_13_link", "bh_finger_23_link", "bh_finger_32_link")
    for i in range(model.nc):
        n = model.frames[i][:, 0]
        angle = np.degrees(np.arccos(np.clip(n @ _torus_inward(model.points[i]), -1, 1)))
        # within half the angle between neighbouring facets (~11°); was 72° for bh_finger_23_link
        assert angle < 6.0, (model.contact_names[i], angle)
    # the corrected normal of link 23 is the mean of the 6 faces around the vertex Coal found
    assert not np.allclose(model.frames[1][:, 0], [1.0, 0.0, 0.0], atol=0.1)


@pytest.mark.slow
def test_plan_2_prediction_matches_the_simulation():
    """With the tube's normal the analysis and MuJoCo agree (21.9 N and 22.2 N along +fy+fz;
    with the tangent normal: 50 N predicted, 0 simulated)."""
    model, command, _ = build_grasp(PLAN_2)
    w = np.array([0.0, 1.0, 1.0, 0.0, 0.0, 0.0]) / np.sqrt(2.0)
    predicted = pg.max_resistible_wrench(model, command, w, upper=50.0, steps=6).magnitude
    simulated = pg.simulate_max_wrench(model, w, command, upper=45.0).load
    assert 5.0 < predicted < 45.0
    assert simulated is not None and abs(simulated - predicted) <= 0.1 * predicted


@pytest.fixture(scope="module")
def cube() -> tuple[coal.BVHModelOBBRSS, coal.Transform3s]:
    """A 2 cm cube as a BVH surface at the origin (outward-wound, 12 triangles)."""
    mesh = trimesh.creation.box((0.02, 0.02, 0.02))
    g = coal.BVHModelOBBRSS()
    g.beginModel(len(mesh.faces), len(mesh.vertices))
    g.addVertices(np.asarray(mesh.vertices, dtype=float))
    g.addTriangles(np.asarray(mesh.faces, dtype=np.int32))
    g.endModel()
    return g, coal.Transform3s(np.eye(3), np.zeros(3))


def test_face_interior_keeps_coal_normal_bit_for_bit(cube):
    g, T = cube
    point = np.array([0.003, -0.002, 0.01])  # inside the top face
    normal = np.array([0.0, 0.0, -1.0])
    assert cone_normal(normal, g, T, point) is normal
    tilted = np.array([np.sin(np.radians(30)), 0.0, -np.cos(np.radians(30))])
    assert np.allclose(cone_normal(tilted, g, T, point), normal)  # outside the face's cone


def test_sharp_edge_keeps_a_normal_inside_its_wedge(cube):
    g, T = cube
    point = np.array([0.0, 0.01, 0.01])  # the middle of the edge between the +y and +z faces
    assert len(feature_faces(g, T, point)) >= 2
    pad = np.array([0.0, -np.sin(np.radians(20)), -np.cos(np.radians(20))])  # 20° from -z
    assert cone_normal(pad, g, T, point) is pad  # a finger pad against the edge: its own normal
    along = np.array([1.0, 0.0, 0.0])  # along the edge: tangent to both faces
    bisector = np.array([0.0, -1.0, -1.0]) / np.sqrt(2.0)
    assert np.allclose(cone_normal(along, g, T, point), bisector)
    assert 0 < CONE_MARGIN < np.radians(10)


def test_the_old_normals_preload_is_refused_not_held(monkeypatch):
    """With Coal's tangent normal (the bug above) the quasi-static preload "settled" with contact
    forces of 1.3e14 N from commands of ~1 N·m and every direction came out ``above_limit``
    (held to 50 N) with no audit failure: a runaway, now refused at the preload
    (``PRELOAD_AMPLIFICATION``: at most 1e6 times the commands' largest force)."""
    import pinograsp.robots.collision as col
    from pinograsp.analysis.quasistatic.preload import PRELOAD_AMPLIFICATION

    monkeypatch.setattr(col, "cone_normal", lambda n, *a, **k: n)
    model, command, _ = build_grasp(PLAN_2)
    assert abs(model.frames[1][:, 0] @ np.array([1.0, 0.0, 0.0])) > 0.999  # the tangent normal
    with pytest.raises(pg.PreloadNotInEquilibriumError, match="times the commands' largest force") as info:
        pg.max_resistible_wrench(model, command, "fx", upper=50.0)
    assert "bh_finger_32_link" in str(info.value) and PRELOAD_AMPLIFICATION == 1e6
