"""Choosing a preload (pg.equilibrium_preload): closed forms on the pinch, the reasons given
where no preload exists, the hint of PreloadNotInEquilibriumError, the CLI, determinism."""

import json
import warnings

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples
from pinograsp.cli import main


@pytest.mark.parametrize("method", ["iterative", "prp"])
def test_pinch_closed_forms(method):
    """Pinch: arm L = 0.1 m, so a command tau presses its contact with tau / L."""
    m = examples.pinch()
    bal = pg.equilibrium_preload(m, method)
    assert bal.found and bal.command == {"left": 1.0, "right": 1.0}
    np.testing.assert_allclose(bal.normal_forces, [10.0, 10.0], rtol=1e-6)
    np.testing.assert_allclose(bal.response.normal_forces, [10.0, 10.0], rtol=1e-6)
    least = pg.equilibrium_preload(m, method, objective="least_norm", grip=5.0, max_command=2.0)
    assert least.found
    np.testing.assert_allclose(list(least.command.values()), [0.5, 0.5], rtol=1e-6)
    bounded = pg.equilibrium_preload(m, method, max_command={"left": 1.0, "right": 0.3})
    np.testing.assert_allclose(list(bounded.command.values()), [0.3, 0.3], rtol=1e-9)


def test_unbalanced_preload_error_names_the_residual_and_the_way_out():
    """Backdrivable fingers at 1 and 0.5 N·m: the object is pushed by 10 - 5 = 5 N along +x."""
    m = examples.pinch(kind="backdrivable")
    for method in ("quasistatic", "iterative"):  # the default path's held preload, the staged solve
        with pytest.raises(pg.PreloadNotInEquilibriumError, match="equilibrium_preload") as info:
            pg.max_resistible_wrench(m, [1.0, 0.5], "fy", method, upper=20, steps=4)
        np.testing.assert_allclose(info.value.residual, [5.0, 0, 0, 0, 0, 0], atol=1e-9)
        assert "fx=5" in str(info.value)
    with pytest.raises(pg.PreloadNotInEquilibriumError, match="release path") as info:
        pg.loading_path(m, [1.0, 0.5], "fy")
    np.testing.assert_allclose(info.value.residual, [5.0, 0, 0, 0, 0, 0], atol=1e-9)
    assert "net wrench of the contacts on the held object: fx=5" in str(info.value)
    fixed = pg.equilibrium_preload(m)
    assert fixed.found and fixed.command == {"left": 1.0, "right": 1.0}
    mw = pg.max_resistible_wrench(m, fixed.command, "fy", upper=20, steps=10)
    assert abs(mw.magnitude - 2 * 0.5 * 10.0) <= mw.resolution + 2e-3  # 2 mu tau / L


def test_a_lone_contact_cannot_be_pressed():
    left = pg.Contact.revolute(
        [-0.05, 0, 0], [1, 0, 0], {0: ([-0.05, -0.1, 0], [0, 0, -1])}, nq=1, mu=0.5, name="left"
    )
    m = pg.GraspModel.from_contacts([left], planar=True)
    r = pg.equilibrium_preload(m)
    assert r.status == "infeasible" and r.command is None
    assert r.unloadable_contacts == ("left",) and "left" in r.reason


def test_a_finger_that_would_have_to_pull_is_named_and_bidirectional_solves_it():
    """The pinch with the right joint axis reversed: closing needs a negative torque."""
    ez = np.array([0.0, 0.0, 1.0])

    def model(bidirectional):
        cs = [
            pg.Contact.revolute([-0.05, 0, 0], [1, 0, 0], {0: ([-0.05, -0.1, 0], -ez)}, nq=2, name="left"),
            pg.Contact.revolute([0.05, 0, 0], [-1, 0, 0], {1: ([0.05, -0.1, 0], -ez)}, nq=2, name="right"),
        ]
        acts = [
            pg.Actuator({0: 1.0}, name="left"),
            pg.Actuator({1: 1.0}, name="right", bidirectional=bidirectional),
        ]
        return pg.GraspModel.from_contacts(cs, actuators=acts, planar=True, joint_names=("l", "r"))

    r = pg.equilibrium_preload(model(False))
    assert r.status == "infeasible" and r.unbalanced_actuators == ("right",) and "pull" in r.reason
    r = pg.equilibrium_preload(model(True))
    assert r.found and r.command == {"left": 1.0, "right": -1.0}


def test_allegro_without_and_with_its_description():
    """The README's Allegro grasp: with every joint a closing motor (no description) the
    abduction joint 4 and the thumb's joint 13 would have to pull; with the shipped description
    (abduction and thumb rotation locked) a balanced preload exists and analyses run on it, but
    its released state already slides: ``"slides"``, the contacts named, the states those of the
    quasi-static path at zero load."""
    share = pg.example_robot_data_dir()
    urdf = share / "example-robot-data/robots/allegro_hand_description/urdf/allegro_right_hand.urdf"
    ball = pg.RigidObject.sphere(0.04, pose=[0.07, 0.0, 0.03])
    bare = pg.Hand.from_urdf(urdf, package_dirs=[share])
    m = pg.grasp_model_from_scene(bare, bare.close_on(ball, {"joint_12.0": 1.2}), ball, mu=0.5)
    r = pg.equilibrium_preload(m)
    assert r.status == "infeasible" and set(r.unbalanced_actuators) == {"joint_4.0", "joint_13.0"}
    hand = pg.Hand.builtin("allegro_right")
    m = pg.grasp_model_from_scene(hand, hand.close_on(ball, {"joint_12.0": 1.2}), ball, mu=0.5)
    r = pg.equilibrium_preload(m)
    assert r.status == "slides" and not r.found
    assert max(r.command.values()) == 1.0 and r.normal_forces.min() > 1.0
    zero = pg.loading_path(m, r.command, "fx", up_to=0.0)
    assert r.released_states == zero.contact_states[0] == r.response.contact_states
    assert r.sliding_at_zero == tuple(n for n, s in zip(m.contact_names, r.released_states) if s == "sliding")
    assert r.sliding_at_zero and all(n in r.reason for n in r.sliding_at_zero)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pg.AuditWarning)
        mw = pg.max_resistible_wrench(m, r.command, "-fz", upper=20, steps=6)
    assert mw.status in ("finite", "unbounded", "above_limit")


def test_deterministic_and_cli_matches_api(capsys):
    s = pg.load_scene("case1")
    a = pg.equilibrium_preload(s.model)
    b = pg.equilibrium_preload(s.model)
    assert a.command == b.command and np.array_equal(a.normal_forces, b.normal_forces)
    assert main(["preload", "case1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["status"] == "found" and data["preload"] == a.command
    assert data["normal_forces"] == pytest.approx(a.normal_forces.tolist())
    with pytest.raises(pg.InvalidInputError):
        pg.equilibrium_preload(s.model, objective="fair")
    with pytest.raises(pg.UnknownNameError):
        pg.equilibrium_preload(s.model, max_command={"f9": 1.0})


def test_held_still_versus_settled_preload():
    """Unequal commands on the pinch: 10 N vs 5 N on a held object (iterative: no equilibrium);
    a settling object pushes the weaker finger onto its non-backdrivable motor (PRP: 10 N each)."""
    m = examples.pinch()
    it = pg.passive_response(m, [1.0, 0.5], np.zeros(3), "iterative")
    prp = pg.passive_response(m, [1.0, 0.5], np.zeros(3), "prp")
    assert it.status == "not_resisted" and prp.status == "resisted"
    np.testing.assert_allclose(prp.normal_forces, [10.0, 10.0], rtol=1e-9)
    assert prp.actuator_modes == ("moving", "holding")
