"""The application layer: ``runtime`` (config, scheduler, robot assembly, navigation wiring,
heal), ``patrol`` (mission and events files, the tree, the report and its picture), ``jobs``
(what a command runs: drive, navigate, the patrol, the service; their sim halves apart, so the
robot never loads the simulator), ``scenario`` (scenario files, runner, judge), ``link`` (the
Zenoh link) and ``record`` (Foxglove). The ``lupin`` command and its benchmarks sit above, in
``lupin/``.
"""
