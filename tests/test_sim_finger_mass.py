"""The simulation's finger mass (``finger_mass``, docs/simulation.md, "Finger mass") on the grasp
where it decides the answer: issue 34's Ability hand × box, plan 5 along -fz (docs/planning.md,
"Acceptance"), stored in ``tests/data/ability_box_plan5_fz.json``.

The loading path reaches its first limit at 40.49 N, snaps 15 µm onto a soft branch and gives
way at 61.11 N. The simulation follows the path to the micrometre up to the limit; past it the
object jumps, and the fingers that follow it must accelerate: at the default finger mass (each
finger as heavy as the object at its contacts) their contacts unload, friction falls and the
grasp gives way at the limit (40.46 N); with fingers ten times lighter it lands and gives way
where the path says.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support.grasps import stored_grasp

import pinograsp as pg

DATA = Path(__file__).parent / "data" / "ability_box_plan5_fz.json"
MINUS_FZ = np.array([0.0, 0.0, -1.0, 0.0, 0.0, 0.0])
#: The simulation of this grasp: the model's pyramid, a 0.1 s ramp, the held object released as
#: the path releases it (docs/simulation.md).
SIM = {"friction": "pyramid", "ramp_time": 0.1, "release_time": 0.05}


@pytest.fixture(scope="module")
def grasp() -> tuple[pg.GraspModel, dict[str, float]]:
    return stored_grasp(DATA)


def test_the_paths_answer_follows_a_snap_onto_a_soft_branch(grasp):
    model, command = grasp
    mw = pg.max_resistible_wrench(model, command, MINUS_FZ, upper=70.0)
    assert mw.status == "finite" and mw.magnitude == pytest.approx(61.108, abs=0.01)
    assert mw.giveway.first_limit == pytest.approx(40.495, abs=0.01)
    assert len(mw.giveway.snaps) == 1


def test_the_finger_mass_scales_every_hand_joints_armature(grasp):
    pytest.importorskip("mujoco")
    from pinograsp.sim.integrator import Engine
    from pinograsp.sim.simulate import _options

    model, command = grasp
    armature = {}
    for ratio in (1.0, 0.25):
        opts = _options(model, MINUS_FZ, 70.0, {**SIM, "finger_mass": ratio})
        run = Engine(model, model.command_vector(command), opts)
        armature[ratio] = run.red.model.dof_armature[run.red.hand_dof].copy()
    assert len(armature[1.0]) == model.nq and (armature[1.0] > 0).all()
    np.testing.assert_allclose(armature[0.25], 0.25 * armature[1.0], rtol=1e-15)


def test_light_fingers_land_the_snap_and_give_way_where_the_path_says(grasp):
    pytest.importorskip("mujoco")
    model, command = grasp
    light = pg.simulate_max_wrench(model, MINUS_FZ, command, upper=70.0, finger_mass=0.1, **SIM)
    assert light.status in ("gave_way", "gradual")
    assert light.load == pytest.approx(61.108, rel=0.01)  # measured: 61.14 N (+0.05 %)


@pytest.mark.slow
def test_at_the_default_finger_mass_the_snap_does_not_land(grasp):
    pytest.importorskip("mujoco")
    model, command = grasp
    heavy = pg.simulate_max_wrench(model, MINUS_FZ, command, upper=45.0, **SIM)
    assert heavy.status in ("gave_way", "gradual")
    assert heavy.load == pytest.approx(40.495, rel=0.01)  # measured: 40.50 N


def test_the_damping_refers_to_the_lighter_body(grasp):
    """Each contact's damping ``2 zeta sqrt(k m)`` takes ``m`` the lighter of the object and a
    finger: ``sqrt(finger_mass)`` times the object's below 1, the object's at and above it."""
    pytest.importorskip("mujoco")
    from pinograsp.sim.integrator import Engine
    from pinograsp.sim.simulate import _options

    model, command = grasp
    b = {}
    for ratio in (3.0, 1.0, 0.25):
        opts = _options(model, MINUS_FZ, 70.0, {**SIM, "finger_mass": ratio})
        b[ratio] = Engine(model, model.command_vector(command), opts).law.b
    assert np.array_equal(b[3.0], b[1.0])
    np.testing.assert_allclose(b[0.25], 0.5 * b[1.0], rtol=1e-15)
    np.testing.assert_allclose(
        b[1.0], 2 * 0.7 * np.sqrt(opts.stiffness * model.k / model.k.max() * opts.mass)
    )


def test_light_fingers_hold_where_heavy_ones_do(grasp):
    """Damped as the object, fingers ten times lighter vibrated (the contact wrench along the
    load swung between 9 and 20 N at loads below 1 mN) and the grasp "gave way" along +fz at
    0.79 N; it holds to 45 N, as at the default finger mass (docs/simulation.md, "Finger mass")."""
    pytest.importorskip("mujoco")
    model, command = grasp
    plus_fz = -MINUS_FZ
    for ratio in (0.1, 1.0):
        r = pg.simulate_max_wrench(model, plus_fz, command, upper=45.0, finger_mass=ratio)
        assert r.status == "held" and r.load is None, (ratio, r.summary())
        early = slice(0, len(r.trace.applied) // 10)  # the ramp's first loads, below 1 N
        swing = np.abs(np.asarray(r.trace.resisted) - np.asarray(r.trace.applied))[early]
        assert swing.max() < 0.05, (ratio, swing.max())  # it swung between 9 and 20 N


@pytest.mark.parametrize("bad", [0.05, 1e3, -1.0, "1", float("nan"), None, True])
def test_a_bad_finger_mass_names_the_option_its_range_and_the_choice(grasp, bad):
    pytest.importorskip("mujoco")
    model, command = grasp
    with pytest.raises(pg.InvalidInputError) as err:
        pg.simulate_max_wrench(model, MINUS_FZ, command, upper=45.0, finger_mass=bad)
    assert err.value.name == "finger_mass"
    text = str(err.value)
    assert "[0.1, 100]" in text and "pass 1 (the default)" in text and repr(bad) in text


def test_the_result_records_the_finger_mass_release_and_friction_it_ran_with(capsys):
    """A user comparing runs reads the options back from the result, its JSON and the CLI text."""
    pytest.importorskip("mujoco")
    from pinograsp.cli import main

    scene = pg.load_scene("pinch")
    r = pg.simulate_max_wrench(scene, "fy", finger_mass=0.5, release_time=0.05, friction="pyramid")
    assert (r.finger_mass, r.release_time, r.friction) == (0.5, 0.05, "pyramid")
    assert r.load == pytest.approx(10.0, rel=0.01)  # 2 mu tau0 / L: the pinch closes balanced
    d = r.to_dict()
    assert (d["finger_mass"], d["release_time"], d["friction"]) == (0.5, 0.05, "pyramid")
    default = pg.simulate_max_wrench(scene, "fy")
    assert (default.finger_mass, default.release_time, default.friction) == (1.0, 0.0, "cone")
    assert main(["simulate", "pinch", "-d", "fy", "--finger-mass", "0.5", "--release-time", "0.05"]) == 0
    text = capsys.readouterr().out
    assert "held preload released over 0.05 s, finger mass 0.5 x the object's 0.2 kg" in text
    assert "cone friction" in text
