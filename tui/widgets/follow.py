"""Keeping a line in view (the tree's running step, the pot in progress) without scrolling on
every change: a scroll makes Textual render the whole panel again (a 200-row table's visible
rows, cell by cell), and a panel that jumps at every pot is hard to read. The line may move
freely in the middle half of the panel; past it, the panel scrolls to put it in the middle."""
from __future__ import annotations


def follow_top(line: int, top: float, height: int) -> int | None:
    """The new first line for a panel ``height`` lines high showing from ``top``, or None when
    ``line`` is in its middle half (or the panel has no height yet)."""
    if height <= 0:
        return None
    margin = height // 4
    if top + margin <= line < top + height - margin:
        return None
    return max(0, line - height // 2)
