"""Resistance set, passive-resistance score and Ferrari–Canny epsilon (docs/metrics.md), on the
analytic pinch (+Y limit 2 mu tau0 / L = 10 N at mu 0.5, ±X unbounded) with few directions."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples
from pinograsp.cli import main

KW = dict(upper=100.0, steps=10)
A = 0.05  # pinch half-width = its length scale [m]


@pytest.fixture(scope="module")
def pinch():
    return examples.pinch(mu=0.5)


@pytest.fixture(scope="module")
def rset(pinch):
    return pg.resistance_set(pinch, 1.0, 24, **KW)


def test_sphere_points_even_and_deterministic():
    x = pg.sphere_points(200, 6, seed=3)
    assert x.shape == (200, 6)
    np.testing.assert_allclose(np.linalg.norm(x, axis=1), 1.0, atol=1e-12)
    assert np.array_equal(x, pg.sphere_points(200, 6, seed=3))
    assert not np.array_equal(x, pg.sphere_points(200, 6, seed=4))
    raw = np.random.default_rng(3).standard_normal((200, 6))
    raw /= np.linalg.norm(raw, axis=1, keepdims=True)

    def nearest(p):
        d = np.linalg.norm(p[:, None] - p[None], axis=2)
        np.fill_diagonal(d, np.inf)
        return d.min(axis=1)

    assert nearest(x).min() > 2.5 * nearest(raw).min()  # repelled: no near-duplicates
    assert nearest(x).std() / nearest(x).mean() < 0.05  # nearly equal spacing
    assert np.abs(x.mean(axis=0)).max() < 0.02  # no preferred side


def test_set_fields_and_determinism(pinch, rset):
    assert rset.n == 24 and rset.directions.shape == (24, 6) and rset.sphere.shape == (24, 6)
    assert rset.length == pytest.approx(A) and rset.length_source == "model.length_scale"
    assert np.allclose(rset.directions[:, [2, 3, 4]], 0.0)  # planar: fx, fy, mz only
    np.testing.assert_allclose(np.linalg.norm(rset.directions, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(rset.sphere, axis=1), 1.0, atol=1e-12)
    # the limit wrench is scaled * (u_f, length * u_t), and its Euclidean norm is the magnitude
    fin = np.isfinite(rset.magnitudes)
    limit = rset.scaled[:, None] * rset.sphere * np.r_[1, 1, 1, A, A, A]
    np.testing.assert_allclose(np.linalg.norm(limit[fin], axis=1), rset.magnitudes[fin], rtol=1e-12)
    again = pg.resistance_set(pinch, 1.0, 24, **KW)
    assert np.array_equal(again.directions, rset.directions)
    assert np.array_equal(again.magnitudes, rset.magnitudes) and again.statuses == rset.statuses
    other = pg.resistance_set(pinch, 1.0, 24, length=0.1, **KW)
    assert other.length_source == "given" and not np.array_equal(other.directions, rset.directions)


def test_pinch_closed_form(pinch, rset):
    # pure forces in the plane: F_max = 2 mu tau0 / (L |sin θ|) (docs/analytic_cases.md)
    th = np.radians([30.0, 90.0, 135.0, 270.0])
    d = np.column_stack([np.cos(th), np.sin(th), np.zeros(4)])
    s = pg.resistance_set(pinch, 1.0, directions=d, **KW)
    expect = 2 * 0.5 * 1.0 / (0.1 * np.abs(np.sin(th)))
    assert s.statuses == ("finite",) * 4 and s.seed is None
    assert np.all(s.magnitudes <= expect + 1e-9) and np.all(s.magnitudes > expect - 100 / 2**10 - 2e-3)
    # unbounded: ±X pushes into a non-backdrivable finger, and the one-contact wrench cone of each
    # finger (the pushed contact alone: mz = ±a fy with |fy| <= mu |fx|)
    cone = [[1, 0, 0], [-1, 0, 0], [1, 0.3, 0.3 * A], [-1, 0.3, -0.3 * A], [1, -0.4, -0.4 * A]]
    s = pg.resistance_set(pinch, 1.0, directions=cone, **KW)
    assert s.statuses == ("unbounded",) * 5 and s.unbounded.all() and np.isinf(s.magnitudes).all()
    # off that cone: finite (the wrong sign of mz, or beyond friction)
    s = pg.resistance_set(pinch, 1.0, directions=[[1, 0.3, -0.3 * A], [1, 0.7, 0.7 * A]], **KW)
    assert set(s.statuses) <= {"finite", "above_limit"} and not s.unbounded.any()
    # ... and no direction of the sphere sample is unbounded (the cone has measure zero)
    assert not rset.unbounded.any() and rset.classes()["failed"] == 0


def test_projection_equals_profile(pinch):
    dirs = pg.plane_directions(pinch, ("fx", "fy"), 12)
    s = pg.resistance_set(pinch, 1.0, directions=dirs, **KW)
    p = pg.resistance_profile(pinch, 1.0, ("fx", "fy"), 12, **KW)
    proj = s.project(("fx", "fy"))
    assert np.array_equal(proj.magnitudes, p.magnitudes)  # bit-identical
    assert np.array_equal(proj.unbounded, p.unbounded) and proj.statuses == p.statuses
    np.testing.assert_allclose(proj.angles, p.angles, atol=1e-12)
    assert proj.unbounded[0] and proj.unbounded[6]  # ±X
    with pytest.raises(pg.InvalidInputError, match="plane"):
        s.project(([0, 1, 1], [1, 0, 1]))  # meets the XY plane at 135° and 315° only: not sampled


def test_summary_dict_csv(rset, tmp_path):
    text = rset.summary()
    assert "worst direction" in text and "5%" in text and "fraction unbounded" in text
    worst = rset.worst()
    assert rset.scaled[worst] == rset.scaled.min() == rset.quantile(0.0)
    assert rset.quantile(0.05) <= rset.quantile(0.25) <= rset.quantile(0.5)
    d = json.loads(json.dumps(rset.to_dict(results=True)))
    assert d["n"] == 24 and d["classes"]["finite"] == 24 and len(d["results"]) == 24
    assert d["quantiles"]["0.05"] == pytest.approx(rset.quantile(0.05))
    path = rset.to_csv(tmp_path / "sub" / "set.csv")
    rows = list(csv.DictReader(open(path)))
    assert len(rows) == 24 and float(rows[3]["scaled"]) == rset.scaled[3]
    assert "ResistanceSet(n=24" in repr(rset)


def test_failures_recorded_not_fatal(pinch):
    s = pg.resistance_set(pinch, 1.0, directions=[[0, 1, 0], [1, 0.5, 0]], max_nodes=1, **KW)
    assert s.n == 2 and len(s.failures) == s.classes()["failed"] == sum(x == "failed" for x in s.statuses)
    for i, msg, status in s.failures:
        assert np.isnan(s.magnitudes[i]) and s.results[i] is None and msg and status


def test_bad_input(pinch):
    with pytest.raises(pg.InvalidInputError, match="n"):
        pg.resistance_set(pinch, 1.0, 0)
    with pytest.raises(pg.InvalidInputError, match="length"):
        pg.resistance_set(pinch, 1.0, 4, length=-1.0)
    with pytest.raises(pg.InvalidInputError, match="directions"):
        pg.resistance_set(pinch, 1.0, directions=[1, 0, 0])
    with pytest.raises(pg.InvalidInputError, match="method"):
        pg.resistance_set(pinch, 1.0, 4, method="nope")
    with pytest.raises(pg.InvalidInputError, match="quantile"):
        pg.grasp_score(pinch, 1.0, n=4, quantile=1.5)


def test_ferrari_canny_hand_computation():
    # planar pinch, L = a: primitive wrenches (±1, ±mu, ∓mu): a tetrahedron around the origin whose
    # faces lie mu / sqrt(mu² + 2) from it
    for mu in (0.3, 0.5, 1.0):
        assert pg.ferrari_canny(examples.pinch(mu=mu)) == pytest.approx(mu / np.sqrt(mu**2 + 2), rel=1e-12)
    assert pg.ferrari_canny(examples.pinch(mu=0.5)) == pytest.approx(1 / 3)
    # torques scaled by 2a instead: (±1, ±m, ∓k), k = m/2; face normal (mk, k, m): distance
    # m k / sqrt(m² k² + k² + m²)
    m, k = 0.5, 0.25
    e = pg.ferrari_canny(examples.pinch(mu=m), length=2 * A)
    assert e == pytest.approx(m * k / np.sqrt(m**2 * k**2 + k**2 + m**2), rel=1e-12)
    assert pg.ferrari_canny(examples.pinch(planar=False)) == 0.0  # no torque about the contact line


def test_score_orders_friction_and_preload(pinch):
    base = pg.grasp_score(pinch, 1.0, n=16, **KW)
    more_mu = pg.grasp_score(examples.pinch(mu=1.0), 1.0, n=16, **KW)
    more_preload = pg.grasp_score(pinch, 2.0, n=16, **KW)
    assert base.unit == "N" and base.kind == "quantile" and base.rset.n == 16
    assert more_mu.value > 1.5 * base.value and more_preload.value > 1.5 * base.value
    # the limits are homogeneous in the preload (F_max ∝ tau0): twice the preload, twice the score
    assert more_preload.value == pytest.approx(2 * base.value, rel=0.02)
    assert base.ferrari_canny == pytest.approx(1 / 3) == more_preload.ferrari_canny  # blind to preload
    assert more_mu.ferrari_canny > base.ferrari_canny
    worst = pg.grasp_score(pinch, 1.0, n=16, quantile=0.0, **KW)
    assert worst.kind == "worst" and worst.value == base.rset.scaled.min() <= base.value
    d = json.loads(json.dumps(base.to_dict()))
    assert d["value"] == pytest.approx(base.value) and d["set"]["n"] == 16
    assert "Ferrari–Canny" in base.summary() and "GraspScore(" in repr(base)


def test_score_under_disturbances(pinch):
    loads = [[0, 5, 0], [0, 20, 0], [10, 0, 0], [0, -9, 0]]  # +Y limit 10 N, ±X unbounded
    s = pg.grasp_score(pinch, 1.0, disturbances=loads, **KW)
    assert s.kind == "disturbances" and s.unit == "1" and s.value == pytest.approx(0.75)


def test_cli_resistance_set(tmp_path, capsys):
    out = tmp_path / "out"
    code = main(
        ["resistance-set", "pinch", "-n", "8", "--steps", "8", "--out", str(out), "--csv", str(out / "s.csv")]
    )
    assert code == 0
    text = capsys.readouterr().out
    assert "resistance set: 8 directions" in text and "Ferrari-Canny epsilon" in text
    assert (out / "resistance_set.png").stat().st_size > 0 and (out / "s.csv").exists()
    data = json.loads((out / "resistance_set.json").read_text())
    assert data["n"] == 8 and data["ferrari_canny"] == pytest.approx(1 / 3)
    assert main(["resistance-set", "pinch", "-n", "0"]) == 2


def test_plot_resistance_set(rset):
    from pinograsp.viz.figures import GID_UNBOUNDED

    fig = pg.plot_resistance_set(rset)
    assert len(fig.axes) >= 2
    assert any(c.get_gid() == GID_UNBOUNDED for ax in fig.axes for c in ax.collections)
    with pytest.raises(pg.InvalidInputError, match="rset"):
        pg.plot_resistance_set("nope")


def test_hull_reach_is_directional_ferrari_canny(pinch):
    u = np.zeros((400, 6))
    u[:, [0, 1, 5]] = pg.sphere_points(400, 3, seed=1)
    reach = pg.hull_reach(pinch, u)
    eps = pg.ferrari_canny(pinch)
    assert reach.min() >= eps - 1e-12 and reach.min() < 1.01 * eps
    # along +X the unit normal force of one contact is the farthest point: reach exactly 1
    assert pg.hull_reach(pinch, [[1.0, 0, 0, 0, 0, 0]])[0] == pytest.approx(1.0)
