"""Answers that mean what they say: "unbounded" decided by the model (not by the search limit),
values below the resolution reported as such, and ratios of such values undefined."""

import json

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples
from pinograsp.cli import main


def test_unbounded_is_a_property_of_the_grasp_not_of_upper(case1):
    s = case1
    # the default (quasi-static path): +Y gives way at 4.3354 N at every upper, exactly (the
    # simulation at 4.3287 N, scripts/reproduce/data/qs_sim.jsonl); below it the answer is
    # "above_limit" at upper, as the searches say, with the exact load kept
    for u in (1e-6, 1.0, 50.0, 1e3):
        r = pg.max_resistible_wrench(s.model, s.command, "fy", upper=u, steps=4)
        assert r.giveway.load == pytest.approx(4.3354, abs=1e-4) and not r.unbounded
        if u > 4.3354:
            assert r.status == "finite" and r.magnitude == r.giveway.load
        else:
            assert r.status == "above_limit" and r.magnitude == u
    # the iterative scheme's bisection: +Y is finite (4.30 N): a tiny upper is resisted but
    # is not "unbounded"
    it = "iterative"
    tiny = pg.max_resistible_wrench(s.model, s.command, "fy", it, upper=1e-6, steps=4)
    assert tiny.status == "above_limit" and not tiny.unbounded and tiny.magnitude == 1e-6
    one = pg.max_resistible_wrench(s.model, s.command, "fy", it, upper=1.0)
    assert one.status == "above_limit" and one.magnitude == 1.0
    # the same value at every upper above the limit, to the resolution
    vals = [pg.max_resistible_wrench(s.model, s.command, "fy", it, upper=u) for u in (5.0, 50.0, 1e3)]
    assert all(v.status == "finite" for v in vals)
    for v in vals:
        assert abs(v.magnitude - vals[0].magnitude) <= max(v.resolution, vals[0].resolution)
    # ±X and -Y: passively resisted without bound at upper 50 and 1e3 (iterative, and the
    # path's exact verdict)
    for d in ("fx", "-fx", "-fy"):
        for method in (it, "quasistatic"):
            for upper in (50.0, 1e3):
                r = pg.max_resistible_wrench(s.model, s.command, d, method, upper=upper)
                assert r.status == "unbounded" and r.unbounded and r.magnitude == np.inf


def test_below_resolution_is_not_a_number(case1):
    # (upper within 1e6 times the grasp's force scale, docs/errors.md)
    coarse = pg.max_resistible_wrench(case1.model, case1.command, "fy", "iterative", upper=1e7, steps=4)
    assert coarse.status == "below_resolution" and coarse.floor == pytest.approx(1e7 / 16)
    # the pinch's band is 10 N: below a 50 N resolution it is not distinguishable from zero
    r = pg.max_resistible_wrench(examples.pinch(), 1.0, "fy", "prp", upper=100, steps=1)
    assert r.status == "below_resolution" and r.magnitude == 0.0
    # one resolution step resisted by the PRP is a value (the limit is known to be >= it)
    r = pg.max_resistible_wrench(examples.pinch(), 1.0, "fy", "prp", upper=100, steps=4)
    assert r.status == "finite" and r.magnitude == 100 / 16


def test_iterative_values_below_eps_are_below_resolution():
    """The iterative scheme accepts a net wrench below eps: a limit below eps along the
    direction (eps times the length scale for a torque) is indistinguishable from zero. Seed
    case 3, torque about X with the distal tendon alone held still: one bisection step
    (4.8e-5 N·m) was printed as a value and gave a ratio of 182 that reversed the paper."""
    s = pg.load_scene("case3")
    r = pg.max_resistible_wrench(
        s.model, s.preload("distal_only"), "mx", "iterative", upper=50, settings=s.settings
    )
    assert r.status == "below_resolution" and r.magnitude < r.floor
    assert r.floor == pytest.approx(1e-3 * s.model.length_scale, rel=1e-9)


def _cli_json(capsys, *argv):
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_cli_reports_statuses_and_undefined_ratios(capsys):
    it = ("--method", "iterative")  # the bisection's statuses
    data = _cli_json(capsys, "max-wrench", "case1", "-d", "fy", "--upper", "1e-6", "--steps", "4", *it)
    assert data["status"] == "above_limit" and data["unbounded"] is False
    assert main(["max-wrench", "case1", "-d", "fy", "--upper", "1e7", "--steps", "4", *it]) == 0
    out = capsys.readouterr().out
    assert "< 6.2e+05 N" in out and "UNBOUNDED" not in out
    for method in it, ():  # the iterative scheme below eps; the default path's exact 0
        data = _cli_json(capsys, "compare-preloads", "case3", "-d", "torque_x", *method)
        row = data["directions"][0]
        assert row["ratio"] is None and row["results"]["distal_only"]["status"] == "below_resolution"
    assert row["results"]["distal_only"]["magnitude"] == 0.0 and data["method"] == "quasistatic"


def test_one_default_method_and_scenes_apply_their_analysis_block(case1):
    """The API, the CLI and the scenes default to the quasi-static loading path (it agrees
    with the simulation most often: docs/validation.md); a scene's own upper, steps and method
    apply through ``scene.max_resistible_wrench`` / ``scene.profile``."""
    s = case1
    w = [0.0, -20.0, 0.0, 0.0, 0.0, 0.0]
    default = pg.passive_response(s.model, s.command, w)
    explicit = pg.passive_response(s.model, s.command, w, "quasistatic")
    assert default.method == "quasistatic" and np.array_equal(default.contact_forces, explicit.contact_forces)
    assert s.passive_response(w).method == s.analysis.method == "quasistatic"
    mw = s.max_resistible_wrench("fy")  # the path's limit: exact, upper and steps do not apply
    ref = pg.max_resistible_wrench(s.model, s.command, "fy", "quasistatic")
    assert mw.method == "quasistatic" and mw.resolution == 0 and mw.magnitude == ref.magnitude
    assert mw.magnitude == pytest.approx(4.3354, abs=1e-4)  # the simulation: 4.3287 N
    it = s.max_resistible_wrench("fy", method="iterative")  # the scene's upper and steps apply
    assert it.upper == s.analysis.upper == 50.0
    assert it.resolution == 50.0 / 2**s.analysis.steps
    ref = pg.max_resistible_wrench(s.model, s.command, "fy", "iterative", upper=50.0, steps=s.analysis.steps)
    assert it.magnitude == ref.magnitude
    prp = s.max_resistible_wrench("fy", method="prp", steps=8)
    assert prp.method == "prp" and prp.resolution == 50.0 / 2**8
    p = s.profile(n=4, steps=4, method="iterative")
    assert p.plane == ("fx", "fy") and len(p.magnitudes) == 4 and p.results[0].upper == 50.0


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda m: pg.passive_response(m, [1.0], [0, 1, 0]), "command"),  # 1 value, 2 actuators
        (lambda m: pg.passive_response(m, [-1.0, 1.0], [0, 1, 0]), "command"),
        (lambda m: pg.passive_response(m, -1.0, [0, 1, 0]), "command"),
        (lambda m: pg.max_resistible_wrench(m, 1.0, "fy", upper="100"), "upper"),
        (lambda m: pg.max_resistible_wrench(m, 1.0, "fy", steps="20"), "steps"),
        (lambda m: pg.max_resistible_wrench(m, 1.0, "fy", steps=2.5), "steps"),
        (lambda m: pg.resistance_profile(m, 1.0, n=4.5), "n"),
        (lambda m: pg.max_resistible_wrench(m, 1.0, "fy", settings={"eps": 1e-3}), "settings"),
        (lambda m: pg.passive_response(m, 1.0, [0, 1, 0], max_iterations=2.5), "max_iterations"),
        (lambda m: pg.passive_response(m, 1.0, [0, 1, 0], accelerate="yes"), "accelerate"),
        (lambda m: pg.passive_response(m, 1.0, [0, 1, 0], eps=True), "eps"),
    ],
)
def test_bad_input_names_the_culprit(call, name):
    with pytest.raises(pg.InvalidInputError) as info:
        call(examples.pinch())
    assert info.value.name == name


def test_model_side_errors_name_the_culprit(case1):
    s = case1
    with pytest.raises(pg.UnknownNameError, match="nolink"):
        pg.grasp_model_from_scene(s.hand, s.q, s.object, mu={"nolink": 0.3})
    far = pg.RigidObject.sphere(0.04, pose=[1.0, 1.0, 1.0])
    with pytest.raises(pg.NoContactError) as info:
        s.hand.close_on(far)
    assert min(info.value.distances.values()) > 1.0  # [m]: the closest link is 1.6 m away
    fixed = [
        pg.Contact([x, 0, 0], [sgn, 0, 0], mu=0.5, jacobian=np.zeros((3, 0)))
        for x, sgn in ((0, 1), (0.1, -1))
    ]
    with pytest.raises(pg.ModelError, match="no contact moves"):
        pg.GraspModel.from_contacts(fixed, planar=True)


def _pinch_right_axis(flipped: bool, bidirectional: bool) -> pg.GraspModel:
    """The analytic pinch; with ``flipped`` the right joint's axis is reversed, so that finger
    closes for a negative joint torque."""
    ez = np.array([0.0, 0.0, 1.0])
    left = pg.Contact.revolute(
        [-0.05, 0, 0], [1, 0, 0], {0: ([-0.05, -0.1, 0], -ez)}, nq=2, mu=0.5, name="left"
    )
    right = pg.Contact.revolute(
        [0.05, 0, 0], [-1, 0, 0], {1: ([0.05, -0.1, 0], -ez if flipped else ez)}, nq=2, mu=0.5, name="right"
    )
    acts = [
        pg.Actuator({0: 1.0}, name="left"),
        pg.Actuator({1: 1.0}, name="right", bidirectional=bidirectional),
    ]
    return pg.GraspModel.from_contacts(
        [left, right], actuators=acts, planar=True, joint_names=("left", "right")
    )


@pytest.mark.parametrize("method", ["iterative", "prp"])
def test_bidirectional_actuator_takes_negative_commands(method):
    """A bidirectional actuator commanded -f is the actuator with its column negated commanded
    +f: the mirrored pinch gives the pinch's forces, with signed actuator force and travel."""
    ref_model = _pinch_right_axis(False, False)
    neg_model = _pinch_right_axis(True, True)
    assert neg_model.bidirectional == ("right",)
    w = [2.0, 3.0, 0.0]
    ref = pg.passive_response(ref_model, 1.0, w, method)
    neg = pg.passive_response(neg_model, [1.0, -1.0], w, method)
    assert neg.status == ref.status == "resisted"
    np.testing.assert_allclose(neg.contact_forces, ref.contact_forces, atol=1e-9)
    np.testing.assert_allclose(neg.contact_forces[:, 0], [10.0, 12.0], rtol=1e-6)  # 10 N preload + 2 N
    np.testing.assert_allclose(neg.actuator_forces, ref.actuator_forces * [1, -1], atol=1e-9)
    np.testing.assert_allclose(neg.actuator_displacements, ref.actuator_displacements * [1, -1], atol=1e-9)
    np.testing.assert_allclose(neg.joint_torques, ref.joint_torques * [1, -1], atol=1e-9)
    assert neg.command.tolist() == [1.0, -1.0]
    a = pg.max_resistible_wrench(ref_model, 1.0, "fy", method, upper=50)
    b = pg.max_resistible_wrench(neg_model, {"left": 1.0, "right": -1.0}, "fy", method, upper=50)
    assert a.magnitude == b.magnitude and abs(a.magnitude - 10.0) <= a.resolution + 2e-3  # 2 mu tau / L
    # without the declaration a negative command names the actuator and the way out
    with pytest.raises(pg.InvalidInputError, match=r"\['right'\].*bidirectional=True") as info:
        pg.passive_response(_pinch_right_axis(True, False), [1.0, -1.0], w, method)
    assert info.value.name == "command"


def test_bidirectional_flag_is_validated():
    with pytest.raises(pg.InvalidInputError) as info:
        pg.Actuator({0: 1.0}, name="m", bidirectional="yes")
    assert info.value.name == "actuator 'm'.bidirectional"
