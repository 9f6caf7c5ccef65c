"""``lupin history pests -o FILE.png``: the greenhouse with each pot shaded by pest pressure over
the last patrols, so a spread is seen as a patch growing from one patrol to the next.

The background is the map the latest patrol saved beside its report (``map.yaml``, drawn as
``run.png`` draws it) when it is still there, else a plain white plot of the pots. Each pot is
a disc coloured from green (no pest in any patrol that judged it) through yellow to red (a pest
every time); grey when no patrol judged its flower. A thick dark ring marks a pot whose latest
patrols saw a pest in a row (its streak), and the fraction is written beside the pot's id.
"""
from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from mission.history.records import PestMap, as_utc
from mission.patrol.run_picture import GREY, INK, PAPER, PotMark, canvas
from nav.map_render import render_map, to_pixel
from nav.occupancy import OccupancyMap

FONT = cv2.FONT_HERSHEY_SIMPLEX
GREEN, YELLOW, RED = np.array((60, 170, 60)), np.array((0, 210, 240)), np.array((40, 40, 215))
"""BGR ends of the pressure scale."""
ALL_LABELS, TOP_LABELS = 80, 12
"""Up to ALL_LABELS pots every pot is named; past that, only the TOP_LABELS worst (the rest would
be ink over ink)."""
MIN_WIDTH = 420
"""Pixels: the title and the scale need this much, whatever the map's size."""


def pressure_colour(p: float) -> tuple[int, int, int]:
    """Green at 0, yellow at 0.5, red at 1 (BGR)."""
    p = float(np.clip(p, 0.0, 1.0))
    c = GREEN + (YELLOW - GREEN) * (p * 2) if p <= 0.5 else YELLOW + (RED - YELLOW) * ((p - 0.5) * 2)
    return tuple(int(round(v)) for v in c)


def saved_map(report_path: str | None) -> OccupancyMap | None:
    """The map beside a patrol's report, or None when it is gone or unreadable."""
    if not report_path:
        return None
    yaml_path = Path(report_path).parent / "map.yaml"
    if not yaml_path.is_file():
        return None
    from hw.errors import InputError
    from nav.map_io import load_map

    try:
        return load_map(yaml_path)
    except (InputError, OSError, ValueError):
        return None


def draw_pests(pests: PestMap, occupancy: OccupancyMap | None) -> np.ndarray:
    """BGR uint8 picture: the map (or a plain plot), the pots by pressure, a title and a scale."""
    placed = [p for p in pests.pots if p.x is not None and p.y is not None]
    marks = [PotMark(p.pot_id, p.x, p.y, "inspected", False, p.pot_id, None) for p in placed]
    m, scale = canvas(occupancy, np.zeros((0, 2)), marks, None)
    img = render_map(m, scale)
    h, w = img.shape[:2]
    ppm = scale / m.resolution
    spacing = nearest_spacing(np.array([(p.x, p.y) for p in placed]).reshape(-1, 2)) * ppm
    r = int(max(2, min(max(round(0.15 * ppm), 6), 14, int(0.42 * spacing))))
    ring = 1 if r < 6 else 3
    labelled = {p.pot_id for p in placed} if len(placed) <= ALL_LABELS else {
        p.pot_id for p in sorted(placed, key=lambda p: (-p.pressure, -p.streak))[:TOP_LABELS] if p.pests}
    for p in placed:
        c, rr = to_pixel(m, scale, p.x, p.y)
        c, rr = min(max(c, 0), w - 1), min(max(rr, 0), h - 1)
        colour = pressure_colour(p.pressure) if p.observed else GREY
        cv2.circle(img, (c, rr), r, colour, -1, cv2.LINE_AA)
        cv2.circle(img, (c, rr), r + (ring if p.streak else 0), INK, ring if p.streak else 1, cv2.LINE_AA)
        if p.pot_id not in labelled:
            continue
        label = f"{p.pot_id} {p.pests}/{p.observed}" if p.pests else p.pot_id
        tw = cv2.getTextSize(label, FONT, 0.42, 1)[0][0]
        org = (c + r + 4 if c + r + 4 + tw < w else c - r - 4 - tw, rr + 5)
        cv2.putText(img, label, org, FONT, 0.42, PAPER, 3, cv2.LINE_AA)
        cv2.putText(img, label, org, FONT, 0.42, INK, 1, cv2.LINE_AA)
    width = max(w, MIN_WIDTH)
    return _pad_stack([_title(pests, width), img, _scale(width)])


def nearest_spacing(xy: np.ndarray) -> float:
    """The smallest distance between two pots, m (inf for fewer than two): discs never overlap.

    A sweep in x order: the k-th next pot in x is compared with each pot, k = 1, 2, ... until
    every k-th next is farther in x alone than the best pair found (pots stand in rows, so a
    few dozen steps of O(n) on 2,000 pots, where all pairs were 2 M distances and 0.13 s)."""
    xy = np.asarray(xy, float).reshape(-1, 2)
    if len(xy) < 2:
        return float("inf")
    p = xy[np.lexsort((xy[:, 1], xy[:, 0]))]
    best = np.inf
    for k in range(1, len(p)):
        if float((p[k:, 0] - p[:-k, 0]).min()) >= best:
            break
        best = min(best, float(np.hypot(*(p[k:] - p[:-k]).T).min()))
    return best


def _title(pests: PestMap, width: int) -> np.ndarray:
    band = np.full((46, width, 3), 255, np.uint8)
    n = len(pests.patrols)
    span = f"{_utc(pests.patrols[-1].started_at)} .. {_utc(pests.patrols[0].started_at)} UTC" if n else "no patrols"
    with_pest = sum(1 for p in pests.pots if p.pests)
    cv2.putText(band, f"pest pressure, last {n} patrol(s) of {pests.mission or '-'}", (8, 18), FONT, 0.5, INK, 1,
                cv2.LINE_AA)
    cv2.putText(band, f"{span}; {with_pest} of {len(pests.pots)} pots with a pest", (8, 38), FONT, 0.42, INK, 1,
                cv2.LINE_AA)
    return band


def _utc(t) -> str:
    return as_utc(t).strftime("%Y-%m-%d %H:%M")


def _scale(width: int) -> np.ndarray:
    band = np.full((44, width, 3), 255, np.uint8)
    x0, x1 = 8, min(width - 120, 260)
    for x in range(x0, x1):
        band[8:22, x] = pressure_colour((x - x0) / max(1, x1 - x0 - 1))
    cv2.putText(band, "0", (x0, 38), FONT, 0.4, INK, 1, cv2.LINE_AA)
    cv2.putText(band, "1: a pest every patrol", (x1 - 40, 38), FONT, 0.4, INK, 1, cv2.LINE_AA)
    cv2.circle(band, (x1 + 20, 15), 6, GREY, -1, cv2.LINE_AA)
    cv2.putText(band, "not judged", (x1 + 30, 20), FONT, 0.4, INK, 1, cv2.LINE_AA)
    return band


def _pad_stack(parts: list[np.ndarray]) -> np.ndarray:
    width = max(p.shape[1] for p in parts)
    return np.vstack([np.pad(p, ((0, 0), (0, width - p.shape[1]), (0, 0)), constant_values=255) for p in parts])
