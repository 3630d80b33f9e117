"""Solver paths: every backend against the exact answer, big-M retry, polish, time-outs,
fixed-mode QP against brute force over modes, and solver errors."""

import itertools
import warnings

import numpy as np
import pytest

import pinograsp as pg
from pinograsp.solvers import Formulation, Mode, available_miqp_solvers
from pinograsp.solvers.fixed_mode import FixedModeQP

TAU = 1.0


@pytest.mark.parametrize("solver", available_miqp_solvers())
def test_each_installed_miqp_backend_matches_closed_form(pinch, solver):
    r = pg.max_resistible_wrench(pinch, TAU, "fy", method="prp", upper=100, steps=16, solver=solver)
    assert 10.0 - 100 / 2**16 <= r.magnitude <= 10.0
    r = pg.passive_response(pinch, TAU, [20.0, 5.0, 0], method="iterative", solver=solver)
    np.testing.assert_allclose(r.normal_forces, [10.0, 30.0], atol=1e-6)


def random_model(seed, nc=3):
    rng = np.random.default_rng(seed)
    cs = []
    for i in range(nc):
        ang = 2 * np.pi * i / nc + rng.uniform(-0.3, 0.3)
        p = 0.05 * np.array([np.cos(ang), np.sin(ang), 0])
        n = -p / np.linalg.norm(p)
        piv = p + 0.08 * np.array([np.sin(ang), -np.cos(ang), 0]) * rng.choice([-1, 1])
        axis = np.array([0, 0, 1.0])
        jac_col = np.cross(axis, p - piv)
        if jac_col @ n < 0:
            axis = -axis
        cs.append(
            pg.Contact.revolute(
                p,
                n,
                {i: (piv, axis)},
                nq=nc,
                mu=rng.uniform(0.2, 0.8),
                stiffness=rng.uniform(0.5, 2),
                name=f"c{i}",
            )
        )
    return pg.GraspModel.from_contacts(cs, planar=True)


@pytest.mark.parametrize("seed", range(2))
def test_prp_optimum_equals_best_fixed_mode_qp(seed):
    """Brute force over all 2^(nc+na) modes with the fixed-mode QP is the exact oracle of the
    PRP on small models: same feasibility verdict and the same minimum spring energy."""
    m = random_model(seed)
    rng = np.random.default_rng(100 + seed)
    form = Formulation(m)
    qp = FixedModeQP(form, "prp")
    for _ in range(2):
        w = rng.normal(size=3) * [2, 2, 0.05]
        data = form.scale_data(w, np.ones(m.na))
        best = np.inf
        for bits in itertools.product([False, True], repeat=m.nc + m.na):
            sol = qp.solve(data, Mode(bits[: m.nc], bits[m.nc :]))
            if sol.status == "optimal":
                best = min(best, sol.objective)
        r = pg.passive_response(m, 1.0, w, method="prp")
        assert r.resistible == np.isfinite(best)
        if r.resistible:
            energy = np.sum(r.normal_forces**2) / data.F**2
            assert energy == pytest.approx(best, rel=1e-6, abs=1e-9)


def test_bigm_retry_and_warning(pinch):
    # a deliberately tiny big-M: the first solve saturates, the retry enlarges M and succeeds
    r = pg.passive_response(pinch, TAU, [30.0, 0, 0], method="prp", bigm=2.0, bigm_retries=2)
    assert r.resistible and r.audit.bigm_retries >= 1 and r.audit.bigm_ratio < 0.1
    np.testing.assert_allclose(r.normal_forces, [10.0, 40.0], atol=1e-6)
    # no retries allowed: reported, not silently returned
    with pytest.warns(pg.BigMWarning):
        r = pg.passive_response(pinch, TAU, [30.0, 0, 0], method="prp", bigm=5.0, bigm_retries=0)
    assert r.audit.bigm_ratio >= 0.1 and not r.audit.ok


def test_unpolished_solution_is_audited(pinch):
    r = pg.passive_response(pinch, TAU, [3.0, 4.0, 0], method="prp", polish=False)
    assert r.resistible and not r.audit.polished
    assert r.audit.complementarity < 1e-5 * 40 and r.audit.equilibrium < 1e-6
    np.testing.assert_allclose(r.normal_forces, [10.0, 13.0], atol=1e-5)


def test_timeout_is_reported_not_answered(pinch):
    m = random_model(7, nc=6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = pg.passive_response(m, 1.0, [1.0, 2.0, 0.01], method="prp", time_limit=1e-6)
    assert r.status == "timeout" and not r.resistible
    with pytest.raises(pg.SolverTimeoutError):
        pg.max_resistible_wrench(m, 1.0, "fy", method="prp", time_limit=1e-6)


def test_missing_and_unknown_solvers(pinch):
    with pytest.raises(pg.SolverNotAvailableError, match="install"):
        pg.passive_response(pinch, TAU, [0, 1, 0], solver="mosek")
    with pytest.raises(pg.SolverNotAvailableError, match="supported"):
        pg.passive_response(pinch, TAU, [0, 1, 0], solver="simplex9000")


def test_solver_is_built_once_per_model_and_settings(pinch):
    s1 = pg.solver_for(pinch)
    s2 = pg.solver_for(pinch)
    assert s1 is s2 and pg.solver_for(pinch, gamma=2.0) is not s1
    n0 = s1.exact("prp").miqp.n_solves
    pg.passive_response(pinch, TAU, [0, 1, 0])
    a0 = s1.stats["prp"].accepted
    pg.passive_response(pinch, TAU, [0, 2, 0])
    # at most the first solve is a MIQP; the second reuses its mode (fast path)
    assert s1.exact("prp").miqp.n_solves <= n0 + 1
    assert s1.stats["prp"].accepted == a0 + 1
    exact = pg.solver_for(pinch, fast=False)
    m0 = exact.exact("prp").miqp.n_solves
    pg.passive_response(pinch, TAU, [0, 1, 0], fast=False)
    pg.passive_response(pinch, TAU, [0, 2, 0], fast=False)
    assert exact.exact("prp").miqp.n_solves == m0 + 2


def test_iterative_reports_history_and_cap(pinch):
    r = pg.passive_response(pinch, TAU, [40.0, 0, 0], method="iterative")
    assert r.converged and r.residual_history[-1] <= 1e-3 and r.iterations == len(r.residual_history)
    assert all(b <= a for a, b in zip(r.residual_history, r.residual_history[1:]))
    capped = pg.passive_response(
        pinch, TAU, [400.0, 0, 0], method="iterative", gamma=0.05, max_iterations=2, variant="single-step"
    )
    assert capped.status == "not_converged" and not capped.resistible and capped.iterations == 2


def _pinch_miqp(pinch):
    from pinograsp.solvers.miqp import CvxpyMIQP

    s = pg.solver_for(pinch)
    data = s.form.scale_data(np.array([0.0, 5.0, 0.0]), pinch.command_vector(TAU))
    return CvxpyMIQP(s.form, "prp", time_limit=10.0), data


@pytest.mark.skipif("SCIP" not in [s.upper() for s in available_miqp_solvers()], reason="SCIP missing")
def test_backend_status_is_read_from_cvxpy(pinch):
    """cvxpy 1.9 keeps SCIP's status in a dict: reading it is what tells a time-out from an optimum."""
    from pinograsp.solvers.miqp import _backend_status

    miqp, data = _pinch_miqp(pinch)
    sol = miqp.solve(data, 1e3)
    assert sol.status == "optimal" and _backend_status(miqp.problem) == "optimal"


@pytest.mark.skipif("SCIP" not in [s.upper() for s in available_miqp_solvers()], reason="SCIP missing")
def test_scip_time_limit_with_incumbent_is_a_timeout_then_retried(pinch, monkeypatch):
    """SCIP stopping at its time limit with an incumbent (cvxpy: "optimal_inaccurate") is a
    time-out; the big-M solve re-runs once with SCIP_RETRY and reports both attempts."""
    import pinograsp.solvers.miqp as mq

    miqp, data = _pinch_miqp(pinch)
    good = miqp.solve(data, 1e3)
    calls = []

    def fake(problem):
        calls.append(1)
        return "timelimit" if len(calls) == 1 else "optimal"

    monkeypatch.setattr(mq, "_backend_status", fake)
    sol = miqp.solve(data, 1e3)
    assert sol.status == "optimal" and miqp.n_retries == 1 and "re-run" in sol.message
    np.testing.assert_allclose(sol.z, good.z, atol=1e-6)
    monkeypatch.setattr(mq, "_backend_status", lambda problem: "timelimit")
    sol = miqp.solve(data, 1e3)
    assert sol.status == "timeout" and sol.z is None and miqp.n_retries == 2
