"""A local pool of worker processes that survives its workers, and batch interruption.

:func:`run_pool` maps a module-level function over tasks on ``workers`` processes of its own
(``multiprocessing``, fork on Linux), one task per worker at a time, over a pipe each:

- a worker that dies (``os._exit``, a segfault, the OOM killer) costs one retry of its task
  (``retries``) on a fresh process, then the task's result is a :class:`TaskFailure`
  (``"worker_crashed"``): never the batch (no ``BrokenProcessPool``);
- an opt-in per-task wall-clock limit (``timeout`` [s]) kills the worker and makes the result a
  :class:`TaskFailure` (``"timeout"``); it is the only wall-clock limit of pinograsp and the
  row says so;
- workers die with their parent (:func:`pinograsp.core.processes.die_with_parent`: prctl on
  Linux plus a watchdog thread); they ignore SIGINT (the parent decides);
- Ctrl-C (SIGINT) or SIGTERM in the parent kills every worker at once and raises
  :class:`Interrupted`; a second signal during the clean-up exits the process at once.

Results are reported as they arrive through ``on_result(i, result)`` (in this process).
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
import time
import traceback
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any, Literal

from ..core.processes import die_with_parent


@dataclass(frozen=True)
class TaskFailure:
    """A task that produced no result.

    Attributes:
        kind: ``"worker_crashed"`` (its process died, on every attempt), ``"timeout"`` (the
            opt-in wall-clock limit) or ``"exception"`` (the function raised; text in ``detail``).
        detail: One sentence: the exit signal or code, the limit, or the exception.
        attempts: How many times the task was started.
        seconds: Wall time of the last attempt [s] (when known).
    """

    kind: Literal["worker_crashed", "timeout", "exception"]
    detail: str
    attempts: int = 1
    seconds: float = 0.0


class Interrupted(KeyboardInterrupt):
    """The batch was interrupted by SIGINT (Ctrl-C) or SIGTERM; pending work was cancelled.

    Attributes:
        signum: The signal (``signal.SIGINT`` or ``signal.SIGTERM``).
        done: Tasks finished (kept), when known; ``total``: tasks of the batch.
        journal: The file holding the finished rows, when there is one.
    """

    def __init__(self, signum: int = signal.SIGINT, done: int = 0, total: int = 0, journal: object = None):
        super().__init__(signum)
        self.signum = int(signum)
        self.done = done
        self.total = total
        self.journal = journal

    @property
    def exit_code(self) -> int:
        """The shell convention ``128 + signal``: 130 for SIGINT, 143 for SIGTERM."""
        return 128 + self.signum


def _hard_exit(signum: int, frame: object) -> None:  # pragma: no cover - exits the process
    os._exit(128 + signum)


def _raise_interrupted(signum: int, frame: object) -> None:
    raise Interrupted(signum)


@contextlib.contextmanager
def interruptible() -> Iterator[None]:
    """SIGTERM raises :class:`Interrupted` like Ctrl-C does, while the block runs (main thread
    only, and only where SIGTERM still has its default action)."""
    main = threading.current_thread() is threading.main_thread()
    previous = signal.getsignal(signal.SIGTERM) if main else None
    if main and previous in (signal.SIG_DFL, None):
        signal.signal(signal.SIGTERM, _raise_interrupted)
    try:
        yield
    finally:
        if main and previous in (signal.SIG_DFL, None):
            signal.signal(signal.SIGTERM, signal.SIG_DFL)


@contextlib.contextmanager
def hard_exit_on_signal() -> Iterator[None]:
    """During a clean-up after an interrupt: a second SIGINT or SIGTERM exits at once."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    saved = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    for s in saved:
        signal.signal(s, _hard_exit)
    try:
        yield
    finally:
        for s, h in saved.items():
            signal.signal(s, h if h is not None else signal.SIG_DFL)


# ------------------------------------------------------------------------------------ worker side
def _worker_main(conn: Any, parent: int, fn: Callable, args: tuple) -> None:
    """A worker: ``(key, task)`` in, ``(key, fn(task, *args))`` out, until ``None`` or EOF."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    die_with_parent(parent)
    while True:
        try:
            msg = conn.recv()
        except (EOFError, OSError):
            break
        if msg is None:
            break
        key, task = msg
        try:
            result: Any = fn(task, *args)
        except Exception as exc:  # the function's own failure: reported, the worker lives on
            text = " ".join(f"{type(exc).__name__}: {exc}".split())
            result = TaskFailure("exception", text + " | " + traceback.format_exc(limit=-3).strip())
        try:
            conn.send((key, result))
        except Exception as exc:  # an unpicklable result
            conn.send((key, TaskFailure("exception", f"the result cannot be sent back: {exc}")))
    conn.close()


# ------------------------------------------------------------------------------------ parent side
def _signal_text(code: int | None) -> str:
    if code is None:
        return "an unknown cause"
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        hint = " (killed: e.g. the out-of-memory killer)" if -code == signal.SIGKILL else ""
        return f"{name}{hint}"
    return f"exit code {code}"


class _Worker:
    """One worker process, its pipe, and the task it runs."""

    def __init__(self, ctx: Any, fn: Callable, args: tuple) -> None:
        parent_end, child_end = ctx.Pipe(duplex=True)
        self.proc = ctx.Process(target=_worker_main, args=(child_end, os.getpid(), fn, args), daemon=True)
        self.proc.start()
        child_end.close()
        self.conn = parent_end
        self.task: int | None = None
        self.started = 0.0

    def assign(self, i: int, task: Any) -> None:
        self.task, self.started = i, time.monotonic()
        self.conn.send((i, task))

    def kill(self) -> None:
        with contextlib.suppress(Exception):
            self.proc.kill()
        self.proc.join(5.0)
        with contextlib.suppress(Exception):
            self.conn.close()

    def stop(self) -> None:
        with contextlib.suppress(Exception):
            self.conn.send(None)
        self.proc.join(1.0)
        if self.proc.is_alive():
            self.kill()
        with contextlib.suppress(Exception):
            self.conn.close()


def _context(fn: Callable, args: tuple) -> Any:
    import multiprocessing as mp

    fork = "fork" in mp.get_all_start_methods()
    if not fork:  # spawn pickles the function and its arguments
        import pickle

        from ..errors import InvalidInputError

        try:
            pickle.dumps((fn, args))
        except Exception as exc:
            raise InvalidInputError("score", f"cannot be sent to worker processes: {exc}") from exc
    return mp.get_context("fork" if fork else "spawn")


def run_pool(
    fn: Callable[..., Any],
    tasks: Sequence[Any],
    args: tuple,
    workers: int,
    on_result: Callable[[int, Any], None],
    *,
    timeout: float | None = None,
    retries: int = 1,
) -> None:
    """Run ``fn(task, *args)`` for every task on ``workers`` processes; report each result
    (or :class:`TaskFailure`) through ``on_result(i, result)`` as it arrives.

    Raises:
        Interrupted: SIGINT/SIGTERM (workers killed first; finished results were reported).
    """
    from multiprocessing.connection import wait

    ctx = _context(fn, args)
    pending = deque(range(len(tasks)))
    attempts = [0] * len(tasks)
    pool: list[_Worker] = []
    left = len(tasks)
    try:
        while left:
            _fill(pool, pending, attempts, workers, lambda: _Worker(ctx, fn, args), tasks)
            busy = [w for w in pool if w.task is not None]
            limit = None
            if timeout is not None and busy:
                limit = max(0.0, min(w.started + timeout for w in busy) - time.monotonic()) + 1e-3
            ready = set(wait([w.conn for w in busy] + [w.proc.sentinel for w in busy], limit))
            for w in busy:
                outcome = _outcome(w, ready, attempts, retries, timeout)
                if outcome is None:
                    continue
                kind, value = outcome
                i = w.task
                assert i is not None
                w.task = None
                if kind == "retry":
                    pending.appendleft(i)
                else:
                    left -= 1
                    on_result(i, value)
                if kind != "result":
                    pool.remove(w)
    except KeyboardInterrupt as exc:
        with hard_exit_on_signal():
            for w in pool:
                w.kill()
        pool.clear()
        raise exc if isinstance(exc, Interrupted) else Interrupted(signal.SIGINT) from None
    finally:
        for w in pool:
            w.stop()


def _fill(
    pool: list[_Worker],
    pending: deque,
    attempts: list[int],
    workers: int,
    new: Callable[[], _Worker],
    tasks: Sequence[Any],
) -> None:
    """Give every idle worker a pending task, starting workers up to ``workers``; a worker that
    died while idle is replaced (its task is not charged an attempt)."""
    failures = 0
    while pending:
        while len(pool) < workers and sum(w.task is None for w in pool) < len(pending):
            pool.append(new())
        idle = [w for w in pool if w.task is None]
        if not idle:
            return
        for w in idle:
            if not pending:
                return
            i = pending.popleft()
            try:
                w.assign(i, tasks[i])
                attempts[i] += 1
            except (OSError, ValueError):  # the pipe of a worker that died while idle
                w.task = None
                pending.appendleft(i)
                w.kill()
                pool.remove(w)
                failures += 1
                if failures > 10 * workers:
                    from ..errors import PinograspError

                    raise PinograspError(
                        f"{failures} worker processes died before they could take a task "
                        "(memory? process limits?): run with workers=1 to see the cause"
                    ) from None


def _outcome(
    w: _Worker, ready: set, attempts: list[int], retries: int, timeout: float | None
) -> tuple[str, Any] | None:
    """What happened to a busy worker: ``("result", value)``, ``("retry", None)`` or
    ``("failed", TaskFailure)``; ``None`` while it is still working."""
    i = w.task
    assert i is not None
    if w.conn in ready or w.proc.sentinel in ready:
        try:
            if w.conn.poll():
                key, value = w.conn.recv()
                if key == i:
                    return "result", value
        except (EOFError, OSError):
            pass
        w.proc.join(5.0)
        code = w.proc.exitcode
        w.kill()
        if attempts[i] <= retries:
            return "retry", None
        return "failed", TaskFailure(
            "worker_crashed",
            f"the worker process died ({_signal_text(code)}) while evaluating it, on each of "
            f"{attempts[i]} attempts",
            attempts[i],
            time.monotonic() - w.started,
        )
    if timeout is not None and time.monotonic() - w.started > timeout:
        w.kill()
        return "failed", TaskFailure(
            "timeout",
            f"not finished within the per-grasp time limit of {timeout:g} s (timeout={timeout:g}: "
            "an opt-in wall-clock limit, so whether it is hit depends on the machine)",
            attempts[i],
            time.monotonic() - w.started,
        )
    return None
