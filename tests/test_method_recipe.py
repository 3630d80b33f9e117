"""The recipe of docs/design.md, "Adding a method", stays true (issue #32 item 1): a toy method
that is only its row (``support.rigid_lp.SPEC``) and its module (``support.rigid_lp``),
registered here, answers ``max_resistible_wrench``, profiles, a scene file and ``--method`` on
the command line with the right resolution text; the package never names it."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from support.clirun import run
from support.rigid_lp import SPEC, RigidLpMethod

import pinograsp as pg
from pinograsp.analysis.method_base import MethodBase
from pinograsp.analysis.registry import get_method
from pinograsp.core import examples
from pinograsp.core.methods import method_names, register_method, search_text, unregister_method

PACKAGE = Path(pg.__file__).parent
MU, TAU, L = 0.5, 1.0, 0.1
TOY = SPEC.name


def closed_form(theta: float) -> float:
    """The rigid LP's limit on the pinch along ``(cos θ, sin θ)`` [N]: each normal force in
    ``[0, τ0 / L]`` (the tangential forces do not load the joints), equal tangential forces (the
    moment about the object's centre) and ``|t| <= μ n``: ``λ = (2 μ τ0 / L) / (|sin θ| + 2 μ
    |cos θ|)``."""
    return (2 * MU * TAU / L) / (abs(np.sin(theta)) + 2 * MU * abs(np.cos(theta)))


@pytest.fixture
def toy():
    register_method(SPEC)
    yield examples.pinch()
    unregister_method(TOY)


def test_the_toy_is_its_row_and_the_methods_it_overrides(toy):
    assert method_names()[-1] == TOY and get_method(TOY).spec == SPEC
    declared = {k for k in vars(RigidLpMethod) if not k.startswith("__")}
    assert declared == {"response", "max_load"}  # every other rule: the base class's default
    base = MethodBase(SPEC)
    assert base.floor(None, np.zeros(6), 1e3, 20) == 0.0 and base.preload_method == TOY  # type: ignore[arg-type]
    assert base.preload_error(None, 1.0) is None  # type: ignore[arg-type]
    hits = [p for p in PACKAGE.rglob("*.py") if TOY in p.read_text() or "rigid_lp" in p.read_text()]
    assert hits == []  # nothing in the package names it


@pytest.mark.parametrize("deg", range(0, 360, 30))
def test_max_resistible_wrench_is_the_closed_form(toy, deg):
    t = np.radians(deg)
    d = [np.cos(t), np.sin(t), 0.0]
    mw = pg.max_resistible_wrench(toy, TAU, d, TOY, upper=1.0, steps=99)  # upper/steps do not apply
    assert mw.status == "finite" and mw.magnitude == pytest.approx(closed_form(t), rel=1e-9)
    assert mw.method == TOY and mw.search == "direct" and mw.resolution == 0.0
    # its own responses bracket it: resisted just below, not just above
    below = pg.passive_response(toy, TAU, 0.999 * mw.magnitude * np.array(d), TOY)
    above = pg.passive_response(toy, TAU, 1.001 * mw.magnitude * np.array(d), TOY)
    assert below.resistible and below.method == TOY and not above.resistible
    assert np.allclose(below.net_wrench, 0.0, atol=1e-9)


def test_profile_and_scene_file(toy, tmp_path):
    p = pg.resistance_profile(toy, TAU, n=8, method=TOY)
    expected = [closed_form(a) for a in p.angles]
    np.testing.assert_allclose(p.magnitudes, expected, rtol=1e-9)
    assert all(r.method == TOY for r in p.results)
    text = (PACKAGE / "data" / "scenes" / "pinch.yaml").read_text()
    scene_file = tmp_path / "pinch_rigid.yaml"
    scene_file.write_text(text.replace("  steps: 20\n", f"  steps: 99\n  method: {TOY}\n"))
    scene = pg.load_scene(str(scene_file))
    assert scene.analysis.method == TOY and scene.analysis.steps == 99  # steps: not bounded
    assert scene.max_resistible_wrench("up").magnitude == pytest.approx(closed_form(np.pi / 2), rel=1e-9)


def test_command_line_method_and_resolution_text(toy, capsys, tmp_path):
    rc, out, _ = run(capsys, "max-wrench", "pinch", "-d", "fy", "--method", TOY)
    assert rc == 0 and search_text(TOY, 1e3, 20) in out and "resolution" not in out
    assert "max resistible magnitude: 10.0000 N (exact)" in out
    rc, out, _ = run(capsys, "max-wrench", "pinch", "-d", "fy", "--method", TOY, "--json")
    data = json.loads(out)
    assert rc == 0 and data["method"] == TOY and data["magnitude"] == pytest.approx(10.0, rel=1e-9)
    rc, out, _ = run(capsys, "max-wrench", "--help")
    assert rc == 0 and f"{TOY} ({SPEC.help})" in " ".join(out.split())


def test_one_rule_for_its_variants_and_its_missing_preload_stage(toy):
    with pytest.raises(pg.InvalidInputError, match="'preload-first' does not apply to method='rigid_lp'"):
        pg.max_resistible_wrench(toy, TAU, "fy", TOY, variant="preload-first")
    with pytest.raises(pg.InvalidInputError, match="'settled-preload' does not apply to method='rigid_lp'"):
        pg.passive_response(toy, TAU, [0, 1.0, 0], TOY, variant="settled-preload")
    with pytest.raises(pg.InvalidInputError, match="'rigid_lp' has no preload stage"):
        pg.equilibrium_preload(toy, TOY)
    with pytest.raises(pg.InvalidInputError, match="'rigid_lp' has no preload stage"):
        pg.optimal_preload(toy, [[0.0, 5.0, 0.0]], TOY)
