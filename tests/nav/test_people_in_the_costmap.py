"""A person walking across in front of the robot is marked in the local costmap while there and
cleared behind (no ghost trail), from real MuJoCo scans of a walker."""
from __future__ import annotations

import numpy as np
import pytest

from hw.config import HwConfig
from nav.config import NavConfig
from nav.costmap.grid import LETHAL
from nav.costmap.layered import local_costmap
from sim.backend import SimRobot
from sim.config import SimConfig
from sim.world import Floor, Pose2, Walker, World

pytestmark = pytest.mark.slow


def test_a_walker_crossing_is_marked_where_it_is_and_cleared_where_it_was():
    walker = Walker(id="W1", path=[[2.2, 0.4], [2.2, 3.6]], speed=1.0, pause=100.0)
    world = World(name="crossing", floor=Floor(x=6.0, y=4.0), spawn=Pose2(x=1.0, y=2.0, yaw=0.0), pots=[],
                  walkers=[walker])
    sim = SimRobot(world, SimConfig(), HwConfig())
    nav = NavConfig()
    costmap = local_costmap(nav.costmap)
    mx, my, _ = nav.navigator.lidar_mount
    marked_on_path = []
    for k in range(1, 45):  # 4.4 s: across the window and out of it
        t = 0.1 * k
        sim.engine.advance_to(t)
        costmap.update(sim.lidar.latest_scan(), (1.0 + mx, 2.0 + my, 0.0), (1.0, 2.0))
        if abs(sim.walkers.positions()["W1"][1] - 2.0) < 0.1:  # right in front of the robot
            g = costmap.grid
            cx, cy = g.geometry.cell_of(2.2, 2.0)
            marked_on_path.append(int(g.data[cy - 3:cy + 4, cx - 4:cx + 3].max()))
    assert marked_on_path and max(marked_on_path) == LETHAL  # seen while it crossed
    g = costmap.grid
    x0, y0 = g.geometry.cell_of(2.0, 1.2)
    x1, y1 = g.geometry.cell_of(2.4, 2.8)
    behind = g.data[y0:y1 + 1, x0:x1 + 1]
    assert not np.any(behind == LETHAL)  # where it walked, in the lidar's view: cleared
