"""The map panel: occupancy, inflated-cost shading, the plan, the pots and the robot, in
half-block characters (each character is two square pixels, top and bottom).

:func:`render_map` is pure (view in, one ``Strip`` per line out) so it can be measured and
tested without a terminal. The picture is built as one RGB array with numpy (nearest-cell
sampling of the grid, no per-cell Python), the few overlays drawn on it, then cut into runs of
one colour pair, each a ``Segment`` with a cached style. The panel hands Textual those strips
through its line API: going through ``Text`` / ``Content`` costs ~10x more per frame.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from rich.segment import Segment
from rich.style import Style
from rich.text import Text
from textual.strip import Strip
from textual.widget import Widget

from mission.link.view import RobotView

UNKNOWN, FREE, OCCUPIED = (28, 28, 36), (70, 74, 70), (235, 235, 225)
COST = np.array([200, 60, 40], dtype=np.float32)
PLAN, ROBOT, HEADING, SCAN = (250, 210, 60), (60, 200, 255), (255, 255, 255), (255, 80, 160)
POT_COLOURS = {"pending": (150, 150, 150), "active": (60, 130, 255), "inspected": (40, 210, 80),
               "failed": (230, 40, 40), "skipped": (90, 90, 90)}
ANOMALY = (255, 160, 0)
MARGIN = 0.5
"""Metres around what is drawn (the grid, the pots, the robot)."""


def _bounds(view: RobotView) -> tuple[float, float, float, float]:
    xs, ys = [view.pose[0]], [view.pose[1]]
    for g in (view.grid, view.costmap):
        if g is not None:
            h, w = g.data.shape
            xs += [g.origin_x, g.origin_x + w * g.resolution]
            ys += [g.origin_y, g.origin_y + h * g.resolution]
    xs += [p.x for p in view.pots]
    ys += [p.y for p in view.pots]
    if len(xs) == 1:
        xs += [view.pose[0] - 2.0, view.pose[0] + 2.0]
        ys += [view.pose[1] - 2.0, view.pose[1] + 2.0]
    return min(xs) - MARGIN, max(xs) + MARGIN, min(ys) - MARGIN, max(ys) + MARGIN


class Canvas:
    """Pixels over a world window: (0, 0) is the top-left pixel, +y is up in the world."""

    def __init__(self, view: RobotView, width: int, height: int):
        x0, x1, y0, y1 = _bounds(view)
        self.w, self.h = width, 2 * height
        self.scale = min(self.w / (x1 - x0), self.h / (y1 - y0))  # pixels per metre, square pixels
        self.x0 = (x0 + x1) / 2 - self.w / (2 * self.scale)
        self.y1 = (y0 + y1) / 2 + self.h / (2 * self.scale)
        self.rgb = np.empty((self.h, self.w, 3), np.uint8)
        self.rgb[:] = UNKNOWN

    def pixel_centres(self) -> tuple[np.ndarray, np.ndarray]:
        px = self.x0 + (np.arange(self.w) + 0.5) / self.scale
        py = self.y1 - (np.arange(self.h) + 0.5) / self.scale
        return px, py

    def to_pixel(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        return (np.floor((np.asarray(x) - self.x0) * self.scale).astype(int),
                np.floor((self.y1 - np.asarray(y)) * self.scale).astype(int))

    def dots(self, x, y, colour) -> None:
        c, r = self.to_pixel(x, y)
        ok = (c >= 0) & (c < self.w) & (r >= 0) & (r < self.h)
        self.rgb[r[ok], c[ok]] = colour

    def sample(self, grid) -> tuple[np.ndarray, np.ndarray]:
        """The grid's cell under each pixel (nearest), and which pixels fall on the grid."""
        px, py = self.pixel_centres()
        ix = np.floor((px - grid.origin_x) / grid.resolution).astype(int)
        iy = np.floor((py - grid.origin_y) / grid.resolution).astype(int)
        h, w = grid.data.shape
        inside = ((iy >= 0) & (iy < h))[:, None] & ((ix >= 0) & (ix < w))[None, :]
        cells = grid.data[np.clip(iy, 0, h - 1)[:, None], np.clip(ix, 0, w - 1)[None, :]]
        return cells, inside


def render_map(view: RobotView, width: int, height: int) -> list[Strip]:
    """``width`` x ``height`` characters of the map around everything the view knows."""
    width, height = max(width, 4), max(height, 2)
    cv = Canvas(view, width, height)
    if view.grid is not None:
        cells, inside = cv.sample(view.grid)
        known = inside & (cells >= 0)
        occupied = known & (cells >= 65)
        cv.rgb[known & ~occupied] = FREE
        cv.rgb[occupied] = OCCUPIED
    if view.costmap is not None:
        cost, inside = cv.sample(view.costmap)
        shade = inside & (cost > 0) & (cost <= 100)
        if view.grid is not None:
            shade &= ~occupied
        a = (cost[shade].astype(np.float32) / 100.0)[:, None] * 0.6
        cv.rgb[shade] = (cv.rgb[shade] * (1 - a) + COST * a).astype(np.uint8)
    if len(view.scan):
        cv.dots(view.scan[:, 0], view.scan[:, 1], SCAN)
    if len(view.plan) > 1:
        p = view.plan
        seg = np.linspace(0.0, 1.0, 8)[:, None, None]
        pts = (p[:-1][None] * (1 - seg) + p[1:][None] * seg).reshape(-1, 2)  # the plan's segments, dotted densely
        cv.dots(pts[:, 0], pts[:, 1], PLAN)
    for pot in view.pots:
        colour = ANOMALY if pot.anomalies and pot.status == "inspected" else POT_COLOURS.get(pot.status, POT_COLOURS["pending"])
        r = 0.1
        cv.dots([pot.x - r, pot.x, pot.x + r, pot.x, pot.x], [pot.y, pot.y, pot.y, pot.y - r, pot.y + r], colour)
    x, y, yaw = view.pose
    body = np.linspace(-0.15, 0.15, 5)
    bx, by = np.meshgrid(body, body)
    cv.dots(x + bx.ravel(), y + by.ravel(), ROBOT)
    nose = np.linspace(0.0, 0.35, 8)
    cv.dots(x + nose * math.cos(yaw), y + nose * math.sin(yaw), HEADING)
    return [Strip(row, width) for row in half_block_rows(cv.rgb)]


@lru_cache(maxsize=4096)
def _style(top: tuple[int, int, int], bottom: tuple[int, int, int]) -> Style:
    return Style.parse(f"rgb({top[0]},{top[1]},{top[2]}) on rgb({bottom[0]},{bottom[1]},{bottom[2]})")


def half_block_rows(rgb: np.ndarray) -> list[list[Segment]]:
    """An (2H, W, 3) image as H rows of '▀' runs: the top pixel is the foreground colour, the
    bottom one the background."""
    h2 = rgb.shape[0] - rgb.shape[0] % 2
    rows = []
    for top, bottom in zip(rgb[0:h2:2].tolist(), rgb[1:h2:2].tolist()):
        keys = [(tuple(t), tuple(b)) for t, b in zip(top, bottom)]
        row, start = [], 0
        for col in range(1, len(keys) + 1):
            if col == len(keys) or keys[col] != keys[start]:
                row.append(Segment("▀" * (col - start), _style(*keys[start])))
                start = col
        rows.append(row)
    return rows


def half_blocks(rgb: np.ndarray) -> Text:
    """The same picture as ``rich`` text (small pictures: the camera snapshot)."""
    text = Text(no_wrap=True, overflow="crop")
    for i, row in enumerate(half_block_rows(rgb)):
        if i:
            text.append("\n")
        for seg in row:
            text.append(seg.text, seg.style)
    return text


class MapPanel(Widget):
    """Redrawn from the view at the app's poll rate, fitted to the panel's size."""

    def __init__(self, **kw):
        super().__init__(**kw)
        self._strips: list[Strip] = []

    def show(self, view: RobotView) -> None:
        size = self.content_size
        self._strips = render_map(view, size.width, size.height)
        self.refresh()

    def render_line(self, y: int) -> Strip:
        return self._strips[y] if y < len(self._strips) else Strip.blank(self.content_size.width)
