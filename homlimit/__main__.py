"""``python -m homlimit ...`` ≡ the ``homlimit`` console script."""

from .app.cli import main

main()
