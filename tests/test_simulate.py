"""The MuJoCo cross-check (docs/simulation.md): simulated give-way loads against the closed form
of the analytic pinch (docs/design.md) and the iterative prediction of seed case 1.

Simulations are skipped only when mujoco is not installed; the long ones are marked slow.
"""

from __future__ import annotations

import json
import sys

import numpy as np
import pytest

import pinograsp as pg

#: Pinch closed form (docs/design.md): F_max(θ) = 2 mu tau0 / (L |sin θ|), mu 0.5, tau0 1, L 0.1.
PINCH_Y = 2 * 0.5 * 1.0 / 0.1


@pytest.fixture(scope="module")
def pinch():
    pytest.importorskip("mujoco")
    return pg.load_scene("pinch")


def test_missing_mujoco_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # makes `import mujoco` raise ImportError
    with pytest.raises(pg.MissingDependencyError, match=r'pip install "pinograsp\[mujoco\]"'):
        pg.simulate_max_wrench(pg.load_scene("pinch"), "fy")


def test_pinch_up_gives_way_at_the_closed_form(pinch):
    r = pg.simulate_max_wrench(pinch, "fy")
    assert r.status == "gave_way"
    assert r.load == pytest.approx(PINCH_Y, rel=0.02)
    assert r.unit == "N" and r.timestep == 1e-4 and r.steps > 0 and r.wall_time > 0
    assert r.evidence and any(ok for _, ok in r.evidence) and not all(ok for _, ok in r.evidence)
    assert r.trace.applied.shape == r.trace.translation.shape
    data = json.loads(json.dumps(r.to_dict(trace=True)))
    assert data["status"] == "gave_way" and data["load"] == pytest.approx(r.load)
    assert "gave way at" in r.summary()


def test_bad_options_are_named(pinch):
    with pytest.raises(pg.InvalidInputError, match="unknown simulation option"):
        pg.simulate_max_wrench(pinch, "fy", stifness=1e6)
    with pytest.raises(pg.InvalidInputError, match="preload"):
        pg.simulate_max_wrench(pinch, "fy", preload="free")
    with pytest.raises(pg.InvalidInputError, match="command"):
        pg.simulate_max_wrench(pinch.model, "fy")


@pytest.mark.slow
@pytest.mark.parametrize("theta_deg", [90.0, 45.0, 30.0, 150.0])
def test_pinch_three_directions_within_two_percent(pinch, theta_deg):
    t = np.radians(theta_deg)
    r = pg.simulate_max_wrench(pinch, [np.cos(t), np.sin(t), 0.0])
    assert r.status == "gave_way"
    assert r.load == pytest.approx(PINCH_Y / abs(np.sin(t)), rel=0.02)


@pytest.mark.slow
@pytest.mark.parametrize("direction", ["fx", "-fx"])
def test_pinch_holds_along_x(pinch, direction):
    r = pg.simulate_max_wrench(pinch, direction)
    assert r.status == "held" and r.load is None and r.applied_load == r.upper == 1000.0


@pytest.mark.slow
def test_pinch_insensitive_to_step_mass_and_ramp(pinch):
    base = pg.simulate_max_wrench(pinch, "fy").load
    for opts in ({"timestep": 5e-5}, {"mass": 0.1}, {"ramp_time": 0.04}):
        assert pg.simulate_max_wrench(pinch, "fy", **opts).load == pytest.approx(base, rel=0.01), opts


@pytest.mark.slow
def test_case1_pull_within_five_percent_of_the_iterative_prediction():
    pytest.importorskip("mujoco")
    scene = pg.load_scene("case1")
    predicted = scene.max_resistible_wrench("fy", method="iterative")
    r = pg.simulate_max_wrench(scene, "fy")
    assert predicted.status == "finite" and predicted.magnitude == pytest.approx(4.30, abs=0.01)
    assert r.status == "gave_way"
    assert r.load == pytest.approx(predicted.magnitude, rel=0.05)


# ---------------------------------------------------------------------------- the CLI command
def test_cli_simulate_pinch_compare_json(pinch, capsys):
    from pinograsp.cli import main

    assert main(["simulate", "pinch", "-d", "fy", "--compare", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)  # stdout holds exactly one JSON document
    assert data["scene"] == "pinch" and data["label"] == "+fy" and data["method"] == "quasistatic"
    assert data["status"] == "gave_way" and data["same_class"] is True
    assert data["load"] == pytest.approx(PINCH_Y, rel=0.02)
    # the default path's limit is the closed form, exactly
    assert data["predicted"] == pytest.approx(PINCH_Y, rel=1e-12) and data["predicted_status"] == "finite"
    assert abs(data["agreement"]) < 0.02 and data["direction"] == [0.0, 1.0, 0.0, 0.0, 0.0, 0.0]


def test_cli_simulate_text_held_along_x(pinch, capsys):
    from pinograsp.cli import main

    assert main(["simulate", "pinch", "-d", "-fx", "--compare", "--upper", "100"]) == 0
    out = capsys.readouterr().out
    assert "status: held" in out and "held up to the upper load 100 N" in out
    assert "predicted (quasistatic): unbounded; class agrees" in out


@pytest.mark.parametrize(
    "flag, option, value, bad, valid",
    [
        ("--release-time", "release_time", 0.05, "-1", "[0, 10]"),
        ("--finger-mass", "finger_mass", 0.3, "0.01", "[0.1, 100]"),
    ],
)
def test_cli_simulate_passes_the_release_time_and_finger_mass(pinch, capsys, flag, option, value, bad, valid):
    """``--release-time`` and ``--finger-mass`` are the API's options: the same load, bit for
    bit; a bad value is the API's error, naming the option and its range."""
    from pinograsp.cli import main

    assert main(["simulate", "pinch", "-d", "fy", flag, str(value), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    api = pg.simulate_max_wrench(pg.load_scene("pinch"), "fy", **{option: value})
    assert data["load"] == api.load and data["status"] == api.status
    assert main(["simulate", "pinch", "-d", "fy", flag, bad]) == 2
    err = capsys.readouterr().err
    assert err.startswith("pinograsp: error:") and option in err and valid in err


def test_cli_simulate_without_mujoco_names_the_extra(monkeypatch, capsys):
    from pinograsp.cli import main

    monkeypatch.setitem(sys.modules, "mujoco", None)
    assert main(["simulate", "pinch", "-d", "fy"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("pinograsp: error:") and 'pip install "pinograsp[mujoco]"' in err
