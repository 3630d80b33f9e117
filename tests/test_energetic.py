"""The energetic (maximum-dissipation) method, cone refinement and normal uncertainty
(docs/methods.md): closed forms, bounds against the PRP, agreement with the iterative scheme,
symmetry and monotone refinement."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import pinograsp as pg
from pinograsp.errors import InvalidInputError


def _dir(deg: float) -> list[float]:
    a = math.radians(deg)
    return [math.cos(a), math.sin(a), 0.0, 0.0, 0.0, 0.0]


def _mw(model, command, d, method="energetic", **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pg.AuditWarning)
        return pg.max_resistible_wrench(model, command, d, method=method, **kw)


@pytest.mark.parametrize("deg", [30.0, 60.0, 90.0, 135.0, 270.0])
def test_pinch_band_closed_form(deg):
    # DESIGN.md §6: F_max = 2 mu tau0 / (L |sin θ|) = 10 / |sin θ| N
    r = _mw(pg.examples.pinch(), 1.0, _dir(deg), upper=1e3)
    assert r.status == "finite"
    assert r.magnitude == pytest.approx(10.0 / abs(math.sin(math.radians(deg))), rel=1e-6)


def test_pinch_along_x_unbounded():
    r = _mw(pg.examples.pinch(), 1.0, "fx", upper=1e3)
    assert r.status == "unbounded" and math.isinf(r.magnitude)


def test_differential_pinch():
    m = pg.examples.pinch(differential=True)
    assert _mw(m, 1.0, "fy", upper=1e3).magnitude == pytest.approx(10.0, rel=1e-6)
    r = _mw(m, 1.0, _dir(30.0), upper=1e3)
    assert r.status == "below_resolution" and r.magnitude == 0.0


def test_wedge_finite_where_prp_is_unbounded():
    m = pg.examples.wedge()
    prp = _mw(m, 1.0, "fy", method="prp", upper=1e3)
    energetic = _mw(m, 1.0, "fy", upper=1e3)
    iterative = _mw(m, 1.0, "fy", method="iterative", upper=1e3)
    assert prp.status == "unbounded"
    assert energetic.status == "finite"
    assert energetic.magnitude == pytest.approx(iterative.magnitude, rel=1e-3)  # 2.5565 vs 2.5568 N
    assert energetic.magnitude == pytest.approx(2.5565, abs=1e-3)


@pytest.mark.parametrize("deg", [0.0, 30.0, 60.0, 90.0, 150.0, 240.0])
def test_energetic_never_exceeds_prp(case1, deg):
    m, cmd = case1.model, case1.command
    kw = dict(upper=50.0, variant="single-step")
    prp = _mw(m, cmd, _dir(deg), method="prp", search="direct", **kw)
    energetic = _mw(m, cmd, _dir(deg), **kw)
    assert energetic.magnitude <= prp.magnitude * (1 + 1e-9)


@pytest.mark.parametrize("deg", [30.0, 60.0, 90.0, 180.0, 270.0])
def test_case1_agrees_with_iterative(case1, deg):
    m, cmd = case1.model, case1.command
    it = _mw(m, cmd, _dir(deg), method="iterative", upper=50.0)
    en = _mw(m, cmd, _dir(deg), upper=50.0)
    assert en.status == it.status
    if it.status == "finite":
        assert en.magnitude == pytest.approx(it.magnitude, rel=2e-3)


def test_case1_mirror_symmetric(case1):
    m, cmd = case1.model, case1.command
    a = _mw(m, cmd, _dir(30.0), upper=50.0)
    b = _mw(m, cmd, _dir(150.0), upper=50.0)
    assert a.magnitude == pytest.approx(b.magnitude, rel=1e-9)
    assert a.magnitude == pytest.approx(35.714, abs=2e-3)  # the simulation gives way at 35.7 N


def test_same_answer_twice(case1):
    m, cmd = case1.model, case1.command
    a = _mw(m, cmd, _dir(60.0), upper=50.0)
    b = _mw(m, cmd, _dir(60.0), upper=50.0)
    assert repr(a.magnitude) == repr(b.magnitude)
    assert np.array_equal(a.response.contact_forces, b.response.contact_forces)


def test_refinement_converges_monotonically():
    m = pg.examples.pinch(planar=False)
    d = [0.0, math.cos(math.radians(80)), math.sin(math.radians(80)), 0.0, 0.0, 0.0]
    values, edges = [], []
    for tol in (None, 8.0, 2.0, 1.0, 0.25):
        r = _mw(m, 1.0, d, upper=50.0, cone_tolerance=None if tol is None else math.radians(tol))
        values.append(r.magnitude)
        edges.append(max(r.response.edge_counts))
    # 8-edge inscribed pyramid: 10 cos(22.5°) / cos(12.5°) N; the circular cone: 10 N
    assert values[0] == pytest.approx(
        10 * math.cos(math.radians(22.5)) / math.cos(math.radians(12.5)), rel=1e-5
    )
    assert all(b >= a * (1 - 1e-9) for a, b in zip(values, values[1:]))
    assert values[-1] == pytest.approx(10.0, rel=1e-4)
    assert edges[0] == 8 and edges[-1] <= 100 and edges == sorted(edges)


def test_refinement_of_the_prp_matches():
    m = pg.examples.pinch(planar=False)
    d = [0.0, math.cos(math.radians(67.5)), math.sin(math.radians(67.5)), 0.0, 0.0, 0.0]
    r = _mw(m, 1.0, d, method="prp", upper=50.0, cone_tolerance=math.radians(1.0))
    assert r.magnitude == pytest.approx(10.0, rel=1e-4)


def test_normal_uncertainty_zero_is_nominal(case1):
    m, cmd = case1.model, case1.command
    a = _mw(m, cmd, _dir(60.0), upper=50.0)
    b = _mw(m, cmd, _dir(60.0), upper=50.0, normal_uncertainty=0.0)
    assert repr(a.magnitude) == repr(b.magnitude)


@pytest.mark.parametrize("method", ["energetic", "prp", "iterative"])
def test_normal_uncertainty_pinch_closed_form(method):
    u = math.radians(5.0)
    mu_eff = math.tan(math.atan(0.5) - u)
    r = _mw(pg.examples.pinch(), 1.0, "fy", method=method, upper=1e3, normal_uncertainty=u)
    assert r.magnitude == pytest.approx(10.0 * mu_eff / 0.5, rel=1e-4)


def test_normal_uncertainty_never_increases_resistance(case1):
    m, cmd = case1.model, case1.command
    for deg in (30.0, 90.0):
        vals = [
            _mw(m, cmd, _dir(deg), upper=50.0, normal_uncertainty=math.radians(u)).magnitude
            for u in (0.0, 1.0, 2.5, 5.0)
        ]
        assert all(b <= a * (1 + 1e-9) for a, b in zip(vals, vals[1:])), vals


def test_reference_backend_agrees():
    m = pg.examples.pinch()
    a = _mw(m, 1.0, _dir(60.0), upper=1e3)
    b = _mw(m, 1.0, _dir(60.0), upper=1e3, backend="miqp")
    assert b.magnitude == pytest.approx(a.magnitude, rel=1e-6)


@pytest.mark.parametrize("complementarity", ["bigm", "indicator"])
def test_reference_backends_on_the_wedge(complementarity):
    m = pg.examples.wedge()
    a = _mw(m, 1.0, "fy", upper=1e3)
    b = _mw(m, 1.0, "fy", upper=1e3, backend="miqp", complementarity=complementarity)
    assert b.magnitude == pytest.approx(a.magnitude, rel=1e-7)
    assert b.response.solver.startswith("scip")


def test_resistance_set_of_the_3d_pinch_is_empty():
    # two point contacts on the x axis cannot resist a torque about it: every 6D direction with
    # an mx component has limit 0 (the iterative scheme reports its tolerance, 1e-3 to 0.05 N)
    m = pg.examples.pinch(planar=False)
    rs = pg.resistance_set(m, 1.0, n=16, method="energetic", upper=50.0)
    assert np.all(np.abs(rs.directions[:, 3]) > 1e-6)
    assert rs.classes()["not_resistible"] == 16 and np.all(rs.magnitudes == 0.0)


def test_contact_states_and_slip():
    m = pg.examples.wedge()
    r = pg.passive_response(m, 1.0, [0.0, 2.0, 0.0], method="energetic")
    assert r.resistible and r.contact_states == ("sticking", "sticking")
    assert np.allclose(r.contact_slip, 0.0, atol=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pg.AuditWarning)
        prp = pg.passive_response(m, 1.0, [0.0, 3.0, 0.0], method="prp")
    # the PRP's wedging: both contacts slide, and the object moves against the load
    assert prp.contact_states == ("sliding", "sliding")
    assert prp.object_displacement[1] < 0
    d = prp.to_dict()
    assert [c["state"] for c in d["contacts"]] == ["sliding", "sliding"]
    assert [c["edges"] for c in d["contacts"]] == [2, 2]


def test_energetic_friction_opposes_slip(case1):
    # case 1 at 30°, 95 % of its limit: the sliding contacts' friction points against their
    # slip (at a pyramid edge: within the 8-edge polygon's 22.5° half sector) and is saturated
    m, cmd = case1.model, case1.command
    w = 0.95 * 35.714 * np.array(_dir(30.0))
    r = pg.passive_response(m, cmd, w, method="energetic")
    assert r.resistible
    sliding = [i for i, s in enumerate(r.contact_states) if s == "sliding"]
    assert sliding
    for i in sliding:
        n = m.frames[i][:, 0]
        f = r.contact_forces_world[i]
        ft = f - np.dot(f, n) * n
        cos = np.dot(ft, r.contact_slip[i]) / (np.linalg.norm(ft) * np.linalg.norm(r.contact_slip[i]))
        assert cos <= -math.cos(math.radians(22.5)) + 1e-9
        assert r.friction_use[i] == pytest.approx(1.0, abs=1e-6)


def test_bad_settings():
    m = pg.examples.pinch()
    with pytest.raises(InvalidInputError, match="normal_uncertainty"):
        pg.passive_response(m, 1.0, [0, 1, 0], method="energetic", normal_uncertainty=-0.1)
    with pytest.raises(InvalidInputError, match="cone_tolerance"):
        pg.max_resistible_wrench(pg.examples.pinch(planar=False), 1.0, "fy", cone_tolerance=0.01)
    with pytest.raises(InvalidInputError, match="search"):
        pg.max_resistible_wrench(m, 1.0, "fy", method="energetic", search="secant")


@pytest.fixture(scope="module")
def case3():
    sc = pg.load_scene("case3")
    return sc.model, sc.command


def test_case3_agrees_with_iterative(case3):
    m, cmd = case3
    up = _mw(m, cmd, "fy", upper=50.0)
    assert up.magnitude == pytest.approx(
        _mw(m, cmd, "fy", method="iterative", upper=50.0).magnitude, rel=2e-3
    )
    assert up.magnitude == pytest.approx(1.4834, abs=1e-3)
    assert _mw(m, cmd, "-fy", upper=50.0).status == "unbounded"
    assert _mw(m, cmd, "-fy", method="iterative", upper=50.0).status == "unbounded"


@pytest.mark.parametrize("deg", [0.0, 60.0])
def test_case3_sideways_is_zero_as_the_tight_iterative_scheme(case3, deg):
    # the iterative scheme's 0.009-0.018 N here is its equilibrium tolerance eps: tightened,
    # it agrees with the energetic answer (below the resolution)
    m, cmd = case3
    en = _mw(m, cmd, _dir(deg), upper=50.0)
    tight = _mw(m, cmd, _dir(deg), method="iterative", upper=50.0, eps=1e-6, eps_rel=1e-9)
    assert en.status == tight.status == "below_resolution"


def test_case3_where_the_iterative_scheme_stalls(case3):
    # docs/validation.md: at 255° the default iterative scheme stalls at 0.035 N; the energetic
    # answer equals the PRP's (its audit passes there) and the tightened iterative scheme's
    m, cmd = case3
    en = _mw(m, cmd, _dir(255.0), upper=50.0)
    prp = _mw(m, cmd, _dir(255.0), method="prp", search="direct", upper=50.0, variant="preload-first")
    assert en.magnitude == pytest.approx(23.1769, abs=1e-3)
    assert en.magnitude <= prp.magnitude * (1 + 1e-9) + 1e-9
    mirror = _mw(m, cmd, _dir(285.0), upper=50.0)
    assert mirror.magnitude == pytest.approx(en.magnitude, rel=1e-6)
