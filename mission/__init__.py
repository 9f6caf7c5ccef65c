"""The top layer: ``runtime`` (config, scheduler, robot assembly, heal), ``jobs`` (drive,
navigate, approach trials), ``cli`` (the ``lupin`` command, one module per command group) and
``bench`` (the benchmark harness, one module per group). The patrol mission arrives beside them.
"""
