"""``method="energetic"`` and the contact-model settings on the command line, in batches and in
scene files: closed forms of the pinch, the API with the same arguments, and one-line errors
naming the option or key (issue 16)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from support.clirun import run, run_json

import pinograsp as pg
from pinograsp.batch.evaluate import WorstAxisScore
from pinograsp.cli import main
from pinograsp.core.methods import method_names

#: The pinch's closed form along ±fy: 2 mu tau0 / L with mu = 0.5, tau0 = 1 N·m, L = 0.1 m.
PINCH_FY = 10.0
MU = 0.5
#: ``pinograsp max-wrench pinch -d fy`` and ``analyze pinch -w fy=5``, options to follow.
MW = ("max-wrench", "pinch", "-d", "fy")
AN = ("analyze", "pinch", "-w", "fy=5")
NU = "--normal-uncertainty"


def pinch_limit(deg: float) -> float:
    """The pinch's ±fy limit [N] under a normal uncertainty of ``deg``: the band scales with the
    effective friction coefficient ``tan(atan(mu) - u)``."""
    return PINCH_FY * math.tan(math.atan(MU) - math.radians(deg)) / MU


# ---------------------------------------------------------------------------- CLI: numbers
def test_max_wrench_energetic_pinch_closed_form(capsys):
    scene = pg.load_scene("pinch")
    api = pg.max_resistible_wrench(scene.model, scene.command, "fy", "energetic", settings=scene.settings)
    assert api.magnitude == pytest.approx(PINCH_FY, rel=1e-6)
    data = run_json(capsys, *MW, "--method", "energetic")
    assert data["method"] == "energetic" and data["search"] == "direct" and data["status"] == "finite"
    assert data["magnitude"] == pytest.approx(PINCH_FY, rel=1e-6)
    assert data["magnitude"] == pytest.approx(api.magnitude, rel=1e-12)
    assert data["normal_uncertainty"] == 0.0 and data["cone_tolerance"] is None
    contacts = data["response"]["contacts"]
    assert [c["state"] for c in contacts] == ["sticking", "sticking"]
    # at the limit both fingers press with tau0 / L = 10 N and use all their friction: 2 mu c_n = 10
    np.testing.assert_allclose([c["force"][0] for c in contacts], [10.0, 10.0], rtol=1e-6)
    np.testing.assert_allclose([abs(c["force"][1]) for c in contacts], [5.0, 5.0], rtol=1e-6)
    rc, out, _ = run(capsys, "max-wrench", "pinch", "-d", "-fy", "--method", "energetic")
    assert rc == 0 and "method energetic," in out and re.search(r"max resistible magnitude: 10\.0+ N", out)
    assert re.search(r"state\s+c_n \[N\]", out) and out.count("sticking") == 2


@pytest.mark.parametrize("method", ["energetic", "prp"])
def test_normal_uncertainty_in_degrees_scales_the_pinch(method, capsys):
    want = pinch_limit(5.0)  # 7.9045 N
    data = run_json(capsys, *MW, "--method", method, NU, "5")
    assert data["normal_uncertainty"] == pytest.approx(math.radians(5.0), rel=1e-15)
    res = data["resolution"] if method == "prp" else 0.0  # PRP: bisection, energetic: direct
    assert data["magnitude"] == pytest.approx(want, rel=1e-6, abs=res)
    scene = pg.load_scene("pinch")
    api = pg.max_resistible_wrench(
        scene.model, scene.command, "fy", method, normal_uncertainty=math.radians(5.0)
    )
    assert data["magnitude"] == pytest.approx(api.magnitude, rel=1e-12)
    rc, out, _ = run(capsys, *MW, "--method", method, NU, "5")
    assert rc == 0 and f"method {method}, normal uncertainty 5°" in out


def test_analyze_shows_states_and_settings(capsys):
    data = run_json(
        capsys, "analyze", "pinch", "-w", "fy=5", "--method", "energetic", "--normal-uncertainty", "2"
    )
    scene = pg.load_scene("pinch")
    ref = pg.passive_response(
        scene.model, scene.command, [0, 5, 0], "energetic", normal_uncertainty=math.radians(2.0)
    )
    assert data["method"] == "energetic" and data["resistible"] is True
    assert [c["state"] for c in data["contacts"]] == list(ref.contact_states) == ["sticking"] * 2
    np.testing.assert_allclose([c["force"] for c in data["contacts"]], ref.contact_forces, atol=1e-12)
    # symmetric pinch: each finger carries half the load in friction, c_n = tau0 / L = 10 N
    np.testing.assert_allclose([c["force"][0] for c in data["contacts"]], [10.0, 10.0], rtol=1e-9)
    np.testing.assert_allclose([abs(c["force"][1]) for c in data["contacts"]], [2.5, 2.5], rtol=1e-9)
    assert data["normal_uncertainty"] == pytest.approx(math.radians(2.0))
    assert [c["edges"] for c in data["contacts"]] == [2, 2]
    rc, out, _ = run(
        capsys, "analyze", "pinch", "-w", "fy=5", "--method", "energetic", "--normal-uncertainty", "2"
    )
    assert rc == 0 and "method: energetic (preload-first, normal uncertainty 2°)" in out


def test_sliding_contacts_at_the_limit_oppose_their_slip(capsys):
    """case1 along +fy at the energetic limit: the loaded contacts slide (the others are just
    losing touch); the friction force on the object is anti-parallel to the object's slip (maximum
    dissipation)."""
    data = run_json(capsys, "max-wrench", "case1", "-d", "fy", "--method", "energetic")
    scene = pg.load_scene("case1")
    api = pg.max_resistible_wrench(scene.model, scene.command, "fy", "energetic", settings=scene.settings)
    assert data["magnitude"] == pytest.approx(api.magnitude, rel=1e-9)
    contacts = data["response"]["contacts"]
    states = list(api.response.contact_states)
    assert [c["state"] for c in contacts] == states
    assert states.count("sliding") >= 2 and set(states) <= {"sliding", "separated"}
    for c, normal in zip(contacts, api.response.contact_forces):
        if normal[0] < 1e-3:  # a contact just touching carries (almost) no friction
            continue
        f, s = np.asarray(c["force_world"]), np.asarray(c["slip"])
        ft = np.hypot(*c["force"][1:])
        assert f @ s == pytest.approx(-ft * np.linalg.norm(s), rel=1e-6)
    rc, out, _ = run(capsys, "max-wrench", "case1", "-d", "fy", "--method", "energetic")
    assert rc == 0 and out.count("sliding") == states.count("sliding")


def test_profile_energetic_pinch(capsys):
    data = run_json(capsys, "profile", "pinch", "-n", "4", "--method", "energetic", "--no-normalize")
    assert data["method"] == "energetic" and data["unbounded"] == [True, False, True, False]
    np.testing.assert_allclose([data["magnitudes"][i] for i in (1, 3)], [PINCH_FY] * 2, rtol=1e-6)
    rc, out, _ = run(capsys, "profile", "pinch", "-n", "4", "--method", "energetic", "--no-normalize")
    assert rc == 0 and "method energetic" in out


def test_cone_tolerance_is_passed_in_radians(capsys):
    data = run_json(capsys, *MW, "--method", "energetic", "--cone-tolerance", "2")
    assert data["cone_tolerance"] == pytest.approx(math.radians(2.0), rel=1e-15)
    # planar pyramids are exact: no refinement, the closed form stays
    assert data["magnitude"] == pytest.approx(PINCH_FY, rel=1e-6)


# ---------------------------------------------------------------------------- CLI: errors
@pytest.mark.parametrize(
    "argv, fragment",
    [
        (
            ["--normal-uncertainty", "-1"],
            "--normal-uncertainty: must be an angle in [0, 1.5708) rad; got -1 deg",
        ),
        (["--normal-uncertainty", "90"], "--normal-uncertainty: must be an angle"),
        (["--normal-uncertainty", "nan"], "--normal-uncertainty"),
        (["--cone-tolerance", "abc"], "argument --cone-tolerance: invalid float value: 'abc'"),
        (["--cone-tolerance", "0"], "--cone-tolerance: must be a positive angle"),
        (["--cone-tolerance", "50"], "--cone-tolerance: must be an angle"),
        (["--method", "energy"], "invalid choice: 'energy'"),
    ],
)
def test_bad_values_exit_2_naming_the_option(argv, fragment, capsys):
    rc, out, err = run(capsys, *MW, *argv)
    assert rc == 2 and out == ""
    assert err.startswith("pinograsp: error: ") and err.count("\n") == 1, err
    assert fragment in err and "Traceback" not in err


def test_help_lists_energetic_and_the_angles(capsys):
    assert main(["max-wrench", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "{prp,iterative,energetic,quasistatic}" in text and "energetic (maximum dissipation" in text
    assert "quasistatic (the loading path followed exactly" in text
    assert "--normal-uncertainty DEG" in text and "--cone-tolerance DEG" in text


# ---------------------------------------------------------------------------- batch
def test_worst_axis_score_accepts_energetic():
    score = WorstAxisScore(upper=20, steps=4, method="energetic")
    assert score.method is pg.Method.ENERGETIC
    with pytest.raises(pg.InvalidInputError, match=re.escape(f"method: must be one of {method_names()}")):
        WorstAxisScore(method="simplex")
    spec = pg.GraspSpec("barrett_bh8_282", pg.ObjectSpec("sphere", radius=0.04), preload_method="energetic")
    assert spec.preload_method is pg.Method.ENERGETIC
    with pytest.raises(pg.InvalidInputError, match="preload_method"):
        pg.GraspSpec("barrett_bh8_282", pg.ObjectSpec("sphere", radius=0.04), preload_method="x")


def test_batch_energetic_matches_the_api(tmp_path, capsys):
    pd = pytest.importorskip("pandas")
    score = WorstAxisScore(upper=20, steps=4, method="energetic")
    table = pg.evaluate_grasps(["pinch", "wedge"], score=score, workers=1)
    assert table["status"].tolist() == ["ok", "ok"]
    for i, name in enumerate(["pinch", "wedge"]):
        scene = pg.load_scene(name)
        for axis in ("fx", "-fx", "fy", "-fy"):
            mw = pg.max_resistible_wrench(scene.model, scene.command, axis, "energetic", 20, 4)
            col = "max_" + (axis if axis[0] == "-" else "+" + axis)
            assert table.loc[i, col] == pytest.approx(mw.magnitude, rel=1e-12)
    assert table.loc[0, "score"] == pytest.approx(PINCH_FY, rel=1e-6)  # ±fx unbounded, ±fy 10 N
    # the file and the command line
    path = tmp_path / "g.yaml"
    path.write_text(
        "grasps:\n  - scene: pinch\n  - scene: wedge\nscore: {upper: 20, steps: 4, method: energetic}\n"
    )
    batch = pg.load_grasps(path)
    assert batch.score["method"] is pg.Method.ENERGETIC
    out = tmp_path / "r.csv"
    rc, text, err = run(capsys, "batch", str(path), "--out", str(out), "--workers", "1", "--no-progress")
    assert rc == 0, err
    assert "(worst axis, energetic, upper 20, steps 4)" in text
    df = pd.read_csv(out)
    np.testing.assert_allclose(df["score"], table["score"], rtol=1e-12)
    path.write_text("grasps:\n  - scene: pinch\nscore: {method: iterative}\n")
    rc, text, err = run(
        capsys, "batch", str(path), "--method", "energetic", "--workers", "1", "--no-progress"
    )
    assert rc == 0 and "energetic" in text and "min 10" in text
    path.write_text("grasps:\n  - scene: pinch\nscore: {method: energy}\n")
    with pytest.raises(pg.InvalidInputError, match=r"score.method: must be one of prp, iterative, energetic"):
        pg.load_grasps(path)


# ---------------------------------------------------------------------------- scenes
SCENE = """\
extends: pinch
name: pinch-energetic
analysis:
  method: energetic
  normal_uncertainty_deg: 5
  cone_tolerance_deg: {cone}
  upper: 100
"""


def test_scene_analysis_block_energetic_in_degrees(tmp_path, capsys):
    path = tmp_path / "p.yaml"
    path.write_text(SCENE.format(cone="null"))
    scene = pg.load_scene(path)
    assert scene.analysis.method is pg.Method.ENERGETIC
    assert scene.settings.normal_uncertainty == pytest.approx(math.radians(5.0), rel=1e-15)
    assert scene.settings.cone_tolerance is None
    data = run_json(capsys, "max-wrench", str(path), "-d", "fy")
    assert data["method"] == "energetic" and data["magnitude"] == pytest.approx(pinch_limit(5.0), rel=1e-6)
    # the command line overrides the file
    data = run_json(capsys, "max-wrench", str(path), "-d", "fy", "--normal-uncertainty", "0")
    assert data["magnitude"] == pytest.approx(PINCH_FY, rel=1e-6)
    path.write_text(SCENE.format(cone="3"))
    assert pg.load_scene(path).settings.cone_tolerance == pytest.approx(math.radians(3.0), rel=1e-15)
    described = run_json(capsys, "scenes", str(path))["analysis"]
    assert described["method"] == "energetic"
    assert described["normal_uncertainty"] == pytest.approx(math.radians(5.0))
    assert described["cone_tolerance"] == pytest.approx(math.radians(3.0))


@pytest.mark.parametrize(
    "old, new, key",
    [
        (
            "normal_uncertainty_deg: 5",
            "normal_uncertainty_deg: -1",
            "analysis.normal_uncertainty_deg: must be",
        ),
        (
            "normal_uncertainty_deg: 5",
            "normal_uncertainty_deg: abc",
            "analysis.normal_uncertainty_deg: expected",
        ),
        ("cone_tolerance_deg: null", "cone_tolerance_deg: 0", "analysis.cone_tolerance_deg: must be"),
        ("method: energetic", "method: energy", "analysis.method: must be one of prp, iterative, energetic"),
    ],
)
def test_scene_errors_name_the_key(tmp_path, old, new, key):
    path = tmp_path / "p.yaml"
    path.write_text(SCENE.format(cone="null").replace(old, new))
    with pytest.raises(pg.SceneError, match=re.escape(f"p.yaml: {key}")):
        pg.load_scene(path)
