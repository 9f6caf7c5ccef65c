"""The composition root: the ``lupin`` command (:mod:`lupin.cli`) and its benchmarks
(:mod:`lupin.bench`).

It sits above every other package: it is the one place that wires the application layer
(``mission/``), the console (``tui/``) and the simulator (``sim/``) together, so that nothing
below imports upwards (DESIGN.md: the arrows point down). The robot's own runtime
(``lupin serve --backend hw``) reaches the simulator only on the sim path.
"""
