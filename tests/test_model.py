"""GraspModel construction: matrices, conventions, validation, pruning."""

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples


def test_pinch_matrices_match_hand_derivation(pinch):
    m = pinch
    assert m.planar and m.nc == 2 and m.nq == 2 and m.na == 2 and m.nb == 4
    # left contact: n = +x, t1 = ez x n = +y; right: n = -x, t1 = -y
    np.testing.assert_allclose(m.frames[0][:, 0], [1, 0, 0])
    np.testing.assert_allclose(m.frames[0][:, 1], [0, 1, 0])
    np.testing.assert_allclose(m.frames[1][:, 1], [0, -1, 0])
    # G columns (fx, fy, mz) of (n, t) per contact; moments about the origin
    G = np.array([[1, 0, -1, 0], [0, 1, 0, -1], [0, -0.05, 0, -0.05]])
    np.testing.assert_allclose(m.G, G, atol=1e-15)
    # closing a finger moves its contact along its normal with moment arm L
    np.testing.assert_allclose(m.J, [[0.1, 0], [0, 0], [0, 0.1], [0, 0]], atol=1e-15)
    np.testing.assert_allclose(m.D[:2, :2], [[1, 1], [0.5, -0.5]])
    assert m.length_scale == pytest.approx(0.05)


def test_grasp_map_is_finite_difference_of_contact_velocity():
    rng = np.random.default_rng(0)
    contacts = []
    for i in range(4):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        contacts.append(
            pg.Contact(rng.normal(size=3), n, mu=0.3, jacobian=rng.normal(size=(3, 3)), name=f"c{i}")
        )
    o = np.array([0.1, -0.2, 0.3])
    m = pg.GraspModel.from_contacts(contacts, reference_point=o)
    # G^T x = contact-frame velocity of the object point at p_i for a small rigid motion x
    x = rng.normal(size=6) * 1e-7
    for i, c in enumerate(contacts):
        R = np.eye(3) + np.array([[0, -x[5], x[4]], [x[5], 0, -x[3]], [-x[4], x[3], 0]])
        moved = R @ (c.point - o) + o + x[:3]
        vel_world = moved - c.point
        np.testing.assert_allclose(m.G[:, 3 * i : 3 * i + 3].T @ x, c.frame.T @ vel_world, atol=1e-13)
        np.testing.assert_allclose(m.J[3 * i : 3 * i + 3], c.frame.T @ c.jacobian, atol=1e-14)
    # edges: unit normal component, edge 0 along t1, inscribed in the cone
    E = pg.friction_edges(0.3, 8)
    np.testing.assert_allclose(E[0], 1.0)
    np.testing.assert_allclose(E[1:, 0], [0.3, 0.0])
    np.testing.assert_allclose(np.linalg.norm(E[1:], axis=0), 0.3)
    Ec = pg.friction_edges(0.3, 8, circumscribed=True)
    np.testing.assert_allclose(np.linalg.norm(Ec[1:], axis=0), 0.3 / np.cos(np.pi / 8))


def test_tangent_frame_is_right_handed():
    c = pg.Contact([0, 0, 0], [0, 0.6, 0.8])
    np.testing.assert_allclose(np.cross(c.tangent, c.t2), c.normal, atol=1e-15)
    assert abs(c.tangent @ c.normal) < 1e-15


def test_pruning_records_what_is_dropped():
    # joints 2 and 3 reach no contact and are coupled only to each other; actuator "idle" drives
    # only joint 2; contact c1 has mu = 0
    j = np.zeros((3, 4))
    j[:, 0] = [0.1, 0, 0]
    j2 = np.zeros((3, 4))
    j2[:, 1] = [-0.1, 0, 0]
    cs = [
        pg.Contact([-0.05, 0, 0], [1, 0, 0], mu=0.5, jacobian=j, name="c0"),
        pg.Contact([0.05, 0, 0], [-1, 0, 0], mu=0.0, jacobian=j2, name="c1"),
    ]
    acts = [
        pg.Actuator({0: 1.0}, name="a0"),
        pg.Actuator({1: 1.0}, name="a1"),
        pg.Actuator({2: 1.0}, name="idle"),
    ]
    cps = [pg.Coupling.follow(3, 2, 0.5, name="k")]
    names = ("j0", "j1", "j2", "j3")
    m = pg.GraspModel.from_contacts(cs, acts, cps, joint_names=names)
    assert m.joint_names == ("j0", "j1") and m.pruned.joints == ("j2", "j3")
    assert m.actuator_names == ("a0", "a1") and m.pruned.actuators == ("idle",)
    assert m.pruned.couplings == ("k",) and m.ncp == 0
    assert m.pruned.tangential == ("c1",)
    assert m.nb == 8 + 1  # 8 edges for c0, the normal alone for c1
    # commands may be given for all actuators (pruned ones dropped) or by name
    np.testing.assert_allclose(m.command_vector([1, 2, 3]), [1, 2])
    np.testing.assert_allclose(m.command_vector({"a1": 4.0}), [0, 4])
    unpruned = pg.GraspModel.from_contacts(cs, acts, cps, joint_names=names, prune=False)
    assert unpruned.nq == 4 and unpruned.nb == 16
    # a solver cannot hold joints that move no contact and are coupled to none that does (j3
    # follows j2 only): a named error, not an AssertionError
    with pytest.raises(pg.ModelError, match="j2, j3.*prune=True") as err:
        pg.passive_response(unpruned, [1, 2, 3], np.zeros(6), method="prp")
    assert err.value.argument == "prune"


def test_pruning_keeps_a_motor_coupled_to_a_touching_joint():
    # issue 27 item 1: "idle" drives j2, whose own link touches nothing, but j2 drives j1 (which
    # touches) through the coupling q1 = 0.5 q2 (a URDF mimic): j2, "idle" and the coupling stay
    j = np.zeros((3, 3))
    j[:, 0] = [0.1, 0, 0]
    j2 = np.zeros((3, 3))
    j2[:, 1] = [-0.1, 0, 0]
    cs = [
        pg.Contact([-0.05, 0, 0], [1, 0, 0], mu=0.5, jacobian=j, name="c0"),
        pg.Contact([0.05, 0, 0], [-1, 0, 0], mu=0.5, jacobian=j2, name="c1"),
    ]
    acts = [
        pg.Actuator({0: 1.0}, kind="backdrivable", name="a0"),
        pg.Actuator({2: 1.0}, kind="backdrivable", name="idle"),
    ]
    m = pg.GraspModel.from_contacts(
        cs, acts, [pg.Coupling.follow(1, 2, 0.5, name="k")], joint_names=("j0", "j1", "j2")
    )
    assert m.joint_names == ("j0", "j1", "j2") and not m.pruned
    assert m.actuator_names == ("a0", "idle") and m.coupling_names == ("k",)
    # closed form (virtual work): a0 at 1 N·m presses c0 with 1 / 0.1 m = 10 N; "idle" moves c1
    # 0.5 * 0.1 m per rad, so tau_idle = 0.5 N·m presses it with 10 N and balances the object
    r = pg.passive_response(m, {"a0": 1.0, "idle": 0.5}, np.zeros(6), "prp")
    assert r.status == "resisted"
    np.testing.assert_allclose(r.normal_forces, [10.0, 10.0], rtol=1e-6)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"normal": [1, 1, 0]}, "unit vector"),
        ({"mu": -0.1}, "mu"),
        ({"stiffness": 0.0}, "stiffness"),
        ({"point": [0, np.nan, 0]}, "NaN"),
        ({"jacobian": np.zeros((2, 3))}, "shape"),
        ({"tangent": [1, 0, 0]}, "orthogonal"),
    ],
)
def test_contact_validation(kwargs, match):
    base = {"point": [0, 0, 0], "normal": [1, 0, 0], "name": "tip"}
    base.update(kwargs)
    with pytest.raises(pg.InvalidInputError, match=match) as err:
        pg.Contact(**base)
    assert "tip" in str(err.value)


def test_model_validation_names_the_culprit():
    c0 = pg.Contact([0, 0, 0], [1, 0, 0], jacobian=np.ones((3, 2)), name="a")
    c1 = pg.Contact([1, 0, 0], [-1, 0, 0], jacobian=np.ones((3, 3)), name="b")
    with pytest.raises(pg.ModelError, match="disagree"):
        pg.GraspModel.from_contacts([c0, c1])
    with pytest.raises(pg.UnknownNameError) as err:
        pg.GraspModel.from_contacts(
            [c0], actuators=[pg.Actuator({"elbow": 1.0}, name="m")], joint_names=("j0", "j1")
        )
    assert err.value.valid == ["j0", "j1"] and "elbow" in str(err.value)
    with pytest.raises(pg.InvalidInputError, match="kind"):
        pg.Actuator({0: 1.0}, kind="springy")
    off_plane = pg.Contact([0, 0, 0.1], [1, 0, 0], jacobian=np.ones((3, 2)) * [[1], [1], [0]], name="lifted")
    with pytest.raises(pg.ModelError, match="lifted"):
        pg.GraspModel.from_contacts([off_plane], planar=True)
    with pytest.raises(pg.ModelError):
        pg.GraspModel.from_contacts([])
    m = examples.pinch()
    with pytest.raises(pg.UnknownNameError, match="valid actuators"):
        m.command_vector({"thumb": 1.0})
    with pytest.raises(pg.InvalidInputError, match="command"):
        m.command_vector([1.0, 2.0, 3.0])
    with pytest.raises(pg.InvalidInputError, match="planar"):
        m.wrench_vector([0, 0, 1, 0, 0, 0])
    with pytest.raises(pg.InvalidInputError, match="NaN"):
        m.wrench_vector([0, np.nan, 0])


def test_model_errors_name_the_argument_at_fault():
    import pinograsp as pg

    contacts = pg.examples.pinch_contacts()
    with pytest.raises(pg.ModelError) as exc:
        pg.GraspModel.from_contacts([])
    assert exc.value.argument == "contacts"
    with pytest.raises(pg.ModelError) as exc:
        pg.GraspModel.from_contacts(contacts, joint_names=("a", "a"))
    assert exc.value.argument == "joint_names"
    tilted = [contacts[0], pg.Contact([0.05, 0.0, 0.01], [-1.0, 0.0, 0.0], jacobian=contacts[1].jacobian)]
    with pytest.raises(pg.ModelError) as exc:
        pg.GraspModel.from_contacts(tilted, planar=True)
    assert exc.value.argument == "planar"
    twins = [pg.Actuator({0: 1.0}, name="m"), pg.Actuator({1: 1.0}, name="m")]
    with pytest.raises(pg.ModelError) as exc:
        pg.GraspModel.from_contacts(contacts, twins)
    assert exc.value.argument == "actuators"
