"""The fixed query list of scripts/reproduce/bit_identity.py gives the committed baseline's
answers bit for bit (issue #24: the registry refactor changes no number)."""

import importlib.util
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "reproduce" / "bit_identity.py"


@pytest.mark.slow
def test_answers_bit_identical_to_baseline():
    spec = importlib.util.spec_from_file_location("bit_identity", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    lines = mod.run()
    assert len(lines) >= 40
    assert mod.compare(lines, mod.BASELINE.read_text().splitlines()) == []
