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


def _c_block() -> trimesh.Trimesh:
    """A 30 x 60 x 40 mm block with a 15 x 20 mm notch through its +x face (a non-convex
    triangle mesh): five 15 x 20 mm cells of a conforming grid, extruded 40 mm along z."""
    xs, ys = [-0.015, 0.0, 0.015], [-0.03, -0.01, 0.01, 0.03]
    V = np.array([[x, y] for y in ys for x in xs])
    faces = []
    for i, j in [(0, 0), (0, 1), (0, 2), (1, 0), (1, 2)]:  # the left bar and the two arms
        a, b, c, d = j * 3 + i, j * 3 + i + 1, (j + 1) * 3 + i + 1, (j + 1) * 3 + i
        faces += [[a, b, c], [a, c, d]]
    mesh = trimesh.creation.extrude_triangulation(V, np.array(faces), 0.04)
    mesh.apply_translation([0.0, 0.0, -0.02])
    return mesh


@pytest.mark.parametrize("y", [0.04, 0.0401])
def test_a_jaw_flush_on_a_mesh_face_whose_edges_coincide_takes_the_face_normal(tmp_path, y):
    """The parallel jaw on the notched block: at y = 40 mm the left jaw's 60 mm face covers the
    block's left face exactly, their edges meeting at y = 10 mm, where the nearest points land.
    The edge's normal cone holds every direction between the two faces, and Coal's there was
    (0.707, 0.707, 0): one point, and +fy 1.67 N, -fy unbounded. The flush box face decides: +x,
    the 4 corners, and the closed form mu F = 10 N both ways, as 0.1 mm further (y = 40.1 mm)."""
    path = tmp_path / "c_block.stl"
    _c_block().export(path)
    obj = pg.RigidObject.from_mesh(path, pose=[0.0, y, 0.0])
    hand = pg.Hand.builtin("parallel_jaw")
    q = hand.close_on(obj)
    report = pg.detect_contacts(hand, q, obj)
    assert report.points_per_patch == (4, 4)
    np.testing.assert_allclose(report.patches[0].normal, [1.0, 0.0, 0.0], atol=1e-7)  # Coal: 5e-9
    m = pg.grasp_model_from_scene(hand, q, obj, mu=0.5)
    for d in ("fy", "-fy"):
        assert pg.max_resistible_wrench(m, 20.0, d, upper=50).magnitude == pytest.approx(10.0, rel=1e-6)


def test_flush_normal_keeps_other_shapes_and_face_interiors():
    """Only a box's face flush on one of several mesh faces at the nearest point decides: a
    sphere, or a nearest point inside a face, keeps the normal given."""
    from pinograsp.robots.mesh_normals import flush_normal

    mesh = _c_block()
    g = coal.BVHModelOBBRSS()
    g.beginModel(len(mesh.faces), len(mesh.vertices))
    g.addVertices(np.asarray(mesh.vertices, dtype=float))
    g.addTriangles(np.asarray(mesh.faces, dtype=int))
    g.endModel()
    T, I3 = coal.Transform3s(np.eye(3), np.zeros(3)), np.eye(3)
    edge = np.array([-0.015, -0.03, 0.0])  # the left face meets the -y face
    given = np.array([0.5, 0.5, 0.0]) / np.sqrt(0.5)
    jaw = coal.Box(0.010, 0.060, 0.020)
    T_jaw = coal.Transform3s(I3, np.array([-0.020, 0.0, 0.0]))  # its +x face on x = -15 mm
    np.testing.assert_allclose(flush_normal(given, jaw, T_jaw, edge, g, T, edge), [1.0, 0.0, 0.0], atol=1e-12)
    assert flush_normal(given, coal.Sphere(0.005), T_jaw, edge, g, T, edge) is given
    inside = np.array([-0.015, 0.0, 0.0])
    assert flush_normal(given, jaw, T_jaw, inside, g, T, inside) is given
