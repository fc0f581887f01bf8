"""``python -m homlimit ...`` ≡ the ``homlimit`` console script."""

import sys


def main():
    """The command line; Ctrl-C while its modules are still importing exits 130 with one
    line (``cli.interrupted``), never a KeyboardInterrupt traceback."""
    try:
        from .app.cli import main as cli_main
    except KeyboardInterrupt:
        print("homlimit: interrupted (SIGINT): nothing was written", file=sys.stderr)
        raise SystemExit(130) from None
    cli_main()


if __name__ == "__main__":
    main()
