"""Traps a new user fell into on example-robot-data hands the package does not ship (issue 27).

Each test uses the exact input that triggered the bug and asserts numbers.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

import pinograsp as pg

TALOS_JOINTS = [
    "gripper_left_joint",
    "gripper_left_inner_double_joint",
    "gripper_left_fingertip_1_joint",
    "gripper_left_fingertip_2_joint",
    "gripper_left_motor_single_joint",
    "gripper_left_inner_single_joint",
    "gripper_left_fingertip_3_joint",
]


def robots_dir():
    return pg.example_robot_data_dir() / "example-robot-data" / "robots"


@functools.lru_cache(maxsize=None)
def talos_gripper() -> pg.Hand:
    """Talos' left gripper: one motor, ``gripper_left_joint``, drives six ``<mimic>`` joints."""
    return pg.Hand.from_urdf(
        robots_dir() / "talos_data/robots/talos_full_v2.urdf",
        {
            "joints": TALOS_JOINTS,
            "base_link": "gripper_left_base_link",
            "closing": {"gripper_left_joint": -1, "gripper_left_inner_double_joint": -1},
        },
        package_dirs=[pg.example_robot_data_dir()],
    )


def talos_model(y: float = 0.0) -> pg.GraspModel:
    box = pg.RigidObject.box((0.1, 0.03, 0.02), pose=[0.0, y, -0.135])
    hand = talos_gripper()
    return pg.grasp_model_from_scene(hand, hand.close_on(box), box, mu=0.5)


# ------------------------------------------------------------------ 1. pruning keeps the motor
def test_talos_motor_survives_pruning_and_balances_both_jaws():
    # before: "3 contacts, 5 joints, 0 actuators, 0 couplings" (the motor's link touches nothing)
    m = talos_model()
    assert m.contact_names == (
        "gripper_left_fingertip_1_link",
        "gripper_left_fingertip_2_link",
        "gripper_left_fingertip_3_link",
    )
    assert m.nq == 7 and m.actuator_names == ("gripper_left_joint",) and m.ncp == 6
    assert not m.pruned
    # the motor's own link moves no contact: its Jacobian column is zero
    assert not np.any(m.J[:, m.joint_names.index("gripper_left_joint")])
    choice = pg.equilibrium_preload(m)
    assert choice.status == "found" and choice.command == {"gripper_left_joint": 1.0}
    r = pg.passive_response(m, choice.command, np.zeros(6))
    assert r.status == "resisted"
    # closed form 1: both jaws press equally (the double jaw's two tips against the single one)
    cn = np.asarray(r.normal_forces)
    np.testing.assert_allclose(cn[0] + cn[1], cn[2], rtol=1e-6)
    assert cn[2] > 1.0
    # closed form 2 (virtual work): with every mimic ratio +1 in closing coordinates, the motor
    # torque equals the contact forces' work along the common closing motion (all joints +1)
    e = np.ones(m.nq)
    c = np.concatenate([np.asarray(f) for f in r.contact_forces])
    np.testing.assert_allclose(e @ (m.J.T @ c), 1.0, rtol=1e-6)


def test_talos_one_jaw_touching_has_no_preload_and_says_why():
    # before: raw TypeError "ufunc 'bitwise_and' not supported" (0 actuators after pruning)
    m = talos_model(-0.001)
    assert m.contact_names == ("gripper_left_fingertip_3_link",)
    assert m.actuator_names == ("gripper_left_joint",)
    choice = pg.equilibrium_preload(m)
    assert choice.status == "infeasible" and choice.command is None
    assert choice.unloadable_contacts == ("gripper_left_fingertip_3_link",)


def test_preload_of_a_model_without_actuators_is_an_answer():
    # before: raw TypeError from analysis/preload.py (empty float arrays combined with '&')
    box = pg.RigidObject.box((0.1, 0.03, 0.02), pose=[0.0, 0.0, -0.135])
    hand = talos_gripper()
    m = pg.grasp_model_from_scene(hand, hand.close_on(box), box, mu=0.5, actuators=[])
    assert m.na == 0
    assert pg.equilibrium_preload(m).status == "infeasible"


# ------------------------------------------------------ 3. energetic "finite" at upper
@pytest.mark.parametrize("backend", ["bnb", "miqp"])
def test_energetic_limit_at_upper_is_not_finite(pinch, backend):
    # before: backend="miqp" gave +fx "finite 49.99994 N" at upper=50 (the bound binding within
    # the MIQP gap) and +fy "finite 4.99997 N" at upper=5; the PRP says unbounded / above_limit
    cmd = {"left": 1.0, "right": 1.0}
    r = pg.max_resistible_wrench(pinch, cmd, "fx", "energetic", upper=50, backend=backend)
    assert r.status == "unbounded" and r.magnitude == float("inf")
    r = pg.max_resistible_wrench(pinch, cmd, "fy", "energetic", upper=5, backend=backend)
    assert r.status == "above_limit" and r.magnitude == 5.0
    # a finite limit well inside the bound is untouched: F = 2 mu f / L = 10 N
    r = pg.max_resistible_wrench(pinch, cmd, "fy", "energetic", upper=50, backend=backend)
    assert r.status == "finite" and abs(r.magnitude - 10.0) < 1e-5
