"""Generic leaves: do a thing once, or wait for a condition; the tree passes the callables in.

They keep the leaves that talk to subsystems free of bookkeeping, and they let ``mission/``
hand a leaf a callback (record a pot, heal the controllers) without ``behaviours/`` importing
upwards (DESIGN.md: arrows point down).
"""
from __future__ import annotations

from typing import Callable, Optional

import py_trees
from py_trees.common import Status


class Do(py_trees.behaviour.Behaviour):
    """Call ``fn()`` once per run: SUCCESS, or FAILURE when it returns False (None counts as
    done). A string return is a failure reason."""

    def __init__(self, name: str, fn: Callable[[], object]):
        super().__init__(name)
        self.fn = fn

    def update(self) -> Status:
        result = self.fn()
        if isinstance(result, str):
            self.feedback_message = result
            return Status.FAILURE
        return Status.FAILURE if result is False else Status.SUCCESS


class Check(Do):
    """A condition: SUCCESS when ``fn()`` is true, else FAILURE (a guard's first child)."""

    def __init__(self, name: str, fn: Callable[[], bool]):
        super().__init__(name, lambda: bool(fn()))


class WaitUntil(py_trees.behaviour.Behaviour):
    """RUNNING until ``done()``; FAILURE as soon as ``failed()`` returns a reason."""

    def __init__(self, name: str, done: Callable[[], bool],
                 failed: Callable[[], Optional[str]] = lambda: None):
        super().__init__(name)
        self.done, self.failed = done, failed

    def update(self) -> Status:
        if self.done():
            return Status.SUCCESS
        reason = self.failed()
        if reason:
            self.feedback_message = reason
            return Status.FAILURE
        return Status.RUNNING
