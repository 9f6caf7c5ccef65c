"""An occupancy map as a picture a person can read: the one renderer for ``lupin map show``
and the patrol's run picture, and the path drawing the navigation picture shares.

Free white, occupied black, unknown grey, north up; cells scaled up by whole pixels (nearest
neighbour, so every cell stays a crisp square) until the short side is about 400 px (the long
side kept within 4000 px); a light 1 m grid; the map origin (the dock, in SLAM mode) as a
small axis cross, x red and y green. Pure drawing: no file I/O here.
"""
from __future__ import annotations

import math

import cv2
import numpy as np

from nav.grid_geometry import GridGeometry
from nav.occupancy import OccupancyMap

WHITE, BLACK, GREY = (255, 255, 255), (0, 0, 0), (160, 160, 160)
GRID = (225, 215, 205)
RED, GREEN = (40, 40, 220), (40, 170, 40)
MIN_SHORT_SIDE = 400
MAX_LONG_SIDE = 4000


def render_map(m: OccupancyMap, scale: int | None = None, occupied_thresh: int = 65,
               free_thresh: int = 25) -> np.ndarray:
    """BGR uint8 image of ``m``, ``scale`` pixels per cell (default: fit ~400 px)."""
    if scale is None:
        scale = default_scale(m)
    if scale < 1:
        raise ValueError(f"render_map: scale must be a whole number of pixels >= 1, got {scale}")
    occ = m.occupancy
    img = np.empty(occ.shape + (3,), np.uint8)
    img[:] = GREY
    known = (occ >= 0) & (occ <= 100)
    img[known & (occ <= free_thresh)] = WHITE
    img[known & (occ >= occupied_thresh)] = BLACK
    img = np.repeat(np.repeat(img[::-1], scale, axis=0), scale, axis=1)
    _grid(img, m, scale)
    _origin(img, m, scale)
    return img


def default_scale(m: OccupancyMap) -> int:
    """Whole pixels per cell making the short side at least ``MIN_SHORT_SIDE``, unless that
    would make the long side pass ``MAX_LONG_SIDE`` (a long thin map stays a sane size)."""
    up = math.ceil(MIN_SHORT_SIDE / max(1, min(m.width, m.height)))
    return max(1, min(up, MAX_LONG_SIDE // max(1, m.width, m.height)))


def to_pixel(m: OccupancyMap, scale: int, x: float, y: float) -> tuple[int, int]:
    """Map-frame point -> (column, row) in a ``render_map`` image."""
    c, r = m.geometry.pixel_of(x, y, scale)
    return int(round(float(c))), int(round(float(r)))


def polyline(img: np.ndarray, geometry: GridGeometry, scale: float, xy, colour, thickness: int = 2) -> None:
    """A path of world points (N, 2) drawn on a north-up picture of ``geometry`` at ``scale``
    pixels per cell (anti-aliased; nothing for fewer than two points)."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    if len(xy) > 1:
        c, r = geometry.pixel_of(xy[:, 0], xy[:, 1], scale)
        cv2.polylines(img, [np.column_stack([c, r]).round().astype(np.int32)], False, colour, thickness, cv2.LINE_AA)


def _grid(img: np.ndarray, m: OccupancyMap, scale: int) -> None:
    """A 1 m grid, drawn only over free cells so walls and pots stay solid."""
    free = np.all(img == WHITE, axis=2)
    x0, x1, y0, y1 = m.geometry.extent
    lines = np.zeros(img.shape[:2], bool)
    for gx in range(math.ceil(x0), math.floor(x1) + 1):
        c = to_pixel(m, scale, gx, y0)[0]
        lines[:, max(0, min(c, img.shape[1] - 1))] = True
    for gy in range(math.ceil(y0), math.floor(y1) + 1):
        r = to_pixel(m, scale, x0, gy)[1]
        lines[max(0, min(r, img.shape[0] - 1)), :] = True
    img[lines & free] = GRID


def _origin(img: np.ndarray, m: OccupancyMap, scale: int) -> None:
    c, r = to_pixel(m, scale, 0.0, 0.0)
    if not (0 <= c < img.shape[1] and 0 <= r < img.shape[0]):
        return
    arm = max(8, int(round(0.3 / m.resolution * scale)))
    cv2.arrowedLine(img, (c, r), (c + arm, r), RED, 2, tipLength=0.3)
    cv2.arrowedLine(img, (c, r), (c, r - arm), GREEN, 2, tipLength=0.3)
