"""URDF scene -> GraspModel: Jacobians against finite differences, and against a hand-built model."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import pinograsp as pg
from pinograsp.robots.grasp import contact_jacobian, scene_contacts
from pinograsp.robots.kinematics import HandConfiguration


def _fd_jacobian(
    hand: pg.Hand, q: np.ndarray, joint_id: int, point: np.ndarray, eps: float = 1e-6
) -> np.ndarray:
    """Central differences of the hand point's position under closing joint motion, (3, nq)."""
    p_local = HandConfiguration.at(hand, q).data.oMi[joint_id].actInv(point)  # the point, fixed on the link
    out = np.zeros((3, hand.nq))
    for j in range(hand.nq):
        dq = np.zeros(hand.nq)
        dq[j] = hand.closing_signs[j] * eps  # +eps of closing motion
        plus = HandConfiguration.at(hand, q + dq).data.oMi[joint_id].act(p_local)
        minus = HandConfiguration.at(hand, q - dq).data.oMi[joint_id].act(p_local)
        out[:, j] = (plus - minus) / (2 * eps)
    return out


@pytest.mark.parametrize(
    "name", ["barrett_bh8_282", "underactuated_2f", "allegro_right", "panda_hand", "parallel_jaw", "so101"]
)
def test_contact_jacobian_matches_finite_differences(name):
    hand = pg.Hand.builtin(name)
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(3):
        q = hand.lower + rng.uniform(0.1, 0.9, hand.nq) * (hand.upper - hand.lower)
        config = HandConfiguration.at(hand, q)
        for go in hand.geometry.geometryObjects:
            if go.parentJoint == 0:
                continue
            # a point near the geometry, expressed in the base frame
            point = config.geometry_data.oMg[hand.geometry.getGeometryId(go.name)].act(rng.normal(0, 0.01, 3))
            J = contact_jacobian(hand, q, go.parentJoint, point)
            J_fd = _fd_jacobian(hand, q, go.parentJoint, point)
            worst = max(worst, np.abs(J - J_fd).max())
    assert worst < 1e-8


# ----------------------------------------------------------------------------- planar pinch
A, L, R_TIP = 0.03, 0.08, 0.01  # half-width of the object, joint-to-contact height, fingertip radius [m]


def _pinch_urdf(flip_right: bool) -> str:
    """Two single-link fingers; pivots at (-+A, -L); sphere tips touching the object at (-+A, 0)."""
    axis_r = "0 0 -1" if flip_right else "0 0 1"
    return textwrap.dedent(
        f"""\
        <robot name="pinch">
          <link name="palm"/>
          <link name="left"><collision><origin xyz="{-R_TIP} {L} 0"/><geometry><sphere radius="{R_TIP}"/>
          </geometry></collision></link>
          <link name="right"><collision><origin xyz="{R_TIP} {L} 0"/><geometry><sphere radius="{R_TIP}"/>
          </geometry></collision></link>
          <joint name="jl" type="revolute"><parent link="palm"/><child link="left"/>
            <origin xyz="{-A} {-L} 0"/><axis xyz="0 0 -1"/>
            <limit lower="-1" upper="1" effort="1" velocity="1"/>
          </joint>
          <joint name="jr" type="revolute"><parent link="palm"/><child link="right"/>
            <origin xyz="{A} {-L} 0"/><axis xyz="{axis_r}"/>
            <limit lower="-1" upper="1" effort="1" velocity="1"/>
          </joint>
        </robot>
        """
    )


@pytest.mark.parametrize("flip_right", [False, True])
def test_planar_urdf_grasp_equals_hand_built_model(tmp_path: Path, flip_right: bool):
    f = tmp_path / "pinch.urdf"
    f.write_text(_pinch_urdf(flip_right))
    desc = {
        "closing": {"jr": -1} if flip_right else {},
        "actuators": [{"name": "diff", "transmission": {"jl": 1.0, "jr": 1.0}}],
    }
    hand = pg.Hand.from_urdf(f, desc)
    obj = pg.RigidObject.box((2 * A, 0.05, 0.02))
    for planar in (True, False):
        urdf_model = pg.grasp_model_from_scene(hand, [0.0, 0.0], obj, mu=0.4, planar=planar)
        contacts = [
            pg.Contact.revolute(
                [-A, 0, 0], [1, 0, 0], {0: ([-A, -L, 0], [0, 0, -1])}, nq=2, mu=0.4, name="left"
            ),
            pg.Contact.revolute(
                [A, 0, 0], [-1, 0, 0], {1: ([A, -L, 0], [0, 0, 1])}, nq=2, mu=0.4, name="right"
            ),
        ]
        ref = pg.GraspModel.from_contacts(
            contacts,
            [pg.Actuator({"jl": 1.0, "jr": 1.0}, name="diff")],
            planar=planar,
            joint_names=["jl", "jr"],
        )
        for attr in ("G", "J", "D", "R", "C", "k", "mu", "points", "frames", "reference_point"):
            np.testing.assert_allclose(
                getattr(urdf_model, attr), getattr(ref, attr), atol=1e-12, err_msg=attr
            )
        assert urdf_model.contact_names == ref.contact_names
        assert urdf_model.kinds == ref.kinds
    # the analytic pinch (docs/analytic_cases.md): closing moves each contact along its normal with arm L
    np.testing.assert_allclose(urdf_model.J[[0, 3]], [[L, 0], [0, L]], atol=1e-12)


def test_scene_model_couplings_reference_point_and_per_link_mu():
    hand = pg.Hand.builtin("panda_hand")
    box = pg.RigidObject.box((0.03, 0.03, 0.03), pose=[0.002, 0.0, 0.105])
    q = hand.close_on(box)
    gm = pg.grasp_model_from_scene(hand, q, box, mu={"panda_leftfinger": 0.3}, patches=False)
    np.testing.assert_allclose(gm.reference_point, [0.002, 0, 0.105])
    np.testing.assert_allclose(gm.mu, [0.3, 0.5])
    assert gm.contact_names == ("panda_leftfinger", "panda_rightfinger")
    np.testing.assert_allclose(gm.C, [[-1.0, 1.0]])  # mimic coupling in closing coordinates
    np.testing.assert_allclose(gm.R, [[1.0], [0.0]])
    # normals from the hand into the object; closing moves each pad along its normal at 1 m/m
    np.testing.assert_allclose(gm.frames[:, :, 0], [[0, -1, 0], [0, 1, 0]], atol=1e-9)
    np.testing.assert_allclose(gm.J[[0, 3]], np.eye(2), atol=1e-12)


def test_barrett_scene_prunes_and_keeps_couplings():
    hand = pg.Hand.builtin("barrett_bh8_282")
    obj = pg.RigidObject.box((0.05, 0.06, 0.08), pose=[0.0, 0.0, 0.045])
    q = hand.close_on(obj)
    contacts, report = scene_contacts(hand, q, obj, patches=False)  # one point per link
    assert [c.name for c in contacts] == ["bh_finger_13_link", "bh_finger_23_link", "bh_finger_33_link"]
    for c in contacts:  # the normal points from the finger into the object: towards the object's centre
        assert np.dot(c.normal, obj.center_of_mass - c.point) > 0
    gm = pg.grasp_model_from_scene(hand, q, obj, patches=False)
    assert gm.actuator_names == ("spread", "f1", "f2", "f3")
    assert set(gm.coupling_names) == {"mimic:bh_j21", "f1_distal", "f2_distal", "f3_distal"}


def test_no_contact_error_lists_distances_per_link():
    hand = pg.Hand.builtin("underactuated_2f")
    far = pg.RigidObject.sphere(0.01, pose=pin.SE3(np.eye(3), np.array([0.0, 0.3, 0.0])))
    with pytest.raises(pg.NoContactError) as exc:
        pg.grasp_model_from_scene(hand, [0.0] * 4, far)
    assert set(exc.value.distances) == {
        "uf_palm",
        "uf_proximal_1",
        "uf_distal_1",
        "uf_proximal_2",
        "uf_distal_2",
    }
    assert exc.value.distances["uf_palm"] == pytest.approx(0.29, abs=1e-9)
    with pytest.raises(pg.InvalidInputError, match="expected 4 joint values"):
        pg.grasp_model_from_scene(hand, [0.0] * 3, far)


def test_planar_urdf_pinch_resists_the_analytic_load(tmp_path: Path):
    """The URDF pinch gives the same answer as the hand-built one: F_max = 2 mu tau0 / (L |sin θ|)."""
    if not pg.available_miqp_solvers():
        pytest.skip("no MIQP solver installed")
    f = tmp_path / "pinch.urdf"
    f.write_text(_pinch_urdf(False))
    hand = pg.Hand.from_urdf(f)  # default description: direct drive on jl and jr
    m = pg.grasp_model_from_scene(
        hand, [0.0, 0.0], pg.RigidObject.box((2 * A, 0.05, 0.02)), mu=0.4, planar=True
    )
    theta = np.pi / 4
    res = pg.max_resistible_wrench(m, [1.0, 1.0], [np.cos(theta), np.sin(theta), 0.0])
    assert res.magnitude == pytest.approx(2 * 0.4 * 1.0 / (L * np.sin(theta)), rel=1e-3)


def test_mismatched_configuration_length_names_the_joints():
    import numpy as np
    import pytest

    import pinograsp as pg

    hand = pg.Hand.builtin("underactuated_2f")
    with pytest.raises(pg.InvalidInputError, match="expected 4 joint values") as err:
        pg.grasp_model_from_scene(hand, np.zeros(3), pg.RigidObject.box([0.04, 0.04, 0.04]))
    assert "uf_j11" in str(err.value)


def test_urdf_collision_mesh_triangles_are_bounded(monkeypatch):
    """Issue 33: meshes referenced from a URDF have a triangle limit, as object meshes do
    (``MAX_MESH_TRIANGLES``); the error names the mesh, its triangles and what to do."""
    from pinograsp.robots import urdf

    monkeypatch.setattr(urdf, "MAX_MESH_TRIANGLES", 10)
    with pytest.raises(pg.UrdfError, match=r"triangles, more than 10 \(MAX_MESH_TRIANGLES\): decimate"):
        pg.Hand.builtin("ezgripper")
    monkeypatch.undo()
    assert pg.Hand.builtin("ezgripper").nq > 0  # within the limit: loads
