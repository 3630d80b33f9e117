"""A batch that loses nothing (issue #26): interrupted, killed and resumed batches give the table
of an uninterrupted run, row for row, without duplicates or orphaned worker processes.

The CLI runs as a real subprocess (signals need a process of its own) through
``tests/support/batch_faults_cli.py``: the real ``pinograsp`` with the default score made slower by a
fixed sleep, so that the batch is still running when the test interrupts it. Grasps are the
cheap analytic pinch and wedge scenes. Waiting loops are bounded hang guards, never timed
asserts.
"""

import faulthandler
import json
import math
import os
import signal
import subprocess
import sys
import time
import types
from pathlib import Path

import pytest
from test_batch import BOX, CASE1_Q, FAST, same_table

import pinograsp as pg
from pinograsp.batch.journal import Journal
from pinograsp.batch.pool import Interrupted
from pinograsp.cli import main

pd = pytest.importorskip("pandas")
pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="uses /proc and signals")

HERE = Path(__file__).parent
N = 12
GRASPS = "score: {upper: 20, steps: 4}\ngrasps:\n" + "".join(
    f"  - {{scene: {'pinch' if i % 2 == 0 else 'wedge'}, id: g{i}}}\n" for i in range(N)
)


@pytest.fixture(scope="module")
def batch_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("faults") / "grasps.yaml"
    path.write_text(GRASPS)
    return path


@pytest.fixture(scope="module")
def reference(batch_file):
    """The uninterrupted run (in this process, one worker), as written by the CLI."""
    out = batch_file.parent / "reference.csv"
    assert main(["batch", str(batch_file), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    return read(out)


def read(path):
    """A CSV table as written (floats round-trip exactly; empty strings stay strings)."""
    df = pd.read_csv(path, dtype={"id": str})  # pandas >= 3: floats round-trip by default
    text = [c for c in df.columns if df[c].dtype == object or str(df[c].dtype).startswith("str")]
    return df.fillna(dict.fromkeys(text, ""))


def same_rows(a, b):
    """Equal row for row (bit for bit but the wall times), no duplicate grasp."""
    assert a["id"].is_unique and len(a) == len(b) == N
    same_table(a, b)


def spawn(tmp_path, delay, *extra, hold_after=None):
    """The slow CLI batch; ``hold_after=K``: grasps ending after K journaled rows wait to be killed
    (tests/support/batch_faults_cli.py), so an interrupt never races the batch's end."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(HERE.parent), os.environ.get("PYTHONPATH", "")]))
    if hold_after is not None:
        env["PINOGRASP_TEST_HOLD_AFTER"] = str(hold_after)
    cmd = [sys.executable, str(HERE / "support" / "batch_faults_cli.py"), str(delay), "batch", "grasps.yaml",
           "--out", "out.csv", "--workers", "2", "--no-progress", *extra]  # fmt: skip
    return subprocess.Popen(
        cmd, cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )


def journal_rows(path):
    if not path.is_file():
        return []
    return [json.loads(line) for line in path.read_text().splitlines()[1:] if line.endswith("}")]


def wait_until(predicate, what, tries=600):
    """Poll every 0.05 s (bounded: a hang guard of 30 s, not a timing assertion)."""
    for _ in range(tries):
        if predicate():
            return
        time.sleep(0.05)
    raise AssertionError(f"never happened: {what}")


def children(pid):
    """Process ids whose parent is ``pid`` (from /proc)."""
    out = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                stat = (d / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                out.append(int(d.name))
    return out


def alive(pid):
    """Running (a zombie waiting for its reaper counts as dead)."""
    try:
        return (Path("/proc") / str(pid) / "stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def busy_workers(proc, journal, rows=2):
    """Wait for ``rows`` finished rows and two live workers; their ids."""
    wait_until(lambda: len(journal_rows(journal)) >= rows, f"{rows} rows in the journal")
    wait_until(lambda: len(children(proc.pid)) == 2, "two worker processes")
    return children(proc.pid)


def finish(proc, timeout, workers=()):
    """``proc.communicate`` within ``timeout`` [s]; past it the test fails with what was still
    running (the batch process's state, its children, the workers alive) and the stack of every
    thread of the batch process (faulthandler on SIGUSR1, tests/support/batch_faults_cli.py):
    a hang is reported with its cause, never as a bare timeout."""
    try:
        return proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        running = proc.poll() is None
        kids = children(proc.pid) if running else []
        state = (
            f"batch process {'running' if running else f'exited with {proc.returncode}'}; "
            f"its children {kids}; workers alive {[w for w in workers if alive(w)]}"
        )
        if running:
            os.kill(proc.pid, signal.SIGUSR1)  # the batch's stacks, to its stderr
            time.sleep(1.0)
        for pid in {*kids, *workers}:
            if alive(pid):
                os.kill(pid, signal.SIGKILL)
        proc.kill()
        _, err = proc.communicate(timeout=30)
        pytest.fail(f"the batch did not end within {timeout} s of the test's signal: {state}\n{err[-6000:]}")


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupt_then_resume_equals_uninterrupted(tmp_path, batch_file, reference, sig, code):
    (tmp_path / "grasps.yaml").write_text(batch_file.read_text())
    journal = tmp_path / "out.csv.partial.jsonl"
    proc = spawn(tmp_path, 0.4, hold_after=2)
    workers = busy_workers(proc, journal)
    proc.send_signal(sig)
    _, err = finish(proc, 30, workers)
    assert proc.returncode == code, err
    assert "grasps finished; kept in out.csv.partial.jsonl" in err
    kept = journal_rows(journal)
    assert 2 <= len(kept) < N and not (tmp_path / "out.csv").exists()  # no table until complete
    wait_until(lambda: not any(alive(w) for w in workers), "workers gone after the interrupt")
    # resume: only the missing grasps run, the table is the uninterrupted one
    done = []
    grasps = pg.load_grasps(tmp_path / "grasps.yaml").grasps
    df = pg.evaluate_grasps(grasps, score=FAST, workers=2, out=tmp_path / "out.csv", resume=True,
                            progress=lambda d, t: done.append((d, t)))  # fmt: skip
    assert done[0] == (len(kept), N) and done[-1] == (N, N)
    same_rows(read(tmp_path / "out.csv"), reference)
    assert len(df) == N and not journal.exists()


def test_sigkill_of_a_worker_costs_one_retry(tmp_path, batch_file, reference):
    (tmp_path / "grasps.yaml").write_text(batch_file.read_text())
    proc = spawn(tmp_path, 0.4)
    workers = busy_workers(proc, tmp_path / "out.csv.partial.jsonl", rows=1)
    os.kill(workers[0], signal.SIGKILL)  # mid-grasp: that grasp runs again on a fresh worker
    _, err = finish(proc, 60, workers)
    assert proc.returncode == 0, err
    df = read(tmp_path / "out.csv")
    assert (df["status"] != "error").all()
    same_rows(df, reference)
    assert not children(proc.pid) and not any(alive(w) for w in workers)


def test_sigkill_of_the_batch_kills_its_workers_and_resume_finishes(tmp_path, batch_file, reference):
    (tmp_path / "grasps.yaml").write_text(batch_file.read_text())
    journal = tmp_path / "out.csv.partial.jsonl"
    proc = spawn(tmp_path, 0.4, hold_after=2)
    workers = busy_workers(proc, journal)
    proc.kill()
    finish(proc, 30, workers)
    wait_until(lambda: not any(alive(w) for w in workers), "workers die with their parent")
    with journal.open("a") as f:
        f.write('{"index": 11, "id": "g1')  # a line cut by the kill: dropped on resume
    rc = main(["batch", str(tmp_path / "grasps.yaml"), "--out", str(tmp_path / "out.csv"), "--resume",
               "--workers", "2", "--no-progress"])  # fmt: skip
    assert rc == 0
    same_rows(read(tmp_path / "out.csv"), reference)


def _is_wedge(values):
    """The wedge's row, whatever method FAST uses: the pinch's worst axis is its closed form
    2 mu tau0 / L = 10 N under every method (the wedge's: 6 N on the default path, 5 N by the
    iterative bisection at upper 20, steps 4)."""
    return values["score"] != 10.0


def _crash_on_wedge(model, command):
    values = FAST(model, command)
    if _is_wedge(values):
        os._exit(3)
    return values


def _crash_once(model, command):
    marker = Path(os.environ["PINOGRASP_TEST_MARKER"])
    if not marker.exists():
        marker.write_text("crashed")
        faulthandler.disable()  # a deliberate crash: no traceback dump
        os.kill(os.getpid(), signal.SIGSEGV)
    return FAST(model, command)


def test_crashing_grasp_is_an_error_row_after_one_retry(tmp_path, monkeypatch):
    df = pg.evaluate_grasps(["pinch", "wedge", "pinch"], score=_crash_on_wedge, workers=2)
    assert df["status"].tolist() == ["ok", "error", "ok"]
    assert df.loc[1, "reason"] == "worker_crashed" and math.isnan(df.loc[1, "score"])
    assert "exit code 3" in df.loc[1, "error_message"] and "2 attempts" in df.loc[1, "error_message"]
    assert df.loc[0, "score"] == df.loc[2, "score"] == 10.0
    monkeypatch.setenv("PINOGRASP_TEST_MARKER", str(tmp_path / "marker"))
    once = pg.evaluate_grasps(["pinch", "wedge"], score=_crash_once, workers=2)
    same_table(once, pg.evaluate_grasps(["pinch", "wedge"], score=FAST, workers=1))  # the retry succeeded


def _slow_wedge(model, command):
    values = FAST(model, command)
    if _is_wedge(values):
        time.sleep(60)
    return values


def test_timeout_row_is_never_a_number():
    # 5 s: far above the pinch's evaluation on a loaded machine, far below the wedge's 60 s sleep
    df = pg.evaluate_grasps(["pinch", "wedge"], score=_slow_wedge, workers=1, timeout=5.0)
    assert df["status"].tolist() == ["ok", "timeout"] and df["reason"].tolist() == ["", "timeout"]
    assert math.isnan(df.loc[1, "score"]) and "wall-clock" in df.loc[1, "error_message"]
    assert df.loc[1, "time_total"] >= 5.0
    with pytest.raises(pg.InvalidInputError, match="timeout"):
        pg.evaluate_grasps(["pinch"], executor="dask", timeout=1.0)
    with pytest.raises(pg.InvalidInputError, match="timeout"):
        pg.evaluate_grasps(["pinch"], timeout=0)


def test_every_table_has_its_columns(tmp_path):
    df = pg.evaluate_grasps(["no_such_scene", {"scene": "nor_this", "id": "x"}], workers=1)
    assert (df["status"] == "error").all() and (df["reason"] == "unknown_name").all()
    assert df.sort_values("score")["score"].isna().all() and "max_-fz" in df
    custom = pg.evaluate_grasps(["no_such_scene"], score=lambda m, c: {"nc": m.nc}, workers=1)
    assert "score" in custom and custom["score"].dtype == float
    pg.save_results(df, tmp_path / "e.csv")
    assert list(pd.read_csv(tmp_path / "e.csv").columns) == list(df.columns)


def test_rows_are_answers_no_preload_and_penetration():
    sampled = pg.sample_grasps("barrett_bh8_282", BOX, 3, seed=0, q_open={"bh_j11": math.pi / 2})
    inside = BOX.with_pose((0.0, 0.0, 0.0678), (0.0, 0.0, 0.0))
    deep = pg.GraspSpec("barrett_bh8_282", pg.ObjectSpec("box", size=(0.16, 0.05, 0.1), xyz=inside.xyz),
                        q=CASE1_Q, command=0.5, max_penetration=0.001, id="deep")  # fmt: skip
    palm = pg.GraspSpec("barrett_bh8_282", pg.ObjectSpec("box", size=(0.05, 0.05, 0.1), xyz=(0, 0, 0.0505)),
                        q=[0.0] * 8, id="palm-only")  # fmt: skip
    df = pg.evaluate_grasps([sampled[2], deep, palm], score=FAST, workers=1)
    assert df["status"].tolist() == ["no_grasp"] * 3
    assert df["reason"].tolist() == ["no_preload", "penetration", "no_preload"]
    assert "no actuator can press the object" in df.loc[2, "error_message"]
    assert df.loc[0, "error_type"] == "NoPreloadError" and "command None" not in df.loc[0, "error_message"]
    assert "no preload exists" in df.loc[0, "error_message"] and (df["score"] == 0).all()
    # the closing options reach the contact detection: a 5 mm limit accepts the same overlap
    tolerant = pg.evaluate_grasps([pg.GraspSpec(**{**deep.to_dict(), "max_penetration": 0.02})],
                                  score=FAST, workers=1)  # fmt: skip
    assert tolerant.loc[0, "status"] == "ok"  # the deepest overlap is 6.6 mm


def test_output_checked_before_work(tmp_path, capsys):
    blocker = tmp_path / "file.txt"
    blocker.write_text("x")
    started = []
    with pytest.raises(pg.InvalidInputError, match="out: cannot write"):
        pg.evaluate_grasps(["pinch"], out=blocker / "r.csv", progress=lambda d, t: started.append(d))
    assert not started
    assert main(["batch", "grasps.yaml", "--out", str(blocker / "r.csv")]) == 2
    assert "--out: cannot write" in capsys.readouterr().err
    assert main(["batch", "grasps.yaml", "--resume"]) == 2
    assert "--resume: needs --out" in capsys.readouterr().err
    with pytest.raises(pg.InvalidInputError, match="resume"):
        pg.evaluate_grasps(["pinch"], resume=True)
    busy = Journal(tmp_path / "busy.csv")  # another batch writing the same table
    busy.start("x", 1, resume=False)
    with pytest.raises(pg.InvalidInputError, match="another pinograsp batch is writing"):
        pg.evaluate_grasps(["pinch"], score=FAST, workers=1, out=tmp_path / "busy.csv")
    busy.close()
    done = pg.evaluate_grasps(["pinch"], score=FAST, workers=1, out=tmp_path / "busy.csv")
    assert done["status"].tolist() == ["ok"]


def test_second_interrupt_exits_at_once():
    code = "\n".join([
        "import os, signal, time", "from pinograsp.batch.pool import hard_exit_on_signal",
        "with hard_exit_on_signal():", "    os.kill(os.getpid(), signal.SIGINT)", "    time.sleep(60)",
    ])  # fmt: skip
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(HERE.parent), os.environ.get("PYTHONPATH", "")]))
    assert subprocess.run([sys.executable, "-c", code], env=env, timeout=30).returncode == 130


def test_resume_refuses_another_batch(tmp_path):
    out = tmp_path / "r.csv"
    journal = tmp_path / "r.csv.partial.jsonl"
    with pytest.raises(Interrupted):
        pg.evaluate_grasps(["pinch", "wedge"], score=_interrupt_on_wedge, workers=1, out=out)
    assert len(journal_rows(journal)) == 1
    with pytest.raises(pg.InvalidInputError, match="another batch"):
        pg.evaluate_grasps(["wedge", "pinch"], score=_interrupt_on_wedge, workers=1, out=out, resume=True)
    df = pg.evaluate_grasps(["pinch", "wedge"], score=FAST, workers=1, out=out)  # no resume: afresh
    assert df["status"].tolist() == ["ok", "ok"] and not journal.exists()


def _interrupt_on_wedge(model, command):
    values = FAST(model, command)
    if _is_wedge(values):
        raise KeyboardInterrupt
    return values


@pytest.mark.parametrize("suffix", ["csv", "parquet"])
def test_resume_of_a_finished_batch_runs_nothing(tmp_path, suffix):
    if suffix == "parquet":
        pytest.importorskip("pyarrow")
    out = tmp_path / f"r.{suffix}"
    grasps = ["pinch", "no_such_scene", {"scene": "wedge", "id": "w"}]
    first = pg.evaluate_grasps(grasps, score=FAST, workers=1, out=out)
    calls = []
    again = pg.evaluate_grasps(grasps, score=FAST, workers=1, out=out, resume=True,
                               progress=lambda d, t: calls.append((d, t)))  # fmt: skip
    assert calls == [(3, 3)]  # nothing evaluated: every row came from the table, bit for bit
    pd.testing.assert_frame_equal(again, first, check_exact=True)
    with pytest.raises(pg.InvalidInputError, match="another batch"):
        pg.evaluate_grasps(["pinch", "wedge", "wedge"], score=FAST, workers=1, out=out, resume=True)


def _pinch_last(model, command):
    values = FAST(model, command)
    if values["score"] == 10.0:  # pinch rows finish after the wedge rows
        time.sleep(0.5)
    return values


def test_rows_in_input_order_whatever_the_completion_order(tmp_path):
    grasps = ["pinch", "wedge", "pinch", "wedge", "no_such_scene"]
    df = pg.evaluate_grasps(grasps, score=_pinch_last, workers=3, out=tmp_path / "r.csv")
    assert df["index"].tolist() == list(range(5))  # wedge rows arrived first; the table is sorted
    same_table(df, pg.evaluate_grasps(grasps, score=FAST, workers=1))


class _Ref:
    """An object reference: hashable by identity, holding its call."""

    def __init__(self, f, args):
        self.call = (f, args)


class _FakeRay(types.ModuleType):
    """Just enough of Ray's API (remote, put, wait, get, cancel) to run the executor's own logic
    in this process: a task whose chunk holds ``crash`` fails as Ray's WorkerCrashedError does
    after its retries; ``interrupt_after`` waits, Ctrl-C."""

    def __init__(self, crash="", interrupt_after=None):
        super().__init__("ray")
        self.exceptions = types.SimpleNamespace(RayError=type("RayError", (Exception,), {}))
        self.crash, self.interrupt_after, self.waits = crash, interrupt_after, 0
        self.options, self.cancelled = {}, []

    def is_initialized(self):
        return True

    def cluster_resources(self):
        return {"CPU": 2}

    def put(self, value):
        return value

    def remote(self, **options):
        self.options = options
        return lambda f: types.SimpleNamespace(remote=lambda *a: _Ref(f, a))

    def wait(self, refs, num_returns=1):
        self.waits += 1
        if self.interrupt_after is not None and self.waits > self.interrupt_after:
            raise KeyboardInterrupt
        return refs[:1], refs[1:]

    def get(self, ref):
        f, (fn, chunk, args) = ref.call
        if any(task[3] == self.crash for task in chunk):
            raise self.exceptions.RayError("WorkerCrashedError: the worker died unexpectedly")
        return f(fn, chunk, args)

    def cancel(self, ref, force=False):
        self.cancelled.append((ref.call[1][1][0][1], force))


def test_ray_executor_retries_and_cancels(monkeypatch, tmp_path):
    ray = _FakeRay(crash="wedge")
    monkeypatch.setitem(sys.modules, "ray", ray)
    df = pg.evaluate_grasps(["pinch", "wedge", "pinch"], score=FAST, executor="ray")
    assert ray.options["max_retries"] == 1  # Ray retries a task whose worker died, once
    assert df["status"].tolist() == ["ok", "error", "ok"] and df.loc[1, "reason"] == "worker_crashed"
    ray = _FakeRay(interrupt_after=1)
    monkeypatch.setitem(sys.modules, "ray", ray)
    with pytest.raises(Interrupted) as info:
        pg.evaluate_grasps(["pinch"] * 5, score=FAST, executor="ray", workers=1, out=tmp_path / "r.csv")
    assert info.value.done == 1 and info.value.exit_code == 130
    assert ray.cancelled == [("1", True), ("2", True)]  # in flight (two per worker); 3, 4 never sent
    assert len(journal_rows(tmp_path / "r.csv.partial.jsonl")) == 1


class _FakeFuture:
    def __init__(self, key, call, crash):
        self.key, self.call, self.crash = key, call, crash

    def result(self):
        f, fn, chunk, args = self.call
        if any(task[3] == self.crash for task in chunk):
            raise RuntimeError("KilledWorker: the task's worker died 3 times")
        return f(fn, chunk, args)


class _FakeClient:
    """Just enough of ``distributed.Client`` (submit, cancel) for the executor's own logic."""

    __module__ = "distributed.client"

    def __init__(self, crash="", interrupt_after=None):
        self.crash, self.interrupt_after = crash, interrupt_after
        self.options, self.cancelled = {}, []

    def submit(self, f, fn, chunk, args, **options):
        self.options = options
        return _FakeFuture(f"k{chunk[0][0]}", (f, fn, chunk, args), self.crash)

    def cancel(self, futures):
        self.cancelled = [f.key for f in futures]


def test_dask_executor_retries_and_cancels(monkeypatch):
    client = _FakeClient(crash="wedge", interrupt_after=None)

    def as_completed(futures):
        for k, f in enumerate(futures):
            if client.interrupt_after is not None and k >= client.interrupt_after:
                raise KeyboardInterrupt
            yield f

    monkeypatch.setitem(sys.modules, "distributed", types.SimpleNamespace(as_completed=as_completed))
    df = pg.evaluate_grasps(["pinch", "wedge"], score=FAST, executor=client)
    assert client.options == {"pure": False, "retries": 1}  # Dask retries a lost task once
    assert df["reason"].tolist() == ["", "worker_crashed"] and "KilledWorker" in df.loc[1, "error_message"]
    client.interrupt_after = 1
    with pytest.raises(Interrupted):
        pg.evaluate_grasps(["pinch", "pinch", "pinch"], score=FAST, executor=client)
    assert client.cancelled == ["k0", "k1", "k2"]  # every future cancelled (finished ones: no-op)
