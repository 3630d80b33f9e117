"""Geometry updates of the load stage (pinograsp/analysis/quasistatic/geometry.py): the turned
grasp map and its geometric stiffness against finite differences, paths that do not turn
unchanged bit for bit, and the turning random grasp that the simulation arbitrates."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import pinograsp as pg
from pinograsp.analysis.quasistatic import api
from pinograsp.analysis.quasistatic import path as qpath
from pinograsp.analysis.quasistatic.geometry import (
    GeometryUpdates,
    geometric_stiffness,
    grasp_map,
    rotation_matrix,
)
from pinograsp.analysis.quasistatic.model import build_qs_model

SIM = Path(__file__).resolve().parents[1] / "scripts" / "reproduce" / "data" / "qs_sim.jsonl"
#: ``random/n2s1/d0`` of scripts/reproduce/qs_cases.py: random_grasp(1, 2, 2 per finger), its
#: first seeded 6D direction (default_rng(1001)), command 1 N·m per finger, upper 50.
CASE = "random/n2s1/d0"


def _case() -> tuple[pg.GraspModel, np.ndarray]:
    m = pg.examples.random_grasp(1, 2, contacts_per_finger=2)
    d = np.random.default_rng(1001).normal(size=6)
    return m, d / np.linalg.norm(d)


def _sim(key: str, friction: str) -> dict:
    for line in SIM.read_text().splitlines():
        rec = json.loads(line)
        if rec["key"] == key and rec["friction"] == friction and not rec.get("refined"):
            return rec
    raise KeyError(key)


MODELS = [pg.examples.random_grasp(1, 3, contacts_per_finger=2), pg.examples.pinch()]


@pytest.mark.parametrize("model", MODELS)
def test_grasp_map_at_rest_is_the_models_and_its_derivative_is_the_geometric_stiffness(model):
    qm = build_qs_model(model)
    assert np.abs(grasp_map(qm, np.eye(3)) - np.asarray(model.G)).max() == 0.0
    rng = np.random.default_rng(0)
    c = rng.normal(size=qm.ncd)
    R = rotation_matrix(np.array([0.1, -0.2, 0.3]) if not model.planar else np.array([0, 0, 0.3]))
    K = geometric_stiffness(qm, R, c)
    h = 1e-6
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        if model.planar and j < 2:
            continue
        num = (grasp_map(qm, rotation_matrix(e) @ R) - grasp_map(qm, rotation_matrix(-e) @ R)) @ c / (2 * h)
        col = [k for k, a in enumerate((0, 1, 5) if model.planar else range(6)) if a == 3 + j][0]
        np.testing.assert_allclose(K[:, col], num, atol=1e-7 * np.abs(num).max(initial=1.0))


def test_a_path_whose_object_does_not_turn_is_unchanged(monkeypatch):
    """The pinch and case 1 turn less than one step before they give way: the same records bit
    for bit as without geometry updates."""
    cases = [(pg.examples.pinch(), 1.0, [0.3, 1.0, 0.0]), (pg.load_scene("case1").model, None, "fy")]
    got = []
    for m, cmd, d in cases:
        cmd = pg.load_scene("case1").preload(None) if cmd is None else cmd
        got.append(pg.max_resistible_wrench(m, cmd, d, upper=50.0).to_dict())
    monkeypatch.setattr(qpath, "step_to_update", lambda *a: float("inf"))
    for (m, cmd, d), before in zip(cases, got):
        cmd = pg.load_scene("case1").preload(None) if cmd is None else cmd
        after = pg.max_resistible_wrench(m, cmd, d, upper=50.0).to_dict()
        for k in ("magnitude", "status", "giveway"):
            assert after[k] == before[k]


def test_the_turning_random_grasp_gives_way_where_the_simulation_does(monkeypatch):
    """Turned by degrees before it gives way, the grasp's second-order contact motion dwarfs its
    springs' deflections: linearised once it 'held' to 22.2 N at 0.1 rad; followed as it turns it
    reaches a limit at 12.50 N (simulated, cached: 11.78 N with the model's pyramid, 13.04 N with
    the cone)."""
    m, d = _case()
    mw = pg.max_resistible_wrench(m, 1.0, d, upper=50.0)
    pyr, cone = _sim(CASE, "pyramid"), _sim(CASE, "cone")
    assert mw.status == "finite" and mw.giveway.reason == "limit"
    assert abs(pyr["load"] / mw.magnitude - 1) < 0.07 and abs(cone["load"] / mw.magnitude - 1) < 0.05
    assert 0.09 < mw.giveway.turned < 0.13  # [rad], physical at 1e6 N/m
    # the step converges: half the step moves the answer by less than 0.5 %
    base = api.GeometryUpdates

    def half(**kw):
        return base(**kw, step=0.0025, min_step=0.000125, max_step=0.0025)

    monkeypatch.setattr(api, "GeometryUpdates", half)
    finer = pg.max_resistible_wrench(m, 1.0, d, upper=50.0)
    assert abs(finer.magnitude / mw.magnitude - 1) < 0.005
    # without the updates the linearised path holds 50 N (as the simulation does with its own
    # rotation linearised); it used to stop at 0.1 rad of turn, at 22.2 N
    monkeypatch.setattr(qpath, "step_to_update", lambda *a: float("inf"))
    linear = pg.max_resistible_wrench(m, 1.0, d, upper=50.0)
    assert linear.status == "unbounded" and linear.giveway.reason == "held"


def test_softer_contacts_turn_the_object_further():
    """The rotation is the model's times ``max(k) / contact_stiffness``: at 1e5 N/m the same grasp
    turns ten times as far per newton and its turned geometry gives way at a lower load."""
    m, d = _case()
    stiff = pg.max_resistible_wrench(m, 1.0, d, upper=50.0)
    soft = pg.max_resistible_wrench(m, 1.0, d, upper=50.0, settings=pg.Settings(contact_stiffness=1e5))
    assert soft.magnitude < stiff.magnitude and soft.giveway.stiffness == 1e5


def test_adapted_steps_shrink_towards_a_limit_and_grow_back():
    g = GeometryUpdates()
    assert g.adapted(g.step, 1.0, 1.0) == g.step  # steady: at most the step
    assert g.adapted(g.step / 4, 1.0, 1.0) == g.step / 2  # grows back
    # stiffness 1 -> 0.8 per step: the limit 4 steps ahead, a quarter of that
    assert g.adapted(g.step, 1.0, 1.25) == pytest.approx(g.step, rel=1e-12)
    assert g.adapted(g.step, 1.0, 2.0) == pytest.approx(0.25 * g.step, rel=1e-12)
    assert g.adapted(g.step, 1.0, -1.0) == g.min_step  # past the limit


def test_states_reached_with_the_geometry_updated_pass_their_audit():
    """The response at a turned state is audited against the linear model that reached it
    (equilibrium invariant, incremental gaps): residuals at rounding level, as elsewhere."""
    m, d = _case()
    mw = pg.max_resistible_wrench(m, 1.0, d, upper=50.0)
    assert mw.giveway.turned > 0.05 and mw.response.audit.ok
    for load in (5.0, 10.0, 12.0):
        r = pg.quasistatic_response(m, 1.0, load * d)
        assert r.status == "resisted" and r.audit.ok
        assert r.audit.equilibrium < 1e-9 * load and r.audit.complementarity < 1e-9 * load
    lp = pg.loading_path(m, 1.0, d)
    assert lp.geometries and any(g is not None for g in lp.geometries)
    assert max(lp.audit["equilibrium"]) < 1e-9 * max(lp.loads)


def test_the_stage_cache_of_an_updated_model_is_the_rebuilt_one():
    """``StageCache.rebased`` (kept per update: speed only) holds exactly what
    ``StageCache.of`` builds for the re-linearised model."""
    from dataclasses import fields

    from pinograsp.analysis.quasistatic.geometry import moved
    from pinograsp.analysis.quasistatic.state import StageSpec, State
    from pinograsp.analysis.quasistatic.system import StageCache

    m, d = _case()
    qm = build_qs_model(m)
    spec = StageSpec(np.zeros(qm.nx), m.reduce_wrench(d), np.ones(qm.na), np.zeros(qm.na),
                     float("inf"), held=False, friction=True)  # fmt: skip
    rng = np.random.default_rng(3)
    st = State(rng.normal(size=qm.nv) * 1e-3, rng.normal(size=qm.ncd), np.ones(qm.na),
               np.zeros(qm.ncp), np.zeros(qm.nx), np.zeros(qm.ncd), 2.0)  # fmt: skip
    sc = StageCache.of(qm, spec)
    qm2 = moved(qm, st, spec.dw * 2.0, np.array([0.002, -0.001, 0.003]), 1.0)
    assert qm2.KG is not None and qm2.turn == pytest.approx(np.arccos((np.trace(qm2.rot) - 1.0) / 2.0))
    fresh, kept = StageCache.of(qm2, spec), sc.rebased(qm2, spec)
    for f in fields(StageCache):
        a, b = getattr(fresh, f.name), getattr(kept, f.name)
        if isinstance(a, np.ndarray):
            assert np.array_equal(a, b), f.name
        elif f.name == "rates":
            assert all(np.array_equal(x, y) for x, y in zip(a, b))
        elif f.name != "col_of":
            assert a == b, f.name


@pytest.mark.parametrize("model", MODELS)
def test_turned_grasp_map_is_the_cross_products_bit_for_bit(model):
    """The per-model constants of an update (``geometry._constants``) change no bit: the turned
    grasp map's rows are the frames' columns and ``R a_i x`` them (``np.cross``), and the
    constraints of the stage an update does not use (computed on first read) are the products
    with the new ``A``."""
    from pinograsp.analysis.quasistatic.geometry import moved
    from pinograsp.analysis.quasistatic.state import State

    qm = build_qs_model(model)
    R = rotation_matrix(np.array([0.1, -0.2, 0.3]) if not model.planar else np.array([0, 0, 0.3]))
    Gt = grasp_map(qm, R)
    arms = (np.asarray(model.points, float) - np.asarray(model.reference_point, float)) @ R.T
    F = np.asarray(model.frames, float)[:, :, : qm.d]
    full = np.stack(
        [np.concatenate([F[:, :, j], np.cross(arms, F[:, :, j])], axis=1) for j in range(qm.d)], 2
    )
    axes = [0, 1, 5] if model.planar else list(range(6))
    assert np.array_equal(Gt, full[:, axes].transpose(1, 0, 2).reshape(qm.nx, -1))
    rng = np.random.default_rng(1)
    st = State(
        rng.normal(size=qm.nv) * 1e-3,
        rng.normal(size=qm.ncd),
        np.zeros(qm.na),
        np.zeros(qm.ncp),
        np.zeros(qm.nx),
        np.zeros(qm.ncd),
    )
    up = moved(qm, st, np.zeros(qm.nx), np.array([0.0, 0.0, 0.01]), 1.0)
    for con in (up.held, up.free):
        assert np.array_equal(con.AZ, up.A.T @ con.Z) and np.array_equal(con.BpA, con.B_pinv @ up.A)
        assert np.array_equal(con.AtBt, up.A.T @ con.Bt_pinv)
    assert up.held.Z is qm.held.Z and not np.array_equal(up.A, qm.A)
