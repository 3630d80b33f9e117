"""Grippers of any shape: a prismatic parallel jaw with a mimic coupling (closed forms) and
example-robot-data's one-joint SO-101 (Pinocchio returns its 6x1 frame Jacobian as shape (6,))."""

import warnings

import numpy as np
import pytest

import pinograsp as pg

MU, F, R = 0.5, 20.0, 0.02  # friction, motor force [N], ball radius [m]


@pytest.fixture(scope="module")
def jaw():
    hand = pg.Hand.builtin("parallel_jaw")
    ball = pg.RigidObject.sphere(R, pose=[0.0, 0.04, 0.0])
    q = hand.close_on(ball)
    return hand, q, pg.grasp_model_from_scene(hand, q, ball, mu=MU)


def test_parallel_jaw_model(jaw):
    hand, q, m = jaw
    assert hand.joint_names == ("pj_left", "pj_right") and q[0] == pytest.approx(q[1], abs=1e-12)  # mimic
    assert m.nc == 2 and m.nq == 2 and m.na == 1 and m.C.shape == (1, 2)
    np.testing.assert_allclose(m.C @ [1.0, 1.0], 0.0)  # q_right = q_left
    # prismatic Jacobians: closing the left jaw moves its contact along +x by 1 m per m
    np.testing.assert_allclose(m.frames[0][:, 0], [1, 0, 0], atol=1e-9)
    assert m.J[0, 0] == pytest.approx(1.0) and m.J[0, 1] == 0.0


@pytest.mark.parametrize("method", ["iterative", "prp"])
def test_parallel_jaw_closed_forms(jaw, method):
    """Each jaw presses with F/2 (one motor, a rigid mimic); a load across the jaws (y, z) is
    resisted up to 2 mu F/2 = mu F = 10 N; a torque about y or z up to 2 a mu F/2 (a = contact
    distance from the centre); about the jaws' common normal (x) not at all (point contacts
    have no torsional friction); along x the non-backdrivable motor holds: unbounded."""
    _, _, m = jaw
    a = abs(m.points[0, 0])
    r = pg.passive_response(m, F, np.zeros(6), method)
    np.testing.assert_allclose(r.normal_forces, [F / 2, F / 2], rtol=1e-6)
    upper, steps = 100.0, 14
    res = upper / 2**steps
    slack = res + (2e-3 if method == "iterative" else 1e-6)  # the iterative tolerance eps'
    for d, limit in (("fy", MU * F), ("-fz", MU * F), ("mz", a * MU * F), ("-my", a * MU * F)):
        mw = pg.max_resistible_wrench(m, F, d, method, upper=upper, steps=steps)
        assert mw.status == "finite" and limit - res - 1e-6 <= mw.magnitude <= limit + slack, (
            d,
            mw.magnitude,
        )
    for d in ("fx", "-fx"):
        assert pg.max_resistible_wrench(m, F, d, method, upper=upper, steps=steps).status == "unbounded"
    assert pg.max_resistible_wrench(m, F, "mx", method, upper=upper, steps=steps).status == "below_resolution"


@pytest.fixture(scope="module")
def so101():
    hand = pg.Hand.builtin("so101")
    ball = pg.RigidObject.sphere(0.012, pose=[0.00175, 0.0, -0.08])  # touching the fixed jaw
    q = hand.close_on(ball)
    return hand, q, ball


def test_so101_one_joint_gripper(so101):
    hand, q, ball = so101
    assert hand.nq == 1 and hand.closing_signs.tolist() == [-1.0]
    m = pg.grasp_model_from_scene(hand, q, ball)
    assert m.nc == 2 and m.J.shape == (6, 1)
    assert set(m.contact_names) == {"gripper_link", "moving_jaw_so101_v1_link"}
    fixed = m.contact_names.index("gripper_link")
    assert np.all(m.J[3 * fixed : 3 * fixed + 3] == 0.0)  # the fixed jaw does not move
    # the preload: two contacts in equilibrium push equal and opposite along the line joining
    # them, and the moving jaw's force balances the motor torque (J^T c = f, 1 N·m)
    r = pg.passive_response(m, 1.0, np.zeros(6))
    c = r.contact_forces_world
    np.testing.assert_allclose(c[0], -c[1], atol=1e-9)
    line = m.points[1] - m.points[0]
    assert np.linalg.norm(np.cross(c[0], line)) <= 1e-9 * np.linalg.norm(c[0]) * np.linalg.norm(line)
    np.testing.assert_allclose(r.joint_torques, [1.0], rtol=1e-9)
    np.testing.assert_allclose(r.actuator_forces, [1.0], rtol=1e-9)
    # pushing the ball towards the palm is held by the fingers' passive reaction
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pg.AuditWarning)
        mw = pg.max_resistible_wrench(m, 1.0, "-fz", upper=50, steps=10)
    assert mw.status == "unbounded"


def test_jacobian_of_a_one_joint_hand_matches_finite_differences(so101):
    """The contact Jacobian column equals the finite-difference motion of the contact point on
    the moving jaw when the joint closes (closing sign -1)."""
    import pinocchio as pin

    from pinograsp.robots.grasp import contact_jacobian
    from pinograsp.robots.kinematics import HandConfiguration

    hand, q, _ = so101
    jid = hand.model.getJointId("gripper")
    p = np.array([0.012, 0.0, -0.086])  # a point on the moving jaw [m]
    J = contact_jacobian(hand, q, jid, p)
    assert J.shape == (3, 1)
    local = HandConfiguration.at(hand, q).data.oMi[jid].actInv(p)
    h = 1e-6
    moved = []
    for dq in (h, -h):
        data = hand.model.createData()
        pin.forwardKinematics(hand.model, data, q + hand.closing_signs * dq)
        moved.append(data.oMi[jid].act(local))
    np.testing.assert_allclose(J[:, 0], (moved[0] - moved[1]) / (2 * h), atol=1e-8)
