"""The application layer: case files, the pipeline, reports, pictures and the command line."""

from . import (
    models,  # noqa: F401  (registers the built-in models and mechanisms)
    overturning,  # noqa: F401  (registers the simple overturning)
)
