"""``python -m analytic``: print every identity of the derivations and whether it holds."""

from . import mechanism_I, mechanism_II

for mod in (mechanism_I, mechanism_II):
    print(f"--- {mod.__name__}")
    for name, ok in mod.checks().items():
        print(f"{'holds ' if ok else 'FAILS '} {name}")
