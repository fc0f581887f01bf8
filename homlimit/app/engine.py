"""The sweep engine: Dask as the executor, one record per finished task, nothing lost on a stop.

``Engine`` owns a ``dask.distributed.Client``: by default on an embedded ``LocalCluster`` (one
single-threaded worker process per core, BLAS threads pinned to one per worker), or on an
existing scheduler (``scheduler="tcp://host:8786"``: ``dask scheduler`` + ``dask worker``, or
dask-jobqueue on a batch cluster) with no other change. It offers

- ``map(fn, items)``: an ordered, blocking map (``mechanism.analysis.h_scan``'s ``map`` hook:
  each height of a scan becomes a task);
- ``run(fn, items, keys, store)``: every item a task; each result is written to the
  ``RecordStore`` as soon as it arrives (atomically, keyed by a hash of its resolved inputs and
  the package version), items already in the store are not run again, and a live progress bar
  shows done / failed / remaining and the ETA.

SIGTERM is turned into the same ``Interrupted`` as Ctrl-C: the client and the cluster are shut
down, and the records written so far stay complete (``_io.atomic_path``); a rerun resumes.
The embedded workers never see SIGINT (Ctrl-C at a terminal signals the whole process group:
the workers start with it blocked, and this process shuts them down), so an interrupt prints
no worker's traceback; Dask's own logs are silenced while the cluster shuts down after one.
The embedded cluster serves no dashboard (its scheduler's HTTP endpoint takes a free port on
127.0.0.1, never 8787). A scheduler address is checked before any connection, and a scheduler
that does not answer within ``SCHEDULER_TIMEOUT`` is a ParameterError (exit 2), not a wait.
"""

from __future__ import annotations

import logging
import os
import signal
import socket
import threading
import time
from collections.abc import Callable, Iterable, Sequence
from contextlib import contextmanager

from .. import _threads
from .._io import to_jsonable
from ..errors import ParameterError, check_range
from ..params import MESHER_DEFAULT, PART_DIVISIONS
from .records import RecordStore, batch_json, json_text, read_json, record_key
from .scheduler import ADDRESS_HINT, SCHEDULER_TIMEOUT, check_scheduler, handshake

__all__ = ["BLAS_ENV", "Engine", "Interrupted", "RecordStore", "SCHEDULER_TIMEOUT", "batch_json",
           "check_scheduler", "cpu_count", "json_text", "read_json", "record_key"]

log = logging.getLogger(__name__)

#: environment of every embedded worker process: one BLAS/OpenMP thread (one task per core)
BLAS_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
#: seconds an embedded worker has to stop after an interrupt before it is killed
STOP_TIMEOUT = 0.5


@contextmanager
def _sigint_blocked():
    """SIGINT blocked in this thread: the threads started meanwhile (the cluster's event loop)
    inherit the mask, and so do the worker processes they start (the mask survives fork and
    exec, and Python leaves it as it is): Ctrl-C at a terminal, sent to the whole process
    group, reaches this process only, which shuts the workers down. A Ctrl-C meanwhile is
    delivered when the block ends."""
    if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - not POSIX
        yield
        return
    from multiprocessing import resource_tracker

    # started now: when it starts, it unblocks SIGINT in the thread that starts it (CPython's
    # ensure_running ends with SIG_UNBLOCK, not the mask it found), the cluster's loop here
    resource_tracker.ensure_running()
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


@contextmanager
def _logs_silenced(enabled: bool):
    """Every log record up to ERROR dropped (``logging.disable``) while the cluster shuts
    down after an interrupt: Dask's reports of the tasks it cancels are no news then."""
    if not enabled:
        yield
        return
    before = logging.root.manager.disable
    logging.disable(logging.ERROR)
    try:
        yield
    finally:
        logging.disable(before)


class Interrupted(KeyboardInterrupt):
    """A sweep stopped by SIGINT (Ctrl-C) or SIGTERM; ``signum`` names the signal."""

    def __init__(self, signum: int = signal.SIGINT):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def cpu_count() -> int:
    """Cores this process may run on (the default number of embedded workers)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1



def _progress(total: int, description: str, enabled: bool):
    """A rich progress bar on stderr: done, failed, remaining, elapsed time and ETA."""
    from rich import progress as rp
    from rich.console import Console

    prog = rp.Progress(rp.TextColumn("[bold]{task.description}"), rp.BarColumn(),
                       rp.MofNCompleteColumn(),
                       rp.TextColumn("done, {task.fields[failed]} failed, "
                                     "{task.fields[remaining]} remaining"),
                       rp.TimeElapsedColumn(), rp.TextColumn("ETA"), rp.TimeRemainingColumn(),
                       console=Console(stderr=True), disable=not enabled, transient=False)
    task = prog.add_task(description, total=total, failed=0, remaining=total)
    return prog, task


class Engine:
    """A Dask client for the duration of a ``with`` block (see the module docstring).

    workers: embedded worker processes (default: one per core; ignored with ``scheduler``);
    scheduler: address of an existing Dask scheduler; progress: show the progress bar.
    """

    def __init__(self, workers: int | None = None, scheduler: str | None = None,
                 progress: bool = True):
        if workers is not None:
            workers = int(check_range("workers", workers, 1, 1024))
        self._where = check_scheduler(scheduler) if scheduler is not None else None
        self.workers = workers or cpu_count()
        self.scheduler = None if scheduler is None else self._where[0]
        self.progress = progress
        self.client = None
        self._cluster = None
        self._old_term = None

    # ------------------------------------------------------------------ lifetime
    def __enter__(self) -> Engine:
        from distributed import Client, LocalCluster

        if threading.current_thread() is threading.main_thread():
            self._old_term = signal.signal(signal.SIGTERM, _sigterm)
        try:
            if self.scheduler:
                self.client = self._connect(Client)
            else:
                log.info("starting %d local Dask workers (one thread each)", self.workers)
                with _sigint_blocked():
                    self._cluster = LocalCluster(
                        n_workers=self.workers, threads_per_worker=1, processes=True,
                        host="127.0.0.1", dashboard_address=None, env=dict(BLAS_ENV),
                        silence_logs=logging.ERROR,
                        # no dashboard; the scheduler's HTTP endpoint on a free local port
                        scheduler_kwargs={"dashboard": False,
                                          "dashboard_address": "127.0.0.1:0"})
                self.client = Client(self._cluster)
        except BaseException as e:
            self.__exit__(type(e), e, None)
            raise
        return self

    def _connect(self, client_cls):
        """A client of the scheduler at ``self.scheduler``, or ParameterError within
        SCHEDULER_TIMEOUT: a refused or unreachable address is found by a plain TCP connection
        at once (a Dask client would retry it until its timeout), then the client must
        complete its handshake in the time left."""
        address, host, port = self._where
        log.info("connecting to the Dask scheduler at %s", address)
        t0 = time.monotonic()

        def fail(reason: str):
            raise ParameterError(f"scheduler (--scheduler) = {address!r}: no Dask scheduler "
                                 f"answers there ({reason}; waited at most "
                                 f"{SCHEDULER_TIMEOUT:g} s); {ADDRESS_HINT}") from None

        if host is not None:
            try:
                socket.create_connection((host, port), timeout=SCHEDULER_TIMEOUT).close()
            except OSError as e:
                fail(str(e.strerror or e or type(e).__name__))
        error = handshake(address, max(0.5, SCHEDULER_TIMEOUT - (time.monotonic() - t0)))
        if isinstance(error, MemoryError):  # a length prefix read from another server
            fail("the reply is not a Dask scheduler's")
        if error is not None:
            fail((str(error).splitlines() or [type(error).__name__])[0][:200]
                 or type(error).__name__)
        left = max(1.0, SCHEDULER_TIMEOUT - (time.monotonic() - t0))
        try:
            return client_cls(address, timeout=f"{left:.1f}s")
        except MemoryError:          # a length prefix read from a server that is not Dask's
            fail("the reply is not a Dask scheduler's")
        except Exception as e:  # a timeout, a closed comm, a server that is not Dask's
            fail((str(e).splitlines() or [type(e).__name__])[0][:200])

    def __exit__(self, *exc):
        interrupted = isinstance(exc[1] if len(exc) > 1 else None, KeyboardInterrupt)
        try:
            with _logs_silenced(interrupted):
                if self.client is not None:
                    self.client.close()
                if self._cluster is not None:
                    if interrupted:
                        self._stop_workers()
                    self._cluster.close()
        finally:
            self.client = self._cluster = None
            if self._old_term is not None:
                signal.signal(signal.SIGTERM, self._old_term)
                self._old_term = None
        return False

    def _stop_workers(self):
        """The embedded workers stopped within ``STOP_TIMEOUT`` (then killed): a worker busy
        in a task would otherwise hold the cluster's close for its nanny's 4 s of grace."""
        import asyncio

        nannies = list(self._cluster.workers.values())

        async def stop():
            await asyncio.gather(*(w.close(timeout=STOP_TIMEOUT) for w in nannies),
                                 return_exceptions=True)

        try:
            self._cluster.sync(stop)
        except Exception as e:  # the ordinary close follows
            log.debug("stopping the workers at once failed: %s", e)

    @property
    def n_workers(self) -> int:
        """Workers connected now."""
        return len(self.client.scheduler_info()["workers"])

    # ------------------------------------------------------------------ work
    def submit(self, fn: Callable, *args, **kwargs):
        """One task (a ``distributed.Future``); never cached (``pure=False``)."""
        return self.client.submit(fn, *args, pure=False, **kwargs)

    def map(self, fn: Callable, items: Iterable) -> list:
        """``[fn(x) for x in items]``, each call a task; blocks; the first error is raised."""
        futures = [self.submit(fn, x) for x in items]
        return self.client.gather(futures)

    def run(self, fn: Callable, items: Sequence, *, on_result: Callable | None = None,
            failed: Callable | None = None, weight: Callable | None = None,
            total: int | None = None, already: tuple[int, int] = (0, 0),
            description: str = "tasks", show: bool = True) -> list:
        """``[fn(x) for x in items]``, every call a task, results in item order; ``items`` may
        be an iterator (each item is submitted as it comes, e.g. as a sweep plans its cases).

        on_result(k, result): called in this process as soon as task k finishes (to store its
        record); failed(item, exc): the result of a task that raised (a lost worker, say;
        None: the error is raised). Progress counts ``weight(result)`` = (cases, failed
        cases) per result (default: 1 case, failed if the result is a dict with status
        "failed") out of ``total``, ``already`` = (done, failed) counted before. show: False
        hides the progress bar (a caller that runs many small maps at once and logs its own).
        """
        from distributed import as_completed

        weight = weight or _weight
        if total is None:
            items = list(items)
            total = len(items)
        done, n_failed = already
        prog, bar = _progress(total, description, self.progress and show)
        with prog:
            prog.update(bar, completed=done, failed=n_failed, remaining=total - done)
            submitted, futures = [], {}
            for k, x in enumerate(items):   # an iterator's items are submitted as they come
                submitted.append(x)
                futures[self.submit(fn, x)] = k
            results: list = [None] * len(submitted)
            for fut in as_completed(futures):
                k = futures[fut]
                if fut.status == "finished":
                    res = fut.result()
                    if on_result is not None:
                        on_result(k, res)
                elif failed is None:
                    raise fut.exception()
                else:
                    res = failed(submitted[k], fut.exception())
                results[k] = res
                m, f = weight(res)
                done, n_failed = done + m, n_failed + f
                prog.update(bar, completed=done, failed=n_failed, remaining=total - done)
        return results

    def stored_map(self, store: RecordStore, kind: str, description: str = "tasks",
                   show: bool = True):
        """A map hook ``map(fn, items)`` whose results (JSON-able records) are stored as they
        arrive and read back instead of rerun: the key of a call is ``record_key(kind, ...)``
        of ``fn``'s name and bound arguments and the item. show: ``run``'s progress bar."""

        def map_(fn: Callable, items: Iterable) -> list:
            items = list(items)
            keys = [record_key(kind, {"fn": _name(fn), "args": _plain(getattr(fn, "args", ())),
                                      "kwargs": _plain(getattr(fn, "keywords", {})),
                                      "item": _plain(x)}) for x in items]
            stored = store.load()
            todo = [k for k, key in enumerate(keys) if key not in stored]
            if len(todo) < len(items):
                log.info("%s: %d of %d already done (records in %s)", description,
                         len(items) - len(todo), len(items), store.folder)
            new = self.run(fn, [items[k] for k in todo], total=len(items),
                           already=(len(items) - len(todo), 0), description=description,
                           show=show,
                           on_result=lambda j, rec: store.put(keys[todo[j]], rec, exact=True))
            out = [stored.get(key) for key in keys]
            for j, k in enumerate(todo):
                out[k] = new[j]
            return out

        return map_

    def fe_results(self, cases: Sequence, mesh_size: float, facade: str, heights: int,
                   options=None, mesher: str = MESHER_DEFAULT,
                   divisions: int = PART_DIVISIONS) -> list:
        """The FE path of several walls with every collapse height a task: each wall's scan
        (``analysis.fe_result``: its starting heights, whole wall included, then each round
        of the refinement around the minimum) through its ``map`` hook, all walls at once (a
        client thread per wall only waits). Returns one ``mechanism.analysis.FEResult`` per
        wall, as ``fe_result(case, mesh_size, facade, options, heights=heights,
        mesher=mesher, divisions=divisions)`` would. The walls' threads are daemon threads
        (``_threads.map_threads``): an interrupt leaves at once, abandoning the scans, whose
        waits end when the engine's client closes (an executor would join them first)."""
        from ..mechanism.analysis import fe_result

        def one(case):
            return fe_result(case, mesh_size, facade, options, heights=heights, map=self.map,
                             mesher=mesher, divisions=divisions)

        if not cases:
            return []
        return _threads.map_threads(one, cases, len(cases))


def _weight(result) -> tuple[int, int]:
    return 1, int(isinstance(result, dict) and result.get("status") == "failed")


def _name(fn) -> str:
    fn = getattr(fn, "func", fn)
    return f"{getattr(fn, '__module__', '')}.{getattr(fn, '__qualname__', repr(fn))}"


def _plain(obj):
    """JSON-able data from containers of numbers, strings and dataclasses."""
    import dataclasses

    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    return to_jsonable(obj)


def _sigterm(signum, frame):
    raise Interrupted(signum)

