"""Threads that never hold up an interrupt.

A native solver call (Clarabel) does not return to Python until it ends, and Python runs a
signal's handler only in the main thread, between bytecodes: a conic solve in the main thread
held Ctrl-C and SIGTERM back for its whole length (12.5 s in the demo's static bound, minutes
on a large mesh). Here such a call runs in a daemon thread while the main thread waits on its
``Future``, a wait that a handler interrupts at once. The abandoned call runs on until it
ends or the process exits (daemon threads do not hold the exit up).

- ``background(fn, ...)``: ``fn`` started in a daemon thread, its ``Future``;
- ``call(fn, ...)``: ``fn``'s result, waited for interruptibly (in the main thread);
- ``map_threads(fn, items, n)``: ``[fn(x) for x in items]``, n at a time, in order;
- ``map_here(fn, items)``: the same with ``threads_here(len(items))`` threads;
- ``abandoned()``: whether such a call still runs (one that an interrupt left behind: the
  command line then ends the process at once, ``os._exit``, since a thread that leaves native
  code while the interpreter finalises is forced to exit, and Clarabel's Rust core aborts
  the process on that forced unwind, exit 134);
- ``threads_here(k)``: how many of k independent solves to run at once here: up to the cores,
  one on a Dask worker (the engine already runs one task per core).
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
from collections.abc import Callable, Iterable
from concurrent.futures import Future

__all__ = ["abandoned", "background", "call", "map_here", "map_threads", "on_dask_worker",
           "threads_here"]


def background(fn: Callable, *args, gate: threading.Semaphore | None = None, **kwargs
               ) -> Future:
    """``fn(*args, **kwargs)`` in a new daemon thread (after acquiring ``gate``, if given);
    its ``Future``. A future cancelled before the call starts never runs it."""
    fut: Future = Future()

    def run():
        try:
            with gate if gate is not None else contextlib.nullcontext():
                if not fut.set_running_or_notify_cancel():
                    return
                try:
                    fut.set_result(fn(*args, **kwargs))
                except BaseException as exc:   # delivered to the waiting thread
                    fut.set_exception(exc)
        finally:
            _RUNNING.discard(thread)

    thread = threading.Thread(target=run, name=f"homlimit-{getattr(fn, '__name__', 'call')}",
                              daemon=True)
    _RUNNING.add(thread)
    thread.start()
    return fut


#: the threads of ``background`` that have not ended
_RUNNING: set[threading.Thread] = set()


def abandoned() -> bool:
    """Whether a call started by ``background`` still runs: at the end of a command, one
    that an interrupt (or another call's failure) left behind."""
    return any(t.is_alive() for t in list(_RUNNING))


def call(fn: Callable, *args, **kwargs):
    """``fn(*args, **kwargs)``: in the main thread run in a daemon thread and waited for, so
    that a signal interrupts the wait; elsewhere (a worker's thread) called directly."""
    if threading.current_thread() is not threading.main_thread():
        return fn(*args, **kwargs)
    return background(fn, *args, **kwargs).result()


def map_threads(fn: Callable, items: Iterable, n: int) -> list:
    """``[fn(x) for x in items]``, at most ``n`` at a time, each in a daemon thread; results in
    order. Interrupted (or one call raising), the calls not yet started are cancelled and the
    exception propagates at once."""
    gate = threading.Semaphore(max(1, int(n)))
    futures = [background(fn, x, gate=gate) for x in items]
    try:
        return [f.result() for f in futures]
    except BaseException:
        for f in futures:
            f.cancel()
        raise


def map_here(fn: Callable, items: Iterable) -> list:
    """``[fn(x) for x in items]``, in order, ``threads_here(len(items))`` at a time: one after
    another in this thread on a Dask worker or on one core, else ``map_threads``."""
    items = list(items)
    n = threads_here(len(items))
    if n < 2:
        return [fn(x) for x in items]
    return map_threads(fn, items, n)


def threads_here(k: int) -> int:
    """How many of ``k`` independent solves to run at once in this process: as many as there
    are cores (at most k), or 1 on a Dask worker, where the engine runs one task per core."""
    return 1 if on_dask_worker() else max(1, min(int(k), os.cpu_count() or 1))


def on_dask_worker() -> bool:
    """Whether this thread runs a Dask worker's task."""
    dist = sys.modules.get("distributed")       # not imported: not a worker
    if dist is None:
        return False
    try:
        dist.get_worker()
    except ValueError:
        return False
    return True
