"""Running the ``pinograsp`` command line in-process, for the CLI tests."""

from __future__ import annotations

import json

from pinograsp.cli import main


def run(capsys, *argv: str) -> tuple[int, str, str]:
    """Exit code, stdout and stderr of ``pinograsp ARGV``."""
    rc = main(list(argv))
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


def run_json(capsys, *argv: str) -> dict:
    """The one JSON document ``pinograsp ARGV --json`` writes on stdout (exit code 0)."""
    rc, out, err = run(capsys, *argv, "--json")
    assert rc == 0, err
    return json.loads(out)  # stdout holds exactly one JSON document
