"""Every notebook in ``notebooks/`` executes with ``PINOGRASP_FAST=1`` (few directions and
steps), and is stored without outputs."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

import pinograsp as pg  # noqa: E402

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))
#: Notebooks that need a built-in scene (skipped, with the reason, while the scene is missing).
NEEDS_SCENE = {"case1": "case1", "case2": "case2", "case3": "case3", "fig1": "fig1"}


def test_notebooks_exist():
    names = {p.stem for p in NOTEBOOKS}
    assert {"case1", "case2", "case3", "fig1", "own_hand_allegro"} <= names


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_is_stripped(path):
    nb = nbformat.read(path, as_version=4)
    nbformat.validate(nb)
    for cell in nb.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, f"{path.name}: outputs not stripped"
    first = "\n".join(c.source for c in nb.cells if c.cell_type == "code")
    assert 'FAST = os.environ.get("PINOGRASP_FAST", "0") == "1"' in first


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_executes_fast(path, monkeypatch, tmp_path):
    scene = NEEDS_SCENE.get(path.stem)
    if scene is not None and scene not in pg.builtin_scenes():
        pytest.skip(f"built-in scene {scene!r} not available")
    monkeypatch.setenv("PINOGRASP_FAST", "1")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(
        nb,
        timeout=300,
        kernel_name="python3",
        resources={"metadata": {"path": str(tmp_path)}},
    )
    t0 = time.perf_counter()
    client.execute()  # raises CellExecutionError with the failing cell and traceback
    elapsed = time.perf_counter() - t0
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs if o.output_type == "error"]
    assert not errors
    print(f"{path.name}: {elapsed:.1f} s")
    assert os.environ["PINOGRASP_FAST"] == "1"
