"""Where things live beside the package (README "Layout", docs/design.md): benchmarks and the
reproduction scripts are packages whose modules import their siblings relatively, never by bare
name, never through ``sys.path``, never from ``tests/``; the benchmark suite's runner finds every
benchmark and its parameter grid."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("benchmarks", "scripts")


def _modules() -> list[Path]:
    return sorted(p for folder in FOLDERS for p in (ROOT / folder).rglob("*.py"))


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(ROOT)))
def test_scripts_import_only_packages_and_siblings_relatively(path):
    siblings = {p.stem for p in path.parent.glob("*.py")}
    tree = ast.parse(path.read_text())
    bad = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            names = [node.module or ""]
        else:
            names = []
        bad += [n for n in names if n.split(".")[0] in siblings | {"tests", "support"}]
        if isinstance(node, ast.Attribute) and ast.unparse(node) == "sys.path":
            bad.append("sys.path")
    assert bad == []


def test_every_folder_is_a_package_with_a_docstring():
    for init in (ROOT / "benchmarks" / "__init__.py", ROOT / "scripts" / "reproduce" / "__init__.py"):
        assert ast.get_docstring(ast.parse(init.read_text())), init


def test_the_runner_finds_every_benchmark_and_its_grid():
    from benchmarks import runner

    found = dict(runner.benchmark_classes())
    modules = {p.stem for p in (ROOT / "benchmarks").glob("bench_*.py")}
    assert {name.split(".")[0] for name in found} == modules
    for cls in found.values():
        grid = runner._grid(cls, quick=False)
        assert len(grid) == math.prod(len(p) for p in cls.params)
        assert runner._grid(cls, quick=True) == [tuple(p[0] for p in cls.params)]
