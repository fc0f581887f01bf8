"""A Dask scheduler's address, checked before any connection (``check_scheduler``), and
Dask's own handshake with it within a time limit (``handshake``): a scheduler that does not
answer within ``SCHEDULER_TIMEOUT`` is a ParameterError (exit 2), not a wait."""

from __future__ import annotations

import threading

from ..errors import ParameterError

__all__ = ["ADDRESS_HINT", "SCHEDULER_TIMEOUT", "check_scheduler", "handshake"]

#: seconds to wait for a scheduler (``--scheduler``) to answer before giving up
SCHEDULER_TIMEOUT = 5.0
#: schemes of a scheduler address whose location is host:port
_HOST_PORT = ("tcp", "tls", "ws", "wss")
_SCHEMES = (*_HOST_PORT, "inproc", "ucx")
ADDRESS_HINT = ("allowed the address of a running Dask scheduler, tcp://HOST:PORT (e.g. "
                 "tcp://127.0.0.1:8786, as `dask scheduler` prints it)")


def check_scheduler(address: str) -> tuple[str, str | None, int | None]:
    """(address, host, port) of a scheduler address ``[scheme://]host:port`` (scheme tcp by
    default; host and port None for the schemes without them), checked before any
    connection: ParameterError naming the option otherwise."""
    text = str(address).strip()
    scheme, sep, loc = text.rpartition("://")
    scheme = scheme if sep else "tcp"

    def bad(why: str):
        raise ParameterError(f"scheduler (--scheduler) = {text[:80]!r} is not a scheduler "
                             f"address: {why}; {ADDRESS_HINT}")

    if not text:
        bad("it is empty")
    if scheme not in _SCHEMES:
        bad(f"unknown scheme {scheme!r} (allowed {', '.join(_SCHEMES)})")
    if scheme not in _HOST_PORT:
        return text, None, None
    if loc.startswith("["):                       # IPv6: [addr]:port
        host, _, tail = loc[1:].partition("]")
        port = tail[1:] if tail.startswith(":") else ""
    else:
        host, colon, port = loc.rpartition(":")
        host, port = (host, port) if colon else (loc, "")
    if not port.isdigit() or not 1 <= int(port) <= 65535:
        bad("no port number 1 .. 65535")
    if not host or any(ch.isspace() or ch in "/?#@" for ch in host):
        bad("no host name")
    return f"{scheme}://{loc}", host, int(port)


def handshake(address: str, timeout: float) -> BaseException | None:
    """Dask's own connection to ``address``, handshake included, within ``timeout`` s: None,
    or the error. A Client alone waits forever for a server that accepts the connection and
    never answers; this runs in a thread of its own (an event loop may run in this one), left
    behind if it hangs."""
    import asyncio  # here, not at start-up: only a --scheduler run needs it

    from distributed.comm import connect

    errors: list[BaseException] = []

    async def probe():
        comm = await asyncio.wait_for(connect(address, timeout=timeout), timeout)
        await comm.close()

    def run():
        try:
            asyncio.run(probe())
        except BaseException as e:  # reported to the caller, whatever it is
            errors.append(e)

    thread = threading.Thread(target=run, name="homlimit scheduler probe", daemon=True)
    thread.start()
    thread.join(timeout + 1.0)
    if thread.is_alive():
        return TimeoutError(f"no handshake within {timeout:.1f} s")
    return errors[0] if errors else None
