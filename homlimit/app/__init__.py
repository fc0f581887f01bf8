"""The application layer: case files, the pipeline, reports, pictures and the command line."""
