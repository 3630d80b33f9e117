"""Hands from URDF: descriptions, reduced models, mimic couplings, auto-close, errors."""

from __future__ import annotations

import filecmp
from pathlib import Path

import numpy as np
import pytest

import pinograsp as pg
from pinograsp.robots.collision import DEFAULT_TOLERANCE, link_distances
from pinograsp.robots.description import DATA_DIR
from pinograsp.robots.kinematics import HandConfiguration

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def barrett() -> pg.Hand:
    return pg.Hand.builtin("barrett_bh8_282")


@pytest.fixture(scope="module")
def panda() -> pg.Hand:
    return pg.Hand.builtin("panda_hand")


def test_shipped_urdfs_are_the_package_data():
    for name in ("barrett_bh8_282", "underactuated_2f"):
        for ext in ("urdf", "yaml"):
            assert filecmp.cmp(
                REPO / "urdf" / f"{name}.{ext}", DATA_DIR / "urdf" / f"{name}.{ext}", shallow=False
            )
    # loading from the top-level folder picks up the YAML next to the URDF
    hand = pg.Hand.from_urdf(REPO / "urdf" / "underactuated_2f.urdf")
    assert hand.actuator_names == ("proximal_tendon", "distal_tendon")


def test_barrett_description(barrett):
    assert barrett.joint_names == (
        "bh_j11",
        "bh_j12",
        "bh_j13",
        "bh_j21",
        "bh_j22",
        "bh_j23",
        "bh_j32",
        "bh_j33",
    )
    np.testing.assert_allclose(barrett.upper[[1, 2]], np.radians([140, 48]))
    assert {a.name: a.kind for a in barrett.actuators} == {
        "spread": "locked",
        "f1": "non-backdrivable",
        "f2": "non-backdrivable",
        "f3": "non-backdrivable",
    }
    C = barrett.coupling_matrix()
    assert C.shape == (4, 8)
    np.testing.assert_allclose(C[0], [-1, 0, 0, 1, 0, 0, 0, 0])  # URDF mimic: bh_j21 = bh_j11
    np.testing.assert_allclose(C[1], [0, -1 / 3, 1, 0, 0, 0, 0, 0])  # distal at 1/3 of proximal
    # closing moves the flexion joints (distal at 1/3), never the locked spread
    np.testing.assert_allclose(barrett.closing_direction(), [0, 1, 1 / 3, 0, 1, 1 / 3, 1, 1 / 3])
    # geometry facts: flexion axes 50 mm from the spread axes at x = +-25 mm; finger 3 opposite
    hand = barrett
    oMi = HandConfiguration.at(hand, np.zeros(8)).data.oMi
    np.testing.assert_allclose(
        oMi[hand.model.getJointId("bh_j12")].translation, [0.025, -0.05, 0], atol=1e-12
    )
    np.testing.assert_allclose(
        oMi[hand.model.getJointId("bh_j22")].translation, [-0.025, -0.05, 0], atol=1e-12
    )
    np.testing.assert_allclose(oMi[hand.model.getJointId("bh_j32")].translation, [0, 0.05, 0], atol=1e-12)
    # spread 90 deg: fingers 1 and 2 face each other across x, symmetrically
    oMi = HandConfiguration.at(hand, [np.pi / 2, 0, 0, np.pi / 2, 0, 0, 0, 0]).data.oMi
    np.testing.assert_allclose(oMi[hand.model.getJointId("bh_j12")].translation, [0.075, 0, 0], atol=1e-12)
    np.testing.assert_allclose(oMi[hand.model.getJointId("bh_j22")].translation, [-0.075, 0, 0], atol=1e-12)


def test_panda_reduced_to_hand_joints_with_mimic_coupling(panda):
    assert panda.joint_names == ("panda_finger_joint1", "panda_finger_joint2")
    assert panda.model.nq == 2
    np.testing.assert_allclose(panda.closing_signs, [-1, -1])
    # mimic q2 = q1 in URDF coordinates -> closing coordinates: qc2 = (-1)(1)(-1) qc1
    (cp,) = panda.couplings
    assert cp.weights == {"panda_finger_joint2": 1.0, "panda_finger_joint1": -1.0}
    assert panda.actuator_names == ("gripper",)
    # world frame = panda_hand: fingers slide along +-y at z = 58.4 mm whatever the arm pose
    oMi = HandConfiguration.at(panda, [0.04, 0.04]).data.oMi
    np.testing.assert_allclose(oMi[1].translation, [0, 0.04, 0.0584], atol=1e-9)
    np.testing.assert_allclose(oMi[2].translation, [0, -0.04, 0.0584], atol=1e-9)
    # only hand links carry contact geometry (arm links reduced away and filtered out)
    assert panda.contact_link_names == ("panda_hand", "panda_leftfinger", "panda_rightfinger")


def test_allegro_default_description_loads_from_example_robot_data():
    share = pg.example_robot_data_dir()
    urdf = share / "example-robot-data/robots/allegro_hand_description/urdf/allegro_right_hand.urdf"
    hand = pg.Hand.from_urdf(urdf, package_dirs=[share])
    assert hand.nq == 16
    assert all(a.kind == "non-backdrivable" and len(a.transmission) == 1 for a in hand.actuators)
    np.testing.assert_allclose(hand.closing_signs, np.ones(16))
    assert not hand.couplings


def test_unknown_names_list_the_valid_ones(tmp_path):
    urdf = DATA_DIR / "urdf" / "underactuated_2f.urdf"
    with pytest.raises(pg.UnknownNameError) as exc:
        pg.Hand.from_urdf(urdf, {"closing": {"uf_j99": -1}})
    assert exc.value.kind == "joint" and exc.value.name == "uf_j99"
    assert exc.value.valid == ["uf_j11", "uf_j12", "uf_j21", "uf_j22"]
    with pytest.raises(pg.UnknownNameError, match="uf_j11"):
        pg.Hand.from_urdf(urdf, {"actuators": [{"name": "t", "transmission": {"nope": 1.0}}]})
    with pytest.raises(pg.UnknownNameError) as exc:
        pg.Hand.from_urdf(urdf, {"contact_links": ["uf_thumb"]})
    assert exc.value.kind == "link" and "uf_distal_1" in exc.value.valid
    with pytest.raises(pg.UnknownNameError, match="proximal_tendon"):
        pg.Hand.from_urdf(urdf, {**_yaml(urdf), "commands": {"nope": 1.0}})
    with pytest.raises(pg.UnknownNameError, match="hand description key"):
        pg.Hand.from_urdf(urdf, {"closeing": {}})
    with pytest.raises(pg.UnknownNameError, match="barrett_bh8_282"):
        pg.Hand.builtin("shadow")
    bad = tmp_path / "bad.yaml"
    bad.write_text("closing: {uf_j11: 2}\n")
    with pytest.raises(pg.ModelFileError, match="bad.yaml"):
        pg.Hand.from_urdf(urdf, bad)


def test_a_description_yaml_anywhere_is_the_dict_it_holds(tmp_path):
    # docs/hands.md: the description may be a YAML path away from the URDF (an installed package)
    urdf = DATA_DIR / "urdf" / "underactuated_2f.urdf"
    mine = tmp_path / "my_hand.yaml"
    mine.write_text(urdf.with_suffix(".yaml").read_text())
    a, b = pg.Hand.from_urdf(urdf, str(mine)), pg.Hand.from_urdf(urdf, _yaml(urdf))
    assert a.joint_names == b.joint_names and a.closing_signs.tolist() == b.closing_signs.tolist()
    assert [(x.name, x.kind, x.transmission) for x in a.actuators] == [
        (x.name, x.kind, x.transmission) for x in b.actuators
    ]


def _yaml(urdf: Path) -> dict:
    import yaml

    return yaml.safe_load(urdf.with_suffix(".yaml").read_text())


def test_malformed_urdf_and_missing_mesh_name_the_file(tmp_path):
    bad = tmp_path / "broken.urdf"
    bad.write_text('<robot name="x"><link name="a"></robot>')
    with pytest.raises(pg.UrdfError) as exc:
        pg.Hand.from_urdf(bad)
    assert exc.value.path == str(bad) and "malformed XML" in str(exc.value)
    nomesh = tmp_path / "nomesh.urdf"
    nomesh.write_text(
        '<robot name="x"><link name="a"><collision><geometry><mesh filename="ghost_finger.stl"/>'
        '</geometry></collision></link><link name="b"/><joint name="j" type="revolute"><parent link="a"/>'
        '<child link="b"/><axis xyz="0 0 1"/><limit lower="0" upper="1" effort="1" velocity="1"/>'
        "</joint></robot>"
    )
    with pytest.raises(pg.UrdfError) as exc:
        pg.Hand.from_urdf(nomesh)
    assert "nomesh.urdf" in str(exc.value) and "ghost_finger.stl" in str(exc.value)
    with pytest.raises(pg.UrdfError, match="not found"):
        pg.Hand.from_urdf(tmp_path / "absent.urdf")


def test_configuration_validation(barrett):
    with pytest.raises(pg.InvalidInputError, match="expected 8 joint values"):
        barrett.configuration([0.0, 0.0])
    q = barrett.configuration({"bh_j12": 1.0})
    assert q[1] == 1.0 and q[0] == 0.0
    with pytest.raises(pg.UnknownNameError):
        barrett.configuration({"bh_j99": 1.0})


def test_auto_close_barrett_touches_on_every_finger(barrett):
    obj = pg.RigidObject.box((0.05, 0.06, 0.08), pose=[0.0, 0.0, 0.045])
    q = barrett.close_on(obj)
    d = link_distances(barrett, q, obj)
    for finger in ("1", "2", "3"):
        touching = min(d[f"bh_finger_{finger}2_link"], d[f"bh_finger_{finger}3_link"])
        assert abs(touching) <= DEFAULT_TOLERANCE / 2 + 1e-12
    # couplings and limits respected: distal = proximal / 3, spread unchanged (locked)
    np.testing.assert_allclose(barrett.coupling_matrix() @ (q * barrett.closing_signs), 0, atol=1e-12)
    assert q[0] == 0.0 and np.all(q >= barrett.lower) and np.all(q <= barrett.upper)
    # symmetric scene -> symmetric fingers
    assert q[1] == pytest.approx(q[4]) and q[1] == pytest.approx(q[6])
    gm = pg.grasp_model_from_scene(barrett, q, obj, patches=False)  # one point per fingertip
    assert gm.nc == 3


def test_auto_close_raises_no_contact_when_nothing_is_reached(barrett):
    far = pg.RigidObject.sphere(0.01, pose=[0.0, 0.0, 0.5])
    with pytest.raises(pg.NoContactError) as err:
        barrett.close_on(far)
    # the error carries each link's closest distance [m] at the joint limits; the sphere is ~0.4 m away
    distances = err.value.distances
    assert set(distances) >= {"bh_finger_13_link", "bh_finger_23_link", "bh_finger_33_link"}
    assert min(distances.values()) > 0.2


def test_auto_close_underactuated_and_panda(panda):
    hand = pg.Hand.builtin("underactuated_2f")
    obj = pg.RigidObject.box((0.05, 0.05, 0.02), pose=[0.0, 0.07, 0.0])
    q = hand.close_on(obj)
    d = link_distances(hand, q, obj)
    assert min(d["uf_proximal_1"], d["uf_distal_1"]) == pytest.approx(0.0, abs=DEFAULT_TOLERANCE / 2)
    assert min(d["uf_proximal_2"], d["uf_distal_2"]) == pytest.approx(0.0, abs=DEFAULT_TOLERANCE / 2)
    box = pg.RigidObject.box((0.03, 0.03, 0.03), pose=[0.0, 0.0, 0.105])
    q = panda.close_on(box)
    assert q[0] == pytest.approx(q[1])  # mimic respected
    assert q[0] == pytest.approx(0.015, abs=DEFAULT_TOLERANCE / 2)  # finger pad meets the box face
