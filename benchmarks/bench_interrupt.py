"""How fast `homlimit demo` stops on a signal sent in the middle of a conic solve.

Starts the demo in a subprocess (SIGINT at its default, as at a terminal), waits for the stage
named on the command line to begin, waits ``delay`` seconds more (inside that stage's first
solve), sends the signal and prints the seconds from the signal to the exit, the exit code and
the last line of stderr. Before ``homlimit._threads`` the wait lasted until the running solve
ended (12.5 s in the bracket's static bound); the README quotes the figure this prints.

    python benchmarks/bench_interrupt.py [TERM|INT] [stage text] [delay]
           (default: TERM "adaptive bracket (target" 3)
"""

from __future__ import annotations

import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def main(sig: str = "TERM", stage: str = "adaptive bracket (target", delay: float = 3.0):
    out = Path(tempfile.mkdtemp()) / "demo"
    proc = subprocess.Popen([sys.executable, "-m", "homlimit", "demo", "-o", str(out)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    for line in proc.stderr:
        if stage in line:
            break
    time.sleep(delay)
    t0 = time.perf_counter()
    proc.send_signal(getattr(signal, f"SIG{sig}"))
    rest = proc.stderr.read().strip().splitlines()
    code = proc.wait()
    print(f"SIG{sig} {delay:g} s into '{stage}': exit {code} after "
          f"{time.perf_counter() - t0:.2f} s; output folder left: {out.exists()}")
    print(f"  {rest[-1] if rest else ''}")


if __name__ == "__main__":
    a = sys.argv[1:]
    main(*(a[:2] + [float(x) for x in a[2:3]]))
