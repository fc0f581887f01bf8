"""The model and mechanism registry: what a run computes, and what it does with each result.

A *model* turns a validated case into results (``Model``): the closed forms, the FE path, the
rigid blocks (``app.models`` registers them), and later the DEM. A *mechanism* is what a model
produces: a rigid body turning about a hinge (``Mechanism`` says what the app may ask of it).
The objects a model puts in ``pipeline.Result.mechanisms`` offer ``name``, ``label``, ``lam``,
``h``, ``vg``, ``vnorm`` and ``as_dict()`` (and ``hinge_ratio`` with a rocker: the hinge
check's |P_x/P_z| under the ideal impulse); where the package computes them,
also ``body`` (an ``impulse.RigidBody``: mass m, centre of gravity x_G, z_G and inertia I_O
about the hinge, i.e. ∫dm, ∫x dm = m x_G, ∫z dm = m z_G and ∫(x² + z²) dm = I_O), ``theta_m``
and ``W_m`` (the peak of W(θ), eqs 4–7), or ``impulse`` (the FE body's one-DOF impulse), and
``multiplier``/``lam_multiplier`` (the static check's smallest a/g), and ``static_mechanism``
(the code check's α₀ and body, ``check.StaticMechanism``).

The pipeline, the pulse spectra, the sweeps, the tables, the plots and the reports iterate
this registry; none of them compares mechanism names. A new model or mechanism is one new
module that calls ``register``. The built-in entries are registered when ``homlimit.app`` is
imported (``app/__init__.py`` imports ``app.models``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from ..errors import ParameterError

__all__ = ["Mechanism", "Model", "PULSE_CHOICES", "mechanism", "mechanisms", "model", "models",
           "needs_mesh", "register", "registered"]

CHECKED = ("lam", "h", "vg", "vnorm")


@dataclass(frozen=True)
class Mechanism:
    """What the app does with one registered mechanism.

    name: its key in ``Result.mechanisms``, summary.json and ``[pulse] mechanisms``;
    model: the name of the model that produces it;
    rocker(case, mechanism, gravity_I=, restitution=): its one-DOF rocker
    (``homlimit.dynamics``) for the hinge check and the pulse spectra; None: neither;
    alone(config): the mechanism for ``homlimit pulse`` without a whole run (None: its model
    is run on the case);
    checked, body_checked: the quantities of the mechanism and of its ``body`` that must be
    finite numbers in a result (``pipeline.check_results``);
    static: it reports a static check's smallest a/g (``multiplier`` at ``lam_multiplier``);
    colour, marker, size: its look in the pictures;
    needs_mesh: ``alone`` runs the FE path (the case's mesh is checked when it is chosen);
    static_of(result): the code check's ``check.StaticMechanism`` (α₀ and its body) when it
    is not the mechanism's own ``static_mechanism`` (None: that one; docs/code-check.md).
    """

    name: str
    model: str
    rocker: Callable[..., Any] | None = None
    alone: Callable[[Any], Any] | None = None
    checked: tuple[str, ...] = CHECKED
    body_checked: tuple[str, ...] = ()
    static: bool = False
    colour: str = "tab:purple"
    marker: str = "^"
    size: float = 10.0
    needs_mesh: bool = False
    static_of: Callable[[Any], Any] | None = None


@dataclass(frozen=True)
class Model:
    """A model: ``enabled(config)`` says whether the case asks for it; ``run(config, result)``
    fills the ``pipeline.Result`` (its ``mechanisms``, and what else the model owns: curves,
    the FE path, the blocks), logging and timing its stages itself; ``check(result)``: a
    ``ResultError`` for what it owns beyond its mechanisms that is not a finite number;
    ``batched``: a sweep evaluates its cases in vectorised batches (``sweep.batch_closed_form``,
    the closed forms) when it is the only kind of model a case asks for; ``files(result)``:
    key → (file name, data for ``report.write``) of the files it adds to a run's result set,
    as ``[output]`` asks (its pictures, tables, meshes; {} when it did not run); ``tasks``:
    ``run`` also takes ``map=``, a map hook (``engine.Engine.stored_map``), and then runs its
    work as that hook's tasks (the DEM: one trial per task)."""

    name: str
    enabled: Callable[[Any], bool]
    run: Callable[..., None]
    check: Callable[[Any], None] | None = None
    batched: bool = False
    files: Callable[[Any], dict] | None = None
    tasks: bool = False


_MODELS: dict[str, Model] = {}
_MECHANISMS: dict[str, Mechanism] = {}


def register(*entries: Model | Mechanism) -> None:
    """Add models and mechanisms (in this order: runs and tables follow it); a name already
    taken is refused."""
    for e in entries:
        table = _MODELS if isinstance(e, Model) else _MECHANISMS
        if e.name in table:
            raise ParameterError(f"name = {e.name!r} is already registered: allowed a new name")
        table[e.name] = e


def unregister(*names: str) -> None:
    """Remove the models and mechanisms of these names (those that are there)."""
    for n in names:
        _MODELS.pop(n, None)
        _MECHANISMS.pop(n, None)


@contextmanager
def registered(*entries: Model | Mechanism):
    """``register`` for the duration of a ``with`` block (tests, studies)."""
    register(*entries)
    try:
        yield
    finally:
        unregister(*(e.name for e in entries))


def models() -> list[Model]:
    return list(_MODELS.values())


def model(name: str) -> Model:
    return _lookup(_MODELS, "model", name)


def mechanisms() -> list[Mechanism]:
    return list(_MECHANISMS.values())


def mechanism(name: str) -> Mechanism:
    return _lookup(_MECHANISMS, "mechanism", name)


def _lookup(table: dict, what: str, name: str):
    try:
        return table[name]
    except (KeyError, TypeError):
        raise ParameterError(f"{what} = {name!r} is out of range: allowed one of "
                             + ", ".join(map(repr, table))) from None


def needs_mesh(names: Iterable) -> bool:
    """Whether any of these mechanism names (unknown ones ignored) runs the FE path alone."""
    if not isinstance(names, (list, tuple)):
        return False
    return any(_MECHANISMS[n].needs_mesh for n in names
               if isinstance(n, str) and n in _MECHANISMS)


class _Rockers:
    """The names of the registered mechanisms that have a rocker, read when asked (a live
    ``choices`` of ``[pulse] mechanisms``: a mechanism registered later is allowed too)."""

    def _names(self) -> tuple[str, ...]:
        return tuple(m.name for m in _MECHANISMS.values() if m.rocker is not None)

    def __iter__(self) -> Iterator[str]:
        return iter(self._names())

    def __contains__(self, name) -> bool:
        return name in self._names()

    def __len__(self) -> int:
        return len(self._names())

    def __repr__(self) -> str:
        return repr(self._names())


#: the mechanisms ``[pulse] mechanisms`` may name: those with a rocker
PULSE_CHOICES = _Rockers()
