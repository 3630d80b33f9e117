"""The six real built-in hands (#27): each loads, closes on its built-in scene, has a preload in
equilibrium for every method, answers its named directions and agrees with the simulation.

Numbers asserted here were measured with the scene files as shipped (docs/hands.md, docs/validation.md
"Built-in hands"); the full 24-direction comparison is ``scripts/reproduce/validate_hands.py``.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml
from support.clirun import run

import pinograsp as pg

HANDS = ("allegro_left", "ezgripper", "hey5", "ability", "dex3", "talos_gripper")
CACHE = Path(__file__).resolve().parents[1] / "scripts" / "reproduce" / "validate_hands"

#: Per hand: contacts, joints, actuators, couplings of the scene's model, smallest normal force of
#: the preload alone under the iterative method [N] (a lower bound).
FACTS = {
    "allegro_left": (7, 16, 16, 0, 2.0),
    "ezgripper": (4, 2, 1, 0, 4.0),
    "hey5": (6, 28, 3, 23, 1.5),  # the middle fingertip along the cylinder: a 14 mm line (2 x 1.55 N)
    "ability": (5, 10, 6, 4, 7.0),
    "dex3": (5, 7, 7, 0, 4.0),
    "talos_gripper": (4, 7, 1, 6, 1.0),
}

#: One named direction per hand, a fast method, and the class both it and the simulation give
#: ("holds" up to the scene's upper load, or "gives way"), with the simulated load [N] if finite.
AGREE = {
    "allegro_left": ("into_palm", "prp", "holds", None),
    "ezgripper": ("pull_out", "iterative", "gives way", 5.148),
    "hey5": ("pull_out", "iterative", "gives way", None),
    "ability": ("pull_out", "iterative", "gives way", None),
    "dex3": ("into_palm", "iterative", "holds", None),
    "talos_gripper": ("pull_out", "iterative", "holds", None),
}

#: Named directions where no method matches the simulation's class (docs/hands.md, "When the
#: methods disagree"): every method resists 50 N into the Talos palm; the simulation gives way
#: gradually (onset 15 N) by turning the ball 0.04 rad, its rotation threshold, at 48 N.
NO_METHOD_AGREES = {("talos_gripper", "into_palm")}


def _scene(name: str) -> pg.Scene:
    return pg.load_scene(name)


def _class(status: str) -> str:
    return "holds" if status in ("unbounded", "above_limit", "held") else "gives way"


@pytest.mark.parametrize("name", HANDS)
def test_loads_and_closes_on_its_scene(name):
    hand = pg.Hand.builtin(name)
    scene = _scene(name)
    m = scene.model
    nc, nq, na, ncp, _ = FACTS[name]
    assert (m.nc, m.nq, m.na, m.ncp) == (nc, nq, na, ncp)
    assert name in pg.builtin_scenes() and "into the palm" in pg.builtin_scenes()[name]
    assert set(scene.analysis.directions) == {"into_palm", "pull_out", "sideways"}
    # auto-close stopped inside the joint limits, every contact within the contact tolerance
    q = np.asarray(scene.q)
    assert np.all(q >= hand.lower - 1e-9) and np.all(q <= hand.upper + 1e-9)
    d = pg.detect_contacts(hand, q, scene.object)
    assert sum(d.points_per_patch) == nc and max(abs(c.distance) for c in d.contacts) <= 1e-3


@pytest.mark.parametrize("name", HANDS)
def test_has_a_preload(name):
    """The scene's preload alone is an equilibrium with every contact pressing (iterative), and
    the PRP agrees that it is one."""
    scene = _scene(name)
    it = scene.passive_response(np.zeros(6), method="iterative")
    assert it.status == "resisted" and it.normal_forces.min() >= FACTS[name][4]
    assert scene.passive_response(np.zeros(6), method="prp").status == "resisted"


@pytest.mark.parametrize(
    "name", [pytest.param(n, marks=pytest.mark.slow) if n == "allegro_left" else n for n in HANDS]
)
def test_energetic_finds_the_preload_in_equilibrium(name):
    """The energetic method agrees, or (the 7-contact Allegro, #27 item 4) says it failed: a
    typed status, never a wrong verdict."""
    scene = _scene(name)
    r = scene.passive_response(np.zeros(6), method="energetic")
    assert r.status == "resisted" or (name == "allegro_left" and r.status == "failed")


@pytest.mark.parametrize("name", HANDS)
def test_agrees_with_the_simulation_on_one_named_direction(name):
    scene = _scene(name)
    key, method, cls, load = AGREE[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pg.AuditWarning)
        mw = scene.max_resistible_wrench(key, method=method)
    sim = pg.simulate_max_wrench(scene, key)
    assert _class(mw.status) == _class(sim.status) == cls
    if load is not None:  # the iterative limit within 0.5 % of the simulated give-way load
        assert sim.load == pytest.approx(load, rel=1e-3) and mw.magnitude == pytest.approx(load, rel=5e-3)


def test_talos_motor_balances_both_jaws_through_its_mimics():
    """One motor, six mimic followers (ratio 1 in closing coordinates, so ``C 1 = 0``): the motor
    survives pruning; at the preload alone the double jaw (fingertips 1, 2 and its inner link)
    and the single jaw (fingertip 3) press the ball equally and oppositely, and the motor torque
    is the virtual work of all the contact forces over one unit of linkage motion,
    ``f = 1^T J^T c`` (closed form, since ``1^T C^T = 0`` and ``1^T R = 1``)."""
    scene = _scene("talos_gripper")
    m = scene.model
    assert m.actuator_names == ("gripper",) and m.ncp == 6 and "gripper_left_joint" in m.joint_names
    np.testing.assert_allclose(m.C @ np.ones(m.nq), 0.0, atol=1e-12)
    single = np.array(["fingertip_3" in n or "single" in n for n in m.contact_names])
    assert single.sum() == 1
    for method in ("prp", "iterative"):
        r = scene.passive_response(np.zeros(6), method=method)
        assert r.status == "resisted"
        fw = r.contact_forces_world
        np.testing.assert_allclose(fw[single].sum(axis=0), -fw[~single].sum(axis=0), atol=1e-6)
        assert fw[single, 1].sum() > 5.0  # the single jaw pushes +y, the double jaw -y [N]
        work = np.ones(m.nq) @ (m.J.T @ r.contact_forces.reshape(-1))
        assert r.actuator_forces[0] == pytest.approx(1.0, abs=1e-9) and work == pytest.approx(1.0, abs=1e-9)


def test_talos_use_mimic_switches_the_six_couplings():
    """``use_mimic`` (default true) turns the six URDF mimics into couplings leading from the
    motor; false leaves seven independent joints (the motor then drives its bar alone)."""
    from pinograsp.robots.description import BUILTIN_HANDS, DATA_DIR

    hand = pg.Hand.builtin("talos_gripper")
    assert len(hand.couplings) == 6
    assert all(set(c.weights) == {c.name.split(":")[1], "gripper_left_joint"} for c in hand.couplings)
    assert all(c.weights["gripper_left_joint"] == -1.0 for c in hand.couplings)
    urdf = (
        pg.example_robot_data_dir() / "example-robot-data" / BUILTIN_HANDS["talos_gripper"][0].split(":")[1]
    )
    desc = yaml.safe_load((DATA_DIR / "hands" / "talos_gripper.yaml").read_text())
    free = pg.Hand.from_urdf(urdf, {**desc, "use_mimic": False})
    assert len(free.couplings) == 0 and free.nq == 7


def test_ezgripper_tendon_is_one_differential_actuator():
    hand = pg.Hand.builtin("ezgripper")
    (tendon,) = hand.actuators
    assert tendon.name == "tendon" and set(tendon.transmission.values()) == {0.01}
    assert len(tendon.transmission) == 2


def test_scenes_command_lists_the_hands(capsys):
    code, out, _ = run(capsys, "scenes")
    assert code == 0 and all(name in out for name in HANDS)


@pytest.mark.slow
@pytest.mark.parametrize("name", HANDS)
def test_named_directions_every_method_against_the_cached_validation(name):
    """Every named direction with every method: a MaxWrench or a typed pinograsp error, the same
    class as in the cached validation, and the simulation's class matched by at least one."""
    scene = _scene(name)
    rows = json.loads((CACHE / f"{name}.json").read_text())["rows"]
    for key in scene.analysis.directions:
        (row,) = [r for r in rows if f"({key})" in r["direction"]]
        sim = pg.simulate_max_wrench(scene, key)
        assert sim.status == row["sim"]["status"]
        agreeing = 0
        for method in ("prp", "iterative", "energetic"):
            extra = {"max_nodes": 2000} if method == "energetic" else {}
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", pg.AuditWarning)
                    mw = scene.max_resistible_wrench(key, method=method, **extra)
            except pg.PinograspError as exc:
                assert row[method]["verdict"] == "no verdict", (key, method, exc)
                continue
            assert mw.status == row[method]["status"], (key, method)
            agreeing += _class(mw.status) == _class(sim.status)
        assert agreeing >= (0 if (name, key) in NO_METHOD_AGREES else 1), key


def test_a_hand_mesh_is_a_surface():
    """docs/hands.md "Mesh hands are surfaces": a 10 mm ball centred in the Hey5's palm body is
    20.3 mm from the palm's BVH surface, and touches nothing."""
    hand = pg.Hand.builtin("hey5")
    ball = pg.RigidObject.sphere(0.005, pose=[0.07, -0.005, 0.0])
    q = np.zeros(hand.nq)
    assert pg.link_distances(hand, q, ball)["hand_palm_link"] == pytest.approx(0.0203, abs=2e-4)
    with pytest.raises(pg.NoContactError):
        pg.detect_contacts(hand, q, ball)


def test_a_two_point_pinch_leaves_the_rotation_about_the_chord_free():
    """docs/hands.md "Grasps that leave a free rotation": the EZGripper's fingertips on a 40 mm
    ball touch it at two points on the y axis; nothing resists a torque about that chord."""
    scene = pg.load_scene(
        "ezgripper",
        object={"shape": "sphere", "radius": 0.02, "pose": {"xyz": [0.0, 0.0, -0.14]}},
        expect_contacts=2,
    )
    p = scene.model.points
    assert (
        abs(p[0, 1]) == pytest.approx(0.0201, abs=2e-4) and np.abs(p[:, [0, 2]] - p[0, [0, 2]]).max() < 1e-4
    )
    assert scene.passive_response(np.zeros(6), method="iterative").status == "resisted"
    mw = scene.max_resistible_wrench("my", method="iterative")
    assert mw.status == "below_resolution" and mw.magnitude == 0.0
