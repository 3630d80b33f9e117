"""Fuzzing the constructors with hypothesis: random (NaN, inf, wrong shapes, wrong types, empty)
inputs give a valid object or a :class:`pinograsp.PinograspError` — never another exception.

Also fuzzed: ``GraspModel.command_vector`` / ``wrench_vector``, a few solver calls on random
wrenches and commands, and the YAML scene loader (random YAML documents and strings written to
temporary files).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from hypothesis import example, given
from hypothesis import strategies as st
from support.strategies import (  # noqa: E402
    FUZZ,
    SLOW,
    expect_pinograsp_error,
    finite,
    floats,
    jacobians,
    junk,
    maybe_unit,
    names,
    scalars,
    vec,
)

import pinograsp as pg
from pinograsp import examples

# ------------------------------------------------------------------------------ Contact
positive = st.floats(1e-6, 1e6)
#: Valid values inside the documented domains (docs/errors.md): mu in [0, 100], k in [1e-6, 1e12] N/m.
valid_mu = st.floats(0.0, 100.0)
valid_k = st.floats(1e-6, 1e12)


@FUZZ
@given(
    point=vec(3),
    normal=maybe_unit,
    mu=st.one_of(valid_mu, st.just(0.0), positive, scalars),
    jacobian=jacobians(),
    tangent=st.one_of(st.none(), st.none(), maybe_unit),
    stiffness=st.one_of(valid_k, positive, scalars),
    name=st.one_of(st.none(), st.text(max_size=4), names),
)
def test_fuzz_contact(point, normal, mu, jacobian, tangent, stiffness, name):
    c = expect_pinograsp_error(
        pg.Contact, point, normal, mu=mu, jacobian=jacobian, tangent=tangent, stiffness=stiffness, name=name
    )
    if c is not None:  # a valid contact is really valid
        assert np.all(np.isfinite(c.point)) and abs(np.linalg.norm(c.normal) - 1) < 1e-6
        assert np.isfinite(c.mu) and c.mu >= 0 and np.isfinite(c.stiffness) and c.stiffness > 0
        np.testing.assert_allclose(np.cross(c.tangent, c.t2), c.normal, atol=1e-9)
        assert c.name is None or isinstance(c.name, str)


pivot_dicts = st.one_of(
    st.none(),
    st.dictionaries(
        st.one_of(st.integers(-2, 4), st.text(max_size=2), st.floats(0, 3)),
        st.one_of(st.tuples(vec(3), maybe_unit), st.tuples(vec(3), maybe_unit), junk, st.tuples(vec(3))),
        max_size=3,
    ),
    junk,
)


@FUZZ
@given(
    point=vec(3),
    normal=maybe_unit,
    pivots=pivot_dicts,
    nq=st.one_of(st.integers(-2, 5), st.integers(0, 4), scalars),
    mu=st.one_of(positive, scalars),
)
@example(point=[0.0, 0.0, 0.0], normal=[1.0, 0.0, 0.0], pivots=None, nq=200_000_000, mu=0.5)  # 4.6 GiB
@example(point=[0.0, 0.0, 0.0], normal=[1.0, 0.0, 0.0], pivots=None, nq=10**9, mu=0.5)
def test_fuzz_contact_revolute(point, normal, pivots, nq, mu):
    c = expect_pinograsp_error(pg.Contact.revolute, point, normal, pivots, nq=nq, mu=mu)
    if c is not None:
        assert c.jacobian.shape[0] == 3 and np.all(np.isfinite(c.jacobian))


# ------------------------------------------------------------------------------ actuation
transmissions = st.one_of(
    st.dictionaries(
        st.one_of(st.integers(-2, 4), st.text(max_size=3)), st.one_of(finite, scalars), max_size=3
    ),
    st.dictionaries(st.integers(0, 2), st.floats(-2, 2), min_size=1, max_size=2),
    junk,
    st.lists(floats, max_size=3),
)


@FUZZ
@given(transmission=transmissions, kind=st.one_of(st.sampled_from(pg.ACTUATOR_KINDS), junk), name=names)
def test_fuzz_actuator(transmission, kind, name):
    a = expect_pinograsp_error(pg.Actuator, transmission, kind=kind, name=name)
    if a is not None:
        assert a.kind in pg.ACTUATOR_KINDS and a.transmission
        assert all(np.isfinite(v) for v in a.transmission.values())


@FUZZ
@given(
    weights=transmissions,
    follower=st.one_of(st.integers(-1, 3), st.text(max_size=2), junk),
    leader=st.one_of(st.integers(-1, 3), st.text(max_size=2), junk),
    ratio=scalars,
    name=names,
)
def test_fuzz_coupling(weights, follower, leader, ratio, name):
    expect_pinograsp_error(pg.Coupling, weights, name=name)
    cp = expect_pinograsp_error(pg.Coupling.follow, follower, leader, ratio, name=name)
    if cp is not None:
        assert all(np.isfinite(v) for v in cp.weights.values())


# ------------------------------------------------------------------------------ GraspModel
EZ = np.array([0.0, 0.0, 1.0])


def good_contacts(nq: int = 2):
    return [
        pg.Contact.revolute([-0.05, 0, 0], [1, 0, 0], {0: ([-0.05, -0.1, 0], -EZ)}, nq=nq, name="left"),
        pg.Contact.revolute([0.05, 0, 0], [-1, 0, 0], {1: ([0.05, -0.1, 0], EZ)}, nq=nq, name="right"),
    ]


contact_lists = st.one_of(
    st.just(good_contacts()),
    st.just(good_contacts(3)),
    st.just(good_contacts()[:1]),
    st.just([good_contacts()[0], good_contacts(3)[1]]),  # Jacobians disagree on nq
    st.lists(st.one_of(st.just(good_contacts()[0]), junk), max_size=3),
    junk,
)
actuator_lists = st.one_of(
    st.none(),
    st.just([pg.Actuator({0: 1.0}, name="a"), pg.Actuator({1: 1.0}, name="b")]),
    st.just([pg.Actuator({0: 1.0, 1: 1.0}, name="t")]),
    st.just([pg.Actuator({"left": 1.0}, name="a"), pg.Actuator({"nope": 1.0}, name="b")]),
    st.just([pg.Actuator({0: 1.0}, name="a"), pg.Actuator({1: 1.0}, name="a")]),
    st.just([pg.Actuator({5: 1.0})]),
    st.lists(junk, max_size=2),
    junk,
)
coupling_sets = st.one_of(
    st.none(),
    st.just([pg.Coupling.follow(1, 0, 0.5)]),
    st.just([pg.Coupling({0: 0.0})]),
    st.just([pg.Coupling.follow("right", "left", 1.0)]),
    st.just([pg.Coupling.follow("x", "left", 1.0)]),
    st.lists(st.lists(floats, min_size=2, max_size=2), max_size=2).map(np.array),
    st.lists(st.lists(floats, min_size=0, max_size=3), max_size=2).map(lambda x: np.array(x, dtype=object)),
    st.just(np.zeros((2, 2, 2))),
    junk,
)


@FUZZ
@given(
    contacts=contact_lists,
    actuators=actuator_lists,
    couplings=coupling_sets,
    planar=st.one_of(st.booleans(), junk),
    reference_point=st.one_of(st.none(), vec(3)),
    joint_names=st.one_of(
        st.none(),
        st.just(("left", "right")),
        st.just(("l", "l")),
        st.lists(st.text(max_size=3), max_size=3),
        junk,
    ),
    edges=st.one_of(st.none(), st.integers(-2, 40), scalars),
    circumscribed=st.booleans(),
    prune=st.booleans(),
    length_scale=st.one_of(st.none(), scalars),
)
def test_fuzz_grasp_model_from_contacts(
    contacts,
    actuators,
    couplings,
    planar,
    reference_point,
    joint_names,
    edges,
    circumscribed,
    prune,
    length_scale,
):
    m = expect_pinograsp_error(
        pg.GraspModel.from_contacts,
        contacts,
        actuators,
        couplings,
        planar,
        reference_point=reference_point,
        joint_names=joint_names,
        edges=edges,
        circumscribed=circumscribed,
        prune=prune,
        length_scale=length_scale,
    )
    if m is not None:
        for a in (m.G, m.J, m.D, m.k, m.mu, m.R, m.C):
            assert np.all(np.isfinite(a))
        assert m.G.shape == (m.nw, m.nc * m.d) and m.J.shape == (m.nc * m.d, m.nq)
        assert np.isfinite(m.length_scale) and m.length_scale > 0
        assert all(isinstance(n, str) for n in m.contact_names + m.joint_names + m.actuator_names)


@pytest.fixture(scope="module")
def models():
    return {
        "planar": examples.pinch(),
        "3d": examples.pinch(planar=False),
        "tendon": examples.pinch(differential=True),
    }


commands = st.one_of(
    scalars,
    vec(2),
    vec(1),
    st.dictionaries(
        st.one_of(st.sampled_from(["left", "right", "tendon"]), st.text(max_size=3)), scalars, max_size=3
    ),
    st.dictionaries(st.sampled_from(["left", "right"]), st.floats(-5, 5), max_size=2),
)


@FUZZ
@given(kind=st.sampled_from(["planar", "3d", "tendon"]), command=commands, wrench=st.one_of(vec(3), vec(6)))
def test_fuzz_command_and_wrench_vectors(models, kind, command, wrench):
    m = models[kind]
    c = expect_pinograsp_error(m.command_vector, command)
    if c is not None:
        assert c.shape == (m.na,) and np.all(np.isfinite(c))
    w = expect_pinograsp_error(m.wrench_vector, wrench)
    if w is not None:
        assert w.shape == (6,) and np.all(np.isfinite(w))


@SLOW
@given(
    command=st.one_of(
        st.floats(-1e6, 1e6), st.floats(0.01, 100), st.sampled_from([0.0, 1e-300, 1e300, math.nan]), junk
    ),
    wrench=st.one_of(
        st.lists(st.floats(-1e6, 1e6), min_size=3, max_size=3),
        st.lists(st.floats(-20, 20), min_size=3, max_size=3),
        st.lists(st.sampled_from([0.0, 1e300, -1e300, 1e-300, 1.0]), min_size=3, max_size=3),
        vec(3),
    ),
    method=st.sampled_from(["prp", "iterative", "prp", "iterative", "magic"]),
)
def test_fuzz_passive_response(models, command, wrench, method):
    """The solver path too: any command and wrench give a response or a pinograsp error."""
    r = expect_pinograsp_error(pg.passive_response, models["planar"], command, wrench, method=method)
    if r is not None:
        assert r.status in ("resisted", "not_resisted", "not_converged", "timeout", "failed")
        if r.resistible:
            assert np.all(np.isfinite(r.contact_forces))


# ------------------------------------------------------------------------------ scene files
from pinograsp.scenes import loading as _scenes  # noqa: E402
from pinograsp.scenes import schema as _schema  # noqa: E402

load_scene = _scenes.load_scene

yaml_scalars = st.one_of(
    st.none(), st.booleans(), st.integers(-5, 5), st.floats(allow_nan=True), st.text(max_size=6)
)
yaml_values = st.recursive(
    yaml_scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=12,
)
SCENE_KEYS = sorted(set(_schema.URDF_KEYS + _schema.EXPLICIT_KEYS))
CONTACT = {
    "name": "left",
    "point": [-0.05, 0, 0],
    "normal": [1, 0, 0],
    "revolute": {"left": {"pivot": [-0.05, -0.1, 0], "axis": [0, 0, -1]}},
}


def _mutate(base: dict, data) -> dict:
    out = dict(base)
    for _ in range(data.draw(st.integers(1, 3))):
        key = data.draw(st.sampled_from(SCENE_KEYS + list(base)))
        if data.draw(st.booleans()) and key in out:
            del out[key]
        else:
            out[key] = data.draw(yaml_values)
    return out


@pytest.fixture(scope="module")
def scene_docs():
    """Valid scene documents (the built-in explicit ones) to mutate."""
    return [yaml.safe_load((_scenes.SCENE_DIR / f"{name}.yaml").read_text()) for name in ("pinch", "wedge")]


@FUZZ
@given(data=st.data())
def test_fuzz_scene_loader(tmp_path_factory, scene_docs, data):
    path = tmp_path_factory.mktemp("scene") / "fuzz.yaml"
    choice = data.draw(st.integers(0, 3))
    if choice == 0 or not scene_docs:
        doc = data.draw(st.dictionaries(st.sampled_from(SCENE_KEYS), yaml_values, max_size=5))
        text = yaml.safe_dump(doc)
    elif choice == 1:
        text = data.draw(st.text(max_size=200))
    elif choice == 2:
        text = yaml.safe_dump(_mutate(data.draw(st.sampled_from(scene_docs)), data))
    else:
        doc = dict(data.draw(st.sampled_from(scene_docs)))
        contacts = [dict(CONTACT)]
        key = data.draw(
            st.sampled_from(
                ["point", "normal", "revolute", "friction", "mu", "stiffness", "jacobian", "name"]
            )
        )
        contacts[0][key] = data.draw(yaml_values)
        doc["contacts"] = contacts + list(doc.get("contacts", []))[1:]
        text = yaml.safe_dump(doc)
    path.write_text(text)
    expect_pinograsp_error(load_scene, path)


# ------------------------------------------------------------------------------ URDF side
description_keys = st.sampled_from(
    [
        "name",
        "joints",
        "base_link",
        "reference_configuration",
        "closing",
        "open_configuration",
        "actuators",
        "couplings",
        "commands",
        "contact_links",
        "use_mimic",
        "urdf",
        "bogus",
    ]
)
description_values = st.one_of(
    yaml_values,
    st.just([{"name": "t", "transmission": {"uf_j11": 1.0}}]),
    st.just([{"name": "t", "transmission": "uf_j11"}]),
    st.just([{"name": "t", "kind": "springy", "transmission": {"uf_j11": 1.0}}]),
    st.just([{"follower": "uf_j12", "leader": "uf_j11", "ratio": "half"}]),
    st.just([{"follower": "uf_j12", "leader": "uf_j11"}]),
    st.just([{"weights": {"uf_j11": 1.0, "uf_j12": -1.0}}]),
    st.just({"uf_j11": -1}),
    st.just(["uf_j11", "uf_j12"]),
)


@FUZZ
@given(doc=st.dictionaries(description_keys, description_values, max_size=4))
def test_fuzz_hand_description(doc):
    from pinograsp.robots.hand import DATA_DIR

    desc = expect_pinograsp_error(pg.HandDescription.from_dict, doc)
    if desc is not None:
        expect_pinograsp_error(pg.Hand.from_urdf, DATA_DIR / "urdf" / "underactuated_2f.urdf", desc)


@FUZZ
@given(
    size=st.one_of(vec(3), scalars),
    radius=scalars,
    length=scalars,
    pose=st.one_of(st.none(), vec(3), st.just(np.eye(4)), st.lists(vec(4), min_size=4, max_size=4), junk),
    com=vec(3),
    translation=vec(3),
)
def test_fuzz_rigid_objects(size, radius, length, pose, com, translation):
    objs = [
        expect_pinograsp_error(pg.RigidObject.box, size, pose=pose),
        expect_pinograsp_error(pg.RigidObject.sphere, radius, pose=pose),
        expect_pinograsp_error(pg.RigidObject.cylinder, radius, length, pose=pose),
    ]
    base = pg.RigidObject.sphere(0.02)
    expect_pinograsp_error(pg.RigidObject, base.geometry, pose, com_local=com)
    expect_pinograsp_error(base.moved, translation)
    expect_pinograsp_error(base.with_pose, pose)
    for o in objs:
        if o is not None:
            assert np.all(np.isfinite(o.pose)) and np.all(np.isfinite(o.center_of_mass))


@FUZZ
@given(
    q=st.one_of(
        vec(4),
        st.dictionaries(
            st.sampled_from(["uf_j11", "uf_j12", "nope"]), st.one_of(finite, scalars), max_size=3
        ),
    ),
    tolerance=st.one_of(st.floats(0, 0.01), scalars),
    links=st.one_of(st.none(), st.just(["uf_distal_1"]), st.just(["nope"]), st.just("uf_distal_1"), junk),
    mu=st.one_of(
        st.floats(0, 1),
        st.floats(allow_nan=True, allow_infinity=True),
        st.lists(st.floats(-1, 1), max_size=3),
        st.dictionaries(st.text(max_size=3), st.floats(allow_nan=True), max_size=2),
    ),
)
def test_fuzz_scene_contacts(small_hand, q, tolerance, links, mu):
    from pinograsp.robots.collision import detect_contacts

    obj = pg.RigidObject.box((0.05, 0.05, 0.02), pose=[0.0, 0.07, 0.0])
    expect_pinograsp_error(small_hand.configuration, q)
    expect_pinograsp_error(detect_contacts, small_hand, q, obj, tolerance=tolerance, links=links)
    expect_pinograsp_error(pg.grasp_model_from_scene, small_hand, q, obj, mu=mu)


@pytest.mark.parametrize("mu", ["abc", object(), {"uf_distal_1": "high"}])
def test_scene_friction_of_the_wrong_type(small_hand, mu):
    obj = pg.RigidObject.box((0.05, 0.05, 0.02), pose=[0.0, 0.07, 0.0])
    q = small_hand.close_on(obj)
    with pytest.raises(pg.InvalidInputError, match="mu"):
        pg.grasp_model_from_scene(small_hand, q, obj, mu=mu)
    with pytest.raises(pg.InvalidInputError, match="stiffness"):
        pg.grasp_model_from_scene(small_hand, q, obj, stiffness=mu)


# ------------------------------------------------------------------------------ named culprits
def _hand():
    return pg.Hand.builtin("underactuated_2f")


@pytest.mark.parametrize(
    "call, err, match",
    [
        (lambda: pg.Contact([0, 0, 0], [1, 0, 0], mu="high", name="tip"), pg.InvalidInputError, "'tip'.mu"),
        (
            lambda: pg.Contact([0, 0, 0], [1, 0, 0], stiffness=None, name="tip"),
            pg.InvalidInputError,
            "stiffness",
        ),
        (lambda: pg.Contact([0, 0, 0], [1, 0, 0], name=3), pg.InvalidInputError, "name"),
        (
            lambda: pg.Contact.revolute([0, 0, 0], [1, 0, 0], {0: ([0, -1, 0], [0, 0, 0])}, nq=1),
            pg.InvalidInputError,
            r"pivots\[0\].axis",
        ),
        (
            lambda: pg.Contact.revolute([0, 0, 0], [1, 0, 0], {3: ([0, -1, 0], [0, 0, 1])}, nq=1),
            pg.InvalidInputError,
            "joint index 3",
        ),
        (lambda: pg.Contact.revolute([0, 0, 0], [1, 0, 0], nq=-1), pg.InvalidInputError, "nq"),
        (lambda: pg.Actuator({0: "one"}, name="motor"), pg.InvalidInputError, "'motor'.transmission"),
        (lambda: pg.Actuator({0: 1.0}, kind=np.array(["locked"])), pg.InvalidInputError, "kind"),
        (lambda: pg.Coupling.follow("distal", "proximal", "1/3"), pg.InvalidInputError, "ratio"),
        (lambda: pg.Coupling.follow(["distal"], "proximal", 0.3), pg.InvalidInputError, "follower"),
        (
            lambda: pg.GraspModel.from_contacts(good_contacts(), planar=True, edges=1000),
            pg.InvalidInputError,
            "edges",
        ),
        (
            lambda: pg.GraspModel.from_contacts(good_contacts(), edges=1000),
            pg.InvalidInputError,
            "at most 256",
        ),
        (
            lambda: pg.GraspModel.from_contacts(good_contacts(), reference_point="origin"),
            pg.InvalidInputError,
            "reference_point",
        ),
        (
            lambda: pg.GraspModel.from_contacts(good_contacts(), joint_names="lr"),
            pg.InvalidInputError,
            "joint_names",
        ),
        (lambda: pg.GraspModel.from_contacts(good_contacts(), planar="yes"), pg.InvalidInputError, "planar"),
        (
            lambda: pg.GraspModel.from_contacts(good_contacts(), length_scale="1 m"),
            pg.InvalidInputError,
            "length_scale",
        ),
        (lambda: pg.GraspModel.from_contacts(5), pg.InvalidInputError, "contacts"),
        (
            lambda: pg.GraspModel.from_contacts(
                [pg.Contact([1e200, 0, 0], [1, 0, 0], jacobian=[[1e200], [0], [0]])]
            ),
            pg.InvalidInputError,
            "overflows|too far",
        ),
        (lambda: examples.pinch().wrench_vector([10**400, 0, 0]), pg.InvalidInputError, "wrench"),
        (
            lambda: examples.pinch().command_vector({"left": "max"}),
            pg.InvalidInputError,
            r"command\['left'\]",
        ),
        (lambda: examples.pinch().command_vector({3: 1.0}), pg.UnknownNameError, "actuator"),
        (lambda: pg.RigidObject.box("big"), pg.InvalidInputError, "size"),
        (lambda: pg.RigidObject.sphere(0.02).moved([0, "up", 0]), pg.InvalidInputError, "translation"),
        (lambda: pg.RigidObject.sphere(0.02).moved(rotation=2 * np.eye(3)), pg.InvalidInputError, "rotation"),
        (lambda: _hand().configuration({"uf_j11": "open"}), pg.InvalidInputError, r"q\['uf_j11'\]"),
        (lambda: pg.Hand.from_urdf(42), pg.InvalidInputError, "urdf_path"),
        (lambda: pg.HandDescription.from_dict({"actuators": {"a": 1}}), pg.InvalidInputError, "actuators"),
        (
            lambda: pg.HandDescription.from_dict(
                {"couplings": [{"follower": "a", "leader": "b", "ratio": "x"}]}
            ),
            pg.InvalidInputError,
            "ratio",
        ),
        (lambda: pg.HandDescription.from_dict({"base_link": 3}), pg.InvalidInputError, "base_link"),
        (lambda: pg.HandDescription.from_dict({"use_mimic": "no"}), pg.InvalidInputError, "use_mimic"),
    ],
)
def test_bad_input_names_the_culprit(call, err, match):
    with pytest.raises(err, match=match):
        call()


def test_detect_contacts_arguments(small_hand):
    from pinograsp.robots.collision import detect_contacts

    obj = pg.RigidObject.box((0.05, 0.05, 0.02), pose=[0.0, 0.07, 0.0])
    q = small_hand.close_on(obj)
    with pytest.raises(pg.InvalidInputError, match="links"):
        detect_contacts(small_hand, q, obj, links="uf_distal_1")
    with pytest.raises(pg.InvalidInputError, match="tolerance"):
        detect_contacts(small_hand, q, obj, tolerance="1 mm")
    with pytest.raises(pg.UnknownNameError, match="link"):
        detect_contacts(small_hand, q, obj, links=[3])


def test_malformed_description_file_names_the_file(tmp_path):
    from pinograsp.robots.hand import DATA_DIR

    bad = tmp_path / "hand.yaml"
    bad.write_text("actuators: 5\n")
    with pytest.raises(pg.ModelFileError, match="hand.yaml"):
        pg.Hand.from_urdf(DATA_DIR / "urdf" / "underactuated_2f.urdf", bad)
    bad.write_text("couplings:\n  - {follower: uf_j12, leader: uf_j11, ratio: [1]}\n")
    with pytest.raises(pg.ModelFileError, match="ratio"):
        pg.Hand.from_urdf(DATA_DIR / "urdf" / "underactuated_2f.urdf", bad)


# ------------------------------------------------------------------------------ the profile
def test_the_default_profile_cannot_fail_by_chance():
    """Without HYPOTHESIS_PROFILE (and in .ci/run) the fuzz tests run the derandomised ``ci``
    profile: the same examples in every clone, no database, no deadline (tests/conftest.py)."""
    import os

    from hypothesis import settings

    if os.environ.get("HYPOTHESIS_PROFILE", "ci") != "ci":
        pytest.skip("another profile was asked for")
    s = settings.default
    assert s.derandomize and s.database is None and s.deadline is None and s.max_examples == 150
    assert FUZZ.derandomize and FUZZ.database is None
    assert FUZZ.max_examples == int(os.environ.get("FUZZ_EXAMPLES", 150))
    run = (__import__("pathlib").Path(__file__).parents[1] / ".ci" / "run").read_text()
    assert "HYPOTHESIS_PROFILE=ci" in run and "CI=1" in run
