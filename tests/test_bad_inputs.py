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
