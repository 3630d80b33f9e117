"""The README's "Your own hand" examples run end to end (load, close, preload, max wrench,
profile, pictures), each under 25 lines; numbers they print are checked against the API."""

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import pinograsp as pg

README = Path(__file__).resolve().parents[1] / "README.md"


def _example(name: str) -> str:
    text = README.read_text()
    m = re.search(rf"<!-- readme-example: {name} -->\n```python\n(.*?)```", text, re.S)
    assert m, f"README example {name!r} not found"
    return m.group(1)


@pytest.mark.parametrize("name", ["allegro", "so101"])
def test_readme_own_hand_example(name, tmp_path, monkeypatch, capsys):
    code = _example(name)
    assert len(code.strip().splitlines()) < 25
    monkeypatch.chdir(tmp_path)
    ns: dict = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pg.AuditWarning)
        exec(compile(code, f"README:{name}", "exec"), ns)
    out = capsys.readouterr().out
    preload, model = ns["preload"], ns["model"]
    assert preload.in_equilibrium and max(abs(v) for v in preload.command.values()) > 0
    # the Allegro's balanced preload balances, but 5 contacts sit on their friction limits
    assert preload.status == ("slides" if name == "allegro" else "found"), preload.reason
    r = pg.passive_response(model, preload.command, np.zeros(6))
    assert r.resistible and r.normal_forces.min() > 0  # every contact presses at the preload
    assert ns["r"].resistible  # the example's one wrench is resisted
    for png in tmp_path.glob("*.png"):
        assert png.stat().st_size > 10_000
    assert len(list(tmp_path.glob("*.png"))) == (2 if name == "allegro" else 1)
    assert name == "so101" or preload.reason in out
    result = ns["push"] if name == "allegro" else ns["pull"]
    assert result.status in ("finite", "unbounded", "above_limit", "below_resolution")
    assert ns["profile"].summary() in out


def test_readme_giveway_example(capsys):
    """The give-way example prints what the README says it prints (the numbers from the API)."""
    text = README.read_text()
    printed = re.search(
        r"<!-- readme-example: giveway -->\n```python\n.*?```\n\nprints\n\n```\n(.*?)```", text, re.S
    )
    assert printed, "the README's printed lines of the give-way example"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        exec(compile(_example("giveway"), "README:giveway", "exec"), {})
    assert capsys.readouterr().out == printed.group(1)


def test_readme_pinch_example(capsys):
    """The pinch example prints what its comments say: 10 N per contact at 5 N along +y, both
    motors at their command 1 N·m (labels moving/holding with the PRP), 10 N = 2 mu tau0 / L."""
    ns: dict = {}
    exec(compile(_example("pinch"), "README:pinch", "exec"), ns)
    first = capsys.readouterr().out.splitlines()[0]
    assert first == "True [10. 10.] ('moving', 'holding')"
    r, p = ns["r"], ns["p"]
    np.testing.assert_allclose(r.normal_forces, [10.0, 10.0], rtol=1e-9)
    np.testing.assert_allclose(r.actuator_forces, [1.0, 1.0], rtol=1e-9)  # exactly the command
    iterative = pg.passive_response(ns["model"], 1.0, [0.0, 5.0, 0.0], method="iterative")
    assert iterative.actuator_modes == ("moving", "moving")
    assert p.magnitudes[18] == pytest.approx(2 * 0.5 * 1.0 / 0.1, abs=1e-3) and p.unbounded[0]
