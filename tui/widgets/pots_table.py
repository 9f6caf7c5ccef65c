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

Once the robot's patrol history has answered (:mod:`tui.history_marks`), two columns follow:
what changed at the pot since the last patrol (blank: nothing) and its pest streak; the gaps
narrow to one space so they fit the side panel. A robot without a history has no such columns.

One pot is *selected* for its timeline (the operator's ``i``): the row clicked or moved to with
``[`` / ``]`` (shown reversed), else the pot in progress, else the first row in view.
"""
from __future__ import annotations

from rich.text import Text

from textual import events

from mission.link.view import PotView, RobotView
from tui.history_marks import PotMarks
from tui.widgets.follow import follow_top
from tui.widgets.text_lines import TextLines

COLUMNS = ("pot", "status", "tag", "flower", "blooms", "anomalies")
HISTORY_COLUMNS = ("since last", "pests")
"""What changed since the last patrol; the pest streak (``x3``: the latest three patrols saw one)."""
STATUS_STYLE = {"inspected": "green", "failed": "bold red", "skipped": "dim", "active": "bold cyan", "pending": ""}
HISTORY_STYLE = {6: "yellow", 7: "bold red"}
"""Column -> style of a non-blank history cell."""
GAP, NARROW_GAP = "  ", " "
NO_MARKS = PotMarks()


def pot_row(p: PotView, marks: dict[str, PotMarks] | None = None) -> tuple[str, ...]:
    """The row's cells (``COLUMNS``, then ``HISTORY_COLUMNS`` when ``marks`` is not None)."""
    row = (p.id, p.status, "-" if p.tag is None else str(p.tag), p.flower or "-",
           str(p.blooms) if p.blooms else "-", " ".join(p.anomalies) or "-")
    if marks is None:
        return row
    m = marks.get(p.id, NO_MARKS)
    return row + (m.since, m.streak_text)


def row_text(row: tuple[str, ...], widths: list[int], selected: bool = False) -> Text:
    gap = NARROW_GAP if len(row) > len(COLUMNS) else GAP
    t = Text(" ", no_wrap=True)
    for column, (value, width) in enumerate(zip(row, widths)):
        if column:
            t.append(gap)
        style = STATUS_STYLE.get(value, "") if column == 1 else HISTORY_STYLE.get(column, "") if value else ""
        t.append(value.ljust(width), style)
    if selected:
        t.stylize("reverse")
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
        self.marks: dict[str, PotMarks] | None = None
        """Each pot's history cells; None: no history answer (no history columns)."""
        self.selected: str | None = None
        """The pot the operator picked (a click, ``[`` / ``]``); None: none picked."""
        self._shown_selected: str | None = None

    @property
    def row_count(self) -> int:
        return len(self.rows)

    def row(self, pot: str) -> tuple[str, ...]:
        return self.rows[self._index[pot]]

    def toggle_anomalies(self) -> None:
        self.anomalies_only = not self.anomalies_only
        self._followed = None
        self.show(self._view or RobotView())

    def set_marks(self, marks: dict[str, PotMarks] | None) -> None:
        """The history's cells for each pot (None: the robot gave no history answer)."""
        if marks != self.marks:
            self.marks = marks
            self.show(self._view or RobotView())

    def show(self, view: RobotView) -> None:
        self._view = view
        pots = [p for p in view.pots if p.anomalies] if self.anomalies_only else view.pots
        rows = [pot_row(p, self.marks) for p in pots]
        title = table_title(len(rows), len(view.pots), self.anomalies_only)
        if title != self._title:  # setting a border title repaints, even unchanged
            self.border_title = self._title = title
        if rows != self.rows or not self.lines or self.selected != self._shown_selected:
            names = COLUMNS + (HISTORY_COLUMNS if self.marks is not None else ())
            widths = [max([len(name)] + [len(r[i]) for r in rows]) for i, name in enumerate(names)]
            header = row_text(names, widths)
            header.stylize("bold")
            self.set_lines([row_text(r, widths, r[0] == self.selected) for r in rows], header)
            self.rows, self._index = rows, {r[0]: i for i, r in enumerate(rows)}
            self._shown_selected = self.selected
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

    # --- the selected pot (for its timeline) -----------------------------------------------------
    def selected_pot(self) -> str | None:
        """The pot whose timeline ``i`` opens: the one picked, else the one in progress, else the
        first row in view (None: no rows)."""
        if self.selected in self._index:
            return self.selected
        active = next((r[0] for r in self.rows if r[1] == "active"), None)
        if active is not None:
            return active
        top = int(self.scroll_y)
        return self.rows[top][0] if top < len(self.rows) else None

    def select(self, pot: str | None) -> None:
        self.selected = pot
        self.show(self._view or RobotView())
        row = self._index.get(pot) if pot is not None else None
        if row is not None and not self.in_view(row):
            self.scroll_to(y=max(0, row - self.view_height // 2), animate=False, immediate=True)

    def select_next(self, step: int) -> None:
        """Pick the next (``step`` 1) or previous (-1) row from the selected pot."""
        if not self.rows:
            return
        here = self._index.get(self.selected_pot() or "")
        row = 0 if here is None else min(max(here + step, 0), len(self.rows) - 1)
        self.select(self.rows[row][0])

    def on_click(self, event: events.Click) -> None:
        at = event.get_content_offset(self)
        if at is None or at.y < 1:  # a border, the header
            return
        row = int(self.scroll_y) + at.y - 1
        if row < len(self.rows):
            self.select(self.rows[row][0])

    def visible_rows(self) -> range:
        """Indices of the rows on the panel now."""
        top = int(self.scroll_y)
        return range(top, min(top + self.view_height, self.row_count))
