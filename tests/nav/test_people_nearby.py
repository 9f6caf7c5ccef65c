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



def test_waiting_in_a_paused_pacers_walk_it_steps_out_before_they_come_back():
    """Held-out seed 4, 1,580 s: a cart pusher who does not yield walked the cross aisle north
    and paused at its end, 4.1 m from the robot waiting in the aisle for someone else. In no
    one's keep-out, the robot stood there; in the lane they walked, it steps out of it now,
    at the layer's step speed (nobody within 1 m)."""
    people = [Person(6, 3.0, 0.3, 0.0, 0.7, 0.35, 0.9)]
    nearby = PeopleNearby(CFG, lambda: people, Pose2D)
    for k in range(1, 12):  # walking north up x = 3, 0.5 m a read
        people[:] = [Person(6, 3.0, 0.3 + 0.5 * k, 0.0, 0.7, 0.35, 0.9)]
        nearby.counted()
    people[:] = [Person(6, 3.0, 5.8, 0.0, 0.0, 0.35, 0.9)]  # paused at the north end
    here = Pose2D(3.1, 1.6, 0.0)  # 4.2 m south of them, in the aisle they walked
    twist = nearby.evade(here, CostGrid.filled(120, 120, 0.05, 0.0, 0.0), CFG.costmap.global_costmap.people.wait_clearance)
    assert abs(twist.vx) > 0.5 * CFG.costmap.global_costmap.people.step_speed  # sideways, out of the aisle's line
    assert abs(np.hypot(twist.vx, twist.vy) - CFG.costmap.global_costmap.people.step_speed) < 1e-9
    fresh = PeopleNearby(CFG, lambda: people, Pose2D)  # never saw them walk: no lane, no step
    assert fresh.evade(here, CostGrid.filled(120, 120, 0.05, 0.0, 0.0),
                       CFG.costmap.global_costmap.people.wait_clearance) == ZERO_TWIST
