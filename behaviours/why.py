"""Why a subtree failed, in its leaves' own words: what a patrol records for a pot or a step."""
from __future__ import annotations

from py_trees.behaviour import Behaviour
from py_trees.common import Status


def why(node: Behaviour) -> str:
    """The reason a failed subtree gives: the deepest failed behaviour that says why, named
    (py_trees iterates children first). A ``Retry`` only says how many times it failed."""
    for n in node.iterate():
        if n.status is Status.FAILURE and n.feedback_message:
            return f"{n.name}: {n.feedback_message}"
    return f"{node.name}: failed"
