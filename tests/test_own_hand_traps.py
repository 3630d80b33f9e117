"""Issue 33, own-hand traps: inputs a new user gives a hand the package does not ship."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import pinograsp as pg


def _talos(**changes: object) -> pg.Hand:
    base = pg.Hand.builtin("talos_gripper")
    desc = dataclasses.replace(base.description, **changes)
    return pg.Hand.from_urdf(base.urdf_path, desc)


def test_open_configuration_of_a_mimic_leader_opens_its_followers():
    """``open_configuration: {gripper_left_joint: -0.5}`` (the Talos motor, six URDF mimics):
    every follower sits at ``multiplier * -0.5 + offset`` of its tag, not at 0 (before: the
    followers stayed closed at 0 while the motor was opened)."""
    hand = _talos(open_configuration={"gripper_left_joint": -0.5})
    lead = hand.joint_names.index("gripper_left_joint")
    assert hand.q_open[lead] == -0.5
    assert len(hand.mimics) == 6
    for m in hand.mimics:
        f = hand.joint_names.index(m.follower)
        want = np.clip(m.multiplier * -0.5 + m.offset, hand.lower[f], hand.upper[f])
        assert hand.q_open[f] == pytest.approx(want, abs=1e-15)
        assert abs(hand.q_open[f]) > 0.1  # opened with the leader
    # a follower given explicitly keeps its own value
    hand2 = _talos(open_configuration={"gripper_left_joint": -0.5, "gripper_left_inner_double_joint": -0.25})
    assert hand2.q_open[hand2.joint_names.index("gripper_left_inner_double_joint")] == -0.25
    # the default (the leader at 0) is unchanged: every joint at 0 within its limits
    closed = np.clip(0.0, hand.lower, hand.upper)
    np.testing.assert_array_equal(pg.Hand.builtin("talos_gripper").q_open, closed)


def test_no_preload_row_shows_the_contacts_detected():
    """A sampled Barrett grasp (seed 0, the third) touches the box but no preload balances it:
    its ``no_preload`` row gives the contact count of its grasp model (before: 0)."""
    from pinograsp.batch.grasps import grasp_configuration
    from pinograsp.robots.grasp import grasp_model_from_scene

    box = pg.ObjectSpec("box", size=(0.1462, 0.05, 0.10), xyz=(0.0, 0.0, 0.0678))  # test_batch.BOX
    spec = pg.sample_grasps("barrett_bh8_282", box, 3, seed=0, q_open={"bh_j11": np.pi / 2})[2]
    df = pg.evaluate_grasps([spec], score=pg.WorstAxisScore(upper=20, steps=4), workers=1)
    assert df.loc[0, "reason"] == "no_preload"
    hand, obj, q = grasp_configuration(spec)
    model = grasp_model_from_scene(hand, q, obj, mu=spec.mu, stiffness=spec.stiffness, patches=False)
    assert model.nc > 0 and df.loc[0, "n_contacts"] == model.nc


def test_rigid_mimic_group_stopped_by_one_touch_warns_with_the_way_out():
    """Issue 33: a URDF mimic hand (one motor, its followers rigidly coupled) auto-closes as one
    rigid body: one link touches, no preload can squeeze the object, and nothing pointed to the
    description that works. Exact input: the TIAGo Pro left gripper (example-robot-data; one
    motor, five mimic followers) on a 15 mm ball 20 mm off its centre line."""
    import warnings

    from scripts.reproduce.ownhands.__main__ import _object, load_hand

    hand = load_hand("tiago_pro_left")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        q = hand.close_on(_object("ball", 0.015, np.array([0.0, 0.02, 0.13])))
        centred = hand.close_on(_object("ball", 0.015, np.array([0.0, 0.0, 0.13])))
    ours = [str(w.message) for w in caught if issubclass(w.category, pg.PinograspWarning)]
    assert len(ours) == 1 and "gripper_left_fingertip_right_link touched: 1 of their" in ours[0]
    assert "Tendon and underactuated fingers" in ours[0]
    rep = pg.detect_contacts(hand, q, _object("ball", 0.015, np.array([0.0, 0.02, 0.13])))
    assert [c.link for c in rep.contacts] == ["gripper_left_fingertip_right_link"]
    two = pg.detect_contacts(hand, centred, _object("ball", 0.015, np.array([0.0, 0.0, 0.13])))
    assert len(two.contacts) == 2  # centred: both fingertips touch, no warning
