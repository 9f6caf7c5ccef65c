"""How good is a map: its occupied cells against the world file, rasterised on the map's grid.

Judging only (it reads the sim's world, which the robot never does). The truth is what a lidar
in the greenhouse could see: the faces of pots, boxes and walls, i.e. the cells of the
rasterised solids that border the free floor. The map's occupied cells (p >= 0.65, map_server's
threshold) are then scored both ways with a one-cell tolerance:

* recall: the share of true face cells with a mapped occupied cell within one cell;
* precision: the share of mapped occupied cells with a true solid cell within one cell.

``tolerance`` (m) widens "within one cell" to as many cells as it holds (10 cm: two cells, the
issue-30 figures). ``wall_errors`` judges where the map draws each long wall, a metre at a time.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from hw.odometry import Pose2D
from nav.occupancy import OccupancyMap
from sim.config import GreenhouseGeometry
from sim.greenhouse import WALL_THICKNESS
from sim.world import World

_NEIGHBOURS = np.ones((3, 3), np.uint8)


@dataclass(frozen=True)
class MapQuality:
    recall: float
    precision: float
    true_cells: int
    mapped_cells: int


def solid_cells(m: OccupancyMap, world: World, spawn: Pose2D,
                geometry: GreenhouseGeometry = GreenhouseGeometry()) -> tuple[np.ndarray, np.ndarray]:
    """Boolean [iy, ix] rasters on ``m``'s grid: (solid, floor) from the world file; the map
    frame is the robot's start pose ``spawn`` (world frame)."""
    ix, iy = np.meshgrid(np.arange(m.width), np.arange(m.height))
    mx, my = m.geometry.centre_of(ix, iy)
    c, s = math.cos(spawn.yaw), math.sin(spawn.yaw)
    wx, wy = spawn.x + c * mx - s * my, spawn.y + s * mx + c * my
    fx, fy = world.floor.x, world.floor.y
    floor = (wx >= 0) & (wx <= fx) & (wy >= 0) & (wy <= fy)
    t = WALL_THICKNESS
    solid = ~floor & (wx >= -t) & (wx <= fx + t) & (wy >= -t) & (wy <= fy + t)
    for pot in world.pots:
        solid |= np.hypot(wx - pot.x, wy - pot.y) <= geometry.pot_radius
    for box in world.obstacles:
        bc, bs = math.cos(box.yaw), math.sin(box.yaw)
        lx, ly = bc * (wx - box.x) + bs * (wy - box.y), -bs * (wx - box.x) + bc * (wy - box.y)
        solid |= (np.abs(lx) <= box.sx / 2) & (np.abs(ly) <= box.sy / 2)
    return solid, floor & ~solid


def map_quality(m: OccupancyMap, world: World, spawn: Pose2D, tolerance: float | None = None) -> MapQuality:
    solid, free = solid_cells(m, world, spawn)
    faces = solid & (cv2.dilate(free.astype(np.uint8), np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], np.uint8)) > 0)
    mapped = m.occupied()
    cells = 1 if tolerance is None else max(1, int(round(tolerance / m.resolution)))
    near = _NEIGHBOURS if cells == 1 else np.ones((2 * cells + 1, 2 * cells + 1), np.uint8)
    near_mapped = cv2.dilate(mapped.astype(np.uint8), near) > 0
    near_solid = cv2.dilate(solid.astype(np.uint8), near) > 0
    n_true, n_mapped = int(faces.sum()), int(mapped.sum())
    return MapQuality(recall=float((faces & near_mapped).sum()) / max(n_true, 1),
                      precision=float((mapped & near_solid).sum()) / max(n_mapped, 1),
                      true_cells=n_true, mapped_cells=n_mapped)


LONG_WALL = 2.0
"""A wall face this long or longer is judged for where the map draws it, m (the outer walls, a
bay divider's stretches between doorways; a crate is not a wall)."""
WALL_STRIP = 0.3
"""How far either side of a wall's true face the map's cells are taken as drawing it, m (a map
drawn further off than this has lost the wall, which recall counts)."""
WALL_SEGMENT = 1.0
"""A face is judged a metre at a time: the mean offset of its mapped face over a metre, so one
cell's quantisation (5 cm) averages out and a wall drawn a few centimetres off shows."""
WALL_END = 0.1
"""Stations nearer than this to a face's end are not judged, m (two cells): at a corner the walk
in from the floor runs down the other wall's own cells, drawn in the floor cell beside its face
as the lidar's noise puts them, and read them as this wall 25-30 cm off: a corner metre drawn
true read 0.015, one drawn 5 cm off 0.06 (the 180-pot greenhouse's north wall). Precision and
recall still judge the corners."""


@dataclass(frozen=True)
class WallFace:
    """One side of a wall the robot can see: from ``a`` to ``b`` (world, m)."""

    a: tuple[float, float]
    b: tuple[float, float]
    normal: tuple[float, float]
    """Unit vector from the face into the floor (where the lidar sees it from)."""


def long_wall_faces(world: World) -> list[WallFace]:
    """The faces of the outer walls and of every long thin box (a bay divider) of ``world``."""
    fx, fy = world.floor.x, world.floor.y
    faces = [WallFace((0.0, 0.0), (fx, 0.0), (0.0, 1.0)), WallFace((0.0, fy), (fx, fy), (0.0, -1.0)),
             WallFace((0.0, 0.0), (0.0, fy), (1.0, 0.0)), WallFace((fx, 0.0), (fx, fy), (-1.0, 0.0))]
    for box in world.obstacles:
        c, s = math.cos(box.yaw), math.sin(box.yaw)
        long_x = box.sx >= box.sy
        length, thick = (box.sx, box.sy) if long_x else (box.sy, box.sx)
        if length < LONG_WALL:
            continue
        u = (c, s) if long_x else (-s, c)  # along the wall
        n = (-u[1], u[0])
        for sign in (1.0, -1.0):
            off = (box.x + sign * n[0] * thick / 2, box.y + sign * n[1] * thick / 2)
            faces.append(WallFace((off[0] - u[0] * length / 2, off[1] - u[1] * length / 2),
                                  (off[0] + u[0] * length / 2, off[1] + u[1] * length / 2), (sign * n[0], sign * n[1])))
    return [f for f in faces if math.dist(f.a, f.b) >= LONG_WALL]


def wall_errors(m: OccupancyMap, world: World, spawn: Pose2D) -> list[float]:
    """For each metre of each long wall face, how far (m, signed: + into the floor) the map
    draws the face from where it stands: the mean, along that metre, of how far the occupied
    cell nearest the floor within ``WALL_STRIP`` of the face lies from it (0 for a cell that
    holds or touches the face: the lidar's noise puts a face on a cell boundary in the cells
    either side). Metres the map shows nothing of are left out, and ``WALL_END`` at each end."""
    out = []
    for face in long_wall_faces(world):
        length = math.dist(face.a, face.b)
        along = ((face.b[0] - face.a[0]) / length, (face.b[1] - face.a[1]) / length)
        for start in np.arange(0.0, length - WALL_SEGMENT / 2, WALL_SEGMENT):
            stations = np.arange(start + m.resolution / 2, min(start + WALL_SEGMENT, length), m.resolution)
            stations = stations[(stations >= WALL_END) & (stations <= length - WALL_END)]
            offsets = [o for o in (_drawn_off(m, spawn, (face.a[0] + along[0] * t, face.a[1] + along[1] * t), face.normal)
                                   for t in stations) if o is not None]
            if len(offsets) >= WALL_SEGMENT / m.resolution / 2:
                out.append(float(np.mean(offsets)))
    return out


def _drawn_off(m: OccupancyMap, spawn: Pose2D, point: tuple[float, float], normal: tuple[float, float]) -> float | None:
    """How far from the face at world ``point`` the map draws it: walking in from the floor
    side along ``-normal``, the first occupied cell met, its distance off the face (0 when it
    holds or touches it); None when no cell within ``WALL_STRIP`` either side is occupied."""
    res, occupied = m.resolution, m.occupied()
    c, s = math.cos(spawn.yaw), math.sin(spawn.yaw)
    for d in np.arange(WALL_STRIP, -WALL_STRIP - 1e-9, -res / 2):
        dx, dy = point[0] + normal[0] * d - spawn.x, point[1] + normal[1] * d - spawn.y
        ix, iy = m.geometry.cell_of(c * dx + s * dy, -s * dx + c * dy)
        if m.geometry.contains(ix, iy) and occupied[iy, ix]:
            cx, cy = m.geometry.centre_of(ix, iy)
            wx, wy = spawn.x + c * cx - s * cy, spawn.y + s * cx + c * cy
            off = (wx - point[0]) * normal[0] + (wy - point[1]) * normal[1]  # the cell's centre off the face
            return max(off - res / 2, 0.0) + min(off + res / 2, 0.0)
    return None
