"""Resume checks what it resumes (issue 33): the fingerprint covers the score, the records, the
contents of the files they name and in-memory scenes; a finished table resumes only with its
stamp; cut or damaged tables and journals are named errors that leave the files as they are; a
full disk is ``InvalidInputError('out')`` with the rows written so far intact.

Grasps are the analytic pinch (closed form 2 mu tau0 / L: 10 N at tau0 = 1, 30 N at tau0 = 3,
50 N at tau0 = 5) and wedge scenes."""

import errno
import json
import math

import pytest

import pinograsp as pg
from pinograsp.batch.pool import Interrupted
from pinograsp.cli import main

pd = pytest.importorskip("pandas")

SCORE = pg.WorstAxisScore(upper=100, steps=4)
PINCH = (pg.load_scene("pinch").path).read_text()


def _stop_at_wedge(model, command):
    """The score, interrupting the batch at a wedge (the pinch rows before it are journaled)."""
    values = SCORE(model, command)
    if not math.isclose(values["score"], 10.0 * max(command.values())):  # not a pinch: the wedge
        raise KeyboardInterrupt
    return values


def _interrupted(records, out):
    with pytest.raises(Interrupted):
        pg.evaluate_grasps(records, score=_stop_at_wedge, workers=1, out=out)
    assert out.with_name(out.name + ".partial.jsonl").is_file()


def test_an_edited_referenced_scene_file_is_another_batch(tmp_path):
    base = tmp_path / "base.yaml"
    base.write_text(PINCH)
    scene = tmp_path / "grasp.yaml"
    scene.write_text("extends: base.yaml\nname: mine\n")
    out = tmp_path / "r.csv"
    _interrupted([str(scene), "wedge"], out)
    base.write_text(PINCH.replace("preload: 1.0 ", "preload: 3.0 "))  # edited between kill and resume
    journal = out.with_name("r.csv.partial.jsonl").read_bytes()
    with pytest.raises(pg.InvalidInputError, match="resume: .* another batch .*start afresh"):
        pg.evaluate_grasps([str(scene), "wedge"], score=_stop_at_wedge, workers=1, out=out, resume=True)
    assert out.with_name("r.csv.partial.jsonl").read_bytes() == journal  # left as it is
    base.write_text(PINCH)  # undone: the same batch again, its journal's row is kept
    with pytest.raises(Interrupted) as info:
        pg.evaluate_grasps([str(scene), "wedge"], score=_stop_at_wedge, workers=1, out=out, resume=True)
    assert info.value.done == 1
    base.write_text(PINCH.replace("preload: 1.0 ", "preload: 3.0 "))
    fresh = pg.evaluate_grasps([str(scene), "wedge"], score=SCORE, workers=1, out=out)
    assert fresh.loc[0, "score"] == pytest.approx(30.0, rel=1e-12)  # 2 mu tau0 / L, tau0 = 3 (stale: 10)


def test_a_loaded_scene_with_another_preload_is_another_batch(tmp_path):
    out = tmp_path / "r.csv"
    first = pg.evaluate_grasps([pg.load_scene("pinch")], score=SCORE, workers=1, out=out)
    assert first.loc[0, "score"] == 10.0
    other = pg.load_scene("pinch", preload=5.0)
    with pytest.raises(pg.InvalidInputError, match="another batch"):
        pg.evaluate_grasps([other], score=SCORE, workers=1, out=out, resume=True)
    again = pg.evaluate_grasps([other], score=SCORE, workers=1, out=out)
    assert again.loc[0, "score"] == pytest.approx(50.0, rel=1e-12)


def _grasps_file(tmp_path, mu):
    path = tmp_path / "grasps.yaml"
    path.write_text(
        f"defaults: {{mu: {mu}}}\nscore: {{upper: 20, steps: 4}}\ngrasps:\n"
        "  - hand: parallel_jaw\n"
        "    object: {shape: box, size: [0.04, 0.04, 0.04], pose: {xyz: [0, 0, 0.1]}}\n"
        "  - {scene: pinch, id: p}\n"
    )
    return path


def test_cli_resume_of_a_finished_batch_with_another_method_or_mu_is_refused(tmp_path, capsys):
    grasps, out = _grasps_file(tmp_path, 0.5), tmp_path / "r.csv"
    argv = ["batch", str(grasps), "--out", str(out), "--workers", "1", "--no-progress"]
    assert main(argv) == 0
    table = out.read_bytes()
    capsys.readouterr()
    assert main([*argv, "--resume", "--method", "iterative"]) == 2
    assert "another batch" in capsys.readouterr().err and out.read_bytes() == table
    _grasps_file(tmp_path, 0.9)  # mu: 0.5 -> 0.9 in the GRASPS file
    assert main([*argv, "--resume"]) == 2
    assert "another batch" in capsys.readouterr().err and out.read_bytes() == table
    _grasps_file(tmp_path, 0.5)
    assert main([*argv, "--resume"]) == 0 and out.read_bytes() == table  # the same batch: nothing runs


def test_a_table_cut_mid_row_or_without_stamp_is_refused(tmp_path):
    out = tmp_path / "r.csv"
    records = ["pinch", "wedge", "pinch"]
    pg.evaluate_grasps(records, score=SCORE, workers=1, out=out)
    text = out.read_bytes()
    out.write_bytes(text[: len(text) - 40])  # cut in the last row
    with pytest.raises(pg.InvalidInputError, match="edited, cut or damaged"):
        pg.evaluate_grasps(records, score=SCORE, workers=1, out=out, resume=True)
    assert out.read_bytes() == text[: len(text) - 40]
    out.write_bytes(text)
    out.with_name("r.csv.batch.json").unlink()
    with pytest.raises(pg.InvalidInputError, match="no readable stamp"):
        pg.evaluate_grasps(records, score=SCORE, workers=1, out=out, resume=True)


@pytest.mark.parametrize(
    "line", [b'["a list"]\n', b'{"index": 0}\n', b"\xff\xfe not utf-8\n", b'{"index": "0", "id": "0"}\n']
)
def test_a_damaged_journal_line_is_a_named_error(tmp_path, line):
    out = tmp_path / "r.csv"
    _interrupted(["pinch", "pinch", "wedge"], out)
    journal = out.with_name("r.csv.partial.jsonl")
    lines = journal.read_bytes().splitlines(keepends=True)
    damaged = b"".join([lines[0], line, *lines[1:]])
    journal.write_bytes(damaged)
    with pytest.raises(pg.InvalidInputError, match="line 2 .*damaged"):
        pg.evaluate_grasps(["pinch", "pinch", "wedge"], score=_stop_at_wedge, workers=1, out=out, resume=True)
    assert journal.read_bytes() == damaged  # the sound rows are kept


def test_a_full_disk_is_the_named_error_and_keeps_the_rows_written(tmp_path, monkeypatch, capsys):
    from pinograsp.batch import journal as journal_module

    real = journal_module.Journal._write
    calls = []

    def full(self, records):
        records = list(records)
        calls.append(len(records))
        if len(calls) > 2:  # the header and one row fit, then the disk is full
            self._file.write(json.dumps(records[0])[:17])  # a part of the line reaches the disk
            self._file.flush()
            raise pg.InvalidInputError("out", "cannot append: No space left on device")
        real(self, records)

    monkeypatch.setattr(journal_module.Journal, "_write", full)
    out = tmp_path / "r.csv"
    with pytest.raises(pg.InvalidInputError, match="^out: .*No space left"):
        pg.evaluate_grasps(["pinch", "wedge", "pinch"], score=SCORE, workers=1, out=out)
    monkeypatch.setattr(journal_module.Journal, "_write", real)
    df = pg.evaluate_grasps(["pinch", "wedge", "pinch"], score=SCORE, workers=1, out=out, resume=True)
    assert df["score"].tolist()[0::2] == [10.0, 10.0] and df["status"].tolist() == ["ok"] * 3


def test_enospc_in_the_journal_and_the_table_are_out_errors(tmp_path, monkeypatch, capsys):
    """A real ``OSError(ENOSPC)`` from the file: the journal's append, its close (the flush that
    failed is not raised again: 'unexpected failure: OSError' before), the table's write."""
    from pinograsp.batch import journal as journal_module

    class FullFile:
        def __init__(self, f, budget):
            self.f, self.budget = f, budget

        def write(self, text):
            self.budget -= len(text)
            if self.budget < 0:
                raise OSError(errno.ENOSPC, "No space left on device")
            return self.f.write(text)

        def __getattr__(self, name):
            return getattr(self.f, name)

        def close(self):
            self.f.close()
            raise OSError(errno.ENOSPC, "No space left on device")  # the buffered flush again

    real_lock = journal_module.Journal._lock

    def lock(self):
        real_lock(self)
        self._file = FullFile(self._file, 1500)

    monkeypatch.setattr(journal_module.Journal, "_lock", lock)
    grasps = _grasps_file(tmp_path, 0.5)
    grasps.write_text("grasps:\n" + "".join("  - {scene: pinch}\n" for _ in range(6)))
    out = tmp_path / "r.csv"
    assert main(["batch", str(grasps), "--out", str(out), "--workers", "1", "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "--out" in err or "out: cannot append" in err, err
    assert "unexpected" not in err and "No space left on device" in err
    monkeypatch.undo()
    kept = out.with_name("r.csv.partial.jsonl").read_text().splitlines()
    assert 2 <= len(kept) < 7  # the header and the rows that fitted

    def enospc(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(pd.DataFrame, "to_csv", enospc)
    with pytest.raises(pg.InvalidInputError, match="out: cannot write .*No space left"):
        pg.evaluate_grasps(["pinch"], score=SCORE, workers=1, out=tmp_path / "t.csv")
    assert (tmp_path / "t.csv.partial.jsonl").is_file() and not (tmp_path / "t.csv").exists()
