"""Every process pinograsp starts dies with its parent (issue 33): the direction pools of
``profile``, ``resistance-set`` and ``demo`` with ``--workers 2``, killed by SIGTERM or SIGKILL
while their workers are busy, leave no process behind (the batch pool: tests/test_batch_faults.py).
Waiting loops are bounded hang guards, not timed asserts."""

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from test_batch_faults import alive, children, wait_until

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="uses /proc and signals")
HERE = Path(__file__).parent
COMMANDS = {
    "profile": ["profile", "pinch", "-n", "8", "--workers", "2"],
    "resistance-set": ["resistance-set", "pinch", "-n", "8", "--workers", "2"],
    "demo": ["demo", "--scene", "pinch", "-n", "8", "--workers", "2", "--out", "{tmp}"],
}


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
@pytest.mark.parametrize("command", list(COMMANDS))
def test_killed_parent_leaves_no_worker(command, sig, tmp_path):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(HERE.parent), os.environ.get("PYTHONPATH", "")]))
    argv = [a.replace("{tmp}", str(tmp_path)) for a in COMMANDS[command]]
    proc = subprocess.Popen(
        [sys.executable, str(HERE / "support" / "slow_directions_cli.py"), *argv, "--no-progress"],
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    workers = []
    try:
        wait_until(lambda: len(children(proc.pid)) >= 2 or proc.poll() is not None, "two workers", 1200)
        workers = children(proc.pid)
        assert len(workers) >= 2 and all(alive(w) for w in workers), proc.stderr.read() if proc.poll() else ""
        os.kill(proc.pid, sig)
        proc.wait(timeout=30)
        wait_until(lambda: not any(alive(w) for w in workers), "the workers die with their parent")
    finally:
        for pid in {*children(proc.pid), *workers}:  # a failed test leaves nothing either
            if alive(pid):
                os.kill(pid, signal.SIGKILL)
        proc.kill()
        proc.wait(timeout=30)
    assert proc.returncode == -sig
