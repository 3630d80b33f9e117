"""pg.optimal_preload: smallest preloads and budget splits (docs/optimal_preload.md)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples
from pinograsp.analysis.optimal import simplex_grid
from pinograsp.cli import main

F_Y = [0.0, 3.0, 0.0]  # +Y load on the pinch [N]; closed form: tau >= F L / (2 mu) = 0.3 N·m


def _resisted(model, command, wrench, method):
    return pg.passive_response(model, command, wrench, method).resistible


@pytest.mark.parametrize("method", ["iterative", "prp"])
def test_pinch_smallest_preload_closed_form(method):
    m = examples.pinch()
    r = pg.optimal_preload(m, [F_Y], method, objective="max")
    assert r.status == "optimal" and r.task == "smallest" and r.verified
    assert r.value == pytest.approx(0.3, abs=1e-3)  # tau = F L / (2 mu)
    assert r.exact is (method == "prp")
    assert r.checks[0].needs_preload and r.checks[0].limit == pytest.approx(1.0, abs=5e-3)
    smaller = {k: 0.95 * v for k, v in r.command.items()}
    assert not _resisted(m, smaller, F_Y, method)


def test_default_method_is_the_documented_quasistatic_search():
    # docs/optimal_preload.md and docs/hands.md give the signature with the default method
    from pathlib import Path

    r = pg.optimal_preload(examples.pinch(), [F_Y])
    assert r.method == "quasistatic" and r.status == "optimal" and not r.exact
    assert r.value == pytest.approx(0.3, abs=1e-9)  # tau = F L / (2 mu): the path's exact limit
    docs = Path(__file__).resolve().parents[1] / "docs"
    assert (
        'optimal_preload(model, disturbances, method="quasistatic"'
        in (docs / "optimal_preload.md").read_text()
    )
    assert 'disturbances, method="quasistatic", objective="max"' in (docs / "hands.md").read_text()


def test_pinch_prp_exact_to_the_margin():
    r = pg.optimal_preload(examples.pinch(), [F_Y], "prp", objective="max")
    assert max(r.command.values()) == pytest.approx(0.3 * (1 + 1e-6), rel=1e-9)
    again = pg.optimal_preload(examples.pinch(), [F_Y], "prp", objective="max")
    assert again.command == r.command  # the same bits


def test_differential_pinch_equal_torques():
    m = examples.pinch(differential=True)  # one tendon: tau_L = tau_R = f
    r = pg.optimal_preload(m, [F_Y], "iterative")
    assert r.command["tendon"] == pytest.approx(0.3, abs=1e-3)
    assert not _resisted(m, 0.95 * r.command["tendon"], F_Y, "iterative")


def test_sum_objective_and_weights_prp():
    m = examples.pinch()
    r = pg.optimal_preload(m, [F_Y], "prp", objective="sum")
    assert sum(r.command.values()) == pytest.approx(0.3, rel=1e-5)  # one finger presses into the other
    w = pg.optimal_preload(m, [F_Y], "prp", objective="sum", weights={"right": 3.0})
    assert w.command["right"] < 1e-9 and w.command["left"] == pytest.approx(0.3, rel=1e-5)


def test_bound_hit_and_infeasible():
    m = examples.pinch()
    hit = pg.optimal_preload(m, [[0.0, 30.0, 0.0]], "prp", max_command=3.0)  # needs exactly 3
    assert hit.status == "bound_hit" and set(hit.bound) <= {"left", "right"} and hit.bound
    assert hit.verified
    no = pg.optimal_preload(m, [[0.0, 30.0, 0.0]], "prp", max_command=1.0)
    assert no.status == "infeasible" and no.infeasible == (0,) and no.command is None
    it = pg.optimal_preload(m, [[0.0, 30.0, 0.0]], "iterative", max_command=1.0, refine=0)
    assert it.status == "infeasible" and it.infeasible == (0,)


def test_passively_resisted_needs_no_preload():
    r = pg.optimal_preload(examples.pinch(), [[-5.0, 0.0, 0.0]], "iterative")
    assert r.value == 0.0 and not r.checks[0].needs_preload and r.verified
    assert all(v == 0.0 for v in r.command.values())


def test_split_of_a_budget_pinch():
    m = examples.pinch()
    exact = pg.optimal_preload(m, ["fy"], "prp", objective="sum", budget=1.0)
    assert exact.task == "split" and exact.value == pytest.approx(10.0, rel=1e-6)  # 2 mu B / L
    assert "budget" in exact.bound and exact.verified
    both = pg.optimal_preload(m, ["fy", ("fy", 2.0)], "prp", objective="sum", budget=1.0, resistance="sum")
    assert both.value == pytest.approx(10.0 + 5.0, rel=1e-6)  # factors of 1 N and of 2 N
    search = pg.optimal_preload(m, ["fy"], "iterative", objective="sum", budget=1.0, refine=0)
    assert search.value == pytest.approx(10.0, abs=0.02) and search.verified


def test_case2_budget_goes_to_finger_1():
    """Seed case 2: preloading finger 1 resists more along +X than finger 2 (paper 2.48, ours
    2.36 with the paper's iterative scheme; the default quasi-static path: 35.74 N vs 2.83 N)."""
    scene = pg.load_scene("case2")
    kw = dict(objective="sum", budget=0.5, actuators=["f1", "f2"], grid=1, refine=0, settings=scene.settings)
    r = pg.optimal_preload(scene.model, ["fx"], "iterative", upper=50, steps=12, **kw)
    assert r.command == {"f1": 0.5, "f2": 0.0, "f3": 0.0}
    assert r.value == pytest.approx(9.2, abs=0.05) and r.verified and r.evaluations == 2
    path = pg.optimal_preload(scene.model, ["fx"], **kw)  # the default method
    assert path.command == r.command and path.verified and path.evaluations == 2
    one = pg.max_resistible_wrench(scene.model, scene.preload("finger1_only"), "fx", settings=scene.settings)
    assert one.method == "quasistatic" and path.value == one.magnitude == pytest.approx(35.736, abs=1e-3)


def test_simplex_grid():
    pts = simplex_grid(3, 2)
    assert len(pts) == 6 and np.allclose([p.sum() for p in pts], 1.0)
    assert np.array_equal(pts[0], [1.0, 0.0, 0.0])


def test_bad_input():
    m = examples.pinch()
    for kwargs, name in (
        (dict(disturbances=[[0.0, 0.0, 0.0]]), "disturbances[0]"),
        (dict(disturbances=[F_Y], objective="min"), "objective"),
        (dict(disturbances=[F_Y], actuators=["thumb"]), "actuators"),
        (dict(disturbances=[F_Y], budget=-1.0), "budget"),
        (dict(disturbances=[F_Y], grid=0), "grid"),
        (dict(disturbances=[F_Y], weights={"left": 0.0}), "weights"),
        (dict(disturbances=[], method="prp"), "disturbances"),
    ):
        with pytest.raises(pg.InvalidInputError, match=name.replace("[", r"\[").replace("]", r"\]")):
            pg.optimal_preload(m, **kwargs)


def test_to_dict_and_summary():
    r = pg.optimal_preload(examples.pinch(), [F_Y], "prp")
    d = json.loads(json.dumps(r.to_dict()))
    assert d["status"] == "optimal" and d["verified"] and d["checks"][0]["resisted"]
    assert "exact program" in r.summary()


def test_cli(capsys):
    assert main(["optimal-preload", "pinch", "-w", "fy=3", "--method", "prp", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["command"] == "optimal-preload" and max(data["preload"].values()) == pytest.approx(
        0.3, rel=1e-5
    )
    assert main(["optimal-preload", "pinch", "-w", "fy=3", "--objective", "nope"]) == 2
