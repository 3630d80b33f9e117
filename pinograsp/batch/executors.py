"""Where a batch runs: this process, a local process pool, a Ray cluster or a Dask cluster.

:func:`run_chunks` maps a module-level function over chunks of tasks and returns the results
**in the order of the chunks**, whatever order they complete in, calling ``on_result(i,
result)`` and ``progress(done, total)`` as chunks arrive. A chunk that produced no result (its
worker died on every attempt, it ran past the opt-in time limit, its function raised) has a
:class:`~pinograsp.batch.pool.TaskFailure` as its result: the batch goes on. Ctrl-C or SIGTERM
cancels the pending work and raises :class:`~pinograsp.batch.pool.Interrupted`.

The local executor is pinograsp's own pool (:mod:`.pool`). Ray and Dask are optional (``pip
install "pinograsp[ray]"``, ``"pinograsp[dask]"``), imported only when asked for, and used with
what they offer: one retry of a task whose worker died (Ray ``max_retries=1``, Dask
``retries=1``), cancellation of pending tasks on an interrupt.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import Any, Literal

from ..errors import InvalidInputError, MissingDependencyError
from .pool import Interrupted, TaskFailure, run_pool

#: Executor names accepted by :func:`run_chunks` (besides a ``distributed.Client`` or a
#: ``concurrent.futures.Executor``).
EXECUTORS = ("local", "ray", "dask")
ExecutorName = Literal["local", "ray", "dask"]
Progress = Callable[[int, int], None] | None
Arrived = Callable[[int, Any], None]
#: Seconds to reach an existing Ray or Dask cluster at ``address`` before the named error.
CONNECT_TIMEOUT = 30.0


def connect(
    what: str, address: str, open_connection: Callable[[], Any], seconds: float = CONNECT_TIMEOUT
) -> Any:
    """``open_connection()`` (e.g. ``ray.init(address=...)``), refused with a named error when it
    fails or has not returned within ``seconds`` (it then goes on in a daemon thread, abandoned).

    Raises:
        InvalidInputError: ``address``: the cluster cannot be reached (the address and what to check).
    """
    import threading

    box: dict[str, Any] = {}

    def run() -> None:
        try:
            box["value"] = open_connection()
        except Exception as exc:  # the cluster library's own types (OSError, ConnectionError, ...)
            box["error"] = exc

    thread = threading.Thread(target=run, name=f"pinograsp-{what}-connect", daemon=True)
    thread.start()
    thread.join(seconds)
    hint = f"check that a {what} cluster runs there and is reachable from this machine"
    if thread.is_alive():
        raise InvalidInputError(
            "address", f"no {what} cluster answered at {address!r} within {seconds:g} s: {hint}"
        )
    if "error" in box:
        exc = box["error"]
        text = " ".join(f"{type(exc).__name__}: {exc}".split())[:300]
        raise InvalidInputError("address", f"cannot reach the {what} cluster at {address!r} ({text}): {hint}")
    return box.get("value")


def _call(fn: Callable, chunk: Any, args: tuple) -> Any:
    return fn(chunk, *args)


def worker_count(workers: object, default: int | None = None) -> int | None:
    """``workers`` validated: ``None`` -> ``default``; ``0`` -> one per CPU; else the count."""
    if workers is None:
        return default
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
        raise InvalidInputError("workers", f"must be an integer >= 0 or None, got {workers!r}")
    return workers or (os.cpu_count() or 1)


def is_dask_client(obj: object) -> bool:
    """Whether ``obj`` is a ``distributed.Client`` (checked without importing distributed)."""
    return type(obj).__module__.split(".")[0] == "distributed" and hasattr(obj, "submit")


def check_executor(executor: object, address: object, timeout: object) -> None:
    """Refuse an unknown executor name, an address for the local executor and a time limit
    anywhere but the local executor (before any work starts)."""
    if isinstance(executor, str):
        if executor not in EXECUTORS:
            raise InvalidInputError("executor", f"must be one of {EXECUTORS}, a dask Client or an Executor")
        if address is not None and executor == "local":
            raise InvalidInputError("address", "an address goes with executor='ray' or 'dask'")
    if timeout is not None and executor != "local":
        raise InvalidInputError(
            "timeout", "a per-grasp time limit needs executor='local' (pinograsp's own worker processes)"
        )


def run_chunks(
    fn: Callable[..., Any],
    chunks: Sequence[Any],
    args: tuple,
    *,
    executor: object = "local",
    workers: int | None = None,
    address: str | None = None,
    progress: Progress = None,
    sizes: Sequence[int] | None = None,
    on_result: Arrived | None = None,
    timeout: float | None = None,
) -> list[Any]:
    """``[fn(chunk, *args) for chunk in chunks]`` on an executor, results in chunk order.

    Args:
        fn: A module-level function (importable by workers).
        chunks: The work, one item per task.
        args: Extra arguments of every call (the score, options).
        executor: ``"local"`` (own process pool; ``workers=1`` without ``timeout``: this
            process), ``"ray"``, ``"dask"``, a ``distributed.Client`` or any
            ``concurrent.futures.Executor``.
        workers: Processes (local), Ray tasks in flight, or Dask local workers; ``0``: one per
            CPU; ``None``: one per CPU (local, a new Dask cluster) or as many as the cluster runs.
        address: Ray (``"auto"``, ``"ray://host:10001"``) or Dask scheduler (``"tcp://host:8786"``)
            address of an existing cluster.
        progress: ``progress(done, total)`` in this process as results arrive; ``sizes[i]``
            (default 1) counts chunk ``i``.
        sizes: Items per chunk, for ``progress``.
        on_result: ``on_result(i, result)`` in this process as chunk ``i`` finishes.
        timeout: Per-chunk wall-clock limit [s] (local executor only; opt-in).

    Raises:
        Interrupted: SIGINT or SIGTERM (pending work cancelled; finished chunks were reported).
    """
    check_executor(executor, address, timeout)
    sizes = list(sizes) if sizes is not None else [1] * len(chunks)
    total = sum(sizes)
    state = {"done": 0}
    out: list[Any] = [None] * len(chunks)

    def arrived(i: int, result: Any) -> None:
        out[i] = result
        if on_result is not None:
            on_result(i, result)
        state["done"] += sizes[i]
        if progress is not None:
            progress(state["done"], total)

    if progress is not None:
        progress(0, total)
    if executor == "ray":
        _run_ray(fn, chunks, args, workers, address, arrived)
    elif executor == "dask":
        _run_dask(fn, chunks, args, workers, address, None, arrived)
    elif executor == "local":
        nw = min(worker_count(workers, os.cpu_count() or 1) or 1, max(1, len(chunks)))
        if nw == 1 and timeout is None:
            for i, c in enumerate(chunks):
                arrived(i, fn(c, *args))
        else:
            run_pool(fn, chunks, args, nw, arrived, timeout=timeout)
    elif is_dask_client(executor):
        _run_dask(fn, chunks, args, workers, address, executor, arrived)
    else:
        from concurrent.futures import Executor

        if not isinstance(executor, Executor):
            raise InvalidInputError(
                "executor", f"must be one of {EXECUTORS}, a dask Client or an Executor, got {executor!r}"
            )
        _collect([executor.submit(_call, fn, c, args) for c in chunks], arrived)
    return out


def _failure(exc: BaseException) -> TaskFailure:
    """A chunk lost to its executor (a dead worker, a broken pool, a lost task)."""
    return TaskFailure("worker_crashed", " ".join(f"{type(exc).__name__}: {exc}".split()))


def _collect(futures: list, arrived: Arrived) -> None:
    from concurrent.futures import as_completed

    index = {f: i for i, f in enumerate(futures)}
    try:
        for f in as_completed(futures):
            try:
                result = f.result()
            except Exception as exc:  # a broken executor or a dead worker: this chunk's failure
                result = _failure(exc)
            arrived(index[f], result)
    except KeyboardInterrupt as exc:
        for f in futures:
            f.cancel()
        raise exc if isinstance(exc, Interrupted) else Interrupted() from None


def _missing(package: str, extra: str, feature: str) -> MissingDependencyError:
    return MissingDependencyError(package, feature, extra=extra)


def _run_ray(
    fn: Callable, chunks: Sequence, args: tuple, workers: int | None, address: str | None, arrived: Arrived
) -> None:
    try:
        import ray
    except ImportError:
        raise _missing("ray", "ray", "executor='ray'") from None
    nw = worker_count(workers)
    owned = not ray.is_initialized()
    if owned:
        if address is not None:
            connect("Ray", address, lambda: ray.init(address=address, log_to_driver=False))
        else:
            ray.init(num_cpus=nw or os.cpu_count() or 1, include_dashboard=False, log_to_driver=False)
    pending: dict[Any, int] = {}
    try:
        remote = ray.remote(num_cpus=1, max_retries=1)(_call)  # one retry of a task whose worker died
        limit = nw or max(1, int(ray.cluster_resources().get("CPU", 1)))
        shared = ray.put(args)
        nxt = 0
        while nxt < len(chunks) or pending:
            while nxt < len(chunks) and len(pending) < 2 * limit:  # two per worker: no idle gaps
                pending[remote.remote(fn, chunks[nxt], shared)] = nxt
                nxt += 1
            ready, _ = ray.wait(list(pending), num_returns=1)
            i = pending.pop(ready[0])
            try:
                result = ray.get(ready[0])
            except ray.exceptions.RayError as exc:  # WorkerCrashedError, lost object, ...
                result = _failure(exc)
            arrived(i, result)
    except KeyboardInterrupt as exc:
        for ref in pending:
            try:
                ray.cancel(ref, force=True)
            except Exception:  # noqa: S112 - best effort: already finished or lost
                continue
        raise exc if isinstance(exc, Interrupted) else Interrupted() from None
    finally:
        if owned:
            ray.shutdown()


def _run_dask(
    fn: Callable,
    chunks: Sequence,
    args: tuple,
    workers: int | None,
    address: str | None,
    client: Any,
    arrived: Arrived,
) -> None:
    try:
        import distributed
    except ImportError:
        raise _missing("distributed", "dask", "executor='dask'") from None
    owned: list[Any] = []
    if client is None:
        if address is not None:
            client = connect("Dask", address, lambda: distributed.Client(address, timeout=CONNECT_TIMEOUT))
        else:
            nw = worker_count(workers, os.cpu_count() or 1)
            cluster = distributed.LocalCluster(
                n_workers=nw, threads_per_worker=1, processes=True, dashboard_address=":0"
            )
            owned.append(cluster)
            client = distributed.Client(cluster)
        owned.insert(0, client)
    futures: list[Any] = []
    try:
        futures = [client.submit(_call, fn, c, args, pure=False, retries=1) for c in chunks]
        index = {f.key: i for i, f in enumerate(futures)}
        for f in distributed.as_completed(futures):
            try:
                result = f.result()
            except Exception as exc:  # KilledWorker (its worker died), a lost task
                result = _failure(exc)
            arrived(index[f.key], result)
    except KeyboardInterrupt as exc:
        try:
            client.cancel(futures)
        except Exception:  # noqa: S110 - best effort
            pass
        raise exc if isinstance(exc, Interrupted) else Interrupted() from None
    finally:
        for o in owned:
            o.close()
