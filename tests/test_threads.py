"""homlimit._threads: a native call in the main thread no longer holds a signal back (Ctrl-C,
SIGTERM), and the threaded map keeps its order and stops at the first failure."""

from __future__ import annotations

import os
import signal
import threading

import numpy as np
import pytest

from homlimit import _threads


def test_a_signal_interrupts_the_wait_for_a_native_call():
    # an eigenvalue solve of 1200 x 1200 stays in LAPACK (0.64 s on one core here) without
    # returning to Python, so the main thread would run the handler only after it; through
    # call() the handler runs at once (at 0.05 s) and the call is abandoned, unfinished
    done = threading.Event()
    a = np.random.default_rng(0).random((1200, 1200))

    def native():
        try:
            np.linalg.eigvals(a)
        finally:
            done.set()

    def handler(signum, frame):
        raise KeyboardInterrupt

    old = signal.signal(signal.SIGUSR1, handler)
    try:
        threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGUSR1)).start()
        with pytest.raises(KeyboardInterrupt):
            _threads.call(native)
        assert not done.is_set()
    finally:
        signal.signal(signal.SIGUSR1, old)
    assert done.wait(60)                    # the abandoned call ends on its own


def test_call_returns_the_result_and_raises_the_exception_of_the_call():
    assert _threads.call(divmod, 17, 5) == (3, 2)
    with pytest.raises(ZeroDivisionError):
        _threads.call(divmod, 1, 0)


def test_map_threads_keeps_the_order_and_starts_nothing_after_a_failure():
    assert _threads.map_threads(lambda x: x * x, range(7), 3) == [0, 1, 4, 9, 16, 25, 36]
    started = []
    gate = threading.Event()

    def fn(x):
        started.append(x)
        if x == 0:
            raise ValueError("first")
        gate.wait(5)
        return x

    with pytest.raises(ValueError, match="first"):
        _threads.map_threads(fn, range(6), 1)        # one at a time: 0 fails first
    gate.set()
    # cancelled: all but the one that may have taken the free slot before the cancel
    assert started[0] == 0 and len(started) <= 2


def test_threads_here_are_the_cores_and_one_on_a_dask_worker():
    from distributed import Client, LocalCluster

    assert _threads.threads_here(64) == os.cpu_count()
    assert _threads.threads_here(1) == 1 and not _threads.on_dask_worker()
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        assert client.submit(_threads.threads_here, 64, pure=False).result() == 1
