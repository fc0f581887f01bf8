"""The command line's door: what every command shares (exit codes, logging on stderr, the
mapping of failures to exit codes and one line, signals, a quiet stdout under --json, JSON and
table output, Dask's engine and its interrupt). Light: imported when the CLI starts."""

from __future__ import annotations

import functools
import json
import logging
import os
import signal
import sys
from contextlib import contextmanager

import typer

from .. import _threads
from .._io import rounded  # floats to 15 digits, as in the files (_io.write_output)
from .._version import package_version
from ..errors import (
    HomlimitError,
    MeshError,
    OutputError,
    ParameterError,
    ResultError,
    SolverError,
)
from .config import ConfigError
from .engine import Engine
from .engine import Interrupted as EngineInterrupted
from .report import format_table

__all__ = ["EXIT_BAD_INPUT", "EXIT_BROKEN_PIPE", "EXIT_SOLVER", "LOG", "Interrupted",
           "check_verbosity", "emit_json", "fail", "guarded", "interruptible", "leave",
           "open_engine", "setup_logging", "show", "signals", "stored_tasks", "stdout_quiet"]

EXIT_BAD_INPUT = 2
EXIT_SOLVER = 3
EXIT_BROKEN_PIPE = 128 + 13     # SIGPIPE: stdout's reader has gone

HANDLER: logging.Handler | None = None
LOG = logging.getLogger("homlimit")


def check_verbosity(verbose: bool, quiet: bool):
    """ParameterError for -q and -v together: they contradict each other."""
    if verbose and quiet:
        raise ParameterError("-q/--quiet and -v/--verbose contradict each other: allowed one "
                             "of them, or neither")


def setup_logging(verbose: bool = False, quiet: bool = False, as_json: bool = False):
    """Progress and logs of the library on stderr: stages at INFO (the default), solver logs
    at DEBUG (-v); only warnings with -q or --json (stdout carries the JSON document). -q
    with -v is refused (``check_verbosity``)."""
    global HANDLER
    check_verbosity(verbose, quiet)
    logger = logging.getLogger("homlimit")
    if HANDLER is not None:
        logger.removeHandler(HANDLER)
    HANDLER = logging.StreamHandler(sys.stderr)
    HANDLER.setFormatter(logging.Formatter("[homlimit] %(message)s"))
    logger.addHandler(HANDLER)
    logger.propagate = False
    logger.setLevel(logging.DEBUG if verbose else
                    logging.WARNING if (quiet or as_json) else logging.INFO)


def print_version(value: bool):
    if value:
        print(f"homlimit {package_version()}")
        raise typer.Exit()


def fail(code: int, message: str):
    print(f"homlimit: error: {message}", file=sys.stderr)
    raise typer.Exit(code)


class Interrupted(KeyboardInterrupt):
    """SIGTERM or SIGHUP, raised like Ctrl-C so that every clean-up on the way runs."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def raise_interrupt(signum, frame):
    raise Interrupted(signum)


@contextmanager
def signals():
    """SIGTERM and SIGHUP raise like SIGINT (the result set's clean-up runs); SIGXFSZ is
    ignored, so that a write over ``ulimit -f`` fails with EFBIG (an OutputError) instead of
    killing the process. The previous handlers are put back on exit."""
    wanted = {"SIGTERM": raise_interrupt, "SIGHUP": raise_interrupt, "SIGXFSZ": signal.SIG_IGN}
    saved = {}
    try:
        for name, handler in wanted.items():
            if hasattr(signal, name):
                saved[name] = signal.signal(getattr(signal, name), handler)
    except ValueError:  # not the main thread: leave the signals alone
        pass
    try:
        yield
    finally:
        for name, handler in saved.items():
            signal.signal(getattr(signal, name), handler)


def leave(code):
    """At the command line's exit with ``code``: when a solve that an interrupt (or another
    solve's failure) abandoned still runs in a daemon thread (``_threads.abandoned``), end the
    process now (``os._exit``), after flushing stdout, stderr and the logs: the result set's
    clean-up and the Dask engine's shutdown have run in their ``with`` blocks before, and the
    interpreter's finalisation would force that thread to exit when it leaves native code,
    which Clarabel's Rust core turns into an abort (SIGABRT, exit 134: "FATAL: exception not
    rethrown"). Otherwise nothing: the ordinary exit follows."""
    if not isinstance(code, int) or not _threads.abandoned():
        return
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # closed, or a broken pipe: nothing more to say
            pass
    logging.shutdown()
    os._exit(code)


def _stdout_closed():
    """Exit 141 (128 + SIGPIPE, as other Unix tools) when stdout's reader has gone (``|
    head``): no message; what remains buffered for stdout goes to /dev/null, so that the
    exit's flush fails no more."""
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)
    except (AttributeError, OSError, ValueError):  # no file descriptor (typer's CliRunner)
        pass
    raise typer.Exit(EXIT_BROKEN_PIPE)


def guarded(fn):
    """Map expected failures to exit codes 2 (bad input) and 3 (computation or disk), and
    interrupts to 128 + the signal number; one line on stderr, no traceback. A closed stdout
    (a broken pipe) exits 141, quietly."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        try:
            with signals():
                return fn(*args, **kwargs)
        except ConfigError as e:
            print(f"homlimit: error: {e.problems[0] if len(e.problems) == 1 else e}",
                  file=sys.stderr)
            raise typer.Exit(EXIT_BAD_INPUT) from None
        except ParameterError as e:
            fail(EXIT_BAD_INPUT, str(e))
        except SolverError as e:
            hint = " [a looser tolerance: --set analysis.tol=1e-7]" if \
                e.status == "optimal_inaccurate" else ""
            fail(EXIT_SOLVER, f"solver failed ({e.status or 'no status'}): {e}{hint}")
        except MeshError as e:
            fail(EXIT_SOLVER, f"meshing failed: {e}")
        except OutputError as e:
            fail(EXIT_SOLVER, f"{e}; the previous result set, if any, is kept")
        except ResultError as e:
            fail(EXIT_SOLVER, f"no result: {e}")
        except HomlimitError as e:  # any other expected failure
            fail(EXIT_SOLVER, str(e))
        except MemoryError:
            fail(EXIT_SOLVER, "out of memory: a coarser [mesh] size, or a lower [mesh] "
                              "max_triangles so that such cases stop before they start")
        except BrokenPipeError:
            _stdout_closed()
        except KeyboardInterrupt as e:
            signum = getattr(e, "signum", signal.SIGINT)
            print(f"homlimit: interrupted ({signal.Signals(signum).name}): the result set "
                  "being written was removed, the previous one is kept", file=sys.stderr)
            raise typer.Exit(128 + signum) from None

    return wrapper


@contextmanager
def stdout_quiet(enabled: bool):
    """Under --json or -v, send everything written to stdout during the computation to stderr
    (Python or native libraries: gmsh, and Clarabel's log, which its Rust core prints to file
    descriptor 1), so that stdout carries the JSON document or the result table only. Yields
    the real stdout."""
    real = sys.stdout
    if not enabled:
        yield real
        return
    saved_fd = None
    try:
        fd = real.fileno()
    except (AttributeError, OSError, ValueError):  # e.g. typer's CliRunner
        fd = None
    real.flush()
    if fd is not None:
        saved_fd = os.dup(fd)
        os.dup2(sys.stderr.fileno(), fd)
    sys.stdout = sys.stderr
    try:
        yield real
    finally:
        sys.stdout.flush()
        real.flush()  # what a library wrote to the real stream meanwhile goes to stderr too
        sys.stdout = real
        if saved_fd is not None:
            os.dup2(saved_fd, fd)
            os.close(saved_fd)


def emit_json(stream, data):
    stream.write(json.dumps(rounded(data), indent=2, ensure_ascii=False) + "\n")
    stream.flush()


def show(stdout, as_json: bool, data, records: list[dict], cols: list[str], title: str,
         files):
    """--json: ``data`` on stdout; otherwise the ``cols`` of ``records`` as a table, then the
    files written."""
    if as_json:
        emit_json(stdout, data)
        return
    print(format_table(cols, [[r.get(k) for k in cols] for r in records], title=title))
    print("\nfiles: " + ", ".join(map(str, files)))


@contextmanager
def interruptible(where):
    """Ctrl-C / SIGTERM: what is recorded stays; exit 130 / 143 with a one-line note."""
    try:
        yield
    except KeyboardInterrupt as e:
        signum = e.signum if isinstance(e, EngineInterrupted) else 2
        print(f"homlimit: interrupted; the finished records are kept in {where}: run the same "
              "command again to resume", file=sys.stderr)
        raise typer.Exit(128 + signum) from None


def open_engine(workers: int | None, scheduler: str | None, quiet: bool):
    return Engine(workers=workers, scheduler=scheduler, progress=not quiet)


@contextmanager
def stored_tasks(store, kind: str, description: str, *, resume: bool, workers: int | None,
                 scheduler: str | None, quiet: bool, show: bool = True):
    """The map hook of a command whose tasks' records live in ``store`` (a ``RecordStore``):
    its records cleared first unless ``resume``, an engine open for the block (``open_engine``),
    ``engine.stored_map(store, kind, description, show=show)``."""
    if not resume:
        store.clear()
    with open_engine(workers, scheduler, quiet) as engine:
        yield engine.stored_map(store, kind, description, show=show)
