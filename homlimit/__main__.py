"""The ``homlimit`` console script and ``python -m homlimit ...``.

``homlimit --version`` is answered here, before typer, rich and the computing packages are
imported (``import homlimit`` is light, see its docstring); everything else goes to the typer
application in ``app.cli``.
"""

import sys


def main():
    """Console-script entry point (``homlimit``, ``python -m homlimit``)."""
    if sys.argv[1:] == ["--version"]:
        from ._version import package_version

        print(f"homlimit {package_version()}")
        return
    try:
        from .app.cli import main as cli_main
    except KeyboardInterrupt:   # Ctrl-C while the modules import: one line, no traceback
        print("homlimit: interrupted (SIGINT): nothing was written", file=sys.stderr)
        raise SystemExit(130) from None

    cli_main()


if __name__ == "__main__":
    main()
