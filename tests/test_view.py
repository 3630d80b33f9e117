"""Scene view before contact (closing arrows, distances), the upright view, and check_closing."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

import pinograsp as pg
from pinograsp.robots.collision import link_distances
from pinograsp.robots.hand import DATA_DIR
from pinograsp.robots.kinematics import HandConfiguration
from pinograsp.viz import figures, view3d, viewer
from pinograsp.viz.scene_elements import scene_elements
from pinograsp.viz.scene_mpl import scene_axes

plt = figures.pyplot()
UF_URDF = DATA_DIR / "urdf" / "underactuated_2f.urdf"


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def uf() -> pg.Hand:
    return pg.Hand.builtin("underactuated_2f")


@pytest.fixture(scope="module")
def uf_box() -> pg.RigidObject:
    return pg.RigidObject.box((0.05, 0.05, 0.02), pose=[0.0, 0.07, 0.0])  # between the open fingers


def so101(sign: int) -> pg.Hand:
    urdf = pg.example_robot_data_dir() / "example-robot-data/robots/so_arm_description/urdf/so101.urdf"
    desc = {"joints": ["gripper"], "base_link": "gripper_link", "closing": {"gripper": sign}}
    return pg.Hand.from_urdf(urdf, desc)


SO_Q = [0.8]  # jaw open [rad]
SO_BALL = pg.RigidObject.sphere(0.01, pose=[0.03, 0.0, -0.07])  # between the jaws


def screen_direction(ax, origin, vector) -> np.ndarray:
    """Unit 2D screen direction of a 3D vector drawn at origin (projected with the Axes' camera)."""
    from mpl_toolkits.mplot3d import proj3d

    ax.figure.canvas.draw()
    M = ax.get_proj()
    a = np.array(proj3d.proj_transform(*origin, M)[:2])
    b = np.array(proj3d.proj_transform(*(np.asarray(origin) + vector), M)[:2])
    d = b - a
    return d / np.linalg.norm(d)


# ----------------------------------------------------------------------------- before contact
def test_png_and_figure_without_contact_draw_closing_arrows(uf, uf_box, tmp_path):
    assert min(link_distances(uf, uf.q_open, uf_box).values()) > 5e-3  # nothing touches
    path = viewer.save_png(None, hand=uf, obj=uf_box, path=tmp_path / "open.png")
    assert path.is_file() and path.stat().st_size > 5000
    ax = scene_axes(None, hand=uf, q=uf.q_open, obj=uf_box)
    arrows = [c for c in ax.collections if str(c.get_gid()).startswith(view3d.GID_CLOSING)]
    assert sorted(c.get_gid() for c in arrows) == sorted(view3d.GID_CLOSING + j for j in uf.joint_names)
    labels = [t for t in ax.texts if t.get_gid() == view3d.GID_DISTANCE]
    assert len(labels) == 3
    assert "no contact" in ax.get_title()
    pytest.importorskip("plotly")
    fig = viewer.scene_figure(None, hand=uf, obj=uf_box)  # q defaults to the open configuration
    closing = [t for t in fig.data if t.legendgroup == view3d.CLOSING_GROUP]
    assert len(closing) == uf.nq == 4
    assert {"hand", "object", "closest distances"} <= {t.name for t in fig.data}
    assert viewer.save_html(fig, tmp_path / "open.html").stat().st_size > 1000


def test_closing_arrows_point_towards_the_object_and_match_finite_differences(uf, uf_box):
    el = scene_elements(None, hand=uf, q=uf.q_open, obj=uf_box)
    assert [a.joint for a in el.closing] == list(uf.joint_names)
    for a in el.closing:
        assert a.approach > 0  # right signs: every joint moves its link towards the box
        # velocity = finite difference of the link-fixed point [m/rad]
        j, h = uf.joint_index(a.joint), 1e-6
        k = next(i for i, g in enumerate(uf.geometry.geometryObjects) if uf.link_of_geometry(i) == a.link)
        local = HandConfiguration.at(uf, uf.q_open).geometry_data.oMg[k].actInv(a.point)
        q1 = np.array(uf.q_open)
        q1[j] += uf.closing_signs[j] * h
        fd = (HandConfiguration.at(uf, q1).geometry_data.oMg[k].act(local) - a.point) / h
        np.testing.assert_allclose(a.velocity, fd, atol=1e-6)


def test_reported_distances_equal_link_distances(uf, uf_box):
    q = [0.2, 0.1, 0.3, 0.0]
    el = scene_elements(None, hand=uf, q=q, obj=uf_box)
    expected = link_distances(uf, q, uf_box)
    assert el.link_distances.keys() == expected.keys()
    for k, v in expected.items():
        assert el.link_distances[k] == pytest.approx(v, abs=1e-12)
    nearest = sorted(expected, key=expected.get)[:3]
    for ln in nearest:
        assert f"{ln} {1e3 * expected[ln]:.1f} mm" in el.title
    ax = scene_axes(None, hand=uf, q=q, obj=uf_box)
    texts = {t.get_text().strip() for t in ax.texts if t.get_gid() == view3d.GID_DISTANCE}
    assert texts == {f"{ln}: {1e3 * expected[ln]:.1f} mm" for ln in nearest}


def test_without_model_bad_input(uf, uf_box):
    with pytest.raises(pg.InvalidInputError, match="model=None needs"):
        scene_elements(None)
    with pytest.raises(pg.InvalidInputError, match="response"):
        scene_elements(None, np.zeros((1, 3)), hand=uf, obj=uf_box)
    with pytest.raises(pg.InvalidInputError, match="show_distances"):
        scene_axes(None, hand=uf, obj=uf_box, show_distances=-1)


# ----------------------------------------------------------------------------- upright view
def test_upright_view_puts_the_hand_up_axis_up():
    case1 = pg.load_scene("case1")
    el = scene_elements(case1)
    v = el.view
    # analysis frame: Y = hand z (palm normal, towards the object)
    assert v.vertical_axis == "y" and v.roll == 0.0 and v.elev > 0
    ax = scene_axes(case1)
    assert (ax.elev, ax.azim, ax.roll) == (v.elev, v.azim, v.roll)
    centre = np.asarray(case1.model.reference_point)
    up = screen_direction(ax, centre, np.array([0.0, 0.05, 0.0]))
    assert up[1] > 0.95  # the palm normal points up on the page
    # the camera is on the object's side of the palm: the object is nearer than the palm
    palm = np.zeros(3)
    assert (centre - palm) @ v.eye > 0
    # SO-101: the jaws point along -z of gripper_link -> -z up (roll 180°)
    hand = so101(-1)
    ax = scene_axes(None, hand=hand, q=SO_Q, obj=SO_BALL)
    assert ax.roll == 180.0 and ax.elev < 0
    up = screen_direction(ax, SO_BALL.center_of_mass, np.array([0.0, 0.0, -0.05]))
    assert up[1] > 0.95
    # explicit angles still win
    ax = scene_axes(case1, elev=10, azim=20)
    assert (ax.elev, ax.azim) == (10, 20)


def test_upright_view_avoids_occluders():
    # hand points on the -x side of the object hide it from cameras on that side
    pts = np.array([[-0.1, 0.0, 0.05], [-0.1, 0.01, 0.05], [-0.1, -0.01, 0.05]])
    v = view3d.upright_view(np.array([0.0, 0.0, 1.0]), pts, np.array([0.0, 0.0, 0.05]), 0.03)
    assert v.vertical_axis == "z" and v.eye[0] > 0


# ----------------------------------------------------------------------------- check_closing
def test_check_closing_underactuated_right_signs(uf, uf_box):
    r = pg.check_closing(uf, uf_box)
    assert isinstance(r, pg.ClosingCheck) and r.ok and r.wrong == ()
    assert [j.verdict for j in r.joints] == ["closes"] * 4
    assert all(j.change < 0 and j.distance_after < j.distance_before for j in r.joints)
    assert r.suggested_closing == {j: 1 for j in uf.joint_names}
    d = r.to_dict()
    assert d["ok"] is True and len(d["joints"]) == 4 and d["joints"][0]["verdict"] == "closes"
    assert "sign ok" in str(r) and str(r) == r.summary()
    with pytest.raises(dataclasses_frozen()):
        r.ok = False  # type: ignore[misc]


def dataclasses_frozen():
    import dataclasses

    return dataclasses.FrozenInstanceError


def test_check_closing_flags_a_flipped_sign(uf_box):
    desc = yaml.safe_load(UF_URDF.with_suffix(".yaml").read_text())
    desc["closing"] = {"uf_j12": -1}
    hand = pg.Hand.from_urdf(UF_URDF, desc)
    r = pg.check_closing(hand, uf_box)
    assert not r.ok and r.wrong == ("uf_j12",)
    assert r["uf_j12"].verdict == "opens" and r["uf_j12"].sign_ok is False
    assert r["uf_j12"].suggested_sign == 1 and r.suggested_closing["uf_j12"] == 1
    assert "closing: {uf_j12: 1}" in r.summary()
    assert r["uf_j11"].verdict == "closes"
    with pytest.raises(pg.UnknownNameError):
        r["nope"]


def test_check_closing_so101_gripper_sign():
    right = pg.check_closing(so101(-1), SO_BALL, SO_Q)
    assert right.ok and right["gripper"].verdict == "closes"
    assert right["gripper"].link == "moving_jaw_so101_v1_link"
    wrong = pg.check_closing(so101(+1), SO_BALL, SO_Q)
    assert wrong.wrong == ("gripper",) and wrong.suggested_closing == {"gripper": -1}
    assert "closing: {gripper: -1}" in str(wrong)
    # distances in the report are pg.link_distances
    assert right.link_distances == pytest.approx(link_distances(so101(-1), SO_Q, SO_BALL))


def test_check_closing_mimic_followers_and_locked_joints_have_their_documented_verdicts():
    # docs/hands.md "Check my description": every verdict the report can print is in its table
    from pathlib import Path

    jaw = pg.check_closing(
        pg.Hand.builtin("parallel_jaw"), pg.RigidObject.box([0.03, 0.04, 0.05], pose=[0, 0.04, 0])
    )
    assert [j.verdict for j in jaw.joints] == ["closes", "follows"] and jaw.ok
    allegro = pg.check_closing(
        pg.Hand.builtin("allegro_right"), pg.RigidObject.sphere(0.04, pose=[0.07, 0, 0.03])
    )
    locked = [j.joint for j in allegro.joints if j.verdict == "locked"]
    assert locked == ["joint_0.0", "joint_12.0", "joint_4.0", "joint_8.0"]  # abduction, thumb rotation
    table = (Path(__file__).resolve().parents[1] / "docs" / "hands.md").read_text()
    from pinograsp.robots.closing import VERDICTS

    assert all(f'| `"{v}"` |' in table for v in VERDICTS)


def test_check_closing_no_effect_and_bad_input(uf, uf_box):
    # a box far out along the finger axis: the step moves the closest points sideways
    far = pg.RigidObject.sphere(0.005, pose=[0.0, 0.0, 0.5])
    r = pg.check_closing(uf, far, threshold=0.5)
    assert all(j.verdict == "no effect" and j.sign_ok is None for j in r.joints)
    assert r.ok
    with pytest.raises(pg.InvalidInputError, match="step"):
        pg.check_closing(uf, uf_box, step=0.0)
    with pytest.raises(pg.InvalidInputError, match="threshold"):
        pg.check_closing(uf, uf_box, threshold=1.5)
    with pytest.raises(pg.InvalidInputError, match="obj"):
        pg.check_closing(uf, "box")
    with pytest.raises(pg.InvalidInputError, match="hand"):
        pg.check_closing("hand", uf_box)


def test_a_style_record_draws_what_the_loose_keywords_draw(pinch):
    """``style=pg.SceneStyle(...)`` is one value for the keywords scene_figure and scene_axes
    forward (issue #24): the same segments, arrows and title; both at once is an error."""
    r = pg.passive_response(pinch, 1.0, [0.0, 5.0, 0.0], method="prp")
    style = pg.SceneStyle(cone_scale=0.02, force_scale=0.001, show_cones=False, title="pinch")
    a = scene_elements(pinch, r, style=style)
    loose = pg.scene_figure(pinch, r, cone_scale=0.02, force_scale=0.001, show_cones=False, title="pinch")
    fig = pg.scene_figure(pinch, r, style=style)
    assert [t.name for t in fig.data] == [t.name for t in loose.data]
    assert fig.layout.title.text == loose.layout.title.text == "pinch"
    normals = next(sg for sg in a.segments if sg.name == "contact normals")
    np.testing.assert_allclose(np.linalg.norm(normals.segments[:, 1] - normals.segments[:, 0], axis=1), 0.02)
    assert not any(m.name == "friction cones" for m in a.meshes)
    ax = scene_axes(pinch, r, style=style)
    assert ax.get_title() == "pinch"
    with pytest.raises(pg.InvalidInputError, match="not both"):
        pg.scene_figure(pinch, r, style=style, show_cones=True)
    with pytest.raises(pg.InvalidInputError, match="cone_scale"):
        pg.SceneStyle(cone_scale=-1.0)
