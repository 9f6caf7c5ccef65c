"""``Hold``: a guard decorator that freezes its subtree while a condition gives a reason.

While ``holding()`` returns a reason, the child is stopped (INVALID: its running leaves cancel
what they started, the navigation goal; the arm holds) and the guard reports RUNNING with that
reason as its feedback. When the reason clears, the child is ticked again and starts over; the
tree decides what "over" means (``py_trees.decorators.OneShot`` keeps work already finished).

A decorator, not a flag inside leaves (DESIGN.md): the e-stop and the operator's pause wrap the
whole mission, so no leaf needs to know about either.
"""
from __future__ import annotations

from typing import Callable, Iterator

from py_trees.behaviour import Behaviour
from py_trees.common import Status
from py_trees.decorators import Decorator


class Hold(Decorator):
    def __init__(self, name: str, child: Behaviour, holding: Callable[[], str | None]):
        super().__init__(name=name, child=child)
        self.holding = holding
        self.reason: str | None = None

    def tick(self) -> Iterator[Behaviour]:
        self.reason = self.holding()
        if self.reason is None:
            yield from Decorator.tick(self)
            return
        if self.decorated.status is Status.RUNNING:
            self.decorated.stop(Status.INVALID)
        yield from Behaviour.tick(self)

    def update(self) -> Status:
        self.feedback_message = self.reason or ""
        return Status.RUNNING if self.reason is not None else self.decorated.status
