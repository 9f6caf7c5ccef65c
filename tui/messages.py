"""What the console's background work tells the app (typed messages, posted from the worker
threads that talk to the robot; handled on the UI's thread)."""
from __future__ import annotations

from textual.message import Message


class CommandRefused(Message):
    """The robot (or the link) refused a command: show the reason."""

    def __init__(self, command: str, reason: str):
        super().__init__()
        self.command, self.reason = command, reason


class SnapshotTaken(Message):
    """A camera snapshot arrived (``jpeg`` None: the robot had no frame)."""

    def __init__(self, camera: str, jpeg: bytes | None):
        super().__init__()
        self.camera, self.jpeg = camera, jpeg


class HistoryRead(Message):
    """The robot's history answered for the pot table: its ``changes`` and ``pests`` answers
    (None each: no answer), for the patrol view it was asked about."""

    def __init__(self, changes: dict | None, pests: dict | None):
        super().__init__()
        self.changes, self.pests = changes, pests


class TimelineRead(Message):
    """One pot's timeline came (``answer`` None: ``error`` says why not)."""

    def __init__(self, pot: str, answer: dict | None, error: str | None):
        super().__init__()
        self.pot, self.answer, self.error = pot, answer, error
