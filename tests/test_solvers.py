"""Solver paths: every backend against the exact answer, big-M retry, time-outs, the
branch-and-bound against brute force over modes, and solver errors."""

import itertools
import warnings

import numpy as np
import pytest

import pinograsp as pg
from pinograsp.solvers import BranchAndBound, Formulation, Mode, available_miqp_solvers, build_problem

TAU = 1.0


@pytest.mark.parametrize("solver", available_miqp_solvers())
def test_each_installed_miqp_backend_matches_closed_form(pinch, solver):
    kw = dict(solver=solver, backend="miqp")
    r = pg.max_resistible_wrench(pinch, TAU, "fy", method="prp", upper=100, steps=16, **kw)
    assert 10.0 - 100 / 2**16 <= r.magnitude <= 10.0
    r = pg.passive_response(pinch, TAU, [20.0, 5.0, 0], method="iterative", **kw)
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
    for _ in range(2):
        w = rng.normal(size=3) * [2, 2, 0.05]
        data = form.scale_data(w, np.ones(m.na))
        bb = BranchAndBound(build_problem(form, "prp", data))
        best = np.inf
        for bits in itertools.product([False, True], repeat=m.nc + m.na):
            sol = bb.solve_mode(Mode(bits[: m.nc], bits[m.nc :]))
            if sol.status == "optimal":
                best = min(best, sol.objective)
        r = pg.passive_response(m, 1.0, w, method="prp")
        assert r.resistible == np.isfinite(best)
        if r.resistible:
            energy = np.sum(r.normal_forces**2) / data.F**2
            assert energy == pytest.approx(best, rel=1e-6, abs=1e-9)


def test_bigm_retry_and_warning(pinch):
    # a deliberately tiny big-M: the first solve saturates, the retry enlarges M and succeeds
    kw = dict(method="prp", backend="miqp")
    r = pg.passive_response(pinch, TAU, [30.0, 0, 0], bigm=2.0, bigm_retries=2, **kw)
    assert r.resistible and r.audit.bigm_retries >= 1 and r.audit.bigm_ratio < 0.1
    np.testing.assert_allclose(r.normal_forces, [10.0, 40.0], atol=1e-6)
    # no retries allowed: reported, not silently returned
    with pytest.warns(pg.BigMWarning):
        r = pg.passive_response(pinch, TAU, [30.0, 0, 0], bigm=5.0, bigm_retries=0, **kw)
    assert r.audit.bigm_ratio >= 0.1 and not r.audit.ok


def test_timeout_is_reported_not_answered(pinch):
    m = random_model(7, nc=6)
    kw = dict(method="prp", time_limit=1e-6, backend="miqp")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = pg.passive_response(m, 1.0, [1.0, 2.0, 0.01], **kw)
    assert r.status == "timeout" and not r.resistible
    with pytest.raises(pg.SolverTimeoutError):
        pg.max_resistible_wrench(m, 1.0, "fy", **kw)


def test_node_limit_is_reported_not_answered():
    """The branch-and-bound's limit is a count: hitting it is a status, never an answer."""
    m = random_model(7, nc=6)
    r = pg.passive_response(m, 1.0, [1.0, 2.0, 0.01], method="prp", max_nodes=1)
    assert r.status == "node_limit" and not r.resistible
    with pytest.raises(pg.SolverError, match="node limit"):
        pg.max_resistible_wrench(m, 1.0, "fy", method="prp", max_nodes=1)


def test_missing_and_unknown_solvers(pinch):
    with pytest.raises(pg.SolverNotAvailableError, match="install"):
        pg.passive_response(pinch, TAU, [0, 1, 0], "prp", solver="mosek", backend="miqp")
    # the session builds a backend only for a method that solves complementarity problems: the
    # default (quasi-static) path answers without one
    r = pg.passive_response(pinch, TAU, [0, 1, 0], solver="mosek", backend="miqp")
    assert r.method == "quasistatic" and r.resistible
    with pytest.raises(pg.SolverNotAvailableError, match="supported"):
        pg.passive_response(pinch, TAU, [0, 1, 0], solver="simplex9000")
    with pytest.raises(pg.InvalidInputError, match="backend"):
        pg.passive_response(pinch, TAU, [0, 1, 0], backend="gurobi")


def test_no_hidden_state_between_queries(pinch):
    """Every public query gets its own session: answers do not depend on what ran before."""
    assert pg.Session(pinch) is not pg.Session(pinch)
    first = pg.passive_response(pinch, TAU, [3.0, 4.0, 0], method="iterative")
    for w in ([40.0, 0, 0], [0, -9.0, 0], [1.0, 12.0, 0.0]):  # unrelated queries
        pg.passive_response(pinch, TAU, w, method="iterative")
        pg.passive_response(pinch, TAU, w, method="prp")
    again = pg.passive_response(pinch, TAU, [3.0, 4.0, 0], method="iterative")
    assert again.status == first.status and again.residual_history == first.residual_history
    assert np.array_equal(again.contact_forces, first.contact_forces)
    # a caller-owned session shares only pure preload stages: the same bits again
    session = pg.Session(pinch)
    assert np.array_equal(
        session.response(TAU, [3.0, 4.0, 0], "iterative").contact_forces, first.contact_forces
    )


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

    form = Formulation(pinch)
    data = form.scale_data(np.array([0.0, 5.0, 0.0]), pinch.command_vector(TAU))
    return CvxpyMIQP(form, "prp", time_limit=10.0), data


@pytest.mark.skipif("SCIP" not in [s.upper() for s in available_miqp_solvers()], reason="SCIP missing")
def test_scip_time_limit_with_incumbent_is_a_timeout(pinch, monkeypatch):
    """SCIP stopping at its time limit with an incumbent (cvxpy: "optimal_inaccurate") is a
    time-out, read from cvxpy's status dict, and is never retried with other settings (a
    retry would make the verdict depend on the machine's speed)."""
    import pinograsp.solvers.miqp as mq

    miqp, data = _pinch_miqp(pinch)
    good = miqp.solve(data, 1e3)
    assert good.status == "optimal" and good.message == "optimal"
    monkeypatch.setattr(mq, "_backend_status", lambda problem: "timelimit")
    sol = miqp.solve(data, 1e3)
    assert sol.status == "timeout" and sol.z is None
