"""Stepping out of a walker's way (nav.people_nearby): square to their way on the robot's side
when there is room there to be wholly out of it; not into a pocket against a wall they would
pass it in."""
from __future__ import annotations

import numpy as np

from hw.odometry import Pose2D
from hw.people import Person
from nav.config import NavConfig
from nav.costmap.grid import LETHAL, CostGrid
from nav.people_nearby import PeopleNearby

CFG = NavConfig()


def _beside_a_wall() -> CostGrid:
    """6 x 6 m open floor (5 cm) with a wall x >= 3.45 (inflated: lethal from 3.25)."""
    grid = CostGrid.filled(120, 120, 0.05, 0.0, 0.0)
    grid.data[:, int(3.25 / 0.05):] = LETHAL
    return grid


def _step(walker: Person, grid: CostGrid, at=(3.0, 3.0)) -> np.ndarray:
    twist = PeopleNearby(CFG, lambda: [walker], Pose2D).evade(Pose2D(at[0], at[1], 0.0), grid, reach=4.0)
    return np.array([twist.vx, twist.vy])


def test_a_robot_between_a_walkers_way_and_a_wall_does_not_step_into_the_pocket():
    walker = Person(1, 2.6, 0.0, 0.0, 1.0, 0.35, 0.9)  # 3 m south, walking north 0.4 m west of the robot
    step = _step(walker, _beside_a_wall())
    assert step[0] < 0.1 and np.hypot(*step) > 0.1  # not east against the wall: along, away from them


def test_with_room_on_its_own_side_it_steps_there():
    walker = Person(1, 2.6, 0.0, 0.0, 1.0, 0.35, 0.9)
    step = _step(walker, CostGrid.filled(120, 120, 0.05, 0.0, 0.0))
    assert step[0] > 0.2 and abs(step[1]) < 0.1 * step[0]  # east, away from their way

