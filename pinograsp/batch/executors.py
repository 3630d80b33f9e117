"""Where a batch runs: this process, a local process pool, a Ray cluster or a Dask cluster.

:func:`run_chunks` maps a module-level function over chunks of tasks and returns the results
**in the order of the chunks**, whatever order they complete in, calling ``progress(done,
total)`` as chunks arrive. Ray and Dask are optional (``pip install "pinograsp[ray]"``,
``"pinograsp[dask]"``) and imported only when asked for.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import Any, Literal

from ..errors import InvalidInputError, MissingDependencyError

#: Executor names accepted by :func:`run_chunks` (besides a ``distributed.Client`` or a
#: ``concurrent.futures.Executor``).
EXECUTORS = ("local", "ray", "dask")
ExecutorName = Literal["local", "ray", "dask"]
Progress = Callable[[int, int], None] | None

# state installed in local pool workers (fork: passed without pickling, so lambdas work)
_INSTALLED: list[Any] = []


def _install(fn: Callable, args: tuple) -> None:
    _INSTALLED[:] = [fn, args]


def _run_installed(chunk: Any) -> Any:
    fn, args = _INSTALLED
    return fn(chunk, *args)


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
) -> list[Any]:
    """``[fn(chunk, *args) for chunk in chunks]`` on an executor, results in chunk order.

    Args:
        fn: A module-level function (importable by workers).
        chunks: The work, one item per task.
        args: Extra arguments of every call (the score, options).
        executor: ``"local"`` (process pool; ``workers=1``: this process), ``"ray"``, ``"dask"``,
            a ``distributed.Client`` or any ``concurrent.futures.Executor``.
        workers: Processes (local), Ray tasks in flight, or Dask local workers; ``0``: one per
            CPU; ``None``: one per CPU (local, a new Dask cluster) or as many as the cluster runs.
        address: Ray (``"auto"``, ``"ray://host:10001"``) or Dask scheduler (``"tcp://host:8786"``)
            address of an existing cluster.
        progress: ``progress(done, total)`` in this process as results arrive; ``sizes[i]``
            (default 1) counts chunk ``i``.
        sizes: Items per chunk, for ``progress``.
    """
    sizes = list(sizes) if sizes is not None else [1] * len(chunks)
    total = sum(sizes)
    state = {"done": 0}

    def arrived(i: int) -> None:
        state["done"] += sizes[i]
        if progress is not None:
            progress(state["done"], total)

    if progress is not None:
        progress(0, total)
    if isinstance(executor, str):
        name = executor if executor in EXECUTORS else None
        if name is None:
            raise InvalidInputError("executor", f"must be one of {EXECUTORS}, a dask Client or an Executor")
        if address is not None and name == "local":
            raise InvalidInputError("address", "an address goes with executor='ray' or 'dask'")
        if name == "ray":
            return _run_ray(fn, chunks, args, workers, address, arrived)
        if name == "dask":
            return _run_dask(fn, chunks, args, workers, address, None, arrived)
        nw = min(worker_count(workers, os.cpu_count() or 1) or 1, max(1, len(chunks)))
        if nw == 1:
            out = []
            for i, c in enumerate(chunks):
                out.append(fn(c, *args))
                arrived(i)
            return out
        return _run_pool(fn, chunks, args, nw, arrived)
    if is_dask_client(executor):
        return _run_dask(fn, chunks, args, workers, address, executor, arrived)
    from concurrent.futures import Executor

    if isinstance(executor, Executor):
        futures = [executor.submit(_call, fn, c, args) for c in chunks]
        return _collect(futures, arrived)
    raise InvalidInputError(
        "executor", f"must be one of {EXECUTORS}, a dask Client or an Executor, got {executor!r}"
    )


def _collect(futures: list, arrived: Callable[[int], None]) -> list[Any]:
    from concurrent.futures import as_completed

    index = {f: i for i, f in enumerate(futures)}
    out: list[Any] = [None] * len(futures)
    for f in as_completed(futures):
        out[index[f]] = f.result()
        arrived(index[f])
    return out


def _run_pool(fn: Callable, chunks: Sequence, args: tuple, workers: int, arrived: Callable) -> list[Any]:
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor

    fork = "fork" in mp.get_all_start_methods()
    ctx = mp.get_context("fork" if fork else "spawn")
    if not fork:  # spawn pickles the initializer's arguments
        import pickle

        try:
            pickle.dumps((fn, args))
        except Exception as exc:
            raise InvalidInputError("score", f"cannot be sent to worker processes: {exc}") from exc
    with ProcessPoolExecutor(workers, mp_context=ctx, initializer=_install, initargs=(fn, args)) as pool:
        return _collect([pool.submit(_run_installed, c) for c in chunks], arrived)


def _missing(package: str, extra: str, feature: str) -> MissingDependencyError:
    return MissingDependencyError(package, feature, extra=extra)


def _run_ray(
    fn: Callable, chunks: Sequence, args: tuple, workers: int | None, address: str | None, arrived: Callable
) -> list[Any]:
    try:
        import ray
    except ImportError:
        raise _missing("ray", "ray", "executor='ray'") from None
    nw = worker_count(workers)
    owned = not ray.is_initialized()
    if owned:
        if address is not None:
            ray.init(address=address, log_to_driver=False)
        else:
            ray.init(num_cpus=nw or os.cpu_count() or 1, include_dashboard=False, log_to_driver=False)
    try:
        remote = ray.remote(num_cpus=1, max_retries=0)(_call)
        limit = nw or max(1, int(ray.cluster_resources().get("CPU", 1)))
        shared = ray.put(args)
        out: list[Any] = [None] * len(chunks)
        pending: dict[Any, int] = {}
        nxt = 0
        while nxt < len(chunks) or pending:
            while nxt < len(chunks) and len(pending) < 2 * limit:  # two per worker: no idle gaps
                pending[remote.remote(fn, chunks[nxt], shared)] = nxt
                nxt += 1
            ready, _ = ray.wait(list(pending), num_returns=1)
            i = pending.pop(ready[0])
            out[i] = ray.get(ready[0])
            arrived(i)
        return out
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
    arrived: Callable,
) -> list[Any]:
    try:
        import distributed
    except ImportError:
        raise _missing("distributed", "dask", "executor='dask'") from None
    owned: list[Any] = []
    if client is None:
        if address is not None:
            client = distributed.Client(address)
        else:
            nw = worker_count(workers, os.cpu_count() or 1)
            cluster = distributed.LocalCluster(
                n_workers=nw, threads_per_worker=1, processes=True, dashboard_address=":0"
            )
            owned.append(cluster)
            client = distributed.Client(cluster)
        owned.insert(0, client)
    try:
        futures = [client.submit(_call, fn, c, args, pure=False) for c in chunks]
        index = {f.key: i for i, f in enumerate(futures)}
        out: list[Any] = [None] * len(chunks)
        for f in distributed.as_completed(futures):
            i = index[f.key]
            out[i] = f.result()
            arrived(i)
        return out
    finally:
        for o in owned:
            o.close()
