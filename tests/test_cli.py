"""The ``pinograsp`` command line: every command on every built-in scene (small n/steps), JSON
checked against the Python API with the same settings, exit codes and one-line errors."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import numpy as np
import pytest
from support.clirun import run, run_json

import pinograsp as pg
from pinograsp.cli import main
from pinograsp.cli.report import ProgressBar
from pinograsp.core.serialize import unbounded_runs

SCENES = sorted(pg.builtin_scenes())
FAST = ["--steps", "3"]


def mags(values) -> np.ndarray:
    return np.array([np.inf if v is None else v for v in values], dtype=float)


# ---------------------------------------------------------------------------- scenes
def test_scenes_lists_builtins(capsys):
    rc, out, _ = run(capsys, "scenes")
    assert rc == 0
    for name, desc in pg.builtin_scenes().items():
        assert any(line.startswith(name) and desc[:30] in line for line in out.splitlines())
    assert run_json(capsys, "scenes") == pg.builtin_scenes()


def test_scenes_describes_one(capsys):
    rc, out, _ = run(capsys, "scenes", "pinch")
    assert rc == 0 and "preload: left=1, right=1" in out and "directions: up" in out
    data = run_json(capsys, "scenes", "case1")
    scene = pg.load_scene("case1")
    assert data["contacts"] == list(scene.model.contact_names)
    assert data["analysis"]["upper"] == scene.analysis.upper


# ---------------------------------------------------------------------------- every built-in scene
@pytest.mark.parametrize("name", SCENES)
def test_profile_every_scene_matches_api(name, capsys, tmp_path):
    scene = pg.load_scene(name)
    # PRP: one MIQP per magnitude, deterministic (the iterative scheme's verdict can depend on which
    # of several optimal MIQP solutions the solver returns near a boundary; see the demo test)
    argv = ["profile", name, "-n", "4", *FAST, "--method", "prp", "--no-normalize", "--out", str(tmp_path)]
    data = run_json(capsys, *argv)
    api = pg.resistance_profile(
        scene.model,
        scene.command,
        scene.analysis.plane,
        n=4,
        method="prp",
        upper=scene.analysis.upper,
        steps=3,
        settings=scene.settings,
    )
    assert data["scene"] == name and data["n"] == 4 and data["steps"] == 3
    assert data["method"] == "prp"
    assert data["unbounded"] == api.unbounded.tolist()
    np.testing.assert_allclose(mags(data["magnitudes"]), api.magnitudes, atol=1e-9)
    np.testing.assert_allclose(data["angles_deg"], [0, 90, 180, 270])
    assert data["normalized_by"] is None
    assert json.loads((tmp_path / "profile.json").read_text())["magnitudes"] == data["magnitudes"]
    assert (tmp_path / "profile.png").stat().st_size > 5000


@pytest.mark.parametrize("name", SCENES)
def test_max_wrench_and_analyze_every_scene(name, capsys):
    scene = pg.load_scene(name)
    direction = next(iter(scene.analysis.directions), "fy")
    data = run_json(capsys, "max-wrench", name, "--direction", direction, "--steps", "4", "--method", "prp")
    api = pg.max_resistible_wrench(
        scene.model,
        scene.command,
        scene.analysis.directions.get(direction, direction),
        "prp",
        scene.analysis.upper,
        4,
        settings=scene.settings,
    )
    assert data["unbounded"] == api.unbounded
    assert (data["magnitude"] is None) == api.unbounded
    if not api.unbounded:
        assert data["magnitude"] == pytest.approx(api.magnitude, abs=1e-9)
    assert [tuple(e) for e in data["evidence"]] == [(pytest.approx(m), ok) for m, ok in api.evidence]
    # the passive response at w = 0: the preload is an equilibrium on every built-in scene
    zero = ",".join(["0"] * (3 if scene.model.planar else 6))
    resp = run_json(capsys, "analyze", name, "--wrench", zero, "--method", "prp")
    ref = pg.passive_response(scene.model, scene.command, np.zeros(6), "prp", settings=scene.settings)
    assert resp["resistible"] and resp["status"] == "resisted"
    forces = np.array([c["force"] for c in resp["contacts"]])
    np.testing.assert_allclose(forces, ref.contact_forces, atol=1e-6)
    assert [c["name"] for c in resp["contacts"]] == list(ref.contact_names)
    # the PRP wedges the wedge scene's object at zero load (rotation, locked fingers): its energy
    # audit fails (springs store 100 J, nothing supplied); every other scene passes
    assert resp["audit"]["ok"] == ref.audit.ok == (name != "wedge")
    assert resp["audit"]["energy"]["spring_energy"] == pytest.approx(ref.audit.energy.spring_energy)


# ---------------------------------------------------------------------------- numbers on the pinch
def test_max_wrench_pinch_closed_form(capsys):
    rc, out, _ = run(capsys, "max-wrench", "pinch", "--direction", "-fy", "--upper", "100", "--steps", "14")
    assert rc == 0 and re.search(r"max resistible magnitude: (9\.99|10\.00)\d* N", out)
    data = run_json(capsys, "max-wrench", "pinch", "-d", "-fy", "--upper", "100", "--steps", "14")
    assert data["magnitude"] == pytest.approx(10.0, abs=100 / 2**14 + 2e-3)  # 2 mu tau0 / L
    np.testing.assert_allclose(data["direction"], [0, -1, 0, 0, 0, 0])
    cn = [c["force"][0] for c in data["response"]["contacts"]]
    np.testing.assert_allclose(cn, [10.0, 10.0], atol=1e-2)
    # ±x is passively unbounded: magnitude null, never the upper limit
    data = run_json(capsys, "max-wrench", "pinch", "-d", "1,0,0,0,0,0", "--upper", "100", "--steps", "4")
    assert data["unbounded"] and data["magnitude"] is None
    # a named direction of the scene, PRP
    data = run_json(
        capsys, "max-wrench", "pinch", "-d", "up", "--method", "prp", "--upper", "100", "--steps", "10"
    )
    assert data["label"] == "up" and data["method"] == "prp"
    assert data["magnitude"] == pytest.approx(10.0, abs=0.1)


def test_analyze_pinch_table_and_json(capsys, tmp_path):
    rc, out, _ = run(capsys, "analyze", "pinch", "--wrench", "fy=5", "--out", str(tmp_path))
    assert rc == 0
    assert "RESISTED" in out and "left" in out and "audit: ok" in out
    assert (tmp_path / "analyze.json").is_file() and (tmp_path / "analyze.png").stat().st_size > 5000
    data = run_json(capsys, "analyze", "pinch", "--wrench", "0,5,0", "--method", "prp")
    ref = pg.passive_response(pg.load_scene("pinch").model, 1.0, [0, 5, 0], "prp")
    np.testing.assert_allclose([c["force"] for c in data["contacts"]], ref.contact_forces, atol=1e-9)
    np.testing.assert_allclose([c["force"][0] for c in data["contacts"]], [10.0, 10.0], atol=1e-6)
    assert [a["mode"] for a in data["actuators"]] == list(ref.actuator_modes)
    # not resisted: well above 2 mu tau0 / L along y
    data = run_json(capsys, "analyze", "pinch", "--wrench", "0,-50,0,0,0,0")
    assert data["resistible"] is False and data["status"] != "resisted"


def test_profile_normalised_pinch(capsys):
    data = run_json(capsys, "profile", "pinch", "-n", "8", "--upper", "100", "--steps", "12", "--normalize")
    assert data["unbounded"] == [True, False, False, False, True, False, False, False]
    assert data["normalized_by"] == pytest.approx(10.0, abs=0.03)
    norm = mags(data["normalized"])
    np.testing.assert_allclose(norm[[2, 6]], [1.0, 1.0], atol=1e-9)
    np.testing.assert_allclose(norm[[1, 3, 5, 7]], np.sqrt(2), atol=0.01)  # 1 / |sin 45°|
    assert data["unbounded_runs_deg"] == [[0.0, 0.0], [180.0, 180.0]]
    # --normalize on a plane whose +b2 is unbounded is an error; the scene default only warns
    rc, _, err = run(capsys, "profile", "pinch", "--plane", "fy,fx", "-n", "4", "--steps", "3", "--normalize")
    assert rc == 2 and err.startswith("pinograsp: error: --normalize") and err.count("\n") == 1


def test_demo_writes_table_plot_and_json(capsys, tmp_path):
    out_dir = tmp_path / "demo"
    rc, out, _ = run(capsys, "demo", "-n", "4", "--out", str(out_dir))
    assert rc == 0
    assert "scene 'case1'" in out and "angle [deg]" in out and "unbounded" in out
    assert "method quasistatic, the load at which the loading path gives way (exact" in out
    data = json.loads((out_dir / "profile.json").read_text())
    assert data["command"] == "demo" and data["scene"] == "case1" and data["method"] == "quasistatic"
    # case 1: ±X and -Y unbounded, +Y finite (the paper's findings); +Y exact on the default
    # path: 4.3354 N (the simulation gives way at 4.3287 N, scripts/reproduce/data/qs_sim.jsonl)
    assert data["unbounded"] == [True, False, True, True]
    assert data["magnitudes"][1] == pytest.approx(4.3354, abs=1e-4)
    assert data["normalized_by"] == data["magnitudes"][1]  # the scene normalises by +Y
    assert (out_dir / "profile.png").stat().st_size > 5000
    # the paper's iterative scheme stays selectable: +Y 4.2982 N at a 1 N resolution
    it = tmp_path / "iterative"
    args = ("demo", "-n", "4", "--upper", "16", "--steps", "4", "--method", "iterative", "--out", str(it))
    assert run(capsys, *args)[0] == 0
    data = json.loads((it / "profile.json").read_text())
    assert data["method"] == "iterative" and data["unbounded"] == [True, False, True, True]
    assert data["magnitudes"][1] == pytest.approx(4.0) and data["normalized_by"] == pytest.approx(4.0)


def test_compare_preloads(capsys, tmp_path):
    scene = pg.load_scene("case3")
    names = list(scene.analysis.preloads)
    kw = ["--upper", "1", "--steps", "5", "--method", "prp"]
    data = run_json(
        capsys, "compare-preloads", "case3", "--direction", "torque_x", *kw, "--out", str(tmp_path)
    )
    assert data["ratio_of"] == names[:2]
    (row,) = data["directions"]
    api = {
        n: pg.max_resistible_wrench(scene.model, scene.preload(n), scene.direction("torque_x"), "prp", 1.0, 5)
        for n in names
    }
    for n in names:
        got = row["results"][n]
        assert got["unbounded"] == api[n].unbounded
        if not api[n].unbounded:
            assert got["magnitude"] == pytest.approx(api[n].magnitude, abs=1e-9)
    a, b = (api[n] for n in names[:2])
    if not (a.unbounded or b.unbounded) and b.magnitude > 0:
        assert row["ratio"] == pytest.approx(a.magnitude / b.magnitude)
    assert (tmp_path / "compare_preloads.png").stat().st_size > 5000
    rc, out, _ = run(capsys, "compare-preloads", "case3", "-d", "torque_x", "--steps", "2", "--upper", "1")
    assert rc == 0 and "ratio" in out and names[0] in out


def test_progress_bar_and_helpers():
    import io

    buf = io.StringIO()
    bar = ProgressBar("x", stream=buf, width=10)
    bar(0, 4)
    bar(2, 4)
    bar.close()
    text = buf.getvalue()
    assert "[#####.....] 2/4" in text and "ETA" in text and text.endswith("\n")
    assert ProgressBar.clock(3725) == "1:02:05" and ProgressBar.clock(65) == "01:05"
    deg = np.arange(0, 360, 45.0)
    assert unbounded_runs(deg, [True, False, False, True, True, False, False, True]) == [
        (135.0, 180.0),
        (315.0, 0.0),
    ]
    assert unbounded_runs(deg, [False] * 8) == []


# ---------------------------------------------------------------------------- errors
@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["analyze", "nosuch", "--wrench", "0,0,0"], "unknown scene 'nosuch'"),
        (["analyze", "pinch", "--wrench", "0,5"], "--wrench: expected 6 numbers"),
        (["analyze", "pinch", "--wrench", "a,b,c"], "--wrench: expected fx,fy,fz"),
        (["analyze", "pinch", "--wrench", "nan,0,0"], "NaN"),
        (["analyze", "pinch", "--wrench", "fq=1"], "unknown wrench axis 'fq'"),
        (["analyze", "case1", "--wrench", "0,1,0"], "expected 6 numbers"),
        (["max-wrench", "pinch", "--direction", "fq"], "unknown direction 'fq'"),
        (["max-wrench", "pinch", "--direction", "-fz"], "planar"),
        (["max-wrench", "pinch", "--direction", "0,0,0,0,0,0"], "zero-length"),
        (["max-wrench", "pinch", "-d", "fy", "--preload", "nope"], "unknown preload 'nope'"),
        (["max-wrench", "pinch", "-d", "fy", "--upper", "-1"], "--upper"),
        (["profile", "pinch", "--plane", "fx"], "--plane"),
        (["profile", "pinch", "--plane", "fx,fq"], "unknown wrench axis 'fq'"),
        (["profile", "pinch", "-n", "0"], "-n"),
        (["compare-preloads", "pinch"], "named preload"),
        (["max-wrench", "/nonexistent/scene.yaml", "-d", "fy"], "scene file not found"),
        (["analyze", "pinch"], "required: --wrench"),
        (["frobnicate"], "invalid choice"),
        (["profile", "pinch", "--method", "simplex"], "invalid choice"),
    ],
)
def test_bad_input_exits_2_with_one_line(argv, fragment, capsys):
    rc, out, err = run(capsys, *argv)
    assert rc == 2
    assert err.startswith("pinograsp: error: ") and err.count("\n") == 1, err
    assert fragment in err
    assert "Traceback" not in err and out == ""


def test_malformed_scene_file(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("contacts: [\n")
    rc, _, err = run(capsys, "max-wrench", str(bad), "-d", "fy")
    assert rc == 2 and "bad.yaml" in err and "malformed YAML" in err and err.count("\n") == 1


def test_debug_shows_the_traceback(capsys):
    with pytest.raises(pg.UnknownNameError):
        main(["--debug", "analyze", "nosuch", "--wrench", "0,0,0"])
    with pytest.raises(pg.InvalidInputError):
        main(["analyze", "pinch", "--wrench", "0,5", "--debug"])


def test_help_exits_0(capsys):
    assert main(["--help"]) == 0
    assert "compare-preloads" in capsys.readouterr().out
    assert main(["profile", "--help"]) == 0
    assert "--normalize" in capsys.readouterr().out


def test_installed_entry_point_json_only_on_stdout(tmp_path):
    """One subprocess: the console script (or ``python -m pinograsp.cli``), JSON on stdout only."""
    cmd = [sys.executable, "-m", "pinograsp.cli", "max-wrench", "pinch", "-d", "-fy"]
    cmd += ["--upper", "100", "--steps", "10", "--json"]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    assert data["magnitude"] == pytest.approx(10.0, abs=0.1)
    res = subprocess.run(
        [sys.executable, "-m", "pinograsp.cli", "profile", "nosuch"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert res.returncode == 2 and res.stdout == ""
    assert res.stderr.strip().splitlines() == [res.stderr.strip()]
    assert res.stderr.startswith("pinograsp: error: unknown scene 'nosuch'")


def test_variant_and_html_options(tmp_path, capsys):
    """--variant reaches the solver (seed case 3, distal tendon alone: the held-still and the
    settled preload differ); --html writes the standalone plotly view."""
    s = pg.load_scene("case3")
    for variant in ("preload-first", "settled-preload"):
        assert main(["analyze", "case3", "-w", "0,0,0,0.01,0,0", "--preload", "distal_only",
                     "--variant", variant, "--json"]) == 0  # fmt: skip
        data = json.loads(capsys.readouterr().out)
        ref = pg.passive_response(
            s.model, s.preload("distal_only"), [0, 0, 0, 0.01, 0, 0], settings=s.settings, variant=variant
        )
        assert data["variant"] == variant and data["status"] == ref.status
    assert ref.variant == "settled-preload"
    html = tmp_path / "view.html"
    assert main(["max-wrench", "pinch", "-d", "fy", "--steps", "4", "--html", str(html)]) == 0
    assert html.stat().st_size > 100_000 and "plotly" in html.read_text()[:20000].lower()
