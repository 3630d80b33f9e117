"""``--json`` on every command writes exactly one JSON document on stdout and nothing else
(issue 33: ``pinograsp scenes --json`` wrote its document to stderr). Every sub-command that
takes ``--json`` is run (the parser is enumerated, so a new command cannot be forgotten), at the
file-descriptor level (solvers may write to fd 1 directly)."""

import argparse
import json

import pytest

from pinograsp.cli import main
from pinograsp.cli.parse import build_parser

#: A cheap run of each command (the analytic pinch: 10 N along ±y at command 1).
RUNS = {
    "demo": ["demo", "--scene", "pinch", "-n", "4", "--out", "{tmp}"],
    "scenes": ["scenes"],
    "analyze": ["analyze", "pinch", "--wrench", "0,5,0"],
    "max-wrench": ["max-wrench", "pinch", "-d", "fy"],
    "profile": ["profile", "pinch", "-n", "4"],
    "compare-preloads": ["compare-preloads", "{tmp}/two.yaml"],
    "resistance-set": ["resistance-set", "pinch", "-n", "4"],
    "preload": ["preload", "pinch"],
    "optimal-preload": ["optimal-preload", "pinch", "-w", "fy=1", "--grid", "2", "--refine", "0"],
    "simulate": ["simulate", "pinch", "-d", "fy"],
    "path": ["path", "pinch", "-d", "fy"],
    "plan": ["plan", "parallel_jaw", "sphere:0.02", "--n", "2", "--top", "1", "--mu", "0.5"],
}


def _json_commands():
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sorted(n for n, p in sub.choices.items() if any("--json" in a.option_strings for a in p._actions))


def test_every_json_command_is_run():
    assert sorted(RUNS) == _json_commands()


@pytest.mark.parametrize("argv", [*RUNS.values(), ["scenes", "pinch"]], ids=[*RUNS, "scenes-one"])
def test_json_is_one_document_on_stdout(argv, tmp_path, capfd):
    if argv[0] == "simulate":
        pytest.importorskip("mujoco")
    (tmp_path / "two.yaml").write_text(
        "extends: pinch\nanalysis: {plane: [fx, fy], directions: {up: fy},\n"
        "  preloads: {one: {left: 1.0, right: 1.0}, two: {left: 2.0, right: 2.0}}}\n"
    )
    code = main([a.replace("{tmp}", str(tmp_path)) for a in argv] + ["--json"])
    out, err = capfd.readouterr()
    assert code == 0, err
    doc = json.loads(out)  # exactly one document: json.loads refuses trailing text
    assert isinstance(doc, dict) and doc
    assert not err.lstrip().startswith("{"), err[:200]  # the document is not (also) on stderr
    if argv == ["scenes"]:
        assert "pinch" in doc
    if argv[:2] == ["max-wrench", "pinch"]:
        assert json.dumps(doc).count("10.0") >= 1  # the closed form
