"""The bad-input table (tests/data/bad_inputs.py; docs/errors.md): every designed bad input gets
its named pinograsp error with the expected message fragment, or its verdict. No raw exception,
no silently wrong number, no hang (each row is cheap: refused before any work)."""

from __future__ import annotations

import importlib.util
import sys
import warnings
from collections import Counter
from pathlib import Path

import pytest

import pinograsp as pg

_spec = importlib.util.spec_from_file_location("bad_inputs", Path(__file__).parent / "data" / "bad_inputs.py")
table = importlib.util.module_from_spec(_spec)  # type: ignore[arg-type]
sys.modules["bad_inputs"] = table  # dataclasses look their module up
_spec.loader.exec_module(table)  # type: ignore[union-attr]


def test_the_table_covers_every_area():
    areas = Counter(c.area for c in table.CASES)
    assert len(table.CASES) >= 80 and len({c.id for c in table.CASES}) == len(table.CASES)
    assert set(areas) == {"api", "cli", "scene", "hand", "batch", "sim"}, areas


@pytest.mark.parametrize("case", table.CASES, ids=[c.id for c in table.CASES])
def test_bad_input(case, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if case.error is None:
            out = case.run(tmp_path)
            assert case.verdict(out), out
            return
        with pytest.raises(pg.PinograspError) as info:
            case.run(tmp_path)
    assert isinstance(info.value, case.error), f"{type(info.value).__name__}: {info.value}"
    assert case.match in str(info.value)
    assert len(str(info.value)) < 2000  # a message never expands its input


def test_the_quasistatic_path_keeps_only_the_domains_that_apply_to_it():
    """``method="quasistatic"`` (the method table, core/methods.py: not bounded by upper and
    steps) does not bisect: ``steps`` is not
    bounded by MAX_STEPS, ``upper`` is not checked against the grasp; a load the path must
    reach (``up_to``) keeps the load domain (docs/errors.md, "Input domains")."""
    from pinograsp.core import examples

    pinch = examples.pinch()  # closed form 2 mu tau0 / L = 10 N along +y at command 1
    assert pg.Query("quasistatic", steps=1000).steps == 1000
    with pytest.raises(pg.InvalidInputError, match=r"steps: must be an integer in \[1, 60\]"):
        pg.Query("iterative", steps=1000)
    with pytest.raises(pg.InvalidInputError, match="steps"):
        pg.Query("quasistatic", steps=2.5)
    with pytest.raises(pg.InvalidInputError, match=r"upper: must be in \[1e-06, 1e\+12\]"):
        pg.Query("quasistatic", upper=1e300)
    with pytest.raises(pg.InvalidInputError, match="times the grasp's force scale"):
        pg.max_resistible_wrench(pinch, 1.0, "fy", "iterative", upper=1e9)
    ref = pg.max_resistible_wrench(pinch, 1.0, "fy", "quasistatic")
    far = pg.max_resistible_wrench(pinch, 1.0, "fy", "quasistatic", upper=1e9, steps=500)
    assert far.status == ref.status and far.magnitude == ref.magnitude  # neither applies
    with pytest.raises(pg.InvalidInputError, match="up_to"):
        pg.loading_path(pinch, 1.0, "fy", up_to=1e11)  # > 1e6 x the 10 N pinch's force scale
    with pytest.raises(pg.InvalidInputError, match="up_to"):
        pg.loading_path(pinch, 1.0, "fy", up_to="5 N")
    with pytest.raises(pg.InvalidInputError, match=r"max_segments: must be an integer in \[1, 1000000\]"):
        pg.loading_path(pinch, 1.0, "fy", max_segments=10**7)
    assert pg.loading_path(pinch, 1.0, "fy", up_to=1.0).status == "reached"
    from pinograsp.cli import main  # the CLI's --steps: the same rule

    argv = ["max-wrench", "pinch", "--direction", "fy", "--steps", "500"]
    assert main([*argv, "--method", "quasistatic"]) == 0 and main(argv) == 0  # (the default)
    assert main([*argv, "--method", "iterative"]) == 2
