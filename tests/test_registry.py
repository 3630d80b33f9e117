"""Methods and backends as registry rows, the session a caller owns, the query record, and
profiles that record failed directions (issues #24 items 1-4, #27 item 9)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

import pinograsp as pg
from pinograsp.analysis.registry import available_methods, get_method, resolve_search
from pinograsp.cli import main
from pinograsp.core import examples
from pinograsp.core.methods import BUILT_IN, method_names
from pinograsp.solvers import BACKENDS, Formulation, ProblemKind, available_backends, build_problem

PACKAGE = Path(pg.__file__).parent


def run(capsys, *argv: str) -> tuple[int, str]:
    """Exit code and stdout of ``pinograsp ARGV`` (in this process)."""
    rc = main(list(argv))
    return rc, capsys.readouterr().out


F_MAX = 10.0  # the pinch's closed form 2 mu tau0 / L [N] along +y


@pytest.fixture(scope="module")
def pinch():
    return examples.pinch()


# ------------------------------------------------------------------------------ methods
def test_registry_lists_every_method_with_its_rules():
    assert available_methods() == method_names() == tuple(s.name for s in BUILT_IN)
    assert {m.value for m in pg.Method} == set(method_names())  # the constants name the built-in rows
    for name in available_methods():
        rules = get_method(name)
        assert rules.spec == get_method(pg.Method(name)).spec and rules.name == name
        assert rules.searches and resolve_search("auto", rules) is rules.searches[0]
    assert resolve_search("auto", get_method("iterative")) is pg.Search.SECANT
    assert resolve_search("auto", get_method("energetic")) is pg.Search.DIRECT
    assert resolve_search("auto", get_method("prp")) is pg.Search.BISECTION
    assert get_method("iterative").load_factor_kind is None  # a trajectory: no one-solve limit
    assert get_method("energetic").preload_method == pg.Method.ITERATIVE
    qs = get_method("quasistatic")  # a path, not stages: no problem kinds, one search
    assert qs.load_kind is None and qs.load_factor_kind is None and qs.searches == (pg.Search.PATH,)


def test_unknown_method_and_unsupported_search_name_the_valid_ones(pinch):
    with pytest.raises(pg.UnknownNameError) as err:
        get_method("magic")
    assert isinstance(err.value, pg.InvalidInputError) and err.value.valid == list(method_names())
    with pytest.raises(pg.InvalidInputError, match=re.escape(f"method: must be one of {method_names()}")):
        pg.passive_response(pinch, 1.0, [0, 1, 0], method="magic")
    with pytest.raises(pg.InvalidInputError, match="'secant' exists for method='iterative' only"):
        pg.max_resistible_wrench(pinch, 1.0, "fy", "prp", 50.0, 6, search="secant")
    with pytest.raises(pg.InvalidInputError, match="'direct' exists for method='prp' and 'energetic' only"):
        pg.max_resistible_wrench(pinch, 1.0, "fy", "iterative", 50.0, 6, search="direct")
    with pytest.raises(pg.InvalidInputError, match="cone refinement applies to method='prp' or 'energetic'"):
        pg.passive_response(pinch, 1.0, [0, 1, 0], "iterative", cone_tolerance=0.1)
    with pytest.raises(pg.InvalidInputError, match="'path' exists for method='quasistatic' only"):
        pg.max_resistible_wrench(pinch, 1.0, "fy", "iterative", search="path")
    with pytest.raises(pg.InvalidInputError, match=r"its searches: \['path'\]"):
        pg.max_resistible_wrench(pinch, 1.0, "fy", "quasistatic", search="bisection")


def test_no_method_tests_outside_the_registry():
    """Every rule of a method lives in its module: no ``== Method.X`` / ``is Method.X`` elsewhere."""
    pattern = re.compile(r"(==|!=|\bis|\bis not)\s+Method\.")
    hits = [
        f"{p.relative_to(PACKAGE)}:{i}"
        for p in PACKAGE.rglob("*.py")
        for i, line in enumerate(p.read_text().splitlines(), 1)
        if pattern.search(line)
    ]
    assert hits == []


def test_problem_and_solution_carry_their_named_layout(pinch):
    form = Formulation(pinch)
    data = form.scale_data(np.array([0.0, 3.0, 0.0]), np.ones(2))
    for kind in ProblemKind:
        lay = form.layout(kind)
        assert lay.name == kind.value and lay.beta == slice(0, form.nb) and lay["qh"] == lay.qh
        assert (lay.t is not None) == kind.load and (lay.slip.stop > lay.slip.start) == kind.energetic
    session = pg.Session(pinch)
    raw = session.solve(ProblemKind.PRP, data)
    assert raw.layout == form.layout("prp") and raw.z[raw.layout.beta].shape == (form.nb,)
    assert build_problem(form, "energetic", data).layout == form.layout(ProblemKind.ENERGETIC)
    with pytest.raises(pg.InvalidInputError, match="kind"):
        form.layout("alg9")


def test_formulation_refuses_an_unpruned_model_with_a_model_error():
    ez = np.array([0.0, 0.0, 1.0])
    left = examples._finger_contact(
        [-0.05, 0, 0], [1, 0, 0], 0.1, 0, 3, -ez, mu=0.5, stiffness=1.0, name="left"
    )
    right = examples._finger_contact(
        [0.05, 0, 0], [-1, 0, 0], 0.1, 1, 3, ez, mu=0.5, stiffness=1.0, name="right"
    )
    bad = pg.GraspModel.from_contacts([left, right], joint_names=["l", "r", "idle"], planar=True, prune=False)
    with pytest.raises(pg.ModelError, match="idle"):
        Formulation(bad)


# ------------------------------------------------------------------------------ backends
def test_backend_registry_and_the_one_solve_path(pinch):
    assert set(BACKENDS) == {b.value for b in pg.Backend} and "bnb" in available_backends()
    s = pg.Session(pinch)
    assert s.backend.name == "bnb" and s.backend.capabilities.deterministic
    assert s.backend.capabilities.node_limit and not s.backend.capabilities.time_limit
    if "miqp" not in available_backends() or not pg.available_miqp_solvers():
        pytest.skip("no MIQP solver")
    ref = pg.Session(pinch, pg.Settings(backend="miqp"))
    assert ref.backend.name == "miqp" and ref.backend.capabilities.time_limit
    # a load factor and an optimal-preload program through the reference backend
    lf = ref.max_load_factor(1.0, np.array([0.0, 1.0, 0, 0, 0, 0]), 50.0)
    assert lf.magnitude == pytest.approx(F_MAX, rel=1e-6)
    r = pg.optimal_preload(pinch, [[0.0, 5.0, 0.0]], "prp", settings=pg.Settings(backend="miqp"))
    assert r.status == "optimal" and r.value == pytest.approx(0.5, rel=1e-5)  # tau0 = F L / (2 mu)


# ------------------------------------------------------------------------------ session, query
def test_a_session_the_caller_owns_gives_the_same_answers(pinch):
    alone = pg.max_resistible_wrench(pinch, 1.0, "fy", "iterative", 50.0, 10)
    s = pg.Session(pinch)
    first = pg.max_resistible_wrench(pinch, 1.0, "fy", "iterative", 50.0, 10, session=s)
    again = pg.max_resistible_wrench(pinch, 1.0, "fy", "iterative", 50.0, 10, session=s)
    assert first.magnitude == again.magnitude == alone.magnitude
    assert first.evidence == again.evidence == alone.evidence
    assert again.n_solves < first.n_solves == alone.n_solves  # the preload stage is kept
    r1 = pg.passive_response(pinch, 1.0, [0.0, 4.0, 0.0], "iterative", session=s)
    r2 = pg.passive_response(pinch, 1.0, [0.0, 4.0, 0.0], "iterative")
    np.testing.assert_array_equal(r1.contact_forces, r2.contact_forces)
    assert r1.n_solves < r2.n_solves  # the session's preload stage is kept
    q1 = pg.passive_response(pinch, 1.0, [0.0, 4.0, 0.0], session=s)  # the default path
    q2 = pg.passive_response(pinch, 1.0, [0.0, 4.0, 0.0])
    assert q1.method == q2.method == "quasistatic"
    np.testing.assert_array_equal(q1.contact_forces, q2.contact_forces)
    p1 = pg.resistance_profile(pinch, 1.0, n=6, upper=50.0, steps=8)
    p2 = pg.resistance_profile(pinch, 1.0, n=6, upper=50.0, steps=8, session=s)
    np.testing.assert_array_equal(p1.magnitudes, p2.magnitudes)
    with pytest.raises(pg.InvalidInputError, match="session: was built for another model"):
        pg.max_resistible_wrench(examples.pinch(), 1.0, "fy", session=s)
    with pytest.raises(pg.InvalidInputError, match="session: carries its own settings"):
        pg.max_resistible_wrench(pinch, 1.0, "fy", session=s, eps=1e-4)


def test_query_record_is_validated_once_and_equals_the_loose_arguments(pinch):
    q = pg.Query("prp", 50.0, 10, "direct")
    assert q.method is pg.Method.PRP and q.search is pg.Search.DIRECT and q.resolution == 50.0 / 2**10
    a = pg.max_resistible_wrench(pinch, 1.0, "fy", query=q)
    b = pg.max_resistible_wrench(pinch, 1.0, "fy", "prp", 50.0, 10, search="direct")
    assert a.magnitude == b.magnitude == pytest.approx(F_MAX) and a.search == "direct"
    rs = pg.resistance_set(pinch, 1.0, directions=[[0, 1, 0], [1, 1, 0]], query=q)
    assert rs.method == "prp" and rs.upper == 50.0 and rs.steps == 10
    for bad, name in (
        (dict(method="magic"), "method"),
        (dict(upper=-1.0), "upper"),
        (dict(steps=0), "steps"),
    ):
        with pytest.raises(pg.InvalidInputError, match=name):
            pg.Query(**bad)
    with pytest.raises(pg.InvalidInputError, match="query: pass either"):
        pg.max_resistible_wrench(pinch, 1.0, "fy", "prp", query=q)
    scene = pg.load_scene("pinch")
    assert scene.analysis.query == pg.Query("quasistatic", 1000.0, 20)  # the default method
    assert scene.max_resistible_wrench("up", steps=8, method="prp").method == "prp"


# ------------------------------------------------------------------------------ failed directions
def test_profile_records_failed_directions_and_keeps_the_others(pinch, capsys, tmp_path):
    full = pg.resistance_profile(pinch, 1.0, n=8, method="prp", upper=50.0, steps=8)
    p = pg.resistance_profile(pinch, 1.0, n=8, method="prp", upper=50.0, steps=8, max_nodes=1)
    failed = [i for i, st in enumerate(p.statuses) if st == "failed"]
    assert failed and len(failed) < 8 and [i for i, _, _ in p.failures] == failed
    for i in range(8):
        if i in failed:
            r = p.results[i]
            assert (
                r.status == "failed"
                and np.isnan(r.magnitude)
                and np.isnan(p.magnitudes[i])
                and not r.evidence
            )
            assert not p.unbounded[i] and r.n_solves == 0
        else:
            assert p.magnitudes[i] == full.magnitudes[i] and p.statuses[i] == full.statuses[i]
    assert all(st == "node_limit" and "max_nodes" in msg for _, msg, st in p.failures)
    d = p.to_dict(results=True)
    assert [r["status"] for r in d["results"]].count("failed") == len(failed)
    assert [r["status"] for r in p.rows()] == list(p.statuses)
    assert f"failed={len(failed)}" in repr(p) and f"failed {len(failed)}" in p.summary()
    # the command line prints them
    text = (PACKAGE / "data" / "scenes" / "pinch.yaml").read_text()
    scene = tmp_path / "pinch_limited.yaml"
    scene.write_text(text.replace("analysis:\n", "analysis:\n  max_nodes: 1\n"))
    argv = ("profile", str(scene), "-n", "8", "--upper", "50", "--steps", "8", "--method", "prp")
    rc, out = run(capsys, *argv)
    assert rc == 0 and f"{len(failed)} direction(s) FAILED" in out and "45° (node_limit)" in out
    rc, out = run(capsys, *argv, "--json")
    data = json.loads(out)
    assert data["statuses"] == list(p.statuses) and [f["index"] for f in data["failures"]] == failed
