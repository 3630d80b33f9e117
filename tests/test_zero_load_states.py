"""The quasi-static method's states at zero load are those of the preloaded state itself (not
"separated" for want of a load segment), in the path record, the response, and the pictures.

Closed forms and cross-checks:

* pinch (commands 1 N·m, arms 0.1 m): both contacts press with 10 N and no tangential force:
  sticking, as on every load path's first segment;
* case 1 and case 2: the zero-load states equal the states of the first segment of the load
  paths along every named axis (the paths' states just after 0+), and a contact is
  ``"separated"`` exactly where its normal force is 0 and ``"sticking"`` where it is strictly
  inside its friction polygon (friction use < 1);
* :func:`slipping_grasp` (three fingers; the right contact's normal tilted 0.3 rad, friction
  0.2, so its release needs friction from the left contacts; the top one has 0.05): the
  release slides the top contact to its friction limit, ``|c_t| = 0.05 c_n``, where the
  preload leaves it: ``"sliding"`` at zero load.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import Actuator, GraspModel, examples
from pinograsp.core.examples import EZ, _finger_contact
from pinograsp.viz.scene_elements import scene_elements

AXES = ("fx", "-fx", "fy", "-fy", "mz", "-mz")


def slipping_grasp() -> GraspModel:
    """Three single-joint fingers (arms 0.1 m, stiffness 1 N/m): ``top`` and ``bottom`` at
    ``(-0.05, ±0.02)`` pressing along +x (friction 0.05 and 0.8), ``right`` at ``(0.05, 0)``
    with its normal tilted 0.3 rad towards +y (friction 0.2)."""
    t = 0.3
    top = _finger_contact([-0.05, 0.02, 0], [1, 0, 0], 0.1, 0, 3, -EZ, mu=0.05, stiffness=1.0, name="top")
    bot = _finger_contact([-0.05, -0.02, 0], [1, 0, 0], 0.1, 1, 3, -EZ, mu=0.8, stiffness=1.0, name="bottom")
    n = [-math.cos(t), math.sin(t), 0.0]
    right = _finger_contact([0.05, 0, 0], n, 0.1, 2, 3, EZ, mu=0.2, stiffness=1.0, name="right")
    names = ("top", "bottom", "right")
    acts = [Actuator({i: 1.0}, name=nm) for i, nm in enumerate(names)]
    return GraspModel.from_contacts([top, bot, right], actuators=acts, planar=True, joint_names=names)


#: The preload :func:`pinograsp.equilibrium_preload` designs for :func:`slipping_grasp` [N·m].
SLIPPING_COMMAND = {"top": 0.757415, "bottom": 0.242585, "right": 1.0}


def _cases():
    out = [("pinch", examples.pinch(), {"left": 1.0, "right": 1.0})]
    for name in ("case1", "case2"):
        scene = pg.load_scene(name)
        out.append((name, scene.model, dict(scene.command)))
    return out


@pytest.mark.parametrize("name,model,command", _cases(), ids=lambda v: v if isinstance(v, str) else "")
def test_zero_load_states_are_the_preloaded_states(name, model, command):
    zero = pg.loading_path(model, command, "fx", up_to=0.0)
    assert zero.segments == 0 and len(zero.contact_states) == 1
    states = zero.contact_states[0]
    for axis in AXES:  # just after 0+: the first segment of every load path
        assert pg.loading_path(model, command, axis).contact_states[0] == states, axis
    resp = pg.passive_response(model, command, np.zeros(6))
    assert resp.method == "quasistatic" and resp.contact_states == states
    assert resp.contact_modes == tuple("separated" if s == "separated" else "touching" for s in states)
    cn = resp.normal_forces
    use = resp.friction_use
    for i, s in enumerate(states):  # the states read off the forces
        if s == "separated":
            assert cn[i] == 0.0
        else:
            assert s == "sticking" and cn[i] > 0 and use[i] < 1.0 - 1e-6
    assert "separated" not in states or name == "case2"
    if name != "case2":
        assert states == ("sticking",) * model.nc
        assert zero.actuator_modes[0] == ("holding",) * model.na


def test_pinch_zero_load_forces_and_title():
    m = examples.pinch()
    resp = pg.passive_response(m, {"left": 1.0, "right": 1.0}, np.zeros(6))
    np.testing.assert_allclose(resp.normal_forces, [10.0, 10.0], rtol=1e-12)
    assert resp.contact_states == ("sticking", "sticking")
    assert scene_elements(m, resp).title == "2 contacts — resisted: 2 sticking"


def test_released_to_the_friction_limit_is_sliding_at_zero_load():
    m = slipping_grasp()
    zero = pg.loading_path(m, SLIPPING_COMMAND, "fx", up_to=0.0)
    assert zero.contact_states[0] == ("sliding", "sticking", "sticking")
    c = zero.contact_forces[0]
    assert abs(c[0, 1]) == pytest.approx(0.05 * c[0, 0], rel=1e-9)  # top on its friction limit
    assert len(zero.sliding_faces[0][0]) == 1 and zero.sliding_faces[0][1:] == ((), ())
    # a load that pushes the top contact on along its limit slides it from 0+
    assert pg.loading_path(m, SLIPPING_COMMAND, "fy").contact_states[0][0] == "sliding"
    resp = pg.passive_response(m, SLIPPING_COMMAND, np.zeros(6))
    assert scene_elements(m, resp).title == "3 contacts — resisted: 2 sticking, 1 sliding"


def test_designed_preload_that_slides_is_not_found():
    """``equilibrium_preload`` designs :data:`SLIPPING_COMMAND` (the design is feasible: the
    bottom contact's friction 0.8 can carry the right contact's tilt), but the release, which
    shares the tangential load by stiffness, slides the top contact to its limit: "slides"."""
    m = slipping_grasp()
    r = pg.equilibrium_preload(m)
    assert r.status == "slides" and not r.found
    assert r.command == pytest.approx(SLIPPING_COMMAND, abs=1e-6)
    zero = pg.loading_path(m, r.command, "fx", up_to=0.0)
    assert r.released_states == zero.contact_states[0] == ("sliding", "sticking", "sticking")
    assert r.sliding_at_zero == ("top",) and r.separated_at_zero == ()
    assert "['top'] slide on their friction limit" in r.reason
    assert 0.0 < r.released_motion < 1.0  # sliding, not a large motion
    d = r.to_dict()
    assert d["status"] == "slides" and d["sliding_at_zero"] == ["top"]
    assert d["released_states"] == ["sliding", "sticking", "sticking"]


def test_pinch_preload_is_found_all_sticking_without_motion():
    r = pg.equilibrium_preload(examples.pinch())
    assert r.found and r.released_states == ("sticking", "sticking")
    assert r.released_motion == pytest.approx(0.0, abs=1e-12)  # symmetric: nothing to release
    assert r.sliding_at_zero == r.separated_at_zero == ()
