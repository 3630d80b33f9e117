"""Contact patches (pinograsp.robots.patches): a flat pad on a flat face is several points.

Closed forms on the built-in parallel jaw squeezing a 30 mm square bar (scene parallel_jaw_bar):
each jaw face touches the bar on a 30 x 20 mm rectangle, its 4 corners the patch points, each
pressing F/8 (F = 20 N motor force, 10 N per jaw, the stiffness split evenly). Along the pads
the friction limit is mu F; about the squeeze axis (x) a rigid twist slides every corner across
its radius r_i, so the torque limit is sum_i mu (F/8) r_i h_i, h_i the friction polygon's reach
in the direction perpendicular to the radius (1 on the polygon's vertices). With patches off the
two single points leave the twist unresisted (0).
"""

import json
from pathlib import Path

import coal
import numpy as np
import pytest

import pinograsp as pg
from pinograsp.core.cones import edge_angles
from pinograsp.errors import InvalidInputError, SceneError
from pinograsp.robots.kinematics import HandConfiguration
from pinograsp.robots.patches import contact_patches, pair_patch

MU, F = 0.5, 20.0
ACCEPTANCE = "scripts/reproduce/data/planning_acceptance.json"
TOL = 1e-3


def T(p, R=None) -> coal.Transform3s:
    return coal.Transform3s(np.eye(3) if R is None else np.asarray(R, float), np.asarray(p, float))


def rot(axis, angle) -> np.ndarray:
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


PAD = coal.Box(0.010, 0.060, 0.020)  # the parallel jaw's jaw
BAR = coal.Box(0.030, 0.030, 0.150)
PAD_POSE = ([-0.0205, 0.0, 0.0], np.eye(3))  # face 0.5 mm from the bar's face x = -15 mm


# ---------------------------------------------------------------------------- geometry
def test_face_patch_is_the_overlap_rectangle():
    kind, pts, n = pair_patch(PAD, T(*PAD_POSE), BAR, T([0, 0, 0]), TOL, 4)
    assert kind == "face" and pts.shape == (4, 3)
    np.testing.assert_allclose(n, [1, 0, 0], atol=1e-9)
    # midway between the faces (x = -15.25 mm), corners of the 30 (y) x 20 (z) mm overlap
    want = {(y, z) for y in (-0.015, 0.015) for z in (-0.01, 0.01)}
    assert {(round(p[1], 9), round(p[2], 9)) for p in pts} == want
    np.testing.assert_allclose(pts[:, 0], -0.01525, atol=1e-9)


def test_patch_points_invariant_under_a_rigid_motion_of_the_scene():
    rng = np.random.default_rng(7)
    base = pair_patch(PAD, T(*PAD_POSE), BAR, T([0, 0, 0]), TOL, 4)
    for _ in range(5):
        R = rot(rng.normal(size=3), rng.uniform(0, 2 * np.pi))
        t = rng.uniform(-0.5, 0.5, 3)
        moved = pair_patch(PAD, T(R @ PAD_POSE[0] + t, R), BAR, T(t, R), TOL, 4)
        assert moved[0] == base[0]
        np.testing.assert_allclose(moved[1], base[1] @ R.T + t, atol=1e-9)  # same points, same order
        np.testing.assert_allclose(moved[2], R @ base[2], atol=1e-9)


def test_a_face_reduces_to_patch_points_by_farthest_point_selection():
    # a cylinder cap (flat) on the bar face: Coal samples the rim; 4 points, then 3
    cyl = coal.Cylinder(0.01, 0.04)
    cap = T([-0.0352, 0, 0], rot([0, 1, 0], np.pi / 2))
    kind, pts, _ = pair_patch(cyl, cap, BAR, T([0, 0, 0]), TOL, 4)
    assert kind == "face" and len(pts) == 4
    np.testing.assert_allclose(np.linalg.norm(pts[:, 1:], axis=1), 0.01, atol=1e-9)  # on the rim
    kind3, pts3, _ = pair_patch(cyl, cap, BAR, T([0, 0, 0]), TOL, 3)
    assert kind3 == "face" and len(pts3) == 3
    # farthest-point selection: a diameter, then the rim point a quarter turn from both ends
    d = sorted(np.linalg.norm(pts3[i] - pts3[j]) for i, j in ((0, 1), (1, 2), (0, 2)))
    np.testing.assert_allclose(d, [0.01 * np.sqrt(2), 0.01 * np.sqrt(2), 0.02], atol=1e-9)


def test_a_line_contact_gives_its_two_end_points():
    # a 20 mm cube turned 45 deg about z: its vertical edge (z +-10 mm) on the bar face
    h = 0.01 * np.sqrt(2)
    kind, pts, n = pair_patch(
        coal.Box(0.02, 0.02, 0.02),
        T([-0.015 - h - 2e-4, 0, 0], rot([0, 0, 1], np.pi / 4)),
        BAR,
        T([0, 0, 0]),
        TOL,
        4,
    )
    assert kind == "line" and pts.shape == (2, 3)
    np.testing.assert_allclose(sorted(pts[:, 2]), [-0.01, 0.01], atol=1e-9)
    np.testing.assert_allclose(pts[:, :2], [[-0.0151, 0.0], [-0.0151, 0.0]], atol=1e-9)


@pytest.mark.parametrize(
    "shape, pose",
    [
        (coal.Sphere(0.01), T([-0.0252, 0, 0])),
        (coal.Capsule(0.01, 0.04), T([-0.0352, 0, 0], rot([0, 1, 0], np.pi / 2))),  # its round end
        (coal.Cylinder(0.01, 0.04), T([-0.0252, 0, 0], rot([0, 1, 0], 0.05))),  # tilted 2 mm over its length
    ],
)
def test_curved_touches_stay_single_points(shape, pose):
    assert pair_patch(shape, pose, BAR, T([0, 0, 0]), TOL, 4) is None


def test_a_curved_side_on_a_straight_side_stays_a_single_point():
    # a cylinder on a sphere, and two cylinders with crossing axes: Coal's patch is one point
    cyl = coal.Cylinder(0.01, 0.04)
    assert pair_patch(cyl, T([0, 0, 0]), coal.Sphere(0.01), T([0.0202, 0, 0]), TOL, 4) is None
    crossing = T([0.0202, 0, 0], rot([1, 0, 0], np.pi / 2))
    assert pair_patch(cyl, T([0, 0, 0]), coal.Cylinder(0.01, 0.04), crossing, TOL, 4) is None


@pytest.mark.parametrize("shape", [coal.Cylinder(0.01, 0.04), coal.Capsule(0.01, 0.04)])
def test_a_straight_side_on_a_face_is_a_line_of_its_generator(shape):
    # the side along the bar's face x = -15 mm (axis z): the generator z +-20 mm, midway at -15.1 mm
    kind, pts, n = pair_patch(shape, T([-0.0252, 0, 0]), BAR, T([0, 0, 0]), TOL, 4)
    assert kind == "line" and pts.shape == (2, 3)
    np.testing.assert_allclose(n, [1, 0, 0], atol=1e-9)
    np.testing.assert_allclose(pts, [[-0.0151, 0, -0.02], [-0.0151, 0, 0.02]], atol=1e-9)


def test_a_cone_side_on_a_face_is_its_generator():
    # cone radius r, height h (apex at +h/2): the generator from (r, 0, -h/2) to (0, 0, h/2)
    r, h = 0.02, 0.1
    n = np.array([h, 0, r]) / np.hypot(h, r)
    pad = T(np.array([r / 2, 0, 0]) + n * (0.01 + 2e-4), rot([0, 1, 0], -np.arctan2(r, h)))
    kind, pts, normal = pair_patch(coal.Cone(r, h), T([0, 0, 0]), coal.Box(0.02, 0.06, 0.2), pad, TOL, 4)
    assert kind == "line"
    np.testing.assert_allclose(normal, n, atol=1e-9)
    ends = np.array([[r, 0, -h / 2], [0, 0, h / 2]]) + 1e-4 * n  # midway across the 0.2 mm gap
    # (Coal's support of the cone stops 0.1 mm short of the base rim, on the generator)
    np.testing.assert_allclose(sorted(pts.tolist(), key=lambda p: p[2]), ends, atol=1e-4)
    off = (pts - ends[0]) - np.outer((pts - ends[0]) @ (ends[1] - ends[0]), ends[1] - ends[0]) / np.sum(
        (ends[1] - ends[0]) ** 2
    )
    np.testing.assert_allclose(off, 0.0, atol=1e-5)


def test_a_pad_on_a_cylinder_side_is_the_generator_under_the_pad():
    # the 20 mm tall pad on a 200 mm cylinder (axis z): the generator clipped to the pad, z +-10 mm
    kind, pts, n = pair_patch(PAD, T([-0.0205, 0, 0]), coal.Cylinder(0.015, 0.2), T([0, 0, 0]), TOL, 4)
    assert kind == "line"
    np.testing.assert_allclose(n, [1, 0, 0], atol=1e-9)
    np.testing.assert_allclose(sorted(pts[:, 2]), [-0.01, 0.01], atol=1e-9)
    np.testing.assert_allclose(pts[:, :2], [[-0.01525, 0], [-0.01525, 0]], atol=1e-9)


# ---------------------------------------------------------------------------- the hand
@pytest.fixture(scope="module")
def bar():
    hand = pg.Hand.builtin("parallel_jaw")
    obj = pg.RigidObject.box([0.030, 0.030, 0.150], pose=[0.0, 0.040, 0.0])
    return hand, hand.close_on(obj), obj


def test_detect_contacts_reports_points_per_patch(bar):
    hand, q, obj = bar
    on = pg.detect_contacts(hand, q, obj)
    off = pg.detect_contacts(hand, q, obj, patches=False)
    assert on.points_per_patch == (4, 4) and [p.kind for p in on.patches] == ["face", "face"]
    assert off.points_per_patch == (1, 1) and len(on.contacts) == len(off.contacts) == 2
    assert "4 point(s) (face)" in on.summary() and on.to_dict()["patches"][0]["kind"] == "face"
    for p in on.patches:  # the corners of the 30 x 20 mm overlap, centred on the bar
        np.testing.assert_allclose(np.sort(np.abs(p.points[:, 1] - 0.04)), [0.015] * 4, atol=1e-9)
        np.testing.assert_allclose(np.abs(p.points[:, 2]), 0.01, atol=1e-9)
    with pytest.raises(InvalidInputError, match="patch_points"):
        pg.detect_contacts(hand, q, obj, patch_points=1)


def test_patch_stiffness_is_split_evenly(bar):
    hand, q, obj = bar
    m_on = pg.grasp_model_from_scene(hand, q, obj, stiffness=2.0)
    m_off = pg.grasp_model_from_scene(hand, q, obj, stiffness=2.0, patches=False)
    assert m_on.nc == 8 and m_off.nc == 2
    assert m_on.contact_names[:4] == tuple(f"pj_left_jaw#{i}" for i in range(4))
    np.testing.assert_allclose(m_on.k, 0.5)
    np.testing.assert_allclose(m_on.k.sum(), m_off.k.sum())
    # the preload: every corner presses F/8 (to 1e-4: Coal's normal at a touching pose is off the
    # face normal by ~1e-5 rad, which tilts the pad and shares the load unevenly at that order)
    r = pg.passive_response(m_on, F, np.zeros(6))
    np.testing.assert_allclose(r.normal_forces, F / 8, rtol=1e-4)


def test_patches_do_not_depend_on_the_geometry_order(bar):
    """The contacts listed in reverse order give the same patches (points, order, names) reversed."""
    hand, q, obj = bar
    config = HandConfiguration.at(hand, q)
    report = pg.detect_contacts(hand, q, obj)
    back = contact_patches(config, obj, tuple(reversed(report.contacts)), report.tolerance)
    for p, r in zip(report.patches, reversed(back)):
        assert p.names == r.names and p.kind == r.kind
        np.testing.assert_array_equal(p.points, r.points)


# ---------------------------------------------------------------------------- resistance
def _twist_limit(m, F_point: float, centre: np.ndarray) -> float:
    """sum_i mu F_point r_i h_i about x through ``centre`` (h_i: the polygon's reach across r_i)."""
    total = 0.0
    for i in range(m.nc):
        r = (m.points[i] - centre) * [0.0, 1.0, 1.0]  # the radius about the x axis
        t = np.cross([1.0, 0, 0], r)  # the corner's velocity in a twist about +x
        frame = m.frames[i]
        phi = np.arctan2(frame[:, 2] @ t, frame[:, 1] @ t)
        h = np.max(np.cos(edge_angles(m, i) - phi))
        total += m.mu[i] * F_point * np.linalg.norm(r) * h
    return float(total)


def _assert_line_twist(hand, q, obj, *, closed_rtol: float, answer_rtol: float) -> None:
    """A 40 mm line per jaw resists a twist about the squeeze axis of mu F L / 2 (hand
    computation within ``closed_rtol``), the default answer finds it in both senses (within
    ``answer_rtol`` and the bisection's resolution); one point per jaw resists none."""
    m = pg.grasp_model_from_scene(hand, q, obj, mu=MU)
    twist = _twist_limit(m, F / 4, obj.center_of_mass)
    assert twist == pytest.approx(MU * F * 0.040 / 2, rel=closed_rtol)
    upper, steps = 50.0, 14
    for d in ("mx", "-mx"):
        mw = pg.max_resistible_wrench(m, F, d, upper=upper, steps=steps)
        assert mw.status == "finite" and mw.magnitude == pytest.approx(
            twist, abs=upper / 2**steps + answer_rtol * twist
        )
    off = pg.grasp_model_from_scene(hand, q, obj, mu=MU, patches=False)
    assert off.nc == 2 and pg.max_resistible_wrench(off, F, "mx", upper=upper, steps=steps).magnitude == 0.0


def test_flat_pads_resist_twist_and_forces_along_the_pads(bar):
    hand, q, obj = bar
    m_on = pg.grasp_model_from_scene(hand, q, obj, mu=MU)
    m_off = pg.grasp_model_from_scene(hand, q, obj, mu=MU, patches=False)
    upper, steps = 50.0, 14
    res = upper / 2**steps
    twist = _twist_limit(m_on, F / 8, obj.center_of_mass)
    assert twist == pytest.approx(8 * MU * (F / 8) * 0.025 / np.sqrt(2), rel=1e-9)  # 0.1768 N m
    for d, limit in (("fy", MU * F), ("fz", MU * F), ("mx", twist), ("-mx", twist)):
        mw = pg.max_resistible_wrench(m_on, F, d, upper=upper, steps=steps)
        assert mw.status == "finite" and mw.magnitude == pytest.approx(limit, abs=res + 1e-4 * limit), d
    off = pg.max_resistible_wrench(m_off, F, "mx", upper=upper, steps=steps)
    assert off.status == "below_resolution" and off.magnitude == 0.0
    for d in ("fy", "fz"):  # along the pads: the same friction limit with one point per jaw
        assert pg.max_resistible_wrench(m_off, F, d, upper=upper, steps=steps).magnitude == pytest.approx(
            MU * F, abs=res + 1e-3
        )


def test_builtin_scenes_and_their_options():
    bar = pg.load_scene("parallel_jaw_bar")
    assert bar.model.nc == 8 and "twist" in bar.analysis.directions
    assert pg.load_scene("parallel_jaw_bar", patches=False).model.nc == 2
    assert pg.load_scene("parallel_jaw_bar", patch_points=3).model.nc == 6
    box = pg.load_scene("parallel_jaw_box")
    assert box.model.nc == 8
    # the box face overlaps the jaw on y 20..70 mm, z +-10 mm: corners 25 mm and 10 mm from its centre
    np.testing.assert_allclose(sorted(set(np.round(box.model.points[:, 1], 9))), [0.02, 0.07], atol=1e-9)
    for bad in (1, 17, 2.5, "yes"):
        with pytest.raises(SceneError, match="patch_points"):
            pg.load_scene("parallel_jaw_bar", patch_points=bad)
    with pytest.raises(SceneError, match="patches"):
        pg.load_scene("parallel_jaw_bar", patches="no")


@pytest.mark.slow
def test_twist_limit_matches_the_simulation():
    """MuJoCo (the model's own 8-edge pyramid) against the quasi-static twist limit: the
    simulation calls the give-way once the object has turned its rotation threshold, with finite
    tangential springs and a ramped load; 1 % covers that (measured 0.04 %)."""
    scene = pg.load_scene("parallel_jaw_bar")
    qs = pg.max_resistible_wrench(scene.model, scene.command, "mx", upper=50.0, steps=14)
    sim = pg.simulate_max_wrench(scene, "mx", upper=50.0, friction="pyramid")
    assert sim.status == "gave_way" and sim.load == pytest.approx(qs.magnitude, rel=1e-2)


# ---------------------------------------------------------------------------- lines on cylinders
def _closed_on_cylinder(hand):
    """``hand`` closed on a 30 mm cylinder, 40 mm long, its axis along y at y = 40 mm."""
    pose = np.eye(4)
    pose[:3, :3] = rot([1, 0, 0], -np.pi / 2)  # the cylinder's z axis along y
    pose[:3, 3] = [0.0, 0.040, 0.0]
    obj = pg.RigidObject.cylinder(0.015, 0.040, pose=pose)
    return hand, hand.close_on(obj), obj


@pytest.fixture(scope="module")
def cylinder():
    """The parallel jaw on a 30 mm cylinder, 40 mm long, its axis along the jaws' long side (y)."""
    hand = pg.Hand.builtin("parallel_jaw")
    return _closed_on_cylinder(hand)


def test_a_cylinder_between_flat_jaws_touches_each_along_a_line(cylinder):
    hand, q, obj = cylinder
    report = pg.detect_contacts(hand, q, obj)
    assert report.points_per_patch == (2, 2) and [p.kind for p in report.patches] == ["line", "line"]
    for p in report.patches:  # the generator x = -+15 mm, its ends y = 40 -+ 20 mm: L = 40 mm apart
        np.testing.assert_allclose(sorted(p.points[:, 1]), [0.02, 0.06], atol=1e-9)
        np.testing.assert_allclose(np.abs(p.points[:, 0]), 0.015, atol=2e-4)  # the auto-close gap
        np.testing.assert_allclose(p.points[:, 2], 0.0, atol=1e-6)  # Coal's normal ~3e-5 rad off x
    assert pg.detect_contacts(hand, q, obj, patches=False).points_per_patch == (1, 1)


def test_a_line_resists_the_twist_about_the_jaw_normal(cylinder):
    """Twist about the squeeze axis x: the 4 end points, F/4 each, slide across their radius
    L/2 = 20 mm: mu F L / 2 = 0.2 N m (sum_i mu (F/4) r_i h_i, h_i = 1 along the y edge of the
    8-edge pyramid); one point per jaw on the axis: 0. MuJoCo (pyramid): 0.1999 N m."""
    hand, q, obj = cylinder
    assert pg.grasp_model_from_scene(hand, q, obj, mu=MU).nc == 4
    _assert_line_twist(hand, q, obj, closed_rtol=1e-9, answer_rtol=1e-4)


def test_a_cylinder_pushed_across_the_jaws_gives_way_at_the_squeeze_both_ways(cylinder):
    """Along the squeeze axis x the far jaw unloads and the near one carries the whole load at
    its command: the grasp gives way at F = 20 N in both senses. At +x the far jaw's line
    unloads to ~2e-5 N per end on a pyramid vertex, where the rate problem's face block is
    singular and it has no solution (its singular index sets decided by a linear program,
    pinograsp.solvers.lcp_certificates.provably_unsolvable): the grasp gives way there. That side used to
    stop without a verdict (SolverError) while -x answered 20.0 N."""
    hand, q, obj = cylinder
    m = pg.grasp_model_from_scene(hand, q, obj, mu=MU)
    loads = []
    for d in ("fx", "-fx"):
        mw = pg.max_resistible_wrench(m, F, d, upper=50.0)
        assert mw.status == "finite" and mw.giveway.reason == "limit"
        loads.append(mw.magnitude)
    assert loads == pytest.approx([F, F], rel=1e-4)


def test_line_points_invariant_under_a_rigid_motion_and_relabelling(cylinder):
    hand, q, obj = cylinder
    config = HandConfiguration.at(hand, q)
    report = pg.detect_contacts(hand, q, obj)
    back = contact_patches(config, obj, tuple(reversed(report.contacts)), report.tolerance)
    for p, r in zip(report.patches, reversed(back)):
        assert p.names == r.names and p.kind == r.kind == "line"
        np.testing.assert_array_equal(p.points, r.points)
    rng = np.random.default_rng(3)
    cyl, jaw = coal.Cylinder(0.015, 0.040), coal.Box(0.010, 0.060, 0.020)
    Rc, jaw_pose = rot([1, 0, 0], -np.pi / 2), [-0.0202, 0.0, 0.0]
    base = pair_patch(jaw, T(jaw_pose), cyl, T([0, 0, 0], Rc), TOL, 4)
    assert base[0] == "line"
    for _ in range(5):
        R = rot(rng.normal(size=3), rng.uniform(0, 2 * np.pi))
        t = rng.uniform(-0.5, 0.5, 3)
        moved = pair_patch(jaw, T(R @ jaw_pose + t, R), cyl, T(t, R @ Rc), TOL, 4)
        assert moved[0] == "line"
        np.testing.assert_allclose(moved[1], base[1] @ R.T + t, atol=1e-9)
        np.testing.assert_allclose(moved[2], R @ base[2], atol=1e-9)


# ---------------------------------------------------------------------------- meshes
def _mesh_object(tmp_path, mesh, convex):
    path = tmp_path / "shape.stl"
    mesh.export(path)
    return pg.RigidObject.from_mesh(path, convex=convex)


@pytest.mark.parametrize("convex", [True, False])
def test_a_mesh_box_on_a_flat_jaw_gives_the_primitive_box_corners(tmp_path, convex):
    trimesh = pytest.importorskip("trimesh")
    mesh = _mesh_object(tmp_path, trimesh.creation.box([0.030, 0.030, 0.150]), convex)
    assert mesh.kind == ("convex" if convex else "mesh")
    prim = pair_patch(PAD, T(*PAD_POSE), BAR, T([0, 0, 0]), TOL, 4)
    got = pair_patch(PAD, T(*PAD_POSE), mesh.geometry, mesh.transform, TOL, 4, np.array([1.0, 0, 0]))
    assert got[0] == prim[0] == "face"
    np.testing.assert_allclose(got[1], prim[1], atol=1e-9)  # same corners, same canonical order
    np.testing.assert_allclose(got[2], prim[2], atol=1e-8)  # Coal's hull normal to ~3e-9


@pytest.mark.parametrize("convex", [True, False])
def test_tessellated_curves_stay_single_points(tmp_path, convex):
    """A sphere mesh, and an ellipsoid mesh (15 x 15 x 45 mm) with its long axis along the pad:
    their vertices within 1 mm of the pad plane are not coplanar within 0.1 mm (the facets
    bend), and their top vertices (within 0.1 mm) span a few facets (the ellipsoid, of radius of
    curvature c^2 / a = 135 mm along z: 6.2 mm, under both 10 mm and a quarter of its 90 mm), so
    one point each."""
    trimesh = pytest.importorskip("trimesh")
    for mesh, x in (
        (trimesh.creation.icosphere(3, 0.015), 0.0152),
        (trimesh.creation.icosphere(4, 0.015).apply_scale([1.0, 1.0, 3.0]), 0.0152),  # 135 mm along z
    ):
        obj = _mesh_object(tmp_path, mesh, convex)
        pad = T([-0.005 - x, 0, 0], rot([1, 0, 0], np.pi / 2))  # the pad's 60 mm along z
        assert pair_patch(PAD, pad, obj.geometry, obj.transform, TOL, 4, np.array([1.0, 0, 0])) is None


def test_a_pad_on_the_torus_mesh_stays_one_point():
    """The shipped torus (a non-convex triangle mesh): the jaws of talos_torus touch its tube with
    one point each."""
    scene = pg.load_scene("talos_torus")
    on = pg.detect_contacts(scene.hand, scene.q, scene.object)
    assert set(on.points_per_patch) == {1}


# ---------------------------------------------------------------------------- lines Coal gives as a point
CYL_A, CYL_B = coal.Cylinder(0.010, 0.040), coal.Cylinder(0.015, 0.060)  # L1 = 40 mm, L2 = 60 mm


@pytest.mark.parametrize("shape", [CYL_A, coal.Capsule(0.010, 0.040)])
@pytest.mark.parametrize("offset", [0.0, 0.010, 0.035])
def test_parallel_sides_touch_along_the_overlap_of_their_lengths(shape, offset):
    """Axes along z, 0.2 mm apart at x: the first side spans z +-20 mm (a capsule: its straight
    part), the second 60 mm centred at ``offset``; the line is their overlap, midway (x = 10.1 mm)."""
    got = pair_patch(shape, T([0, 0, 0]), CYL_B, T([0.0252, 0, offset]), TOL, 4)
    assert got is not None and got[0] == "line"
    lo, hi = max(-0.02, offset - 0.03), min(0.02, offset + 0.03)
    np.testing.assert_allclose(got[1], [[0.0101, 0, lo], [0.0101, 0, hi]], atol=1e-9)
    np.testing.assert_allclose(got[2], [1, 0, 0], atol=1e-9)


def test_parallel_sides_that_only_share_an_end_touch_at_a_point():
    # the second cylinder starts where the first ends (z = 20 mm): no overlap
    assert pair_patch(CYL_A, T([0, 0, 0]), CYL_B, T([0.0252, 0, 0.05]), TOL, 4) is None


@pytest.mark.parametrize("axis", [[1, 0, 0], [0, 1, 0]])  # about the normal (crossing), across it
def test_a_tilted_pair_is_a_line_within_the_tolerance_and_a_point_beyond(axis):
    """The second 40 mm cylinder tilted by theta: a line while sin(theta) * overlap <= 1 mm
    (theta <= ~0.025 rad over 40 mm); its ends at +-20 cos(theta / 2) mm along the mean axis."""
    for theta, line in ((0.02, True), (0.03, False)):
        R = rot(axis, theta)
        got = pair_patch(CYL_A, T([0, 0, 0]), CYL_A, T([0.0202, 0, 0], R), TOL, 4)
        if not line:
            assert got is None, theta
            continue
        assert got is not None and got[0] == "line", theta
        length = np.linalg.norm(got[1][1] - got[1][0])
        assert np.sin(theta) * length <= TOL
        if axis == [1, 0, 0]:  # the mean axis turned theta / 2 about x
            assert length == pytest.approx(0.04 * np.cos(theta / 2), rel=1e-9)


def test_crossing_straight_sides_stay_one_point():
    crossing = T([0.0252, 0, 0], rot([1, 0, 0], np.pi / 2))
    assert pair_patch(CYL_A, T([0, 0, 0]), CYL_B, crossing, TOL, 4) is None
    assert pair_patch(coal.Capsule(0.01, 0.04), T([0, 0, 0]), CYL_B, crossing, TOL, 4) is None


def test_parallel_sides_invariant_under_a_rigid_motion_and_relabelling():
    rng = np.random.default_rng(11)
    pose = [0.0252, 0.0, 0.01]
    base = pair_patch(CYL_A, T([0, 0, 0]), CYL_B, T(pose), TOL, 4)
    swapped = pair_patch(CYL_B, T(pose), CYL_A, T([0, 0, 0]), TOL, 4)  # the other as the hand
    by_z = np.argsort(swapped[1][:, 2])  # the hand's frame orders them; the same two points
    np.testing.assert_allclose(swapped[1][by_z], base[1], atol=1e-9)
    np.testing.assert_allclose(swapped[2], -base[2], atol=1e-9)
    for _ in range(5):
        R = rot(rng.normal(size=3), rng.uniform(0, 2 * np.pi))
        t = rng.uniform(-0.5, 0.5, 3)
        moved = pair_patch(CYL_A, T(t, R), CYL_B, T(R @ pose + t, R), TOL, 4)
        assert moved[0] == "line"
        np.testing.assert_allclose(moved[1], base[1] @ R.T + t, atol=1e-9)  # same points, same order
        np.testing.assert_allclose(moved[2], R @ base[2], atol=1e-9)


def _cylinder_mesh(tmp_path, convex, turn, sections=32, length=0.1):
    """A trimesh cylinder (radius 15 mm, axis z) turned ``turn`` about its axis."""
    trimesh = pytest.importorskip("trimesh")
    mesh = trimesh.creation.cylinder(0.015, length, sections=sections)
    mesh.apply_transform(trimesh.transformations.rotation_matrix(turn, [0, 0, 1]))
    return _mesh_object(tmp_path, mesh, convex)


@pytest.mark.parametrize("convex", [True, False])
@pytest.mark.parametrize("turn", [0.0, np.pi / 32])  # a vertex line, a facet under the pad
def test_a_cylinder_mesh_on_a_flat_jaw_gives_the_primitive_line(tmp_path, convex, turn):
    """The pad 0.2 mm from the tessellated side (32 sections) and from the primitive cylinder:
    the same end points z = +-10 mm (the pad's 20 mm), on the same line, to the tessellation's
    accuracy: a facet lies r (1 - cos(pi / 32)) = 0.072 mm inside the circle."""
    obj = _cylinder_mesh(tmp_path, convex, turn)
    x = 0.015 * np.cos(turn)  # the mesh's side under the pad
    got = pair_patch(
        PAD, T([-0.005 - x - 2e-4, 0, 0]), obj.geometry, obj.transform, TOL, 4, np.array([1.0, 0, 0])
    )
    prim = pair_patch(PAD, T([-0.0202, 0, 0]), coal.Cylinder(0.015, 0.1), T([0, 0, 0]), TOL, 4)
    assert got is not None and got[0] == prim[0] == "line"
    np.testing.assert_allclose(got[1][:, 1:], prim[1][:, 1:], atol=1e-9)  # same y, z: same order
    np.testing.assert_allclose(got[1][:, 0], -x - 1e-4, atol=1e-9)  # midway across the 0.2 mm gap
    np.testing.assert_allclose(got[1][:, 0], prim[1][:, 0], atol=0.015 * (1 - np.cos(np.pi / 32)) + 1e-9)
    np.testing.assert_allclose(got[2], prim[2], atol=1e-8)


@pytest.mark.parametrize("convex", [True, False])
def test_a_cylinder_mesh_finger_along_a_face_is_its_generator(tmp_path, convex):
    """The tessellated cylinder as the hand geometry, along the 150 mm bar: its whole 100 mm."""
    fing = _cylinder_mesh(tmp_path, convex, 0.0)
    got = pair_patch(fing.geometry, T([-0.0302, 0, 0]), BAR, T([0, 0, 0]), TOL, 4, np.array([1.0, 0, 0]))
    assert got is not None and got[0] == "line"
    np.testing.assert_allclose(got[1], [[-0.0151, 0, -0.05], [-0.0151, 0, 0.05]], atol=1e-9)


@pytest.mark.parametrize("convex", [True, False])
@pytest.mark.parametrize("offset", [0.0, 0.030])
def test_a_cylinder_mesh_finger_along_a_cylinder_is_their_overlap(tmp_path, convex, offset):
    """The tessellated cylinder (100 mm, 32 sections) as the hand geometry, its axis parallel to
    a primitive cylinder's (60 mm, radius 10 mm) 0.2 mm away, the finger's centre at z =
    -offset: two straight sides, a line over their overlap (z from max(-offset - 50, -30) to
    min(-offset + 50, 30) mm), midway across the gap. Crossing at 30 degrees: one point."""
    fing = _cylinder_mesh(tmp_path, convex, 0.0)
    other, n = coal.Cylinder(0.010, 0.060), np.array([1.0, 0, 0])
    got = pair_patch(fing.geometry, T([-0.0252, 0, -offset]), other, T([0, 0, 0]), TOL, 4, n)
    assert got is not None and got[0] == "line"
    lo, hi = max(-offset - 0.05, -0.03), min(-offset + 0.05, 0.03)
    np.testing.assert_allclose(np.sort(got[1][:, 2]), [lo, hi], atol=1e-9)
    np.testing.assert_allclose(got[1][:, 0], -0.0101, atol=1e-9)
    np.testing.assert_allclose(got[2], n, atol=1e-8)
    crossing = T([0, 0, 0], rot([1, 0, 0], np.pi / 6))
    assert pair_patch(fing.geometry, T([-0.0252, 0, 0]), other, crossing, TOL, 4, n) is None


def test_the_hey5_middle_fingertip_lies_along_the_cylinder():
    """The hey5 scene: the middle fingertip's straight side (a tessellated strip of 14 mm) runs
    parallel to the cylinder's axis: a 14 mm line; the other fingertips cross it (30 degrees) or
    touch with a rounded tip: one point each."""
    scene = pg.load_scene("hey5")
    report = pg.detect_contacts(scene.hand, scene.q, scene.object)
    kinds = {p.link: p.kind for p in report.patches}
    assert kinds.pop("hand_middle_flex_3_link") == "line" and set(kinds.values()) == {"point"}
    (line,) = [p for p in report.patches if p.kind == "line"]
    assert np.linalg.norm(line.points[1] - line.points[0]) == pytest.approx(0.014, abs=1e-6)
    axis = (line.points[1] - line.points[0]) / np.linalg.norm(line.points[1] - line.points[0])
    assert abs(axis @ scene.object.transform.getRotation()[:, 2]) == pytest.approx(1.0, abs=1e-9)
    assert scene.model.nc == 6


def test_a_short_cylinder_mesh_stays_one_point(tmp_path):
    """A 8 mm long tessellated cylinder: its line would be under 10 tolerances (10 mm)."""
    obj = _cylinder_mesh(tmp_path, False, 0.0, length=0.008)
    assert (
        pair_patch(PAD, T([-0.0202, 0, 0]), obj.geometry, obj.transform, TOL, 4, np.array([1.0, 0, 0]))
        is None
    )


def test_mesh_line_invariant_under_a_rigid_motion(tmp_path):
    obj = _cylinder_mesh(tmp_path, False, np.pi / 32)
    pad = np.array([-0.005 - 0.015 * np.cos(np.pi / 32) - 2e-4, 0.0, 0.0])
    n = np.array([1.0, 0, 0])
    base = pair_patch(PAD, T(pad), obj.geometry, T([0, 0, 0]), TOL, 4, n)
    rng = np.random.default_rng(5)
    for _ in range(4):
        R = rot(rng.normal(size=3), rng.uniform(0, 2 * np.pi))
        t = rng.uniform(-0.5, 0.5, 3)
        moved = pair_patch(PAD, T(R @ pad + t, R), obj.geometry, T(t, R), TOL, 4, R @ n)
        assert moved[0] == "line"
        np.testing.assert_allclose(moved[1], base[1] @ R.T + t, atol=1e-8)
        np.testing.assert_allclose(moved[2], R @ base[2], atol=1e-8)


@pytest.fixture(scope="module")
def rods(tmp_path_factory):
    """The parallel jaw with round jaws (cylinders, 5 mm radius, 60 mm along y) closed on the
    30 mm cylinder, 40 mm long along y: each rod touches it along their 40 mm overlap."""
    root = Path(__file__).resolve().parents[1] / "urdf"
    folder = tmp_path_factory.mktemp("rod_jaw")
    box = '<origin xyz="0 0.040 0" rpy="0 0 0"/>\n      <geometry><box size="0.010 0.060 0.020"/></geometry>'
    rod = (
        '<origin xyz="0 0.040 0" rpy="1.5707963267948966 0 0"/>\n'
        '      <geometry><cylinder radius="0.005" length="0.060"/></geometry>'
    )
    text = (root / "parallel_jaw.urdf").read_text()
    assert text.count(box) == 2
    (folder / "rod_jaw.urdf").write_text(text.replace(box, rod))
    (folder / "rod_jaw.yaml").write_text((root / "parallel_jaw.yaml").read_text())
    hand = pg.Hand.from_urdf(folder / "rod_jaw.urdf")
    return _closed_on_cylinder(hand)


def test_round_jaws_on_a_cylinder_touch_along_lines_and_resist_twist(rods):
    """Twist about the squeeze axis x: the 4 line ends, F/4 each, slide across their radius
    L/2 = 20 mm: mu F L / 2 = 0.2 N m, less the 8-edge pyramid's reach along the slide (Coal's
    cylinder-on-cylinder normal is 6e-3 rad off x, which turns the pyramid: 0.9 %); one point per
    rod (Coal's closest pair, as before the lines): 0."""
    hand, q, obj = rods
    report = pg.detect_contacts(hand, q, obj)
    assert report.points_per_patch == (2, 2) and {p.kind for p in report.patches} == {"line"}
    for p in report.patches:  # the overlap y = 20..60 mm, at the contact x = -+15 mm
        np.testing.assert_allclose(sorted(p.points[:, 1]), [0.02, 0.06], atol=1e-9)
        np.testing.assert_allclose(np.abs(p.points[:, 0]), 0.015, atol=2e-4)
    _assert_line_twist(hand, q, obj, closed_rtol=1.5e-2, answer_rtol=1e-3)


@pytest.mark.slow
def test_round_jaw_twist_matches_the_simulation(rods):
    """MuJoCo (the model's own pyramid) against the quasi-static twist limit of the rod lines
    (measured 0.19807 vs 0.19824 N m, 0.09 %)."""
    hand, q, obj = rods
    m = pg.grasp_model_from_scene(hand, q, obj, mu=MU)
    qs = pg.max_resistible_wrench(m, F, "mx", upper=50.0, steps=14)
    sim = pg.simulate_max_wrench(m, "mx", {"gripper": F}, upper=50.0, friction="pyramid")
    assert sim.status == "gave_way" and sim.load == pytest.approx(qs.magnitude, rel=1e-2)


@pytest.mark.slow
@pytest.mark.parametrize("obj", ["box", "cylinder", "torus"])
def test_the_ability_hand_gives_no_mesh_line_artefacts(obj):
    """The Ability hand's rounded mesh fingers on the planning acceptance's sampled grasps of a
    box, a cylinder and the torus mesh (50, 50 and 50): one point per contact, as before
    the mesh lines (their top sets are one facet, or their Coal line is under 10 mm; with a 5 mm
    length alone, 2 box contacts were 5.5-6 mm lines)."""
    from pinograsp.batch.grasps import grasp_configuration
    from scripts.reproduce.planning_acceptance import spec_of

    data = json.loads((Path(__file__).resolve().parents[1] / ACCEPTANCE).read_text())
    counts = []
    for g in data["pairs"][f"ability × {obj}"]["grasps"]:
        hand, body, q = grasp_configuration(spec_of(g["spec"]))
        counts += pg.detect_contacts(hand, q, body).points_per_patch
    assert len(counts) >= 250 and set(counts) == {1}


@pytest.mark.parametrize("convex", [True, False])
def test_a_cylinder_mesh_between_the_jaws_resists_twist_like_the_primitive(tmp_path, convex):
    """The 40 mm cylinder of test_a_line_resists_the_twist_about_the_jaw_normal as a trimesh STL
    (32 sections, a vertex line on each jaw): a line per jaw, mu F L / 2 = 0.2 N m (before the
    mesh lines: one point per jaw, 0). MuJoCo (pyramid, convex): 0.19994 N m."""
    trimesh = pytest.importorskip("trimesh")
    hand = pg.Hand.builtin("parallel_jaw")
    path = tmp_path / "cylinder.stl"
    trimesh.creation.cylinder(0.015, 0.040, sections=32).export(path)
    pose = np.eye(4)
    pose[:3, :3] = rot([1, 0, 0], -np.pi / 2)
    pose[:3, 3] = [0.0, 0.040, 0.0]
    obj = pg.RigidObject.from_mesh(path, convex=convex, pose=pose)
    q = hand.close_on(obj)
    report = pg.detect_contacts(hand, q, obj)
    assert report.points_per_patch == (2, 2)
    for p in report.patches:
        np.testing.assert_allclose(sorted(p.points[:, 1]), [0.02, 0.06], atol=1e-9)
    m = pg.grasp_model_from_scene(hand, q, obj, mu=MU)
    twist = _twist_limit(m, F / 4, obj.center_of_mass)
    assert twist == pytest.approx(MU * F * 0.040 / 2, rel=1e-6)
    mw = pg.max_resistible_wrench(m, F, "mx", upper=50.0, steps=14)
    assert mw.status == "finite" and mw.magnitude == pytest.approx(twist, abs=50.0 / 2**14 + 1e-4 * twist)
