"""A scrolling panel of rich ``Text`` lines drawn through Textual's line API, for the panels
that change twice a second and hold hundreds of lines (the mission tree, the pot table).

Only the lines in view are rendered, each once: its ``Strip`` is kept until that line's text
changes, so a new pot status re-renders one row, not the panel. (A ``Static`` lays out and
renders its whole text on every update, and a ``DataTable`` renders every visible row again,
cell by cell, after any cell changes: a hundred milliseconds or more a time with 200 pots.) An
optional header line stays at the top while the lines scroll under it.
"""
from __future__ import annotations

from rich.cells import cell_len
from rich.text import Text
from textual.geometry import Size
from textual.scroll_view import ScrollView
from textual.strip import Strip


class TextLines(ScrollView, can_focus=False):  # the arrows drive the robot
    def __init__(self, **kw):
        super().__init__(**kw)
        self.lines: list[Text] = []
        self.header: Text | None = None
        self._strips: dict[int, Strip] = {}
        self._header_strip: Strip | None = None

    def set_lines(self, lines: list[Text], header: Text | None = None) -> None:
        """Show ``lines`` (under ``header``); the strips of lines that did not change are kept."""
        lines, old = list(lines), self.lines
        self._strips = {i: s for i, s in self._strips.items() if i < len(lines) and i < len(old) and lines[i] == old[i]}
        if header != self.header:
            self._header_strip = None
        self.lines, self.header = lines, header
        width = max((cell_len(t.plain) for t in ([header] if header is not None else []) + lines), default=0)
        self.virtual_size = Size(width, len(lines) + (header is not None))
        self.refresh()

    @property
    def view_height(self) -> int:
        """Lines (not counting the header) the panel shows at once."""
        return max(self.scrollable_content_region.height - (self.header is not None), 0)

    def in_view(self, line: int) -> bool:
        top = int(self.scroll_y)
        return top <= line < top + self.view_height

    def _strip(self, text: Text) -> Strip:
        return Strip(text.render(self.app.console), cell_len(text.plain))

    def render_line(self, y: int) -> Strip:
        scroll_x, scroll_y = self.scroll_offset
        width, style = self.size.width, self.rich_style
        if self.header is not None:
            if y == 0:
                if self._header_strip is None:
                    self._header_strip = self._strip(self.header)
                return self._header_strip.crop_extend(scroll_x, scroll_x + width, style)
            y -= 1
        i = scroll_y + y
        if i >= len(self.lines):
            return Strip.blank(width, style)
        strip = self._strips.get(i)
        if strip is None:
            strip = self._strips[i] = self._strip(self.lines[i])
        return strip.crop_extend(scroll_x, scroll_x + width, style).apply_offsets(scroll_x, i)
