"""The footer: every key of :mod:`tui.keys`, grouped as the table groups them, one section a
line (the robot's keys, then the view's), wrapping between keys on a narrow terminal.

Textual's ``Footer`` is one line that cuts off what does not fit: with the map and pot-table
keys the console has more than 160 columns of keys, and an operator should not have to guess the
ones past the edge. The footer only tells; the app's bindings do the work (and ctrl+p lists
them too).
"""
from __future__ import annotations

from dataclasses import replace
from itertools import groupby

from rich.cells import cell_len
from rich.text import Text
from textual.binding import Binding
from textual.widgets import Static


def chips(bindings: list[Binding], key_display) -> list[tuple[str, str]]:
    """(keys, what they do) per shown binding, consecutive bindings of one group as one chip:
    its keys side by side (apart unless the group is compact) and the group's description."""
    out = []
    shown = [b for b in bindings if b.show]
    for group, run in groupby(shown, key=lambda b: b.group):
        run = list(run)
        keys = [key_display(replace(b, key=b.key.split(",")[0])) for b in run]
        if group is None:
            out += [(k, b.description) for k, b in zip(keys, run)]
        else:
            out.append(("".join(keys) if group.compact else " ".join(keys), group.description))
    return out


def key_text(sections: list[list[tuple[str, str]]], width: int, key_style="bold", label_style="") -> Text:
    """The chips two spaces apart, each section on a line of its own, a new line where the
    next chip would pass ``width`` (0: never)."""
    t = Text(no_wrap=True, overflow="ellipsis")
    for n, section in enumerate(sections):
        if n:
            t.append("\n")
        used = 0
        for keys, label in section:
            size = cell_len(keys) + 1 + cell_len(label)
            if used:
                if width and used + 2 + size > width:
                    t.append("\n")
                    used = 0
                else:
                    t.append("  ")
                    used += 2
            t.append(keys, key_style)
            t.append(" " + label, label_style)
            used += size
    return t


class KeyBar(Static):
    COMPONENT_CLASSES = {"key-bar--key"}

    def __init__(self, sections: list[list[Binding]], **kw):
        super().__init__(**kw)
        self.sections = sections
        self.text = Text()
        """What it shows."""

    def on_mount(self) -> None:
        self._wrap()

    def on_resize(self) -> None:
        self.call_after_refresh(self._wrap)

    def _wrap(self) -> None:
        chipped = [chips(s, self.app.get_key_display) for s in self.sections]
        self.text = key_text(chipped, self.content_size.width, self.get_component_rich_style("key-bar--key"))
        self.update(self.text)
