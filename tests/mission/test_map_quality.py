"""How the map is judged (``mission.jobs.map_quality``): a map that draws every wall where the
lidar's noise puts it reads no wall error, corners included."""
from __future__ import annotations

import cv2
import numpy as np

from hw.odometry import Pose2D
from mission.jobs.map_quality import solid_cells, wall_errors
from nav.occupancy import OccupancyMap
from sim.generate import generate_world


def test_walls_drawn_in_the_floor_cell_beside_their_faces_are_no_metre_off_even_at_the_corners():
    """Every face drawn in the floor cell touching it (0 off by the convention): the walk in
    from the floor at a wall's last station ran down the next wall's cells and read them 30 cm
    off, each corner metre 0.015 (``slam.generated``'s worst wall error) before ``WALL_END``."""
    world = generate_world(3, 5, 1, bays=2).model_copy(update={"pots": []})
    spawn = Pose2D(1.0, 0.5, 0.0)
    blank = OccupancyMap(np.zeros((int(8.0 / 0.05), int(26.0 / 0.05)), np.int8), 0.05, -1.5, -1.0)
    solid, free = solid_cells(blank, world, spawn)
    beside = free & (cv2.dilate(solid.astype(np.uint8), np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], np.uint8)) > 0)
    drawn = OccupancyMap(np.where(beside, 100, 0).astype(np.int8), 0.05, -1.5, -1.0)
    errors = wall_errors(drawn, world, spawn)
    assert len(errors) == 40 and max(abs(e) for e in errors) < 1e-9, errors  # 16 + 16 + 4 + 4 m
