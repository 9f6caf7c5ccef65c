"""A picture of a navigation run a person can look at: the global costmap, the plan, and the
driven path as the robot believed it (its map pose: SLAM's ``map -> odom`` composed with wheel
odometry) and as it was (sim ground truth).

Drawn in the map frame (origin = the robot's start pose), north of the map up. Colours: unknown
grey, free white, inflated cost in orange shades, inscribed red, lethal black; the plans light blue
(the last one dark blue),
belief green, truth magenta; the goal as a circle of the xy tolerance with its heading.
"""
from __future__ import annotations

from typing import Sequence

import cv2
import numpy as np

from hw.odometry import Pose2D
from nav.costmap.grid import INSCRIBED, LETHAL, UNKNOWN, CostGrid
from nav.map_render import polyline

PX_PER_CELL = 4
MARGIN_M = 0.6
BLUE, LIGHT_BLUE, GREEN, MAGENTA, BLACK = (200, 80, 0), (240, 200, 150), (40, 160, 40), (180, 40, 200), (0, 0, 0)


def _palette() -> np.ndarray:
    lut = np.zeros((256, 3), dtype=np.uint8)
    shade = np.linspace(235, 120, 252).astype(np.uint8)  # 1..252: light to deep orange
    lut[0] = (255, 255, 255)
    lut[1:253, 0] = shade // 3
    lut[1:253, 1] = shade * 3 // 4
    lut[1:253, 2] = 255
    lut[INSCRIBED] = (60, 60, 220)
    lut[LETHAL] = (0, 0, 0)
    lut[UNKNOWN] = (190, 190, 190)
    return lut


def draw_navigation(grid: CostGrid, plans: Sequence[np.ndarray], odom: Sequence[Pose2D], truth: Sequence[Pose2D],
                    goal: Pose2D, xy_tolerance: float) -> np.ndarray:
    """BGR image; every pose in the map frame. Earlier plans are drawn thin, the last one bold."""
    pts = [np.array([[p.x, p.y] for p in list(odom) + list(truth)] + [[goal.x, goal.y]])]
    pts += [np.asarray(p)[:, :2] for p in plans]
    geo = grid.geometry
    iy, ix = np.nonzero(grid.data != UNKNOWN)
    if len(ix):
        pts.append(np.column_stack(geo.centre_of(ix, iy)))
    allp = np.vstack(pts)
    (x0, x1), (y0, y1) = (np.clip(c, 0, n - 1) for c, n in zip(
        geo.cell_of(*(np.array([allp.min(axis=0) - MARGIN_M, allp.max(axis=0) + MARGIN_M]).T)), (geo.width, geo.height)))
    crop = geo.cropped(int(x0), int(y0), int(x1) + 1, int(y1) + 1)
    img = _palette()[grid.data[y0:y1 + 1, x0:x1 + 1][::-1]]  # rows flipped: map north up
    img = cv2.resize(img, (img.shape[1] * PX_PER_CELL, img.shape[0] * PX_PER_CELL), interpolation=cv2.INTER_NEAREST)

    for old in plans[:-1]:
        polyline(img, crop, PX_PER_CELL, np.asarray(old)[:, :2], LIGHT_BLUE, 1)
    if len(plans):
        polyline(img, crop, PX_PER_CELL, np.asarray(plans[-1])[:, :2], BLUE, 2)
    for path, colour in ((odom, GREEN), (truth, MAGENTA)):
        polyline(img, crop, PX_PER_CELL, [(p.x, p.y) for p in path], colour, 2)
    (gc, gr), (tc, tr) = (np.round(crop.pixel_of(x, y, PX_PER_CELL)).astype(int) for x, y in (
        (goal.x, goal.y), (goal.x + 0.3 * np.cos(goal.yaw), goal.y + 0.3 * np.sin(goal.yaw))))
    cv2.circle(img, (gc, gr), int(xy_tolerance / grid.resolution * PX_PER_CELL), BLACK, 1, cv2.LINE_AA)
    cv2.arrowedLine(img, (gc, gr), (tc, tr), BLACK, 2, cv2.LINE_AA, tipLength=0.3)
    legend = [("plan", BLUE), ("belief (map pose)", GREEN), ("truth", MAGENTA)]
    for k, (name, colour) in enumerate(legend):
        cv2.putText(img, name, (8, 18 + 18 * k), cv2.FONT_HERSHEY_SIMPLEX, 0.5, colour, 1, cv2.LINE_AA)
    return img
