"""Running chunks of work: a thread pool on this machine, or a Dask cluster, with one reduction order.

:func:`run_chunks` keeps a bounded window of chunks in flight (twice the worker threads),
so memory is bounded by the chunk size, not by the number of chunks. Results are handed to
``consume`` in chunk order whatever order they finish in (a finished chunk waits in the
window for the ones before it), so floating-point sums come out bit for bit the same on
any engine, with any number of workers, and after a resume.

The local engine is a :class:`concurrent.futures.ThreadPoolExecutor`: the batch kernels
spend their time in NumPy and compiled code that release the GIL. A Dask engine is a
``dask.distributed.Client``; tasks go out with ``client.submit`` and come back through
``distributed.as_completed`` (Dask schedules them; nothing here does). Tasks must then be
picklable: a top-level function, bound with :func:`functools.partial` to plain data. The
bound data is scattered to every worker once (``client.scatter(..., broadcast=True)``) and
each chunk's task refers to it, so a large argument (the dexterity map's voxel list) is not
pickled again with every chunk.

Ctrl-C: the chunks in flight are dropped, ``checkpoint`` runs once more (it records the
chunks consumed so far) and :class:`InterruptedRun` is raised; ``checkpoint`` itself always
runs with Ctrl-C held back until it is done, so a store is never left half-written by it.
"""

from __future__ import annotations

import os
import signal
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from contextlib import contextmanager
from functools import partial
from numbers import Integral
from typing import Any

from armkit._params import thread_count
from armkit.errors import ArmkitError, InputError

__all__ = ["InterruptedRun", "connect", "engine_threads", "run_chunks"]

#: Seconds between checkpoints of a long run.
CHECKPOINT_SECONDS = 30.0


class InterruptedRun(ArmkitError):
    """A run stopped by Ctrl-C; the chunks finished before it are kept (in the store, if any)."""


def connect(address: str) -> Any:
    """A ``dask.distributed.Client`` for the scheduler at ``address`` (e.g. ``tcp://host:8786``)."""
    try:
        from distributed import Client
    except ImportError as exc:
        raise InputError("--dask needs dask.distributed: pip install 'armkit[workspace]'") from exc
    try:
        return Client(address, timeout="10s")
    except (OSError, TimeoutError) as exc:
        raise InputError(f"cannot reach the Dask scheduler at {address!r}: {exc}") from exc


def engine_threads(engine: Any) -> int:
    """Worker threads of ``engine``: ``None`` (all local cores), an int (that many threads) or a Client."""
    if engine is None:
        return os.cpu_count() or 1
    if isinstance(engine, Integral) and not isinstance(engine, bool):
        return thread_count(engine, "engine")
    if hasattr(engine, "nthreads") and hasattr(engine, "submit"):
        return max(1, sum(engine.nthreads().values()))
    raise InputError(f"engine: expected None, a number of threads or a dask.distributed.Client, "
                     f"got {engine!r}")


@contextmanager
def _holding_interrupts() -> Iterator[None]:
    """Hold Ctrl-C back until the block is done, then deliver it (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[Any] = []
    previous = signal.signal(signal.SIGINT, lambda *args: caught.append(args))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if caught:
        raise KeyboardInterrupt


class _Threads:
    def __init__(self, workers: int, task: Callable[[int], Any]) -> None:
        self.pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="armkit-workspace")
        self.task = task

    def submit(self, chunk: int) -> Any:
        return self.pool.submit(self.task, chunk)

    def finished(self, futures: set) -> set:
        return wait(futures, return_when=FIRST_COMPLETED).done

    def close(self, cancel: bool) -> None:
        self.pool.shutdown(wait=True, cancel_futures=cancel)


class _Dask:
    def __init__(self, client: Any, task: Callable[[int], Any]) -> None:
        from distributed import as_completed

        self.client, self.completed = client, as_completed()
        self.function, self.args = task, ()
        if isinstance(task, partial):  # its data goes to every worker once, not with every chunk
            self.function = partial(task.func, **task.keywords)
            self.args = tuple(client.scatter(list(task.args), broadcast=True, hash=False))

    def submit(self, chunk: int) -> Any:
        future = self.client.submit(self.function, *self.args, chunk, pure=False)
        self.completed.add(future)
        return future

    def finished(self, futures: set) -> set:
        return {next(self.completed)}

    def close(self, cancel: bool) -> None:
        if cancel:
            self.completed.clear()
        self.args = ()  # the scattered data is released with its futures


def run_chunks(task: Callable[[int], Any], chunks: Sequence[int], consume: Callable[[int, Any], None], *,
               engine: Any = None, progress: bool = False, description: str = "",
               checkpoint: Callable[[], None] | None = None,
               checkpoint_seconds: float = CHECKPOINT_SECONDS) -> None:
    """Run ``task(chunk)`` for every chunk and hand each result to ``consume(chunk, result)``, in order.

    Parameters
    ----------
    task : callable
        ``task(chunk) -> result``; picklable for a Dask engine.
    chunks : sequence of int
        The chunks to run, in the order their results are consumed.
    consume : callable
        Called in the main thread, in the order of ``chunks``.
    engine : None, int or dask.distributed.Client
        ``None``: a thread per local core; an int: that many threads; a Client: its cluster.
    progress : bool
        Show a progress bar with the time remaining (on stderr).
    checkpoint : callable, optional
        Called every ``checkpoint_seconds`` [s], at the end and on Ctrl-C, with Ctrl-C held back.

    Raises
    ------
    InterruptedRun
        On Ctrl-C, after the last checkpoint.
    """
    window = 2 * engine_threads(engine)
    pending = iter(chunks)
    order = list(chunks)
    in_flight: dict[Any, int] = {}
    done: dict[int, Any] = {}
    position, last_saved = 0, time.monotonic()
    bar = _progress_bar(progress, description, len(order))

    def fill() -> None:
        for chunk in pending:
            in_flight[runner.submit(chunk)] = chunk
            if len(in_flight) >= window:
                return

    def save() -> None:
        if checkpoint is not None:
            with _holding_interrupts():
                checkpoint()

    cancelled = False
    runner: _Threads | _Dask | None = None
    try:
        local = engine is None or isinstance(engine, int)
        runner = _Threads(engine_threads(engine), task) if local else _Dask(engine, task)
        fill()
        while position < len(order):
            for future in runner.finished(set(in_flight)):
                done[in_flight.pop(future)] = future.result()
            while position < len(order) and order[position] in done:
                consume(order[position], done.pop(order[position]))
                position += 1
                bar.advance()
            fill()
            if time.monotonic() - last_saved > checkpoint_seconds:
                save()
                last_saved = time.monotonic()
        save()
    except KeyboardInterrupt:
        cancelled = True
        for future in in_flight:
            future.cancel()
        save()
        raise InterruptedRun(f"interrupted after {position} of {len(order)} chunks{description and ' of '}"
                             f"{description}") from None
    finally:
        if runner is not None:
            runner.close(cancel=cancelled)
        bar.stop()


class _NoBar:
    def advance(self) -> None:
        pass

    def stop(self) -> None:
        pass


class _Bar:
    def __init__(self, description: str, total: int) -> None:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.progress = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                                 TextColumn("tasks"), TimeElapsedColumn(), TextColumn("eta"),
                                 TimeRemainingColumn(), console=Console(stderr=True), transient=False)
        self.task = self.progress.add_task(description, total=total)
        self.progress.start()

    def advance(self) -> None:
        self.progress.advance(self.task)

    def stop(self) -> None:
        self.progress.stop()


def _progress_bar(show: bool, description: str, total: int) -> _Bar | _NoBar:
    return _Bar(description, total) if show else _NoBar()
