"""The mission panel: py_trees' tree with its statuses, and the table of pot results."""
from __future__ import annotations

from textual.widgets import DataTable, Static

from mission.link.view import RobotView

COLUMNS = ("pot", "status", "tag", "flower", "blooms", "anomalies")
STATUS_STYLE = {"inspected": "green", "failed": "bold red", "skipped": "dim", "active": "bold cyan", "pending": ""}


class MissionTree(Static):
    def show(self, view: RobotView) -> None:
        self.update(view.tree or "no mission yet: press m to start one")


class PotsTable(DataTable):
    can_focus = False  # the arrows drive the robot

    def on_mount(self) -> None:
        self.add_columns(*COLUMNS)
        self.cursor_type = "row"
        self._rows: list[tuple] = []

    def show(self, view: RobotView) -> None:
        rows = [(p.id, p.status, "-" if p.tag is None else str(p.tag), p.flower or "-",
                 str(p.blooms) if p.blooms else "-", " ".join(p.anomalies) or "-") for p in view.pots]
        if rows == self._rows:
            return
        self._rows = rows
        self.clear()
        for r in rows:
            style = STATUS_STYLE.get(r[1], "")
            self.add_row(r[0], f"[{style}]{r[1]}[/]" if style else r[1], *r[2:], key=r[0])
