"""The mode-guess fast path against the exact (MIQP) path.

Same resistible/unbounded classification and magnitudes within the stated tolerance on the
analytic models and on seeded random grasps; the fallback and the stop certification exercised.
"""

from __future__ import annotations

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import analytic
from pinograsp.solvers import Mode
from pinograsp.synthetic import random_grasp

UPPER, STEPS = 100.0, 14
RES = UPPER / 2**STEPS

ANALYTIC = {
    "pinch": analytic.pinch,
    "palm": analytic.palm_pinch,
    "wedge": lambda: analytic.pinch(h=0.01),
    "coupled": analytic.coupled_finger,
    "pinch3d": lambda: analytic.pinch(planar=False),
}
DIRS = ["fy", "-fy", "fx", [1.0, 1.0, 0, 0, 0, 0], [0.3, -1.0, 0, 0, 0, 0]]


def both(factory, direction, method, **kw):
    """(exact, fast) answers on fresh models (no shared mode history)."""
    ex = pg.max_resistible_wrench(factory(), 1.0, direction, method, UPPER, STEPS, fast=False, **kw)
    fa = pg.max_resistible_wrench(factory(), 1.0, direction, method, UPPER, STEPS, fast=True, **kw)
    return ex, fa


@pytest.mark.parametrize("case", sorted(ANALYTIC))
def test_prp_fast_path_is_exact_on_analytic_models(case):
    for d in DIRS:
        ex, fa = both(ANALYTIC[case], d, "prp")
        assert ex.unbounded == fa.unbounded
        if not ex.unbounded:
            # PRP verdicts of the fast path are exact (a feasible mode proves resistibility)
            assert fa.magnitude == pytest.approx(ex.magnitude, abs=1e-9)
        assert fa.n_miqp <= ex.n_miqp


@pytest.mark.parametrize("case", ["pinch", "palm", "coupled", "wedge"])
def test_iterative_fast_path_matches_exact_on_analytic_models(case):
    model = ANALYTIC[case]()
    for d in DIRS[:4]:
        ex = pg.max_resistible_wrench(model, 1.0, d, "iterative", UPPER, STEPS, fast=False)
        # one fast model reused across directions: warm starts from the previous direction's mode
        fa = pg.max_resistible_wrench(model, 1.0, d, "iterative", UPPER, STEPS, fast=True)
        assert ex.unbounded == fa.unbounded, d
        if not ex.unbounded:
            assert abs(fa.magnitude - ex.magnitude) <= RES + 1e-9, d


def test_fast_forces_equal_exact_forces():
    m = analytic.pinch(planar=False)
    for w in ([0, 3.0, 0, 0, 0, 0], [1.0, 2.0, 0.5, 0, 0, 0], [0, 6.0, 0, 0, 0, 0]):
        a = pg.passive_response(m, 1.0, w, fast=False)
        b = pg.passive_response(m, 1.0, w, fast=True)
        assert a.resistible == b.resistible
        np.testing.assert_allclose(b.contact_forces, a.contact_forces, atol=1e-7)
        c = pg.passive_response(m, 1.0, w, method="iterative", fast=False)
        d = pg.passive_response(m, 1.0, w, method="iterative", fast=True)
        assert c.resistible == d.resistible
        np.testing.assert_allclose(d.contact_forces, c.contact_forces, atol=1e-6)


def _random_factory(seed):
    if seed % 2:
        return lambda: random_grasp(seed, n_pairs=2, planar=True)
    return lambda: random_grasp(seed, n_pairs=1, contacts_per_finger=2, planar=True)


def _random_dirs(seed, n=2):
    rng = np.random.default_rng(1000 + seed)
    out = []
    for _ in range(n):
        d = np.zeros(6)
        d[[0, 1, 5]] = rng.normal(size=3) * [1, 1, 0.05]
        out.append(d)
    return out


@pytest.mark.parametrize(
    "seed", [1, 3, pytest.param(0, marks=pytest.mark.slow), pytest.param(2, marks=pytest.mark.slow)]
)
def test_random_planar_grasps_prp(seed):
    """PRP verdicts of the fast path are exact: identical magnitudes. Odd seeds: two pairs of
    single-contact fingers; even seeds (slow): one pair of two-contact coupled fingers."""
    for d in _random_dirs(seed):
        ex, fa = both(_random_factory(seed), d, "prp")
        assert ex.unbounded == fa.unbounded
        if not ex.unbounded:
            assert fa.magnitude == pytest.approx(ex.magnitude, abs=1e-9)


@pytest.mark.parametrize("seeds", [(1, 3), pytest.param((0, 2), marks=pytest.mark.slow)])
def test_random_planar_grasps_iterative(seeds):
    """The iterative verdict is a trajectory's: where the net wrench creeps down to ``eps`` at
    ~1 % per step, a different (equally optimal, or locally optimal) step can flip it. Stated
    tolerance (docs/error_vs_runtime.md): same classification on >= 3/4 of the directions,
    finite magnitudes within 5 %."""
    agree, total = 0, 0
    for seed in seeds:
        for d in _random_dirs(seed):
            ex, fa = both(_random_factory(seed), d, "iterative")
            total += 1
            if ex.unbounded == fa.unbounded:
                agree += 1
                if not ex.unbounded:
                    assert abs(fa.magnitude - ex.magnitude) <= max(RES, 0.05 * ex.magnitude) + 1e-9
    assert agree >= 0.75 * total


def test_random_grasp_preload_is_in_equilibrium():
    for seed in range(5):
        for cpf in (1, 2):
            m = random_grasp(seed, n_pairs=2, contacts_per_finger=cpf)
            r = pg.passive_response(m, 1.0, np.zeros(6))
            assert r.resistible and r.audit.equilibrium < 1e-8
            assert m.nc == 4 * cpf


def test_infeasible_guess_falls_back_and_is_counted():
    m = analytic.pinch()
    s = pg.solver_for(m, fast=True)
    ok = s.response(1.0, [0, 3.0, 0], "prp")
    assert ok.resistible
    # a guess with both contacts separated cannot carry the load: the MIQP answers
    data = s.form.scale_data(np.array([0, 3.0, 0]), m.command_vector(1.0))
    before = s.stats["prp"].infeasible
    s.fast("prp").recent.clear()  # no other recently accepted mode to try either
    raw = s.solve("prp", data, guess=Mode((False, False), (True, True)))
    assert raw.path == "fallback" and raw.status == "optimal"
    assert s.stats["prp"].infeasible == before + 1
    assert raw.mode.touching == (True, True)
    # a load beyond the limit: guess fails, MIQP says infeasible
    far = s.response(1.0, [0, 30.0, 0], "prp")
    assert not far.resistible and far.n_miqp >= 1


def test_stop_certification_prevents_a_stalled_guess():
    """Pushing the single-step pinch sideways after a +y query: the +y mode (both fingers
    yielding) is locally optimal but stalls; only the certified stop finds the holding mode."""

    def run(certify):
        m = analytic.pinch()
        kw = dict(variant="single-step", certify=certify)
        pg.max_resistible_wrench(m, 1.0, "fy", "iterative", UPPER, STEPS, **kw)
        return pg.max_resistible_wrench(m, 1.0, "fx", "iterative", UPPER, STEPS, **kw)

    exact = pg.max_resistible_wrench(
        analytic.pinch(), 1.0, "fx", "iterative", UPPER, STEPS, variant="single-step", fast=False
    )
    assert exact.unbounded
    assert run(True).unbounded
    assert not run(False).unbounded  # the uncertified fast path is wrong here: why certify=True


def test_check_local_optimality_finds_a_better_switched_mode():
    m = analytic.pinch()
    s = pg.solver_for(m, fast=True)
    qp = s.fast("prp").qp
    data = s.form.scale_data(np.zeros(3), m.command_vector(1.0))
    exact = s.solve_exact("prp", data)
    # at w = 0 the preload is an equilibrium with c_n = f_c / L > 0 on both contacts
    assert exact.status == "optimal" and np.all(s.form.E @ exact.z[: s.form.nb] > 0)
    sol = qp.solve(data, exact.mode)
    ok, _, better = qp.check_local_optimality(data, sol)
    assert ok and better is None


@pytest.mark.parametrize(
    "case, direction, expected",
    [
        ("pinch", "fy", 10.0),
        ("pinch", [1.0, 1.0, 0, 0, 0, 0], 10.0 * np.sqrt(2)),
        ("pinch3d", "-fy", 10.0),
        ("palm", "-fy", np.inf),
        ("coupled", "fy", 2 * 0.5 / (0.1 + 0.04 / 3)),
        ("wedge", "fy", np.inf),
    ],
)
def test_direct_load_factor_matches_closed_form_and_bisection(case, direction, expected):
    m = ANALYTIC[case]()
    direct = pg.max_resistible_wrench(m, 1.0, direction, "prp", UPPER, search="direct")
    bis = pg.max_resistible_wrench(m, 1.0, direction, "prp", UPPER, STEPS)
    assert direct.search == "direct" and direct.unbounded == bis.unbounded == np.isinf(expected)
    if not np.isinf(expected):
        assert direct.magnitude == pytest.approx(expected, abs=1e-6)
        assert bis.magnitude <= direct.magnitude <= bis.magnitude + RES
        # preload check, upper-limit test, load-factor MILP, response at the limit: at most 4
        assert direct.response.resistible and direct.n_miqp <= 4 < bis.n_miqp


def test_direct_search_is_prp_only():
    with pytest.raises(pg.InvalidInputError, match="prp"):
        pg.max_resistible_wrench(analytic.pinch(), 1.0, "fy", "iterative", search="direct")
    with pytest.raises(pg.InvalidInputError, match="search"):
        pg.max_resistible_wrench(analytic.pinch(), 1.0, "fy", "prp", search="golden")


def test_parallel_profile_equals_sequential():
    m = analytic.pinch()
    a = pg.resistance_profile(m, 1.0, n=8, method="prp", upper=UPPER, steps=10)
    b = pg.resistance_profile(analytic.pinch(), 1.0, n=8, method="prp", upper=UPPER, steps=10, workers=2)
    np.testing.assert_array_equal(a.unbounded, b.unbounded)
    np.testing.assert_allclose(a.magnitudes, b.magnitudes)
    with pytest.raises(pg.InvalidInputError, match="workers"):
        pg.resistance_profile(m, 1.0, n=4, method="prp", workers=-1)


def test_verified_bisection_returns_the_exact_paths_bracket():
    for d in ("fy", [1.0, 1.0, 0, 0, 0, 0], "fx"):
        ex = pg.max_resistible_wrench(analytic.pinch(), 1.0, d, "iterative", UPPER, STEPS, fast=False)
        ve = pg.max_resistible_wrench(analytic.pinch(), 1.0, d, "iterative", UPPER, STEPS, verify=True)
        assert ve.unbounded == ex.unbounded
        if not ex.unbounded:
            assert ve.magnitude == pytest.approx(ex.magnitude, abs=1e-12)
            # the bracket's two ends were re-tested by the exact path: last two evidence entries
            (m1, ok1), (m2, ok2) = ve.evidence[-2:]
            assert ok1 and not ok2 and m2 - m1 == pytest.approx(RES)


def test_a_failed_certificate_fails_the_stop(monkeypatch):
    """A certificate MIQP that times out must not leave the guessed "not resisted" standing."""
    from pinograsp.solvers.base import TIMEOUT, RawSolution

    m = analytic.pinch()
    kw = dict(variant="single-step", certify=True)
    pg.max_resistible_wrench(m, 1.0, "fy", "iterative", UPPER, STEPS, **kw)  # leaves the +y mode
    solver = pg.solver_for(m, **kw)

    class TimesOut:
        def solve(self, data):
            return RawSolution(status=TIMEOUT, solve_time=1.0, message="timelimit")

    monkeypatch.setattr(type(solver), "certifier", lambda self: TimesOut())
    r = pg.passive_response(m, 1.0, [5.0, 0, 0], "iterative", **kw)
    assert r.status == "timeout" and not r.resistible
    with pytest.raises(pg.SolverTimeoutError):
        pg.max_resistible_wrench(m, 1.0, "fx", "iterative", UPPER, STEPS, **kw)


def test_gap_limited_certificate_gives_the_exact_verdicts():
    """The certificate may stop at CERTIFY_GAP; verdicts equal the exact path on random grasps."""
    from pinograsp.response import CERTIFY_GAP

    assert 0 < CERTIFY_GAP <= 1e-3
    for seed in range(3):
        ex = pg.max_resistible_wrench(random_grasp(seed), 1.0, "fx", "iterative", 20.0, 8, fast=False)
        fa = pg.max_resistible_wrench(random_grasp(seed), 1.0, "fx", "iterative", 20.0, 8, fast=True)
        assert ex.unbounded == fa.unbounded
        assert fa.magnitude == pytest.approx(ex.magnitude, abs=20.0 / 2**8)
