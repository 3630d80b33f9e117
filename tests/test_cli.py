"""The CLI demo writes numbers that match the closed form."""

import json

import numpy as np

from pinograsp.cli import main


def test_demo_writes_pinch_profile(tmp_path, capsys):
    rc = main(
        ["demo", "--out", str(tmp_path), "-n", "4", "--methods", "prp", "--upper", "100", "--steps", "14"]
    )
    assert rc == 0
    data = json.loads((tmp_path / "profile.json").read_text())
    prof = data["profiles"]["prp"]
    assert prof["unbounded"] == [True, False, True, False]  # ±x unbounded, ±y finite
    np.testing.assert_allclose([prof["magnitude"][1], prof["magnitude"][3]], [10.0, 10.0], atol=100 / 2**14)
    assert (tmp_path / "profile.png").stat().st_size > 1000
    assert "unbounded" in capsys.readouterr().out


def test_cli_errors_are_one_line(capsys):
    rc = main(["demo", "--out", "/tmp/x", "-n", "0"])
    assert rc == 2
    err = capsys.readouterr().err
    assert err.startswith("pinograsp: error:") and err.count("\n") == 1
