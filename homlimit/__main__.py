"""``python -m homlimit ...`` ≡ the ``homlimit`` console script."""

from .cli import main

main()
