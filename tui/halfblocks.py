"""Pictures in a terminal: an RGB image as rows of '▀' characters, two square pixels per
character (the top pixel is the foreground colour, the bottom one the background).

Used by the map (every redraw) and the camera panel. The colour pairs are packed into one int64
per character with numpy and cut into runs where the pair changes; only the runs (a few hundred
on a map, at worst one per character) are visited in Python, each becoming a ``Segment`` with a
cached ``Style``.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
from rich.color import Color
from rich.segment import Segment
from rich.style import Style
from rich.text import Text

BLOCK = "▀"


@lru_cache(maxsize=8192)
def _style(pair: int) -> Style:
    top, bottom = pair >> 24, pair & 0xFFFFFF
    return Style(color=Color.from_rgb(top >> 16, (top >> 8) & 255, top & 255),
                 bgcolor=Color.from_rgb(bottom >> 16, (bottom >> 8) & 255, bottom & 255))


@lru_cache(maxsize=1024)
def _bar(n: int) -> str:
    return BLOCK * n


def half_block_rows(rgb: np.ndarray) -> list[list[Segment]]:
    """An (2H, W, 3) uint8 image as H rows of segments (an odd last pixel row is dropped)."""
    h2 = rgb.shape[0] - rgb.shape[0] % 2
    if h2 == 0 or rgb.shape[1] == 0:
        return []
    c = rgb[:h2].astype(np.int64)
    packed = (c[..., 0] << 16) | (c[..., 1] << 8) | c[..., 2]
    pair = (packed[0::2] << 24) | packed[1::2]  # (H, W): top and bottom colour of each character
    h, w = pair.shape
    starts = np.ones((h, w), bool)
    starts[:, 1:] = pair[:, 1:] != pair[:, :-1]
    row, col = np.nonzero(starts)  # row-major: runs in reading order
    end = np.empty_like(col)
    end[:-1] = col[1:]
    last = np.ones(len(row), bool)
    last[:-1] = row[1:] != row[:-1]
    end[last] = w
    rows: list[list[Segment]] = [[] for _ in range(h)]
    for r, p, n in zip(row.tolist(), pair[row, col].tolist(), (end - col).tolist()):
        rows[r].append(Segment(_bar(n), _style(p)))
    return rows


def half_blocks(rgb: np.ndarray) -> Text:
    """The same picture as ``rich`` text (the camera snapshot)."""
    text = Text(no_wrap=True, overflow="crop")
    for i, row in enumerate(half_block_rows(rgb)):
        if i:
            text.append("\n")
        for seg in row:
            text.append(seg.text, seg.style)
    return text
