"""Numerical stability on stiff and extreme cases.

The stress catalogue is ``tests/data/stress_catalogue.yaml``, read and judged by
``tests/support/stress.py`` (``tests/support/stability.py`` writes its report, ``docs/stability.md``): every
case has a closed-form nominal answer and must be answered within the stated tolerance or flagged
(error, warning, audit) — never silently wrong. The ``quick`` cases run by default, the full grid
with ``pytest -m slow``. Cases marked ``known`` are silent errors whose fix lies outside the
solvers (see docs/stability.md); they are ``xfail``.

Below the catalogue: the MIQP's own safeguards (per-row big-M, verified infeasibility,
integrality artefacts, empty equilibrium rows, indicator constraints, SCIP's stdout line).
"""

from __future__ import annotations

import itertools
import os

import numpy as np
import pytest
from support.grasps import double_pinch, pinch_contacts, with_stiffness
from support.stress import catalogue, run_case

import pinograsp as pg
from pinograsp import examples
from pinograsp.solvers import BranchAndBound, Formulation, Mode, ScaledData, build_problem
from pinograsp.solvers.miqp import CvxpyMIQP, quiet_stdout

CASES = catalogue()


def _param(i, case):
    marks = []
    if not case.quick:
        marks.append(pytest.mark.slow)
    if case.known:
        marks.append(pytest.mark.xfail(reason=f"known: {case.known} (docs/stability.md)", strict=False))
    cid = f"{i:03d}-{case.group}-{case.name}-{case.method}-{case.query}".replace(" ", "_")
    return pytest.param(case, marks=marks, id=cid)


@pytest.mark.parametrize("case", [_param(i, c) for i, c in enumerate(CASES)])
def test_stress_case(case):
    out = run_case(case)
    assert out.verdict != "WRONG", (
        f"silently wrong: {out.case} ({out.method}, {out.query}): {out.answer} vs nominal {out.nominal} "
        f"(relative deviation {out.deviation:.3g}) {out.notes}"
    )


def test_catalogue_covers_every_stress_group():
    groups = {c.group for c in CASES}
    assert groups >= {
        "uniform stiffness",
        "stiffness ratio",
        "friction",
        "large wrench",
        "homogeneity",
        "preload",
        "units",
        "degenerate",
        "pyramid edges",
        "many contacts",
    }
    assert sum(c.quick for c in CASES) >= 40 and len(CASES) >= 300


# ------------------------------------------------------------------------------ MIQP safeguards
def _stiff_pinch(kl, kr):
    return with_stiffness(examples.pinch(), (kl, kr))


def test_bigm_rows_scale_with_the_stiffness_spread():
    m = _stiff_pinch(1e4, 1.0)
    f = Formulation(m)
    data = f.scale_data(np.zeros(3), np.ones(2))
    factor = build_problem(f, "prp", data).bigm_factor  # (pair, side): contacts, then actuators
    np.testing.assert_allclose(factor[:2, 1], [1e4, 1.0])  # spring gaps
    np.testing.assert_allclose(factor[2:, 0], [1e4, 1.0])  # actuator displacements
    f1 = Formulation(examples.pinch(k=1e3))
    np.testing.assert_allclose(
        build_problem(f1, "prp", f1.scale_data(np.zeros(3), np.ones(2))).bigm_factor, 1.0
    )


@pytest.mark.parametrize("ratio", [1e4, 1e6])
@pytest.mark.filterwarnings("ignore::pinograsp.ConditioningWarning")
def test_stiff_left_contact_without_verification(ratio):
    """Before the per-row big-M the MIQP said 'infeasible' here: every solution moved the stiff finger's
    actuator beyond M = 1e3 (scaled). The per-row M alone (no verification) fixes it."""
    m = _stiff_pinch(ratio, 1.0)
    f = Formulation(m)
    mi = CvxpyMIQP(f, "prp", verify_infeasible=False)
    data = f.scale_data(np.array([3.0, 4.0, 0.0]), np.ones(2))
    sol = mi.solve(data, 1e3)
    assert sol.status == "optimal" and sol.bigm_ratio < 0.1
    r = pg.passive_response(m, 1.0, [3.0, 4.0, 0.0], method="prp", backend="miqp")
    np.testing.assert_allclose(r.normal_forces, [10.0, 13.0], atol=1e-5)
    if ratio > 1e5:  # beyond the branch-and-bound's node QPs: it says so
        with pytest.warns(pg.ConditioningWarning, match="backend='miqp'"):
            pg.Session(m)
    else:
        r = pg.passive_response(m, 1.0, [3.0, 4.0, 0.0], method="prp")
        np.testing.assert_allclose(r.normal_forces, [10.0, 13.0], atol=1e-5)


def test_infeasible_verdict_is_verified_with_a_larger_m():
    """M = 0.05 (scaled) cuts off the pinch's solution at w = (3, 4): the first solve is
    infeasible, the verification with 100 M finds it."""
    m = examples.pinch()
    f = Formulation(m)
    data = f.scale_data(np.array([3.0, 4.0, 0.0]), np.ones(2))
    unverified = CvxpyMIQP(f, "prp", verify_infeasible=False)
    assert unverified.solve(data, 0.05).status == "infeasible"
    verified = CvxpyMIQP(f, "prp")
    sol = verified.solve(data, 0.05)
    assert sol.status == "optimal" and "solved with M = 5" in sol.message
    # a truly infeasible load stays infeasible, and says which M verified it
    data = f.scale_data(np.array([0.0, 30.0, 0.0]), np.ones(2))
    sol = verified.solve(data, 1e3)
    assert sol.status == "infeasible" and "verified with M = 1e+05" in sol.message


def test_integrality_artefact_of_the_verification_is_rejected():
    """The rotated 3D pinch 0.1 % above its limit: with 100 M, SCIP returns a point whose
    complementarity leaks (integrality tolerance x M); it fits inside the first M, so it is an
    artefact and the verdict stays 'not resisted'."""
    Rm = np.array([[np.cos(0.7), -np.sin(0.7), 0], [np.sin(0.7), np.cos(0.7), 0], [0, 0, 1]])
    Rm = Rm @ np.array([[1, 0, 0], [0, np.cos(0.4), -np.sin(0.4)], [0, np.sin(0.4), np.cos(0.4)]])
    t = np.array([0.3, -0.2, 0.5])
    base = pinch_contacts()
    moved = [
        pg.Contact(
            Rm @ c.point + t, Rm @ c.normal, jacobian=Rm @ c.jacobian, tangent=Rm @ c.tangent, name=c.name
        )
        for c in base
    ]
    m = pg.GraspModel.from_contacts(moved, reference_point=t, joint_names=("left", "right"))
    d = np.concatenate([Rm @ [0, 1.0, 0], [0, 0, 0]])
    assert pg.passive_response(m, 1.0, 9.99 * d, method="prp").resistible
    for mag in (10.0098, 10.05):
        r = pg.passive_response(m, 1.0, mag * d, method="prp")
        assert not r.resistible, mag


@pytest.mark.parametrize("method", ["prp", "iterative"])
def test_wrench_component_no_contact_can_produce(method):
    """cvxpy's SCIP interface drops a constraint row without variables: a mu = 0 pinch under a
    tangential load was 'optimal' (then 'failed', and the bisection raised SolverError)."""
    m = examples.pinch(mu=0.0)
    r = pg.passive_response(m, 1.0, [0.0, 1.0, 0.0], method=method)
    assert r.status == "not_resisted" and not r.resistible
    mw = pg.max_resistible_wrench(m, 1.0, "fy", method=method, upper=10, steps=8)
    assert not mw.unbounded and mw.magnitude <= (0.0 if method == "prp" else 1e-3 + 10 / 2**8)
    f = Formulation(m)
    sol = CvxpyMIQP(f, "prp").solve(f.scale_data(np.array([0.0, 1.0, 0.0]), np.ones(2)), 1e3)
    assert sol.status == "infeasible" and "fy" in sol.message


def _random_model(seed, nc=3, spread=0.0):
    rng = np.random.default_rng(seed)
    cs = []
    for i in range(nc):
        ang = 2 * np.pi * i / nc + rng.uniform(-0.3, 0.3)
        p = 0.05 * np.array([np.cos(ang), np.sin(ang), 0])
        n = -p / np.linalg.norm(p)
        piv = p + 0.08 * np.array([np.sin(ang), -np.cos(ang), 0]) * rng.choice([-1, 1])
        axis = np.array([0, 0, 1.0])
        if np.cross(axis, p - piv) @ n < 0:
            axis = -axis
        k = 10 ** rng.uniform(-spread, spread)
        cs.append(pg.Contact.revolute(p, n, {i: (piv, axis)}, nq=nc, mu=rng.uniform(0.2, 0.8), stiffness=k))
    return pg.GraspModel.from_contacts(cs, planar=True)


@pytest.mark.parametrize("seed, spread", [(0, 0.0), (1, 3.0), (2, 6.0)])
def test_indicator_constraints_match_bigm(seed, spread):
    """SCIP indicator constraints (no M): the same verdicts and optimal energies as the big-M
    model, on stiffness spreads up to 1e6 too."""
    m = _random_model(seed, spread=spread)
    f = Formulation(m)
    bigm, ind = CvxpyMIQP(f, "prp"), CvxpyMIQP(f, "prp", options={"complementarity": "indicator"})
    assert ind.complementarity == "indicator"
    rng = np.random.default_rng(100 + seed)
    for _ in range(4):
        w = rng.normal(size=3) * [2, 2, 0.05]
        data = f.scale_data(w, np.ones(m.na))
        a, b = bigm.solve(data, 1e3), ind.solve(data, 1e3)
        assert a.status == b.status
        if a.status == "optimal":
            assert b.bigm_ratio == 0.0 and b.backend == "scip-indicator"
            assert a.objective == pytest.approx(b.objective, rel=1e-5, abs=1e-8)


def test_indicator_constraints_match_brute_force():
    """... and both match brute force over all modes with the exact fixed-mode QP."""
    m = with_stiffness(examples.pinch(h=0.01), (1e3, 1.0))  # the wedge with a stiffness ratio
    f = Formulation(m)
    ind = CvxpyMIQP(f, "prp", complementarity="indicator")
    for w in ([3.0, -4.0, 0.02], [-1.5, 12.0, -0.3]):
        data = f.scale_data(np.array(w), np.ones(m.na))
        bb = BranchAndBound(build_problem(f, "prp", data))
        best = np.inf
        for bits in itertools.product([False, True], repeat=m.nc + m.na):
            sol = bb.solve_mode(Mode(bits[: m.nc], bits[m.nc :]))
            if sol.status == "optimal":
                best = min(best, sol.objective)
        b = ind.solve(data, 1e3)
        own = bb.solve()
        assert b.status == own.status == ("optimal" if np.isfinite(best) else "infeasible")
        if np.isfinite(best):
            assert b.objective == pytest.approx(best, rel=1e-5, abs=1e-8)
            assert own.objective == pytest.approx(best, rel=1e-9, abs=1e-12)


def test_indicator_movement_step_matches_bigm():
    m = examples.palm_pinch()
    f = Formulation(m)
    bigm, ind = CvxpyMIQP(f, "move"), CvxpyMIQP(f, "move", complementarity="indicator")
    rng = np.random.default_rng(3)
    for _ in range(4):
        w = rng.normal(size=3) * [10, 10, 0.5]
        d = f.scale_data(w, np.ones(m.na))
        d = ScaledData(d.F, d.w, d.fc, d.p, np.zeros(f.nx), d.w / np.linalg.norm(d.w))
        a, b = bigm.solve(d, 1e3), ind.solve(d, 1e3)
        assert a.status == b.status == "optimal"
        assert a.objective == pytest.approx(b.objective, rel=1e-5, abs=1e-8)


def test_miqp_options_are_validated():
    f = Formulation(examples.pinch())
    with pytest.raises(pg.InvalidInputError, match="complementarity"):
        CvxpyMIQP(f, "prp", complementarity="sos1")
    with pytest.raises(pg.InvalidInputError, match="kind"):
        CvxpyMIQP(f, "alg9")
    others = [s for s in pg.available_miqp_solvers() if s != "scip"]
    if others:
        with pytest.raises(pg.InvalidInputError, match="scip"):
            CvxpyMIQP(f, "prp", solver=others[0], complementarity="indicator")


def test_scip_gmp_line_is_dropped_and_other_output_kept(capfd):
    gmp = b"Cannot set feasibility tolerance to small value 1e-11 without GMP - using 1e-10.\n"
    with quiet_stdout():
        os.write(2, gmp)
        os.write(1, gmp)
        os.write(1, b"a line that matters\n")
        os.write(2, b"an error that matters\n")
    cap = capfd.readouterr()
    assert "without GMP" not in cap.out + cap.err
    assert "a line that matters" in cap.out and "an error that matters" in cap.err
    with quiet_stdout(False):
        os.write(1, b"verbatim\n")
    assert "verbatim" in capfd.readouterr().out


def test_highs_banner_of_the_preload_fallback_is_dropped(capfd, monkeypatch):
    """equilibrium_preload's HiGHS fallback (Clarabel failing) prints no banner: the lines
    HiGHS writes at its first solve in a process are dropped by quiet_stdout."""
    banner = (
        b"Running HiGHS 1.16.0 (git hash: f3f113d): Copyright (c) 2026 under MIT licence terms\n"
        b"Includes third-party software components, see THIRD_PARTY_NOTICES.md for full details\n"
    )
    with quiet_stdout():
        os.write(1, banner)
    assert capfd.readouterr().out == ""
    import cvxpy as cp

    solve = cp.Problem.solve

    def clarabel_fails(self, *args, solver=None, **kwargs):
        if solver == cp.CLARABEL:
            raise cp.error.SolverError("Solver 'CLARABEL' failed.")
        return solve(self, *args, solver=solver, **kwargs)

    monkeypatch.setattr(cp.Problem, "solve", clarabel_fails)
    bal = pg.equilibrium_preload(examples.pinch(), "iterative")
    assert bal.found and bal.command == {"left": 1.0, "right": 1.0}  # the design is linear: HiGHS
    assert "HiGHS" not in capfd.readouterr().out


def test_solves_print_nothing(capfd):
    """The double pinch at offset 1e-4 and a mu = 1e-3 pinch made SCIP (SoPlex) print its GMP
    line on stderr during iterative solves."""
    pg.max_resistible_wrench(double_pinch(1e-4), 1.0, "fy", method="iterative", upper=100, steps=6)
    pg.max_resistible_wrench(examples.pinch(mu=1e-3), 1.0, "fy", method="iterative", upper=0.2, steps=12)
    cap = capfd.readouterr()
    assert cap.out == "" and "GMP" not in cap.err


def test_indicator_time_out_is_reported():
    m = _random_model(7, nc=6)
    f = Formulation(m)
    mi = CvxpyMIQP(f, "prp", complementarity="indicator", time_limit=1e-6)
    assert mi.solve(f.scale_data(np.array([1.0, 2.0, 0.01]), np.ones(m.na)), 1e3).status == "timeout"
