"""Stepping out of a walker's way (nav.people_nearby): square to their way on the robot's side
when there is room there to be wholly out of it; not into a pocket against a wall they would
pass it in."""
from __future__ import annotations

import numpy as np

from hw.interfaces import ZERO_TWIST
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



def test_a_wait_does_not_stand_in_the_walk_of_someone_paused_at_its_far_end():
    """safety.people seed 105, 1,386 s: waiting (for a grower at its goal, 5 m off) in a cross
    aisle a cart pusher paces, the cart paused at the far end 3 m south: the robot steps out of
    the cart's walk rather than wait in it; for a worker who never walked there is no walk to
    step out of."""
    now = [Person(1, 3.0, 0.0, 0.0, 1.1, 0.45, 0.9)]
    nearby = PeopleNearby(CFG, lambda: now, Pose2D)
    nearby.counted()
    now[:] = [Person(1, 3.0, 0.5, 0.0, 1.1, 0.45, 0.9)]  # walking north up x 3
    nearby.counted()
    now[:] = [Person(1, 3.0, 0.5, 0.0, 0.0, 0.45, 0.9)]  # paused at the end of their walk
    robot, floor = Pose2D(3.1, 3.5, 0.0), CostGrid.filled(120, 120, 0.05, 0.0, 0.0)
    wait = CFG.costmap.global_costmap.people.wait_clearance
    assert nearby.gap(now[0], robot.x, robot.y) > wait  # nobody near: only the walk says step
    twist = nearby.evade(robot, floor, wait)
    assert twist.vx > 0.1 and abs(twist.vy) < 0.5 * twist.vx  # east, off their line
    worker = PeopleNearby(CFG, lambda: [Person(2, 3.0, 0.5, 0.0, 0.0, 0.45, 0.9)], Pose2D)
    assert worker.evade(robot, floor, wait) == ZERO_TWIST
