"""The mission panel: py_trees' tree with its statuses, following the running step, and the
table of pot results."""
from __future__ import annotations

from rich.text import Text
from textual.app import ComposeResult
from textual.containers import VerticalScroll
from textual.widgets import DataTable, Static

from mission.link.view import PotView, RobotView

COLUMNS = ("pot", "status", "tag", "flower", "blooms", "anomalies")
STATUS_STYLE = {"inspected": "green", "failed": "bold red", "skipped": "dim", "active": "bold cyan", "pending": ""}
MARKS = ((r"\[\*\]", "bold cyan"), (r"\[✓\]", "green"), (r"\[✕\]", "bold red"))
"""py_trees' unicode status marks: running, success, failure."""
NO_TREE = "no mission yet: press m to start one"


def tree_text(tree: str) -> Text:
    """The tree as the runtime rendered it (py_trees colours it with ANSI codes on a
    terminal: they are read, not shown raw), its status marks coloured."""
    text = Text.from_ansi(tree, no_wrap=True, overflow="ellipsis")
    for pattern, style in MARKS:
        text.highlight_regex(pattern, style)
    return text


def running_line(tree: str) -> int | None:
    """The line of the deepest running behaviour (the step the robot is on), if any."""
    best, depth = None, -1
    for i, line in enumerate(tree.splitlines()):
        if "[*]" in line:
            indent = len(line) - len(line.lstrip())
            if indent > depth:
                best, depth = i, indent
    return best


class MissionTree(VerticalScroll, can_focus=False):  # the arrows drive the robot
    """The whole tree (a patrol's is a few hundred lines), scrolled to keep the running step in
    view; the operator may scroll away with the mouse until the step changes."""

    def __init__(self, **kw):
        super().__init__(**kw)
        self._tree: str | None = None
        self._followed: int | None = None
        self._body = Static(Text(NO_TREE, "dim"), classes="tree-text")

    def compose(self) -> ComposeResult:
        yield self._body

    def show(self, view: RobotView) -> None:
        if view.tree == self._tree:
            return
        self._tree = view.tree
        if not view.tree:
            self._body.update(Text(NO_TREE, "dim"))
            return
        text = tree_text(view.tree)
        self._body.update(text)
        line = running_line(text.plain)
        if line is not None and line != self._followed:
            self._followed = line
            self.call_after_refresh(self._follow, line)

    def _follow(self, line: int) -> None:
        self.scroll_to(y=max(0, line - self.scrollable_content_region.height // 2), animate=False)


def pot_row(p: PotView) -> tuple[str, ...]:
    return (p.id, p.status, "-" if p.tag is None else str(p.tag), p.flower or "-",
            str(p.blooms) if p.blooms else "-", " ".join(p.anomalies) or "-")


def _cell(column: int, value: str) -> Text:
    return Text(value, STATUS_STYLE.get(value, "") if column == 1 else "")


class PotsTable(DataTable):
    """One row per pot of the mission; changed cells are updated in place (the scroll position
    stays), the rows rebuilt only when the pots themselves change."""

    can_focus = False  # the arrows drive the robot

    def __init__(self, **kw):
        super().__init__(show_cursor=False, **kw)
        self._rows: list[tuple[str, ...]] = []

    def show(self, view: RobotView) -> None:
        if not self.columns:
            for name in COLUMNS:
                self.add_column(name, key=name)
        rows = [pot_row(p) for p in view.pots]
        if rows == self._rows:
            return
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
