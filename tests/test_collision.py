"""Coal conventions, objects and hand–object contact detection, against analytic answers."""

from __future__ import annotations

import textwrap
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin
import pytest

import pinograsp as pg
from pinograsp.robots.collision import DEFAULT_TOLERANCE, detect_contacts, link_distances
from pinograsp.robots.objects import RigidObject, coal_transform, pose_matrix


def _coal_distance(g1, p1, g2, p2):
    req = coal.DistanceRequest()
    req.enable_signed_distance = True
    res = coal.DistanceResult()
    T1, T2 = coal_transform(pose_matrix(p1)), coal_transform(pose_matrix(p2))
    d = coal.distance(g1, T1, g2, T2, req, res)
    return d, np.array(res.normal), np.array(res.getNearestPoint1()), np.array(res.getNearestPoint2())


# ----------------------------------------------------------------------------- Coal conventions
def test_coal_normal_points_from_first_to_second_and_depth_is_negative():
    # sphere r = 0.1 at the origin, box of half-size 0.1 centred at x = 0.25: gap 0.05 along +x
    d, n, p1, p2 = _coal_distance(coal.Sphere(0.1), None, coal.Box(0.2, 0.2, 0.2), [0.25, 0, 0])
    assert d == pytest.approx(0.05, abs=1e-9)
    np.testing.assert_allclose(n, [1, 0, 0], atol=1e-9)
    np.testing.assert_allclose(p1, [0.1, 0, 0], atol=1e-9)
    np.testing.assert_allclose(p2, [0.15, 0, 0], atol=1e-9)
    # overlapping by 1 cm: negative distance, same normal direction (first -> second)
    d, n, _, _ = _coal_distance(coal.Sphere(0.1), None, coal.Box(0.2, 0.2, 0.2), [0.19, 0, 0])
    assert d == pytest.approx(-0.01, abs=1e-9)
    np.testing.assert_allclose(n, [1, 0, 0], atol=1e-9)
    # swapping the arguments flips the normal
    d, n, _, _ = _coal_distance(coal.Box(0.2, 0.2, 0.2), [0.19, 0, 0], coal.Sphere(0.1), None)
    assert d == pytest.approx(-0.01, abs=1e-9)
    np.testing.assert_allclose(n, [-1, 0, 0], atol=1e-9)


# ----------------------------------------------------------------------------- objects
def test_pose_as_se3_and_matrix_agree_and_bad_pose_is_rejected():
    R = pin.utils.rotate("z", 0.3)
    se3 = pin.SE3(R, np.array([0.1, 0.2, 0.3]))
    a = RigidObject.box((0.1, 0.2, 0.3), pose=se3)
    b = RigidObject.box((0.1, 0.2, 0.3), pose=se3.homogeneous)
    np.testing.assert_allclose(a.pose, b.pose)
    np.testing.assert_allclose(a.center_of_mass, [0.1, 0.2, 0.3])
    bad = np.eye(4)
    bad[0, 0] = 2.0
    with pytest.raises(pg.InvalidInputError, match="rotation"):
        RigidObject.sphere(0.1, pose=bad)
    with pytest.raises(pg.InvalidInputError, match="radius"):
        RigidObject.sphere(-1.0)


def test_mesh_objects_convex_and_bvh(tmp_path):
    import trimesh

    box = trimesh.creation.box((0.04, 0.06, 0.08))
    box.apply_translation([0.01, 0.0, 0.0])
    f = tmp_path / "box.stl"
    box.export(f)
    hull = RigidObject.from_mesh(f, pose=[0, 0, 0.1])
    assert hull.kind == "convex" and hull.is_solid
    np.testing.assert_allclose(hull.center_of_mass, [0.01, 0, 0.1], atol=1e-9)
    bvh = RigidObject.from_mesh(f, convex=False)
    assert bvh.kind == "mesh" and not bvh.is_solid
    # mm file with scale
    box_mm = trimesh.creation.box((40.0, 60.0, 80.0))
    g = tmp_path / "box_mm.obj"
    box_mm.export(g)
    assert RigidObject.from_mesh(g, scale=1e-3).dimensions["extents"] == pytest.approx((0.04, 0.06, 0.08))
    with pytest.raises(pg.ModelFileError, match="nope.stl"):
        RigidObject.from_mesh(tmp_path / "nope.stl")


# ----------------------------------------------------------------------------- hand contacts
PROBE = textwrap.dedent(
    """\
    <robot name="probe">
      <link name="base"/>
      <link name="slider">
        <collision><origin xyz="0 0 0"/><geometry><sphere radius="0.01"/></geometry></collision>
      </link>
      <link name="bar">
        <collision>
          <origin xyz="0 0 0.05"/><geometry><cylinder radius="0.005" length="0.1"/></geometry>
        </collision>
      </link>
      <joint name="slide" type="prismatic">
        <parent link="base"/><child link="slider"/><axis xyz="1 0 0"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/>
      </joint>
      <joint name="swing" type="revolute">
        <parent link="base"/><child link="bar"/><origin xyz="0 0.3 0"/><axis xyz="0 1 0"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/>
      </joint>
    </robot>
    """
)


@pytest.fixture()
def probe(tmp_path: Path) -> pg.Hand:
    f = tmp_path / "probe.urdf"
    f.write_text(PROBE)
    return pg.Hand.from_urdf(f)


def test_sphere_fingertip_on_box_face(probe):
    # box face at x = 0.05 (box centre 0.1, half size 0.05); fingertip sphere r = 1 cm at x = q
    obj = RigidObject.box(0.1, pose=[0.1, 0.0, 0.0])
    rep = detect_contacts(probe, [0.0395, 0.0], obj, links=["slider"])
    (c,) = rep.contacts
    assert c.link == "slider"
    assert c.distance == pytest.approx(0.0005, abs=1e-9)
    np.testing.assert_allclose(c.normal, [1, 0, 0], atol=1e-9)  # hand -> object
    np.testing.assert_allclose(c.point_hand, [0.0495, 0, 0], atol=1e-9)
    np.testing.assert_allclose(c.point_object, [0.05, 0, 0], atol=1e-9)
    np.testing.assert_allclose(c.point, [0.04975, 0, 0], atol=1e-9)
    # 2 mm away: beyond the default 1 mm tolerance -> no contact, distances listed per link
    with pytest.raises(pg.NoContactError) as exc:
        detect_contacts(probe, [0.038, 0.0], obj, links=["slider"])
    assert exc.value.distances["slider"] == pytest.approx(0.002, abs=1e-9)
    assert "slider: 2.000 mm" in str(exc.value)
    # a rotated box: the normal follows the face
    R = pin.utils.rotate("z", 0.4)
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = R @ [0.06, 0, 0]
    rep = detect_contacts(
        probe,
        [0.0, 0.0],
        RigidObject.box(0.1, pose=T).moved([0.0, 0.0, 0.0]),
        links=["slider"],
        tolerance=0.02,
    )
    np.testing.assert_allclose(rep.contacts[0].normal, R[:, 0], atol=1e-9)
    assert rep.contacts[0].distance == pytest.approx(0.01 - 0.01, abs=1e-9)


def test_cylinder_link_against_cylinder_object(probe):
    # bar: cylinder r = 5 mm along z from the pivot (0, 0.3, 0); object: cylinder r = 2 cm along
    # x, centred at (0, 0.3, 0.05) shifted in +y by 0.0255: gap 0.0005 along +y
    R = pin.utils.rotate("y", np.pi / 2)  # object axis along x
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = [0.0, 0.3 + 0.0255, 0.05]
    obj = RigidObject.cylinder(0.02, 0.2, pose=T)
    rep = detect_contacts(probe, [0.5, 0.0], obj)
    (c,) = rep.contacts
    assert c.link == "bar"
    assert c.distance == pytest.approx(0.0005, abs=2e-6)  # GJK on curved shapes: ~1e-6 m
    np.testing.assert_allclose(c.normal, [0, 1, 0], atol=1e-4)
    np.testing.assert_allclose(c.point_object[1:], [0.3055, 0.05], atol=1e-5)
    # every link's closest distance is reported
    d = link_distances(probe, [0.5, 0.0], obj)
    assert set(d) == {"slider", "bar"}
    assert d["bar"] == pytest.approx(0.0005, abs=2e-6)


def test_penetration_is_reported_with_depths(probe):
    obj = RigidObject.box(0.1, pose=[0.1, 0.0, 0.0])
    rep = detect_contacts(probe, [0.043, 0.0], obj, links=["slider"])  # 3 mm deep: accepted
    assert rep.contacts[0].distance == pytest.approx(-0.003, abs=1e-9)
    with pytest.raises(pg.PenetrationError) as exc:
        detect_contacts(probe, [0.05, 0.0], obj, links=["slider"])  # 1 cm deep
    assert exc.value.depths["slider"] == pytest.approx(-0.01, abs=1e-9)
    assert "slider" in str(exc.value)


def test_unknown_link_and_bad_configuration(probe):
    obj = RigidObject.sphere(0.01, pose=[1.0, 0, 0])
    with pytest.raises(pg.UnknownNameError) as exc:
        detect_contacts(probe, [0.0, 0.0], obj, links=["nope"])
    assert exc.value.valid == ["slider", "bar"]
    with pytest.raises(pg.InvalidInputError, match="expected 2 joint values"):
        detect_contacts(probe, [0.0, 0.0, 0.0], obj)
    with pytest.raises(pg.InvalidInputError, match="NaN"):
        detect_contacts(probe, [np.nan, 0.0], obj)
    assert DEFAULT_TOLERANCE == 1e-3
