"""The work of the long commands, one module per group, each a plain function of the
command's options (``cli`` declares the options and calls them): ``case`` (run, demo, pulse,
mesh), ``table1``, ``studies`` (figure2, verify, crack-study), ``sweep`` (sweep run, sweep
report). The names tests replace (``pipeline.run``, ``pipeline.table1_records``, ...) are
called through ``pipeline``."""
