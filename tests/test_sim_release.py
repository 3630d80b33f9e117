"""The simulation's release of a held object (``release_time``, docs/simulation.md) against the
loading path's release stage, on the grasp where the two first disagreed: issue 34's Ability
hand × box, plan 5 (docs/planning.md, "Acceptance"), stored as its GraspModel arrays in
``tests/data/ability_box_plan5.json`` (built from the plan's cached spec).

Its frictionless held closing leaves a holding wrench of ~16 N. Released at once (the default),
the object jumps, the fingers overshoot and their ratchets keep it: the preloaded normal forces
end up to 11 % above the path's, and the grasp gives way at 41-44 N along -fx+fy-fz; released
over 0.05 s, the preload is the path's to 1 % and the grasp holds the acceptance's 45 N.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support.grasps import stored_grasp

import pinograsp as pg

DATA = Path(__file__).parent / "data" / "ability_box_plan5.json"
DIRECTION = np.array([-1.0, 1.0, -1.0, 0.0, 0.0, 0.0]) / np.sqrt(3.0)


@pytest.fixture(scope="module")
def grasp() -> tuple[pg.GraspModel, dict[str, float]]:
    return stored_grasp(DATA)


def _preloaded_normal_forces(
    model: pg.GraspModel, command: dict[str, float], release_time: float
) -> np.ndarray:
    """The simulated preload's normal forces (nc,) [N] (pyramid friction, the acceptance's upper)."""
    from pinograsp.sim.integrator import Engine, preload
    from pinograsp.sim.simulate import _options

    opts = _options(model, DIRECTION, 45.0, {"friction": "pyramid", "release_time": release_time})
    run = Engine(model, model.command_vector(command), opts)
    preload(run)
    d, red = run.data, run.red
    anchors = run.law.anchors.copy()
    f, _, _ = run.law.forces(
        d.qpos[red.hand_qpos],
        d.qvel[red.hand_dof],
        d.qpos[:3] - run.rest[:3],
        run.rot,
        d.qvel[:3],
        run.rot @ d.qvel[3:6],
    )
    run.law.anchors = anchors
    return np.einsum("ij,ij->i", f, run.law.normals)


def test_the_fixture_is_the_plans_grasp(grasp):
    model, command = grasp
    assert (model.nc, model.nq, model.na) == (6, 10, 6)
    mw = pg.max_resistible_wrench(model, command, DIRECTION, upper=100)
    assert mw.status == "finite" and mw.magnitude == pytest.approx(66.323, abs=0.01)  # the path's limit


def test_a_gradual_release_gives_the_paths_preload(grasp):
    pytest.importorskip("mujoco")
    model, command = grasp
    path = pg.loading_path(model, command, DIRECTION, up_to=1e-9).contact_forces[0][:, 0]
    gradual = _preloaded_normal_forces(model, command, 0.05)
    at_once = _preloaded_normal_forces(model, command, 0.0)
    np.testing.assert_allclose(gradual, path, rtol=0.01)  # measured: within 0.5 %
    assert np.max(at_once / path - 1.0) > 0.05  # measured: +7.8 % thumb base, +11 % ring


@pytest.mark.parametrize("bad", [-0.1, 1e6, 10.5, "0.05", float("nan"), float("inf"), None, True])
def test_a_bad_release_time_names_the_option_its_range_and_the_choice(grasp, bad):
    pytest.importorskip("mujoco")
    model, command = grasp
    with pytest.raises(pg.InvalidInputError) as err:
        pg.simulate_max_wrench(model, DIRECTION, command, upper=45.0, release_time=bad)
    assert err.value.name == "release_time"
    text = str(err.value)
    assert "[0, 10]" in text and "seconds" in text  # the valid range and its unit, for any bad value
    assert "pass 0 (the default)" in text and "0.05" in text  # what to do instead
    assert repr(bad) in text


@pytest.mark.parametrize("edge", [0, 10])
def test_release_time_range_ends_are_accepted(edge):
    from pinograsp.sim.simulate import _release_time

    assert _release_time(edge) == float(edge)


@pytest.mark.slow
def test_released_gradually_the_plan_holds_its_acceptance_load(grasp):
    pytest.importorskip("mujoco")
    model, command = grasp
    kw = {"upper": 45.0, "friction": "pyramid", "ramp_time": 0.3}
    assert pg.simulate_max_wrench(model, DIRECTION, command, release_time=0.05, **kw).status == "held"
    at_once = pg.simulate_max_wrench(model, DIRECTION, command, **kw)
    assert at_once.status != "held" and at_once.load < 45.0  # measured: 43.8 N
