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
from nav.walks import Walks

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



def test_the_way_out_of_a_keep_out_keeps_out_of_a_paused_pacers_walk():
    """Seed 107, 741-752 s: the way out of a yielding cart pusher's keep-out led across the end
    of a cross aisle whose cart had paused at its far end; it came back up and into the robot.
    The way-out grid lays a paused walker's walk back to where it began; while they walk on,
    only their next steps."""
    t = [0.0]
    walker = [Person(1, 1.0, 0.0, 0.0, 1.0, 0.35, 0.9)]
    near = PeopleNearby(CFG, Walks(lambda: walker, lambda: t[0]), Pose2D)
    for k in range(31):  # walks north from (1, 0) to (1, 3) at 1 m/s
        t[0] = 0.1 * k
        walker[:] = [Person(1, 1.0, 0.1 * k, 0.0, 1.0, 0.35, 0.9)]
        near.counted()
    floor = CostGrid.filled(120, 120, 0.05, 0.0, 0.0)
    behind = floor.geometry.cell_of(np.array([1.0]), np.array([1.0]))

    def laid() -> bool:
        return near.way_out(floor, 4.0, 4.0).data[int(behind[1][0]), int(behind[0][0])] == LETHAL

    assert not laid()  # walking on north: where they walked is behind them
    t[0] += 2.0
    walker[:] = [Person(1, 1.0, 3.0, 0.0, 0.0, 0.35, 0.9)]
    near.counted()
    assert laid()  # paused at the end of their walk: they come back down it
