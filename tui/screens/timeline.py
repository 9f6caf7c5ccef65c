"""One pot's timeline (the operator's ``i`` on the selected pot): every patrol that recorded it,
newest first, read from the robot's patrol history over the link (the ``pot`` answer of
:mod:`mission.history.answers`).

The screen opens at once saying it is reading; the answer comes from a worker thread (a year
of patrols is a few hundred milliseconds over a slow link, and the console never waits on the
robot). A robot without a history, or a link that cannot ask, says so in the screen. Escape
(or ``i`` again) closes it; the app's priority keys (driving, the e-stop) still work under it.
Newest first: the grower's question is what happened lately, and the arrows drive the robot,
so the top of the list is what is read without scrolling.
"""
from __future__ import annotations

from typing import Mapping, Sequence

from rich.text import Text
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import Label

from tui.widgets.text_lines import TextLines

COLUMNS = ("date (UTC)", "patrol", "mission", "status", "flower", "blooms", "pest", "anomalies")


def _date(iso: object) -> str:
    """``2025-05-01T06:00:00Z`` as ``2025-05-01 06:00``."""
    s = str(iso or "?")
    return s[:16].replace("T", " ") if len(s) >= 16 else s


def entry_row(e: Mapping) -> tuple[str, ...]:
    """One timeline entry (``TimelineEntry.as_json``) as the table's cells."""
    bug = e.get("bug")
    blooms = e.get("blooms")
    return (_date(e.get("started_at")), f"#{e.get('patrol', '?')}", str(e.get("mission") or "-"),
            str(e.get("status") or "-"), str(e.get("flower_color") or "-"), "-" if blooms is None else str(blooms),
            "-" if bug is None else "PEST" if bug else "no", " ".join(e.get("anomalies") or ()) or "-")


def timeline_lines(timeline: Sequence[Mapping]) -> tuple[Text, list[Text]]:
    """The header and one line per entry, newest first."""
    rows = [entry_row(e) for e in reversed(timeline)]
    widths = [max([len(name)] + [len(r[i]) for r in rows]) for i, name in enumerate(COLUMNS)]

    def line(row: tuple[str, ...]) -> Text:
        t = Text(" ", no_wrap=True)
        for i, (value, width) in enumerate(zip(row, widths)):
            t.append(("  " if i else "") + value.ljust(width),
                     "bold red" if value == "PEST" else "bold red" if value == "failed" else "")
        return t

    header = line(COLUMNS)
    header.stylize("bold")
    return header, [line(r) for r in rows]


class Timeline(ModalScreen[None]):
    BINDINGS = [Binding("escape,i", "close", "close", show=False)]

    def __init__(self, pot: str):
        super().__init__()
        self.pot = pot
        self.message = Label(f"reading {pot}'s history from the robot ...", id="timeline-message")
        self.table = TextLines(id="timeline-table")
        self.entries: list[Mapping] | None = None
        """The timeline shown (oldest first, as answered); None until it came."""

    def compose(self) -> ComposeResult:
        with Vertical(id="timeline"):
            yield self.message
            yield self.table
            yield Label("escape = close", id="timeline-hint")

    def on_mount(self) -> None:
        self.query_one("#timeline").border_title = f"{self.pot}: timeline"

    def show_answer(self, answer: Mapping | None, error: str | None) -> None:
        """The robot's ``pot`` answer, or why there is none."""
        if answer is None:
            self.message.update(f"no history for {self.pot}: {error or 'no answer'}")
            self.message.add_class("-error")
            return
        timeline = [e for e in answer.get("timeline") or () if isinstance(e, Mapping)]
        self.entries = timeline
        if not timeline:
            self.message.update(f"no patrol has recorded {self.pot} yet")
            return
        pests = sum(1 for e in timeline if e.get("bug") is True)
        self.message.update(f"{self.pot}: {len(timeline)} patrols, newest first, {pests} with a pest")
        header, lines = timeline_lines(timeline)
        self.table.set_lines(lines, header)

    def action_close(self) -> None:
        self.dismiss(None)
