"""The mission tree panel: py_trees' tree with its statuses, folded to the running branch and
scrolled to keep the running step in view.

A 200-pot patrol's tree is thousands of lines (some fifteen per pot), nearly all of them the
steps of pots finished or not started, and at the top the battery-low branch, which only runs
when the pack is flat. Shown whole, the panel opened on that idle branch with the pot in
progress far below, and took hundreds of milliseconds to lay the text out at every change. So
the panel folds: a node's children are shown only while the node runs. Every pot keeps its one line (its status mark says done or to do), the pot in
progress is open down to the running step, the battery-low branch is one line.

While a guard holds the mission (e-stop, pause), py_trees stops the subtree (every status below
it goes to ``[-]``), which would fold the pot in progress away just when the operator looks for
it: then the branch that ran last stays open. A tree in which nothing runs and no branch ran
before (a console started after the end) is shown whole. The panel draws only the lines in
view (:mod:`tui.widgets.text_lines`).
"""
from __future__ import annotations

import re

from rich.text import Text

from mission.link.view import RobotView
from tui.widgets.follow import follow_top
from tui.widgets.text_lines import TextLines

MARKS = ((r"\[\*\]", "bold cyan"), (r"\[✓\]", "green"), (r"\[✕\]", "bold red"))
"""py_trees' unicode status marks: running, success, failure."""
NO_TREE = "no mission yet: press m to start one"
_ANSI = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")


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


Path = tuple[str, ...]


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip(" "))


def _node(line: str) -> tuple[str, str]:
    """A line's node name (with py_trees' type marker) and status mark ('*', '✓', '✕', '-';
    '' for a line that is not a node): the first `` [x]`` after the type marker (``[o]`` for
    a selector) ends the name."""
    at = line.find(" [", _indent(line))
    while at >= 0 and not (len(line) > at + 3 and line[at + 3] == "]"):
        at = line.find(" [", at + 1)
    if at < 0:
        return line.strip(), ""
    return line[:at].strip(), line[at + 2]


def fold(lines: list[str], keep_open: set[Path]) -> tuple[list[int], set[Path], int | None]:
    """One pass over the tree's lines (ANSI codes removed): the lines shown (the root, and a
    node's children only while it runs or its path, the names from the root down to it, is in
    ``keep_open``), the paths of the running nodes, and the line to keep in view (the deepest
    open or running one). A closed node's subtree is skipped on its indent alone."""
    shown: list[int] = []
    running: set[Path] = set()
    stack: list[tuple[int, str]] = []
    closed_below, focus, focus_key = None, None, (-1, False)  # indent of the closed node being skipped
    for i, line in enumerate(lines):
        indent = _indent(line)
        if closed_below is not None:
            if indent > closed_below:
                continue
            closed_below = None
        name, mark = _node(line)
        while stack and stack[-1][0] >= indent:
            stack.pop()
        stack.append((indent, name))
        path = tuple(n for _, n in stack)
        shown.append(i)
        if mark == "*":
            running.add(path)
        elif path not in keep_open:
            closed_below = indent
            continue
        if (indent, mark == "*") > focus_key:
            focus, focus_key = i, (indent, mark == "*")
    return shown, running, focus


def narrow(line: str) -> str:
    """Half the indent (py_trees gives four spaces a level): a pot's step is ten levels deep
    and the side panel is some sixty columns wide."""
    spaces = len(line) - len(line.lstrip(" "))
    return line[spaces // 2:]


class TreeFolder:
    """Decides which lines of successive trees are shown, remembering the branch that ran
    last (kept open while a guard holds the mission)."""

    def __init__(self) -> None:
        self.last_running: set[Path] = set()

    def lines(self, tree: str) -> tuple[list[str], int | None]:
        """The raw lines to show and, among them, the line to keep in view."""
        raw = tree.splitlines()
        clean = [_ANSI.sub("", line) for line in raw] if "\x1b" in tree else raw
        stars = [i for i, line in enumerate(clean) if "[*]" in line]
        deepest = max(stars, key=lambda i: _indent(clean[i]), default=None)
        held = deepest is None or (deepest + 1 < len(clean) and _indent(clean[deepest + 1]) > _indent(clean[deepest]))
        if held and not self.last_running:
            return raw, deepest  # nothing ran yet that we saw: the whole tree
        shown, running, focus = fold(clean, self.last_running if held else set())
        if not held:
            self.last_running = running
        return [raw[i] for i in shown], None if focus is None else shown.index(focus)


class MissionTree(TextLines):
    """The tree folded to its running branch, kept in view as the step changes; the operator
    may scroll away with the mouse until the step changes."""

    def __init__(self, **kw):
        super().__init__(**kw)
        self._tree: str | None = None
        self._followed: int | None = None
        self._focus: int | None = None
        self._folder = TreeFolder()
        self.shown: list[str] = []
        """The tree's lines on the panel now (folded, narrowed, ANSI codes and all)."""

    def show(self, view: RobotView) -> None:
        if view.tree != self._tree:
            self._tree = view.tree
            if not view.tree:
                self.set_lines([Text(NO_TREE, "dim")])
                self.shown, self._focus = [], None
                return
            lines, self._focus = self._folder.lines(view.tree)
            self.shown = [narrow(line) for line in lines]
            self.set_lines(list(tree_text("\n".join(self.shown)).split("\n")))
        if self._focus is not None and self._focus != self._followed:
            self._followed = self._focus
            self.call_after_refresh(self._follow, self._focus)

    def _follow(self, line: int) -> None:
        """Keep the line in the middle half; if the panel was not laid out yet (it cannot
        scroll that far), try again at the next poll."""
        top = follow_top(line, self.scroll_y, self.view_height)
        if top is not None:
            self.scroll_to(y=top, animate=False, immediate=True)
        if not self.in_view(line):
            self._followed = None
