"""py_trees leaves of the patrol: thin and non-blocking.

Each leaf's ``update()`` polls a subsystem (nav/, arm/, perception/, hw/ services) and returns
a status; ``terminate(INVALID)`` cancels what its ``initialise()`` started. Timeouts and retries
are decorators (``behaviours.timeout``, py_trees' ``Retry``), never flags inside a leaf. The
tree that joins them is ``mission.patrol.tree``.
"""
