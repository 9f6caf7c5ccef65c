"""The log: the runtime's log lines from the link, and what the console itself has to say
(a refused command and its reason)."""
from __future__ import annotations

from textual.widgets import RichLog

from mission.link.view import RobotView


def new_lines(before: list[str], now: list[str]) -> list[str]:
    """The lines of ``now`` not yet shown, when ``before`` was shown last. The view's log is a
    rolling window (the link client keeps the last 200 lines), so once it is full its length no
    longer grows: find where the window moved to by the longest overlap (end of ``before`` =
    start of ``now``), trying a pure append first. No overlap at all: everything is new."""
    for dropped in range(len(before) + 1):
        kept = len(before) - dropped
        if kept <= len(now) and now[:kept] == before[dropped:]:
            return now[kept:] if kept else now
    return now


class LogPanel(RichLog):
    can_focus = False  # the arrows drive the robot

    def __init__(self, **kw):
        super().__init__(**kw)
        self._shown: list[str] = []

    def show(self, view: RobotView) -> None:
        lines = view.log
        if lines == self._shown:
            return
        for line in new_lines(self._shown, lines):
            self.write(line)
        self._shown = list(lines)

    def say(self, line: str) -> None:
        self.write(f"[console] {line}")
