"""The log: the runtime's log lines from the link, and what the console itself has to say
(a refused command, its reason)."""
from __future__ import annotations

from textual.widgets import RichLog

from mission.link.view import RobotView


class LogPanel(RichLog):
    can_focus = False  # the arrows drive the robot

    def on_mount(self) -> None:
        self._seen = 0

    def show(self, view: RobotView) -> None:
        lines = view.log
        if len(lines) < self._seen:  # the client's window rolled over: show what is new from the end
            self._seen = max(0, len(lines) - 1)
        for line in lines[self._seen:]:
            self.write(line)
        self._seen = len(lines)

    def say(self, line: str) -> None:
        self.write(f"[console] {line}")
