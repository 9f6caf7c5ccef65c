"""The patrol's ``run.png``: the map, the driven path, every pot by its result, a thumbnail each.

The map is ``nav.map_render``'s (free white, occupied black, unknown grey, 1 m grid, origin cross),
cropped to what was explored and grown with unknown cells where the path or a pot lies off it;
with no map, a blank white canvas covering the path and pots. Either way one world -> pixel
mapping, ``nav.map_render.to_pixel`` on the map ``canvas`` returns, and the map sits at the top
left of the picture, so that mapping holds in the whole image.

Colour code (the pot discs and their thumbnails' borders):

* green  -- inspected, nothing wrong;
* orange -- inspected, with an anomaly (bug, no_bloom, tag_mismatch, no_tag, ...);
* red    -- failed (never inspected: unreachable, no tag, ...);
* grey   -- skipped or pending (not tried), and any status this module does not know.

The driven path is blue with its start a blue dot; home is a purple square. Under the map a
legend (with counts), then the thumbnails in the pots' order, each captioned with its label. A
patrol of more than ``INLINE_THUMBNAILS`` pots keeps ``run.png`` a picture of the greenhouse:
its thumbnails go to a contact sheet beside it (``contact_sheet``, ``contact.png``), the legend
says so, and 200 pots make a sheet to scroll, not a map lost above 7 m of tiles.
"""
from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from typing import Sequence

import cv2
import numpy as np

from nav.grid_geometry import paste
from nav.map_render import default_scale, render_map, to_pixel
from nav.occupancy import FREE, UNKNOWN, OccupancyMap

GREEN, ORANGE, RED, GREY = (60, 170, 60), (0, 150, 255), (50, 50, 220), (130, 130, 130)
PATH, HOME, INK, PAPER = (200, 90, 20), (160, 40, 160), (30, 30, 30), (255, 255, 255)
MARGIN_M = 0.6
"""Room round the path and the pots, m."""
MAX_PAD_M = 10.0
"""The canvas reaches at most this far beyond the map (no map: the path and home) to take in a pot
or the path; anything farther is drawn clamped to the edge, so a stray coordinate keeps a sane size."""
FAR_M = 10_000.0
"""Coordinates farther from the origin than this are not places (a bug upstream): not drawn."""
BLANK_RESOLUTION, BLANK_MAX_CELLS = 0.05, 1000
THUMB_W, THUMB_MAX_H, BORDER, GAP, PER_ROW = 160, 200, 4, 12, 6
INLINE_THUMBNAILS = 24
"""Most pots whose thumbnails go under the map (four rows); more go to the contact sheet."""
CONTACT_PER_ROW = 10
FONT = cv2.FONT_HERSHEY_SIMPLEX


@dataclass(frozen=True)
class PotMark:
    id: str
    x: float
    y: float
    """Pot centre, map frame, m."""
    status: str
    """'inspected' | 'failed' | 'skipped' | 'pending'."""
    anomaly: bool
    """Any anomaly recorded for this pot."""
    label: str
    """Short caption for the thumbnail, e.g. "P04 red x2 bug"."""
    thumbnail: np.ndarray | None
    """BGR uint8 image (the wrist frame), any size, or None."""


RESULTS = {"inspected": GREEN, "anomaly": ORANGE, "failed": RED, "skipped/pending": GREY}
"""The legend's names for the colour code, in its order."""


def result(pot: PotMark) -> str:
    """The pot's key in ``RESULTS``."""
    if pot.status == "inspected":
        return "anomaly" if pot.anomaly else "inspected"
    return "failed" if pot.status == "failed" else "skipped/pending"


def pot_colour(pot: PotMark) -> tuple[int, int, int]:
    return RESULTS[result(pot)]


def canvas(occupancy: OccupancyMap | None, path_xy: np.ndarray, pots: Sequence[PotMark],
           home: tuple[float, float] | None = None) -> tuple[OccupancyMap, int]:
    """The map ``draw_run`` renders and its scale: ``to_pixel(*canvas(...), x, y)`` is where a
    map-frame point lands in the picture."""
    home_xy = np.array([] if home is None else [home], float).reshape(-1, 2)
    driven = _sane(np.vstack([np.asarray(path_xy, float).reshape(-1, 2), home_xy]))
    spots = _sane(np.array([[p.x, p.y] for p in pots], float).reshape(-1, 2))
    pts = np.vstack([driven, spots])
    if occupancy is not None:
        base, fill = occupancy.cropped(), UNKNOWN
        if not len(pts):
            return base, default_scale(base)
        core = np.array([[base.origin_x, base.origin_y], [base.origin_x + base.width * base.resolution,
                                                           base.origin_y + base.height * base.resolution]])
    else:  # the path (and home) make the core; with neither, the pots; with nothing, the origin
        core = driven if len(driven) else spots if len(spots) else np.zeros((1, 2))
        pts = pts if len(pts) else core
    lo = np.maximum(pts.min(axis=0) - MARGIN_M, core.min(axis=0) - MAX_PAD_M)
    hi = np.minimum(pts.max(axis=0) + MARGIN_M, core.max(axis=0) + MAX_PAD_M)
    if occupancy is None:
        res = max(BLANK_RESOLUTION, float((hi - lo).max()) / BLANK_MAX_CELLS)
        base, fill = OccupancyMap(np.full((1, 1), FREE, np.int8), res, float(lo[0]), float(lo[1])), FREE
    geo = base.geometry.grown_to_cover(lo[0], lo[1], hi[0], hi[1])
    if geo != base.geometry:
        base = OccupancyMap(paste(base.occupancy, base.geometry, geo, fill), geo.resolution, geo.origin_x, geo.origin_y,
                            base.origin_yaw)
    return base, default_scale(base)


def _sane(xy: np.ndarray) -> np.ndarray:
    """The rows of an N x 2 array that are real places (finite, within FAR_M of the origin)."""
    return xy[np.isfinite(xy).all(axis=1) & (np.abs(xy) <= FAR_M).all(axis=1)]


def draw_run(occupancy: OccupancyMap | None, path_xy: np.ndarray, pots: Sequence[PotMark],
             home: tuple[float, float] | None = None) -> np.ndarray:
    """BGR uint8 picture of a patrol: the map with path, start, home and pots, a legend, thumbnails."""
    m, scale = canvas(occupancy, path_xy, pots, home)
    img = render_map(m, scale)
    h, w = img.shape[:2]
    ppm = scale / m.resolution

    def px(x: float, y: float) -> tuple[int, int]:
        c, r = to_pixel(m, scale, x, y)
        return min(max(c, 0), w - 1), min(max(r, 0), h - 1)

    path = _sane(np.asarray(path_xy, float).reshape(-1, 2))
    if len(path):
        cv2.polylines(img, [np.array([px(x, y) for x, y in path], np.int32)], False, PATH, 2, cv2.LINE_AA)
        cv2.circle(img, px(*path[0]), 5, PATH, -1, cv2.LINE_AA)
    r = int(min(max(round(0.15 * ppm), 6), 14))
    if home is not None and len(_sane(np.array([home], float))):
        c, rr = px(*home)
        cv2.rectangle(img, (c - r - 3, rr - r - 3), (c + r + 3, rr + r + 3), HOME, 2)
    for pot in pots:
        if not len(_sane(np.array([[pot.x, pot.y]], float))):
            continue
        c, rr = px(pot.x, pot.y)
        cv2.circle(img, (c, rr), r, pot_colour(pot), -1, cv2.LINE_AA)
        cv2.circle(img, (c, rr), r, INK, 1, cv2.LINE_AA)
        tw = cv2.getTextSize(pot.id, FONT, 0.45, 1)[0][0]
        _text(img, pot.id, (c + r + 3 if c + r + 3 + tw < w else c - r - 3 - tw, rr + 5), 0.45, halo=True)
    thumbs = _thumbnails(pots) if len(pots) <= INLINE_THUMBNAILS else None
    note = "" if len(pots) <= INLINE_THUMBNAILS else "thumbnails: contact.png"
    out = _below(img, _legend(pots, max(w, thumbs.shape[1] if thumbs is not None else 0), note), thumbs)
    return _pad(out, out.shape[0] + GAP // 2, out.shape[1])


def contact_sheet(pots: Sequence[PotMark]) -> np.ndarray | None:
    """The thumbnails of a patrol too big to carry them under its map (``INLINE_THUMBNAILS``),
    ten to a row in the pots' order; None for a patrol that keeps them in ``run.png``."""
    if len(pots) <= INLINE_THUMBNAILS:
        return None
    out = _thumbnails(pots, CONTACT_PER_ROW)
    return _pad(out, out.shape[0] + GAP, out.shape[1] + GAP, top=GAP)


def _text(img: np.ndarray, text: str, org: tuple[int, int], size: float, colour=INK, halo: bool = False) -> None:
    if halo:  # a white outline keeps an id legible over walls and the grid
        cv2.putText(img, text, org, FONT, size, PAPER, 3, cv2.LINE_AA)
    cv2.putText(img, text, org, FONT, size, colour, 1, cv2.LINE_AA)


def _legend(pots: Sequence[PotMark], width: int, note: str = "") -> np.ndarray:
    counts = Counter(result(p) for p in pots)
    entries = [("path", PATH), ("home", HOME)] + [(f"{name} ({counts[name]})", c) for name, c in RESULTS.items()]
    entries += [(note, None)] if note else []
    rows, x = [[]], GAP
    for name, colour in entries:
        step = 22 + cv2.getTextSize(name, FONT, 0.5, 1)[0][0] + 18
        if x + step > width and rows[-1]:
            rows.append([])
            x = GAP
        rows[-1].append((x, name, colour))
        x += step
    img = np.full((8 + 24 * len(rows), width, 3), PAPER, np.uint8)
    img[0] = (200, 200, 200)  # a rule under the map (a blank map has no edge of its own)
    for k, row in enumerate(rows):
        y = 8 + 24 * k + 12
        for x, name, colour in row:
            if colour == PATH:
                cv2.line(img, (x, y), (x + 16, y), PATH, 2, cv2.LINE_AA)
            elif colour == HOME:
                cv2.rectangle(img, (x + 2, y - 7), (x + 15, y + 6), HOME, 2)
            elif colour is None:  # a note, no swatch
                pass
            else:
                cv2.circle(img, (x + 8, y), 7, colour, -1, cv2.LINE_AA)
                cv2.circle(img, (x + 8, y), 7, INK, 1, cv2.LINE_AA)
            _text(img, name, (x + 22, y + 5), 0.5)
    return img


def fit_thumbnail(image: np.ndarray) -> np.ndarray:
    """``image`` (BGR or grey) as a BGR tile's picture, fit in THUMB_W x THUMB_MAX_H."""
    t = cv2.cvtColor(image, cv2.COLOR_GRAY2BGR) if image.ndim == 2 else image[..., :3]
    f = min(THUMB_W / t.shape[1], THUMB_MAX_H / t.shape[0])
    size = (max(1, round(t.shape[1] * f)), max(1, round(t.shape[0] * f)))
    return cv2.resize(np.ascontiguousarray(t, np.uint8), size, interpolation=cv2.INTER_AREA)


def _thumbnail(pot: PotMark) -> np.ndarray:
    """One tile: the image fit in THUMB_W x THUMB_MAX_H, a border in the pot's colour, its caption."""
    t = pot.thumbnail
    if t is not None and t.size:
        t = fit_thumbnail(t)
    else:
        t = np.full((THUMB_W * 3 // 4, THUMB_W, 3), 215, np.uint8)
        _text(t, "no image", (THUMB_W // 2 - 38, THUMB_W * 3 // 8 + 5), 0.5, (90, 90, 90))
    t = cv2.copyMakeBorder(t, BORDER, BORDER, BORDER, BORDER, cv2.BORDER_CONSTANT, value=pot_colour(pot))
    lines = _wrap(pot.label or pot.id, t.shape[1])
    tile = np.full((t.shape[0] + 6 + 18 * len(lines), THUMB_W + 2 * BORDER, 3), PAPER, np.uint8)
    tile[:t.shape[0], :t.shape[1]] = t
    for k, line in enumerate(lines):
        _text(tile, line, (2, t.shape[0] + 18 + 18 * k), 0.45)
    return tile


def _wrap(text: str, width: int, lines: int = 2) -> list[str]:
    """Words in up to ``lines`` lines of ``width`` px, a line too long cut with '..'."""
    fits = lambda s: cv2.getTextSize(s, FONT, 0.45, 1)[0][0] <= width - 4  # noqa: E731
    out = [""]
    for word in text.split():
        if out[-1] and not fits(f"{out[-1]} {word}") and len(out) < lines:
            out.append(word)
        else:
            out[-1] = f"{out[-1]} {word}".strip()
    for k, line in enumerate(out):
        if not fits(line):
            while line and not fits(line + ".."):
                line = line[:-1]
            out[k] = line + ".."
    return out


def _thumbnails(pots: Sequence[PotMark], per_row: int = PER_ROW) -> np.ndarray | None:
    """The tiles in rows of ``per_row``, in the given order; None when there are no pots."""
    if not pots:
        return None
    tiles = [_thumbnail(p) for p in pots]
    rows = [tiles[k:k + per_row] for k in range(0, len(tiles), per_row)]
    strips = [np.hstack([_pad(t, max(u.shape[0] for u in row), t.shape[1] + GAP) for t in row]) for row in rows]
    return _below(*strips, left=GAP)


def _below(*parts: np.ndarray | None, left: int = 0) -> np.ndarray:
    """Stack images top to bottom, left-aligned (the first at (0, 0)) on white, ``left`` px indented."""
    parts = [p for p in parts if p is not None]
    width = max(p.shape[1] for p in parts) + left
    gaps = [0] + [GAP] * (len(parts) - 1)
    return np.vstack([_pad(p, p.shape[0] + g, width, left, g) for p, g in zip(parts, gaps)])


def _pad(img: np.ndarray, height: int, width: int, left: int = 0, top: int = 0) -> np.ndarray:
    out = np.full((height, width, 3), PAPER, np.uint8)
    out[top:top + img.shape[0], left:left + img.shape[1]] = img
    return out
