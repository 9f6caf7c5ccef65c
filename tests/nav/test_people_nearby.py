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



def test_a_way_into_the_lane_of_a_walker_coming_is_seen_before_the_robot_is_in_it():
    """A cart walking north up a cross aisle (x = 0) 2.5 m off; the robot 1.2 m east of its way,
    in no lane, its way ahead going west across the aisle: held at the edge. Behind the cart, or
    with its way along the edge, it goes on."""
    cart = Person(1, 0.0, 0.0, 0.0, 0.7, 0.45, 1.0)
    nearby = PeopleNearby(CFG, lambda: [cart], Pose2D)
    nearby.counted()  # one read: the cart's walk is remembered
    robot = Pose2D(1.2, 2.5, 0.0)
    west = np.column_stack([np.linspace(1.2, 0.7, 11), np.full(11, 2.5)])
    east = np.column_stack([np.linspace(1.2, 1.7, 11), np.full(11, 2.5)])
    assert not nearby.in_lane(robot)
    assert nearby.lane_ahead(robot, west) and not nearby.lane_ahead(robot, east)
    behind = Pose2D(1.2, -1.0, 0.0)  # the cart has passed: its way back is not its lane now
    assert not nearby.lane_ahead(behind, west - [0.0, 3.5])
    near = PeopleNearby(CFG, lambda: [Person(1, 0.0, 2.6, 0.0, 0.7, 0.45, 1.0)], Pose2D)
    assert not near.lane_ahead(robot, west)  # within arm's length: the touching rule's, not this


def test_the_way_back_of_someone_paused_at_the_end_of_their_walk_is_their_lane_too():
    """A cart pusher walked south down a cross aisle and paused at its end: they walk back up it.
    The robot's way into the aisle north of them waits; with them standing for good, it does not."""
    now = [0.0]
    people = [Person(1, 0.0, 0.5, 0.0, -0.7, 0.45, 1.0)]
    nearby = PeopleNearby(CFG, lambda: people, Pose2D)
    nearby.people.clock = lambda: now[0]
    nearby.counted()  # walking south: their walk is remembered
    people[:] = [Person(1, 0.0, 0.0, 0.0, 0.0, 0.45, 1.0)]
    robot = Pose2D(1.2, 2.5, 0.0)
    west = np.column_stack([np.linspace(1.2, 0.7, 11), np.full(11, 2.5)])
    assert not nearby.in_lane(robot) and nearby.lane_ahead(robot, west)
    now[0] = 60.0  # paused a minute: standing, not turning round
    assert not nearby.lane_ahead(robot, west)

