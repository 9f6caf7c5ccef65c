"""The pot table: one row per pot of the mission (or, on the operator's ``a``, only the pots
with anomalies), scrolled to keep the pot in progress in view.

With a few pots the table fits its panel; with 200 the pot in progress scrolls out of sight
within minutes, so the table follows it the way the tree follows the running step: it scrolls
when another pot starts, and the operator may scroll away with the mouse meanwhile. The
anomaly filter is the question an operator asks of a long patrol ("which pots need me?"); the
title says how many pots it shows of how many.
"""
from __future__ import annotations

from rich.text import Text
from textual.widgets import DataTable
from textual.widgets.data_table import RowDoesNotExist

from mission.link.view import PotView, RobotView

COLUMNS = ("pot", "status", "tag", "flower", "blooms", "anomalies")
STATUS_STYLE = {"inspected": "green", "failed": "bold red", "skipped": "dim", "active": "bold cyan", "pending": ""}


def pot_row(p: PotView) -> tuple[str, ...]:
    return (p.id, p.status, "-" if p.tag is None else str(p.tag), p.flower or "-",
            str(p.blooms) if p.blooms else "-", " ".join(p.anomalies) or "-")


def _cell(column: int, value: str) -> Text:
    return Text(value, STATUS_STYLE.get(value, "") if column == 1 else "")


def table_title(shown: int, total: int, anomalies_only: bool) -> str:
    if anomalies_only:
        return f"pots with anomalies: {shown} of {total}"
    return f"pots: {total}" if total else "pots"


class PotsTable(DataTable):
    """Changed cells are updated in place (the scroll position stays); the rows are rebuilt
    only when the pots shown change (another mission, the filter, a new anomaly under it)."""

    can_focus = False  # the arrows drive the robot

    def __init__(self, **kw):
        super().__init__(show_cursor=False, **kw)
        self._rows: list[tuple[str, ...]] = []
        self._view: RobotView | None = None
        self._followed: str | None = None
        self._title = ""
        self.anomalies_only = False
        """Show only the pots with anomalies (the operator's ``a``)."""

    def toggle_anomalies(self) -> None:
        self.anomalies_only = not self.anomalies_only
        self._followed = None
        self.show(self._view or RobotView())

    def show(self, view: RobotView) -> None:
        self._view = view
        if not self.columns:
            for name in COLUMNS:
                self.add_column(name, key=name)
        pots = [p for p in view.pots if p.anomalies] if self.anomalies_only else view.pots
        rows = [pot_row(p) for p in pots]
        title = table_title(len(rows), len(view.pots), self.anomalies_only)
        if title != self._title:  # setting a border title repaints the whole table, even unchanged
            self.border_title = self._title = title
        if rows != self._rows:
            self._update(rows)
        active = next((r[0] for r in rows if r[1] == "active"), None)
        if active is not None and active != self._followed:
            self._followed = active
            self.call_after_refresh(self._follow, active)

    def _update(self, rows: list[tuple[str, ...]]) -> None:
        if [r[0] for r in rows] == [r[0] for r in self._rows]:
            for new, old in zip(rows, self._rows):
                for column, (value, was) in enumerate(zip(new, old)):
                    if value != was:
                        self.update_cell(new[0], COLUMNS[column], _cell(column, value))
        else:
            self.clear()
            for r in rows:
                self.add_row(*(_cell(i, v) for i, v in enumerate(r)), key=r[0])
        self._rows = rows

    def _follow(self, key: str) -> None:
        """The row to the middle of the panel; if the table was not laid out yet, again at the
        next poll."""
        try:
            row = self.get_row_index(key)
        except RowDoesNotExist:  # gone (the filter, another mission) before the refresh came
            return
        height = self.scrollable_content_region.height - (self.header_height if self.show_header else 0)
        self.scroll_to(y=max(0, row - height // 2), animate=False, immediate=True)
        if not self.scroll_y <= row < self.scroll_y + max(height, 1):
            self._followed = None

    def visible_rows(self) -> range:
        """Indices of the rows on the panel now."""
        height = self.scrollable_content_region.height - (self.header_height if self.show_header else 0)
        top = int(self.scroll_y)
        return range(top, min(top + max(height, 0), self.row_count))
