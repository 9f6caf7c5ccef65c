"""The pot table: one row per pot of the mission (or, on the operator's ``a``, only the pots
with anomalies), kept scrolled to the pot in progress.

With a few pots the table fits its panel; with 200 the pot in progress scrolls out of sight
within minutes, so the table follows it the way the tree follows the running step: it scrolls
when the pot in progress leaves the middle half of the panel, and the operator may scroll away
with the mouse meanwhile. The anomaly filter is the question an operator asks of a long patrol
("which pots need me?"); the title says how many pots it shows of how many.

The rows are text lines under a fixed header (:mod:`tui.widgets.text_lines`), columns as wide as
their widest cell: a new status re-renders one row, where Textual's ``DataTable`` rendered
every visible row again, cell by cell, after any change.
"""
from __future__ import annotations

from rich.text import Text

from mission.link.view import PotView, RobotView
from tui.widgets.follow import follow_top
from tui.widgets.text_lines import TextLines

COLUMNS = ("pot", "status", "tag", "flower", "blooms", "anomalies")
STATUS_STYLE = {"inspected": "green", "failed": "bold red", "skipped": "dim", "active": "bold cyan", "pending": ""}
GAP = "  "


def pot_row(p: PotView) -> tuple[str, ...]:
    return (p.id, p.status, "-" if p.tag is None else str(p.tag), p.flower or "-",
            str(p.blooms) if p.blooms else "-", " ".join(p.anomalies) or "-")


def row_text(row: tuple[str, ...], widths: list[int]) -> Text:
    t = Text(" ", no_wrap=True)
    for column, (value, width) in enumerate(zip(row, widths)):
        if column:
            t.append(GAP)
        t.append(value.ljust(width), STATUS_STYLE.get(value, "") if column == 1 else "")
    return t


def table_title(shown: int, total: int, anomalies_only: bool) -> str:
    if anomalies_only:
        return f"pots with anomalies: {shown} of {total}"
    return f"pots: {total}" if total else "pots"


class PotsTable(TextLines):
    def __init__(self, **kw):
        super().__init__(**kw)
        self.rows: list[tuple[str, ...]] = []
        """The rows shown, as text (``COLUMNS``)."""
        self._index: dict[str, int] = {}
        self._view: RobotView | None = None
        self._followed: str | None = None
        self._title = ""
        self.anomalies_only = False
        """Show only the pots with anomalies (the operator's ``a``)."""

    @property
    def row_count(self) -> int:
        return len(self.rows)

    def row(self, pot: str) -> tuple[str, ...]:
        return self.rows[self._index[pot]]

    def toggle_anomalies(self) -> None:
        self.anomalies_only = not self.anomalies_only
        self._followed = None
        self.show(self._view or RobotView())

    def show(self, view: RobotView) -> None:
        self._view = view
        pots = [p for p in view.pots if p.anomalies] if self.anomalies_only else view.pots
        rows = [pot_row(p) for p in pots]
        title = table_title(len(rows), len(view.pots), self.anomalies_only)
        if title != self._title:  # setting a border title repaints, even unchanged
            self.border_title = self._title = title
        if rows != self.rows or not self.lines:
            widths = [max([len(name)] + [len(r[i]) for r in rows]) for i, name in enumerate(COLUMNS)]
            header = row_text(COLUMNS, widths)
            header.stylize("bold")
            self.set_lines([row_text(r, widths) for r in rows], header)
            self.rows, self._index = rows, {r[0]: i for i, r in enumerate(rows)}
        active = next((r[0] for r in rows if r[1] == "active"), None)
        if active is not None and active != self._followed:
            self._followed = active
            self.call_after_refresh(self._follow, active)

    def _follow(self, pot: str) -> None:
        """Keep the row in the middle half of the panel; if the table was not laid out yet,
        again at the next poll."""
        row = self._index.get(pot)
        if row is None:  # gone (the filter, another mission) before the refresh came
            return
        top = follow_top(row, self.scroll_y, self.view_height)
        if top is not None:
            self.scroll_to(y=top, animate=False, immediate=True)
        if not self.in_view(row):
            self._followed = None

    def visible_rows(self) -> range:
        """Indices of the rows on the panel now."""
        top = int(self.scroll_y)
        return range(top, min(top + self.view_height, self.row_count))
