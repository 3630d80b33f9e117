"""Bad input gives pinograsp errors naming the culprit."""

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples


def test_preload_not_in_equilibrium():
    """One finger pushing an object that nothing holds: no equilibrium at w = 0."""
    c = pg.Contact.revolute(
        [0.05, 0, 0], [-1, 0, 0], {0: ([0.05, -0.1, 0], [0, 0, 1])}, nq=1, mu=0.5, name="lonely"
    )
    m = pg.GraspModel.from_contacts([c], planar=True)
    for method in ("prp", "iterative"):
        with pytest.raises(pg.PreloadNotInEquilibriumError, match="preload not in equilibrium"):
            pg.max_resistible_wrench(m, 1.0, "fy", method=method)
        r = pg.passive_response(m, 1.0, [0, 0, 0], method=method)
        assert not r.resistible


@pytest.mark.parametrize(
    "call, err, match",
    [
        (lambda m: pg.passive_response(m, 1.0, [0, np.nan, 0]), pg.InvalidInputError, "wrench"),
        (lambda m: pg.passive_response(m, [1.0, np.inf], [0, 1, 0]), pg.InvalidInputError, "command"),
        (lambda m: pg.passive_response(m, 1.0, [0, 1, 0], method="magic"), pg.InvalidInputError, "method"),
        (lambda m: pg.max_resistible_wrench(m, 1.0, [0, 0, 0]), pg.InvalidInputError, "zero-length"),
        (lambda m: pg.max_resistible_wrench(m, 1.0, "fw"), pg.UnknownNameError, "wrench axis"),
        (lambda m: pg.max_resistible_wrench(m, 1.0, "fy", upper=-1), pg.InvalidInputError, "upper"),
        (lambda m: pg.passive_response(m, 1.0, [0, 1, 0], gamma=-1.0), pg.InvalidInputError, "gamma"),
        (lambda m: pg.passive_response(m, 1.0, [0, 1, 0], colour="red"), pg.UnknownNameError, "setting"),
        (
            lambda m: pg.passive_response(m, 1.0, [0, 1, 0], variant="two-step"),
            pg.InvalidInputError,
            "variant",
        ),
        (lambda m: pg.resistance_profile(m, 1.0, ("fx", "fx"), n=4), pg.InvalidInputError, "parallel"),
        (lambda m: pg.passive_response("not a model", 1.0, [0, 1, 0]), pg.InvalidInputError, "model"),
    ],
)
def test_bad_input(call, err, match):
    with pytest.raises(err, match=match):
        call(examples.pinch())


def test_every_error_is_a_pinograsp_error():
    for cls in (
        pg.InvalidInputError,
        pg.UnknownNameError,
        pg.ModelError,
        pg.SolverError,
        pg.SolverNotAvailableError,
        pg.SolverTimeoutError,
        pg.PreloadNotInEquilibriumError,
    ):
        assert issubclass(cls, pg.PinograspError)


def _message(call) -> str:
    with pytest.raises(pg.PinograspError) as info:
        call()
    return str(info.value)


def test_a_new_users_mistakes_name_the_culprit_the_choices_and_what_to_do(tmp_path, monkeypatch):
    """The errors a new user meets first (a mistyped axis, an unknown preload of a scene, a
    zero or parallel direction, an object the hand misses, a mesh file that is not there or
    not a mesh): each names what was wrong, what is valid and what to pass instead."""
    pinch = examples.pinch()
    axis = _message(lambda: pg.max_resistible_wrench(pinch, 1.0, "fxx"))
    assert axis.startswith("unknown wrench axis 'fxx'; valid wrench axes: 'fx', 'fy', 'fz', 'mx', 'my', 'mz'")
    assert "optional sign ('fx', '-fy', '+mz'" in axis and "wrench vector (fx, fy, fz, mx, my, mz)" in axis
    assert "give a nonzero wrench vector" in _message(lambda: pg.max_resistible_wrench(pinch, 1.0, [0, 0, 0]))
    assert "e.g. ('fx', 'fy')" in _message(lambda: pg.resistance_profile(pinch, 1.0, ("fx", "fx"), n=4))

    scene = pg.load_scene("pinch")  # no named preloads
    preload = _message(lambda: scene.preload("nope"))
    assert "there are no preloads to choose from" in preload
    assert "pass None for the scene's own preload {'left': 1.0, 'right': 1.0}" in preload
    case3 = pg.load_scene("case3")  # named directions (torque_x, ...) beside the axes
    direction = _message(lambda: case3.max_resistible_wrench("torque_y"))
    assert "unknown direction 'torque_y'" in direction and "'mz', 'pull'" in direction
    assert "'torque_x'" in direction and "one of the scene's named directions" in direction

    hand = pg.Hand.builtin("parallel_jaw")
    far = pg.RigidObject.box([0.03, 0.04, 0.05], pose=[0.3, 0.04, 0.0])  # 0.3 m beside the jaws
    missed = _message(lambda: hand.close_on(far))
    assert "touches nothing" in missed and "pj_left_jaw: 286.000 mm" in missed
    assert "place the object between the fingers" in missed
    q = hand.close_on(pg.RigidObject.box([0.03, 0.04, 0.05], pose=[0.0, 0.04, 0.0]))
    apart = _message(lambda: pg.grasp_model_from_scene(hand, q, far, mu=0.5))
    assert "pj_left_jaw: 300.000 mm" in apart and "q = hand.close_on(obj)" in apart

    monkeypatch.chdir(tmp_path)
    missing = _message(lambda: pg.RigidObject.from_mesh("nope.stl"))
    assert missing.startswith("nope.stl: mesh file not found")
    assert f"looked for {tmp_path / 'nope.stl'}" in missing and "STL, OBJ, PLY, OFF or GLB" in missing
    absolute = _message(lambda: pg.RigidObject.from_mesh(tmp_path / "nope.stl"))  # no working directory
    hint = "give the path of an existing STL, OBJ, PLY, OFF or GLB file"
    assert absolute == f"{tmp_path / 'nope.stl'}: mesh file not found: {hint}"
    (tmp_path / "notes.txt").write_text("not a mesh")
    unreadable = _message(lambda: pg.RigidObject.from_mesh("notes.txt"))
    assert "cannot read mesh (NotImplementedError: file_type 'txt' not supported)" in unreadable
    assert "STL, OBJ, PLY, OFF or GLB" in _message(lambda: pg.RigidObject.from_mesh(tmp_path))


def test_error_kinds_read_as_plurals():
    from pinograsp.errors import plural

    assert [plural(k) for k in ("wrench axis", "preload", "direction", "hand description key")] == [
        "wrench axes",
        "preloads",
        "directions",
        "hand description keys",
    ]
