"""The runtime: config, clocks and scheduler, robot assembly, jobs (drive, bench) and the CLI.

Later issues add the py_trees patrol mission and its report here.
"""
